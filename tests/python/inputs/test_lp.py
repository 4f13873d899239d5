"""Light-position files: the variants seen in the wild, and one-line errors for bad ones."""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np
import pytest

from lanterna.errors import LanternaInputError
from lanterna.tiler.inputs.lp import read_lp

DISK = ["000.JPG", "001.jpg", "my image 2.png"]

# name → (.lp text, expected file names on disk, expected first light before normalisation)
GOOD = {
    "windows-paths": ("3\njpeg-exports\\000.jpg 1 0 0\njpeg-exports\\001.jpg 0 2 0\n"
                      "C:\\shots\\my image 2.png 0 0 3\n", DISK, (1, 0, 0)),
    "relative-posix": ("3\njpg/000.JPG 0 0 5\njpg/001.jpg 0 1 1\nmy image 2.png 1 1 1\n",
                       DISK, (0, 0, 1)),
    "case-and-crlf": ("3\r\n000.jpg -2 0 2\r\n001.JPG 0 0 1\r\nMY IMAGE 2.PNG 0 0 1\r\n\r\n",
                      DISK, (-1, 0, 1)),
    "tabs-and-exponents": ("2\n000.jpg\t1e-1\t0\t1E-1\n/abs/001.jpg 0 0 1\n",
                           DISK[:2], (1, 0, 1)),
}

# name → (.lp text, fragment expected in the error)
BAD = {
    "empty": ("", "empty light file"),
    "count-not-a-number": ("three\n000.jpg 0 0 1\n", "line 1: expected the image count"),
    "count-zero": ("0\n", "line 1: image count must be at least 1"),
    "too-few-rows": ("3\n000.jpg 0 0 1\n001.jpg 0 0 1\n", "line 1: says 3 images but 2 rows"),
    "too-many-rows": ("1\n000.jpg 0 0 1\n001.jpg 0 0 1\n", "says 1 images but 2 rows"),
    "short-row": ("2\n000.jpg 0 0 1\n001.jpg 0 1\n", "line 3: expected 'filename x y z'"),
    "non-numeric": ("2\n000.jpg 0 0 1\n001.jpg 0 up 1\n", "line 3: non-numeric direction"),
    "zero-vector": ("2\n000.jpg 0 0 0\n001.jpg 0 0 1\n", "line 2: zero light vector for 000.jpg"),
    "nan": ("1\n000.jpg nan 0 1\n", "line 2: non-finite direction"),
    "missing-image": ("2\n000.jpg 0 0 1\nmissing.jpg 0 0 1\n",
                      "line 3: image missing.jpg not found in"),
}


@pytest.fixture
def images(tmp_path: Path) -> Path:
    folder = tmp_path / "imgs"
    folder.mkdir()
    for name in DISK:
        (folder / name).write_bytes(b"x")
    return folder


@pytest.mark.parametrize("case", GOOD, ids=list(GOOD))
def test_reads_variants(case: str, images: Path, tmp_path: Path) -> None:
    text, names, first = GOOD[case]
    lp = tmp_path / "lights.lp"
    lp.write_bytes(text.encode())
    files, lights = read_lp(lp, images)
    assert [f.name for f in files] == names
    assert all(f.parent == images for f in files)
    assert lights.shape == (len(names), 3)
    np.testing.assert_allclose(np.linalg.norm(lights, axis=1), 1.0, atol=1e-12)
    expected = np.asarray(first, float) / np.linalg.norm(first)
    np.testing.assert_allclose(lights[0], expected, atol=1e-12)


@pytest.mark.parametrize("case", BAD, ids=list(BAD))
def test_bad_files_are_one_line_errors(case: str, images: Path, tmp_path: Path) -> None:
    text, fragment = BAD[case]
    lp = tmp_path / "bad.lp"
    lp.write_text(text)
    with pytest.raises(LanternaInputError) as info:
        read_lp(lp, images)
    message = str(info.value)
    assert "\n" not in message
    assert message.startswith(str(lp))
    assert fragment in message


def test_ambiguous_case_is_an_error(tmp_path: Path) -> None:
    folder = tmp_path / "imgs"
    folder.mkdir()
    (folder / "A.jpg").write_bytes(b"x")
    (folder / "a.JPG").write_bytes(b"x")
    lp = tmp_path / "l.lp"
    lp.write_text("1\na.jpg 0 0 1\n")
    with pytest.raises(LanternaInputError, match="differ only in case"):
        read_lp(lp, folder)
    lp.write_text("1\nA.jpg 0 0 1\n")  # an exact match wins
    assert read_lp(lp, folder)[0][0].name == "A.jpg"


def test_unreadable_file(tmp_path: Path) -> None:
    with pytest.raises(LanternaInputError, match="nope.lp: file not found"):
        read_lp(tmp_path / "nope.lp", tmp_path)
    with pytest.raises(LanternaInputError, match="is a directory"):
        read_lp(tmp_path, tmp_path)


def test_a_device_or_fifo_is_refused_without_blocking(tmp_path: Path) -> None:
    """``/dev/zero`` would read forever and a FIFO would block: both are refused at once."""
    with pytest.raises(LanternaInputError, match="not a regular file"):
        read_lp(Path("/dev/zero"), tmp_path)
    fifo = tmp_path / "lights.lp"
    os.mkfifo(fifo)
    with pytest.raises(LanternaInputError, match="lights.lp: is not a regular file"):
        read_lp(fifo, tmp_path)


def _collection(root: Path, names: list[str]) -> Path:
    """``root/dirs.lp`` naming ``jpg/…`` files in ``root/jpg/``, as collections are laid out."""
    (root / "jpg").mkdir(parents=True)
    for name in names:
        (root / "jpg" / name).write_bytes(b"x")
    lp = root / "dirs.lp"
    rows = [f"jpg/{n} 0.1 0.2 0.9" for n in names]
    lp.write_text("\n".join([str(len(rows)), *rows]) + "\n")
    return lp


def test_names_are_paths_relative_to_the_lp_file_first(tmp_path: Path) -> None:
    lp = _collection(tmp_path / "photos", ["a.jpg", "b.jpg"])
    # the README's pattern: the collection's folder as the images folder, the .lp in it
    files, _ = read_lp(lp, tmp_path / "photos")
    assert files == [tmp_path / "photos" / "jpg" / "a.jpg", tmp_path / "photos" / "jpg" / "b.jpg"]
    # the images folder itself, too
    assert read_lp(lp, tmp_path / "photos" / "jpg")[0] == files


def test_relative_parts_match_case_insensitively_and_windows_separators(tmp_path: Path) -> None:
    lp = _collection(tmp_path / "photos", ["IMG_1.JPG"])
    lp.write_text("1\nJPG\\img_1.jpg 0 0 1\n")
    assert read_lp(lp, tmp_path / "elsewhere")[0] == [tmp_path / "photos" / "jpg" / "IMG_1.JPG"]


def test_parent_and_absolute_names_fall_back_to_the_images_folder(tmp_path: Path) -> None:
    (tmp_path / "outside.jpg").write_bytes(b"secret")
    images = tmp_path / "photos" / "jpg"
    images.mkdir(parents=True)
    (images / "outside.jpg").write_bytes(b"x")
    lp = tmp_path / "photos" / "dirs.lp"
    for name in ("../outside.jpg", str(tmp_path / "outside.jpg")):
        lp.write_text(f"1\n{name} 0 0 1\n")
        assert read_lp(lp, images)[0] == [images / "outside.jpg"]  # never the file outside
