"""Multi-scale annotation overlays: level images from patches, GIMP levels or a seed-paper scene.

The contract is docs/annotations.md. A layer's overlay is a set of transparent RGBA level images
(``{layer}_ov{L}``, PNG pyramids) with a short and a long hypertext per level, plus the metadata of
the patches they were composited from. :func:`build_overlays` rewrites a dataset atomically (the
previous overlay stays until the new one is complete); :func:`scene_overlay` builds the levels of a
seed-paper scene's ``overlay`` entry during an import. The pure geometry is in
:mod:`.geometry`, the compositing in :mod:`.composite`, the sources in :mod:`.patches`.
"""

from __future__ import annotations

import json
import logging
import shutil
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import pyvips

from lanterna.errors import LanternaInputError
from lanterna.tiler.dataset.publish import writing
from lanterna.tiler.dataset.writer import DatasetWriter, read_description, rewriting
from lanterna.tiler.iiif.geometry import scale_factors
from lanterna.tiler.iiif.pyramid import write_pyramid

from . import geometry as og
from .composite import fit_level_image, load_rgba
from .patches import levels_from_gimp, levels_from_patches, read_texts

log = logging.getLogger("lanterna.overlays")


class OverlayInputError(LanternaInputError):
    """No overlay level could be built; ``errors`` holds the one-line error of each bad file."""

    def __init__(self, source: str | Path | None, problem: str, errors: list[str]) -> None:
        super().__init__(source, problem)
        self.errors = errors


@dataclass
class OverlayReport:
    """What :func:`build_overlays` did: levels written, patches used, per-file errors."""

    layer: str
    levels: list[int] = field(default_factory=list)
    patches: int = 0
    errors: list[str] = field(default_factory=list)
    warnings: list[str] = field(default_factory=list)


def image_id(layer_id: str, level: int) -> str:
    """Return the IIIF identifier of a layer's overlay level image."""
    return f"{layer_id}_ov{level}"


def build_overlays(dataset_dir: Path, layer_id: str, *, patches_dir: Path | None = None,
                   gimp_dir: Path | None = None,
                   texts: Path | Mapping[Any, Any] | None = None) -> OverlayReport:
    """Build (or replace) the overlay of layer ``layer_id`` of a dataset.

    Parameters
    ----------
    dataset_dir:
        The dataset folder (with ``lanterna.json``).
    layer_id:
        The layer the overlay belongs to.
    patches_dir:
        A folder of ``L_X_Y_W_H_O_INFO.png`` patches (docs/annotations.md).
    gimp_dir:
        Instead of patches, a folder of one transparent image per level (``level_L.png``).
    texts:
        ``{"L": {"short": …, "long": …}}`` as a JSON file or a mapping. A level without an entry
        keeps the texts it had in the previous overlay.

    Returns
    -------
    The report; ``errors`` lists the rejected files (the valid ones are built).

    Raises
    ------
    OverlayInputError
        When no level can be built (the dataset is then unchanged).
    """
    if (patches_dir is None) == (gimp_dir is None):
        raise ValueError("give exactly one of patches_dir and gimp_dir")
    dataset_dir = Path(dataset_dir)
    with writing(dataset_dir):  # from the first read to the publish: no lost update
        return _build(dataset_dir, layer_id, patches_dir, gimp_dir, texts)


def _build(dataset_dir: Path, layer_id: str, patches_dir: Path | None, gimp_dir: Path | None,
           texts: Path | Mapping[Any, Any] | None) -> OverlayReport:
    desc = read_description(dataset_dir)
    layer = _find_layer(desc, layer_id, dataset_dir)
    width, height = int(desc["width"]), int(desc["height"])
    deepest, tile_size = _pyramid_of(dataset_dir, layer["body"])
    new_texts = read_texts(texts)
    report = OverlayReport(layer_id)
    patches: list[og.Patch] = []
    if patches_dir is not None:
        source = Path(patches_dir)
        levels, patches, report.errors = levels_from_patches(source, width, height, deepest)
    else:
        source = Path(gimp_dir)  # type: ignore[arg-type]
        levels, report.errors = levels_from_gimp(source, width, height, deepest)
    if not levels:
        problem = (f"no valid {'patches' if patches_dir is not None else 'level images'}"
                   f"{f' ({len(report.errors)} file(s) rejected)' if report.errors else ''}; "
                   "the dataset is unchanged")
        raise OverlayInputError(source, problem, report.errors)
    for level in sorted(set(new_texts) - set(levels)):
        report.warnings.append(f"texts for level {level} ignored: no overlay image at that level")

    previous = _previous_levels(layer)
    old_images = {e["image"] for e in previous.values()}
    clash = sorted(ident for ident in (image_id(layer_id, lv) for lv in levels)
                   if ident in desc.get("images", {}) and ident not in old_images)
    if clash:
        raise LanternaInputError(dataset_dir, f"image id(s) {', '.join(clash)} already used by "
                                 "something other than this layer's overlay")

    with rewriting(dataset_dir) as (tmp, new_desc):
        new_layer = _find_layer(new_desc, layer_id, dataset_dir)
        for entry in previous.values():  # an old overlay's images go; the new ones are rewritten
            shutil.rmtree(tmp / "iiif" / entry["image"], ignore_errors=True)
            new_desc["images"].pop(entry["image"], None)
        entries = []
        ds_url = f"{new_desc['baseUrl'].rstrip('/')}/{new_desc['name']}"
        for level, rgba in sorted(levels.items()):
            ident = image_id(layer_id, level)
            shutil.rmtree(tmp / "iiif" / ident, ignore_errors=True)
            (tmp / "iiif").mkdir(exist_ok=True)
            write_pyramid(pyvips.Image.new_from_array(rgba).copy(interpretation="srgb"),
                          tmp / "iiif" / ident, f"{ds_url}/iiif/{ident}", fmt="png",
                          tile_size=tile_size)
            h, w = rgba.shape[:2]
            new_desc["images"][ident] = {"format": "png", "width": w, "height": h, "bands": 4}
            text = new_texts.get(level) or previous.get(level) or {}
            entries.append({"level": level, "image": ident, "width": w, "height": h,
                            "short": text.get("short", ""), "long": text.get("long", "")})
        new_layer["overlay"] = {
            "source": "patches" if patches_dir is not None else "gimp",
            "levels": entries,
            "patches": [{"level": p.level, "x": p.x, "y": p.y, "w": p.w, "h": p.h,
                         "order": p.order, "info": p.info, "file": p.file} for p in patches],
        }
    report.levels = sorted(levels)
    report.patches = len(patches)
    return report


