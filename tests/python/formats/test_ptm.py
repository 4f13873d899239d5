"""Tests for the PTM reader (tiler/formats/ptm.py) and the tests' PTM writer (fixtures/)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from lanterna.tiler.formats.ptm import read_ptm
from lanterna.tiler.formats.ptm_model import Ptm
from tests.python.fixtures.ptm import (
    LRGB_PREDICTION,
    RGB_PREDICTION,
    header_bytes,
    jpeg_bytes,
    planes_of,
    random_ptm,
    reference_decode_jpeg_ptm,
    smooth_ptm,
    with_overflow,
)
from tests.python.fixtures.ptm_writer import PtmFormat, PtmPrediction, write_ptm

W, H = 13, 7  # odd, non-square: a transposition or a missed flip cannot pass unnoticed


def assert_same_ptm(a: Ptm, b: Ptm) -> None:
    assert a.colorspace == b.colorspace
    np.testing.assert_array_equal(a.coefficients, b.coefficients)
    np.testing.assert_array_equal(a.scale, b.scale)
    np.testing.assert_array_equal(a.bias, b.bias)
    if a.rgb is None:
        assert b.rgb is None
    else:
        assert b.rgb is not None
        np.testing.assert_array_equal(a.rgb, b.rgb)


# --- uncompressed formats -------------------------------------------------------------------


@pytest.mark.parametrize(
    ("fmt", "version", "colorspace"),
    [
        ("PTM_FORMAT_RGB", "PTM_1.2", "rgb"),
        ("PTM_FORMAT_LRGB", "PTM_1.2", "lrgb"),
        ("PTM_FORMAT_LRGB", "PTM_1.1", "lrgb"),
    ],
)
def test_uncompressed_round_trip_is_byte_exact(
    tmp_path: Path, fmt: PtmFormat, version: str, colorspace: str
) -> None:
    ptm = random_ptm(colorspace, W, H)
    path = tmp_path / "a.ptm"
    write_ptm(path, ptm, fmt, version=version)
    back = read_ptm(path)
    assert (back.width, back.height) == (W, H)
    assert_same_ptm(ptm, back)
    per_texel = 18 if colorspace == "rgb" else 9
    data = path.read_bytes()
    header_end = [i for i, b in enumerate(data) if b == ord("\n")][5] + 1  # six header lines
    assert data[:header_end].split(b"\n")[:2] == [version.encode(), fmt.encode()]
    assert len(data) - header_end == W * H * per_texel
    assert list(tmp_path.iterdir()) == [path]  # no temporary file left behind


def _rows_bottom_up(a: np.ndarray) -> bytes:
    return np.ascontiguousarray(a[::-1]).tobytes()


def test_reader_on_hand_built_rgb_file(tmp_path: Path) -> None:
    ptm = random_ptm("rgb", W, H, seed=1)
    blocks = b"".join(_rows_bottom_up(ptm.coefficients[:, :, c, :]) for c in range(3))
    path = tmp_path / "rgb.ptm"
    path.write_bytes(header_bytes("PTM_FORMAT_RGB", W, H) + blocks)
    back = read_ptm(path)
    assert_same_ptm(ptm, back)
    # The top row of the image is the LAST row of the red block in the file.
    red_block = blocks[: W * H * 6]
    assert back.coefficients[0, :, 0, :].tobytes() == red_block[-W * 6 :]
    assert back.coefficients[H - 1, :, 0, :].tobytes() == red_block[: W * 6]


def test_reader_on_hand_built_lrgb_12_file(tmp_path: Path) -> None:
    ptm = random_ptm("lrgb", W, H, seed=2)
    assert ptm.rgb is not None
    payload = _rows_bottom_up(ptm.coefficients) + _rows_bottom_up(ptm.rgb)
    path = tmp_path / "lrgb12.ptm"
    path.write_bytes(header_bytes("PTM_FORMAT_LRGB", W, H) + payload)
    back = read_ptm(path)
    assert_same_ptm(ptm, back)
    assert back.coefficients[0].tobytes() == payload[W * H * 6 - W * 6 : W * H * 6]
    assert back.rgb is not None and back.rgb[0].tobytes() == payload[-W * 3 :]


def test_reader_on_hand_built_lrgb_11_file(tmp_path: Path) -> None:
    ptm = random_ptm("lrgb", W, H, seed=3)
    assert ptm.rgb is not None
    texels = np.concatenate([ptm.coefficients, ptm.rgb], axis=2)  # a0..a5, R, G, B
    payload = _rows_bottom_up(texels)
    path = tmp_path / "lrgb11.ptm"
    path.write_bytes(header_bytes("PTM_FORMAT_LRGB", W, H, version="PTM_1.1") + payload)
    back = read_ptm(path)
    assert_same_ptm(ptm, back)
    assert back.rgb is not None
    assert back.rgb[0, 0].tobytes() == payload[-W * 9 + 6 : -W * 9 + 9]


def test_header_tolerates_trailing_spaces_and_crlf(tmp_path: Path) -> None:
    ptm = random_ptm("lrgb", W, H, seed=4)
    assert ptm.rgb is not None
    head = header_bytes("PTM_FORMAT_LRGB", W, H).replace(b"\n", b"  \r\n")
    path = tmp_path / "crlf.ptm"
    path.write_bytes(head + _rows_bottom_up(ptm.coefficients) + _rows_bottom_up(ptm.rgb))
    assert_same_ptm(ptm, read_ptm(path))


def test_writer_preserves_unusual_scales(tmp_path: Path) -> None:
    ptm = random_ptm("lrgb", W, H)
    odd = Ptm(
        "lrgb",
        ptm.coefficients,
        np.array([1e-7, 0.1, 1 / 3, 7, 123.456, 2], np.float32),
        ptm.bias,
        ptm.rgb,
    )
    write_ptm(tmp_path / "s.ptm", odd, "PTM_FORMAT_LRGB")
    np.testing.assert_array_equal(read_ptm(tmp_path / "s.ptm").scale, odd.scale)


# --- JPEG formats ---------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("fmt", "colorspace"), [("PTM_FORMAT_JPEG_LRGB", "lrgb"), ("PTM_FORMAT_JPEG_RGB", "rgb")]
)
def test_jpeg_without_prediction_at_q100_is_close(
    tmp_path: Path, fmt: PtmFormat, colorspace: str
) -> None:
    ptm = smooth_ptm(colorspace, 41, 23)
    path = tmp_path / "j.ptm"
    write_ptm(path, ptm, fmt, jpeg_quality=100)
    back = read_ptm(path)
    assert (back.colorspace, back.width, back.height) == (colorspace, 41, 23)
    diff = np.abs(planes_of(back).astype(int) - planes_of(ptm))
    assert diff.max() <= 3
    np.testing.assert_array_equal(planes_of(back), reference_decode_jpeg_ptm(path))
    np.testing.assert_array_equal(back.scale, ptm.scale)
    np.testing.assert_array_equal(back.bias, ptm.bias)


@pytest.mark.parametrize(
    ("fmt", "colorspace", "prediction", "patched_planes"),
    [
        ("PTM_FORMAT_JPEG_LRGB", "lrgb", LRGB_PREDICTION, (0, 6)),
        ("PTM_FORMAT_JPEG_RGB", "rgb", RGB_PREDICTION, (1, 6)),
    ],
)
def test_jpeg_with_prediction_matches_independent_decode(
    tmp_path: Path,
    fmt: PtmFormat,
    colorspace: str,
    prediction: PtmPrediction,
    patched_planes: tuple[int, ...],
) -> None:
    ptm = with_overflow(smooth_ptm(colorspace, 40, 24, seed=5))
    path = tmp_path / "p.ptm"
    write_ptm(path, ptm, fmt, jpeg_quality=90, prediction=prediction)
    lines = path.read_bytes().split(b"\n", 14)
    assert [int(t) for t in lines[7].split()] == list(prediction.transform)
    assert [int(t) for t in lines[10].split()] == list(prediction.order)
    assert [int(t) for t in lines[11].split()] == list(prediction.reference)
    side_sizes = [int(t) for t in lines[13].split()]
    for plane in patched_planes:
        assert side_sizes[plane] >= 5, f"plane {plane} should carry side info"

    back = read_ptm(path)
    got = planes_of(back)
    want = planes_of(ptm)
    np.testing.assert_array_equal(got, reference_decode_jpeg_ptm(path))
    # Side info makes the clipped pixel exact ...
    for plane in patched_planes:
        assert got[plane, 2, 5] == want[plane, 2, 5]
    # ... and the rest stays close (the encoder predicts from the decoded reference).
    assert np.abs(got.astype(int) - want).mean() < 2.0


def test_hand_built_jpeg_lrgb_prediction_transform_and_side_info(tmp_path: Path) -> None:
    """Constant planes decode exactly, so every expected value is known in closed form."""
    w, h = 16, 9
    residual = [200, 150, 20, 128, 128, 128, 60, 70, 80]
    # plane 1 <- inv(plane 0); plane 2 <- plane 1 (wraps below 0); plane 3 <- plane 2.
    reference = [-1, 0, 1, 2, -1, -1, -1, -1, -1]
    transform = [0, 1, 0, 0, 0, 0, 0, 0, 1]  # transform on a plane without reference: ignored
    order = [3, 4, 5, 6, 7, 8, 2, 1, 0]  # planes 8, 7, 6 first, then 0..5
    side = [b""] * 9
    side[2] = (0).to_bytes(4, "big") + bytes([9])  # raster index 0 = bottom-left pixel
    side[2] += (w * h - 1).to_bytes(4, "big") + bytes([250])  # last = top-right pixel
    streams = [jpeg_bytes(np.full((h, w), v, np.uint8)) for v in residual]
    head = header_bytes(
        "PTM_FORMAT_JPEG_LRGB", w, h, scale="2 2 2 2 2 2", bias="160 160 160 127 127 0"
    )
    jpeg_lines = [
        "95",
        " ".join(map(str, transform)),
        " ".join(["0"] * 9),
        " ".join(["0"] * 9),
        " ".join(map(str, order)),
        " ".join(map(str, reference)),
        " ".join(str(len(s)) for s in streams),
        " ".join(str(len(s)) for s in side),
    ]
    body = b"".join(s + q for s, q in zip(streams, side, strict=True))
    path = tmp_path / "hand.ptm"
    path.write_bytes(head + ("\n".join(jpeg_lines) + "\n").encode() + body)

    ptm = read_ptm(path)
    c = ptm.coefficients
    assert ptm.rgb is not None
    np.testing.assert_array_equal(ptm.scale, [2.0] * 6)
    np.testing.assert_array_equal(ptm.bias, [160, 160, 160, 127, 127, 0])
    assert np.all(c[..., 0] == 200)
    assert np.all(c[..., 1] == (255 - 200) + 150 - 128)  # 77
    p2 = (77 + 20 - 128) % 256  # 225
    assert c[h - 1, 0, 2] == 9  # side info at raster 0 lands bottom-left (rows top-down)
    assert c[0, w - 1, 2] == 250  # raster index w*h-1 lands top-right
    interior = np.ones((h, w), bool)
    interior[h - 1, 0] = interior[0, w - 1] = False
    assert np.all(c[..., 2][interior] == p2)
    # plane 3 is predicted from the patched plane 2
    assert c[h - 1, 0, 3] == 9 and c[0, w - 1, 3] == 250 and c[1, 1, 3] == p2
    assert np.all(ptm.rgb[..., 0] == 60) and np.all(ptm.rgb[..., 2] == 80)
