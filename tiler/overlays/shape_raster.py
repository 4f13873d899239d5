"""Rasterise annotation shapes (:mod:`.shapes`) into an RGBA patch at a level; pure numpy.

The rule (docs/annotations.md, "Individual annotations (W3C)"):

- The patch covers the shapes' bounding box grown by half the widest outline, rounded outward
  to whole canvas pixels and clipped to the canvas (:func:`patch_rectangle`); at level ``L`` it
  is the rectangle's destination ``floor(X/2^L) … ceil((X+W)/2^L)`` (docs/annotations.md,
  "Building"), so the PNG is exactly the size a patch of that name is drawn at.
- **Coverage** of a pixel = the fraction of its :data:`SAMPLES` × :data:`SAMPLES` samples that are
  inside, the samples at the centres of an even grid (level pixel ``i`` covers ``[i, i+1)``; its
  samples sit at ``i + (k + ½)/N``). Inside: non-zero winding (SVG's default), or even-odd for
  ``fill-rule="evenodd"``. Edges are half-open in y, so a shared edge is counted once.
- **Outline**: the union of a rectangle of the outline's width around every segment and a disc
  (a 16-gon) at every vertex (round joins and caps), filled non-zero; width ``stroke-width``
  (canvas pixels) scaled to the level, at least :data:`MIN_STROKE` level pixels, and
  :data:`DEFAULT_STROKE` level pixels when the SVG gives none (``stroke-width: 0`` or
  ``stroke: none``: no outline). Open polylines get only the outline.
- Each shape, in document order: its fill (colour at ``fill-opacity × coverage``), then its
  outline (opaque colour × coverage), source-over in float on premultiplied colour, rounded
  once as the overlay levels are (``round(a·255)``, ``round(c/a·255)``, colour 0 where a = 0).
"""

from __future__ import annotations

import math

import numpy as np
import numpy.typing as npt

from .geometry import Patch, destination
from .shapes import Ring, Shape, ShapeError, bbox

#: Samples per pixel side (N × N per pixel).
SAMPLES = 4
#: Outline width (level pixels) when the SVG gives none, and the thinnest one drawn.
DEFAULT_STROKE = 2.0
MIN_STROKE = 1.0
_DISC_SIDES = 16
#: Sample rows × edges (and × columns) processed at once: bounds the memory of a band.
_BAND_CELLS = 1 << 22


def stroke_width(shape: Shape, level: int) -> float:
    """The outline's width of ``shape`` in level pixels (0 when it has none)."""
    style = shape.style
    if style.stroke is None or style.stroke_width == 0:
        return 0.0
    if style.stroke_width is None:
        return DEFAULT_STROKE
    return max(MIN_STROKE, style.stroke_width / (1 << level))


def patch_rectangle(shapes: list[Shape], level: int, width: int,
                    height: int) -> tuple[int, int, int, int]:
    """The patch rectangle ``(x, y, w, h)`` (canvas pixels) that holds ``shapes`` drawn at
    ``level``, clipped to the ``width`` × ``height`` canvas; a ShapeError when it misses it."""
    x0, y0, x1, y1 = bbox(shapes)
    half = max(stroke_width(s, level) for s in shapes) * (1 << level) / 2
    left, top = max(0, math.floor(x0 - half)), max(0, math.floor(y0 - half))
    right, bottom = min(width, math.ceil(x1 + half)), min(height, math.ceil(y1 + half))
    if right <= left or bottom <= top:
        raise ShapeError(f"the shape ({x0:g},{y0:g} to {x1:g},{y1:g}) is outside the "
                         f"{width}x{height} canvas")
    return left, top, right - left, bottom - top


def rasterise(shapes: list[Shape], level: int,
              rect: tuple[int, int, int, int]) -> npt.NDArray[np.uint8]:
    """Draw ``shapes`` into the RGBA patch of rectangle ``rect`` (canvas px) at ``level``."""
    dest = destination(Patch(level, *rect, order=0, info="", file=""))
    acc = np.zeros((dest[3] - dest[1], dest[2] - dest[0], 4), np.float64)
    for shape in shapes:
        style = shape.style
        if style.fill is not None and shape.rings and style.fill_opacity > 0:
            _over(acc, coverage(shape.rings, level, dest, evenodd=style.evenodd)
                  * style.fill_opacity, style.fill)
        width = stroke_width(shape, level)
        if width > 0 and style.stroke is not None:
            outline = outline_rings(shape, width * (1 << level) / 2)
            _over(acc, coverage(outline, level, dest, evenodd=False), style.stroke)
    return _round(acc)


