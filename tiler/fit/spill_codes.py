"""PTM/HSH coefficients held to 16 bits per image row until their global range is known.

A linear layer's bytes quantise each coefficient over its term's range in the whole image, so
the fit keeps every coefficient until its last band is solved (:class:`~.sinks.Spill`).  Held
as float32 that is 4 bytes per coefficient (a 2048² HSH9: 453 MB; a gigapixel one: 108 GB of
scratch); here each term's values in one image row are stored as 16-bit codes over that row's
own range,

    code = rint((v − lo) · 65535 / (hi − lo))        v′ = float32(lo + code · (hi − lo) / 65535)

(float64 arithmetic, ``lo``/``hi`` the row's float32 min and max), half the bytes.  A row's
range never exceeds the term's, so ``|v′ − v|`` is at most 1/131070 of the term's range plus a
float32 rounding: 0.002 of one of the layer's 8-bit steps, which moves a byte by one only when
``v`` lies that close to a rounding boundary (tests/python/fit/test_spill_codes.py).  Rows are
whole in every band, so the streamed fit and the in-memory one (:func:`round_trip`) store the
same codes and write the same bytes, whatever their bands.
"""

from __future__ import annotations

import math
import mmap

import numba
import numpy as np
import numpy.typing as npt

from . import compiled  # noqa: F401 - the threading layer, before any kernel runs

#: The largest code: 16 bits.
LEVELS = 65535.0


@numba.njit(cache=True, nogil=True, inline="always")
def row_step(lo: np.float32, hi: np.float32) -> tuple[float, float]:
    """A row's ``(lo, (hi − lo) / 65535)`` in float64: what its codes' values are made of."""
    base = np.float64(lo)
    return base, (np.float64(hi) - base) / LEVELS


@numba.njit(cache=True, nogil=True, inline="always")
def code_value(code: np.uint16, base: float, step: float) -> np.float32:
    """The value ``v′`` of ``code`` in a row of :func:`row_step` ``(base, step)``."""
    return np.float32(base + np.float64(code) * step)


@numba.njit(cache=True, nogil=True, inline="always")
def value_code(v: np.float32, base: float, inv: float) -> np.uint16:
    """The code of ``v`` in a row from ``base`` with ``inv`` = 65535 / (hi − lo) (0 if flat)."""
    return np.uint16(np.rint((np.float64(v) - base) * inv))


#: The low 31 bits of a float32 as int32: its magnitude's bits.
_MAGNITUDE = np.int32(0x7FFFFFFF)


@numba.njit(cache=True, nogil=True, inline="always")
def order_key(bits: np.int32) -> np.int32:
    """A float32's bits (as int32) → an int32 in the floats' order: the bits of a positive
    float, their magnitude's bits flipped for a negative one (−0.0 just below +0.0; a NaN
    beyond ±∞ on its sign's side).  Its own inverse."""
    return np.int32(bits ^ ((bits >> np.int32(31)) & _MAGNITUDE))


@numba.njit(cache=True, nogil=True, inline="always")
def value_range(src: npt.NDArray[np.float32]) -> tuple[np.float32, np.float32]:
    """The min and max of a row's values (a NaN comes back as one of them: callers refuse
    non-finite values).

    Taken over :func:`order_key`'s integers, whose min and max LLVM vectorises: a float
    compare-and-select it keeps scalar (a NaN's order is not a min's), 13× slower
    (docs/fitting.md "Speed, sixteenth pass").  The same values as the floats' own min and
    max, and of a zero's two signs the order's: −0.0 below +0.0."""
    bits = src.view(np.int32)
    lo, hi = np.int32(0x7FFFFFFF), np.int32(-0x80000000)
    for q in range(bits.shape[0]):
        key = order_key(bits[q])
        lo = np.int32(min(lo, key))
        hi = np.int32(max(hi, key))
    return order_key(lo).view(np.float32), order_key(hi).view(np.float32)


@numba.njit(cache=True, nogil=True, inline="always")
def code_row(src: npt.NDArray[np.float32], a: np.float32, z: np.float32,
             dst: npt.NDArray[np.uint16]) -> None:
    """``dst`` = the codes of a row's values ``src`` over its range ``[a, z]``."""
    base = np.float64(a)
    span = np.float64(z) - base
    inv = LEVELS / span if span > 0.0 else 0.0
    for q in range(src.shape[0]):
        dst[q] = value_code(src[q], base, inv)


