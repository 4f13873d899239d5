"""Background rebuilds of overlay pyramids after patch-store changes (docs/annotations.md).

Each server process has one :class:`Rebuilder`: a thread and a queue of ``(dataset, layer)``
keys. A key already waiting is not queued twice (coalescing: however many uploads arrive, one
rebuild after them takes them all). For a key the thread runs ``while the store's fingerprint is
not the published one: rebuild_from_store`` — each round re-checks under the dataset's lock, so a
layer another worker (or ``lanterna annotate build``) just rebuilt is not rebuilt again. A rebuild
that cannot get the dataset's lock is retried after :data:`RETRY_S`; any other failure is
recorded for the status (``.error`` in the layer's store) and the key dropped until the next
change or status read. The thread starts on the first request in the process that uses it, so
gunicorn's workers (forked after the app is made) each get their own.

With ``inline=True`` (the app's ``REBUILD_INLINE`` config key, for tests) a request rebuilds at
once in the calling thread.
"""

from __future__ import annotations

import logging
import os
import queue
import threading
import time
from pathlib import Path
from typing import Any, Literal

from lanterna.errors import LanternaInputError
from lanterna.tiler.overlays import rebuild, store
from lanterna.tiler.overlays.published import build_number, overlay_of, published_layer
from lanterna.tiler.overlays.store import DatasetBusyError

log = logging.getLogger("lanterna.rebuild")

#: Seconds before a rebuild that found the dataset locked is tried again.
RETRY_S = 1.0
#: Rounds of rebuilding one key before giving up for now (a store changed faster than rebuilt).
MAX_ROUNDS = 100
Key = tuple[str, str]
State = Literal["queued", "building"]


class Rebuilder:
    """One process's background rebuilds: :meth:`request` a layer, ask its :meth:`state`."""

    def __init__(self, *, inline: bool = False) -> None:
        self.inline = inline
        self._mutex = threading.Lock()
        self._pending: set[Key] = set()
        self._current: Key | None = None
        self._queue: queue.Queue[Key] = queue.Queue()
        self._thread: threading.Thread | None = None
        self._pid = os.getpid()

    def request(self, dataset: Path, layer: str) -> None:
        """Ask for ``layer`` of ``dataset`` to be brought up to date with its patch store."""
        key = (str(dataset), layer)
        if self.inline:
            self._run_key(key)
            return
        with self._mutex:
            self._adopt_fork()
            if key in self._pending:
                return
            self._pending.add(key)
            self._queue.put(key)
            if self._thread is None or not self._thread.is_alive():
                self._thread = threading.Thread(target=self._loop, name="lanterna-rebuilder",
                                                daemon=True)
                self._thread.start()

    def state(self, dataset: Path, layer: str) -> State | None:
        """``building`` or ``queued`` if this process is on it, else None."""
        key = (str(dataset), layer)
        with self._mutex:
            if self._current == key:
                return "building"
            return "queued" if key in self._pending else None

    def _adopt_fork(self) -> None:
        """After a fork (gunicorn's workers), start afresh: the parent's thread is not ours."""
        if self._pid != os.getpid():
            self._pid = os.getpid()
            self._pending.clear()
            self._current = None
            self._queue = queue.Queue()
            self._thread = None

    def _loop(self) -> None:
        while True:
            key = self._queue.get()
            with self._mutex:
                self._pending.discard(key)
                self._current = key
            try:
                retry = self._run_key(key)
            finally:
                with self._mutex:
                    self._current = None
            if retry:
                time.sleep(RETRY_S)
                self.request(Path(key[0]), key[1])

    def _run_key(self, key: Key) -> bool:
        """Rebuild until up to date; return True to try again later (the dataset was busy)."""
        dataset, layer = Path(key[0]), key[1]
        try:
            for _ in range(MAX_ROUNDS):
                if not rebuild.is_stale(dataset, layer):
                    rebuild.store_error(dataset, layer, None)  # up to date: nothing failed
                    return False
                report = rebuild.rebuild_from_store(dataset, layer)
                if report.errors:
                    log.warning("%s layer %s: %d file(s) of the patch store rejected: %s",
                                dataset.name, layer, len(report.errors), report.errors[0])
                if not report.changed:
                    return False
        except DatasetBusyError:
            return True
        except LanternaInputError as err:
            log.error("rebuilding %s layer %s failed: %s", dataset.name, layer, err)
            rebuild.store_error(dataset, layer, _public(err, dataset))
        except Exception as err:  # never let the thread die: record and go on
            log.exception("rebuilding %s layer %s failed", dataset.name, layer)
            rebuild.store_error(dataset, layer, f"internal error ({type(err).__name__})")
        return False


def _public(err: LanternaInputError, dataset: Path) -> str:
    """The error's line with its file named relative to the data root (no server paths)."""
    source = err.source or ""
    for base in {str(dataset.parent), os.path.realpath(dataset.parent)}:
        if source.startswith(base + os.sep):
            source = source[len(base) + 1:]
    return f"{source}: {err.problem}" if source else err.problem


def status(rebuilder: Rebuilder, dataset: Path, layer: str) -> dict[str, Any]:
    """The rebuild status of a layer (docs/serving.md "Annotation API").

    ``state`` is ``building`` while this process or a live one (the store's ``.building``
    marker) rebuilds it, ``queued`` while a rebuild waits here, else ``done`` — unless the store
    differs from what the served overlay was built from, in which case a rebuild is requested
    now (after a killed one, or a change another process did not get to), so ``queued``. A store
    whose last rebuild failed as it is now is not retried until it changes: ``done`` with the
    ``error``.
    """
    state = _state(rebuilder, dataset, layer)
    if state is None and _needs_rebuild(dataset, layer):
        rebuilder.request(dataset, layer)  # inline: done when this returns
        state = _state(rebuilder, dataset, layer)
        if state is None and not rebuilder.inline and rebuild.is_stale(dataset, layer):
            state = "queued"  # between the queue and the thread
    entry = published_layer(dataset, layer)
    served = overlay_of(entry)
    failure = rebuild.last_error(dataset, layer)
    return {"layer": layer, "state": state or "done",
            "served": {"build": build_number(entry),
                       "fingerprint": served.get("fingerprint") if served else None},
            "patches": store.patch_count(dataset, layer),
            "error": failure[1] if failure else None}


def _state(rebuilder: Rebuilder, dataset: Path, layer: str) -> State | None:
    state = rebuilder.state(dataset, layer)
    if state is None and rebuild.building_pid(dataset, layer) is not None:
        return "building"
    return state


def _needs_rebuild(dataset: Path, layer: str) -> bool:
    """Whether the store differs from the served overlay and has not failed as it is."""
    if not rebuild.is_stale(dataset, layer):
        return False
    failure = rebuild.last_error(dataset, layer)
    return failure is None or failure[0] != store.fingerprint(dataset, layer)
