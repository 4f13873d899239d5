"""The patch store: a layer's annotations as a plain folder of patch PNGs and their records.

Dataset ``ROOT/NAME`` keeps its patch store beside it, in ``ROOT/NAME.annotations/`` (not
versioned; docs/annotations.md "The patch store"). Layer ``LAYER``'s store is the folder
``ROOT/NAME.annotations/LAYER/`` of

- ``L_X_Y_W_H_O_INFO.png``: a patch (the paper's interop format; a GIMP user may drop files here);
- ``L_X_Y_W_H_O_INFO.json``: its record (``tiler/schemas/patch.schema.json``), optional;
- ``levels.json``: the level texts (``texts.schema.json``).

Files are only ever written whole under a hidden temporary name and renamed into place, so hard
links of them are immutable snapshots (:func:`snapshot`). Every change holds the store's lock, an
exclusive ``flock`` on ``ROOT/.NAME.annotations.lock`` (:func:`store_lock`), briefly: it is never
held while building, and the dataset's own write lock is never taken while holding it. The first
change of a layer without a store folder fills it from the layer's published overlay
(:func:`ensure_store`). The pyramid is rebuilt from the store by :mod:`.rebuild`.
"""

from __future__ import annotations

import os
import re
import secrets
import shutil
from collections.abc import Mapping
from pathlib import Path
from typing import Any

import numpy as np
import numpy.typing as npt

from lanterna.errors import LanternaInputError
from lanterna.tiler.dataset.lock import DatasetBusyError
from lanterna.tiler.dataset.publish import reading
from lanterna.tiler.dataset.writer import link_or_copy, read_description
from lanterna.tiler.documents import check_document

from . import geometry as og
from .composite import decode_rgba
from .png_check import PngHeaderError, read_header
from .published import Canvas, canvas_of, find_layer, overlay_of, read_level_image
from .records import (
    PUBLISHED_ONLY,
    patch_files,
    published_record,
    read_level_texts,
    read_record,
    store_records,
)
from .store_files import (
    BUILDING,
    EMPTY_FINGERPRINT,
    LAST_ERROR,
    LEVEL_TEXTS,
    encode_png,
    fingerprint,
    fingerprint_of,
    listing,
    now_iso,
    put_file,
    put_json,
    store_dir,
    store_lock,
    store_root,
)

__all__ = ["BUILDING", "DatasetBusyError", "EMPTY_FINGERPRINT", "LAST_ERROR", "LEVEL_TEXTS",
           "NoSuchPatch", "PatchError", "add_patch", "delete_patch", "encode_png", "ensure_store",
           "fingerprint", "get_patch", "level_texts", "list_patches", "now_iso", "patch_count",
           "patch_image", "put_file", "read_level_texts", "read_record", "replace_patch",
           "set_level_texts", "snapshot", "store_dir", "store_lock", "store_records",
           "store_root"]

#: Keys a client may give when creating a patch; the rest of a record is derived.
CREATE_KEYS = frozenset({"level", "x", "y", "w", "h", "short", "long", "motivation", "author",
                         "state"})
#: Keys a client may change on an existing patch.
EDIT_KEYS = frozenset({"short", "long", "motivation", "author", "state"})
_FIXED = ("level", "x", "y", "w", "h", "order")
_SLUG = re.compile(r"[^A-Za-z0-9-]+")


class PatchError(LanternaInputError):
    """A patch refused (bad metadata or image); nothing was stored. ``too_large``: a 413."""

    def __init__(self, source: str | Path | None, problem: str, *,
                 too_large: bool = False) -> None:
        super().__init__(source, problem)
        self.too_large = too_large


class NoSuchPatch(LanternaInputError):
    """No patch of that id in the layer's store (or published overlay)."""


def slug(text: str) -> str:
    """The ``INFO`` of a new patch: ASCII letters, digits and ``-`` of ``text`` (≤ 40; "patch")."""
    out = _SLUG.sub("-", text.encode("ascii", "ignore").decode()).strip("-")[:40].strip("-")
    return out or "patch"


def snapshot(dataset: Path, layer: str, into: Path) -> str:
    """Hard-link the layer's store into ``into`` (``patches/``: every file but the ``.json``
    ones, ``meta/``: records and level texts); return the fingerprint of what was linked.

    Takes the store lock briefly (initialising the store if it has none yet).
    """
    patches, meta = Path(into) / "patches", Path(into) / "meta"
    patches.mkdir(parents=True, exist_ok=True)
    meta.mkdir(exist_ok=True)
    with store_lock(dataset):
        folder = ensure_store(dataset, layer)
        entries = listing(folder)
        for name, _, _ in entries:
            target = meta if name.lower().endswith(".json") else patches
            link_or_copy(folder / name, target / name)
    return fingerprint_of(entries)


