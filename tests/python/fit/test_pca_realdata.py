"""The PCA bases fitted to the real 240-light NeuralRTI "Löwenkopf" collection: leave-one-out
against HSH9 (28.83 dB, docs/fitting.md), the streamed report equal to the library's."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import pytest

from lanterna.tiler.fit.models import leave_one_out, model_table
from lanterna.tiler.fit.run import fit_collection
from lanterna.tiler.inputs.lp import read_lp
from lanterna.tiler.inputs.stack import load_stack
from tests.python.fixtures.paths import SHARED

LOEWENKOPF = SHARED / "realdata" / "neuralrti-loewenkopf"

pytestmark = [
    pytest.mark.realdata,
    pytest.mark.skipif(not (LOEWENKOPF / "dirs.lp").is_file(),
                       reason=f"real data not found at {LOEWENKOPF} (../shared/realdata)"),
]


@pytest.fixture(scope="module")
def fitted(tmp_path_factory: pytest.TempPathFactory) -> dict[str, Any]:
    out = tmp_path_factory.mktemp("loewenkopf-pca") / "ds"
    fit_collection(LOEWENKOPF, LOEWENKOPF / "dirs.lp", ["hsh", "rbf", "bilinear"], out)
    quality: dict[str, Any] = json.loads((out / "lanterna.json").read_text())["quality"]
    return quality


@pytest.mark.parametrize("layer", ["rbf", "bilinear"])
def test_pca_bases_beat_hsh9_on_held_out_lights(fitted: dict[str, Any], layer: str) -> None:
    """18 planes (the default; 6 images against HSH9's 9) gain over a dB on the same lights."""
    report, hsh = fitted["models"][layer], fitted["models"]["hsh9"]
    assert report["heldOut"] == hsh["heldOut"] and len(report["heldOut"]) == 24
    assert hsh["meanPsnr"] >= 28.8
    assert report["meanPsnr"] > hsh["meanPsnr"] + 1.0, (report, hsh)


def test_library_report_is_the_stored_one(fitted: dict[str, Any]) -> None:
    files, lights = read_lp(LOEWENKOPF / "dirs.lp", Path(LOEWENKOPF))
    report = leave_one_out(load_stack(files), lights, model_table()["rbf"], band_rows=7)
    assert report == fitted["models"]["rbf"]
