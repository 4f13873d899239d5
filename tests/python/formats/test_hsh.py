"""Tests for the HSH ``.rti`` reader and writer (tiler/formats/hsh.py)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from lanterna.tiler.formats.hsh import quantize_hsh, read_rti
from tests.python.fixtures.rti import H, W, header, random_hsh, table, write_rti

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


