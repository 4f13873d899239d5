"""PNG header checks before decoding (tiler/overlays/png_check.py), on files libvips wrote."""

from __future__ import annotations

import struct
import zlib

import numpy as np
import pytest
import pyvips

from lanterna.tiler.overlays.png_check import MAX_SIDE, PngHeaderError, has_trns, read_header


def encoded(array: np.ndarray, **options: object) -> bytes:
    img = pyvips.Image.new_from_array(array)
    img = img.copy(interpretation="srgb" if array.shape[2] >= 3 else "b-w")
    data: bytes = img.pngsave_buffer(**options)
    return data


def chunk(kind: bytes, body: bytes) -> bytes:
    return struct.pack(">I", len(body)) + kind + body + struct.pack(
        ">I", zlib.crc32(kind + body) & 0xFFFFFFFF)


def test_images_with_alpha_pass_with_their_size() -> None:
    rgba = np.zeros((7, 9, 4), np.uint8)
    assert read_header(encoded(rgba)).width == 9
    grey_alpha = read_header(encoded(np.zeros((3, 5, 2), np.uint8)))
    assert (grey_alpha.width, grey_alpha.height, grey_alpha.colour_type) == (5, 3, 4)
    palette = encoded(rgba + 3, palette=True)  # an indexed PNG with a tRNS chunk
    assert read_header(palette).colour_type == 3 and has_trns(palette)


def test_an_image_without_alpha_is_refused_naming_its_kind() -> None:
    with pytest.raises(PngHeaderError, match=r"no alpha channel \(RGB PNG without "):
        read_header(encoded(np.zeros((4, 4, 3), np.uint8)))
    with pytest.raises(PngHeaderError, match=r"no alpha channel \(grey PNG"):
        read_header(encoded(np.zeros((4, 4, 1), np.uint8)))


def test_a_tRNS_after_the_image_data_does_not_count() -> None:
    sig = b"\x89PNG\r\n\x1a\n"
    ihdr = chunk(b"IHDR", struct.pack(">IIBBBBB", 2, 2, 8, 2, 0, 0, 0))
    late = sig + ihdr + chunk(b"IDAT", b"x") + chunk(b"tRNS", b"\0" * 6)
    early = sig + ihdr + chunk(b"tRNS", b"\0" * 6) + chunk(b"IDAT", b"x")
    assert not has_trns(late) and has_trns(early)
    assert read_header(early).colour_type == 2
    with pytest.raises(PngHeaderError, match="no alpha"):
        read_header(late)


@pytest.mark.parametrize(("width", "height", "too_large"), [
    (MAX_SIDE + 1, 10, True), (10, MAX_SIDE + 1, True), (4200, 4200, True), (4000, 4000, False),
    (0, 10, False)])
def test_sizes_come_from_the_header(width: int, height: int, too_large: bool) -> None:
    sig = b"\x89PNG\r\n\x1a\n"
    data = sig + chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, 6, 0, 0, 0))
    if width and not too_large:
        assert read_header(data).width == width
        return
    with pytest.raises(PngHeaderError) as caught:
        read_header(data)
    assert caught.value.too_large == too_large


@pytest.mark.parametrize("data", [b"", b"GIF89a", b"\x89PNG\r\n\x1a\n" + b"\0" * 30,
                                  b"\x89PNG\r\n\x1a\n\0\0\0\x0dIHDR"])
def test_what_is_not_a_png_is_refused(data: bytes) -> None:
    with pytest.raises(PngHeaderError, match="not a (valid )?PNG"):
        read_header(data)
