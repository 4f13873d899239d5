"""Pure geometry of W3C annotation targets: ``xywh`` fragments and SVG shapes, their bounding box
and the level a patch of them is drawn at (docs/annotations.md, "Individual annotations (W3C)").

- :func:`parse_fragment`: a media-fragment ``xywh=X,Y,W,H``, ``xywh=pixel:…`` or
  ``xywh=percent:…`` (percentages of the canvas size, converted) → a rectangle shape.
- :func:`parse_svg`: an ``SvgSelector`` value → shapes: ``<polygon points>``, ``<polyline>``,
  ``<line>``, ``<path d>`` (:mod:`.svg_path`: straight segments and flattened curves; arcs
  refused), ``<rect>`` (``rx``/``ry`` ignored), ``<circle>`` and ``<ellipse>`` (polygons within
  :data:`~.svg_path.TOLERANCE` px), inside ``<svg>`` and ``<g>``. Each keeps its ``fill``,
  ``stroke``, ``fill-opacity``, ``stroke-width`` and ``fill-rule`` (attributes or ``style``,
  inherited from its groups). ``transform`` is refused, and so are a DOCTYPE or entities.
- :func:`suggested_level`: ``clamp(ceil(log2(max(w, h) / 1024)), 0, deepest)``.

Coordinates are full-resolution canvas pixels. Errors are :class:`ShapeError`, one line.
"""

from __future__ import annotations

import math
import re
import xml.etree.ElementTree as ET
from dataclasses import dataclass, field

from .svg_path import TOLERANCE, PathError, Point, parse_path

Ring = tuple[Point, ...]
Colour = tuple[int, int, int]

#: The colour of fills and outlines an annotation does not give (Lanterna's highlight yellow).
DEFAULT_COLOUR: Colour = (255, 204, 0)
#: Opacity of a fill whose ``fill-opacity`` is not given: translucent, the object shows through.
DEFAULT_FILL_OPACITY = 0.3
#: A shape's size (its bounding box's larger side, level pixels) a patch's level aims at.
TARGET_SIZE = 1024
MAX_SVG_CHARS = 1 << 20
#: Named colours understood (CSS basic colours, and orange); others are an error.
NAMED_COLOURS: dict[str, Colour] = {
    "black": (0, 0, 0), "silver": (192, 192, 192), "gray": (128, 128, 128),
    "grey": (128, 128, 128), "white": (255, 255, 255), "maroon": (128, 0, 0),
    "red": (255, 0, 0), "purple": (128, 0, 128), "fuchsia": (255, 0, 255),
    "magenta": (255, 0, 255), "green": (0, 128, 0), "lime": (0, 255, 0),
    "olive": (128, 128, 0), "yellow": (255, 255, 0), "navy": (0, 0, 128),
    "blue": (0, 0, 255), "teal": (0, 128, 128), "aqua": (0, 255, 255), "cyan": (0, 255, 255),
    "orange": (255, 165, 0)}
_STYLE_KEYS = ("fill", "stroke", "fill-opacity", "stroke-width", "fill-rule")
_CONTAINERS = {"svg", "g"}
_IGNORED = {"title", "desc", "metadata", "defs"}
_NUMBER = r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?"
_FRAGMENT = re.compile(rf"^xywh=(?:(pixel|percent):)?({_NUMBER}),({_NUMBER}),({_NUMBER}),"
                       rf"({_NUMBER})$")


class ShapeError(ValueError):
    """A target Lanterna cannot draw; ``str`` is one line."""


@dataclass(frozen=True)
class Style:
    """How a shape is drawn: fill (None: none) at ``fill_opacity``, outline (None: none) of
    ``stroke_width`` canvas pixels (None: the rasteriser's default), the fill rule."""

    fill: Colour | None = DEFAULT_COLOUR
    fill_opacity: float = DEFAULT_FILL_OPACITY
    stroke: Colour | None = DEFAULT_COLOUR
    stroke_width: float | None = None
    evenodd: bool = False


@dataclass(frozen=True)
class Shape:
    """Closed rings (filled and outlined) and open polylines (outlined only), one style."""

    rings: tuple[Ring, ...]
    lines: tuple[Ring, ...] = ()
    style: Style = field(default_factory=Style)

    @property
    def bbox(self) -> tuple[float, float, float, float]:
        """``(x0, y0, x1, y1)`` of every point."""
        return bbox([self])


def bbox(shapes: list[Shape] | tuple[Shape, ...]) -> tuple[float, float, float, float]:
    """The bounding box ``(x0, y0, x1, y1)`` of every point of ``shapes``."""
    pts = [p for s in shapes for ring in (*s.rings, *s.lines) for p in ring]
    if not pts:
        raise ShapeError("the shape has no points")
    xs, ys = [p[0] for p in pts], [p[1] for p in pts]
    return min(xs), min(ys), max(xs), max(ys)


