"""Write one image as a IIIF Image API 3 level-0 pyramid with pyvips ``dzsave``, gaps fixed.

``dzsave(layout="iiif3")`` writes the tiles; then :func:`write_pyramid` makes the tree complete
for level 0 and for the clients we support (see ``docs/dataset-format.md``, "Pyramids"):
``sizes``, ``full/max`` in jpg (and png), ``preferredFormats``/``extraFormats`` for PNG trees,
``maxWidth``/``maxHeight`` past the JPEG limit, and every tile URL OpenSeadragon or the spec's
algorithm asks for, including single-tile images.
"""

from __future__ import annotations

import json
import os
import shutil
import tempfile
from pathlib import Path
from typing import Any

import numpy as np
import numpy.typing as npt
import pyvips

from . import iiif_geometry as geo

IMAGE_CONTEXT = "http://iiif.io/api/image/3/context.json"
#: Largest side of the ``sizes`` entries we list (and so must serve as whole images).
SIZES_LIMIT = 2048
JPEG_QUALITY = 90


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
    fmt: str = "png",
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
        ``"png"`` (lossless: coefficient planes) or ``"jpg"`` (Q90, 4:4:4).

    Returns
    -------
    The info.json document written.
    """
    if fmt not in ("png", "jpg"):
        raise ValueError(f"unknown tile format {fmt!r}")
    out_dir = Path(out_dir)
    if out_dir.exists():
        raise FileExistsError(out_dir)
    width, height = image.width, image.height
    scratch = Path(tempfile.mkdtemp(prefix=".dz-", dir=out_dir.parent))
    try:
        save: dict[str, Any] = {"layout": "iiif3", "tile_size": tile_size, "overlap": 0}
        if fmt == "png":
            save["suffix"] = ".png[compression=3]"
        else:
            save["Q"] = JPEG_QUALITY
        image.dzsave(str(scratch / out_dir.name), id="http://lanterna.invalid", **save)
        (scratch / out_dir.name).rename(out_dir)
    finally:
        shutil.rmtree(scratch, ignore_errors=True)

    factors = geo.scale_factors(width, height, tile_size)
    _complete_tiles(image, out_dir, fmt, tile_size, factors)
    info = _info_json(width, height, service_id, fmt, tile_size, factors)
    for size in info.get("sizes", []):
        sw, sh = size["width"], size["height"]
        _ensure(image, out_dir, fmt, geo.TileRequest(0, 0, width, height, sw, sh),
                f"full/{sw},{sh}")
    _write_full_max(image, out_dir, fmt)
    (out_dir / "info.json").write_text(json.dumps(info, indent=2))
    return info


def _info_json(width: int, height: int, service_id: str, fmt: str, tile_size: int,
               factors: list[int]) -> dict[str, Any]:
    info: dict[str, Any] = {
        "@context": IMAGE_CONTEXT,
        "id": service_id,
        "type": "ImageService3",
        "protocol": "http://iiif.io/api/image",
        "profile": "level0",
        "width": width,
        "height": height,
    }
    max_w, max_h = geo.constrained_max(width, height)
    if (max_w, max_h) != (width, height):
        info["maxWidth"], info["maxHeight"] = max_w, max_h
    sizes = [geo.level_size(width, height, f) for f in reversed(factors)]
    info["sizes"] = [{"width": w, "height": h} for w, h in sizes if max(w, h) <= SIZES_LIMIT]
    if not info["sizes"]:
        del info["sizes"]
    info["tiles"] = [{"width": tile_size, "height": tile_size, "scaleFactors": factors}]
    if fmt == "png":
        info["preferredFormats"] = ["png"]
        info["extraFormats"] = ["png"]
    return info


def _tile_file(out_dir: Path, path: str, fmt: str) -> Path:
    return out_dir / path / "0" / f"default.{fmt}"


def _complete_tiles(image: pyvips.Image, out_dir: Path, fmt: str, tile_size: int,
                    factors: list[int]) -> None:
    """Give every tile a client may ask for a file, reusing dzsave's file for the same pixels."""
    width, height = image.width, image.height
    for path in set(geo.osd_tile_paths(width, height, tile_size, factors)) | {
        geo.canonical_path(width, height, t)
        for f in factors
        for t in geo.spec_tiles(width, height, tile_size, f)
    }:
        _ensure(image, out_dir, fmt, geo.parse_region_size(width, height, path), path)


def _ensure(image: pyvips.Image, out_dir: Path, fmt: str, req: geo.TileRequest,
            path: str | None = None) -> None:
    """Make sure the request ``req`` (at URL ``path``, else its canonical path) has a file."""
    width, height = image.width, image.height
    path = path or geo.canonical_path(width, height, req)
    target = _tile_file(out_dir, path, fmt)
    if target.exists():
        return
    target.parent.mkdir(parents=True, exist_ok=True)
    for alias in _aliases(width, height, req):
        source = _tile_file(out_dir, alias, fmt)
        if source.exists():
            os.link(source, target)
            return
    _render(image, req, target)


def _aliases(width: int, height: int, req: geo.TileRequest) -> list[str]:
    """Return the other region/size spellings dzsave may have used for the same request."""
    full = (req.x, req.y, req.w, req.h) == (0, 0, width, height)
    regions = ["full", f"0,0,{width},{height}"] if full else [f"{req.x},{req.y},{req.w},{req.h}"]
    sizes = [f"{req.sw},{req.sh}"] + (["max"] if (req.sw, req.sh) == (req.w, req.h) else [])
    return [f"{r}/{s}" for r in regions for s in sizes]


def _render(image: pyvips.Image, req: geo.TileRequest, target: Path) -> None:
    region = image.crop(req.x, req.y, req.w, req.h)
    if (req.sw, req.sh) != (req.w, req.h):
        region = region.resize(req.sw / req.w, vscale=req.sh / req.h)
    _save(region, target)


def _save(image: pyvips.Image, target: Path) -> None:
    if target.suffix == ".png":
        image.pngsave(str(target), compression=3)
    else:
        if image.hasalpha():
            image = image.flatten()
        image.jpegsave(str(target), Q=JPEG_QUALITY)


def _write_full_max(image: pyvips.Image, out_dir: Path, fmt: str) -> None:
    """Write ``full/max/0/default.jpg`` (required at level 0) and ``.png`` for PNG trees."""
    w, h = geo.constrained_max(image.width, image.height)
    for ext in {"jpg", fmt}:
        _ensure(image, out_dir, ext, geo.TileRequest(0, 0, image.width, image.height, w, h),
                "full/max")
