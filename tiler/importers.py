"""Turn source files (a .ptm, a plain image) into dataset layers."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np
import pyvips

from .dataset import DEFAULT_BASE_URL, DatasetWriter, check_identifier
from .errors import LanternaInputError
from .ptm_model import PTM_BASIS, Ptm

IMAGE_SUFFIXES = {".png", ".jpg", ".jpeg", ".tif", ".tiff", ".webp"}


def add_ptm_layer(ds: DatasetWriter, ptm: Ptm, *, layer_id: str = "ptm",
                  label: str = "PTM") -> dict[str, Any]:
    """Tile the planes of ``ptm`` (3 per image, the PTM's own bytes) and add it as a layer.

    The file's ``a = (byte − b)·s`` in 0–255 units becomes ``(t − b/255)·s`` with ``t`` in
    0–1 (docs/dataset-format.md), so the stored texels are exactly the PTM's bytes.
    """
    scale = [float(s) for s in ptm.scale]
    bias = [float(b) / 255.0 for b in ptm.bias]
    planes: list[dict[str, Any]] = []

    def group(ident: str, data: np.ndarray, channels: list[str], sc: list[float],
              bi: list[float]) -> None:
        svc = ds.add_image(ident, np.ascontiguousarray(data), fmt="png")
        planes.append({"service": svc, "format": "png", "channels": channels,
                       "scale": sc, "bias": bi})

    if ptm.colorspace == "lrgb":
        assert ptm.rgb is not None
        for g in range(2):
            k = slice(3 * g, 3 * g + 3)
            group(f"{layer_id}_c{g}", ptm.coefficients[..., k],
                  [f"L{i}" for i in range(3 * g, 3 * g + 3)], scale[k], bias[k])
        group(f"{layer_id}_color", ptm.rgb, ["R", "G", "B"], [1.0] * 3, [0.0] * 3)
    else:
        for c, name in enumerate("RGB"):
            for g in range(2):
                k = slice(3 * g, 3 * g + 3)
                group(f"{layer_id}_{name.lower()}{g}", ptm.coefficients[:, :, c, k],
                      [f"{name}{i}" for i in range(3 * g, 3 * g + 3)], scale[k], bias[k])
    preview = np.round(ptm.relight(0.0, 0.0) * 255.0).astype(np.uint8)
    ds.add_image(f"{layer_id}_preview", preview, fmt="jpg")
    layer = {"id": layer_id, "label": label, "body": f"{layer_id}_preview", "layerType": "ptm",
             "colorspace": ptm.colorspace, "basis": list(PTM_BASIS), "planes": planes}
    ds.add_layer(layer)
    return layer


def add_image_layer(ds: DatasetWriter, image: pyvips.Image, *, layer_id: str = "image",
                    label: str = "Image", fmt: str = "jpg") -> dict[str, Any]:
    """Add a plain (unshaded) RGB image layer."""
    svc = ds.add_image(layer_id, image, fmt=fmt)
    layer = {"id": layer_id, "label": label, "body": layer_id, "layerType": "image",
             "planes": [{"service": svc, "format": fmt, "channels": ["R", "G", "B"],
                         "scale": [1.0] * 3, "bias": [0.0] * 3}]}
    ds.add_layer(layer)
    return layer


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