# -- initialisation ---------------------------------------------------------------------------
def ensure_store(dataset: Path, layer: str) -> Path:
    """Return the layer's store folder, first filling it from its published overlay if absent.

    Call with the store lock held. The published patch files (``annotations/LAYER/*.png`` and the
    overlay's records) if the dataset version has them, else each level image as one
    whole-canvas patch ``L_0_0_W_H_0_level.png``; the level texts into ``levels.json``.
    """
    folder = store_dir(dataset, layer)
    if folder.is_dir():
        return folder
    root = store_root(dataset)
    root.mkdir(exist_ok=True)
    for entry in os.scandir(root):  # a killed initialisation's (we hold the lock)
        if entry.name.startswith(".init-") and entry.is_dir(follow_symlinks=False):
            shutil.rmtree(root / entry.name, ignore_errors=True)
    tmp = root / f".init-{layer}-{secrets.token_hex(4)}"
    tmp.mkdir()
    try:
        with reading(Path(dataset)) as version:
            _fill(version, layer, tmp)
        os.rename(tmp, folder)
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    return folder


def _fill(version: Path, layer_id: str, into: Path) -> None:
    desc = read_description(version)
    layer = find_layer(desc, layer_id, version)
    overlay = overlay_of(layer)
    width, height = int(desc["width"]), int(desc["height"])
    published = version / "annotations" / layer_id
    records = [e for e in overlay.get("patches", []) if isinstance(e, dict)]
    levels = [e for e in overlay.get("levels", []) if isinstance(e, dict) and e.get("image")]
    if records and all((published / str(e.get("file"))).is_file() for e in records):
        for entry in records:
            link_or_copy(published / entry["file"], into / entry["file"])
            record = {k: v for k, v in entry.items() if k not in PUBLISHED_ONLY}
            put_json(into, f"{Path(entry['file']).stem}.json", record)
    else:
        for entry in levels:
            rgba = read_level_image(version, str(entry["image"]))
            put_file(into, f"{int(entry['level'])}_0_0_{width}_{height}_0_level.png",
                     encode_png(rgba))
    texts = {str(int(e["level"])): {"short": str(e.get("short", "")),
                                    "long": str(e.get("long", ""))}
             for e in levels if e.get("short") or e.get("long")}
    if texts:
        put_json(into, LEVEL_TEXTS, texts)


def list_patches(dataset: Path, layer: str) -> list[dict[str, Any]]:
    """The layer's patch records in application order: from its store if it has one, else from
    its published overlay."""
    folder = store_dir(dataset, layer)
    if folder.is_dir():
        return store_records(folder, layer)
    desc = read_description(Path(dataset))
    overlay = overlay_of(find_layer(desc, layer, Path(dataset)))
    return [published_record(e, layer) for e in overlay.get("patches", [])
            if isinstance(e, dict)]


def patch_count(dataset: Path, layer: str) -> int:
    """``len(list_patches(…))`` without reading a record: what a status read reports."""
    folder = store_dir(dataset, layer)
    if folder.is_dir():
        return len(patch_files(folder))
    overlay = overlay_of(find_layer(read_description(Path(dataset)), layer, Path(dataset)))
    return sum(isinstance(e, dict) for e in overlay.get("patches", []))


def get_patch(dataset: Path, layer: str, patch_id: str) -> dict[str, Any]:
    """The record of patch ``patch_id`` (raises :class:`NoSuchPatch`)."""
    for record in list_patches(dataset, layer):
        if record["id"] == patch_id:
            return record
    raise NoSuchPatch(store_dir(dataset, layer), f"no patch {patch_id!r} in layer {layer!r}")


def patch_image(dataset: Path, layer: str, patch_id: str) -> Path:
    """The PNG file of patch ``patch_id``: in the store, else in the published version."""
    record = get_patch(dataset, layer, patch_id)
    name = f"{record['id']}.png"
    folder = store_dir(dataset, layer)
    if folder.is_dir():
        return folder / name
    return Path(os.path.realpath(dataset)) / "annotations" / layer / name


# -- checks -----------------------------------------------------------------------------------
def layer_canvas(dataset: Path, layer: str) -> Canvas:
    """The canvas of ``layer`` of ``dataset`` as published (one-line error if no such layer)."""
    desc = read_description(Path(dataset))
    return canvas_of(Path(dataset), desc, find_layer(desc, layer, Path(dataset)))


