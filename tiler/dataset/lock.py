"""One writer per dataset: an exclusive ``flock`` on ``.NAME.lock`` beside the dataset ``NAME``.

Every command that writes a dataset (import and fit, ``--force`` or not, ``annotate build``,
anything that uses :func:`~lanterna.tiler.dataset.writer.rewriting`) holds this lock from the
moment it reads what it will change until the new version is published, so two writers never
both copy the same version and publish over each other (a lost update). A second writer waits
up to :data:`DEFAULT_WAIT` seconds (``LANTERNA_LOCK_WAIT`` in the environment), saying so once,
then stops with a one-line error naming the holder's process id.

The kernel drops an ``flock`` when its holder exits, however it exits (``kill -9`` included), so
a lock is never stale. The file holds the holder's pid, for the messages. It is removed by its
holder before the lock is released; a waiter that then gets the lock of a removed file notices
(the path no longer names the file it locked) and locks the new file instead. Within one process
the lock is re-entrant: :func:`dataset_lock` may be nested (a fit run holds it while its
:class:`~lanterna.tiler.dataset.writer.DatasetWriter` takes it again), across threads too.
"""

from __future__ import annotations

import fcntl
import os
import sys
import threading
import time
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from dataclasses import dataclass, field
from pathlib import Path

from lanterna.errors import LanternaInputError

from .output import write_error

#: Seconds a writer waits for another one to finish before giving up.
DEFAULT_WAIT = 60.0
#: The environment variable that overrides :data:`DEFAULT_WAIT` (0: do not wait).
WAIT_ENV = "LANTERNA_LOCK_WAIT"
_POLL = 0.05


class DatasetBusyError(LanternaInputError):
    """Another process kept the dataset's lock longer than we could wait; ``pid`` if known."""

    def __init__(self, dataset: Path, pid: int | None) -> None:
        who = f" (pid {pid})" if pid else ""
        super().__init__(dataset, f"another Lanterna process is writing this dataset{who}; "
                         "try again when it has finished")
        self.pid = pid


@dataclass
class _Held:
    """This process's hold on one lock file: a thread lock, a depth and the locked file."""

    thread_lock: threading.RLock = field(default_factory=threading.RLock)
    depth: int = 0
    fd: int | None = None


_registry: dict[str, _Held] = {}
_registry_mutex = threading.Lock()


def lock_path(dataset: Path) -> Path:
    """Return the lock file of ``dataset``: ``.NAME.lock`` in its (resolved) parent folder."""
    dataset = Path(dataset)
    return Path(os.path.realpath(dataset.parent)) / f".{dataset.name}.lock"


def wait_seconds() -> float:
    """Return how long a writer waits for the lock (``LANTERNA_LOCK_WAIT``, else the default)."""
    text = os.environ.get(WAIT_ENV, "")
    try:
        return max(0.0, float(text)) if text else DEFAULT_WAIT
    except ValueError:
        raise LanternaInputError(None, f"{WAIT_ENV} must be a number of seconds, not "
                                 f"{text!r}") from None


def _stderr(message: str) -> None:
    print(f"lanterna: {message}", file=sys.stderr, flush=True)


@contextmanager
def dataset_lock(dataset: Path, *, wait: float | None = None,
                 notice: Callable[[str], None] = _stderr) -> Iterator[bool]:
    """Hold the exclusive write lock of ``dataset``; yield True if this call took the lock.

    Nested calls (same process) yield False: the outermost holder is the one that took it.
    ``wait`` is how long to wait for another holder (default :func:`wait_seconds`); ``notice``
    gets one line when waiting starts. Raises :class:`DatasetBusyError` when the wait runs out,
    and :class:`LanternaInputError` when the lock file cannot be made (a read-only folder).
    """
    dataset = Path(dataset)
    path = lock_path(dataset)
    limit = wait_seconds() if wait is None else wait
    with _registry_mutex:
        held = _registry.setdefault(str(path), _Held())
    if not held.thread_lock.acquire(timeout=limit if limit > 0 else 0):
        raise DatasetBusyError(dataset, os.getpid())
    try:
        first = held.depth == 0
        if first:
            held.fd = _lock_file(dataset, path, time.monotonic() + limit, notice)
        held.depth += 1
    except BaseException:
        held.thread_lock.release()
        raise
    try:
        yield first
    finally:
        held.depth -= 1
        if held.depth == 0 and held.fd is not None:
            _unlock_file(path, held.fd)
            held.fd = None
        held.thread_lock.release()


def _lock_file(dataset: Path, path: Path, deadline: float,
               notice: Callable[[str], None]) -> int:
    """Open and lock ``path`` (waiting until ``deadline``); write our pid in it; return the fd."""
    told = False
    while True:
        try:
            fd = os.open(path, os.O_RDWR | os.O_CREAT | os.O_CLOEXEC, 0o644)
        except OSError as err:
            raise write_error(dataset, err) from None
        try:
            while True:
                try:
                    fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
                    break
                except BlockingIOError:
                    pid = _read_pid(fd)
                    if time.monotonic() >= deadline:
                        raise DatasetBusyError(dataset, pid) from None
                    if not told:
                        who = f" (pid {pid})" if pid else ""
                        notice(f"{dataset}: waiting for another Lanterna process{who} to "
                               "finish writing this dataset …")
                        told = True
                    time.sleep(_POLL)
        except BaseException:
            os.close(fd)
            raise
        if same_file(fd, path):
            os.ftruncate(fd, 0)
            os.pwrite(fd, f"{os.getpid()}\n".encode(), 0)
            return fd
        os.close(fd)  # we locked a file its holder had removed meanwhile: lock the new one


def _unlock_file(path: Path, fd: int) -> None:
    try:
        path.unlink(missing_ok=True)  # while still locked (see the module docstring)
    finally:
        os.close(fd)  # closing the last descriptor releases the flock


def same_file(fd: int, path: Path) -> bool:
    """Return whether the open ``fd`` is the file ``path`` names now (links followed)."""
    try:
        here, there = os.fstat(fd), os.stat(path)
    except FileNotFoundError:
        return False
    return (here.st_dev, here.st_ino) == (there.st_dev, there.st_ino)


def _read_pid(fd: int) -> int | None:
    try:
        text = os.pread(fd, 32, 0).decode("ascii", "replace").strip()
    except OSError:
        return None
    return int(text) if text.isdigit() else None
