"""The photometric models' leave-one-out twin fitted on a pseudo-random share of the pixels:
which pixels, and that the report is exactly the one of those pixels fitted alone."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from lanterna.tiler.fit import held_out
from lanterna.tiler.fit.engine import fit_stream
from lanterna.tiler.fit.held_out import report_sample
from tests.python.fixtures.glossy import H, W, glossy_scene


def test_the_sample_is_fixed_by_the_pixel_alone() -> None:
    whole = report_sample(0, 300, 257, 0.1)
    split = np.vstack([report_sample(0, 37, 257, 0.1), report_sample(37, 1, 257, 0.1),
                       report_sample(38, 262, 257, 0.1)])
    assert np.array_equal(whole, split)
    assert np.array_equal(report_sample(0, 300, 257, 1.0), np.ones((300, 257), bool))
    assert not report_sample(0, 300, 257, 0.0).any()


@pytest.mark.parametrize("share", [1 / 4, 1 / 16, 1 / 64])
def test_the_sample_is_the_share_asked_for_and_no_lattice(share: float) -> None:
    mask = report_sample(0, 512, 512, share)
    expected = mask.size * share
    assert abs(mask.sum() - expected) <= 4 * np.sqrt(expected * (1 - share))  # binomial, 4σ
    ys, xs = np.nonzero(mask)
    for coord in (ys, xs):  # every residue modulo 2–8 about equally often: no period
        for period in range(2, 9):
            counts = np.bincount(coord % period, minlength=period)
            assert counts.min() >= 0.75 * len(coord) / period, (period, counts)
    # neighbours are not chosen together more (or less) often than apart
    both = np.count_nonzero(mask[:, 1:] & mask[:, :-1]) / mask[:, :-1].size
    assert abs(both - share * share) <= 0.5 * share * share + 5e-4


def _report(tmp: Path, img: np.ndarray, lights: np.ndarray, **kw: object) -> dict:
    tmp.mkdir()
    quality: dict = fit_stream(img, lights, ["ptm", "normals", "ward"], tmp, holdout_every=7,
                               **kw).quality  # type: ignore[arg-type]
    return quality


def test_the_sampled_report_is_the_report_of_those_pixels(tmp_path: Path) -> None:
    img, lights, _ = glossy_scene(seed=3)
    limit = H * W // 4
    mask = report_sample(0, H, W, limit / (H * W))
    sampled = _report(tmp_path / "s", img, lights, report_pixels=limit, band_rows=3)
    exact = _report(tmp_path / "e", img, lights, report_pixels=0)
    alone = _report(tmp_path / "a", np.ascontiguousarray(img[:, mask][:, None]), lights,
                    report_pixels=0)
    assert 0.15 * H * W < mask.sum() < 0.35 * H * W
    for k in ("normals", "ward"):
        assert sampled[k]["pixels"] == alone[k]["pixels"] == mask.sum()
        assert exact[k]["pixels"] == H * W
        assert np.allclose(sampled[k]["psnr"], alone[k]["psnr"], atol=2e-3), k
        assert sampled[k]["psnr"] != exact[k]["psnr"]  # another set of pixels …
        assert abs(sampled[k]["meanPsnr"] - exact[k]["meanPsnr"]) < 1.5  # … of the same object
    # the linear models' reports are exact whatever the limit
    assert sampled["ptm"] == exact["ptm"] and sampled["ptm"]["pixels"] == H * W
    # and the sample does not depend on how the rows are banded
    assert _report(tmp_path / "b", img, lights, report_pixels=limit, band_rows=7) == sampled


def test_small_images_keep_the_exact_report(tmp_path: Path,
                                            monkeypatch: pytest.MonkeyPatch) -> None:
    img, lights, _ = glossy_scene(seed=4)
    default = _report(tmp_path / "d", img, lights)
    assert default == _report(tmp_path / "e", img, lights, report_pixels=0)
    monkeypatch.setattr(held_out, "REPORT_PIXELS", 100)
    assert _report(tmp_path / "m", img, lights)["ward"]["pixels"] < H * W / 2


def test_compiled_sample_indices_are_the_sample() -> None:
    from lanterna.tiler.fit.sample_kernel import report_indices

    for y0, rows, width, share in [(0, 300, 257, 0.1), (37, 1, 257, 0.1), (5000, 85, 2048, 1 / 64),
                                   (0, 40, 40, 1.0), (3, 40, 40, 0.0)]:
        mask = report_sample(y0, rows, width, share)
        got = report_indices(y0, rows, width, share)
        assert np.array_equal(got, np.flatnonzero(mask)), (y0, rows, width, share)


def test_the_sampled_twin_fitted_in_batches_gives_the_same_report(
        tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """A local pass fits the sampled twin's pixels in batches of several bands (the last one at
    the end of the pass), a Dask worker band by band: every batch size gives the same report
    over the same pixels."""
    from lanterna.tiler.fit import engine

    img, lights, _ = glossy_scene(seed=5)
    limit = H * W // 4
    reports = {}
    for batch in (None, 0, 50, 10**9):
        if batch is not None:
            monkeypatch.setattr(engine, "_twin_batch", lambda n, width, b=batch: b)
        reports[batch] = _report(tmp_path / f"b{batch}", img, lights, report_pixels=limit,
                                 band_rows=3)
    count = int(report_sample(0, H, W, limit / (H * W)).sum())
    for k in ("normals", "ward"):
        for batch, quality in reports.items():
            assert quality[k]["pixels"] == count, (k, batch)
            assert np.allclose(quality[k]["psnr"], reports[0][k]["psnr"], atol=2e-3), (k, batch)


def test_the_twin_store_keeps_its_pixels_in_order_as_it_grows() -> None:
    """The sampled twin's pixels kept between bands: the filled part is every band's pixels
    in order, whatever the room it was made with (too small: it grows), and a batch fitted
    (``count = 0``) starts it again."""
    from lanterna.tiler.fit.held_out import TwinStore

    rng = np.random.default_rng(2)
    pieces = [rng.random((5, k, 3), dtype=np.float32) for k in (3, 0, 9, 1, 40, 2)]
    for room in (0, 4, 100):
        store = TwinStore()
        for i, piece in enumerate(pieces):
            store.add(piece, room)
            assert np.array_equal(store.pixels, np.concatenate(pieces[:i + 1], axis=1)), room
        store.count = 0
        store.add(pieces[2], room)
        assert np.array_equal(store.pixels, pieces[2])
