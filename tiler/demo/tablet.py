"""A procedural cultural-heritage object for demos and tests: an inscribed stone tablet.

:func:`make_demo_object` builds a weathered limestone tablet on a dark, flat background:
a bevelled slab with chipped edges, a raised moulded frame, a sunken field carrying an
incised inscription with traces of red paint, a raised medallion holding a domed gold
rosette inlay, hairline cracks, pitting and surface grain.  Shading and the PTM fit are in
:mod:`lanterna.tiler.demo.dome`.

Axes follow the RTI convention: x right, y up, z toward the camera; arrays are rows
top-down, so ``y`` grows toward row 0.  Everything is deterministic for a seed.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt
from PIL import Image, ImageDraw, ImageFont

F32 = npt.NDArray[np.float32]

#: Fraction of the albedo seen without direct light (keeps shadows from going black).
AMBIENT = 0.06
#: Inscription on the tablet, one string per line.
INSCRIPTION = ("LANTERNA", "LVX IN TENEBRIS LVCET")

_STONE = np.array([0.78, 0.69, 0.54], dtype=np.float32)
_PAINT = np.array([0.50, 0.17, 0.11], dtype=np.float32)
_GOLD = np.array([0.28, 0.18, 0.05], dtype=np.float32)
_GOLD_SPECULAR = np.array([0.70, 0.55, 0.25], dtype=np.float32)
_BACKGROUND = np.array([0.035, 0.035, 0.04], dtype=np.float32)


@dataclass(frozen=True)
class DemoObject:
    """Geometry and material of the demo tablet, all ``float32``, rows top-down.

    Attributes
    ----------
    height_map : ndarray, shape (H, W)
        Height in pixel units (0 on the background).
    normals : ndarray, shape (H, W, 3)
        Unit normals, x right, y up, z toward the camera.
    albedo : ndarray, shape (H, W, 3)
        Diffuse colour, display-referred 0–1.
    specular : ndarray, shape (H, W)
        Specular weight 0–1 (1 on the gold inlay, 0 on stone and background).
    shininess : float
        Blinn-Phong exponent of the specular lobe.
    specular_color : ndarray, shape (3,)
        Colour of the specular highlight.
    """

    height_map: F32
    normals: F32
    albedo: F32
    specular: F32
    shininess: float
    specular_color: F32

    @property
    def shape(self) -> tuple[int, int]:
        """Return ``(H, W)``."""
        h, w = self.height_map.shape
        return int(h), int(w)


def _blur(a: F32, sigma: float) -> F32:
    """Gaussian-blur a 2-D array by multiplying its spectrum; edges are reflected."""
    if sigma <= 0.0:
        return a
    pad = int(math.ceil(3.0 * sigma))
    p = np.pad(a, pad, mode="reflect")
    fy = np.fft.fftfreq(p.shape[0])[:, None]
    fx = np.fft.rfftfreq(p.shape[1])[None, :]
    gain = np.exp(-2.0 * (math.pi * sigma) ** 2 * (fx * fx + fy * fy))
    out = np.fft.irfft2(np.fft.rfft2(p) * gain, s=p.shape)
    return out[pad:-pad, pad:-pad].astype(np.float32)


def _noise(rng: np.random.Generator, shape: tuple[int, int], sigmas: list[float]) -> F32:
    """Return band-limited noise: blurred white noise per scale, each of unit std, summed."""
    total = np.zeros(shape, dtype=np.float32)
    for i, s in enumerate(sigmas):
        n = _blur(rng.standard_normal(shape).astype(np.float32), s)
        total += n / max(float(n.std()), 1e-9) * np.float32(0.6**i)
    return total


def _smoothstep(e0: float, e1: float, x: F32) -> F32:
    t: F32 = np.clip((x - e0) / (e1 - e0), 0.0, 1.0).astype(np.float32)
    return t * t * (3.0 - 2.0 * t)


def _rounded_box_sdf(
    shape: tuple[int, int], box: tuple[float, float, float, float], radius: float
) -> F32:
    """Signed distance (pixels, negative inside) to a rounded rectangle (x0, y0, x1, y1)."""
    h, w = shape
    yy, xx = np.mgrid[0:h, 0:w].astype(np.float32)
    x0, y0, x1, y1 = box
    cx, cy = (x0 + x1) / 2.0, (y0 + y1) / 2.0
    qx = np.abs(xx - cx) - ((x1 - x0) / 2.0 - radius)
    qy = np.abs(yy - cy) - ((y1 - y0) / 2.0 - radius)
    outside = np.hypot(np.maximum(qx, 0.0), np.maximum(qy, 0.0))
    inside = np.minimum(np.maximum(qx, qy), 0.0)
    sdf: F32 = (outside + inside - radius).astype(np.float32)
    return sdf


def _text_mask(
    shape: tuple[int, int],
    lines: tuple[str, ...],
    box: tuple[int, int, int, int],
    sizes: tuple[float, ...],
) -> F32:
    """Render centred text lines into a 0–1 mask, fitted inside ``box`` (x0, y0, x1, y1).

    ``sizes`` are relative letter heights of the lines.  Uses Pillow's built-in font, so
    the result depends only on the Pillow version.
    """
    h, w = shape
    x0, y0, x1, y1 = box
    bw, bh = x1 - x0, y1 - y0
    gap = 0.45
    unit = bh / (sum(sizes) + gap * (len(lines) - 1))
    img = Image.new("L", (w, h), 0)
    draw = ImageDraw.Draw(img)
    y = float(y0)
    for text, rel in zip(lines, sizes, strict=True):
        size = max(6, int(unit * rel * 1.3))
        font = ImageFont.load_default(size=size)
        left, top, right, bottom = draw.textbbox((0, 0), text, font=font)
        if right - left > bw:  # shrink to the field width
            size = max(6, int(size * bw / (right - left)))
            font = ImageFont.load_default(size=size)
            left, top, right, bottom = draw.textbbox((0, 0), text, font=font)
        tx = x0 + (bw - (right - left)) / 2.0 - left
        ty = y + (unit * rel - (bottom - top)) / 2.0 - top
        draw.text((tx, ty), text, fill=255, font=font)
        y += unit * (rel + gap)
    return np.asarray(img, dtype=np.float32) / 255.0


def _crack_mask(
    rng: np.random.Generator, shape: tuple[int, int], inside: F32, u: float, count: int
) -> F32:
    """Draw random-walk cracks starting inside the slab near its edge; return a 0–1 mask."""
    h, w = shape
    img = Image.new("L", (w, h), 0)
    draw = ImageDraw.Draw(img)
    ys, xs = np.nonzero((inside > 0.5) & (inside < 0.9))
    if ys.size == 0:
        return np.zeros(shape, dtype=np.float32)
    cy, cx = h / 2.0, w / 2.0
    for _ in range(count):
        k = int(rng.integers(ys.size))
        x, y = float(xs[k]), float(ys[k])
        angle = math.atan2(cy - y, cx - x) + float(rng.normal(0.0, 0.5))
        steps = int(rng.integers(25, 90))
        width = 1 if rng.random() < 0.6 else 2
        pts = [(x, y)]
        for _ in range(steps):
            angle += float(rng.normal(0.0, 0.35))
            step = 3.0 * u * float(rng.uniform(0.5, 1.5))
            x += math.cos(angle) * step
            y += math.sin(angle) * step
            pts.append((x, y))
            if rng.random() < 0.03:  # a short branch
                a2 = angle + float(rng.choice([-1.0, 1.0])) * float(rng.uniform(0.5, 1.2))
                bx, by = x, y
                branch = [(bx, by)]
                for _ in range(int(rng.integers(4, 15))):
                    a2 += float(rng.normal(0.0, 0.4))
                    bx += math.cos(a2) * 3.0 * u
                    by += math.sin(a2) * 3.0 * u
                    branch.append((bx, by))
                draw.line(branch, fill=160, width=1)
        draw.line(pts, fill=255, width=max(1, int(round(width * u))), joint="curve")
    return np.asarray(img, dtype=np.float32) / 255.0


def normals_from_height(height_map: npt.NDArray[np.floating]) -> F32:
    """Return unit normals of a height field (x right, y up, z toward the camera).

    Parameters
    ----------
    height_map : ndarray, shape (H, W)
        Heights in pixel units, rows top-down.

    Returns
    -------
    ndarray of float32, shape (H, W, 3)
        ``normalize(−∂h/∂x, −∂h/∂y, 1)`` with y up, i.e. ``ny = +∂h/∂row``.

    Raises
    ------
    ValueError
        If ``height_map`` is not 2-D with at least 2 rows and 2 columns.
    """
    hm = np.asarray(height_map, dtype=np.float32)
    if hm.ndim != 2 or min(hm.shape) < 2:
        raise ValueError(f"height_map must be (H, W) with H, W ≥ 2, got {hm.shape}")
    d_row, d_col = np.gradient(hm)
    n = np.stack([-d_col, d_row, np.ones_like(hm)], axis=-1)
    n /= np.linalg.norm(n, axis=-1, keepdims=True)
    return n.astype(np.float32)


def make_demo_object(width: int = 1024, height: int = 768, seed: int = 0) -> DemoObject:
    """Build the procedural inscribed stone tablet.

    Parameters
    ----------
    width, height : int
        Image size in pixels (each at least 64).  Features scale with
        ``min(width / 1024, height / 768)``.
    seed : int
        Seed of every random choice (cracks, chips, grain, stains).

    Returns
    -------
    DemoObject

    Raises
    ------
    ValueError
        If the size is below 64 × 64.
    """
    if width < 64 or height < 64:
        raise ValueError(f"demo object needs at least 64 x 64 pixels, got {width} x {height}")
    rng = np.random.default_rng(seed)
    shape = (height, width)
    u = min(width / 1024.0, height / 768.0)
    yy, xx = np.mgrid[0:height, 0:width].astype(np.float32)

    # Slab outline: a rounded rectangle with a wobbly, chipped edge.
    mx, my = 0.075 * width, 0.085 * height
    d = _rounded_box_sdf(shape, (mx, my, width - mx, height - my), 26.0 * u)
    d += 2.0 * u * _noise(rng, shape, [30.0 * u, 4.0 * u])
    edge_ys, edge_xs = np.nonzero(np.abs(d) < 2.0)
    chips = np.zeros(shape, dtype=np.float32)
    for _ in range(10):
        k = int(rng.integers(max(edge_ys.size, 1)))
        if edge_ys.size == 0:
            break
        r = float(rng.uniform(10.0, 30.0)) * u
        ex, ey = float(edge_xs[k]), float(edge_ys[k])
        blob = 1.0 - np.hypot(xx - ex, (yy - ey) * float(rng.uniform(0.6, 1.6))) / r
        chips = np.maximum(chips, blob)
    d += 16.0 * u * np.clip(chips, 0.0, 1.0) ** 0.7
    inside = np.sqrt(_smoothstep(-1.0, 9.0 * u, -d))  # rounded edge, 0 outside, 1 inside
    solid = _smoothstep(-1.0, 1.0, -d)  # footprint, antialiased

    rough = _noise(rng, shape, [1.2 * u, 3.0 * u, 9.0 * u])
    hgt = 20.0 * u * inside
    hgt += 2.5 * u * _blur(np.clip(chips, 0.0, 1.0), 2.0 * u) * rough * inside  # broken faces
    # Gentle pillow dome of the slab.
    cx, cy = width / 2.0, height / 2.0
    r2 = ((xx - cx) / (width / 2.0)) ** 2 + ((yy - cy) / (height / 2.0)) ** 2
    hgt += 6.0 * u * (1.0 - np.clip(r2, 0.0, 1.0)) * inside

    # Raised moulded frame and sunken field.
    frame_out, frame_w = 16.0 * u, 30.0 * u
    t = np.clip((-d - frame_out) / frame_w, 0.0, 1.0)
    hgt += 9.0 * u * np.sqrt(np.clip(1.0 - (2.0 * t - 1.0) ** 2, 0.0, 1.0))
    field = _smoothstep(frame_out + frame_w, frame_out + frame_w + 6.0 * u, -d)
    hgt -= 5.0 * u * field

    # Medallion with a domed gold rosette inlay, top centre.
    fx0 = mx + frame_out + frame_w
    fy0 = my + frame_out + frame_w
    field_h = height - 2.0 * fy0
    mr = 0.19 * field_h
    mcx, mcy = width / 2.0, fy0 + 0.08 * field_h + mr
    rr = np.hypot(xx - mcx, yy - mcy)
    ring_t = np.clip((rr - 0.80 * mr) / (0.22 * mr), 0.0, 1.0)
    ring = np.sqrt(np.clip(1.0 - (2.0 * ring_t - 1.0) ** 2, 0.0, 1.0)) * (rr < 1.02 * mr)
    hgt += 5.0 * u * ring
    ir = 0.74 * mr
    theta = np.arctan2(yy - mcy, xx - mcx)
    petal_r = ir * (0.62 + 0.38 * np.abs(np.cos(4.0 * theta)))
    disc = _smoothstep(0.0, 2.0 * u, ir - rr)
    petals = np.sqrt(_smoothstep(0.0, 0.16 * ir, petal_r - rr)) * _smoothstep(
        0.0, 3.0 * u, rr - 0.22 * ir
    )
    boss = _smoothstep(0.0, 2.0 * u, 0.2 * ir - rr)
    dome = np.sqrt(np.clip(1.0 - (rr / ir) ** 2, 0.0, 1.0))
    inlay_h = 0.3 * ir * dome + 6.0 * u * petals + 6.0 * u * boss * dome
    base = float(hgt[int(mcy), int(mcx)])
    hgt = hgt * (1.0 - disc) + (base + inlay_h) * disc

    # Incised inscription below the medallion, V-cut (deeper mid-stroke).
    text_box = (
        int(fx0 + 0.06 * (width - 2.0 * fx0)),
        int(mcy + 1.18 * mr),
        int(width - fx0 - 0.06 * (width - 2.0 * fx0)),
        int(height - fy0 - 0.07 * field_h),
    )
    letters = _text_mask(shape, INSCRIPTION, text_box, (1.5, 1.0))
    cut = _blur(letters, 0.8 * u) * (0.35 + 0.65 * np.clip(_blur(letters, 2.5 * u) * 1.6, 0, 1))
    erosion = np.clip(0.8 + 0.25 * _noise(rng, shape, [6.0 * u]), 0.4, 1.0)
    hgt -= 6.0 * u * cut * erosion

    # Cracks, pits and grain.
    cracks = _blur(_crack_mask(rng, shape, inside, u, 9), 0.6 * u) * (1.0 - disc)
    hgt -= 3.0 * u * cracks
    density = 0.0012 / max(u * u, 0.25)  # pits per pixel, clustered in weathered patches
    weathered = np.clip(_noise(rng, shape, [50.0 * u]) - 0.3, 0.0, 1.0)
    small = (rng.random(shape) < density * weathered).astype(np.float32)
    large = (rng.random(shape) < density / 6.0).astype(np.float32)
    pits = _blur(small, 1.0 * u) * 9.0 * u * u + _blur(large, 2.2 * u) * 28.0 * u * u
    pits = np.clip(pits, 0.0, 1.0) * (1.0 - disc)
    hgt -= 2.0 * u * pits
    hgt += (
        (0.18 * u * rough + 0.5 * u * _noise(rng, shape, [5.0 * u, 14.0 * u]))
        * inside
        * (1.0 - disc)
    )
    hgt = (hgt * inside).astype(np.float32)
    normals = normals_from_height(hgt)

    # Albedo: stained limestone, grime in hollows, paint in letters, gold inlay.
    stains = _noise(rng, shape, [40.0 * u, 15.0 * u, 4.0 * u])
    hue = _noise(rng, shape, [60.0 * u])
    stone = _STONE[None, None, :] * (1.0 + 0.07 * stains[..., None])
    stone = stone * (1.0 + 0.04 * hue[..., None] * np.array([1.0, 0.2, -1.0], np.float32))
    cavity = np.clip((_blur(hgt, 6.0 * u) - hgt) / (4.0 * u), 0.0, 1.0)
    stone = stone * (1.0 - 0.35 * cavity[..., None]) * (1.0 - 0.4 * cracks[..., None])
    paint = np.clip(letters * (0.55 + 0.5 * _noise(rng, shape, [3.0 * u, 10.0 * u])), 0, 0.8)
    stone = stone * (1.0 - paint[..., None]) + _PAINT * paint[..., None]
    gold = _GOLD * (1.0 + 0.05 * _noise(rng, shape, [2.0 * u])[..., None])
    albedo = stone * (1.0 - disc[..., None]) + gold * disc[..., None]
    albedo = albedo * solid[..., None] + _BACKGROUND * (1.0 - solid[..., None])

    return DemoObject(
        height_map=hgt,
        normals=normals,
        albedo=np.clip(albedo, 0.0, 1.0).astype(np.float32),
        specular=(disc * inside).astype(np.float32),
        shininess=14.0,
        specular_color=_GOLD_SPECULAR.copy(),
    )
