"""The linear models' compiled band pass (:mod:`~lanterna.tiler.fit.linear_kernel`): coefficients
against a float64 product of the same samples, their range, the held-out errors, and the same
bits whatever the samples' storage and the chunking."""

from __future__ import annotations

import numpy as np
import pytest

from lanterna.tiler.fit.linear_kernel import linear_band


def _case(n: int, s: int, k: int, seed: int = 0
          ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    rng = np.random.default_rng(seed)
    band = rng.integers(0, 256, (n, s)).astype(np.uint8)
    band[:, :3] = [0, 255, 128]  # both ends of the range in every light
    rows = rng.normal(0.0, 40.0, (k, n)).astype(np.float32)
    held_rows = rng.normal(0.0, 0.3, (3, n)).astype(np.float32)
    return band, rows, held_rows


@pytest.mark.parametrize(("n", "s", "k"), [(24, 5000, 6), (7, 1025, 9), (3, 3, 1), (50, 4096, 18)])
def test_coefficients_and_range_match_a_float64_product(n: int, s: int, k: int) -> None:
    band, rows, _ = _case(n, s, k)
    out = np.full((k, s), np.nan, np.float32)
    lo, hi, sse = linear_band(band, 255.0, rows, out)
    x = band.astype(np.float32) / np.float32(255.0)  # the float band's values
    ref = rows.astype(np.float64) @ x.astype(np.float64)
    bound = 1e-6 * (np.abs(rows).astype(np.float64) @ x.astype(np.float64)) + 1e-6
    assert np.all(np.abs(out - ref) <= bound)
    assert np.array_equal(lo, out.min(axis=1)) and np.array_equal(hi, out.max(axis=1))
    assert sse.shape == (0,)


def test_held_out_errors_match_numpy() -> None:
    band, rows, held_rows = _case(24, 3001, 6, seed=1)
    held = np.array([0, 10, 20])
    out = np.empty((6, 3001), np.float32)
    _, _, sse = linear_band(band, 255.0, rows, out, held_rows=held_rows, held=held)
    x = band.astype(np.float32) / np.float32(255.0)
    pred = np.clip(held_rows.astype(np.float64) @ x.astype(np.float64), 0.0, 1.0)
    ref = ((pred - x[held]) ** 2).sum(axis=1)
    assert sse.shape == (3,) and np.all(sse > 0)
    np.testing.assert_allclose(sse, ref, rtol=1e-5)
    # the report without coefficients (a run with no layers): the same errors
    _, _, alone = linear_band(band, 255.0, np.zeros((0, 24), np.float32),
                              np.empty((0, 3001), np.float32), held_rows=held_rows, held=held)
    assert np.array_equal(alone, sse)


def test_same_bits_for_8_bit_16_bit_and_float_samples_and_any_chunking() -> None:
    band, rows, _ = _case(24, 7000, 9, seed=2)
    out8 = np.empty((9, 7000), np.float32)
    linear_band(band, 255.0, rows, out8)
    as16 = band.astype(np.uint16) * np.uint16(257)  # 255 → 65535: the same fractions
    out16 = np.empty_like(out8)
    linear_band(as16, 65535.0, rows, out16)
    floats = band.astype(np.float32) / np.float32(255.0)
    outf = np.empty_like(out8)
    linear_band(floats, 1.0, rows, outf)
    assert np.array_equal(out8.view(np.uint32), outf.view(np.uint32))
    assert np.array_equal(out16.view(np.uint32), outf.view(np.uint32))
    # two bands written at their offsets of one spill: the bits of one pass over all of it
    spill = np.empty((9, 7000), np.float32)
    linear_band(np.ascontiguousarray(band[:, :2999]), 255.0, rows, spill, at=0)
    linear_band(np.ascontiguousarray(band[:, 2999:]), 255.0, rows, spill, at=2999)
    assert np.array_equal(spill.view(np.uint32), out8.view(np.uint32))


def test_a_non_finite_sample_shows_in_the_range() -> None:
    band = np.full((4, 3000), 0.5, np.float32)
    band[2, 2500] = np.nan
    lo, hi, _ = linear_band(band, 1.0, np.ones((2, 4), np.float32), np.empty((2, 3000), np.float32))
    assert not np.any(np.isfinite(lo) & np.isfinite(hi))  # every term's range says so


def test_no_samples() -> None:
    lo, hi, sse = linear_band(np.zeros((5, 0), np.uint8), 255.0, np.ones((2, 5), np.float32),
                              np.empty((2, 0), np.float32))
    assert lo.shape == hi.shape == (2,) and sse.shape == (0,)


@pytest.mark.parametrize(("n", "b", "width", "k"), [(24, 5, 2049, 9), (7, 3, 4, 6), (9, 3, 1, 1)])
def test_coded_band_is_the_band_coded_per_row(n: int, b: int, width: int, k: int) -> None:
    """:func:`linear_band_coded` — the streamed fit's pass — stores the codes
    :func:`~lanterna.tiler.fit.spill_codes.encode_rows` makes of :func:`linear_band`'s
    coefficients (the same float32 sums, rows of several chunks), with the same errors."""
    from lanterna.tiler.fit.linear_kernel import linear_band_coded
    from lanterna.tiler.fit.spill_codes import encode_rows

    band, rows, held_rows = _case(n, b * width, k, seed=4)
    held = np.array([0, n // 2, n - 1])
    out = np.empty((k, b * width), np.float32)
    lo, hi, sse = linear_band(band, 255.0, rows, out, held_rows=held_rows, held=held)
    codes, row_lo, row_hi, coded_sse = linear_band_coded(band, 255.0, rows, width,
                                                         held_rows=held_rows, held=held)
    ref_codes, ref_lo, ref_hi = encode_rows(out.reshape(k, b, width))
    assert codes.shape == (k, b, width)
    assert np.array_equal(codes, ref_codes)
    assert np.array_equal(row_lo, ref_lo) and np.array_equal(row_hi, ref_hi)
    assert np.array_equal(row_lo.min(axis=1), lo) and np.array_equal(row_hi.max(axis=1), hi)
    np.testing.assert_allclose(coded_sse, sse, rtol=1e-12)
    wide = row_hi > row_lo  # each row's codes run 0–65535; a flat row's (one pixel) are 0
    assert np.array_equal(codes.min(axis=2), np.zeros_like(row_lo, np.uint16))
    assert np.array_equal(codes.max(axis=2), np.where(wide, 65535, 0))
