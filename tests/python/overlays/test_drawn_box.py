"""A level image's drawn box in canvas pixels (the level record's ``box``)."""

from __future__ import annotations

import numpy as np

from lanterna.tiler.overlays.composite import drawn_box
from lanterna.tiler.overlays.geometry import level_size


def test_nothing_drawn_has_no_box() -> None:
    assert drawn_box(np.zeros((4, 5, 4), np.uint8), 0, 5, 4) is None


def test_a_level_pixel_covers_two_to_the_level_canvas_pixels_clipped_to_the_canvas() -> None:
    width, height = 601, 399  # level 1 is 301 x 200: its last column and row reach past
    lw, lh = level_size(width, height, 1)
    rgba = np.zeros((lh, lw, 4), np.uint8)
    rgba[199, 300, 3] = 1  # the corner pixel, barely visible
    rgba[3, 7, 3] = 255
    assert drawn_box(rgba, 1, width, height) == [14, 6, width - 14, height - 6]


def test_colour_without_alpha_is_not_drawn() -> None:
    rgba = np.zeros((8, 8, 4), np.uint8)
    rgba[..., :3] = 255  # transparent white
    rgba[2:4, 5, 3] = 10
    assert drawn_box(rgba, 2, 32, 32) == [20, 8, 4, 8]
