"""Turn source files (a .ptm, a plain image) into datasets."""

from __future__ import annotations

from pathlib import Path

import pyvips

from .dataset import DEFAULT_BASE_URL, DatasetWriter, check_identifier
from .errors import LanternaInputError
from .layers import add_image_layer, add_ptm_layer

IMAGE_SUFFIXES = {".png", ".jpg", ".jpeg", ".tif", ".tiff", ".webp"}


def load_rgb_image(path: Path) -> pyvips.Image:
    """Load an image file as 8-bit sRGB without alpha, with a clear error if it can't be read."""
    try:
        img = pyvips.Image.new_from_file(str(path), access="sequential")
        if img.hasalpha():
            img = img.flatten(background=[0, 0, 0])
        if img.interpretation not in ("srgb", "b-w") or img.format != "uchar":
            img = img.colourspace("srgb").cast("uchar")
        if img.bands == 1:
            img = img.bandjoin([img, img])
        img = img.copy_memory()
    except pyvips.Error as err:
        first = str(err).strip().splitlines()[0] if str(err).strip() else "unreadable image"
        raise LanternaInputError(path, f"cannot read image ({first})") from None
    return img.copy(interpretation="srgb")


def import_source(source: Path, out: Path, *, name: str | None = None, label: str | None = None,
                  base_url: str = DEFAULT_BASE_URL, tile_size: int = 256,
                  force: bool = False) -> Path:
    """Import one source file (``.ptm`` or an image) as the dataset ``out``; return ``out``."""
    from .ptm import read_ptm

    source = Path(source)
    if not source.is_file():
        raise LanternaInputError(source, "no such file")
    name = check_identifier(name or _safe_name(out.name), "dataset name")
    label = label or source.stem
    suffix = source.suffix.lower()
    if suffix == ".ptm":
        ptm = read_ptm(source)
        with DatasetWriter(out, name=name, label=label, width=ptm.width, height=ptm.height,
                           base_url=base_url, tile_size=tile_size, source=source.name,
                           force=force) as ds:
            add_ptm_layer(ds, ptm, label=f"{label} (PTM {ptm.colorspace.upper()})")
    elif suffix in IMAGE_SUFFIXES:
        img = load_rgb_image(source)
        with DatasetWriter(out, name=name, label=label, width=img.width, height=img.height,
                           base_url=base_url, tile_size=tile_size, source=source.name,
                           force=force) as ds:
            add_image_layer(ds, img, label=label)
    else:
        raise LanternaInputError(source, f"unknown source type {suffix or '(no suffix)'}; "
                                 "expected .ptm or an image (.png, .jpg, .tif, .webp)")
    return out


def _safe_name(stem: str) -> str:
    cleaned = "".join(ch if ch.isalnum() or ch == "_" else "_" for ch in stem)
    return cleaned or "dataset"
