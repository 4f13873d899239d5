"""Pure overlay-pyramid geometry: patch names, level sizes, destination rectangles, clipping.

No I/O here (docs/annotations.md, "Building"): a patch ``L_X_Y_W_H_O_INFO.png`` belongs to level
``L``; ``X, Y, W, H`` is its rectangle in full-resolution canvas pixels; at level ``L`` it covers
``floor(X/2^L), floor(Y/2^L)`` to ``ceil((X+W)/2^L), ceil((Y+H)/2^L)``, clipped to the level image.
Patches of a level are applied in increasing ``O``, ties broken by file name.
"""

from __future__ import annotations

import math
import re
from collections.abc import Iterable
from dataclasses import dataclass

#: ``L_X_Y_W_H_O[_INFO].png``: X, Y and O may be negative, INFO may contain ``_`` (or be absent).
_NAME = re.compile(r"^(\d+)_(-?\d+)_(-?\d+)_(\d+)_(\d+)_(-?\d+)(?:_(.*))?\.png$", re.IGNORECASE)
_GIMP_NAME = re.compile(r"^(?:level_)?(\d+)\.png$", re.IGNORECASE)
#: Largest factor by which a patch image may be scaled to its rectangle, up or down.
MAX_PATCH_SCALE = 256


class PatchNameError(ValueError):
    """A patch file name that does not follow ``L_X_Y_W_H_O_INFO.png``; ``str`` is one line."""


@dataclass(frozen=True)
class Patch:
    """One patch: level, full-resolution rectangle, order of application, free text, file name."""

    level: int
    x: int
    y: int
    w: int
    h: int
    order: int
    info: str
    file: str


@dataclass(frozen=True)
class Placement:
    """Where a patch lands on its level image.

    ``dest`` is the unclipped destination rectangle ``(x0, y0, x1, y1)`` at the level (the patch
    image is resized to ``x1 - x0`` × ``y1 - y0``); ``clip`` is the part inside the level image,
    in the same coordinates.
    """

    dest: tuple[int, int, int, int]
    clip: tuple[int, int, int, int]

    @property
    def size(self) -> tuple[int, int]:
        """Return the resized patch's ``(width, height)``."""
        x0, y0, x1, y1 = self.dest
        return x1 - x0, y1 - y0

    @property
    def source_box(self) -> tuple[int, int, int, int]:
        """Return the clipped part of the resized patch as ``(left, top, width, height)``."""
        cx0, cy0, cx1, cy1 = self.clip
        return cx0 - self.dest[0], cy0 - self.dest[1], cx1 - cx0, cy1 - cy0


def parse_patch_name(name: str) -> Patch:
    """Parse ``L_X_Y_W_H_O_INFO.png``; raise :class:`PatchNameError` saying what is wrong."""
    m = _NAME.match(name)
    if m is None:
        if not name.lower().endswith(".png"):
            raise PatchNameError("not a .png patch (expected L_X_Y_W_H_O_INFO.png)")
        raise PatchNameError("malformed patch name (expected L_X_Y_W_H_O_INFO.png with integers "
                             "L, X, Y, W, H, O)")
    level, x, y, w, h, order = (int(v) for v in m.groups()[:6])
    if w < 1 or h < 1:
        raise PatchNameError(f"patch size {w}x{h} is empty (W and H must be at least 1)")
    return Patch(level, x, y, w, h, order, m.group(7) or "", name)


def parse_gimp_name(name: str) -> int:
    """Return the level of a per-level overlay image named ``level_L.png`` or ``L.png``."""
    m = _GIMP_NAME.match(name)
    if m is None:
        raise PatchNameError("malformed level image name (expected level_L.png or L.png)")
    return int(m.group(1))


def level_size(width: int, height: int, level: int) -> tuple[int, int]:
    """Return the size of level ``level`` of a ``width`` × ``height`` canvas (ceil halving)."""
    if level < 0:
        raise ValueError(f"negative level {level}")
    f = 1 << level
    return math.ceil(width / f), math.ceil(height / f)


def canvas_box(extent: tuple[int, int, int, int], level: int, width: int,
               height: int) -> tuple[int, int, int, int]:
    """Return a level-pixel extent ``(x0, y0, x1, y1)`` as a canvas rectangle ``(x, y, w, h)``.

    Level pixel ``(i, j)`` covers canvas pixels ``i·2^L`` to ``(i+1)·2^L``; the result is clipped
    to the ``width`` × ``height`` canvas (the last level pixel may reach past its edge).
    """
    f = 1 << level
    x0, y0, x1, y1 = extent
    left, top = min(x0 * f, width), min(y0 * f, height)
    return left, top, min(x1 * f, width) - left, min(y1 * f, height) - top


def max_level(scale_factors: Iterable[int]) -> int:
    """Return the deepest level of a pyramid with these IIIF ``scaleFactors`` (1, 2, 4, …)."""
    return max(int(s) for s in scale_factors).bit_length() - 1


def destination(patch: Patch) -> tuple[int, int, int, int]:
    """Return the patch's rectangle at its level: floor of the start, ceil of the end."""
    f = 1 << patch.level
    return (patch.x // f, patch.y // f, -(-(patch.x + patch.w) // f), -(-(patch.y + patch.h) // f))


def place(patch: Patch, width: int, height: int) -> Placement | None:
    """Return where ``patch`` lands on its level of a ``width`` × ``height`` canvas.

    ``None`` when its full-resolution rectangle misses the canvas (an error for the caller to
    report); a patch partly outside is clipped.
    """
    if (patch.x >= width or patch.y >= height or patch.x + patch.w <= 0
            or patch.y + patch.h <= 0):
        return None
    lw, lh = level_size(width, height, patch.level)
    x0, y0, x1, y1 = destination(patch)
    return Placement((x0, y0, x1, y1), (max(x0, 0), max(y0, 0), min(x1, lw), min(y1, lh)))


def scale_problem(image_size: tuple[int, int], placement: Placement) -> str | None:
    """Why a patch image of ``image_size`` cannot be drawn at ``placement``, or ``None``.

    It is refused when resizing it to its rectangle would scale it by more than
    :data:`MAX_PATCH_SCALE` either way (a rectangle in the name that does not belong to the
    image: ``…_520_100000_…`` on a 30×20 drawing).
    """
    (iw, ih), (dw, dh) = image_size, placement.size
    factor = max(dw / iw, iw / dw, dh / ih, ih / dh)
    if factor <= MAX_PATCH_SCALE:
        return None
    return (f"its {iw}x{ih} image would be drawn {dw}x{dh} at level (scaled {factor:,.0f}x; at "
            f"most {MAX_PATCH_SCALE}x): check W and H in its name")


def application_order(patches: Iterable[Patch]) -> list[Patch]:
    """Sort patches by level, then order ``O``, then file name (the compositing order)."""
    return sorted(patches, key=lambda p: (p.level, p.order, p.file))
