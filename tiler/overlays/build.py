"""Multi-scale annotation overlays: level images from patches, GIMP levels or a seed-paper scene.

The contract is docs/annotations.md. A layer's overlay is a set of transparent RGBA level images
(``{layer}_ov{L}``, PNG pyramids) with a short and a long hypertext per level, plus the metadata of
the patches they were composited from. :func:`build_overlays` rewrites a dataset atomically (the
previous overlay stays until the new one is complete); :func:`scene_overlay` builds the levels of a
seed-paper scene's ``overlay`` entry during an import. The pure geometry is in
:mod:`.geometry`, the compositing in :mod:`.composite`, the sources in :mod:`.patches`.
"""

from __future__ import annotations

import logging
from collections.abc import Mapping
from pathlib import Path
from typing import Any

import pyvips

from lanterna.errors import LanternaInputError
from lanterna.tiler.dataset.writer import DatasetWriter, read_description
from lanterna.tiler.iiif.geometry import scale_factors

from . import geometry as og
from . import store
from .composite import drawn_box, fit_level_image, load_rgba
from .patches import levels_from_gimp, levels_from_patches, read_texts
from .published import OverlayInputError, OverlayReport, canvas_of, find_layer, image_id
from .rebuild import rebuild_from_store

__all__ = ["OverlayInputError", "OverlayReport", "build_overlays", "image_id", "overlay_rows",
           "overlay_summary", "scene_overlay"]

log = logging.getLogger("lanterna.overlays")


def build_overlays(dataset_dir: Path, layer_id: str, *, patches_dir: Path | None = None,
                   gimp_dir: Path | None = None, texts: Path | Mapping[Any, Any] | None = None,
                   replace: bool = False) -> OverlayReport:
    """Put patches, level images or texts into a layer's patch store, then rebuild its overlay.

    Parameters
    ----------
    dataset_dir:
        The dataset folder (with ``lanterna.json``).
    layer_id:
        The layer the overlay belongs to.
    patches_dir:
        A folder of ``L_X_Y_W_H_O_INFO.png`` patches (docs/annotations.md), added to the store
        (a patch of the same name is replaced).
    gimp_dir:
        A folder of one transparent image per level (``level_L.png``), each put in the store as a
        whole-canvas patch ``L_0_0_W_H_0_level.png`` (earlier ``_level`` patches go).
    texts:
        ``{"L": {"short": …, "long": …}}`` as a JSON file or a mapping, into ``levels.json``. A
        level without an entry keeps its texts.
    replace:
        Empty the layer's store first (only ``patches_dir``/``gimp_dir`` remain).

    With no source at all the overlay is rebuilt from the store as it is (if it changed).

    Returns
    -------
    The report; ``errors`` lists the rejected files (the valid ones are built).

    Raises
    ------
    OverlayInputError
        When a source is given and none of its files is valid (store and dataset unchanged).
    """
    if patches_dir is not None and gimp_dir is not None:
        raise ValueError("give at most one of patches_dir and gimp_dir")
    dataset_dir = Path(dataset_dir)
    desc = read_description(dataset_dir)
    canvas = canvas_of(dataset_dir, desc, find_layer(desc, layer_id, dataset_dir))
    new_texts = read_texts(texts)
    files: dict[str, bytes] = {}
    errors: list[str] = []
    if patches_dir is not None:
        source = Path(patches_dir)
        _, valid, errors = levels_from_patches(source, canvas.width, canvas.height,
                                               canvas.deepest)
        files = {p.file: (source / p.file).read_bytes() for p in valid}
    elif gimp_dir is not None:
        source = Path(gimp_dir)
        levels, errors = levels_from_gimp(source, canvas.width, canvas.height, canvas.deepest)
        files = {f"{lv}_0_0_{canvas.width}_{canvas.height}_0_level.png": store.encode_png(rgba)
                 for lv, rgba in levels.items()}
    if (patches_dir is not None or gimp_dir is not None) and not files:
        what = "patches" if patches_dir is not None else "level images"
        rejected = f" ({len(errors)} file(s) rejected)" if errors else ""
        raise OverlayInputError(source, f"no valid {what}{rejected}; the dataset is unchanged",
                                errors)
    _into_store(dataset_dir, layer_id, files, replace=replace, gimp=gimp_dir is not None,
                texts={str(k): v for k, v in new_texts.items() if k <= canvas.deepest})
    report = rebuild_from_store(dataset_dir, layer_id)
    report.errors = errors + report.errors
    for level in sorted(set(new_texts) - set(report.levels)):
        report.warnings.append(f"texts for level {level} ignored: no overlay image at that level")
    return report


def _into_store(dataset: Path, layer_id: str, files: Mapping[str, bytes], *, replace: bool,
                gimp: bool, texts: Mapping[str, Mapping[str, str]]) -> None:
    """Write ``files`` (name → PNG bytes) and ``texts`` into the layer's store, under its lock."""
    with store.store_lock(dataset):
        folder = store.store_dir(dataset, layer_id)
        if replace:
            store.store_root(dataset).mkdir(exist_ok=True)
            folder.mkdir(exist_ok=True)
        folder = store.ensure_store(dataset, layer_id)
        for path in sorted(folder.iterdir()):
            if path.name.startswith(".") or not path.is_file():
                continue
            level_patch = path.stem.endswith("_level") and path.suffix.lower() == ".png"
            if (replace and path.name != store.LEVEL_TEXTS) or (gimp and level_patch):
                path.unlink()
                if path.suffix.lower() == ".png":
                    (folder / f"{path.stem}.json").unlink(missing_ok=True)
        for name, data in files.items():
            store.put_file(folder, name, data)
    if texts:
        store.set_level_texts(dataset, layer_id, texts)


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
            "long": str(longs[i]) if i < len(longs) else "",
            **({"box": box} if (box := drawn_box(rgba, level, ds.width, ds.height)) else {})})
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
