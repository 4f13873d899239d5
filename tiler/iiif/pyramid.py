"""Write one image as a IIIF Image API 3 level-0 pyramid with pyvips ``dzsave``, gaps fixed.

``dzsave(layout="iiif3")`` writes the tiles; then :func:`write_pyramid` makes the tree complete
for level 0 and for the clients we support (see ``docs/dataset-format.md``, "Pyramids"):
``sizes``, ``full/max`` in jpg (and in the tree's own format), ``preferredFormats``/``extraFormats``
for PNG and WebP trees,
``maxWidth``/``maxHeight`` past the JPEG limit, and every tile URL OpenSeadragon or the spec's
algorithm asks for, including single-tile images.

Cost: besides dzsave's pass, one full-resolution encode (``full/max``, which level 0 requires),
run in a thread *while* dzsave runs (dzsave leaves a core partly idle); the ``sizes`` entries
are joined from the level's tiles dzsave wrote, not resized from the full image again. See
"Tiling" in ``docs/benchmarks.md``.
"""

from __future__ import annotations

import json
import os
import shutil
import tempfile
import threading
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np
import numpy.typing as npt
import pyvips

from . import geometry as geo
from .encoding import JPG, TileFormat, save, tile_format
from .spec import IMAGE_CONTEXT, IMAGE_PROTOCOL

#: Largest side of the ``sizes`` entries we list (and so must serve as whole images).
SIZES_LIMIT = 2048
#: Largest side of ``full/max``: bigger images declare ``maxWidth``/``maxHeight`` = the first
#: pyramid level within it, so ``max`` is that level (the ``sizes`` entry's file, linked), not a
#: full-resolution encode (a gigapixel JPEG nobody should download, costing more than the whole
#: pyramid).
FULL_MAX_LIMIT = SIZES_LIMIT


def vips_from_array(array: npt.NDArray[np.uint8]) -> pyvips.Image:
    """Wrap an ``(H, W, 3)`` or ``(H, W)`` uint8 array as an sRGB / b-w pyvips image."""
    if array.dtype != np.uint8 or array.ndim not in (2, 3):
        raise ValueError(f"expected an (H, W[, 3]) uint8 array, got {array.dtype} {array.shape}")
    img = pyvips.Image.new_from_array(np.ascontiguousarray(array))
    return img.copy(interpretation="srgb" if img.bands >= 3 else "b-w")


def write_pyramid(
    image: pyvips.Image,
    out_dir: Path,
    service_id: str,
    *,
    fmt: str | TileFormat = "png",
    tile_size: int = 256,
) -> dict[str, Any]:
    """Write ``image`` as a level-0 IIIF tree in ``out_dir`` (which must not exist).

    Parameters
    ----------
    image:
        An 8-bit image with 1 or 3 bands (alpha is kept for PNG trees).
    out_dir:
        The image folder to create; its name is the IIIF identifier.
    service_id:
        The ``id`` of the image service (the URL ``out_dir`` is served at).
    fmt:
        The tiles' format (:mod:`.encoding`): ``"png"``, ``"webp"`` (lossless), ``"jpg"``
        (Q90, 4:4:4) or a :class:`~.encoding.TileFormat` with a quality.

    Returns
    -------
    The info.json document written.
    """
    tf = tile_format(fmt)
    out_dir = Path(out_dir)
    if out_dir.exists():
        raise FileExistsError(out_dir)
    width, height = image.width, image.height
    scratch = Path(tempfile.mkdtemp(prefix=".dz-", dir=out_dir.parent))
    try:
        dz: dict[str, Any] = {"layout": "iiif3", "tile_size": tile_size, "overlap": 0,
                              "suffix": tf.dz_suffix()}
        factors = geo.scale_factors(width, height, tile_size)
        cap = full_max_factor(width, height, factors)
        full_max = _FullMax(image, scratch, tf) if cap == 1 else None
        if full_max:
            full_max.start()
        try:
            image.dzsave(str(scratch / out_dir.name), id="http://lanterna.invalid", **dz)
        except pyvips.Error as err:
            if full_max:
                full_max.join()
                raise full_max.with_detail_of(err) from None
            raise
        finally:
            if full_max:
                full_max.join()
        if full_max:
            full_max.raise_error()
        (scratch / out_dir.name).rename(out_dir)
        if full_max:
            full_max.move_into(out_dir)
    finally:
        shutil.rmtree(scratch, ignore_errors=True)

    _complete_tiles(image, out_dir, tf, tile_size, factors)
    info = _info_json(width, height, service_id, tf.ext, tile_size, factors)
    for factor in factors:
        sw, sh = geo.level_size(width, height, factor)
        if max(sw, sh) <= SIZES_LIMIT:
            _ensure(image, out_dir, tf, geo.TileRequest(0, 0, width, height, sw, sh),
                    f"full/{sw},{sh}", _level_from_tiles(out_dir, tf.ext, width, height,
                                                         tile_size, factor))
    if cap > 1:  # full/max is the level `cap`: link its sizes file, encode the other format
        mw, mh = geo.level_size(width, height, cap)
        make = _level_from_tiles(out_dir, tf.ext, width, height, tile_size, cap)
        for ext, ext_fmt in _full_max_formats(tf).items():
            target = _tile_file(out_dir, "full/max", ext)
            target.unlink(missing_ok=True)  # dzsave's own full/max is the full resolution
            target.parent.mkdir(parents=True, exist_ok=True)
            same = _tile_file(out_dir, f"full/{mw},{mh}", ext)
            if same.exists():
                os.link(same, target)
            else:
                level = make()  # a fresh sequential read per file
                assert level is not None
                save(level, target, ext_fmt)
    # only integers and strings: allow_nan=False is a guard, never a user's error
    (out_dir / "info.json").write_text(json.dumps(info, indent=2, allow_nan=False))
    return info


