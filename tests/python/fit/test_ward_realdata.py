"""The Ward fit's specular constraint on the real Löwenkopf (240 lights): plausible ks colours,
no lost leave-one-out PSNR against the unconstrained per-channel fit measured here too."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np
import pytest

from lanterna.tiler.fit import ward_solve
from lanterna.tiler.fit.engine import fit_stream
from lanterna.tiler.inputs.lp import read_lp
from lanterna.tiler.inputs.stack import load_stack
from tests.python.fixtures.paths import SHARED

LOEWENKOPF = SHARED / "realdata" / "neuralrti-loewenkopf"

pytestmark = [
    pytest.mark.realdata,
    pytest.mark.skipif(not (LOEWENKOPF / "dirs.lp").is_file(),
                       reason=f"real data not found at {LOEWENKOPF} (../shared/realdata)"),
]

#: The bound of a plausible specular colour: within this angle (degrees) of the cone from grey to
#: the pixel's stored diffuse colour.  The fit allows MAX_SPECULAR_ANGLE (20°) around the cone
#: of its Lambert-only kd; the rest is the 8-bit rounding of ks ≥ 8/255 and kd.
PLAUSIBLE_DEGREES = 30.0


def _ward(tmp: Path, stack: np.ndarray, lights: np.ndarray) -> tuple[dict[str, Any], np.ndarray,
                                                                        np.ndarray]:
    tmp.mkdir()
    res = fit_stream(stack, lights, ["ward"], tmp, holdout_every=10)
    ch = res.layers["ward"].channels()
    kd = np.stack([ch[f"KD_{c}"] for c in "RGB"], -1).astype(np.float64)
    ks = np.stack([ch[f"KS_{c}"] for c in "RGB"], -1).astype(np.float64)
    return res.quality["ward"], kd, ks


def _off_cone_degrees(kd: np.ndarray, ks: np.ndarray) -> np.ndarray:
    """Angle of each ks colour from the grey–diffuse cone, where ks is at least 8/255."""
    cone = ward_solve.project_specular(ks, ward_solve.diffuse_chroma(kd))
    cos = (ks * cone).sum(-1) / np.maximum(np.linalg.norm(ks, axis=-1)
                                          * np.linalg.norm(cone, axis=-1), 1e-12)
    deg = np.degrees(np.arccos(np.clip(cos, -1.0, 1.0)))
    return deg[ks.max(axis=-1) >= 8 / 255]


def test_specular_colour_is_plausible_and_loo_psnr_holds(
        tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    files, lights = read_lp(LOEWENKOPF / "dirs.lp", LOEWENKOPF / "jpg")
    stack = load_stack(files)
    report, kd, ks = _ward(tmp_path / "constrained", stack, lights)
    with monkeypatch.context() as m:  # the free per-channel fit, as before the constraint
        m.setattr(ward_solve, "MAX_SPECULAR_ANGLE", 180.0)
        m.setattr(ward_solve, "MIN_LOBE_SAMPLES", 0)
        free, kd_free, ks_free = _ward(tmp_path / "free", stack, lights)
    # the free fit does put implausible colours (green/blue sparkles along the silhouette) …
    assert np.count_nonzero(_off_cone_degrees(kd_free, ks_free) > PLAUSIBLE_DEGREES) > 50
    # … the constrained one none, and none of the free fit's isolated bright sparkles
    # (measured: the free fit's brightest ks is 204/255, or the cap with a coarser α grid)
    off = _off_cone_degrees(kd, ks)
    assert off.size > 0.4 * kd[..., 0].size  # most of the object keeps a specular lobe
    assert off.max() <= PLAUSIBLE_DEGREES, np.sort(off)[-5:]
    assert ks.max() < 250 / 255 and ks.max() <= ks_free.max() - 50 / 255
    # and the held-out lights are predicted at least as well
    assert report["heldOut"] == free["heldOut"] and len(report["heldOut"]) == 24
    assert report["meanPsnr"] >= free["meanPsnr"], (report, free)
