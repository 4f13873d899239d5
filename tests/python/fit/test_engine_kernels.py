"""The optimised fit paths against their references on small stacks: the compiled normals and
Ward kernels against the numpy solvers, and the fused leave-one-out report of the linear models
against a float64 least-squares refit written out here."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from lanterna.tiler.fit import sinks
from lanterna.tiler.fit.bands import LUMINANCE_WEIGHTS, predict_ptm_band, ptm_lrgb_band
from lanterna.tiler.fit.engine import fit_stream
from lanterna.tiler.fit.hsh import hsh_design_matrix
from lanterna.tiler.fit.lrgb_kernel import lrgb_band_held_out_compiled
from lanterna.tiler.fit.normals import solve_normals_band
from lanterna.tiler.fit.ptm import ptm_design_matrix, ptm_pinv
from lanterna.tiler.fit.ward import fit_ward
from lanterna.tiler.formats.ptm_model import ptm_weights
from tests.python.fixtures.glossy import F64, H, N, W, glossy_scene


def test_compiled_normals_equal_the_numpy_rank_window() -> None:
    img, lights, _ = glossy_scene()
    lum = (img @ np.array([0.2125, 0.7154, 0.0721], np.float32)).reshape(N, -1)
    colour = img.reshape(N, -1, 3)
    for window, shadow in (((0.25, 0.9), 0.05), ((0.0, 1.0), 0.0), ((0.5, 0.6), 0.3)):
        ref = solve_normals_band(lum, colour, lights, rank_window=window, shadow=shadow,
                                 iterations=0, compiled=False)
        out = solve_normals_band(lum, colour, lights, rank_window=window, shadow=shadow,
                                 iterations=0)
        for a, b in zip(ref, out, strict=True):  # float32 rounding of another summation order
            assert np.abs(a - b).max() <= 1e-6
        assert not np.array_equal(ref[0][:, 2], np.ones(H * W))  # the fit did something


#: An α grid whose 1/α² never doubles: the kernel computes every lobe.
UNCHAINED = np.geomspace(0.6, 0.03, 24)


@pytest.mark.parametrize(("grid", "lights"), [(None, N), (UNCHAINED, N), (None, N - 3)])
def test_compiled_ward_equals_the_numpy_solve(grid: F64 | None, lights: int) -> None:
    """With the default grid (lobes squared along it), one whose lobes are all computed, and
    lights that fill no whole group of the kernel's."""
    img, lts, normals = glossy_scene()
    img, lts = img[:lights], lts[:lights]
    ref = fit_ward(img, lts, normals, alphas=grid, band_rows=7, compiled=False)
    out = fit_ward(img, lts, normals, alphas=grid, band_rows=7)
    assert np.abs(ref[0] - out[0]).max() <= 1e-5  # kd
    assert np.abs(ref[1] - out[1]).max() <= 1e-5  # ks
    glossy = ref[1].max(axis=-1) >= 1e-3
    assert glossy.mean() > 0.3
    # α: equal wherever it matters (ks > 0); where ks ≈ 0 every α ties and either may win
    assert np.array_equal(ref[2][glossy], out[2][glossy])


def test_compiled_ward_does_not_depend_on_how_pixels_are_grouped() -> None:
    """The kernel solves its pixels in lanes of a fixed count: any band height (so any number
    of pixels, full and partial groups) gives the same bits."""
    img, lights, normals = glossy_scene(seed=9)
    whole = fit_ward(img, lights, normals, band_rows=H)
    for rows in (1, 3, 7):
        for a, b in zip(whole, fit_ward(img, lights, normals, band_rows=rows), strict=True):
            assert np.array_equal(a, b)
    assert whole[1].max() > 0.05  # some pixels are glossy


def test_compiled_ward_reads_float32_normals_as_their_float64_values() -> None:
    """The engine hands the kernel float32 normals as they are (no float64 copy a band): the
    same bits as the float64 normals of the same values, in one band and in several."""
    img, lights, normals = glossy_scene(seed=3)
    n32 = normals.astype(np.float32)
    n64 = n32.astype(np.float64)
    for rows in (H, 5):
        a, b = fit_ward(img, lights, n32, band_rows=rows), fit_ward(img, lights, n64,
                                                                     band_rows=rows)
        assert all(np.array_equal(x, y) for x, y in zip(a, b, strict=True)), rows
    assert a[1].max() > 0.05  # some pixels are glossy


@pytest.mark.parametrize("key", ["ptm", "hsh"])
def test_fused_leave_one_out_equals_a_least_squares_refit(tmp_path: Path, key: str) -> None:
    """PSNR of every held-out light from an independent float64 fit on the training lights."""
    img, lights, _ = glossy_scene(8)
    every = 7
    report = fit_stream(img, lights, [key], tmp_path, holdout_every=every, layers=False,
                        band_rows=6).quality[key]
    held = np.arange(0, N, every)
    train = np.setdiff1d(np.arange(N), held)

    def design(lt: F64) -> F64:
        return ptm_design_matrix(lt) if key == "ptm" else hsh_design_matrix(lt, 9).astype(float)

    coeffs, *_ = np.linalg.lstsq(design(lights[train]), img[train].reshape(len(train), -1)
                                 .astype(np.float64), rcond=None)
    pred = np.clip(design(lights[held]) @ coeffs, 0.0, 1.0)
    mse = ((pred - img[held].reshape(len(held), -1)) ** 2).mean(axis=1)
    expected = [10 * math.log10(1 / m) for m in mse]
    assert report["heldOut"] == held.tolist()
    assert np.allclose(report["psnr"], expected, atol=2e-3), (report["psnr"], expected)


