"""Relight/OpenLIME tiled layouts of a web-format folder: one plane reassembled from its tiles.

Besides ``plane_K.jpg`` (the ``image`` layout), Relight writes (``src/deepzoom.cpp``,
``relight/zoom.h`` ``deepZoom``/``tarZoom``/``itarZoom``) and OpenLIME reads
(``src/LayoutTiles.js``, ``LayerRTI.imageUrl``) three tiled layouts of the same planes:

- **deepzoom**: ``plane_K.dzi`` (XML: ``Format``, ``TileSize``, ``Overlap``, ``Size Width/Height``)
  and ``plane_K_files/LEVEL/X_Y.jpg``. Level 0 is one tile, the deepest level the full image
  (Relight halves ``w >>= 1`` until the image fits one tile; libvips ``dzsave`` rounds up; a
  standard Deep Zoom pyramid goes down to 1 px: the deepest level is the highest of these that
  exists). Tile ``(X, Y)`` covers ``[X·T − O, (X+1)·T + O)`` clamped to the image: ``O`` pixels of
  overlap on each inner side.
- **tarzoom**: ``plane_K.tzi`` (JSON ``tilesize``, ``overlap``, ``width``, ``height``,
  ``nlevels``, ``offsets``) indexes ``plane_K.tzb``, the concatenated tile files: tile ``i`` is
  bytes ``offsets[i] .. offsets[i+1]``, in OpenLIME's order: level 0 first, each level's tiles
  row by row (``index = Σ tiles of the levels above + y·nx + x``; a level's ``nx`` is
  ``ceil((width >> (nlevels − 1 − level)) / tilesize)``).
- **itarzoom**: one ``planes.tzi`` (the same fields plus ``stride``, the number of planes, and
  ``mode: "interleaved"``) and ``planes.tzb``: tile ``i`` of plane ``p`` is entry
  ``i·stride + p``.

Relight and OpenLIME define no IIIF layout for RTI planes (OpenLIME's ``imageUrl`` throws
"Unimplemented" for ``iiif``); ``google`` and ``zoomify`` are not read.

Only the deepest level is read. Every size is checked against the headers before a tile is
decoded: the stated image size against ``info.json``, tile counts against the index, index
entries against the blob's real size, and each tile's pixel size against the grid.
"""

from __future__ import annotations

import math
import os
import xml.etree.ElementTree as ET
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import pyvips

from lanterna.errors import LanternaInputError
from lanterna.tiler.documents import load_json
from lanterna.tiler.fileio import check_regular_file, read_input
from lanterna.tiler.limits import check_pixels

#: Accepted tile sizes (Relight writes 256, OpenLIME's documentation 254) and pyramid depths.
TILE_SIZES = (16, 8192)
MAX_LEVELS = 40
#: Largest ``.dzi`` read (a descriptor is a few hundred bytes).
MAX_DZI_BYTES = 1 << 20


