"""Shapes rasterised into patches, checked against an independent rasterisation.

Tolerances: the fill equals the crossing-number evaluation of the same samples exactly (both
apply the documented sample rule); the outline is within one sample (1/16 of a pixel's coverage)
of the distance test, the rasteriser's round joins being 16-gons; against Pillow's polygon fill,
whose vertices are rounded to whole samples and whose boundary is inclusive, the mean difference
of coverage is under 0.02 and the area (total coverage) within 1.5 %.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from lanterna.tiler.overlays.geometry import Patch, destination
from lanterna.tiler.overlays.shape_raster import (
    DEFAULT_STROKE,
    SAMPLES,
    coverage,
    outline_rings,
    patch_rectangle,
    rasterise,
    stroke_width,
)
from lanterna.tiler.overlays.shapes import ShapeError, parse_fragment, parse_svg

from . import raster_reference as ref

#: An Annotorious 3 polygon (its demo page's church), fractional vertices added.
CHURCH = [(172.3, 160), (199, 15.7), (223, 6), (239, 132), (244, 173), (285, 179), (313, 208),
          (313, 251), (218, 306), (170, 290)]
YELLOW = (255, 204, 0)


def _svg(points: list[tuple[float, float]], extra: str = "") -> str:
    return f'<svg><polygon points="{" ".join(f"{x},{y}" for x, y in points)}" {extra}/></svg>'


def _dest(level: int, rect: tuple[int, int, int, int]) -> tuple[int, int, int, int]:
    return destination(Patch(level, *rect, order=0, info="", file=""))


@pytest.mark.parametrize("level", [0, 1, 2])
def test_the_fill_equals_an_independent_point_in_polygon_evaluation(level: int) -> None:
    shapes = parse_svg(_svg(CHURCH))
    dest = _dest(level, patch_rectangle(shapes, level, 400, 400))
    mine = coverage(shapes[0].rings, level, dest, evenodd=False)
    assert np.array_equal(mine, ref.crossing_fill(CHURCH, level, dest, SAMPLES))
    pillow = ref.pillow_fill(CHURCH, level, dest, SAMPLES)
    assert np.abs(mine - pillow).mean() < 0.02
    assert mine.sum() == pytest.approx(pillow.sum(), rel=0.015)
    # and the area is the polygon's (shoelace), to within the sampling
    xs, ys = np.array(CHURCH).T
    area = abs(np.dot(xs, np.roll(ys, -1)) - np.dot(ys, np.roll(xs, -1))) / 2 / 4**level
    assert mine.sum() == pytest.approx(area, rel=0.01)
    assert (mine.min(), mine.max()) == (0.0, 1.0)


@pytest.mark.parametrize("level", [0, 1, 3])
def test_the_outline_is_within_one_sample_of_the_distance_to_the_boundary(level: int) -> None:
    # moved off whole pixels: a sample exactly on the outline's border may go either way
    church = [(x + 0.3, y + 0.3) for x, y in CHURCH]
    shapes = parse_svg(_svg(church))
    dest = _dest(level, patch_rectangle(shapes, level, 400, 400))
    half = DEFAULT_STROKE * (1 << level) / 2
    mine = coverage(outline_rings(shapes[0], half), level, dest, evenodd=False)
    other = ref.distance_outline(church, True, half, level, dest, SAMPLES)
    assert np.abs(mine - other).max() <= 1 / SAMPLES**2
    assert np.abs(mine - other).mean() < 1e-3
    assert mine.sum() > 0


@pytest.mark.parametrize("level", [0, 2])
def test_a_patch_is_a_translucent_fill_under_an_opaque_outline(level: int) -> None:
    shapes = parse_svg(_svg(CHURCH))
    rect = patch_rectangle(shapes, level, 400, 400)
    dest = _dest(level, rect)
    img = rasterise(shapes, level, rect)
    assert img.shape == (dest[3] - dest[1], dest[2] - dest[0], 4)
    half = DEFAULT_STROKE * (1 << level) / 2
    expected = ref.composite([
        (ref.crossing_fill(CHURCH, level, dest, SAMPLES) * 0.3, YELLOW),
        (ref.distance_outline(CHURCH, True, half, level, dest, SAMPLES), YELLOW)])
    diff = np.abs(img.astype(float) - expected)
    assert diff[..., 3].max() <= 255 / SAMPLES**2 + 0.5  # one sample, and the rounding
    assert diff[..., 3].mean() < 0.5
    visible = img[..., 3] > 0
    assert diff[..., :3][visible].max() <= 0.5
    # the middle of the church is the translucent fill, a corner of the patch is empty
    cx, cy = (250 >> level) - dest[0], (220 >> level) - dest[1]
    assert tuple(img[cy, cx]) == (*YELLOW, round(0.3 * 255))
    assert img[0, -1, 3] == 0


def test_the_svg_colours_and_widths_are_used() -> None:
    shapes = parse_svg('<svg><rect x="10" y="10" width="40" height="20" fill="#0000ff" '
                       'fill-opacity="0.5" stroke="red" stroke-width="4"/></svg>')
    assert stroke_width(shapes[0], 0) == 4 and stroke_width(shapes[0], 2) == 1
    rect = patch_rectangle(shapes, 0, 100, 100)
    assert rect == (8, 8, 44, 24)  # grown by half the outline
    img = rasterise(shapes, 0, rect)
    assert tuple(img[12, 22]) == (0, 0, 255, 128)  # inside: the fill
    # the outline: y 8 to 12 around the edge y = 10, then the fill
    assert [tuple(img[y, 22]) for y in range(5)] == [(255, 0, 0, 255)] * 4 + [(0, 0, 255, 128)]


def test_no_fill_and_no_outline() -> None:
    none = parse_svg('<svg><rect width="8" height="8" fill="none" stroke="none"/></svg>')
    assert not rasterise(none, 0, patch_rectangle(none, 0, 50, 50))[..., 3].any()
    outline = parse_svg('<svg><rect x="4" y="4" width="8" height="8" fill="none"/></svg>')
    img = rasterise(outline, 0, patch_rectangle(outline, 0, 50, 50))
    assert img[1, 1, 3] == 255 and img[5, 5, 3] == 0  # the centre stays clear


def test_even_odd_leaves_the_hole_non_zero_fills_it() -> None:
    square = "M0 0 H 40 V 40 H 0 Z M 10 10 H 30 V 30 H 10 Z"  # both turning the same way
    for rule, hole in (("evenodd", 0.0), ("nonzero", 1.0)):
        shapes = parse_svg(f'<svg><path d="{square}" fill-rule="{rule}"/></svg>')
        cov = coverage(shapes[0].rings, 0, (0, 0, 40, 40), evenodd=shapes[0].style.evenodd)
        assert cov[20, 20] == hole and cov[5, 5] == 1.0
        assert cov.sum() == (1600 - 400 if rule == "evenodd" else 1600)


def test_coverage_at_fractional_edges() -> None:
    shape = parse_fragment("xywh=pixel:10.5,10,20,10", 100, 100)
    cov = coverage(shape.rings, 0, (0, 0, 40, 30), evenodd=False)
    assert cov.sum() == 200
    assert (cov[10, 10], cov[10, 11], cov[10, 30], cov[9, 11]) == (0.5, 1.0, 0.5, 0.0)


def test_a_large_shape_is_drawn_at_its_level_at_a_bounded_size() -> None:
    shapes = parse_svg('<svg><circle cx="5000" cy="4000" r="3000"/></svg>')
    rect = patch_rectangle(shapes, 3, 10000, 8000)
    img = rasterise(shapes, 3, rect)
    assert max(img.shape[:2]) <= 1024
    alpha = img[..., 3] > 0
    # the disc's area at level 3 (filled and outlined), to within the outline's ring
    assert alpha.sum() == pytest.approx(math.pi * (3000 / 8) ** 2, rel=0.02)


def test_a_shape_partly_outside_is_clipped_and_one_outside_refused() -> None:
    shapes = parse_svg('<svg><rect x="-20" y="-20" width="30" height="30"/></svg>')
    assert patch_rectangle(shapes, 0, 100, 100) == (0, 0, 11, 11)
    away = parse_svg('<svg><rect x="200" y="5" width="30" height="30"/></svg>')
    with pytest.raises(ShapeError, match="outside the 100x100 canvas"):
        patch_rectangle(away, 0, 100, 100)
