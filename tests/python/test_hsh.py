"""Tests for the HSH ``.rti`` reader and writer (tiler/formats/hsh.py)."""

from __future__ import annotations

import math
import struct
from pathlib import Path

import numpy as np
import numpy.typing as npt
import pytest

from lanterna.errors import LanternaInputError
from lanterna.tiler.formats.hsh import quantize_hsh, read_rti
from lanterna.tiler.formats.hsh_basis import hsh_weights
from lanterna.tiler.formats.hsh_model import Hsh
from tests.python.fixtures.rti_writer import write_rti

SHARED = Path(__file__).resolve().parents[3] / "shared"
VASE = SHARED / "realdata" / "chi-ushabti-vase" / "vase.rti"

W, H = 7, 5  # odd, non-square: a transposition or a row flip cannot pass unnoticed


def random_hsh(terms: int, seed: int = 0, dyadic: bool = False) -> Hsh:
    """Random bytes (0 and 255 present in every term) with per-term scale and bias.

    ``dyadic`` picks scale/bias values for which ``byte/255·scale + bias`` is exact at bytes 0
    and 255, so float files written from it requantise to the same scale and bias.
    """
    rng = np.random.default_rng(seed)
    coeffs = rng.integers(0, 256, (H, W, 3, terms), dtype=np.uint8)
    coeffs[0, 0, 0, :] = 0
    coeffs[H - 1, W - 1, 2, :] = 255
    if dyadic:
        scale = np.array([2.0 ** -(k % 4) for k in range(terms)], np.float32)
        bias = np.array([-(k % 3) * 0.25 for k in range(terms)], np.float32)
    else:
        scale = rng.uniform(0.3, 2.0, terms).astype(np.float32)
        bias = rng.uniform(-1.0, 0.2, terms).astype(np.float32)
    return Hsh(coeffs, scale, bias)


def header(*lines: str, eol: str = "\r\n") -> bytes:
    return ("".join(line + eol for line in lines)).encode("ascii")


def table(scale: list[float], bias: list[float]) -> bytes:
    return struct.pack(f"<{len(scale)}f", *scale) + struct.pack(f"<{len(bias)}f", *bias)


# --- round trips ------------------------------------------------------------------------------


@pytest.mark.parametrize("terms", [4, 9, 16])
@pytest.mark.parametrize("crlf", [True, False])
def test_byte_round_trip_is_exact(tmp_path: Path, terms: int, crlf: bool) -> None:
    hsh = random_hsh(terms, seed=terms)
    path = tmp_path / "a.rti"
    write_rti(path, hsh, crlf=crlf)
    data = path.read_bytes()
    eol = b"\r\n" if crlf else b"\n"
    head = b"#HSH1.2" + eol + b"3" + eol + f"{W} {H} 3".encode() + eol + f"{terms} 2 1".encode()
    assert data.startswith(head + eol)
    assert len(data) == len(head) + len(eol) + 8 * terms + W * H * 3 * terms
    back = read_rti(path)
    np.testing.assert_array_equal(back.coefficients, hsh.coefficients)
    np.testing.assert_array_equal(back.scale, hsh.scale)
    np.testing.assert_array_equal(back.bias, hsh.bias)
    again = tmp_path / "b.rti"
    write_rti(again, back, crlf=crlf)
    assert again.read_bytes() == data
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a.rti", "b.rti"]  # no temp files


