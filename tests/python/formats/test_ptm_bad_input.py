"""PTM reader: every kind of bad input is a one-line error naming the file and the problem."""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

import numpy as np
import pytest
import pyvips

from lanterna.errors import LanternaInputError
from lanterna.tiler.formats.ptm import read_ptm
from tests.python.fixtures.ptm import LRGB_PREDICTION, random_ptm, smooth_ptm, with_overflow
from tests.python.fixtures.ptm_writer import PtmPrediction, write_ptm

W, H = 13, 7


def _raw_lrgb(tmp_path: Path) -> bytes:
    ptm = random_ptm("lrgb", W, H, seed=9)
    write_ptm(tmp_path / "base.ptm", ptm, "PTM_FORMAT_LRGB")
    return (tmp_path / "base.ptm").read_bytes()


def _jpeg_lrgb(tmp_path: Path) -> bytes:
    ptm = with_overflow(smooth_ptm("lrgb", 40, 24))
    write_ptm(tmp_path / "base.ptm", ptm, "PTM_FORMAT_JPEG_LRGB", prediction=LRGB_PREDICTION)
    return (tmp_path / "base.ptm").read_bytes()


def _replace_line(data: bytes, index: int, text: str) -> bytes:
    head = data.split(b"\n", 14)
    head[index] = text.encode()
    return b"\n".join(head)


def _jpeg_offsets(data: bytes) -> tuple[int, list[int], list[int]]:
    lines = data.split(b"\n", 14)
    start = len(data) - len(lines[14])
    return start, [int(t) for t in lines[12].split()], [int(t) for t in lines[13].split()]


