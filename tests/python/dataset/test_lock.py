"""The per-dataset write lock, with real processes: one holder, waiting, giving up, kill -9."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import threading
import time
from pathlib import Path

import pytest

from lanterna.errors import LanternaInputError
from lanterna.tiler.dataset.lock import DatasetBusyError, dataset_lock, lock_path
from tests.python.fixtures.paths import REPO

#: Takes the lock of argv[1] (once the file argv[4] exists, if given), says so, holds it until a
#: line arrives on stdin (or for argv[2] seconds), then appends its (start, end) to the file
#: argv[3] if given.
HOLDER = """
import json, os, sys, time
from pathlib import Path
from lanterna.tiler.dataset.lock import dataset_lock
while len(sys.argv) > 4 and not os.path.exists(sys.argv[4]):
    time.sleep(0.01)
with dataset_lock(Path(sys.argv[1]), wait=30):
    start = time.time()
    print("held", flush=True)
    if sys.argv[2] == "stdin":
        sys.stdin.readline()
    else:
        time.sleep(float(sys.argv[2]))
    end = time.time()
if len(sys.argv) > 3:
    with open(sys.argv[3], "a") as log:
        log.write(json.dumps([start, end]) + "\\n")
"""


def _holder(dataset: Path, hold: str = "stdin", log: Path | None = None,
            go: Path | None = None) -> subprocess.Popen[str]:
    extra = [str(log)] if log else []
    extra += [str(go)] if go else []
    args = [sys.executable, "-c", HOLDER, str(dataset), hold, *extra]
    return subprocess.Popen(args, cwd=REPO, stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                            text=True)


def _started(proc: subprocess.Popen[str]) -> subprocess.Popen[str]:
    assert proc.stdout is not None and proc.stdout.readline() == "held\n"
    return proc


def test_a_second_process_is_told_who_holds_the_lock(tmp_path: Path) -> None:
    ds = tmp_path / "obj"
    holder = _started(_holder(ds))
    try:
        assert lock_path(ds).read_text() == f"{holder.pid}\n"
        t0 = time.monotonic()
        with pytest.raises(DatasetBusyError) as err, dataset_lock(ds, wait=0.3):
            pass
        assert time.monotonic() - t0 >= 0.3
        assert err.value.pid == holder.pid
        assert str(err.value) == (f"{ds}: another Lanterna process is writing this dataset "
                                  f"(pid {holder.pid}); try again when it has finished")
    finally:
        holder.communicate("\n", timeout=10)
    assert holder.returncode == 0
    assert not lock_path(ds).exists()  # removed by its holder


def test_a_waiting_writer_says_so_once_and_goes_on_when_the_holder_finishes(
        tmp_path: Path) -> None:
    ds = tmp_path / "obj"
    holder = _started(_holder(ds))
    notes: list[str] = []
    release = threading.Timer(0.6, lambda: holder.communicate("\n", timeout=10))
    release.start()
    t0 = time.monotonic()
    with dataset_lock(ds, wait=20, notice=notes.append) as first:
        waited = time.monotonic() - t0
        assert first and lock_path(ds).read_text() == f"{os.getpid()}\n"
    release.join()
    assert 0.5 < waited < 10
    assert notes == [f"{ds}: waiting for another Lanterna process (pid {holder.pid}) to finish "
                     "writing this dataset …"]
    assert not lock_path(ds).exists()


def test_a_killed_holder_leaves_no_lock(tmp_path: Path) -> None:
    ds = tmp_path / "obj"
    holder = _started(_holder(ds))
    holder.send_signal(signal.SIGKILL)
    holder.communicate(timeout=10)
    assert holder.returncode == -signal.SIGKILL
    assert lock_path(ds).read_text() == f"{holder.pid}\n"  # the file stays, the lock does not
    with dataset_lock(ds, wait=0) as first:
        assert first and lock_path(ds).read_text() == f"{os.getpid()}\n"
    assert not lock_path(ds).exists()


def test_holders_never_overlap_even_as_lock_files_come_and_go(tmp_path: Path) -> None:
    """Processes queue for one lock while its holder removes the file, then latecomers arrive.

    The waiters hold the removed file open; the latecomers open the path after the removal
    (a new file). A waiter that took the removed file's lock without noticing would overlap
    with them.
    """
    ds, log, go = tmp_path / "obj", tmp_path / "holds.jsonl", tmp_path / "go"
    first = _started(_holder(ds, "stdin", log))
    waiters = [_holder(ds, "0.4", log) for _ in range(3)]
    latecomers = [_holder(ds, "0.1", log, go) for _ in range(2)]
    time.sleep(1.0)  # the waiters are polling the file the first holder will remove
    first.communicate("\n", timeout=10)
    go.touch()
    for proc in waiters + latecomers:
        proc.communicate(timeout=30)
        assert proc.returncode == 0
    spans = sorted(json.loads(line) for line in log.read_text().splitlines())
    assert len(spans) == 6
    for (_, end), (start, _) in zip(spans, spans[1:], strict=False):
        assert start >= end, spans
    assert not lock_path(ds).exists()


def test_the_lock_is_reentrant_in_a_process_and_exclusive_between_threads(
        tmp_path: Path) -> None:
    ds = tmp_path / "obj"
    results: list[str] = []
    with dataset_lock(ds) as outer:
        with dataset_lock(ds) as inner:
            assert (outer, inner) == (True, False)

        def other_thread() -> None:
            try:
                with dataset_lock(ds, wait=0.2):
                    results.append("got it")
            except DatasetBusyError:
                results.append("busy")

        thread = threading.Thread(target=other_thread)
        thread.start()
        thread.join()
        assert lock_path(ds).exists()  # the inner exit kept it
    assert results == ["busy"]
    assert not lock_path(ds).exists()


def test_a_lock_that_cannot_be_made_is_a_one_line_error(tmp_path: Path) -> None:
    (tmp_path / "file").write_text("not a folder")
    ds = tmp_path / "file" / "obj"
    with pytest.raises(LanternaInputError) as err, dataset_lock(ds):
        pass
    assert str(err.value) == f"{ds}: cannot write (Not a directory); nothing was changed"