def suggested_level(box: tuple[float, float, float, float], deepest: int) -> int:
    """``clamp(ceil(log2(max(w, h) / 1024)), 0, deepest)``: the level at which the shape's
    larger side is at most :data:`TARGET_SIZE` pixels (0 for small shapes)."""
    side = max(box[2] - box[0], box[3] - box[1])
    level = 0
    while level < deepest and side > TARGET_SIZE * (1 << level):
        level += 1
    return level


def parse_fragment(value: str, width: int, height: int) -> Shape:
    """A media-fragment ``xywh`` value (pixel or percent of the ``width`` × ``height`` canvas)."""
    m = _FRAGMENT.match(value.strip())
    if m is None:
        raise ShapeError(f"{value[:60]!r} is not an xywh fragment (xywh=X,Y,W,H, "
                         "xywh=pixel:X,Y,W,H or xywh=percent:X,Y,W,H)")
    x, y, w, h = (float(v) for v in m.groups()[1:])
    if m.group(1) == "percent":
        x, w = x * width / 100, w * width / 100
        y, h = y * height / 100, h * height / 100
    if not (w > 0 and h > 0):
        raise ShapeError(f"the rectangle {value!r} has no area (W and H must be positive; "
                         "points are not supported)")
    return Shape(rings=(((x, y), (x + w, y), (x + w, y + h), (x, y + h)),))


def parse_svg(value: str) -> list[Shape]:
    """The shapes of an ``SvgSelector`` value, in document order."""
    if len(value) > MAX_SVG_CHARS:
        raise ShapeError(f"the SVG is over {MAX_SVG_CHARS} characters")
    if re.search(r"<!(DOCTYPE|ENTITY)", value, re.IGNORECASE):
        raise ShapeError("the SVG may not have a DOCTYPE or entities")
    try:
        root = ET.fromstring(value)
    except ET.ParseError as err:
        raise ShapeError(f"the SVG is not well-formed XML ({err})") from None
    shapes: list[Shape] = []
    _walk(root, {}, shapes)
    if not shapes:
        raise ShapeError("the SVG has no shape (polygon, polyline, line, path, rect, circle "
                         "or ellipse)")
    return shapes


def _walk(node: ET.Element, inherited: dict[str, str], out: list[Shape]) -> None:
    tag = node.tag.rsplit("}", 1)[-1]
    if tag in _IGNORED:
        return
    if "transform" in node.attrib:
        raise ShapeError(f"<{tag}> has a transform, which is not supported")
    attrs = {**inherited, **_own_style(node)}
    if tag in _CONTAINERS:
        for child in node:
            _walk(child, attrs, out)
        return
    reader = _ELEMENTS.get(tag)
    if reader is None:
        raise ShapeError(f"unsupported SVG element <{tag}>")
    try:
        rings, lines = reader(node)
    except PathError as err:
        raise ShapeError(f"<path>: {err}") from None
    if not rings and not lines:
        raise ShapeError(f"<{tag}> has no area or points")
    out.append(Shape(tuple(rings), tuple(lines), _style(attrs, tag)))


def _own_style(node: ET.Element) -> dict[str, str]:
    found = {k: node.attrib[k].strip() for k in _STYLE_KEYS if k in node.attrib}
    for decl in node.attrib.get("style", "").split(";"):
        key, _, val = decl.partition(":")
        if key.strip() in _STYLE_KEYS and val.strip():
            found[key.strip()] = val.strip()
    return found


def _style(attrs: dict[str, str], tag: str) -> Style:
    fill = _colour(attrs.get("fill"), tag)
    stroke = _colour(attrs.get("stroke"), tag)
    return Style(fill=fill, stroke=stroke,
                 fill_opacity=min(1.0, max(0.0, _number(attrs, "fill-opacity", tag,
                                                        DEFAULT_FILL_OPACITY))),
                 stroke_width=(_number(attrs, "stroke-width", tag, 0.0)
                               if "stroke-width" in attrs else None),
                 evenodd=attrs.get("fill-rule") == "evenodd")


def _colour(value: str | None, tag: str) -> Colour | None:
    if value is None or value == "currentColor":
        return DEFAULT_COLOUR
    v = value.strip().lower()
    if v in ("none", "transparent"):
        return None
    if v in NAMED_COLOURS:
        return NAMED_COLOURS[v]
    if re.fullmatch(r"#[0-9a-f]{3}", v):
        return int(v[1] * 2, 16), int(v[2] * 2, 16), int(v[3] * 2, 16)
    if re.fullmatch(r"#[0-9a-f]{6}", v):
        return int(v[1:3], 16), int(v[3:5], 16), int(v[5:7], 16)
    m = re.fullmatch(r"rgb\(\s*(\d+)\s*,\s*(\d+)\s*,\s*(\d+)\s*\)", v)
    if m:
        r, g, b = (min(255, int(c)) for c in m.groups())
        return r, g, b
    raise ShapeError(f"<{tag}>: unsupported colour {value!r} (use #rrggbb, #rgb, rgb(r, g, b) "
                     "or a basic colour name)")


