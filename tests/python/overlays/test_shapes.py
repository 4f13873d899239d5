"""Annotation targets → shapes: xywh fragments, SVG elements and path data, levels."""

from __future__ import annotations

import math

import pytest

from lanterna.tiler.overlays.shapes import (
    DEFAULT_COLOUR,
    DEFAULT_FILL_OPACITY,
    ShapeError,
    bbox,
    parse_fragment,
    parse_svg,
    suggested_level,
)
from lanterna.tiler.overlays.svg_path import TOLERANCE, PathError, parse_path


@pytest.mark.parametrize(("value", "box"), [
    ("xywh=10,20,30,40", (10, 20, 40, 60)),
    ("xywh=pixel:270,120,90,170", (270, 120, 360, 290)),
    ("xywh=pixel:10.5,0.25,2,3", (10.5, 0.25, 12.5, 3.25)),
    ("xywh=percent:10,50,25,50", (40, 100, 140, 200)),  # of the 400x200 canvas
])
def test_fragments_are_rectangles(value: str, box: tuple[float, ...]) -> None:
    shape = parse_fragment(value, 400, 200)
    assert shape.bbox == pytest.approx(box)
    assert len(shape.rings) == 1 and len(shape.rings[0]) == 4


@pytest.mark.parametrize(("value", "message"), [
    ("xywh=pixel:315,150,0,0", "no area"),
    ("xywh=1,2,3", "not an xywh fragment"),
    ("t=10,20", "not an xywh fragment"),
    ("xywh=pixel:1,2,-3,4", "no area"),
])
def test_bad_fragments_say_why(value: str, message: str) -> None:
    with pytest.raises(ShapeError, match=message):
        parse_fragment(value, 100, 100)


def test_an_annotorious_polygon() -> None:
    # Annotorious 3 writes <svg><polygon points="x,y x,y …" /></svg>
    shapes = parse_svg('<svg><polygon points="172,160 199,15 223,6 239,132 244,173" /></svg>')
    assert len(shapes) == 1
    assert shapes[0].rings == (((172, 160), (199, 15), (223, 6), (239, 132), (244, 173)),)
    assert shapes[0].bbox == (172, 6, 244, 173)
    style = shapes[0].style
    assert (style.fill, style.stroke, style.fill_opacity, style.evenodd) == (
        DEFAULT_COLOUR, DEFAULT_COLOUR, DEFAULT_FILL_OPACITY, False)


def test_a_mirador_editor_path_with_curves_keeps_its_colours() -> None:
    # mirador-annotations (paper.js) writes a namespaced <svg> with styled paths, curves in them
    value = ("<svg xmlns='http://www.w3.org/2000/svg'><path xmlns='http://www.w3.org/2000/svg' "
             "d='M100,100c0,-50 100,-50 100,0c0,50 -100,50 -100,0z' fill-opacity='0' "
             "fill='#00BFFF' stroke='#00bfff' stroke-width='3'/></svg>")
    (shape,) = parse_svg(value)
    assert shape.style.fill == (0, 191, 255) and shape.style.stroke == (0, 191, 255)
    assert shape.style.fill_opacity == 0 and shape.style.stroke_width == 3
    (ring,) = shape.rings
    x0, y0, x1, y1 = shape.bbox
    # the two cubic halves of an ellipse-like loop: extremes at t=1/2, y = 100 ∓ 37.5
    assert (x0, x1) == pytest.approx((100, 200))
    assert (y0, y1) == pytest.approx((62.5, 137.5), abs=TOLERANCE)
    assert len(ring) > 20