@numba.njit(cache=True, parallel=True, nogil=True)
def _encode(values: npt.NDArray[np.float32], lo: npt.NDArray[np.float32],
            hi: npt.NDArray[np.float32], codes: npt.NDArray[np.uint16]) -> None:
    k, b, _ = values.shape
    for task in numba.prange(k * b):
        t, y = task // b, task % b
        a, z = value_range(values[t, y])
        lo[t, y], hi[t, y] = a, z
        code_row(values[t, y], a, z, codes[t, y])


@numba.njit(cache=True, parallel=True, nogil=True)
def _decode(codes: npt.NDArray[np.uint16], lo: npt.NDArray[np.float32],
            hi: npt.NDArray[np.float32], out: npt.NDArray[np.float32]) -> None:
    k, b, r = codes.shape
    for task in numba.prange(k * b):
        t, y = task // b, task % b
        src, dst = codes[t, y], out[t, y]
        base, step = row_step(lo[t, y], hi[t, y])
        for q in range(r):
            dst[q] = code_value(src[q], base, step)


def mapped_codes(shape: tuple[int, ...]) -> npt.NDArray[np.uint16]:
    """An uninitialised uint16 array in pages of its own (an anonymous map, unmapped when the
    array is freed): a band's codes are freed while the layer's planes are written, and pages
    given back to the system serve those files' page cache at once, where freed heap (the
    allocator keeps what lies below its top) would leave the cache to take fresh pages.

    In small pages (``MADV_NOHUGEPAGE`` where the system has it): the codes are written once
    and read once, in order, so a huge page's fewer TLB misses gain little, and its first
    touch is what a virtual machine that reports free memory to its host (free page
    reporting, from 2 MB blocks up) makes slow — the block is unbacked and the host backs it
    anew.  Measured on this project's VM: 216 MB mapped a band at a time and touched, after
    a few idle seconds, 0.32–0.46 s with huge pages against 0.10–0.13 s in small ones, which
    come from free lists the host still backs (docs/fitting.md "Speed, sixteenth pass")."""
    size = math.prod(shape) * 2
    if size < mmap.PAGESIZE:
        return np.empty(shape, np.uint16)
    pages = mmap.mmap(-1, size, flags=mmap.MAP_PRIVATE | mmap.MAP_ANONYMOUS)
    if hasattr(mmap, "MADV_NOHUGEPAGE"):
        pages.madvise(mmap.MADV_NOHUGEPAGE)
    return np.frombuffer(pages, np.uint16).reshape(shape)


def encode_rows(values: npt.NDArray[np.float32]
                ) -> tuple[npt.NDArray[np.uint16], npt.NDArray[np.float32],
                           npt.NDArray[np.float32]]:
    """``values (K, rows, R)`` float32 (a term's ``R`` samples of a row, its pixels and
    channels) → their 16-bit codes ``(K, rows, R)`` and each row's ``lo``, ``hi`` ``(K, rows)``."""
    src = np.ascontiguousarray(values, np.float32)
    k, b, r = src.shape
    codes = mapped_codes((k, b, r))
    lo = np.empty((k, b), np.float32)
    hi = np.empty((k, b), np.float32)
    if r:
        _encode(src, lo, hi, codes)
    else:
        lo.fill(0.0)
        hi.fill(0.0)
    return codes, lo, hi


def decode_rows(codes: npt.NDArray[np.uint16], lo: npt.NDArray[np.float32],
                hi: npt.NDArray[np.float32], out: npt.NDArray[np.float32] | None = None
                ) -> npt.NDArray[np.float32]:
    """The float32 values ``v′`` of :func:`encode_rows`' codes (into ``out`` if given)."""
    dst = np.empty(codes.shape, np.float32) if out is None else out
    if codes.size:
        _decode(np.ascontiguousarray(codes), np.ascontiguousarray(lo, np.float32),
                np.ascontiguousarray(hi, np.float32), dst)
    return dst


def round_trip(coeffs: npt.NDArray[np.floating]) -> npt.NDArray[np.float32]:
    """An in-memory fit's coefficients ``(H, W, …, K)`` (terms last, rows first) as the
    streamed fit holds them: each term's row through :func:`encode_rows` and back."""
    km = np.ascontiguousarray(np.moveaxis(np.asarray(coeffs, np.float32), -1, 0))
    flat = km.reshape(km.shape[0], km.shape[1], -1)
    back = decode_rows(*encode_rows(flat))
    return np.moveaxis(back.reshape(km.shape), 0, -1)