def coverage(rings: tuple[Ring, ...] | list[Ring], level: int, dest: tuple[int, int, int, int],
             *, evenodd: bool, samples: int = SAMPLES) -> npt.NDArray[np.float64]:
    """The fraction of each level pixel of ``dest`` (x0, y0, x1, y1 at ``level``) inside the
    closed ``rings`` (canvas px), from ``samples`` × ``samples`` samples per pixel."""
    x0, y0, x1, y1 = dest
    wl, hl = x1 - x0, y1 - y0
    n, f = samples, float(1 << level)
    out = np.zeros((hl, wl), np.float64)
    edges = [np.asarray(r, np.float64) for r in rings if len(r) >= 2]
    if not edges or wl <= 0 or hl <= 0:
        return out
    a = np.concatenate(edges)
    b = np.concatenate([np.roll(e, -1, axis=0) for e in edges])
    # to sample units: sample (c, r) sits at (c, r)
    ax, ay = (a[:, 0] / f - x0) * n - 0.5, (a[:, 1] / f - y0) * n - 0.5
    bx, by = (b[:, 0] / f - x0) * n - 0.5, (b[:, 1] / f - y0) * n - 0.5
    keep = ay != by
    ax, ay, bx, by = ax[keep], ay[keep], bx[keep], by[keep]
    if ax.size == 0:
        return out
    low, high = np.minimum(ay, by), np.maximum(ay, by)
    slope = (bx - ax) / (by - ay)
    weight = np.ones_like(ay) if evenodd else np.where(by > ay, 1.0, -1.0)
    rows, cols = hl * n, wl * n
    band = max(1, min(_BAND_CELLS // ax.size, _BAND_CELLS // (cols + 1))) // n * n or n
    for r0 in range(0, rows, band):
        r1 = min(rows, r0 + band)
        ys = np.arange(r0, r1, dtype=np.float64)
        hit_r, hit_e = np.nonzero((low[None, :] <= ys[:, None]) & (ys[:, None] < high[None, :]))
        xs = ax[hit_e] + (ys[hit_r] - ay[hit_e]) * slope[hit_e]
        col = np.clip(np.floor(xs).astype(np.int64) + 1, 0, cols)  # flips samples c > x
        diff = np.bincount(hit_r * (cols + 1) + col, weights=weight[hit_e],
                           minlength=(r1 - r0) * (cols + 1)).reshape(r1 - r0, cols + 1)
        wind = np.rint(np.cumsum(diff[:, :cols], axis=1)).astype(np.int64)
        inside = (wind % 2 == 1) if evenodd else (wind != 0)
        out[r0 // n:r1 // n] = inside.reshape((r1 - r0) // n, n, wl, n).mean(axis=(1, 3))
    return out


def outline_rings(shape: Shape, half: float) -> list[Ring]:
    """Polygons whose non-zero union is the outline of ``shape``, ``half`` px each side."""
    out: list[Ring] = []
    paths = [(*r, r[0]) for r in shape.rings] + list(shape.lines)
    for path in paths:
        for (xa, ya), (xb, yb) in zip(path, path[1:], strict=False):
            length = math.hypot(xb - xa, yb - ya)
            if length == 0:
                continue
            nx, ny = -(yb - ya) / length * half, (xb - xa) / length * half
            out.append(_positive(((xa + nx, ya + ny), (xb + nx, yb + ny), (xb - nx, yb - ny),
                                  (xa - nx, ya - ny))))
        for x, y in set(path):
            out.append(_positive(tuple(
                (x + half * math.cos(2 * math.pi * k / _DISC_SIDES),
                 y + half * math.sin(2 * math.pi * k / _DISC_SIDES)) for k in range(_DISC_SIDES))))
    return out


def _positive(ring: Ring) -> Ring:
    """``ring`` with a positive signed area (all alike, so the non-zero rule is their union)."""
    area = sum(xa * yb - xb * ya for (xa, ya), (xb, yb) in zip(ring, (*ring[1:], ring[0]),
                                                                strict=True))
    return ring if area >= 0 else ring[::-1]


def _over(acc: npt.NDArray[np.float64], alpha: npt.NDArray[np.float64],
          colour: tuple[int, int, int]) -> None:
    src = np.empty_like(acc)
    src[..., 3] = alpha
    src[..., :3] = alpha[..., None] * (np.asarray(colour, np.float64) / 255.0)
    acc *= 1.0 - alpha[..., None]
    acc += src


def _round(pre: npt.NDArray[np.float64]) -> npt.NDArray[np.uint8]:
    alpha = np.clip(pre[..., 3:4], 0.0, 1.0)
    colour = np.where(alpha > 0, np.clip(pre[..., :3] / np.where(alpha > 0, alpha, 1.0), 0, 1),
                      0.0)
    return np.rint(np.concatenate([colour, alpha], axis=-1) * 255.0).astype(np.uint8)