@dataclass(frozen=True)
class TileGrid:
    """The full-resolution level of a tiled plane: ``tile`` px tiles with ``overlap`` px."""

    width: int
    height: int
    tile: int
    overlap: int

    @property
    def nx(self) -> int:
        return -(-self.width // self.tile)

    @property
    def ny(self) -> int:
        return -(-self.height // self.tile)

    def stored(self, col: int, row: int) -> tuple[int, int, int, int]:
        """``(x0, y0, x1, y1)`` of the pixels tile ``(col, row)`` holds, overlap included."""
        t, o = self.tile, self.overlap
        return (max(0, col * t - o), max(0, row * t - o),
                min(self.width, (col + 1) * t + o), min(self.height, (row + 1) * t + o))

    def level_counts(self, nlevels: int) -> list[int]:
        """Tiles per level, level 0 (the smallest) first, as OpenLIME counts them."""
        return [-(-(self.width >> s) // self.tile) * -(-(self.height >> s) // self.tile)
                for s in range(nlevels - 1, -1, -1)]


def tiled_plane_source(folder: Path, index: int, *, name: str | None = None,
                       interleaved: str = "planes") -> tuple[str, Path] | None:
    """The tiled layout holding plane ``index`` and its index file, or ``None``.

    ``name`` is the plane's file stem (default ``plane_{index}``), ``interleaved`` the stem of
    the itarzoom pair (``planes``; OpenLIME's multispectral layers use their ``basename``).
    """
    stem = name or f"plane_{index}"
    for layout, path in (("deepzoom", folder / f"{stem}.dzi"), ("tarzoom", folder / f"{stem}.tzi"),
                         ("itarzoom", folder / f"{interleaved}.tzi")):
        if path.exists():
            return layout, path
    return None


def open_tiled_plane(folder: Path, index: int, count: int, width: int, height: int, *,
                     name: str | None = None, interleaved: str = "planes") -> pyvips.Image | None:
    """Plane image ``index`` (of ``count``) reassembled at full resolution from its tiles.

    Returns ``None`` when ``folder`` has no tiled layout for it (:func:`tiled_plane_source`).
    The image is ``width`` × ``height``, 8-bit, as many bands as the tiles (the caller checks).

    Raises
    ------
    LanternaInputError
        Naming the file at fault: a bad ``.dzi`` or ``.tzi``, a stated size other than
        ``width`` × ``height``, a missing, undecodable or wrongly sized tile, a truncated blob or an
        index entry past its end.
    """
    source = tiled_plane_source(Path(folder), index, name=name, interleaved=interleaved)
    if source is None:
        return None
    layout, path = source
    check_pixels(path, width, height, "the plane")
    return _READERS[layout](path, index, count, width, height)


def open_rgb_plane(data: bytes, path: Path, what: str = "plane") -> pyvips.Image:
    """Decode an 8-bit RGB image (a plane or a tile) from ``data``, read from ``path``."""
    try:
        image = pyvips.Image.new_from_buffer(data, "", fail_on="warning")
        bands, fmt = image.bands, image.format
    except pyvips.Error as exc:
        raise LanternaInputError(path, f"cannot decode {what} ({vips_reason(exc)})") from None
    if bands != 3 or fmt != "uchar":
        raise LanternaInputError(path, f"{what} has {bands} band(s) of {fmt}; expected 8-bit RGB")
    return image


def vips_reason(exc: pyvips.Error) -> str:
    """libvips' own reason: the first line of its detail (the message is often generic)."""
    detail = [line for line in str(exc.detail or "").splitlines() if line.strip()]
    return " ".join((detail[0] if detail else str(exc.message or exc)).split())[:80]


def _deepzoom(dzi: Path, index: int, count: int, width: int, height: int) -> pyvips.Image:
    grid, suffix = _read_dzi(dzi, width, height)
    files = dzi.with_name(f"{dzi.stem}_files")
    level = next((lv for lv in _level_candidates(grid) if (files / str(lv)).is_dir()), None)
    if level is None:
        raise LanternaInputError(files, "has no full-resolution level (expected one of "
                                 f"{', '.join(map(str, _level_candidates(grid)))})")
    tiles = []
    for row in range(grid.ny):
        for col in range(grid.nx):
            path = files / str(level) / f"{col}_{row}.{suffix}"
            if not path.exists():
                raise LanternaInputError(path, f"tile {col}_{row} of level {level} is missing")
            tiles.append(_tile(read_input(path, "a tile image"), path, grid, col, row))
    return _join(tiles, grid)


def _read_dzi(dzi: Path, width: int, height: int) -> tuple[TileGrid, str]:
    data = read_input(dzi, "a Deep Zoom descriptor", max_bytes=MAX_DZI_BYTES)
    if b"<!ENTITY" in data or b"<!DOCTYPE" in data:
        raise LanternaInputError(dzi, "declares a DOCTYPE or entities; refused")
    try:
        root = ET.fromstring(data)
    except ET.ParseError as exc:
        raise LanternaInputError(dzi, f"not valid Deep Zoom XML ({exc})") from None
    if _local(root.tag) != "Image":
        raise LanternaInputError(dzi, f"root element is <{_local(root.tag)}>; expected <Image>")
    size = next((el for el in root if _local(el.tag) == "Size"), None)
    if size is None:
        raise LanternaInputError(dzi, "Image has no <Size> element")
    suffix = root.get("Format", "")
    if suffix.lower() not in ("jpg", "jpeg", "png"):
        raise LanternaInputError(dzi, f"Image Format {suffix!r}: expected jpg, jpeg or png")
    w, h = (_int_attr(size, key, dzi, 1, 1 << 31) for key in ("Width", "Height"))
    if (w, h) != (width, height):
        raise LanternaInputError(dzi, f"Size is {w}x{h}, info.json says {width}x{height}")
    tile = _int_attr(root, "TileSize", dzi, *TILE_SIZES)
    overlap = _int_attr(root, "Overlap", dzi, 0, tile - 1)
    return TileGrid(width, height, tile, overlap), suffix


def _local(tag: str) -> str:
    return tag.rsplit("}", 1)[-1]


def _int_attr(element: ET.Element, key: str, path: Path, low: int, high: int) -> int:
    raw = element.get(key)
    if raw is None or not raw.strip().isdigit() or not low <= int(raw) <= high:
        raise LanternaInputError(path, f"{_local(element.tag)} {key} must be an integer in "
                                 f"{low}..{high}, got {raw!r}")
    return int(raw)


def _level_candidates(grid: TileGrid) -> list[int]:
    """Level numbers the full resolution may have, highest first (see the module notes)."""
    def halvings(half: Callable[[int], int]) -> int:
        w, h, n = grid.width, grid.height, 0
        while w > grid.tile or h > grid.tile:
            w, h, n = half(w), half(h), n + 1
        return n
    one_pixel = (max(grid.width, grid.height) - 1).bit_length()
    return sorted({one_pixel, halvings(lambda v: v >> 1), halvings(lambda v: (v + 1) >> 1)},
                  reverse=True)


def _tarzoom(tzi: Path, index: int, count: int, width: int, height: int) -> pyvips.Image:
    return _read_tar(tzi, width, height, plane=0, count=None)


def _itarzoom(tzi: Path, index: int, count: int, width: int, height: int) -> pyvips.Image:
    return _read_tar(tzi, width, height, plane=index, count=count)


def _read_tar(tzi: Path, width: int, height: int, *, plane: int,
              count: int | None) -> pyvips.Image:
    """Plane ``plane`` of a tarzoom (``count`` None) or itarzoom (``count`` planes) pair.

    An itarzoom's ``stride`` may exceed ``count`` (OpenLIME appends a ``normals`` plane).
    """
    doc = load_json(tzi)
    if not isinstance(doc, dict):
        raise LanternaInputError(tzi, "must be a JSON object")
    w, h = (_int_field(doc, key, tzi, 1, 1 << 31) for key in ("width", "height"))
    if (w, h) != (width, height):
        raise LanternaInputError(tzi, f"width/height are {w}x{h}, info.json says "
                                 f"{width}x{height}")
    tile = _int_field(doc, "tilesize", tzi, *TILE_SIZES)
    grid = TileGrid(width, height, tile, _int_field(doc, "overlap", tzi, 0, tile - 1))
    total = sum(grid.level_counts(_int_field(doc, "nlevels", tzi, 1, MAX_LEVELS)))
    stride = 1 if count is None else _int_field(doc, "stride", tzi, count, 4096)
    offsets = _offsets(doc, tzi, total * stride + 1)
    blob = check_regular_file(tzi.with_suffix(".tzb"), "a tarzoom blob")
    size = os.stat(blob).st_size
    past = next((i for i, v in enumerate(offsets) if v > size), None)
    if past is not None:
        raise LanternaInputError(blob, f"is truncated or badly indexed: {tzi.name} offsets[{past}] "
                                 f"is {offsets[past]}, the blob has {size} bytes")
    first = total - grid.nx * grid.ny  # the deepest level comes last
    tiles = []
    with open(blob, "rb") as fh:
        for t in range(grid.nx * grid.ny):
            entry = (first + t) * stride + plane
            fh.seek(offsets[entry])
            data = fh.read(offsets[entry + 1] - offsets[entry])
            col, row = t % grid.nx, t // grid.nx
            tiles.append(_tile(data, blob, grid, col, row, f"tile {col}_{row} (entry {entry})"))
    return _join(tiles, grid)


def _int_field(doc: dict[str, Any], key: str, path: Path, low: int, high: int) -> int:
    value = doc.get(key)
    if isinstance(value, bool) or not isinstance(value, int) or not low <= value <= high:
        raise LanternaInputError(path, f"{key} must be an integer in {low}..{high}, got "
                                 f"{value!r}"[:200])
    return value


def _offsets(doc: dict[str, Any], path: Path, expected: int) -> list[int]:
    raw = doc.get("offsets")
    if not isinstance(raw, list) or len(raw) != expected:
        got = f"{len(raw)} entries" if isinstance(raw, list) else repr(raw)[:40]
        raise LanternaInputError(path, f"offsets must list {expected} byte offsets (tiles + 1) "
                                 f"for this size, tile size and nlevels, got {got}")
    out: list[int] = []
    for i, v in enumerate(raw):
        ok = isinstance(v, int | float) and not isinstance(v, bool) and math.isfinite(v)
        if not ok or v < 0 or v != int(v) or (out and int(v) < out[-1]):
            raise LanternaInputError(path, f"offsets[{i}] = {v!r}: offsets must be whole, "
                                     "non-negative and non-decreasing")
        out.append(int(v))
    return out


def _tile(data: bytes, path: Path, grid: TileGrid, col: int, row: int,
          what: str | None = None) -> pyvips.Image:
    """Tile ``(col, row)``'s own pixels (overlap cropped), decoded into memory."""
    what = what or f"tile {col}_{row}"
    image = open_rgb_plane(data, path, what)
    x0, y0, x1, y1 = grid.stored(col, row)
    if (image.width, image.height) != (x1 - x0, y1 - y0):
        raise LanternaInputError(path, f"{what} is {image.width}x{image.height}; the layout "
                                 f"needs {x1 - x0}x{y1 - y0}")
    left, top = col * grid.tile - x0, row * grid.tile - y0
    core = image.crop(left, top, min(grid.tile, grid.width - col * grid.tile),
                      min(grid.tile, grid.height - row * grid.tile))
    try:
        return core.copy_memory()
    except pyvips.Error as exc:
        raise LanternaInputError(path, f"cannot decode {what} ({vips_reason(exc)})") from None


def _join(tiles: list[pyvips.Image], grid: TileGrid) -> pyvips.Image:
    joined = pyvips.Image.arrayjoin(tiles, across=grid.nx, hspacing=grid.tile,
                                    vspacing=grid.tile)
    return joined.crop(0, 0, grid.width, grid.height).copy_memory()


_READERS: dict[str, Callable[[Path, int, int, int, int], pyvips.Image]] = {
    "deepzoom": _deepzoom, "tarzoom": _tarzoom, "itarzoom": _itarzoom,
}
