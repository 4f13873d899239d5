"""What a dataset version says about a layer's overlay: its layer entry, its pyramid, its build.

Shared by the builders (:mod:`.build`, :mod:`.rebuild`) and the patch store (:mod:`.store`):
the report of a build, the level image ids (``{layer}_ov{L}``, ``{layer}_ov{L}_b{N}`` from build 2
on: docs/annotations.md "Rebuilds"), the layer's canvas and deepest level, and reading a published
level image back whole.
"""

from __future__ import annotations

import json
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
import numpy.typing as npt
import pyvips

from lanterna.errors import LanternaInputError
from lanterna.tiler.dataset.writer import read_description
from lanterna.tiler.iiif import geometry as geo

from . import geometry as og


class OverlayInputError(LanternaInputError):
    """No overlay level could be built; ``errors`` holds the one-line error of each bad file."""

    def __init__(self, source: str | Path | None, problem: str, errors: list[str]) -> None:
        super().__init__(source, problem)
        self.errors = errors


@dataclass
class OverlayReport:
    """What a build did: levels written, patches used, per-file errors, the build number.

    ``build`` is 0 and ``changed`` False when a rebuild found the overlay up to date.
    """

    layer: str
    levels: list[int] = field(default_factory=list)
    patches: int = 0
    errors: list[str] = field(default_factory=list)
    warnings: list[str] = field(default_factory=list)
    build: int = 0
    fingerprint: str | None = None
    changed: bool = True


@dataclass(frozen=True)
class Canvas:
    """A layer's canvas: full-resolution size, deepest pyramid level, tile size."""

    width: int
    height: int
    deepest: int
    tile_size: int


def image_id(layer_id: str, level: int, build: int = 1) -> str:
    """Return the IIIF identifier of a layer's overlay level image in build ``build``."""
    return f"{layer_id}_ov{level}" if build <= 1 else f"{layer_id}_ov{level}_b{build}"


def find_layer(desc: Mapping[str, Any], layer_id: str, where: Path) -> dict[str, Any]:
    """The layer entry ``layer_id`` of a ``lanterna.json`` (a one-line error naming the others)."""
    layers: list[dict[str, Any]] = desc["layers"]
    for layer in layers:
        if layer["id"] == layer_id:
            return layer
    ids = ", ".join(layer["id"] for layer in layers)
    raise LanternaInputError(where, f"no layer {layer_id!r} (layers: {ids})")


def published_layer(dataset: Path, layer_id: str) -> dict[str, Any]:
    """The layer entry ``layer_id`` of the dataset's current ``lanterna.json``."""
    return find_layer(read_description(Path(dataset)), layer_id, Path(dataset))


def overlay_of(layer: Mapping[str, Any]) -> dict[str, Any]:
    """The layer's ``overlay`` entry, or an empty one."""
    overlay = layer.get("overlay")
    return overlay if isinstance(overlay, dict) else {}


def previous_levels(layer: Mapping[str, Any]) -> dict[int, dict[str, Any]]:
    """The layer's published overlay levels that have an image, by level."""
    return {int(e["level"]): e for e in overlay_of(layer).get("levels", [])
            if isinstance(e, dict) and isinstance(e.get("image"), str)}


def build_number(layer: Mapping[str, Any]) -> int:
    """The build number of the layer's published overlay: 0 if none, 1 if it has no ``build``."""
    overlay = overlay_of(layer)
    if not overlay:
        return 0
    build = overlay.get("build", 1)
    return build if isinstance(build, int) and build >= 1 else 1


def canvas_of(dataset: Path, desc: Mapping[str, Any], layer: Mapping[str, Any]) -> Canvas:
    """The canvas of a layer: the dataset's size, the deepest level of the layer's own pyramid."""
    path = Path(dataset) / "iiif" / str(layer["body"]) / "info.json"
    try:
        tiles = json.loads(path.read_text())["tiles"][0]
        deepest, tile = og.max_level(tiles["scaleFactors"]), int(tiles["width"])
    except (OSError, ValueError, KeyError, IndexError, TypeError):
        raise LanternaInputError(path, "cannot read the layer's pyramid") from None
    return Canvas(int(desc["width"]), int(desc["height"]), deepest, tile)


def read_level_image(version: Path, ident: str) -> npt.NDArray[np.uint8]:
    """Read a published overlay level image whole (RGBA), joined from its full-size tiles."""
    folder = Path(version) / "iiif" / ident
    try:
        info = json.loads((folder / "info.json").read_text())
        width, height = int(info["width"]), int(info["height"])
        tile = int(info["tiles"][0]["width"])
        tiles = list(geo.spec_tiles(width, height, tile, 1))
        images = [pyvips.Image.new_from_file(
            str(folder / geo.canonical_path(width, height, t) / "0" / "default.png"))
            for t in tiles]
        joined = images[0] if len(images) == 1 else pyvips.Image.arrayjoin(
            images, across=-(-width // tile)).crop(0, 0, width, height)
        if joined.bands != 4:
            raise LanternaInputError(folder, "the overlay level image has no alpha channel")
        return np.ascontiguousarray(joined.numpy(), dtype=np.uint8)
    except (OSError, ValueError, KeyError, IndexError, TypeError, pyvips.Error):
        raise LanternaInputError(folder, "cannot read the published overlay level image") from None