def _int(meta: Mapping[str, Any], key: str, source: str) -> int:
    value = meta.get(key)
    if not isinstance(value, int) or isinstance(value, bool):
        raise PatchError(source, f"meta.{key}: expected an integer (got {value!r:.40})")
    return value


def check_image(image: npt.NDArray[np.uint8] | bytes, level: int, x: int, y: int, w: int,
                h: int, canvas: Canvas, source: str) -> bytes:
    """Check a patch image for its rectangle; return the PNG bytes to store.

    Refused: a PNG whose header is not a PNG, too large or without alpha (before decoding); an
    image that does not decode to RGBA; a rectangle outside the canvas; a level deeper than the
    pyramid; an image not exactly the rectangle's destination size at its level.
    """
    if level > canvas.deepest:
        raise PatchError(source, f"level {level} is beyond the pyramid (levels 0–"
                         f"{canvas.deepest})")
    patch = og.Patch(level, x, y, w, h, 0, "", "")
    placement = og.place(patch, canvas.width, canvas.height)
    if placement is None:
        raise PatchError(source, f"rectangle {x},{y},{w},{h} is outside the {canvas.width}x"
                         f"{canvas.height} canvas")
    if isinstance(image, bytes):
        try:
            read_header(image)
        except PngHeaderError as err:
            raise PatchError(source, str(err), too_large=err.too_large) from None
        try:
            rgba, data = decode_rgba(image, source), image
        except LanternaInputError as err:
            raise PatchError(source, str(err).split(": ", 1)[-1]) from None
    else:
        if image.dtype != np.uint8 or image.ndim != 3 or image.shape[2] != 4:
            raise PatchError(source, f"expected an RGBA uint8 image (got {image.dtype} "
                             f"{image.shape})")
        rgba, data = image, encode_png(image)
    want = placement.size
    if (rgba.shape[1], rgba.shape[0]) != want:
        raise PatchError(source, f"the image is {rgba.shape[1]}x{rgba.shape[0]}; rectangle "
                         f"{x},{y},{w},{h} at level {level} is {want[0]}x{want[1]}")
    return data


def _texts_and_state(meta: Mapping[str, Any], record: dict[str, Any], source: str) -> None:
    for key in ("short", "long", "motivation", "author", "state"):
        if key in meta:
            record[key] = meta[key]
    try:
        check_document(record, "patch", source)
    except LanternaInputError as err:
        raise PatchError(source, str(err).split(": ", 1)[-1].replace("(document)", "meta")
                         ) from None


# -- changes ----------------------------------------------------------------------------------
def add_patch(dataset: Path, layer: str, image: npt.NDArray[np.uint8] | bytes,
              meta: Mapping[str, Any], *, created: str | None = None) -> dict[str, Any]:
    """Add a patch on top of the layer's others; return its stored record.

    ``meta`` holds ``level, x, y, w, h`` (full-resolution rectangle) and optionally ``short,
    long, motivation, author, state``; ``image`` is RGBA (an array, or PNG bytes) exactly the
    rectangle's size at its level. Its order is 1 + the largest of the layer's (0 for the first),
    its ``INFO`` a slug of the short text. Every check is made before anything is stored.
    ``created`` (ISO-8601) keeps an imported annotation's own creation time; default now.
    """
    dataset = Path(dataset)
    source = f"patch of layer {layer}"
    unknown = sorted(set(meta) - CREATE_KEYS)
    if unknown:
        raise PatchError(source, f"meta: unknown key(s) {', '.join(unknown)}")
    level, x, y, w, h = (_int(meta, k, source) for k in ("level", "x", "y", "w", "h"))
    if level < 0 or w < 1 or h < 1:
        raise PatchError(source, f"meta: level {level} must be ≥ 0 and size {w}x{h} at least 1x1")
    canvas = layer_canvas(dataset, layer)
    stamp = now_iso()
    record: dict[str, Any] = {"type": "LanternaPatch", "version": 1, "id": "", "layer": layer,
                              "level": level, "x": x, "y": y, "w": w, "h": h, "order": 0,
                              "info": "", "author": "", "created": created or stamp,
                              "modified": stamp,
                              "short": "", "long": "", "motivation": "commenting",
                              "state": None}
    _texts_and_state(meta, record, source)
    data = check_image(image, level, x, y, w, h, canvas, source)
    with store_lock(dataset):
        folder = ensure_store(dataset, layer)
        orders = [og.parse_patch_name(p.name).order for p in patch_files(folder)]
        record["order"] = max(orders) + 1 if orders else 0
        record["info"] = slug(str(record["short"]))
        record["id"] = stem = f"{level}_{x}_{y}_{w}_{h}_{record['order']}_{record['info']}"
        put_json(folder, f"{stem}.json", record)
        put_file(folder, f"{stem}.png", data)  # the patch exists from this rename on
    return record


