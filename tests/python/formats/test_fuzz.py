"""Property-based: mutated PTM, .rti and Relight web-format inputs are read or refused in one line.

Valid files of every kind (PTM RGB, LRGB, JPEG_RGB, JPEG_LRGB; .rti with byte and float
elements; Relight ptm/hsh folders) are mutated — bytes flipped, truncated, inserted, header
numbers made huge, negative or not numbers, info.json values replaced, planes swapped for a PNG
whose header declares 30000×30000 — and each must give a model or a one-line
``LanternaInputError`` naming the file, within the case bounds of ``fixtures/fuzz.py``.
"""

from __future__ import annotations

import json
import shutil
import struct
import tempfile
import zlib
from pathlib import Path

import numpy as np
import pytest
import pyvips
from hypothesis import given, settings
from hypothesis import strategies as st

from lanterna.tiler.formats.hsh import read_rti
from lanterna.tiler.formats.ptm import read_ptm
from lanterna.tiler.formats.relight_web import read_relight
from tests.python.fixtures.fuzz import examples, mutate_bytes, mutate_json, outcome
from tests.python.fixtures.ptm import LRGB_PREDICTION, random_ptm
from tests.python.fixtures.ptm_writer import write_ptm
from tests.python.fixtures.rti import random_hsh, write_rti

FORMATS = {"PTM_FORMAT_RGB": "rgb", "PTM_FORMAT_LRGB": "lrgb", "PTM_FORMAT_JPEG_RGB": "rgb",
           "PTM_FORMAT_JPEG_LRGB": "lrgb"}


@pytest.fixture(scope="module")
def scratch(tmp_path_factory: pytest.TempPathFactory) -> Path:
    return tmp_path_factory.mktemp("fuzz")


@pytest.fixture(scope="module")
def ptm_files(scratch: Path) -> list[bytes]:
    """One valid file per PTM format (and a predicted JPEG-LRGB one)."""
    out = []
    for i, (fmt, colorspace) in enumerate(FORMATS.items()):
        path = scratch / f"base{i}.ptm"
        write_ptm(path, random_ptm(colorspace, 9, 5, seed=i), fmt)  # type: ignore[arg-type]
        out.append(path.read_bytes())
    path = scratch / "predicted.ptm"
    write_ptm(path, random_ptm("lrgb", 9, 5), "PTM_FORMAT_JPEG_LRGB", prediction=LRGB_PREDICTION)
    out.append(path.read_bytes())
    return out


@pytest.fixture(scope="module")
def rti_files(scratch: Path) -> list[bytes]:
    out = []
    for i, (terms, element) in enumerate([(4, 1), (9, 4), (16, 1)]):
        path = scratch / f"base{i}.rti"
        write_rti(path, random_hsh(terms, seed=i, dyadic=True), element_size=element,
                  crlf=bool(i % 2))
        out.append(path.read_bytes())
    return out


def _case_file(scratch: Path, suffix: str, data: bytes) -> Path:
    folder = Path(tempfile.mkdtemp(dir=scratch))
    path = folder / f"case{suffix}"
    path.write_bytes(data)
    return path


@settings(max_examples=examples(600))
@given(data=st.data())
def test_mutated_ptm_files(scratch: Path, ptm_files: list[bytes], data: st.DataObject) -> None:
    base = data.draw(st.sampled_from(ptm_files))
    path = _case_file(scratch, ".ptm", mutate_bytes(base, data.draw))
    ptm = outcome("PTM", path, lambda: read_ptm(path))
    if ptm is not None:
        assert np.isfinite(ptm.scale).all() and ptm.coefficients.dtype == np.uint8
    shutil.rmtree(path.parent)


@settings(max_examples=examples(400))
@given(data=st.data())
def test_mutated_rti_files(scratch: Path, rti_files: list[bytes], data: st.DataObject) -> None:
    base = data.draw(st.sampled_from(rti_files))
    path = _case_file(scratch, ".rti", mutate_bytes(base, data.draw))
    hsh = outcome("HSH .rti", path, lambda: read_rti(path))
    if hsh is not None:
        assert np.isfinite(hsh.scale).all() and np.isfinite(hsh.bias).all()
    shutil.rmtree(path.parent)


def png_declaring(width: int, height: int) -> bytes:
    """A small PNG whose header declares ``width`` × ``height`` RGB (its data is a few rows)."""
    def chunk(kind: bytes, body: bytes) -> bytes:
        return (struct.pack(">I", len(body)) + kind + body
                + struct.pack(">I", zlib.crc32(kind + body) & 0xFFFFFFFF))
    ihdr = struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0)
    rows = zlib.compress(b"\0" + bytes(3 * width) * 1)
    return b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", ihdr) + chunk(b"IDAT", rows) + chunk(b"IEND", b"")


@pytest.fixture(scope="module")
def relight_folders(scratch: Path) -> list[Path]:
    """Relight web-format folders: ptm lrgb (9 planes) and hsh rgb (27 planes), 6 × 4 px."""
    rng = np.random.default_rng(0)
    out = []
    for name, rtype, colorspace, nplanes in (("ptm", "ptm", "lrgb", 9),
                                             ("hsh", "hsh", "rgb", 27)):
        folder = scratch / f"relight-{name}"
        folder.mkdir()
        for k in range(nplanes // 3):
            pixels = rng.integers(0, 256, (4, 6, 3), dtype=np.uint8)
            pyvips.Image.new_from_array(pixels).copy(interpretation="srgb").jpegsave(
                str(folder / f"plane_{k}.jpg"), Q=95)
        info = {"width": 6, "height": 4, "type": rtype, "colorspace": colorspace,
                "nplanes": nplanes, "format": "jpg", "quality": 95,
                "materials": [{"scale": [1.0] * nplanes, "bias": [0.0] * nplanes}]}
        (folder / "info.json").write_text(json.dumps(info))
        out.append(folder)
    return out


@settings(max_examples=examples(300))
@given(data=st.data())
def test_mutated_relight_folders(scratch: Path, relight_folders: list[Path],
                                 data: st.DataObject) -> None:
    base = data.draw(st.sampled_from(relight_folders))
    folder = Path(tempfile.mkdtemp(dir=scratch)) / "rti"
    shutil.copytree(base, folder)
    what = data.draw(st.sampled_from(["info", "info", "plane bytes", "bomb plane", "no plane"]))
    if what == "info":
        info = json.loads((folder / "info.json").read_text())
        (folder / "info.json").write_text(json.dumps(mutate_json(info, data.draw)))
    else:
        plane = folder / f"plane_{data.draw(st.integers(0, 2))}.jpg"
        if what == "plane bytes":
            plane.write_bytes(mutate_bytes(plane.read_bytes(), data.draw))
        elif what == "bomb plane":
            plane.write_bytes(png_declaring(30000, 30000))
        else:
            plane.unlink()
    layer = outcome("Relight web format", folder, lambda: read_relight(folder))
    if layer is not None:
        assert (layer.width, layer.height) == (6, 4)
    shutil.rmtree(folder.parent)


def test_a_plane_declaring_a_huge_image_is_refused_before_decoding(
        relight_folders: list[Path], tmp_path: Path) -> None:
    """The 2.6 MB decompression bomb of the issue, in miniature: refused from its header."""
    folder = tmp_path / "rti"
    shutil.copytree(relight_folders[0], folder)
    (folder / "plane_1.jpg").write_bytes(png_declaring(30000, 30000))
    assert outcome("Relight web format", folder, lambda: read_relight(folder)) is None
