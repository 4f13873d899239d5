"""Fit an LRGB Polynomial Texture Map to a stack of images lit from known directions.

The fit follows HP's ``ptmfit`` (Malzbender et al. 2001): per pixel, the luminance
``Y = 0.2125 R + 0.7154 G + 0.0721 B`` is normalised by its maximum over all lights and
fitted by least squares with the six-term PTM basis ``[lu², lv², lu·lv, lu, lv, 1]``;
the pixel colour is the least-squares factor ``Σ c·Yn / Σ Yn²``.  The design matrix is
the same for every pixel, so its pseudo-inverse is computed once and applied to bands of
rows.
"""

from __future__ import annotations

import numpy as np
import numpy.typing as npt

from lanterna.tiler.formats.ptm_model import Ptm
from lanterna.tiler.inputs.stack import StackReader
from lanterna.tiler.limits import MAX_QUANTISATION

from .bands import LUMINANCE_WEIGHTS, ptm_lrgb_band
from .spill_codes import round_trip

__all__ = ["LUMINANCE_WEIGHTS", "fit_ptm_lrgb", "ptm_design_matrix", "ptm_pinv", "ptm_quantisation",
           "ptm_quantize", "quantize_coefficients"]

#: Default number of image rows processed at once.
DEFAULT_BAND_ROWS = 64


def ptm_design_matrix(lights: npt.ArrayLike) -> npt.NDArray[np.float64]:
    """Return the PTM design matrix for unit light directions.

    Parameters
    ----------
    lights : array_like, shape (N, 3)
        Light directions (x right, y up, z toward the camera).  They are normalised
        here; (lu, lv) are the x and y components of the unit vector.

    Returns
    -------
    ndarray, shape (N, 6)
        Rows ``[lu², lv², lu·lv, lu, lv, 1]``.

    Raises
    ------
    ValueError
        If ``lights`` is not ``(N, 3)``, holds a non-finite value or a zero vector.
    """
    lv = np.asarray(lights, dtype=np.float64)
    if lv.ndim != 2 or lv.shape[1] != 3:
        raise ValueError(f"lights must have shape (N, 3), got {lv.shape}")
    if not np.all(np.isfinite(lv)):
        raise ValueError("lights must be finite")
    norm = np.linalg.norm(lv, axis=1)
    if np.any(norm < 1e-9):
        raise ValueError("lights must not contain zero vectors")
    u = lv[:, 0] / norm
    v = lv[:, 1] / norm
    return np.stack([u * u, v * v, u * v, u, v, np.ones_like(u)], axis=1)


def ptm_pinv(basis: npt.NDArray[np.float64]) -> npt.NDArray[np.float64]:
    """Return the ``(6, N)`` pseudo-inverse of a PTM design matrix (:func:`ptm_design_matrix`).

    Raises
    ------
    ValueError
        If the lights do not determine the six terms (fewer than 6, or rank below 6).
    """
    if basis.shape[0] < 6 or np.linalg.matrix_rank(basis) < 6:
        raise ValueError("the light directions do not determine the 6 PTM terms")
    pinv: npt.NDArray[np.float64] = np.asarray(np.linalg.pinv(basis), np.float64)
    return pinv


def quantize_coefficients(
    coefficients: npt.NDArray[np.floating], *, held: npt.NDArray[np.floating] | None = None,
) -> tuple[npt.NDArray[np.uint8], npt.NDArray[np.float32], npt.NDArray[np.int32]]:
    """Quantise float PTM coefficients to bytes with one scale and bias per coefficient.

    For coefficient k the range ``[lo, hi]`` is its global ``[min, max]`` widened to
    include 0, so the integer bias lands in 0–254 as in real PTM headers.  Then
    ``scale = (hi − lo) / 254``, ``bias = round(−lo / scale)`` and
    ``byte = rint(a / scale + bias)``.  Because the bias is rounded, ``lo/scale + bias``
    lies in [−0.5, 0.5] and ``hi/scale + bias`` in [253.5, 254.5], so no value is
    clipped and ``|(byte − bias)·scale − a| ≤ scale / 2``.

    Parameters
    ----------
    coefficients : ndarray, shape (..., 6)
        Coefficients in 0–255 units.
    held : ndarray, same shape, optional
        The values to quantise, if not the coefficients themselves: the fits pass theirs as a
        streamed fit holds them (:func:`~lanterna.tiler.fit.spill_codes.round_trip`, within
        the range of the coefficients), the range still the exact coefficients'.

    Returns
    -------
    bytes : ndarray of uint8, same shape as ``coefficients``
    scale : ndarray of float32, shape (6,)
    bias : ndarray of int32, shape (6,)

    Raises
    ------
    ValueError
        If the last axis is not 6 long or a value is not finite.
    """
    a = np.asarray(coefficients)
    if a.ndim < 1 or a.shape[-1] != 6:
        raise ValueError(f"coefficients must have shape (..., 6), got {a.shape}")
    flat = a.reshape(-1, 6)
    if flat.shape[0] == 0:
        raise ValueError("coefficients must not be empty")
    if not np.all(np.isfinite(flat)):
        raise ValueError("coefficients must be finite")
    scale, bias = ptm_quantisation(flat.min(axis=0), flat.max(axis=0))
    values = flat if held is None else np.asarray(held).reshape(flat.shape)
    return ptm_quantize(values, scale, bias).reshape(a.shape), scale, bias