def scene_overlay(ds: DatasetWriter, layer_id: str, raw: Mapping[str, Any],
                  base: Path) -> dict[str, Any]:
    """Build the levels of a seed-paper scene ``overlay`` entry while importing a dataset.

    ``img`` is a template completed by a two-digit level (``vis/overlay.png`` →
    ``vis/overlay02.png``, relative to ``base``); ``range [a, b]`` (inclusive) lists the levels,
    ``shortInfo``/``longInfo`` their texts. Missing or unusable level images are warnings (the
    import goes on, the texts stay in the entry); the scene's own keys are kept as given.
    """
    result: dict[str, Any] = {**raw, "source": "scene", "levels": [], "patches": []}
    template, span = raw.get("img"), raw.get("range")
    if not isinstance(template, str) or not (
            isinstance(span, list) and len(span) == 2 and all(isinstance(v, int) for v in span)):
        log.warning("layer %s: overlay needs \"img\" and \"range\": [a, b]; kept as text only",
                    layer_id)
        return result
    shorts, longs = raw.get("shortInfo") or [], raw.get("longInfo") or []
    deepest = og.max_level(scale_factors(ds.width, ds.height, ds.tile_size))
    first, last = max(0, span[0]), min(span[1], deepest)
    if span[1] > deepest or span[0] < 0:
        log.warning("layer %s: overlay range [%s, %s] is clamped to the pyramid's levels 0–%d",
                    layer_id, span[0], span[1], deepest)
    stem = base / template
    for level in range(first, last + 1):
        i = level - span[0]
        path = stem.with_name(f"{stem.stem}{level:02d}{stem.suffix}")
        try:
            if not path.is_file():
                raise LanternaInputError(path, "missing: this overlay level has texts only")
            rgba = fit_level_image(load_rgba(path), level, ds.width, ds.height, path)
        except LanternaInputError as err:
            log.warning("layer %s: overlay %s", layer_id, err)
            continue
        h, w = rgba.shape[:2]
        ident = image_id(layer_id, level)
        ds.add_image(ident, pyvips.Image.new_from_array(rgba).copy(interpretation="srgb"),
                     fmt="png", size=(w, h))
        result["levels"].append({
            "level": level, "image": ident, "width": w, "height": h,
            "short": str(shorts[i]) if i < len(shorts) else "",
            "long": str(longs[i]) if i < len(longs) else ""})
    return result


def overlay_summary(dataset_dir: Path) -> list[dict[str, Any]]:
    """Return, per layer, its overlay levels with texts and its patch count (``annotate list``)."""
    return overlay_rows(read_description(Path(dataset_dir)))


def overlay_rows(desc: Mapping[str, Any]) -> list[dict[str, Any]]:
    """:func:`overlay_summary` of a parsed ``lanterna.json``."""
    rows = []
    for layer in desc["layers"]:
        overlay = layer.get("overlay")
        levels = overlay.get("levels", []) if isinstance(overlay, dict) else []
        patches = overlay.get("patches", []) if isinstance(overlay, dict) else []
        rows.append({"id": layer["id"], "label": layer["label"], "levels": levels,
                     "patches": len(patches),
                     "source": overlay.get("source") if isinstance(overlay, dict) else None})
    return rows


def _find_layer(desc: dict[str, Any], layer_id: str, where: Path) -> dict[str, Any]:
    layers: list[dict[str, Any]] = desc["layers"]
    for layer in layers:
        if layer["id"] == layer_id:
            return layer
    ids = ", ".join(layer["id"] for layer in layers)
    raise LanternaInputError(where, f"no layer {layer_id!r} (layers: {ids})")


def _previous_levels(layer: Mapping[str, Any]) -> dict[int, dict[str, Any]]:
    overlay = layer.get("overlay")
    if not isinstance(overlay, dict):
        return {}
    return {int(e["level"]): e for e in overlay.get("levels", [])
            if isinstance(e, dict) and isinstance(e.get("image"), str)}


def _pyramid_of(dataset_dir: Path, image: str) -> tuple[int, int]:
    """Return the deepest level and the tile size of a stored image's pyramid."""
    path = dataset_dir / "iiif" / image / "info.json"
    try:
        tiles = json.loads(path.read_text())["tiles"][0]
        return og.max_level(tiles["scaleFactors"]), int(tiles["width"])
    except (OSError, ValueError, KeyError, IndexError, TypeError):
        raise LanternaInputError(path, "cannot read the layer's pyramid") from None
