"""Lambert + isotropic Ward fit on a synthetic object rendered by the test (known kd, ks, α, n)."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import numpy.typing as npt
import pytest

from lanterna.cli import main
from lanterna.tiler.fit import bands as fit_bands
from lanterna.tiler.fit import ward_solve
from lanterna.tiler.fit.models import leave_one_out, model_table, psnr
from lanterna.tiler.fit.ward import GLOSS_LIMITS, alpha_grid, fit_ward, predict_ward, quantize_ward
from tests.python.fixtures.photos import spiral_lights, write_collection

H, W, N = 24, 32, 60


def _lights(n: int = N) -> npt.NDArray[np.float64]:
    """``n`` spiral lights, elevation 15°–85°."""
    return spiral_lights(n, (15.0, 85.0))


def _object() -> dict[str, npt.NDArray[np.float64]]:
    """Gentle bumps (slopes ≤ ~20°); kd per pixel; ks = 0 on the left third; α in 0.15–0.45."""
    rng = np.random.default_rng(11)
    y, x = np.mgrid[0:H, 0:W].astype(np.float64)
    g = np.stack([-0.3 * np.cos(x / 5.0), 0.25 * np.sin(y / 4.0), np.ones_like(x)], axis=-1)
    normals = g / np.linalg.norm(g, axis=-1, keepdims=True)
    kd = rng.uniform(0.15, 0.55, (H, W, 3))
    ks = rng.uniform(0.04, 0.12, (H, W, 1)) * np.array([1.0, 0.9, 0.8])
    ks[:, : W // 3] = 0.0
    alpha = rng.uniform(0.15, 0.45, (H, W))
    return {"normals": normals, "kd": kd, "ks": ks, "alpha": alpha}


def _render(obj: dict[str, npt.NDArray[np.float64]],
            lights: npt.NDArray[np.float64]) -> npt.NDArray[np.float32]:
    """docs/rendering.md svbrdf radiance, written out independently of the fitter."""
    n = obj["normals"]
    out = []
    for light in lights:
        half = light + np.array([0.0, 0.0, 1.0])
        half /= np.linalg.norm(half)
        cosi = np.maximum(n @ light, 0.0)
        cosr = np.maximum(n[..., 2], 1e-4)
        nh = np.maximum(n @ half, 1e-4)
        tan2 = (1 - nh**2) / nh**2
        a2 = obj["alpha"] ** 2
        spec = np.exp(-tan2 / a2) * np.sqrt(cosi / cosr) / (4 * a2)
        out.append(obj["kd"] * cosi[..., None] + obj["ks"] * spec[..., None])
    return np.clip(np.array(out), 0.0, 1.0).astype(np.float32)


def test_grid_is_log_spaced_and_doubles_one_over_alpha_squared() -> None:
    grid = alpha_grid()
    lo, hi = GLOSS_LIMITS
    assert grid[-1] == lo and grid[0] >= hi and grid[1] < hi  # widest first, covers the limits
    assert np.all(np.diff(grid) < 0) and np.all(np.abs(np.diff(np.log(grid))) < 0.2)
    # every second step halves α²: the coarse pass runs along those, squaring each lobe for
    # the next (exp(−2x) = exp(−x)²)
    assert np.allclose(grid[2:] ** 2 * 2, grid[:-2] ** 2, rtol=1e-12, atol=0)
    stride, coarse = ward_solve.coarse_steps(grid)
    assert stride == 2 and coarse[0] == 0 and coarse[-1] == len(grid) - 1
    assert np.array_equal(np.diff(coarse), np.full(len(coarse) - 1, 2))


def test_coarse_steps_keep_both_ends_and_a_grid_that_never_doubles() -> None:
    stride, coarse = ward_solve.coarse_steps(alpha_grid(per_octave=6))  # 27 α, doubling every 3
    assert stride == 3 and list(coarse) == [*range(0, 27, 3), 26]
    stride, coarse = ward_solve.coarse_steps(np.geomspace(0.6, 0.03, 24))
    assert stride == 1 and np.array_equal(coarse, np.arange(24))  # every α, in one pass


@pytest.mark.parametrize("per_octave", [4, 6])
def test_coarse_to_fine_search_finds_the_whole_grids_alpha(
        per_octave: int, monkeypatch: pytest.MonkeyPatch) -> None:
    """On a glossy object (60 lights, each pixel's SSE over the grid falling to one minimum,
    lopsided or cut short by the lobe test), the coarse pass and its fine one find the α a
    search of every grid value finds, so the same kd and ks."""
    obj, lights = _object(), _lights()
    images = _render(obj, lights)
    grid = alpha_grid(per_octave=per_octave)
    fast = fit_ward(images, lights, obj["normals"], alphas=grid, compiled=False)
    with monkeypatch.context() as m:  # every grid value in one pass
        m.setattr(ward_solve, "coarse_steps", lambda g: (1, np.arange(len(g))))
        whole = fit_ward(images, lights, obj["normals"], alphas=grid, compiled=False)
    glossy = whole[1].max(axis=-1) > 1e-3
    assert glossy.mean() > 0.5
    assert np.array_equal(fast[2][glossy], whole[2][glossy])
    assert np.abs(fast[0] - whole[0]).max() <= 1e-6 and np.abs(fast[1] - whole[1]).max() <= 1e-6
    # and the compiled search is the same search
    assert np.array_equal(fit_ward(images, lights, obj["normals"], alphas=grid)[2][glossy],
                          fast[2][glossy])


@pytest.mark.parametrize("compiled", [True, False])
def test_alpha_is_a_gloss_level_and_the_maps_are_solved_there(compiled: bool) -> None:
    """The best α is stored as a gloss level, and kd, ks are those a fit at that one α gives."""
    obj, lights = _object(), _lights()
    images = _render(obj, lights)
    kd, ks, alpha = fit_ward(images, lights, obj["normals"], compiled=compiled)
    lo, hi = GLOSS_LIMITS
    levels = (alpha.astype(np.float64) - lo) / (hi - lo) * 255
    assert np.allclose(levels, np.round(levels), atol=1e-3)
    glossy = ks.max(axis=-1) > 0
    assert glossy.mean() > 0.5
    values = np.unique(alpha[glossy])
    assert len(values) > 5 and not np.isin(values, alpha_grid().astype(np.float32)).all()
    for value in values:
        at = glossy & (alpha == value)
        one = fit_ward(images, lights, obj["normals"], alphas=np.array([float(value)]),
                       compiled=compiled)
        assert np.abs(one[0][at] - kd[at]).max() <= 1e-5
        assert np.abs(one[1][at] - ks[at]).max() <= 1e-5


def test_known_material_recovered_with_true_normals() -> None:
    obj, lights = _object(), _lights()
    kd, ks, alpha = fit_ward(_render(obj, lights), lights, obj["normals"], band_rows=7)
    assert kd.shape == ks.shape == (H, W, 3) and alpha.shape == (H, W)
    assert np.abs(kd - obj["kd"]).max() <= 0.02
    glossy = obj["ks"][..., 0] > 0
    # α comes from a grid (19 % steps) and the lobe's peak is ks/(4α²), so ks follows α²
    assert np.max(np.abs(ks - obj["ks"])[glossy] / obj["ks"][glossy]) <= 0.3
    rel = np.abs(alpha[glossy] - obj["alpha"][glossy]) / obj["alpha"][glossy]
    assert rel.max() <= 0.15 and np.median(rel) <= 0.05
    assert np.all(ks[~glossy] <= 0.005)  # diffuse pixels stay diffuse


def test_quantised_maps_reproduce_the_renders() -> None:
    """With the true normals, the stored uint8 maps predict every light within 8-bit error."""
    obj, lights = _object(), _lights()
    images = _render(obj, lights)
    model = quantize_ward(obj["normals"], *fit_ward(images, lights, obj["normals"]))
    assert model.kd.dtype == model.ks.dtype == model.gloss.dtype == np.uint8
    scores = [psnr(predict_ward(model, light), image) for light, image in zip(lights, images,
                                                                              strict=True)]
    assert min(scores) >= 38.0


def test_leave_one_out_beats_lambert_with_fitted_normals() -> None:
    """End to end (robust photometric-stereo normals, then Ward): better than Lambert alone.

    The broad lobes bias the fitted normals, which bounds this figure (about 29 dB here).
    """
    obj, lights = _object(), _lights()
    images = _render(obj, lights)
    table = model_table(9)
    ward = leave_one_out(images, lights, table["ward"])
    lambert = leave_one_out(images, lights, table["normals"])
    assert ward["heldOut"] == [0, 10, 20, 30, 40, 50]
    assert ward["meanPsnr"] >= 28.0 and ward["meanPsnr"] >= lambert["meanPsnr"] + 1.5, (ward,
                                                                                       lambert)


def test_fallbacks_clamp_kd_and_drop_negative_ks() -> None:
    lights = _lights()
    normals = np.tile([0.0, 0.0, 1.0], (2, 2, 1))
    images = np.zeros((N, 2, 2, 3), np.float32)
    images[..., 0] = 0.4 * lights[:, 2, None, None]  # pure Lambert, red only
    images[:, 0, 0, 1] = 0.3 - 0.2 * lights[:, 2]  # brighter at grazing light: no valid ks
    kd, ks, _ = fit_ward(images, lights, normals)
    assert np.all(kd >= 0) and np.all(ks >= 0) and np.all(ks <= 1)
    assert np.allclose(kd[..., 0], 0.4, atol=1e-3) and np.allclose(ks[..., 0], 0.0, atol=1e-6)


def test_cli_ward_shares_one_normal_map_with_normals(tmp_path: Path,
                                                      monkeypatch: pytest.MonkeyPatch) -> None:
    calls = []
    real = fit_bands.normals_band
    monkeypatch.setattr(fit_bands, "normals_band",
                        lambda *a, **k: calls.append(1) or real(*a, **k))
    lights = _lights()
    lp = write_collection(tmp_path / "shots", _render(_object(), lights), lights, depth=16)
    out = tmp_path / "ds"
    assert main(["fit", str(tmp_path / "shots"), "--lp", str(lp), "--model", "normals",
                 "--model", "ward", "-o", str(out)]) == 0
    # one pass, one band (24 rows): the normals are solved once for the layers and once for the
    # leave-one-out fit, each shared by both models
    assert len(calls) == 2
    desc = json.loads((out / "lanterna.json").read_text())
    layers = {layer["id"]: layer for layer in desc["layers"]}
    assert list(layers) == ["normals", "ward"]
    ward = layers["ward"]["service"]
    assert ward["layerType"] == "svbrdf"
    assert ward["glossLimits"] == list(GLOSS_LIMITS) and ward["inputColorSpace"] == "display"
    assert [p["channels"][0] for p in ward["planes"]] == ["NX", "KD_R", "KS_R", "GLOSS"]
    # one normal map, referenced by both layers
    normals_plane = layers["normals"]["service"]["planes"][0]["service"]["id"]
    assert ward["planes"][0]["service"]["id"] == normals_plane
    assert desc["quality"]["models"]["ward"]["meanPsnr"] >= 28.0