def ptm_quantisation(lo: npt.ArrayLike, hi: npt.ArrayLike
                     ) -> tuple[npt.NDArray[np.float32], npt.NDArray[np.int32]]:
    """Return ``(scale, bias)`` per coefficient for the coefficients' global ``lo``/``hi``.

    The range is widened to include 0; see :func:`quantize_coefficients`.
    """
    lo64 = np.minimum(np.asarray(lo, np.float64), 0.0)
    hi64 = np.maximum(np.asarray(hi, np.float64), 0.0)
    span = hi64 - lo64
    scale = np.where(span > 0.0, span / 254.0, 1.0).astype(np.float32)
    if not np.isfinite(scale).all() or np.abs(scale).max() > MAX_QUANTISATION:
        raise ValueError("the fitted coefficients span more than float32 shading can use")
    bias = np.rint(-lo64 / scale.astype(np.float64)).astype(np.int32)
    return scale, bias


def ptm_quantize(values: npt.NDArray[np.floating], scale: npt.NDArray[np.float32],
                 bias: npt.NDArray[np.int32]) -> npt.NDArray[np.uint8]:
    """``rint(a / scale + bias)`` (float32) clipped to bytes (coefficients on the last axis)."""
    q = np.rint(values.astype(np.float32) / scale.astype(np.float32) + bias.astype(np.float32))
    out: npt.NDArray[np.uint8] = np.clip(q, 0, 255).astype(np.uint8)
    return out


def fit_ptm_lrgb(
    images: npt.NDArray[np.generic] | StackReader,
    lights: npt.ArrayLike,
    *,
    band_rows: int = DEFAULT_BAND_ROWS,
) -> Ptm:
    """Fit an LRGB PTM (ptmfit conventions) to images under known light directions.

    Parameters
    ----------
    images : ndarray, shape (N, H, W, 3)
        One RGB image per light, rows top-down; ``uint8`` (0–255) or floating point
        (0–1), or a :class:`~lanterna.tiler.inputs.stack.StackReader` read band by band.
        Values are used as they are (no gamma conversion).
    lights : array_like, shape (N, 3)
        Light directions, x right, y up, z toward the camera; normalised here.
        N must be at least 6 and the lights must determine all six PTM terms.
    band_rows : int, optional
        Rows processed at once; temporaries are ``O(N · band_rows · W)``.  The float
        coefficients of the whole image (24 bytes per pixel) are kept for the
        quantisation, which needs their global range.

    Returns
    -------
    Ptm
        ``colorspace="lrgb"``: luminance coefficients in 0–255 units (L = 255 at the
        brightest light of each pixel), quantised by :func:`quantize_coefficients`, and
        ``rgb = rint(255 · Σ c·Yn / Σ Yn²)`` clipped to 0–255, so that
        ``Ptm.relight`` returns ``rgb/255 · L/255`` ≈ the input images.

    Raises
    ------
    ValueError
        On a bad shape or dtype, fewer than 6 lights, a light count that does not match
        the images, or a degenerate light set (rank of the design matrix below 6).
    """
    if not isinstance(images, (np.ndarray, StackReader)):
        raise ValueError("images must be a numpy array of shape (N, H, W, 3)")
    if images.ndim != 4 or images.shape[3] != 3:
        raise ValueError(f"images must have shape (N, H, W, 3), got {images.shape}")
    n, height, width, _ = images.shape
    if height == 0 or width == 0:
        raise ValueError(f"images must not be empty, got {images.shape}")
    if images.dtype == np.uint8:
        to_unit = 1.0 / 255.0
    elif np.issubdtype(images.dtype, np.floating):
        to_unit = 1.0
    else:
        raise ValueError(f"images must be uint8 or floating point, got {images.dtype}")
    basis = ptm_design_matrix(lights)
    if basis.shape[0] != n:
        raise ValueError(f"got {n} images but {basis.shape[0]} lights")
    if n < 6:
        raise ValueError(f"a PTM needs at least 6 lights, got {n}")
    if band_rows < 1:
        raise ValueError(f"band_rows must be at least 1, got {band_rows}")

    pinv = ptm_pinv(basis).astype(np.float32)  # (6, N), computed once
    coeffs = np.empty((height, width, 6), dtype=np.float32)
    rgb = np.empty((height, width, 3), dtype=np.uint8)
    for r0 in range(0, height, band_rows):
        r1 = min(r0 + band_rows, height)
        band = images[:, r0:r1].astype(np.float32) * np.float32(to_unit)  # (N, h, W, 3)
        out = ptm_lrgb_band(band, pinv)
        coeffs[r0:r1] = out["coeffs"]
        rgb[r0:r1] = out["rgb"]
    q, scale, bias = quantize_coefficients(coeffs, held=round_trip(coeffs))
    return Ptm(colorspace="lrgb", coefficients=q, scale=scale, bias=bias, rgb=rgb)