def test_compiled_lrgb_equals_the_numpy_band_fit() -> None:
    img, lights, _ = glossy_scene()
    pinv = ptm_pinv(ptm_design_matrix(lights)).astype(np.float32)
    ref = ptm_lrgb_band(img, pinv, compiled=False)
    out = ptm_lrgb_band(img, pinv)
    assert out["coeffs"].shape == ref["coeffs"].shape == (H, W, 6)
    assert np.abs(ref["coeffs"] - out["coeffs"]).max() <= 1e-6 * np.abs(ref["coeffs"]).max()
    diff = np.abs(ref["rgb"].astype(int) - out["rgb"])
    assert diff.max() <= 1 and np.count_nonzero(diff) <= 0.001 * diff.size
    assert out["rgb"][0, 0].tolist() == [0, 0, 0] and ref["rgb"].max() > 100


def test_spill_on_disk_equals_spill_in_memory(tmp_path: Path,
                                              monkeypatch: pytest.MonkeyPatch) -> None:
    """PTM/HSH coefficients kept in memory (small fits) or spilled to disk (past the budget)
    give the same planes, and the scratch file is gone at the end."""
    img, lights, _ = glossy_scene(3)
    keys = ["ptm", "ptm-lrgb", "hsh"]
    (tmp_path / "memory").mkdir()
    (tmp_path / "disk").mkdir()
    kept = fit_stream(img, lights, keys, tmp_path / "memory", band_rows=6).layers
    monkeypatch.setattr(sinks, "SPILL_MEMORY", 0)
    spilled = fit_stream(img, lights, keys, tmp_path / "disk", band_rows=6).layers
    assert not list((tmp_path / "disk").glob("*.f32"))
    for k in keys:
        a, b = kept[k].channels(), spilled[k].channels()
        assert a.keys() == b.keys() and all(np.array_equal(a[c], b[c]) for c in a)
        assert any(np.ptp(a[c]) > 0 for c in a)


def test_compiled_lrgb_leave_one_out_equals_refit_and_predict(tmp_path: Path) -> None:
    """The LRGB report fitted and predicted per pixel from the band equals the numpy band fit
    on a copy of the training images followed by the PTM prediction."""
    img, lights, _ = glossy_scene(9)
    every = 5
    report = fit_stream(img, lights, ["ptm-lrgb"], tmp_path, holdout_every=every,
                        layers=False, band_rows=7).quality["ptm-lrgb"]
    held = np.arange(0, N, every)
    train = np.setdiff1d(np.arange(N), held)
    fitted = ptm_lrgb_band(img[train], ptm_pinv(ptm_design_matrix(lights[train]))
                           .astype(np.float32), compiled=False)
    expected = []
    for i in held:
        pred = predict_ptm_band(fitted, lights[i]).astype(np.float64)
        expected.append(10 * math.log10(1 / np.mean((pred - img[i]) ** 2)))
    assert report["heldOut"] == held.tolist()
    assert np.allclose(report["psnr"], expected, atol=2e-3), (report["psnr"], expected)


def test_lrgb_pass_reads_8_and_16_bit_samples_as_their_floats() -> None:
    """The table of 8-/16-bit values gives the bits of the division; the layer and the report
    of one pass are those of a pass for each."""
    rng = np.random.default_rng(4)
    _, lights, _ = glossy_scene()
    held = np.arange(0, N, 7)
    train = np.setdiff1d(np.arange(N), held)
    pinv = ptm_pinv(ptm_design_matrix(lights)).astype(np.float32)
    pinv_t = ptm_pinv(ptm_design_matrix(lights[train])).astype(np.float32)
    basis = np.stack([ptm_weights(float(lt[0]), float(lt[1])) for lt in lights[held]])
    loo = (pinv_t, train, held, basis.astype(np.float32))
    for dtype, full in ((np.uint8, 255.0), (np.uint16, 65535.0)):
        ints = rng.integers(0, int(full) + 1, (N, 5, 230, 3)).astype(dtype)
        ints[:, 0, 0] = 0  # a black pixel
        floats = ints.astype(np.float32) / np.float32(full)
        a = lrgb_band_held_out_compiled(ints, pinv, LUMINANCE_WEIGHTS, full, loo)
        b = lrgb_band_held_out_compiled(floats, pinv, LUMINANCE_WEIGHTS, 1.0, loo)
        for x, y in zip(a, b, strict=True):
            assert x.dtype == y.dtype and np.array_equal(x, y)
        layer = lrgb_band_held_out_compiled(ints, pinv, LUMINANCE_WEIGHTS, full)
        report = lrgb_band_held_out_compiled(ints, None, LUMINANCE_WEIGHTS, full, loo)
        assert np.array_equal(layer[0], a[0]) and np.array_equal(layer[1], a[1])
        assert np.array_equal(report[2], a[2]) and report[0].size == 0
        assert a[2].shape == (len(held),) and np.all(a[2] > 0) and np.ptp(a[0]) > 0
