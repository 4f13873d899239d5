"""Rebuilding a layer's overlay pyramid from its patch store (docs/annotations.md "Rebuilds").

:func:`rebuild_from_store` holds the dataset's write lock throughout; it takes the store's lock
only to hard-link the store into a snapshot (a hidden folder ``.snap-*`` of the store root, swept
by the next rebuild if this one is killed), composites the levels from the snapshot, and publishes
the next version atomically: the level pyramids under new ids (``{layer}_ov{L}_b{N}``), the
snapshot's patch PNGs at ``annotations/LAYER/{id}.png``, and the overlay entry with its build
number and the fingerprint of the store it was built from. A store unchanged since the published
build is not rebuilt. The previous build's level images stay in the new version (unlisted), so a
client that read the previous manifest still gets whole pyramids until the next publish after.
"""

from __future__ import annotations

import json
import os
import re
import shutil
import tempfile
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any

import pyvips

from lanterna.errors import LanternaInputError
from lanterna.tiler.dataset.output import write_errors
from lanterna.tiler.dataset.publish import writing
from lanterna.tiler.dataset.writer import link_or_copy, read_description, rewriting
from lanterna.tiler.iiif.pyramid import write_pyramid

from . import geometry as og
from . import store
from .composite import drawn_box
from .patches import levels_from_patches
from .published import (
    Canvas,
    OverlayReport,
    build_number,
    canvas_of,
    find_layer,
    image_id,
    overlay_of,
    previous_levels,
)


def published_fingerprint(layer: dict[str, Any]) -> str:
    """The fingerprint of the store the layer's published overlay was built from (that of an
    empty store when the layer has no overlay; None-like ``""`` for one not built from a store)."""
    overlay = overlay_of(layer)
    if not overlay:
        return store.EMPTY_FINGERPRINT
    value = overlay.get("fingerprint")
    return value if isinstance(value, str) else ""


def is_stale(dataset: Path, layer_id: str) -> bool:
    """Whether the layer has a store whose content differs from what its overlay was built from."""
    current = store.fingerprint(dataset, layer_id)
    if current is None:
        return False
    desc = read_description(Path(dataset))
    return current != published_fingerprint(find_layer(desc, layer_id, Path(dataset)))


def rebuild_from_store(dataset: Path, layer: str, *, force: bool = False) -> OverlayReport:
    """Bring the overlay of ``layer`` up to date with its patch store; return the report.

    ``changed`` is False (and nothing is written) when the published overlay was built from the
    store as it is, unless ``force``. A store without a valid patch publishes an overlay without
    levels (its build number and fingerprint kept: image ids are never reused).
    """
    dataset = Path(dataset)
    with writing(dataset):
        desc = read_description(dataset)
        entry = find_layer(desc, layer, dataset)
        canvas = canvas_of(dataset, desc, entry)
        snap = _new_snapshot(dataset)
        try:
            fingerprint = store.snapshot(dataset, layer, snap)
            if not force and fingerprint == published_fingerprint(entry):
                store_error(dataset, layer, None)  # nothing to fail: an earlier failure is moot
                overlay = overlay_of(entry)
                return OverlayReport(layer, levels=sorted(previous_levels(entry)),
                                     patches=len(overlay.get("patches", [])),
                                     build=build_number(entry), fingerprint=fingerprint,
                                     changed=False)
            with building(dataset, layer):
                report = _publish(dataset, entry, canvas, snap, fingerprint)
            store_error(dataset, layer, None)
            return report
        finally:
            shutil.rmtree(snap, ignore_errors=True)


def _new_snapshot(dataset: Path) -> Path:
    """Make an empty snapshot folder ``.snap-*`` in the dataset's store root (the same file
    system as the store, for hard links); remove those of killed rebuilds (we hold the dataset's
    lock, which every rebuild holds while its snapshot exists)."""
    root = store.store_root(dataset)
    with write_errors(dataset):
        root.mkdir(exist_ok=True)
        for entry in os.scandir(root):
            if entry.name.startswith(".snap-") and entry.is_dir(follow_symlinks=False):
                shutil.rmtree(root / entry.name, ignore_errors=True)
        return Path(tempfile.mkdtemp(prefix=".snap-", dir=root))


