"""Changing a preset library: add or remove a preset, add an entry to the base or lens list.

Each function returns a new library and leaves its argument unchanged; none checks the result
against a dataset (:func:`~.library.check_library` does, before anything is stored).
"""

from __future__ import annotations

import copy
from collections.abc import Mapping
from typing import Any

from lanterna.errors import LanternaInputError

from .library import LISTS


def add_preset(library: Mapping[str, Any], preset_id: str, preset: Mapping[str, Any], *,
               replace: bool = False) -> dict[str, Any]:
    """Add ``preset`` under ``preset_id`` (an existing id is an error unless ``replace``)."""
    out = copy.deepcopy(dict(library))
    if preset_id in out["presets"] and not replace:
        raise LanternaInputError(None, f"preset {preset_id!r} exists already (remove it first)")
    out["presets"][preset_id] = copy.deepcopy(dict(preset))
    return out


def add_entry(library: Mapping[str, Any], which: str, entry: Mapping[str, Any]) -> dict[str, Any]:
    """Append ``entry`` (``{label, preset[, layer][, opacity]}``) to list ``base`` or ``lens``."""
    if which not in LISTS:
        raise ValueError(f"no list {which!r}")
    out = copy.deepcopy(dict(library))
    out[which].append(copy.deepcopy(dict(entry)))
    return out


def remove_preset(library: Mapping[str, Any],
                  preset_id: str) -> tuple[dict[str, Any], list[str]]:
    """Remove a preset and the entries that use it; return the library and those entries.

    The entries are named ``base: LABEL`` / ``lens: LABEL``, for telling the user.
    """
    if preset_id not in library["presets"]:
        known = ", ".join(sorted(library["presets"])) or "none"
        raise LanternaInputError(None, f"no preset {preset_id!r} (presets: {known})")
    out = copy.deepcopy(dict(library))
    del out["presets"][preset_id]
    dropped: list[str] = []
    for which in LISTS:
        kept = []
        for entry in out[which]:
            if entry["preset"] == preset_id:
                dropped.append(f"{which}: {entry['label']}")
            else:
                kept.append(entry)
        out[which] = kept
    return out, dropped


def merge_libraries(old: Mapping[str, Any], new: Mapping[str, Any]) -> dict[str, Any]:
    """``old`` with ``new``'s presets added (same id: ``new``'s wins) and its entries appended.

    An entry of ``new`` whose label is already in the same list of ``old`` replaces it.
    """
    out = copy.deepcopy(dict(old))
    out["presets"].update(copy.deepcopy(dict(new["presets"])))
    for which in LISTS:
        labels = {entry["label"] for entry in new[which]}
        out[which] = [e for e in out[which] if e["label"] not in labels] + \
            copy.deepcopy(list(new[which]))
    if "label" in new:
        out["label"] = new["label"]
    return out
