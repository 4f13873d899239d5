"""``--force`` over a dataset with annotations: its patch store is moved aside (never composited
over the new dataset unasked), the user is told where, and a failed replacement puts it back."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from lanterna.cli import main
from lanterna.tiler.overlays.store import add_patch, list_patches, store_root
from tests.python.fixtures.ptm import random_ptm_of_size
from tests.python.fixtures.ptm_writer import write_ptm


@pytest.fixture
def annotated(tmp_path: Path) -> tuple[Path, Path]:
    src = tmp_path / "obj.ptm"
    write_ptm(src, random_ptm_of_size(64, 48), "PTM_FORMAT_LRGB")
    out = tmp_path / "root" / "obj"
    assert main(["import", str(src), "-o", str(out)]) == 0
    square = np.zeros((8, 8, 4), np.uint8)
    square[..., 0] = square[..., 3] = 255
    add_patch(out, "obj", square, {"level": 0, "x": 4, "y": 4, "w": 8, "h": 8, "short": "a note"})
    return src, out


def test_force_moves_the_annotations_aside_and_says_where(
        annotated: tuple[Path, Path], capsys: pytest.CaptureFixture[str]) -> None:
    src, out = annotated
    capsys.readouterr()
    assert main(["import", str(src), "--force", "-o", str(out)]) == 0
    err = capsys.readouterr().err
    aside = [p for p in out.parent.iterdir() if p.name.startswith("obj.annotations.replaced-")]
    assert len(aside) == 1
    assert not store_root(out).exists()
    assert list_patches(out, "obj") == []  # the new dataset has no notes of the old one
    assert (aside[0] / "obj").is_dir() and any(aside[0].joinpath("obj").glob("*a-note.png"))
    assert f"moved to {aside[0]}" in err and f"mv {aside[0]} {store_root(out)}" in err


def test_a_failed_replacement_keeps_the_annotations_in_place(
        annotated: tuple[Path, Path], tmp_path: Path) -> None:
    _, out = annotated
    bad = tmp_path / "bad.ptm"
    bad.write_bytes(b"PTM_1.2\nnot a ptm\n")
    assert main(["import", str(bad), "--force", "-o", str(out)]) == 2
    assert [p["short"] for p in list_patches(out, "obj")] == ["a note"]
    assert not [p for p in out.parent.iterdir() if ".replaced-" in p.name]
