"""Property-based: mutated light-position (.lp) files are read or refused in one line.

A valid ``.lp`` file (Windows paths, CRLF, exponents) is mutated byte by byte and line by line;
each must give the files and unit lights or a one-line ``LanternaInputError`` naming it, within
the case bounds of ``fixtures/fuzz.py``.
"""

from __future__ import annotations

import shutil
import tempfile
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from lanterna.tiler.inputs.lp import read_lp
from tests.python.fixtures.fuzz import examples, mutate_bytes, outcome

LP = ("4\r\ncaptures\\IMG_000.jpg 0.5 0.1 0.86\r\ncaptures\\img_001.JPG -0.3 2e-1 9.5E-1\r\n"
      "C:\\shots\\my image 2.png 0 0 3\r\n/abs/IMG_003.jpg 1 1 1\r\n")
NAMES = ["IMG_000.jpg", "IMG_001.jpg", "my image 2.png", "IMG_003.jpg"]


@pytest.fixture(scope="module")
def images(tmp_path_factory: pytest.TempPathFactory) -> Path:
    folder = tmp_path_factory.mktemp("shots")
    for name in NAMES:
        (folder / name).write_bytes(b"")
    return folder


@settings(max_examples=examples(500))
@given(data=st.data())
def test_mutated_lp_files(images: Path, data: st.DataObject) -> None:
    text = LP.encode()
    if data.draw(st.booleans()):  # whole lines: dropped, repeated, or a field replaced
        lines = LP.splitlines(keepends=True)
        i = data.draw(st.integers(0, len(lines) - 1))
        edit = data.draw(st.sampled_from(["drop", "repeat", "field"]))
        if edit == "drop":
            del lines[i]
        elif edit == "repeat":
            lines.insert(i, lines[i])
        else:
            fields = lines[i].split(" ")
            j = data.draw(st.integers(0, len(fields) - 1))
            fields[j] = data.draw(st.sampled_from(["nan", "inf", "-0", "0", "1e400", "x", "",
                                                  "9" * 5000, "../x.jpg", "\t"]))
            lines[i] = " ".join(fields)
        text = "".join(lines).encode()
    folder = Path(tempfile.mkdtemp())
    path = folder / "dirs.lp"
    path.write_bytes(mutate_bytes(text, data.draw) if data.draw(st.booleans()) else text)
    result = outcome(".lp light positions", path, lambda: read_lp(path, images))
    if result is not None:
        files, lights = result
        assert len(files) == len(lights) and all(f.parent == images for f in files)
        np.testing.assert_allclose(np.linalg.norm(lights, axis=1), 1.0, rtol=1e-9)
    shutil.rmtree(folder)
