"""Read one pyramid level of a layer's stored tiles (what the browser gets) as float32 channels."""

from __future__ import annotations

import json
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np
import numpy.typing as npt
import pyvips

from lanterna.tiler.iiif import geometry as geo

from .shading import F32

Region = tuple[int, int, int, int]


def level_image(image_dir: Path, factor: int, fmt: str = "png") -> npt.NDArray[np.uint8]:
    """Assemble the level of scale factor ``factor`` of a stored IIIF image from its tile files.

    Parameters
    ----------
    image_dir:
        The image's folder (holding ``info.json``).
    factor:
        One of the image's scale factors (1 = full resolution).
    fmt:
        Tile format, ``png`` or ``jpg``.

    Returns
    -------
    numpy.ndarray
        uint8 ``(h, w, bands)`` with ``(w, h) = ceil((W, H)/factor)``.
    """
    info = json.loads((image_dir / "info.json").read_text())
    width, height = int(info["width"]), int(info["height"])
    tiles = info["tiles"][0]
    if factor not in tiles["scaleFactors"]:
        raise ValueError(f"{image_dir.name}: no level with scale factor {factor}")
    tile = int(tiles["width"])
    lw, lh = geo.level_size(width, height, factor)
    out: npt.NDArray[np.uint8] | None = None
    for t in geo.spec_tiles(width, height, tile, factor):
        path = image_dir / geo.canonical_path(width, height, t) / "0" / f"default.{fmt}"
        px = pyvips.Image.new_from_file(str(path)).numpy()
        px = px.reshape(px.shape[:2] + (-1,))
        if px.shape[:2] != (t.sh, t.sw):
            raise ValueError(f"{path}: tile is {px.shape[1]}x{px.shape[0]}, expected "
                             f"{t.sw}x{t.sh}")
        if out is None:
            out = np.zeros((lh, lw, px.shape[2]), np.uint8)
        y, x = t.y // factor, t.x // factor
        out[y: y + t.sh, x: x + t.sw] = px
    assert out is not None
    return out


def level_channels(dataset_dir: str | Path, layer: Mapping[str, Any], factor: int,
                   region: Region | None = None) -> dict[str, F32]:
    """Dequantise every channel of a layer at one pyramid level: ``(t − bias)·scale``.

    Parameters
    ----------
    dataset_dir:
        The dataset folder (holding ``iiif/``).
    layer:
        The layer's relight service block (``planes`` with ``service.id``, ``format``,
        ``channels``, ``scale``, ``bias``).
    factor:
        Scale factor of the level (1, 2, 4, …).
    region:
        Optional ``(x, y, w, h)`` crop in level pixels.

    Returns
    -------
    dict
        Channel name → float32 ``(h, w)`` values (``t`` = texel/255). A 1-channel group reads
        the first band of its image.
    """
    root = Path(dataset_dir)
    out: dict[str, F32] = {}
    for plane in layer["planes"]:
        image_id = str(plane["service"]["id"]).rstrip("/").rsplit("/", 1)[1]
        px = level_image(root / "iiif" / image_id, factor, plane.get("format", "png"))
        if region is not None:
            x, y, w, h = region
            if x < 0 or y < 0 or x + w > px.shape[1] or y + h > px.shape[0]:
                raise ValueError(f"region {region} is outside the level ({px.shape[1]}x"
                                 f"{px.shape[0]})")
            px = px[y: y + h, x: x + w]
        out.update(dequantise(px, plane["channels"], plane["scale"], plane["bias"]))
    return out


def dequantise(px: npt.NDArray[np.uint8], channels: Sequence[str], scale: Sequence[float],
               bias: Sequence[float]) -> dict[str, F32]:
    """The channels of one stored image ``px`` (``(h, w, bands)`` or ``(h, w)`` bytes), each
    ``(t − bias)·scale`` with ``t`` = byte/255, in float32; a 1-channel group reads the first
    band."""
    t = px.astype(np.float32) / np.float32(255)
    t = t.reshape(*t.shape[:2], -1)
    out: dict[str, F32] = {}
    for k, name in enumerate(channels):
        band = t[..., k] if t.shape[2] > 1 else t[..., 0]
        out[name] = ((band - np.float32(bias[k])) * np.float32(scale[k])).astype(np.float32)
    return out