def _full_max_formats(fmt: TileFormat) -> dict[str, TileFormat]:
    """The formats ``full/max`` is written in: jpg (level 0 requires it) and the tree's own."""
    return {"jpg": fmt if fmt.ext == "jpg" else JPG, fmt.ext: fmt}


def full_max_factor(width: int, height: int, factors: list[int]) -> int:
    """The scale factor of ``full/max``: 1, or the first level within :data:`FULL_MAX_LIMIT`."""
    for factor in factors:
        if max(geo.level_size(width, height, factor)) <= FULL_MAX_LIMIT:
            return factor
    return factors[-1]


class _FullMax(threading.Thread):
    """Write ``full/max`` (jpg, and the tree's format) into a scratch folder, in a thread.

    Level 0 requires ``full/max/0/default.jpg``; at full resolution it is one more encode of the
    whole image. dzsave keeps the cores only partly busy, so running this alongside it costs
    little wall time. Errors are re-raised by :meth:`raise_error`.
    """

    def __init__(self, image: pyvips.Image, scratch: Path, fmt: TileFormat) -> None:
        super().__init__(name="lanterna-full-max", daemon=True)
        self._image = image
        self._formats = _full_max_formats(fmt)
        self._files = {ext: scratch / f"full-max.{ext}" for ext in self._formats}
        self._error: Exception | None = None

    def run(self) -> None:
        try:
            w, h = self._image.width, self._image.height
            req = geo.TileRequest(0, 0, w, h, w, h)
            for ext, target in self._files.items():
                _render(self._image, req, target, self._formats[ext])
        except Exception as err:  # handed to the caller's thread by raise_error
            # without its traceback: that holds this thread (a cycle) and the failed save's
            # open file, which on a full disk would hold its space until the collector runs
            self._error = err.with_traceback(None)

    def with_detail_of(self, err: pyvips.Error) -> pyvips.Error:
        """Return ``err`` (dzsave's) with this thread's error detail added, if it failed too.

        libvips has one error buffer for all threads: when both saves fail (a full disk), the
        reason may have gone into either error.
        """
        mine = self._error
        if not isinstance(mine, pyvips.Error) or not mine.detail:
            return err
        return pyvips.Error(err.message, "\n".join(filter(None, [err.detail, mine.detail])))

    def raise_error(self) -> None:
        """Re-raise, in the calling thread, the error the thread stopped on (if any)."""
        if self._error is not None:
            raise self._error

    def move_into(self, out_dir: Path) -> None:
        """Put the files at ``full/max/0/default.*`` (unless dzsave wrote them already)."""
        for ext, source in self._files.items():
            target = _tile_file(out_dir, "full/max", ext)
            if not target.exists():
                target.parent.mkdir(parents=True, exist_ok=True)
                source.rename(target)


def _info_json(width: int, height: int, service_id: str, fmt: str, tile_size: int,
               factors: list[int]) -> dict[str, Any]:
    info: dict[str, Any] = {
        "@context": IMAGE_CONTEXT,
        "id": service_id,
        "type": "ImageService3",
        "protocol": IMAGE_PROTOCOL,
        "profile": "level0",
        "width": width,
        "height": height,
    }
    max_w, max_h = geo.level_size(width, height, full_max_factor(width, height, factors))
    if (max_w, max_h) != (width, height):
        info["maxWidth"], info["maxHeight"] = max_w, max_h
    sizes = [geo.level_size(width, height, f) for f in reversed(factors)]
    info["sizes"] = [{"width": w, "height": h} for w, h in sizes if max(w, h) <= SIZES_LIMIT]
    if not info["sizes"]:
        del info["sizes"]
    info["tiles"] = [{"width": tile_size, "height": tile_size, "scaleFactors": factors}]
    if fmt != "jpg":
        info["preferredFormats"] = [fmt]
        info["extraFormats"] = [fmt]
    return info