@pytest.mark.parametrize("terms", [4, 9, 16])
@pytest.mark.parametrize("crlf", [True, False])
def test_float_round_trip_is_exact(tmp_path: Path, terms: int, crlf: bool) -> None:
    hsh = random_hsh(terms, seed=terms + 1, dyadic=True)
    path = tmp_path / "f.rti"
    write_rti(path, hsh, element_size=4, crlf=crlf)
    data = path.read_bytes()
    assert f"{terms} 2 4".encode() in data[:40]
    # hshfitter's float files carry scale 1 and bias 0; the payload is the float coefficients.
    head_len = len(data) - 8 * terms - W * H * 3 * terms * 4
    assert np.frombuffer(data[head_len : head_len + 8 * terms], "<f4").tolist() == (
        [1.0] * terms + [0.0] * terms
    )
    back = read_rti(path)
    np.testing.assert_array_equal(back.coefficients, hsh.coefficients)
    np.testing.assert_array_equal(back.scale, hsh.scale)
    np.testing.assert_array_equal(back.bias, hsh.bias)
    again = tmp_path / "g.rti"
    write_rti(again, back, element_size=4, crlf=crlf)
    assert again.read_bytes() == data


def test_float_elements_quantise_per_term_shared_by_rgb(tmp_path: Path) -> None:
    hsh = random_hsh(9, seed=3)  # non-dyadic: scale/bias come back to float32 rounding only
    path = tmp_path / "f.rti"
    write_rti(path, hsh, element_size=4)
    back = read_rti(path)
    np.testing.assert_array_equal(back.coefficients, hsh.coefficients)
    np.testing.assert_allclose(back.scale, hsh.scale, rtol=1e-5)
    np.testing.assert_allclose(back.bias, hsh.bias, atol=1e-6)
    np.testing.assert_allclose(back.dequantized(), hsh.dequantized(), atol=1e-5)


def test_quantize_hsh_uses_the_full_byte_range_and_handles_constant_terms() -> None:
    rng = np.random.default_rng(5)
    a = rng.uniform(-0.7, 1.3, (H, W, 3, 4))
    a[..., 2] = 0.25  # a constant term
    q = quantize_hsh(a)
    for k in (0, 1, 3):
        assert q.coefficients[..., k].min() == 0 and q.coefficients[..., k].max() == 255
    assert q.scale[2] == 0.0 and q.bias[2] == pytest.approx(0.25)
    np.testing.assert_allclose(q.dequantized(), a, atol=q.scale.max() / 255 / 2 + 1e-6)


def test_comment_lines_and_lf_header_are_read(tmp_path: Path) -> None:
    hsh = random_hsh(4, seed=7)
    path = tmp_path / "c.rti"
    write_rti(path, hsh, crlf=False, comments=("HSH1.2", " made by a test ", "#"))
    assert path.read_bytes().startswith(b"#HSH1.2\n# made by a test \n##\n3\n")
    back = read_rti(path)
    np.testing.assert_array_equal(back.coefficients, hsh.coefficients)


def test_hand_built_file_rows_top_down_and_rgb_term_interleave(tmp_path: Path) -> None:
    w, h, terms = 3, 2, 4

    def byte(y: int, x: int, c: int, k: int) -> int:
        return 100 * y + 30 * x + 10 * c + k  # unique, < 256

    payload = bytes(byte(y, x, c, k) for y in range(h) for x in range(w)
                    for c in range(3) for k in range(terms))
    scale, bias = [1.0, 2.0, 4.0, 8.0], [0.5, -0.25, 0.0, -1.0]
    path = tmp_path / "tiny.rti"
    path.write_bytes(header("#HSH1.2", "3", f"{w} {h} 3", f"{terms} 2 1")
                     + table(scale, bias) + payload)
    hsh = read_rti(path)
    assert (hsh.width, hsh.height, hsh.terms) == (w, h, terms)
    for y in range(h):
        for x in range(w):
            for c in range(3):
                for k in range(terms):
                    assert hsh.coefficients[y, x, c, k] == byte(y, x, c, k)
    assert hsh.scale.tolist() == scale and hsh.bias.tolist() == bias
    # a = byte/255·scale + bias, per term
    assert hsh.dequantized()[1, 2, 1, 3] == pytest.approx(byte(1, 2, 1, 3) / 255 * 8.0 - 1.0)


