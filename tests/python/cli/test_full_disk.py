"""A real full disk: ``lanterna import`` into a 2 MB tmpfs (needs root and a sandbox that lets
the test mount one; skipped otherwise; ``tests/python/dataset/test_write_errors.py`` simulates
the same failures everywhere)."""

from __future__ import annotations

import os
import subprocess
from collections.abc import Iterator
from pathlib import Path

import pytest

from lanterna.cli import main
from lanterna.tiler.dataset.writer import read_description
from tests.python.fixtures.ptm import random_ptm_of_size
from tests.python.fixtures.ptm_writer import write_ptm

FULL = os.strerror(28)  # ENOSPC


@pytest.fixture
def small_disk(tmp_path: Path) -> Iterator[Path]:
    disk = tmp_path / "disk"
    disk.mkdir()
    done = subprocess.run(["mount", "-t", "tmpfs", "-o", "size=2m", "tmpfs", str(disk)],
                          capture_output=True, text=True)
    if done.returncode != 0:
        pytest.skip("cannot mount a 2 MB tmpfs here (needs root and a sandbox allowing "
                    f"mount): {done.stderr.strip() or done.returncode}")
    try:
        yield disk
    finally:
        subprocess.run(["umount", "--lazy", str(disk)], check=True)


def _open_in(folder: Path) -> list[str]:
    """Files of ``folder`` this process holds open (deleted ones still take up the disk)."""
    found = []
    for fd in os.listdir("/proc/self/fd"):
        try:
            target = os.readlink(f"/proc/self/fd/{fd}")
        except OSError:  # closed meanwhile (the listing's own descriptor)
            continue
        if target.startswith(f"{folder}/"):
            found.append(target)
    return found


def test_a_full_disk_is_one_line_and_leaves_nothing(
        small_disk: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    src = tmp_path / "big.ptm"  # ~3 MB of incompressible PNG planes: more than the disk
    write_ptm(src, random_ptm_of_size(640, 480, seed=4), "PTM_FORMAT_LRGB")
    out = small_disk / "obj"
    assert main(["import", str(src), "-o", str(out)]) == 2
    assert capsys.readouterr().err == (f"lanterna: error: {out}: cannot write ({FULL}); "
                                       "nothing was changed\n")
    assert os.listdir(small_disk) == [] and _open_in(small_disk) == []


def test_a_full_disk_keeps_the_previous_dataset(
        small_disk: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    small, big = tmp_path / "small.ptm", tmp_path / "big.ptm"
    write_ptm(small, random_ptm_of_size(64, 48, seed=1), "PTM_FORMAT_LRGB")
    write_ptm(big, random_ptm_of_size(640, 480, seed=4), "PTM_FORMAT_LRGB")
    out = small_disk / "obj"
    assert main(["import", str(small), "-o", str(out), "--label", "small"]) == 0
    version = os.readlink(out)
    capsys.readouterr()
    assert main(["import", str(big), "-o", str(out), "--force", "--label", "big"]) == 2
    assert capsys.readouterr().err == (f"lanterna: error: {out}: cannot write ({FULL}); "
                                       "nothing was changed\n")
    assert sorted(os.listdir(small_disk)) == sorted(["obj", version])
    assert read_description(out)["label"] == "small" and _open_in(small_disk) == []
