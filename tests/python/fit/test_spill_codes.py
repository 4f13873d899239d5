"""The spill's 16-bit row codes (:mod:`~lanterna.tiler.fit.spill_codes`): the error bound the
module states, the layer bytes they give against the exact floats', and the in-memory round
trip the streamed fit's bytes are compared with."""

from __future__ import annotations

import mmap
from pathlib import Path

import numba
import numpy as np
import numpy.typing as npt
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from lanterna.tiler.fit.hsh import hsh_quantisation, hsh_quantize
from lanterna.tiler.fit.spill_codes import (
    decode_rows,
    encode_rows,
    mapped_codes,
    round_trip,
    value_range,
)


def _values(seed: int, shape: tuple[int, int, int], magnitude: float, offset: float
            ) -> npt.NDArray[np.float32]:
    rng = np.random.default_rng(seed)
    values = (rng.normal(offset, magnitude, shape)).astype(np.float32)
    if shape[1] > 1:
        values[:, 0] = np.float32(offset)  # a flat row: its span is 0
    return values


cases = st.tuples(st.integers(0, 2**32 - 1),
                  st.tuples(st.integers(1, 3), st.integers(1, 5), st.integers(1, 400)),
                  st.sampled_from([1e-6, 0.01, 1.0, 30.0, 1e4]),
                  st.sampled_from([0.0, -2.0, 100.0]))


@settings(max_examples=60, deadline=None)
@given(cases)
def test_a_value_moves_by_at_most_its_rows_span_over_131070(case: tuple) -> None:
    values = _values(*case)
    codes, lo, hi = encode_rows(values)
    assert codes.dtype == np.uint16 and codes.shape == values.shape
    assert np.array_equal(lo, values.min(axis=2)) and np.array_equal(hi, values.max(axis=2))
    back = decode_rows(codes, lo, hi)
    span = (hi.astype(np.float64) - lo)[..., None]
    ulp = np.spacing(np.abs(values)).astype(np.float64)
    err = np.abs(back.astype(np.float64) - values)
    assert np.all(err <= span / 131070 * (1 + 1e-9) + ulp)
    assert np.all(back >= lo[..., None]) and np.all(back <= hi[..., None])  # never past the row
    # a row's ends come back exactly (the layer's range is the exact coefficients')
    assert np.array_equal(back.min(axis=2), lo) and np.array_equal(back.max(axis=2), hi)


@settings(max_examples=40, deadline=None)
@given(cases)
def test_layer_bytes_differ_by_one_only_at_a_rounding_boundary(case: tuple) -> None:
    """HSH's bytes of the codes' values against those of the exact floats: at most one level
    apart, and only where the exact value lies within 0.002 of a step of a rounding
    boundary (the bound above is 255 / 131070 = 0.00195 of a step)."""
    values = _values(*case)
    back = decode_rows(*encode_rows(values))
    scale, bias = hsh_quantisation(values.min(axis=(1, 2)), values.max(axis=(1, 2)))
    s, b = scale[:, None, None], bias[:, None, None]
    exact, coded = hsh_quantize(values, s, b), hsh_quantize(back, s, b)
    moved = exact != coded
    assert np.all(np.abs(exact.astype(int) - coded) <= 1)
    steps = (values.astype(np.float64) - b) / s * 255.0
    boundary = np.abs(steps - np.floor(steps) - 0.5)
    assert np.all(boundary[moved] < 0.0021)


def test_few_bytes_move_in_a_realistic_layer() -> None:
    """Over a million smooth coefficients, the share of bytes one level off is about twice the
    bound (0.4 %), not more."""
    y, x = np.mgrid[0:256, 0:1365].astype(np.float32) / np.float32(256)
    values = np.stack([np.sin(3 * x + y) * 0.8, np.cos(2 * y) * x * 3.0 - 1.0])
    values = values.reshape(2, 256, 1365).astype(np.float32)
    back = decode_rows(*encode_rows(values))
    scale, bias = hsh_quantisation(values.min(axis=(1, 2)), values.max(axis=(1, 2)))
    s, b = scale[:, None, None], bias[:, None, None]
    moved = (hsh_quantize(values, s, b) != hsh_quantize(back, s, b)).mean()
    assert 0 < moved < 0.005