def _publish(dataset: Path, entry: dict[str, Any], canvas: Canvas, snap: Path,
             fingerprint: str) -> OverlayReport:
    layer_id = str(entry["id"])
    levels, patches, errors = levels_from_patches(snap / "patches", canvas.width, canvas.height,
                                                  canvas.deepest)
    texts = store.read_level_texts(snap / "meta" / store.LEVEL_TEXTS)
    build = build_number(entry) + 1
    report = OverlayReport(layer_id, levels=sorted(levels), patches=len(patches), errors=errors,
                           build=build, fingerprint=fingerprint)
    current = {e["image"] for e in previous_levels(entry).values()}
    images = read_description(dataset)["images"]
    clash = sorted(ident for ident in (image_id(layer_id, lv, build) for lv in levels)
                   if ident in images and ident not in current)
    if clash:
        raise LanternaInputError(dataset, f"image id(s) {', '.join(clash)} already used by "
                                 "something other than this layer's overlay")
    with rewriting(dataset) as (tmp, desc):
        layer = find_layer(desc, layer_id, dataset)
        _retire_images(tmp, desc, layer_id, current)
        entries = []
        ds_url = f"{desc['baseUrl'].rstrip('/')}/{desc['name']}"
        for level, rgba in sorted(levels.items()):
            ident = image_id(layer_id, level, build)
            shutil.rmtree(tmp / "iiif" / ident, ignore_errors=True)
            (tmp / "iiif").mkdir(exist_ok=True)
            write_pyramid(pyvips.Image.new_from_array(rgba).copy(interpretation="srgb"),
                          tmp / "iiif" / ident, f"{ds_url}/iiif/{ident}", fmt="png",
                          tile_size=canvas.tile_size)
            h, w = rgba.shape[:2]
            desc["images"][ident] = {"format": "png", "width": w, "height": h, "bands": 4}
            text = texts.get(str(level), {})
            entries.append({"level": level, "image": ident, "width": w, "height": h,
                            "short": text.get("short", ""), "long": text.get("long", ""),
                            **_box(rgba, level, canvas)})
        layer["overlay"] = {"source": "store", "build": build, "fingerprint": fingerprint,
                            "levels": entries,
                            "patches": _published_patches(tmp, layer_id, snap, patches)}
    return report


def _box(rgba: Any, level: int, canvas: Canvas) -> dict[str, list[int]]:
    """A level record's ``box``: the canvas region its drawing covers (none when empty)."""
    box = drawn_box(rgba, level, canvas.width, canvas.height)
    return {} if box is None else {"box": box}


def _retire_images(tmp: Path, desc: dict[str, Any], layer_id: str, current: set[str]) -> None:
    """Unlist the current build's level images (their folders stay one more version) and remove
    the folders of older builds."""
    pattern = re.compile(rf"^{re.escape(layer_id)}_ov\d+(?:_b\d+)?$")
    for ident in current:
        desc["images"].pop(ident, None)
    folder = tmp / "iiif"
    if not folder.is_dir():
        return
    for child in os.scandir(folder):
        if pattern.match(child.name) and child.name not in current \
                and child.name not in desc["images"]:
            shutil.rmtree(folder / child.name, ignore_errors=True)


def _published_patches(tmp: Path, layer_id: str, snap: Path,
                       patches: list[og.Patch]) -> list[dict[str, Any]]:
    """Copy the snapshot's valid patch PNGs into ``annotations/LAYER/``; return their records."""
    out = tmp / "annotations" / layer_id
    shutil.rmtree(out, ignore_errors=True)
    records = []
    if patches:
        out.mkdir(parents=True)
    for patch in patches:
        src = snap / "patches" / patch.file
        name = f"{Path(patch.file).stem}.png"
        link_or_copy(src, out / name)
        header = pyvips.Image.new_from_file(str(src))
        record = store.read_record(snap / "meta", src, layer_id)
        records.append({**record, "file": name, "width": header.width,
                        "height": header.height})
    return records


# -- the running-rebuild marker and the last error -------------------------------------------
@contextmanager
def building(dataset: Path, layer: str) -> Iterator[None]:
    """Mark a rebuild of ``layer`` as running (``.building`` in its store: pid, started)."""
    folder = store.store_dir(dataset, layer)
    store.put_file(folder, store.BUILDING, json.dumps(
        {"pid": os.getpid(), "started": store.now_iso()}).encode())
    try:
        yield
    finally:
        (folder / store.BUILDING).unlink(missing_ok=True)


def building_pid(dataset: Path, layer: str) -> int | None:
    """The pid of a live process rebuilding ``layer`` (its marker), else None."""
    try:
        pid = int(json.loads((store.store_dir(dataset, layer) / store.BUILDING)
                             .read_text())["pid"])
        os.kill(pid, 0)
    except (OSError, ValueError, KeyError, TypeError):
        return None
    return pid


def store_error(dataset: Path, layer: str, message: str | None) -> None:
    """Record (or, with None, clear) the last rebuild failure of ``layer``, with the
    fingerprint of the store it failed on."""
    folder = store.store_dir(dataset, layer)
    if message is None:
        (folder / store.LAST_ERROR).unlink(missing_ok=True)
    elif folder.is_dir():
        doc = {"fingerprint": store.fingerprint(dataset, layer), "error": " ".join(message.split())}
        store.put_file(folder, store.LAST_ERROR, json.dumps(doc).encode())


def last_error(dataset: Path, layer: str) -> tuple[str, str] | None:
    """``(fingerprint, message)`` of the last rebuild failure of ``layer``, if it failed."""
    try:
        doc = json.loads((store.store_dir(dataset, layer) / store.LAST_ERROR).read_text())
        return str(doc["fingerprint"]), str(doc["error"])
    except (OSError, ValueError, KeyError, TypeError):
        return None
