"""An independent rasterisation of annotation shapes, for checking ``shape_raster``.

Written differently on purpose: every sample point of the patch is tested on its own — inside a
polygon by the crossing number of a ray to the left (even-odd; our test polygons do not cross
themselves, so it equals non-zero), on the outline when its distance to the nearest segment is
at most half the outline's width (true round joins, where the rasteriser uses 16-gons) — and
Pillow's ``ImageDraw.polygon`` at the supersampled resolution, box-averaged, as a second opinion
on the fill. The sample grid is the documented one: ``N × N`` per level pixel at the centres of
an even grid.
"""

from __future__ import annotations

import numpy as np
import numpy.typing as npt
from PIL import Image, ImageDraw

Points = list[tuple[float, float]]


def sample_grid(level: int, dest: tuple[int, int, int, int],
                n: int) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.float64]]:
    """Canvas coordinates ``(X, Y)`` of every sample, shape ``(rows, cols)``."""
    x0, y0, x1, y1 = dest
    f = float(1 << level)
    u = x0 + (np.arange((x1 - x0) * n) + 0.5) / n
    v = y0 + (np.arange((y1 - y0) * n) + 0.5) / n
    return np.meshgrid(u * f, v * f)


def box_average(inside: npt.NDArray[np.bool_], n: int) -> npt.NDArray[np.float64]:
    rows, cols = inside.shape
    return inside.reshape(rows // n, n, cols // n, n).mean(axis=(1, 3))


def crossing_fill(points: Points, level: int, dest: tuple[int, int, int, int],
                  n: int) -> npt.NDArray[np.float64]:
    """Coverage by the crossing-number test of each sample."""
    xs, ys = sample_grid(level, dest, n)
    odd = np.zeros(xs.shape, bool)
    for (xa, ya), (xb, yb) in zip(points, points[1:] + points[:1], strict=True):
        if ya == yb:
            continue
        spans = (ys >= min(ya, yb)) & (ys < max(ya, yb))
        x_at = xa + (ys - ya) * (xb - xa) / (yb - ya)
        odd ^= spans & (x_at < xs)
    return box_average(odd, n)


def distance_outline(points: Points, closed: bool, half: float, level: int,
                     dest: tuple[int, int, int, int], n: int) -> npt.NDArray[np.float64]:
    """Coverage of the samples within ``half`` canvas px of the (closed) polyline."""
    xs, ys = sample_grid(level, dest, n)
    best = np.full(xs.shape, np.inf)
    path = points + points[:1] if closed else points
    for (xa, ya), (xb, yb) in zip(path, path[1:], strict=False):
        dx, dy = xb - xa, yb - ya
        t = np.clip(((xs - xa) * dx + (ys - ya) * dy) / max(dx * dx + dy * dy, 1e-12), 0, 1)
        best = np.minimum(best, np.hypot(xs - (xa + t * dx), ys - (ya + t * dy)))
    return box_average(best <= half, n)


def pillow_fill(points: Points, level: int, dest: tuple[int, int, int, int],
                n: int) -> npt.NDArray[np.float64]:
    """Coverage from Pillow's polygon fill at ``n``× the level's resolution, box-averaged.

    Pillow's pixel ``k`` is centred on coordinate ``k`` (it rounds vertices and fills the
    boundary inclusively), so a canvas point maps to ``(X/2^L - x0)·n - 0.5``.
    """
    x0, y0, x1, y1 = dest
    f = float(1 << level)
    img = Image.new("L", ((x1 - x0) * n, (y1 - y0) * n))
    ImageDraw.Draw(img).polygon([((x / f - x0) * n - 0.5, (y / f - y0) * n - 0.5)
                                 for x, y in points], fill=255)
    return box_average(np.asarray(img) > 0, n)


def composite(layers: list[tuple[npt.NDArray[np.float64], tuple[int, int, int]]],
              ) -> npt.NDArray[np.float64]:
    """Straight-alpha RGBA (0–255 floats) of coverage layers drawn source-over in order."""
    h, w = layers[0][0].shape
    colour, alpha = np.zeros((h, w, 3)), np.zeros((h, w))
    for a, rgb in layers:  # straight-alpha over: co = (cs·as + cd·ad·(1-as)) / ao
        out_a = a + alpha * (1 - a)
        mix = np.asarray(rgb, float)[None, None] * a[..., None] + colour * (
            alpha * (1 - a))[..., None]
        colour = np.where(out_a[..., None] > 0, mix / np.where(out_a > 0, out_a, 1)[..., None],
                          0)
        alpha = out_a
    return np.concatenate([colour, alpha[..., None] * 255], axis=-1)