@pytest.mark.parametrize(("legacy", "terms"), [(1, 4), (2, 9)])
def test_legacy_term_codes_map_like_rtiviewer(tmp_path: Path, legacy: int, terms: int) -> None:
    payload = bytes(range(256)) * (W * H * 3 * terms // 256 + 1)
    path = tmp_path / "legacy.rti"
    path.write_bytes(header("3", f"{W} {H} 3", f"{legacy} 2 1")
                     + table([1.0] * terms, [0.0] * terms) + payload[: W * H * 3 * terms])
    assert read_rti(path).terms == terms


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


# --- the real vase ----------------------------------------------------------------------------


def three_light_normals(hsh: Hsh) -> npt.NDArray[np.float64]:
    """HSH normals per docs/rendering.md: relight at θ = 45°, φ = 30°, 150°, 270°, sum RGB,
    solve ``M·g = I`` with rows ``l_i``, normalise."""
    s, c = math.sin(math.pi / 4), math.cos(math.pi / 4)
    lights = np.array([[s * math.cos(p), s * math.sin(p), c]
                       for p in (math.pi / 6, 5 * math.pi / 6, 3 * math.pi / 2)])
    weights = np.stack([hsh_weights(lx, ly, hsh.terms) for lx, ly, _ in lights], axis=1)
    intensity = (hsh.dequantized().astype(np.float64) @ weights).sum(axis=2)
    g = intensity @ np.linalg.inv(lights).T
    length = np.linalg.norm(g, axis=-1, keepdims=True)
    n: npt.NDArray[np.float64] = np.where(length >= 1e-6, g / np.maximum(length, 1e-12),
                                          (0.0, 0.0, 1.0))
    return n


@pytest.mark.realdata
def test_real_vase_is_upright_and_its_normals_point_the_right_way() -> None:
    if not VASE.is_file():
        pytest.skip("../shared/realdata/chi-ushabti-vase/vase.rti not present "
                    "(read-only test data beside the repo)")
    hsh = read_rti(VASE)
    assert (hsh.width, hsh.height, hsh.terms) == (320, 470, 9)
    assert VASE.stat().st_size == 4_060_902
    a = hsh.dequantized()
    lum = (a @ hsh_weights(0.0, 0.0, 9)).mean(axis=2)
    mask = lum > 0.08  # the vase against its black background
    widths = mask.sum(axis=1)
    # Upright: black above the mouth, the pedestal at the bottom, the body widest low down.
    assert widths[:30].max() == 0 and widths[-10:].min() > 100
    widest = int(np.argmax(np.where(np.arange(hsh.height) < 430, widths, 0)))
    assert 240 < widest < 310
    # Side lights brighten the matching half of the vase.
    left_half, right_half = mask.copy(), mask.copy()
    left_half[:, hsh.width // 2 :] = False
    right_half[:, : hsh.width // 2] = False
    lit_left = (a @ hsh_weights(-0.8, 0.0, 9)).mean(axis=2)
    lit_right = (a @ hsh_weights(0.8, 0.0, 9)).mean(axis=2)
    assert lit_left[left_half].mean() > 1.3 * lit_left[right_half].mean()
    assert lit_right[right_half].mean() > 1.3 * lit_right[left_half].mean()

    n = three_light_normals(hsh)
    shoulder, lower = np.zeros_like(mask), np.zeros_like(mask)
    shoulder[widest - 80 : widest - 20] = mask[widest - 80 : widest - 20]
    lower[widest + 20 : widest + 110] = mask[widest + 20 : widest + 110]
    assert n[..., 1][shoulder].mean() > 0.15 and (n[..., 1][shoulder] > 0).mean() > 0.8
    assert n[..., 1][lower].mean() < -0.1
    left_rim, right_rim = [], []
    for y in range(200, 400):
        xs = np.nonzero(mask[y])[0]
        left_rim.append(n[y, xs[0] + 4 : xs[0] + 20, 0].mean())
        right_rim.append(n[y, xs[-1] - 19 : xs[-1] - 3, 0].mean())
    assert np.mean(left_rim) < -0.4 and max(left_rim) < 0
    assert np.mean(right_rim) > 0.4 and min(right_rim) > 0
