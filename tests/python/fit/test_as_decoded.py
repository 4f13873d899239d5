"""The photometric kernels read a band as decoded (8-/16-bit, ``band / div`` in 0–1), with the
bytes of the float band they used to be given: luminance, the rank-window normals and their
fused leave-one-out twin, and Ward; and a whole fit streamed from 8-/16-bit files (which takes
that path) reports what the same fit of the loaded float stack reports."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np
import numpy.typing as npt
import pytest

from lanterna.tiler.fit import bands as fb
from lanterna.tiler.fit.engine import fit_stream
from lanterna.tiler.fit.sub_bands import SubBands
from lanterna.tiler.inputs.lp import read_lp
from lanterna.tiler.inputs.stack import StackReader, load_stack, to_unit
from tests.python.fixtures.glossy import glossy_scene
from tests.python.fixtures.photos import write_collection

DEPTHS = [(np.uint8, 255.0), (np.uint16, 65535.0)]


def _decoded(dtype: type, full: float) -> tuple[npt.NDArray[np.generic], npt.NDArray[np.float32],
                                                 npt.NDArray[np.float64]]:
    img, lights, _ = glossy_scene(seed=11)
    raw = np.rint(np.clip(img, 0.0, 1.0) * full).astype(dtype)
    raw[:, 0, 0] = 0  # a black pixel
    raw[:4, 1, :5] = int(full)  # saturated samples
    floats = np.empty(raw.shape, np.float32)
    to_unit(raw, full, floats)
    return raw, floats, lights


def _same(a: npt.NDArray[np.generic], b: npt.NDArray[np.generic]) -> bool:
    return a.dtype == b.dtype and a.tobytes() == b.tobytes()


@pytest.mark.parametrize(("dtype", "full"), DEPTHS)
def test_the_kernels_read_the_decoded_band_as_its_floats(dtype: type, full: float) -> None:
    raw, floats, lights = _decoded(dtype, full)
    assert _same(fb.luminance(raw, full), fb.luminance(floats))
    got, ref = fb.normals_band(raw, lights, div=full), fb.normals_band(floats, lights)
    assert _same(got["normals"], ref["normals"]) and _same(got["albedo"], ref["albedo"])
    held, train = np.arange(0, len(lights), 5), np.setdiff1d(np.arange(len(lights)),
                                                             np.arange(0, len(lights), 5))
    (got, err), (ref, ref_err) = (fb.normals_band_held_out(raw, lights, train, held, full),
                                  fb.normals_band_held_out(floats, lights, train, held))
    assert _same(got["albedo"], ref["albedo"]) and _same(err, ref_err) and err.sum() > 0
    normals = np.asarray(ref["normals"], np.float32)
    got, ref = fb.ward_band(raw, lights, normals, full), fb.ward_band(floats, lights, normals)
    for key in ("kd", "ks", "gloss"):
        assert _same(got[key], ref[key]), key
    assert ref["ks"].max() > 0 and len(np.unique(ref["gloss"])) > 3  # a real specular fit


def test_a_decoded_band_is_refused_where_its_floats_are_needed() -> None:
    raw, _, lights = _decoded(np.uint8, 255.0)
    from lanterna.tiler.fit.normals import solve_normals_band

    lum = fb.luminance(raw, 255.0).reshape(len(lights), -1)
    with pytest.raises(ValueError, match="compiled rank window"):
        solve_normals_band(lum, raw.reshape(len(lights), -1, 3), lights, iterations=2, div=255.0)


@pytest.mark.parametrize("depth", [8, 16])
@pytest.mark.parametrize("sub_rows", [0, 2], ids=["whole-bands", "2-row-pieces"])
@pytest.mark.parametrize(("keys", "report_pixels"), [(["ward"], 200), (["ward"], None),
                                                     (["normals", "ward"], 200)])
def test_a_streamed_fit_reports_what_the_float_stack_reports(
        tmp_path: Path, monkeypatch: pytest.MonkeyPatch, depth: int, sub_rows: int,
        keys: list[str], report_pixels: int | None) -> None:
    # the twin on a sample of the pixels (as decoded), or on every pixel (float sub-bands);
    # pieces of 2 rows as decoded (a budget of their bytes; float pieces of 1 row) are copied
    # out of the decoded band, 7 rows high
    img, lights, _ = glossy_scene(seed=4)
    if sub_rows:
        n, _, w, _ = img.shape
        for name in ("SUB_BAND_BUDGET", "WARD_BAND_BUDGET"):
            monkeypatch.setattr(f"lanterna.tiler.fit.engine.{name}",
                                n * w * 3 * (depth // 8) * sub_rows)
    lp = write_collection(tmp_path / "shots", np.clip(img, 0, 1), lights, depth=depth)
    files, lts = read_lp(lp, lp.parent)
    reader = StackReader(files)
    assert reader.native_dtype() == (np.uint8 if depth == 8 else np.uint16)
    for name in ("streamed", "loaded"):
        (tmp_path / name).mkdir()
    heights: list[int] = []  # the pieces as decoded
    as_decoded = SubBands.as_decoded

    def spy(self: SubBands, band: npt.NDArray[np.generic], div: float, rows: int) -> Any:
        for r0, piece, d in as_decoded(self, band, div, rows):
            heights.append(piece.shape[1])
            yield r0, piece, d
    monkeypatch.setattr(SubBands, "as_decoded", spy)
    runs = [fit_stream(stack, lts, keys, tmp_path / name, holdout_every=5,
                       report_pixels=report_pixels, band_rows=7)
            for stack, name in ((reader, "streamed"), (load_stack(files), "loaded"))]
    if sub_rows and report_pixels is not None:  # the streamed fit's pieces, as decoded
        assert heights and max(heights) == sub_rows
    assert runs[0].quality == runs[1].quality
    for key in keys:
        assert runs[0].quality[key]["meanPsnr"] > 20
