"""HSH ``.rti`` reader: bad input is a one-line error naming the file and the problem."""

from __future__ import annotations

import math
import struct
from pathlib import Path

import pytest

from lanterna.errors import LanternaInputError
from lanterna.tiler.formats.hsh import read_rti
from tests.python.fixtures.rti import H, W, header, table

# --- bad input --------------------------------------------------------------------------------


def _good(terms: int = 4, element: int = 1) -> tuple[bytes, bytes]:
    head = header("#HSH1.2", "3", f"{W} {H} 3", f"{terms} 2 {element}")
    body = table([1.0] * terms, [0.0] * terms) + bytes(W * H * 3 * terms * element)
    return head, body


BAD_CASES: dict[str, tuple[bytes, str]] = {
    "five terms": (header("3", f"{W} {H} 3", "5 2 1") + bytes(8 * 5 + W * H * 15),
                   "unsupported HSH term count 5"),
    "type PTM": (header("1", f"{W} {H} 3", "9 1 1"), "unsupported RTI type 1 (PTM)"),
    "type SH": (header("2", f"{W} {H} 3", "9 2 1"), "unsupported RTI type 2 (SH)"),
    "type adaptive": (header("4", f"{W} {H} 3", "9 2 1"), "unsupported RTI type 4"),
    "short payload": (_good()[0] + _good()[1][:-1], "payload is too short"),
    "long payload": (_good()[0] + _good()[1] + b"\0", "payload is too long"),
    "float payload short": (_good(element=4)[0] + _good(element=4)[1][:-4],
                            "payload is too short"),
    "truncated header": (b"#HSH1.2\r\n3\r\n320 47", "header ends before the size line"),
    "only comments": (b"#HSH1.2\r\n#x\r\n", "header ends before the RTI type line"),
    "empty file": (b"", "header ends before the RTI type line"),
    "non-numeric size": (header("3", "320 abc 3", "9 2 1"), "size line must hold integers"),
    "non-numeric type": (header("HSH", "320 470 3", "9 2 1"), "RTI type line must hold integers"),
    "float size": (header("3", "320.5 470 3", "9 2 1"), "size line must hold integers"),
    "missing value": (header("3", "320 470", "9 2 1"), "size line has 2 values, expected 3"),
    "zero width": (header("3", "0 470 3", "9 2 1"), "image size must be positive"),
    "one colour": (header("3", f"{W} {H} 1", "9 2 1"), "unsupported colour count 1"),
    "element size 2": (header("3", f"{W} {H} 3", "9 2 2"), "unsupported element size 2"),
    "basis type 7": (header("3", f"{W} {H} 3", "9 7 1"), "unknown basis type 7"),
    "truncated table": (header("3", f"{W} {H} 3", "9 2 1") + bytes(40),
                        "file ends inside the scale/bias table"),
    "nan scale": (header("3", f"{W} {H} 3", "4 2 1") + table([math.nan, 1, 1, 1], [0] * 4)
                  + bytes(W * H * 12), "scale/bias table holds a non-finite value"),
    "binary header": (b"\xff\xfe\x00\x01\n", "RTI type line is not ASCII"),
    "ptm file": (b"PTM_1.2\nPTM_FORMAT_RGB\n", "is a PTM file"),
}


@pytest.mark.parametrize("case", sorted(BAD_CASES))
def test_bad_input_gives_one_line_error_naming_the_file(tmp_path: Path, case: str) -> None:
    data, expected = BAD_CASES[case]
    path = tmp_path / "bad.rti"
    path.write_bytes(data)
    with pytest.raises(LanternaInputError) as err:
        read_rti(path)
    message = str(err.value)
    assert expected in message
    assert message.startswith(str(path) + ": ")
    assert "\n" not in message


def test_non_finite_float_payload_is_rejected(tmp_path: Path) -> None:
    head, body = _good(element=4)
    body = body[:-4] + struct.pack("<f", math.inf)
    path = tmp_path / "inf.rti"
    path.write_bytes(head + body)
    with pytest.raises(LanternaInputError, match="non-finite float value"):
        read_rti(path)


def test_missing_file_and_directory(tmp_path: Path) -> None:
    with pytest.raises(LanternaInputError, match="file not found"):
        read_rti(tmp_path / "nope.rti")
    with pytest.raises(LanternaInputError, match="is a directory"):
        read_rti(tmp_path)