def _cut_inside_stream(data: bytes, plane: int) -> bytes:
    start, sizes, sides = _jpeg_offsets(data)
    begin = start + sum(sizes[:plane]) + sum(sides[:plane])
    return data[: begin + sizes[plane] // 2]


def _garble_stream(data: bytes, plane: int) -> bytes:
    """Keep all sizes but replace the middle of one JPEG stream with junk."""
    start, sizes, sides = _jpeg_offsets(data)
    begin = start + sum(sizes[:plane]) + sum(sides[:plane]) + 2  # keep the SOI marker
    junk = bytes(np.random.default_rng(0).integers(0, 256, sizes[plane] - 4, dtype=np.uint8))
    return data[:begin] + junk + data[begin + len(junk) :]


def _truncate_stream_consistently(data: bytes, plane: int) -> bytes:
    """Drop the last 30 bytes (scan data) of one JPEG stream and fix the sizes line."""
    start, sizes, sides = _jpeg_offsets(data)
    begin = start + sum(sizes[:plane]) + sum(sides[:plane])
    kept = sizes[plane] - 30
    data = data[: begin + kept] + data[begin + sizes[plane] :]
    sizes[plane] = kept
    return _replace_line(data, 12, " ".join(map(str, sizes)))


def _colour_stream(data: bytes, plane: int) -> bytes:
    """Replace one stream by a 3-band JPEG of the right size and fix the sizes line."""
    start, sizes, sides = _jpeg_offsets(data)
    begin = start + sum(sizes[:plane]) + sum(sides[:plane])
    colour = pyvips.Image.black(40, 24, bands=3).jpegsave_buffer(Q=90)
    data = data[:begin] + colour + data[begin + sizes[plane] :]
    sizes[plane] = len(colour)
    return _replace_line(data, 12, " ".join(map(str, sizes)))


def _bad_side_index(data: bytes) -> bytes:
    start, sizes, sides = _jpeg_offsets(data)
    assert sides[0] >= 5
    at = start + sizes[0]  # plane 0's side info follows its stream
    return data[:at] + (40 * 24).to_bytes(4, "big") + data[at + 4 :]


BadCase = tuple[str, Callable[[Path], bytes], str]
BAD_CASES: list[BadCase] = [
    ("empty", lambda t: b"", "not a PTM file"),
    ("garbled", lambda t: bytes(range(256)) * 4, "not a PTM file"),
    ("cut in version line", lambda t: _raw_lrgb(t)[:5], "header ends before the version line"),
    ("cut in scale line", lambda t: _raw_lrgb(t)[:30], "header ends before the scale line"),
    ("cut in raw payload", lambda t: _raw_lrgb(t)[:-1], "payload is too short"),
    ("cut at end of header", lambda t: _raw_lrgb(t)[: -W * H * 9], "payload is too short"),
    ("extra bytes after raw payload", lambda t: _raw_lrgb(t) + b"\0", "payload is too long"),
    ("cut in JPEG header lines", lambda t: _jpeg_lrgb(t)[:150], "header ends before"),
    (
        "cut in JPEG stream 3",
        lambda t: _cut_inside_stream(_jpeg_lrgb(t), 3),
        "payload is too short",
    ),
    ("extra bytes after JPEG", lambda t: _jpeg_lrgb(t) + b"xx", "payload is too long"),
    ("corrupt JPEG stream", lambda t: _garble_stream(_jpeg_lrgb(t), 4), "JPEG stream 4 is corrupt"),
    (
        "truncated JPEG stream, sizes consistent",
        lambda t: _truncate_stream_consistently(_jpeg_lrgb(t), 2),
        "JPEG stream 2 is corrupt or truncated",
    ),
    (
        "colour JPEG stream",
        lambda t: _colour_stream(_jpeg_lrgb(t), 1),
        "JPEG stream 1 is 40x24 with 3 bands",
    ),
    (
        "side-info index out of range",
        lambda t: _bad_side_index(_jpeg_lrgb(t)),
        "side-info index 960",
    ),
    (
        "unknown format",
        lambda t: _replace_line(_raw_lrgb(t), 1, "PTM_FORMAT_FOO"),
        "unknown PTM format",
    ),
    (
        "LUM format",
        lambda t: _replace_line(_raw_lrgb(t), 1, "PTM_FORMAT_LUM"),
        "unsupported PTM format",
    ),
    (
        "JPEGLS format",
        lambda t: _replace_line(_raw_lrgb(t), 1, "PTM_FORMAT_JPEGLS_LRGB"),
        "unsupported PTM format",
    ),
    (
        "unknown version",
        lambda t: _replace_line(_raw_lrgb(t), 0, "PTM_1.3"),
        "unsupported PTM version",
    ),
    ("version line wrong", lambda t: _replace_line(_raw_lrgb(t), 0, "PTX_1.2"), "not a PTM file"),
    (
        "width mismatch",
        lambda t: _replace_line(_raw_lrgb(t), 2, str(W + 1)),
        "payload is too short",
    ),
    (
        "height mismatch",
        lambda t: _replace_line(_raw_lrgb(t), 3, str(H - 1)),
        "payload is too long",
    ),
    ("zero width", lambda t: _replace_line(_raw_lrgb(t), 2, "0"), "width must be positive"),
    ("negative height", lambda t: _replace_line(_raw_lrgb(t), 3, "-7"), "height must be positive"),
    ("absurd width", lambda t: _replace_line(_raw_lrgb(t), 2, "9999999"), "too large"),
    (
        "non-numeric width",
        lambda t: _replace_line(_raw_lrgb(t), 2, "thirteen"),
        "width line is not numeric",
    ),
    (
        "non-numeric scale",
        lambda t: _replace_line(_raw_lrgb(t), 4, "2 2 x 2 2 2"),
        "scale line is not numeric",
    ),
    (
        "five scales",
        lambda t: _replace_line(_raw_lrgb(t), 4, "2 2 2 2 2"),
        "scale line has 5 values",
    ),
    ("nan scale", lambda t: _replace_line(_raw_lrgb(t), 4, "2 2 nan 2 2 2"), "non-finite"),
    (
        "fractional bias",
        lambda t: _replace_line(_raw_lrgb(t), 5, "1 2 3 4 5 6.5"),
        "bias line must hold integers",
    ),
    (
        "JPEG width swapped",
        lambda t: _replace_line(_replace_line(_jpeg_lrgb(t), 2, "24"), 3, "40"),
        "expected single-band 24x40",
    ),
    (
        "motion vector",
        lambda t: _replace_line(_jpeg_lrgb(t), 8, "0 0 1 0 0 0 0 0 0"),
        "motion vectors",
    ),
    (
        "order not a permutation",
        lambda t: _replace_line(_jpeg_lrgb(t), 10, "0 0 1 2 3 4 5 6 7"),
        "not a permutation",
    ),
    (
        "reference decoded later",
        lambda t: _replace_line(_jpeg_lrgb(t), 11, "-1 0 -1 -1 -1 -1 -1 -1 -1").replace(
            b"\n8 4 3 2 1 7 5 0 6\n", b"\n1 0 2 3 4 5 6 7 8\n"
        ),
        "decoded before its reference",
    ),
    (
        "bad transform",
        lambda t: _replace_line(_jpeg_lrgb(t), 7, "2 0 0 0 0 1 0 0 0"),
        "unsupported plane transform",
    ),
    (
        "side-info size not a multiple of 5",
        lambda t: _replace_line(_jpeg_lrgb(t), 13, "3 0 0 0 0 0 0 0 0"),
        "multiples of 5",
    ),
]


@pytest.mark.parametrize(("name", "make", "problem"), BAD_CASES, ids=[c[0] for c in BAD_CASES])
def test_bad_input_names_file_and_problem(
    tmp_path: Path, name: str, make: Callable[[Path], bytes], problem: str
) -> None:
    path = tmp_path / "bad.ptm"
    path.write_bytes(make(tmp_path))
    with pytest.raises(LanternaInputError) as info:
        read_ptm(path)
    message = str(info.value)
    assert message.startswith(f"{path}: "), message
    assert problem in message, message
    assert "\n" not in message and "Traceback" not in message
    assert info.value.__cause__ is None or isinstance(info.value.__cause__, LanternaInputError)


def test_missing_file_and_directory(tmp_path: Path) -> None:
    with pytest.raises(LanternaInputError, match=r"nope\.ptm: file not found$"):
        read_ptm(tmp_path / "nope.ptm")
    with pytest.raises(LanternaInputError, match="is a directory"):
        read_ptm(tmp_path)


def test_writer_rejects_inconsistent_arguments(tmp_path: Path) -> None:
    lrgb = random_ptm("lrgb", W, H)
    with pytest.raises(LanternaInputError, match="needs an rgb PTM"):
        write_ptm(tmp_path / "x.ptm", lrgb, "PTM_FORMAT_JPEG_RGB")
    with pytest.raises(LanternaInputError, match="reference 1 is not decoded earlier"):
        bad = PtmPrediction(order=list(range(9)), reference=[1] + [-1] * 8, transform=[0] * 9)
        write_ptm(tmp_path / "x.ptm", lrgb, "PTM_FORMAT_JPEG_LRGB", prediction=bad)
    assert not (tmp_path / "x.ptm").exists()
