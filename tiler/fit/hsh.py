"""Fit an RGB HSH field to images under known lights (least squares, pseudo-inverse once)."""

from __future__ import annotations

import numpy as np
import numpy.typing as npt

from lanterna.tiler.formats.hsh_basis import hsh_weights
from lanterna.tiler.formats.hsh_model import HSH_TERMS, Hsh
from lanterna.tiler.inputs.stack import StackReader
from lanterna.tiler.limits import MAX_QUANTISATION

from .bands import hsh_band
from .spill_codes import round_trip


def hsh_design_matrix(lights: npt.ArrayLike, terms: int) -> npt.NDArray[np.float32]:
    """Return the ``(N, terms)`` HSH basis matrix of unit light directions ``(N, 3)``."""
    lv = np.asarray(lights, dtype=np.float64)
    if lv.ndim != 2 or lv.shape[1] != 3:
        raise ValueError(f"lights must have shape (N, 3), got {lv.shape}")
    lv = lv / np.linalg.norm(lv, axis=1, keepdims=True)
    return np.stack([hsh_weights(float(x), float(y), terms) for x, y, _ in lv])


def hsh_pinv(basis: npt.NDArray[np.floating], terms: int) -> npt.NDArray[np.float32]:
    """Return the ``(terms, N)`` pseudo-inverse (float32) of an HSH design matrix.

    Raises
    ------
    ValueError
        If the lights do not determine ``terms`` terms (too few, or rank too low).
    """
    if basis.shape[0] < terms or np.linalg.matrix_rank(basis) < terms:
        raise ValueError(f"the lights do not determine {terms} HSH terms")
    pinv: npt.NDArray[np.float32] = np.linalg.pinv(basis.astype(np.float64)).astype(np.float32)
    return pinv


def fit_hsh(images: npt.NDArray[np.uint8] | npt.NDArray[np.floating] | StackReader,
            lights: npt.ArrayLike,
            terms: int = 9, *, band_rows: int = 64) -> Hsh:
    """Fit ``terms`` HSH coefficients per pixel and channel, quantised to bytes per term.

    Parameters
    ----------
    images:
        ``(N, H, W, 3)`` uint8 or float in 0–1, or a
        :class:`~lanterna.tiler.inputs.stack.StackReader` read band by band.
    lights:
        ``(N, 3)`` light directions (normalised here).
    terms:
        4, 9 or 16; needs at least ``terms`` lights.

    Returns
    -------
    Hsh
        Bytes ``(H, W, 3, terms)`` with ``a = byte/255·scale + bias``, ``scale = max − min`` and
        ``bias = min`` of each term over all pixels and channels (hshfitter's convention).
    """
    if terms not in HSH_TERMS:
        raise ValueError(f"terms must be 4, 9 or 16, got {terms}")
    stack = images if isinstance(images, StackReader) else np.asarray(images)
    if stack.ndim != 4 or stack.shape[3] != 3:
        raise ValueError(f"images must be (N, H, W, 3), got {stack.shape}")
    basis = hsh_design_matrix(lights, terms)
    if basis.shape[0] != stack.shape[0]:
        raise ValueError(f"{stack.shape[0]} images but {basis.shape[0]} lights")
    pinv = hsh_pinv(basis, terms)  # (terms, N), computed once
    scale_in = np.float32(1 / 255) if stack.dtype == np.uint8 else np.float32(1)
    n, h, w, _ = stack.shape
    coeffs = np.empty((h, w, 3, terms), np.float32)
    for y0 in range(0, h, band_rows):
        band = stack[:, y0:y0 + band_rows].astype(np.float32) * scale_in  # (N, b, W, 3)
        coeffs[y0:y0 + band_rows] = hsh_band(band, pinv)["coeffs"]
    span, lo = hsh_quantisation(coeffs.min(axis=(0, 1, 2)), coeffs.max(axis=(0, 1, 2)))
    return Hsh(hsh_quantize(round_trip(coeffs), span, lo), span, lo)  # as the stream holds them


def hsh_quantisation(lo: npt.ArrayLike, hi: npt.ArrayLike
                     ) -> tuple[npt.NDArray[np.float32], npt.NDArray[np.float32]]:
    """``(scale, bias)`` per term from its global ``lo``/``hi``: ``scale = hi − lo`` (1 if 0)."""
    lo32 = np.asarray(lo, np.float32)
    hi32 = np.asarray(hi, np.float32)
    span = np.where(hi32 > lo32, hi32 - lo32, 1.0).astype(np.float32)
    if not (np.isfinite(span).all() and np.isfinite(lo32).all()) or max(
            np.abs(span).max(), np.abs(lo32 / span).max()) > MAX_QUANTISATION:
        raise ValueError("the fitted coefficients span more than float32 shading can use")
    return span, lo32


def hsh_quantize(coeffs: npt.NDArray[np.floating], scale: npt.NDArray[np.float32],
                 bias: npt.NDArray[np.float32]) -> npt.NDArray[np.uint8]:
    """``rint((a − bias) / scale · 255)`` clipped to bytes (terms on the last axis)."""
    out: npt.NDArray[np.uint8] = np.rint((coeffs - bias) / scale * 255.0).clip(0, 255).astype(
        np.uint8)
    return out