def replace_patch(dataset: Path, layer: str, patch_id: str, *,
                  image: npt.NDArray[np.uint8] | bytes | None = None,
                  meta: Mapping[str, Any] | None = None) -> dict[str, Any]:
    """Change a patch's texts, motivation, author, state and/or image; return its record.

    The rectangle, level and order cannot change (giving them different is an error).
    """
    dataset = Path(dataset)
    source = f"patch {patch_id}"
    meta = meta or {}
    bad = sorted(k for k in meta if k not in EDIT_KEYS and k not in _FIXED)
    if bad:
        raise PatchError(source, f"meta: unknown key(s) {', '.join(bad)}")
    canvas = layer_canvas(dataset, layer)
    with store_lock(dataset):
        folder = ensure_store(dataset, layer)
        png = folder / f"{patch_id}.png"
        if "/" in patch_id or patch_id.startswith(".") or not png.is_file():
            raise NoSuchPatch(folder, f"no patch {patch_id!r} in layer {layer!r}")
        try:
            record = read_record(folder, png, layer)
        except og.PatchNameError:
            raise NoSuchPatch(folder, f"no patch {patch_id!r} in layer {layer!r}") from None
        fixed = [k for k in _FIXED if k in meta and meta[k] != record[k]]
        if fixed:
            raise PatchError(source, f"meta: {', '.join(fixed)} cannot change (add a new patch "
                             "instead)")
        _texts_and_state(meta, record, source)
        data = None if image is None else check_image(
            image, record["level"], record["x"], record["y"], record["w"], record["h"], canvas,
            source)
        record["modified"] = now_iso()
        put_json(folder, f"{patch_id}.json", record)
        if data is not None:
            put_file(folder, f"{patch_id}.png", data)
    return record


def delete_patch(dataset: Path, layer: str, patch_id: str) -> None:
    """Remove a patch (its PNG, then its record) from the layer's store."""
    dataset = Path(dataset)
    with store_lock(dataset):
        folder = ensure_store(dataset, layer)
        png = folder / f"{patch_id}.png"
        if "/" in patch_id or patch_id.startswith(".") or not png.is_file():
            raise NoSuchPatch(folder, f"no patch {patch_id!r} in layer {layer!r}")
        png.unlink()
        (folder / f"{patch_id}.json").unlink(missing_ok=True)


def level_texts(dataset: Path, layer: str) -> dict[str, dict[str, str]]:
    """The layer's level texts ``{"L": {"short", "long"}}``: its store's, else as published."""
    folder = store_dir(dataset, layer)
    if folder.is_dir():
        return read_level_texts(folder / LEVEL_TEXTS)
    desc = read_description(Path(dataset))
    overlay = overlay_of(find_layer(desc, layer, Path(dataset)))
    return {str(int(e["level"])): {"short": str(e.get("short", "")),
                                   "long": str(e.get("long", ""))}
            for e in overlay.get("levels", []) if isinstance(e, dict) and "level" in e}


def set_level_texts(dataset: Path, layer: str, texts: Mapping[str, Any]) -> None:
    """Set the texts of some levels (``{"L": {"short", "long"}}``, others kept).

    Raises :class:`PatchError` for texts that are not ``texts.schema.json`` or a level outside
    the pyramid, before anything is stored.
    """
    dataset = Path(dataset)
    source = f"texts of layer {layer}"
    try:
        checked = check_document({str(k): v for k, v in texts.items()}, "texts", None)
    except LanternaInputError as err:
        raise PatchError(source, str(err)) from None
    canvas = layer_canvas(dataset, layer)
    for key in checked:
        if int(key) > canvas.deepest:
            raise PatchError(source, f"level {key} is not a level of the pyramid (0–"
                             f"{canvas.deepest})")
    with store_lock(dataset):
        folder = ensure_store(dataset, layer)
        current = read_level_texts(folder / LEVEL_TEXTS)
        for key, value in checked.items():
            current[str(int(key))] = {"short": str(value.get("short", "")),
                                      "long": str(value.get("long", ""))}
        put_json(folder, LEVEL_TEXTS, dict(sorted(current.items(), key=lambda kv: int(kv[0]))))