def _number(attrs: dict[str, str], key: str, tag: str, default: float) -> float:
    raw = attrs.get(key)
    if raw is None:
        return default
    m = re.fullmatch(rf"({_NUMBER})(px)?", raw.strip())
    if m is None or not math.isfinite(float(m.group(1))):
        raise ShapeError(f"<{tag}>: {key} {raw!r} is not a number")
    return float(m.group(1))


def _attr(node: ET.Element, key: str, tag: str) -> float:
    if key not in node.attrib:
        raise ShapeError(f"<{tag}> needs {key}")
    return _number(dict(node.attrib), key, tag, 0.0)


def _points(node: ET.Element, tag: str) -> Ring:
    raw = node.attrib.get("points", "")
    nums = re.findall(_NUMBER, raw)
    if re.sub(_NUMBER, "", raw).strip(" \t\r\n,") or len(nums) % 2:
        raise ShapeError(f"<{tag}> points must be pairs of numbers (x,y x,y …)")
    vals = [float(n) for n in nums]
    return tuple((vals[k], vals[k + 1]) for k in range(0, len(vals), 2))


def _polygon(node: ET.Element) -> tuple[list[Ring], list[Ring]]:
    pts = _points(node, "polygon")
    return ([pts] if len(pts) >= 3 else []), ([pts] if len(pts) == 2 else [])


def _polyline(node: ET.Element) -> tuple[list[Ring], list[Ring]]:
    pts = _points(node, "polyline")
    return [], ([pts] if len(pts) >= 2 else [])


def _line(node: ET.Element) -> tuple[list[Ring], list[Ring]]:
    a = (_attr(node, "x1", "line"), _attr(node, "y1", "line"))
    return [], [(a, (_attr(node, "x2", "line"), _attr(node, "y2", "line")))]


def _path(node: ET.Element) -> tuple[list[Ring], list[Ring]]:
    subpaths = parse_path(node.attrib.get("d", ""))
    return ([tuple(p) for p, closed in subpaths if closed and len(p) >= 3],
            [tuple(p) for p, closed in subpaths if not closed or len(p) < 3])


def _rect(node: ET.Element) -> tuple[list[Ring], list[Ring]]:
    x, y = (_number(dict(node.attrib), k, "rect", 0.0) for k in ("x", "y"))
    w, h = _attr(node, "width", "rect"), _attr(node, "height", "rect")
    if not (w > 0 and h > 0):
        raise ShapeError(f"<rect> is empty ({w:g}x{h:g})")
    return [((x, y), (x + w, y), (x + w, y + h), (x, y + h))], []


def _ellipse_ring(cx: float, cy: float, rx: float, ry: float, tag: str) -> Ring:
    if not (rx > 0 and ry > 0):
        raise ShapeError(f"<{tag}> has no area (radius {rx:g}x{ry:g})")
    # chords of a circle of radius r stay within TOLERANCE when cos(pi/n) >= 1 - TOLERANCE/r
    r = max(rx, ry)
    n = max(16, min(4096, math.ceil(math.pi / math.acos(max(-1.0, 1 - TOLERANCE / r)))))
    return tuple((cx + rx * math.cos(2 * math.pi * k / n), cy + ry * math.sin(2 * math.pi * k / n))
                 for k in range(n))


def _circle(node: ET.Element) -> tuple[list[Ring], list[Ring]]:
    r = _attr(node, "r", "circle")
    cx, cy = (_number(dict(node.attrib), k, "circle", 0.0) for k in ("cx", "cy"))
    return [_ellipse_ring(cx, cy, r, r, "circle")], []


def _ellipse(node: ET.Element) -> tuple[list[Ring], list[Ring]]:
    cx, cy = (_number(dict(node.attrib), k, "ellipse", 0.0) for k in ("cx", "cy"))
    rx, ry = _attr(node, "rx", "ellipse"), _attr(node, "ry", "ellipse")
    return [_ellipse_ring(cx, cy, rx, ry, "ellipse")], []


#: SVG element → reader of its (closed rings, open polylines).
_ELEMENTS = {"polygon": _polygon, "polyline": _polyline, "line": _line, "path": _path,
             "rect": _rect, "circle": _circle, "ellipse": _ellipse}
