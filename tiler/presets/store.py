"""A dataset's preset library: read from ``lanterna.json``, changed atomically under its lock.

The library is the ``presets`` key of ``lanterna.json``; every rewrite of the dataset writes it
as ``presets.json`` too and carries it in the manifest (:mod:`lanterna.manifests.extensions`).
:func:`update_library` takes the dataset's write lock, reads the current library, lets the
caller change it, checks the result against the dataset (:func:`~.library.check_library`) and
publishes the dataset's next version (:func:`~lanterna.tiler.dataset.writer.rewriting`), so a
bad library or a failure half-way leaves the previous dataset as it was, and two writers never
lose each other's change.
"""

from __future__ import annotations

import os
from collections.abc import Callable, Mapping
from pathlib import Path
from typing import Any

from lanterna.tiler.dataset.lock import DatasetBusyError
from lanterna.tiler.dataset.output import json_text, write_errors
from lanterna.tiler.dataset.publish import writing
from lanterna.tiler.dataset.writer import read_description, rewriting

from .library import PresetError, check_library, empty_library

#: The errors :func:`update_library` raises besides a write error: a bad library, a busy lock.
__all__ = ["DatasetBusyError", "PresetError", "dataset_library", "store_library",
           "update_library", "write_library_file", "is_empty"]


def dataset_library(dataset: Path) -> dict[str, Any]:
    """The preset library of ``dataset`` (an empty one if it has none)."""
    library = read_description(Path(dataset)).get("presets")
    return library if isinstance(library, dict) else empty_library()


def update_library(dataset: Path,
                   change: Callable[[dict[str, Any], dict[str, Any]], Any], *,
                   source: str | Path | None = "presets.json") -> dict[str, Any]:
    """Replace the library of ``dataset`` by ``change(current library, description)``.

    The new library is checked (errors name ``source`` and the JSON path) before anything is
    written; the stored library is returned. An empty library (no presets, no entries) removes
    the dataset's ``presets`` (and ``presets.json``).
    """
    dataset = Path(dataset)
    with writing(dataset):  # from the read to the publish: no lost update
        desc = read_description(dataset)
        stored = desc.get("presets")
        current: dict[str, Any] = stored if isinstance(stored, dict) else empty_library()
        library = check_library(change(current, desc), desc, source)
        with rewriting(dataset) as (_tmp, new_desc):
            if is_empty(library):
                new_desc.pop("presets", None)
            else:
                new_desc["presets"] = library
    return library


def store_library(dataset: Path, library: Any, *,
                  source: str | Path | None = "presets.json") -> dict[str, Any]:
    """Replace the library of ``dataset`` by ``library`` (checked first); return it."""
    return update_library(dataset, lambda _old, _desc: library, source=source)


def is_empty(library: Mapping[str, Any]) -> bool:
    """Whether a library has no presets and no entries."""
    return not library.get("presets") and not library.get("base") and not library.get("lens")


def write_library_file(path: Path, library: Mapping[str, Any]) -> None:
    """Write ``library`` as the JSON file ``path`` (a new file renamed over the old one)."""
    path = Path(path)
    part = path.with_name(f".{path.name}.part")
    with write_errors(path):
        try:
            part.write_text(json_text(dict(library), path) + "\n")
            os.replace(part, path)
        finally:
            part.unlink(missing_ok=True)
