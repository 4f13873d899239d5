"""Screen-space box filters of the unsharp modes (docs/rendering.md, "Screen-space filters").

The array given is "the canvas": taps outside it are clamped to the nearest edge pixel, and the
filters run on the pair ``(q·a, a)`` with the coverage ``a`` (1 where the layer is drawn), giving
``F(q·a)/F(a)`` (and ``q`` where ``F(a) = 0``).
"""

from __future__ import annotations

import numpy as np
import numpy.typing as npt

from .shading import F32


def box_pass(q: npt.ArrayLike, radius: int) -> F32:
    """One box pass ``B_r``: a horizontal then a vertical ``(2r+1)``-tap mean, taps clamped.

    Parameters
    ----------
    q:
        ``(H, W)`` or ``(H, W, C)`` values.
    radius:
        ``r >= 0``.

    Returns
    -------
    numpy.ndarray
        float32, the shape of ``q``.
    """
    a = np.asarray(q, np.float32)
    if a.ndim not in (2, 3):
        raise ValueError(f"box_pass needs an (H, W) or (H, W, C) array, got {a.shape}")
    if radius < 0:
        raise ValueError(f"radius must be >= 0, got {radius}")
    taps = np.float32(2 * radius + 1)
    for axis in (1, 0):  # horizontal (along x = columns) first, then vertical
        pad = [(0, 0)] * a.ndim
        pad[axis] = (radius, radius)
        p = np.pad(a, pad, mode="edge")
        n = a.shape[axis]
        acc = np.zeros_like(a)
        for k in range(2 * radius + 1):
            acc += np.take(p, np.arange(k, k + n), axis=axis)
        a = (acc / taps).astype(np.float32)
    return a


def box_filter(q: npt.ArrayLike, radius: int, passes: int,
               coverage: npt.ArrayLike | None = None) -> F32:
    """Apply ``(B_r)^passes`` with coverage normalisation: ``F(q·a)/F(a)``, ``q`` where ``F(a)=0``.

    Parameters
    ----------
    q:
        ``(H, W)`` or ``(H, W, C)`` values on the canvas.
    radius, passes:
        Box radius and number of passes (F3: 1, 2; F5: 2, 5).
    coverage:
        ``(H, W)`` coverage ``a`` in 0–1; all ones (the layer covers the canvas) when omitted.
    """
    qa = np.asarray(q, np.float32)
    if coverage is None:
        out = qa
        for _ in range(passes):
            out = box_pass(out, radius)
        return out
    a = np.asarray(coverage, np.float32)
    if a.shape != qa.shape[:2]:
        raise ValueError(f"coverage must be {qa.shape[:2]}, got {a.shape}")
    ab = a[..., None] if qa.ndim == 3 else a
    num, den = qa * ab, a
    for _ in range(passes):
        num, den = box_pass(num, radius), box_pass(den, radius)
    denb = den[..., None] if qa.ndim == 3 else den
    safe = np.where(denb > 0, denb, np.float32(1)).astype(np.float32)
    result: F32 = np.where(denb > 0, num / safe, qa).astype(np.float32)
    return result


def f3(q: npt.ArrayLike, coverage: npt.ArrayLike | None = None) -> F32:
    """``F3 = (B_1)²``: the 3×3 box applied twice (RTIViewer's coefficient unsharp filter)."""
    return box_filter(q, 1, 2, coverage)


def f5(q: npt.ArrayLike, coverage: npt.ArrayLike | None = None) -> F32:
    """``F5 = (B_2)⁵``: the 5×5 box applied five times (RTIViewer's luminance/normal filter)."""
    return box_filter(q, 2, 5, coverage)


def unsharp(q: npt.ArrayLike, blurred: npt.ArrayLike, gain: float) -> F32:
    """``q + g·(q − blurred)``."""
    qa = np.asarray(q, np.float32)
    out: F32 = (qa + np.float32(gain) * (qa - np.asarray(blurred, np.float32))).astype(np.float32)
    return out
