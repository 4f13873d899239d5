"""Patch records: read from a patch's ``.json`` beside it, or derived from its file name.

A record is ``tiler/schemas/patch.schema.json``; a patch without a valid ``.json`` (a file a GIMP
user dropped) gets one from its name (author "", created = the file's mtime, no texts,
motivation "commenting", state null).
"""

from __future__ import annotations

import json
from collections.abc import Mapping
from datetime import UTC, datetime
from pathlib import Path
from typing import Any

from lanterna.errors import LanternaInputError
from lanterna.tiler.documents import check_document

from . import geometry as og
from .store_files import listing

#: Keys of a published patch entry that are not part of its record.
PUBLISHED_ONLY = ("file", "width", "height")


def derived_record(path: Path, layer: str) -> dict[str, Any]:
    """The record of a patch file without a ``.json``: from its name and mtime."""
    p = og.parse_patch_name(path.name)
    created = datetime.fromtimestamp(path.stat().st_mtime, UTC).strftime("%Y-%m-%dT%H:%M:%SZ")
    return {"type": "LanternaPatch", "version": 1, "id": Path(p.file).stem, "layer": layer,
            "level": p.level, "x": p.x, "y": p.y, "w": p.w, "h": p.h, "order": p.order,
            "info": p.info, "author": "", "created": created, "modified": created, "short": "",
            "long": "", "motivation": "commenting", "state": None}


def read_record(folder: Path, png: Path, layer: str) -> dict[str, Any]:
    """The record of the patch file ``png``: its ``.json`` beside it (in ``folder``) if valid,
    over the record derived from the name (which always wins for the rectangle and order)."""
    record = derived_record(png, layer)
    path = folder / f"{png.stem}.json"
    try:
        doc = json.loads(path.read_text(encoding="utf-8"))
        check_document(doc, "patch", path)
    except (OSError, ValueError, LanternaInputError):
        return record
    for key in ("author", "created", "modified", "short", "long", "motivation", "state"):
        if key in doc:
            record[key] = doc[key]
    return record


def patch_files(folder: Path) -> list[Path]:
    """The files of ``folder`` named as patches (``L_X_Y_W_H_O_INFO.png``)."""
    out = []
    for name, _, _ in listing(folder):
        try:
            og.parse_patch_name(name)
        except og.PatchNameError:
            continue
        out.append(folder / name)
    return out


def store_records(folder: Path, layer: str, meta: Path | None = None) -> list[dict[str, Any]]:
    """The records of the patch files of ``folder`` (records read from ``meta``, default the
    same folder), in application order (level, order, file name)."""
    files = patch_files(folder)
    ordered = og.application_order(og.parse_patch_name(p.name) for p in files)
    return [read_record(meta or folder, folder / p.file, layer) for p in ordered]


def published_record(entry: Mapping[str, Any], layer: str) -> dict[str, Any]:
    """The record of a published overlay's patch entry (older overlays lack most keys)."""
    file = str(entry.get("file", ""))
    out: dict[str, Any] = {"type": "LanternaPatch", "version": 1, "id": Path(file).stem,
                           "layer": layer, "author": "", "created": "", "modified": "",
                           "short": "", "long": "", "motivation": "commenting", "state": None}
    out.update({k: v for k, v in entry.items() if k not in PUBLISHED_ONLY})
    return out


def read_level_texts(path: Path) -> dict[str, dict[str, str]]:
    """The level texts of a ``levels.json`` (``{}`` if absent or invalid)."""
    try:
        doc = json.loads(Path(path).read_text(encoding="utf-8"))
        checked = check_document(doc, "texts", path)
    except (OSError, ValueError, LanternaInputError):
        return {}
    return {k: {"short": v.get("short", ""), "long": v.get("long", "")}
            for k, v in checked.items()}
