"""The fused normals + leave-one-out pass against the two fits it replaces."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from lanterna.tiler.fit import engine
from lanterna.tiler.fit.bands import normals_band, normals_band_held_out, predict_normals_band
from lanterna.tiler.fit.engine import fit_stream
from lanterna.tiler.fit.normals_held_out_kernel import rank_window_normals_held_out
from tests.python.fixtures.glossy import N, glossy_scene


@pytest.mark.parametrize("held", [np.arange(0, N, 10), np.array([0, 1, N - 1]), np.array([7])])
def test_fused_pass_is_the_fit_and_a_refit_of_the_training_lights(held: np.ndarray) -> None:
    img, lights, _ = glossy_scene()  # ties, shadows, saturation and a black pixel
    train = np.setdiff1d(np.arange(N), held)
    out, sse = normals_band_held_out(img, lights, train, held)
    ref = normals_band(img, lights)
    for k in ("normals", "albedo"):  # the layer: bit for bit the fit without the report
        assert np.array_equal(out[k], ref[k])
    twin = normals_band(np.ascontiguousarray(img[train]), lights[train])
    expected = []
    for i in held:
        diff = predict_normals_band(twin, lights[i]) - img[i]
        expected.append(float(np.sum(diff.astype(np.float64) ** 2)))
    assert np.allclose(sse, expected, rtol=1e-6, atol=1e-9), (sse, expected)
    assert min(expected) > 0


def test_more_lights_than_the_pass_takes_is_refused() -> None:
    lum = np.zeros((65, 4), np.float32)
    with pytest.raises(ValueError, match="at most 64 lights"):
        rank_window_normals_held_out(lum, np.zeros((65, 4, 3), np.float32), np.zeros((65, 3)),
                                     (1, 2), 0.05, np.arange(60), np.arange(60, 65), (1, 2))


def test_the_report_is_the_one_of_the_separate_refit(tmp_path: Path,
                                                     monkeypatch: pytest.MonkeyPatch) -> None:
    img, lights, _ = glossy_scene(seed=2)
    (tmp_path / "a").mkdir()
    (tmp_path / "b").mkdir()
    fused = fit_stream(img, lights, ["normals"], tmp_path / "a", holdout_every=10, band_rows=6)
    monkeypatch.setattr(engine, "MAX_LIGHTS", 0)  # the separate refit and numpy predictions
    apart = fit_stream(img, lights, ["normals"], tmp_path / "b", holdout_every=10, band_rows=6)
    a, b = fused.quality["normals"], apart.quality["normals"]
    assert a["heldOut"] == b["heldOut"] and len(a["psnr"]) == 4
    assert np.allclose(a["psnr"], b["psnr"], atol=1e-4), (a["psnr"], b["psnr"])
    for ga, gb in zip(fused.layers["normals"].groups, apart.layers["normals"].groups,
                      strict=True):
        assert np.array_equal(ga.data.rows(0, img.shape[1]), gb.data.rows(0, img.shape[1]))

