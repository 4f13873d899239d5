"""Compositing of overlay patches: source-over in order, exact alpha blending, resizing, fitting."""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pytest

from lanterna.errors import LanternaInputError
from lanterna.tiler.overlays import geometry as og
from lanterna.tiler.overlays.composite import composite, fit_level_image
from lanterna.tiler.overlays.patches import read_texts

RED, BLUE = (255, 0, 0), (0, 0, 255)


def _px(rgb: tuple[int, int, int], alpha: int, size: int = 2) -> np.ndarray:
    return np.tile(np.array([*rgb, alpha], np.uint8), (size, size, 1))


def _whole(level_size: int = 2) -> og.Placement:
    return og.Placement((0, 0, level_size, level_size), (0, 0, level_size, level_size))


# (patches in application order as (rgb, alpha), expected RGBA of the composite)
BLENDS = [
    ([(BLUE, 255), (RED, 255)], (255, 0, 0, 255)),  # the later patch wins where opaque
    ([(RED, 255), (BLUE, 255)], (0, 0, 255, 255)),
    ([(BLUE, 255), (RED, 128)], (128, 0, 127, 255)),  # 128/255 red over opaque blue
    ([(RED, 128)], (255, 0, 0, 128)),  # over transparent: straight colour kept
    ([(BLUE, 128), (RED, 128)], (170, 0, 85, 192)),  # two half-transparent layers
    ([(BLUE, 200), (RED, 0)], (0, 0, 255, 200)),  # a transparent patch changes nothing
    ([(RED, 0)], (0, 0, 0, 0)),  # fully transparent: colour 0
]


@pytest.mark.parametrize(("patches", "expected"), BLENDS)
def test_source_over_blending(patches: list[tuple[tuple[int, int, int], int]],
                              expected: tuple[int, int, int, int]) -> None:
    out = composite(2, 2, [(_px(rgb, a), _whole()) for rgb, a in patches])
    assert out.shape == (2, 2, 4) and out.dtype == np.uint8
    assert np.all(out == np.array(expected, np.uint8))


def test_clipped_patch_lands_on_its_clip_only() -> None:
    patch = np.zeros((4, 4, 4), np.uint8)
    patch[..., 3] = 255
    patch[..., 0] = np.arange(16).reshape(4, 4)  # tell the pixels apart
    placement = og.place(og.parse_patch_name("0_-1_-2_4_4_0_x.png"), 5, 5)
    assert placement is not None
    out = composite(5, 5, [(patch, placement)])
    np.testing.assert_array_equal(out[0:2, 0:3, 0], patch[2:4, 1:4, 0])
    assert not out[2:, :, 3].any() and not out[:, 3:, 3].any()


def test_resized_patch_keeps_a_uniform_colour_and_fills_its_rectangle() -> None:
    patch = _px((10, 200, 30), 255, size=64)
    placement = og.place(og.parse_patch_name("2_8_4_64_64_0_x.png"), 200, 100)
    assert placement is not None and placement.dest == (2, 1, 18, 17)
    out = composite(50, 25, [(patch, placement)])
    assert np.all(out[1:17, 2:18] == np.array([10, 200, 30, 255], np.uint8))
    assert out[..., 3].sum() == 16 * 16 * 255


def test_resize_does_not_bleed_transparent_colour() -> None:
    # half opaque green, half transparent *red*: premultiplied resizing keeps red out
    patch = np.zeros((4, 8, 4), np.uint8)
    patch[:, :4] = (0, 255, 0, 255)
    patch[:, 4:] = (255, 0, 0, 0)
    out = composite(2, 1, [(patch, og.Placement((0, 0, 2, 1), (0, 0, 2, 1)))])
    assert out[0, 0, 0] == 0 and out[0, 0, 1] == 255


@pytest.mark.parametrize(("size", "expected"), [
    ((50, 30), (50, 30)),  # the level's size
    ((49, 29), (50, 30)),  # floor-halved: padded
    ((199, 117), (50, 30)),  # the full canvas: downscaled
])
def test_level_image_fitting(size: tuple[int, int], expected: tuple[int, int]) -> None:
    img = _px((1, 2, 3), 255, size=1).repeat(size[1], 0).repeat(size[0], 1)
    out = fit_level_image(img, 2, 199, 117, Path("2.png"))
    assert (out.shape[1], out.shape[0]) == expected
    assert np.all(out[:28, :48] == np.array([1, 2, 3, 255], np.uint8))


def test_level_image_of_another_size_is_refused() -> None:
    with pytest.raises(LanternaInputError, match=r"2.png: is 10x10; level 2 of the 199x117 "
                                                 r"canvas is 50x30"):
        fit_level_image(np.zeros((10, 10, 4), np.uint8), 2, 199, 117, Path("2.png"))


def test_texts_accept_level_keys_and_refuse_others() -> None:
    assert read_texts({"2": {"short": "s"}, 0: {"long": "<p>l</p>"}}) == {
        2: {"short": "s", "long": ""}, 0: {"short": "", "long": "<p>l</p>"}}
    for bad, where in (({"x": {"short": "s"}}, "key 'x'"), ({"-1": {}}, "key '-1'"),
                       ({"1": "text"}, "1: expected an object"), ({"1": {"short": 3}}, "1.short")):
        with pytest.raises(LanternaInputError, match=re.escape(where)):
            read_texts(bad)