def _tile_file(out_dir: Path, path: str, fmt: str) -> Path:
    return out_dir / path / "0" / f"default.{fmt}"


def _complete_tiles(image: pyvips.Image, out_dir: Path, fmt: TileFormat, tile_size: int,
                    factors: list[int]) -> None:
    """Give every tile a client may ask for a file, reusing dzsave's file for the same pixels.

    What dzsave wrote is listed once (``region/size`` folders), so only the few missing paths
    cost any file-system calls.
    """
    width, height = image.width, image.height
    wanted = set(geo.osd_tile_paths(width, height, tile_size, factors)) | {
        geo.canonical_path(width, height, t)
        for f in factors
        for t in geo.spec_tiles(width, height, tile_size, f)
    }
    name = f"default.{fmt.ext}"
    written = {f"{region.name}/{size.name}"
               for region in os.scandir(out_dir) if region.is_dir()
               for size in os.scandir(region.path)
               if os.path.isfile(os.path.join(size.path, "0", name))}
    for path in sorted(wanted - written):
        _ensure(image, out_dir, fmt, geo.parse_region_size(width, height, path), path)


def _ensure(image: pyvips.Image, out_dir: Path, fmt: TileFormat, req: geo.TileRequest,
            path: str | None = None,
            source: Callable[[], pyvips.Image | None] | None = None) -> None:
    """Make sure the request ``req`` (at URL ``path``, else its canonical path) has a file.

    An existing file for the same pixels is hard-linked; otherwise ``source()`` (if given and
    not None) is saved, else the request is rendered from ``image``.
    """
    width, height = image.width, image.height
    path = path or geo.canonical_path(width, height, req)
    target = _tile_file(out_dir, path, fmt.ext)
    if target.exists():
        return
    target.parent.mkdir(parents=True, exist_ok=True)
    for alias in _aliases(width, height, req):
        existing = _tile_file(out_dir, alias, fmt.ext)
        if existing.exists():
            os.link(existing, target)
            return
    made = source() if source is not None else None
    if made is not None and (made.width, made.height) == (req.sw, req.sh):
        save(made, target, fmt)
    else:
        _render(image, req, target, fmt)


def _level_from_tiles(out_dir: Path, fmt: str, width: int, height: int, tile_size: int,
                      factor: int) -> Callable[[], pyvips.Image | None]:
    """Return a maker of the whole level ``factor`` joined from its tile files (None at 1).

    The level's tiles (the spec's grid, all present after :func:`_complete_tiles`) are exactly
    the level's pixels, so a ``sizes`` entry costs decoding them, not resizing the full image.
    """
    def make() -> pyvips.Image | None:
        if factor == 1:  # the full image: render it from the source, not from re-decoded tiles
            return None
        tiles = list(geo.spec_tiles(width, height, tile_size, factor))
        across = -(-width // (tile_size * factor))
        images = [pyvips.Image.new_from_file(
            str(_tile_file(out_dir, geo.canonical_path(width, height, t), fmt)),
            access="sequential") for t in tiles]
        if len(images) == 1:
            return images[0]
        # arrayjoin's cells are all tile_size square, the smaller edge tiles sitting at their
        # cells' top left: exactly the level's layout, plus a margin to crop off
        joined = pyvips.Image.arrayjoin(images, across=across)
        return joined.crop(0, 0, *geo.level_size(width, height, factor))

    return make


def _aliases(width: int, height: int, req: geo.TileRequest) -> list[str]:
    """Return the other region/size spellings dzsave may have used for the same request."""
    full = (req.x, req.y, req.w, req.h) == (0, 0, width, height)
    regions = ["full", f"0,0,{width},{height}"] if full else [f"{req.x},{req.y},{req.w},{req.h}"]
    sizes = [f"{req.sw},{req.sh}"] + (["max"] if (req.sw, req.sh) == (req.w, req.h) else [])
    return [f"{r}/{s}" for r in regions for s in sizes]


def _render(image: pyvips.Image, req: geo.TileRequest, target: Path, fmt: TileFormat) -> None:
    region = image.crop(req.x, req.y, req.w, req.h)
    if (req.sw, req.sh) != (req.w, req.h):
        region = region.resize(req.sw / req.w, vscale=req.sh / req.h)
    save(region, target, fmt)
