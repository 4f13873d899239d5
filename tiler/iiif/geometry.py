"""Pure IIIF Image API 3 pyramid geometry: levels, tiles and the URLs clients request.

No I/O here: every function takes integers and returns integers or strings, so the pyramid
arithmetic is tested on its own (the zimeon/iiif ``static_partial_tile_sizes`` idea).
"""

from __future__ import annotations

import math
from collections.abc import Iterator
from dataclasses import dataclass


@dataclass(frozen=True)
class TileRequest:
    """One image request: a region of the full image (x, y, w, h) scaled to (sw, sh) pixels."""

    x: int
    y: int
    w: int
    h: int
    sw: int
    sh: int


def scale_factors(width: int, height: int, tile_size: int) -> list[int]:
    """Return the scale factors 1, 2, 4, … down to the level that fits one tile.

    This is libvips ``dzsave`` ``depth=onetile``: the pyramid stops at the first level whose
    width and height are both at most ``tile_size``.
    """
    if width < 1 or height < 1 or tile_size < 1:
        raise ValueError(f"bad pyramid geometry {width}x{height} tile {tile_size}")
    factors = [1]
    while math.ceil(width / factors[-1]) > tile_size or math.ceil(height / factors[-1]) > tile_size:
        factors.append(factors[-1] * 2)
    return factors


def level_size(width: int, height: int, factor: int) -> tuple[int, int]:
    """Return the image size at scale factor ``factor``: ``ceil(W/s) × ceil(H/s)``."""
    return math.ceil(width / factor), math.ceil(height / factor)


def spec_tiles(width: int, height: int, tile_size: int, factor: int) -> Iterator[TileRequest]:
    """Yield the tiles of one level by the Image API 3 implementation notes' algorithm."""
    step = tile_size * factor
    for yr in range(0, height, step):
        for xr in range(0, width, step):
            wr = min(step, width - xr)
            hr = min(step, height - yr)
            yield TileRequest(xr, yr, wr, hr, math.ceil(wr / factor), math.ceil(hr / factor))


def canonical_path(width: int, height: int, req: TileRequest) -> str:
    """Return ``region/size`` in the IIIF 3 canonical form for a request on a W×H image."""
    full = req.x == 0 and req.y == 0 and req.w == width and req.h == height
    region = "full" if full else f"{req.x},{req.y},{req.w},{req.h}"
    size = "max" if full and (req.sw, req.sh) == (width, height) else f"{req.sw},{req.sh}"
    return f"{region}/{size}"


def osd_tile_paths(width: int, height: int, tile_size: int, factors: list[int]) -> Iterator[str]:
    """Yield ``region/size`` of every tile OpenSeadragon 6.1's IIIFTileSource requests.

    Mirrors ``IIIFTileSource.getTileUrl`` for a version-3 info.json with one ``tiles`` entry
    and ``scaleFactors`` (levels 0…maxLevel, level scale ``0.5**(maxLevel-level)``).
    """
    max_level = round(math.log2(max(factors)))
    for level in range(max_level + 1):
        scale = 0.5 ** (max_level - level)
        lw, lh = math.ceil(width * scale), math.ceil(height * scale)
        if lw < tile_size and lh < tile_size:
            size = "max" if (lw, lh) == (width, height) else f"{lw},{lh}"
            yield f"full/{size}"
            continue
        step = round(tile_size / scale)
        for ty in range(math.ceil(lh / tile_size)):
            for tx in range(math.ceil(lw / tile_size)):
                x, y = tx * step, ty * step
                w, h = min(step, width - x), min(step, height - y)
                region = "full" if (x, y, w, h) == (0, 0, width, height) else f"{x},{y},{w},{h}"
                sw = min(tile_size, lw - tx * tile_size)
                sh = min(tile_size, lh - ty * tile_size)
                size = "max" if (sw, sh) == (width, height) else f"{sw},{sh}"
                yield f"{region}/{size}"


def parse_region_size(width: int, height: int, path: str) -> TileRequest:
    """Parse a level-0 ``region/size`` pair (``full``/``x,y,w,h`` and ``max``/``w,h``)."""
    region, size = path.split("/")
    if region == "full":
        x, y, w, h = 0, 0, width, height
    else:
        x, y, w, h = (int(v) for v in region.split(","))
    if size == "max":
        sw, sh = w, h
    else:
        sw, sh = (int(v) for v in size.split(","))
    return TileRequest(x, y, w, h, sw, sh)