def test_the_in_memory_round_trip_codes_each_terms_rows() -> None:
    """:func:`round_trip` of ``(H, W, C, K)`` coefficients codes term ``k``'s row ``y`` — its W·C
    samples — as the streamed fit codes its band ``(K, rows, W·C)``."""
    coeffs = np.random.default_rng(2).normal(0, 1, (7, 5, 3, 4)).astype(np.float32)
    coeffs[3] *= np.float32(1e-3)  # one row far narrower than its term's range
    km = np.ascontiguousarray(np.moveaxis(coeffs, -1, 0)).reshape(4, 7, 15)
    back = decode_rows(*encode_rows(km)).reshape(4, 7, 5, 3)
    assert np.array_equal(round_trip(coeffs), np.moveaxis(back, 0, -1))
    err = np.abs(round_trip(coeffs) - coeffs)[3].max()
    assert 0 < err <= np.ptp(coeffs[3]) / 131070 * 1.001  # the narrow row's own step


def test_mapped_codes_are_writable_pages_of_their_own() -> None:
    big = mapped_codes((3, 1000, 700))
    big[...] = 7
    assert big.shape == (3, 1000, 700) and big.dtype == np.uint16 and int(big.sum()) == 7 * big.size
    assert big.base is not None  # a map, not the heap
    small = mapped_codes((2, 3))
    small[...] = 1
    assert small.sum() == 6


def _vm_flags(address: int) -> list[str] | None:
    """The ``VmFlags`` of the mapping holding ``address`` (``/proc/self/smaps``), if listed."""
    inside = False
    for line in Path("/proc/self/smaps").read_text().splitlines():
        head = line.split()[0]
        if "-" in head and not head.endswith(":"):
            start, end = (int(part, 16) for part in head.split("-"))
            inside = start <= address < end
        elif inside and head == "VmFlags:":
            return line.split()[1:]
    return None


@pytest.mark.skipif(not Path("/proc/self/smaps").exists() or not hasattr(mmap, "MADV_NOHUGEPAGE"),
                    reason="needs Linux's /proc/self/smaps and MADV_NOHUGEPAGE")
def test_mapped_codes_ask_for_small_pages() -> None:
    """The spill's pages are advised small ('nh'), never huge ('hg'): a huge page's first touch
    on a VM with free page reporting cost 3–4× (the docstring's figures)."""
    codes = mapped_codes((27, 85, 6144))
    flags = _vm_flags(codes.ctypes.data)
    assert flags is not None and "nh" in flags and "hg" not in flags


_SPECIAL = [0.0, -0.0, np.inf, -np.inf, 1e-45, -1e-45, 3.4e38, -3.4e38, 1.0, -1.0]


#: :func:`value_range` called from compiled code, as the kernels call it (compiled once)
_compiled_range = numba.njit(lambda r: value_range(r))


def _row_range(row: npt.NDArray[np.float32]) -> tuple[float, float]:
    lo, hi = _compiled_range(row)
    return float(lo), float(hi)


@settings(max_examples=80, deadline=None)
@given(st.lists(st.one_of(st.floats(width=32, allow_nan=False), st.sampled_from(_SPECIAL)),
                min_size=1, max_size=70))
def test_value_range_is_the_rows_min_and_max(values: list[float]) -> None:
    """The integer-keyed range equals the floats' own, at every length (the vectorised body
    and its remainder), with infinities, denormals and both zeros (−0.0 below +0.0)."""
    row = np.array(values, np.float32)
    lo, hi = _row_range(row)
    assert lo == row.min() and hi == row.max()
    zeros = row[row == 0]
    if lo == 0:
        assert np.signbit(lo) == bool(np.signbit(zeros).any())
    if hi == 0:
        assert np.signbit(hi) == bool(np.signbit(zeros).all())


@settings(max_examples=30, deadline=None)
@given(st.integers(1, 70), st.integers(0, 69), st.booleans())
def test_a_nan_in_a_row_comes_back_in_its_range(n: int, at: int, negative: bool) -> None:
    row = np.linspace(-3, 5, n).astype(np.float32)
    row[at % n] = -np.nan if negative else np.nan
    lo, hi = _row_range(row)
    assert not (np.isfinite(lo) and np.isfinite(hi))
