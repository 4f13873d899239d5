"""The files of the patch store: where they are, their lock, fingerprints, whole-file writes.

See :mod:`.store` for the design (docs/annotations.md "The patch store").
"""

from __future__ import annotations

import hashlib
import json
import os
import secrets
from collections.abc import Iterator
from contextlib import contextmanager
from datetime import UTC, datetime
from pathlib import Path
from typing import Any

import numpy as np
import numpy.typing as npt
import pyvips

from lanterna.tiler.dataset.lock import dataset_lock
from lanterna.tiler.dataset.writer import check_identifier

#: The store folder of dataset ``NAME`` is ``NAME`` + this suffix, beside it.
STORE_SUFFIX = ".annotations"
#: The level texts of a layer's store.
LEVEL_TEXTS = "levels.json"
#: The marker of a running rebuild in a layer's store: ``{"pid", "started"}``.
BUILDING = ".building"
#: The last rebuild failure of a layer (removed by a successful rebuild).
LAST_ERROR = ".error"


def store_root(dataset: Path) -> Path:
    """The patch store of ``dataset``: ``NAME.annotations`` in its (resolved) parent folder."""
    dataset = Path(dataset)
    return Path(os.path.realpath(dataset.parent)) / f"{dataset.name}{STORE_SUFFIX}"


def store_dir(dataset: Path, layer: str) -> Path:
    """The store folder of layer ``layer`` of ``dataset`` (it may not exist yet)."""
    return store_root(dataset) / check_identifier(layer, "layer id")


@contextmanager
def store_lock(dataset: Path, wait: float | None = None) -> Iterator[None]:
    """Hold the exclusive lock of ``dataset``'s patch store (``.NAME.annotations.lock``)."""
    with dataset_lock(store_root(dataset), wait=wait, notice=lambda _line: None):
        yield


def now_iso() -> str:
    """The current UTC time, ISO-8601 to the second (``2026-01-31T12:00:00Z``)."""
    return datetime.now(UTC).strftime("%Y-%m-%dT%H:%M:%SZ")


def fingerprint_of(entries: list[tuple[str, int, int]]) -> str:
    """sha256 over sorted ``(name, size, mtime_ns)`` entries."""
    digest = hashlib.sha256()
    for name, size, mtime in sorted(entries):
        digest.update(f"{name}\0{size}\0{mtime}\n".encode())
    return digest.hexdigest()


#: The fingerprint of an empty (or absent) store.
EMPTY_FINGERPRINT = fingerprint_of([])


def listing(folder: Path) -> list[tuple[str, int, int]]:
    """``(name, size, mtime_ns)`` of the regular, non-hidden files of ``folder``."""
    try:
        found = list(os.scandir(folder))
    except FileNotFoundError:
        return []
    out = []
    for entry in found:
        if entry.name.startswith(".") or not entry.is_file(follow_symlinks=False):
            continue
        st = entry.stat(follow_symlinks=False)
        out.append((entry.name, st.st_size, st.st_mtime_ns))
    return out


def fingerprint(dataset: Path, layer: str) -> str | None:
    """The fingerprint of a layer's store, None if it has no store folder."""
    folder = store_dir(dataset, layer)
    return fingerprint_of(listing(folder)) if folder.is_dir() else None


def put_file(folder: Path, name: str, data: bytes) -> None:
    """Write ``folder/name`` whole: a hidden temporary file renamed into place.

    A file replacing one of the same name gets a later ``mtime`` than it had even within one tick
    of the clock, so the store's fingerprint always changes.
    """
    tmp = folder / f".tmp-{secrets.token_hex(6)}-{name}"
    try:
        with open(tmp, "xb") as f:
            f.write(data)
            f.flush()
            os.fsync(f.fileno())
        try:
            old = os.stat(folder / name).st_mtime_ns
        except FileNotFoundError:
            old = None
        new = os.stat(tmp).st_mtime_ns
        if old is not None and new <= old:
            os.utime(tmp, ns=(old + 1, old + 1))
        os.replace(tmp, folder / name)
    except BaseException:
        tmp.unlink(missing_ok=True)
        raise


def put_json(folder: Path, name: str, doc: Any) -> None:
    put_file(folder, name, (json.dumps(doc, indent=1, ensure_ascii=False) + "\n").encode())


def encode_png(rgba: npt.NDArray[np.uint8]) -> bytes:
    """PNG bytes of an ``(H, W, 4)`` uint8 RGBA array."""
    img = pyvips.Image.new_from_array(np.ascontiguousarray(rgba)).copy(interpretation="srgb")
    data: bytes = img.pngsave_buffer(compression=6)
    return data