def test_every_element_and_inherited_style() -> None:
    value = ('<svg><g fill="red" style="stroke: blue; fill-opacity: 0.5">'
             '<rect x="1" y="2" width="3" height="4"/>'
             '<circle cx="50" cy="50" r="10" fill="#0f0"/>'
             '<ellipse cx="0" cy="0" rx="20" ry="5" stroke="none"/>'
             '<polyline points="0,0 10,10 20,0"/>'
             '<line x1="1" y1="1" x2="5" y2="9"/>'
             '<path d="M0 0 H 10 V 10 H 0 Z M 20 20 l 5 5" fill-rule="evenodd"/>'
             '</g><title>ignored</title></svg>')
    rect, circle, ellipse, polyline, line, path = parse_svg(value)
    assert rect.rings == (((1, 2), (4, 2), (4, 6), (1, 6)),)
    assert (rect.style.fill, rect.style.stroke, rect.style.fill_opacity) == (
        (255, 0, 0), (0, 0, 255), 0.5)
    assert circle.style.fill == (0, 255, 0)
    assert circle.bbox == pytest.approx((40, 40, 60, 60), abs=TOLERANCE)
    # the circle's chords stay within the tolerance: every vertex on it, midpoints close
    ring = circle.rings[0]
    for (xa, ya), (xb, yb) in zip(ring, (*ring[1:], ring[0]), strict=True):
        assert math.hypot(xa - 50, ya - 50) == pytest.approx(10)
        assert 10 - math.hypot((xa + xb) / 2 - 50, (ya + yb) / 2 - 50) <= TOLERANCE
    assert ellipse.style.stroke is None
    assert ellipse.bbox == pytest.approx((-20, -5, 20, 5), abs=TOLERANCE)
    assert polyline.rings == () and polyline.lines == (((0, 0), (10, 10), (20, 0)),)
    assert line.lines == (((1, 1), (5, 9)),)
    assert path.rings == (((0, 0), (10, 0), (10, 10), (0, 10)),)
    assert path.lines == (((20, 20), (25, 25)),)
    assert path.style.evenodd
    assert bbox([rect, line]) == (1, 1, 5, 9)


def test_path_commands_absolute_and_relative() -> None:
    assert parse_path("M10,10 L20 10 l0 10 h-10 z m 30 0 H 50 V 20 v-5") == [
        ([(10, 10), (20, 10), (20, 20), (10, 20)], True),
        ([(40, 10), (50, 10), (50, 20), (50, 15)], False)]
    assert parse_path("m 1 1 2 0 0 2 z") == [([(1, 1), (3, 1), (3, 3)], True)]  # implicit l
    (points, closed), = parse_path("M0 0 Q 10 10 20 0 T 40 0")
    assert points[-1] == (40, 0) and not closed
    # T mirrors the control point: the second half is the first upside down
    middle = points[len(points) // 2 + len(points) // 4]
    assert middle[1] < 0
    (points, _), = parse_path("M0,0 C 0,10 10,10 10,0 S 20,-10 20,0")
    assert points[-1] == (20, 0)
    assert min(y for _, y in points) == pytest.approx(-7.5, abs=TOLERANCE)


@pytest.mark.parametrize(("d", "message"), [
    ("L 1 2", "must start with a moveto"),
    ("M 1", "needs 2 numbers"),
    ("M0 0 A 5 5 0 0 1 10 10", "arcs"),
    ("M0 0 L 1 1 Z 5 5", "numbers after Z"),
    ("M 0 0 X 1", "unexpected"),
])
def test_bad_path_data(d: str, message: str) -> None:
    with pytest.raises(PathError, match=message):
        parse_path(d)
    with pytest.raises(ShapeError, match=message):
        parse_svg(f'<svg><path d="{d}"/></svg>')


@pytest.mark.parametrize(("value", "message"), [
    ("<svg><polygon points='1,2 3'/></svg>", "pairs of numbers"),
    ("<svg><text>hi</text></svg>", "unsupported SVG element <text>"),
    ("<svg><polygon points='0,0 1,0 1,1' transform='scale(2)'/></svg>", "transform"),
    ("<svg><polygon points='0,0 1,0 1,1'", "not well-formed"),
    ('<!DOCTYPE svg [<!ENTITY a "b">]><svg/>', "DOCTYPE"),
    ("<svg><g/></svg>", "no shape"),
    ("<svg><rect width='0' height='4'/></svg>", "empty"),
    ("<svg><circle cx='1' cy='1'/></svg>", "needs r"),
    ("<svg><rect width='2' height='4' fill='chartreuse'/></svg>", "unsupported colour"),
    ("<svg><rect width='2' height='4' stroke-width='thick'/></svg>", "not a number"),
])
def test_bad_svg_says_why(value: str, message: str) -> None:
    with pytest.raises(ShapeError, match=message):
        parse_svg(value)


@pytest.mark.parametrize(("side", "deepest", "level"), [
    (10, 5, 0), (1024, 5, 0), (1025, 5, 1), (2048, 5, 1), (2049, 5, 2), (5000, 5, 3),
    (10**6, 5, 5), (5000, 1, 1)])
def test_the_suggested_level(side: float, deepest: int, level: int) -> None:
    assert suggested_level((7, 3, 7 + side, 3 + side / 2), deepest) == level
    # the formula of the contract, for the cases inside the clamp
    expected = min(deepest, max(0, math.ceil(math.log2(side / 1024))))
    assert suggested_level((0, 0, side / 3, side), deepest) == expected
