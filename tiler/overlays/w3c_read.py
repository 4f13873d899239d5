"""Read a W3C / IIIF AnnotationPage into patches: a rectangle, a level, RGBA pixels and texts.

docs/annotations.md, "Individual annotations (W3C)". The page is checked against
``tiler/schemas/annotation-page.schema.json`` first; then each Annotation becomes one
:class:`ImportedPatch`, or the whole page is refused with a one-line error naming the file and
the JSON path (``page.json: items[3].target.selector.value: path arcs (A) are not supported``),
so nothing is stored from a page with one bad annotation. No I/O beyond reading the page (and,
through ``own_image``, a patch image the page names in the dataset itself).

- **Target**: a ``canvas#xywh=…`` string, or a SpecificResource whose selector (or list of
  selectors: the first SvgSelector, else the first FragmentSelector) is an ``xywh``
  FragmentSelector or an SvgSelector (:mod:`.shapes`). The target's ``source`` is not checked.
- **Rectangle and level**: an SVG shape's patch holds its bounding box grown by half its outline
  (:func:`~.shape_raster.patch_rectangle`) at :func:`~.shapes.suggested_level`; an ``xywh``
  rectangle is the patch rectangle itself (rounded outward to whole pixels, clipped to the
  canvas), its outline drawn just inside it. A Lanterna patch (an ``Image`` body with a
  ``LanternaPatch`` service, as ``annotate export`` writes) keeps its level, and its pixels when
  ``own_image`` finds its PNG at the destination size.
- **Texts**: ``short`` = the plain TextualBodies' values (purpose commenting, replying or none,
  then tagging; not ``text/html``), joined with ``"; "``, at most 1000 characters; ``long`` =
  the ``text/html`` or ``describing`` ones, joined by newlines, at most 100000; motivation
  ``tagging`` when every short text is a tag, else ``commenting``. ``creator`` (a name, or
  ``name``/``nickname``/``id`` of an object) is the author; ``created`` is kept (else the
  store stamps the time of the import).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import numpy.typing as npt

from lanterna.errors import LanternaInputError
from lanterna.tiler.documents import json_path, read_document

from .geometry import Patch, destination
from .shape_raster import patch_rectangle, rasterise, stroke_width
from .shapes import Shape, ShapeError, bbox, parse_fragment, parse_svg, suggested_level

#: Finds the pixels of a patch image the page names by URL (a Lanterna export), or None.
OwnImage = Callable[[str], "npt.NDArray[np.uint8] | None"]
#: The store's limits of a patch's texts (tiler/schemas/patch.schema.json).
MAX_SHORT, MAX_LONG = 1000, 100000


@dataclass(frozen=True)
class ImportedPatch:
    """One annotation of the page, ready for the store."""

    where: str
    level: int
    rect: tuple[int, int, int, int]
    rgba: npt.NDArray[np.uint8]
    short: str
    long: str
    motivation: str
    author: str
    created: str | None


def read_page(path: Path, *, width: int, height: int, deepest: int,
              own_image: OwnImage | None = None) -> list[ImportedPatch]:
    """Read and check the AnnotationPage file ``path`` for a ``width`` × ``height`` canvas whose
    pyramid's deepest level is ``deepest``; return one patch per annotation."""
    page = read_document(Path(path), "annotation-page")
    out = []
    for i, anno in enumerate(page["items"]):
        try:
            out.append(_patch(anno, ("items", i), width, height, deepest, own_image))
        except _AtPath as err:
            raise LanternaInputError(path, f"{json_path(err.where)}: {err.problem}") from None
    return out


class _AtPath(Exception):
    def __init__(self, where: tuple[str | int, ...], problem: str) -> None:
        super().__init__(problem)
        self.where, self.problem = where, problem


def _patch(anno: dict[str, Any], where: tuple[str | int, ...], width: int, height: int,
           deepest: int, own_image: OwnImage | None) -> ImportedPatch:
    bodies = anno.get("body", [])
    bodies = bodies if isinstance(bodies, list) else [bodies]
    short, long, motivation = _texts(bodies, (*where, "body"))
    kind, value, at = _selector(anno["target"], (*where, "target"))
    lanterna = _lanterna_service(bodies)
    try:
        if kind == "FragmentSelector":
            shape = parse_fragment(value, width, height)
            level = _level(lanterna, [shape], deepest, (*where, "body"))
            rect = _outward(shape.bbox, width, height)
            shapes = [_inset(shape, stroke_width(shape, level) * (1 << level) / 2)]
        else:
            shapes = parse_svg(value)
            level = _level(lanterna, shapes, deepest, (*where, "body"))
            rect = patch_rectangle(shapes, level, width, height)
    except ShapeError as err:
        raise _AtPath(at, str(err)) from None
    rgba = _own_pixels(lanterna, bodies, level, rect, own_image)
    if rgba is None:
        rgba = rasterise(shapes, level, rect)
    return ImportedPatch(json_path(where), level, rect, rgba, short, long, motivation,
                         _author(anno.get("creator")), anno.get("created"))


def _selector(target: Any, where: tuple[str | int, ...]) -> tuple[str, str, tuple[str | int, ...]]:
    """``(selector type, value, JSON path of the value)`` of an annotation's target."""
    if isinstance(target, list):
        target, where = target[0], (*where, 0)
    if isinstance(target, str):
        return "FragmentSelector", "xywh=" + target.split("#xywh=", 1)[1], where
    selectors = target["selector"]
    items = [(s, (*where, "selector", k)) for k, s in enumerate(selectors)] \
        if isinstance(selectors, list) else [(selectors, (*where, "selector"))]
    chosen = next((s for s in items if s[0]["type"] == "SvgSelector"), items[0])
    return chosen[0]["type"], chosen[0]["value"], (*chosen[1], "value")


def _texts(bodies: list[dict[str, Any]], where: tuple[str | int, ...]) -> tuple[str, str, str]:
    plain, tags, html = [], [], []
    for body in bodies:
        if body.get("type") != "TextualBody" or not body["value"].strip():
            continue
        purposes = body.get("purpose")
        purpose = purposes[0] if isinstance(purposes, list) and purposes else purposes
        if body.get("format") == "text/html" or purpose == "describing":
            html.append(body["value"])
        elif purpose == "tagging":
            tags.append(body["value"].strip())
        else:  # commenting, replying, no purpose (or any other)
            plain.append(body["value"].strip())
    short, long = "; ".join(plain + tags), "\n".join(html)
    for what, text, most in (("short text (the plain", short, MAX_SHORT),
                             ("long text (the HTML", long, MAX_LONG)):
        if len(text) > most:
            raise _AtPath(where, f"the {what} TextualBodies) is {len(text)} characters; at "
                          f"most {most}")
    return short, long, "tagging" if tags and not plain else "commenting"


def _author(creator: Any) -> str:
    if isinstance(creator, list):
        creator = creator[0]
    if isinstance(creator, dict):
        creator = creator.get("name") or creator.get("nickname") or creator.get("id") or ""
    return str(creator or "")


def _lanterna_service(bodies: list[dict[str, Any]]) -> dict[str, Any] | None:
    for body in bodies:
        for service in body.get("service", []) if isinstance(body.get("service"), list) else []:
            if isinstance(service, dict) and service.get("type") == "LanternaPatch":
                return service
    return None


def _level(service: dict[str, Any] | None, shapes: list[Shape], deepest: int,
           where: tuple[str | int, ...]) -> int:
    """A Lanterna patch's own level, else the level the shapes' size suggests."""
    if service is not None and isinstance(service.get("level"), int):
        level = int(service["level"])
        if not 0 <= level <= deepest:
            raise _AtPath(where, f"level {level} is beyond the pyramid (levels 0–{deepest})")
        return level
    return suggested_level(bbox(shapes), deepest)


def _outward(box: tuple[float, float, float, float], width: int,
             height: int) -> tuple[int, int, int, int]:
    x0, y0 = max(0, math.floor(box[0])), max(0, math.floor(box[1]))
    x1, y1 = min(width, math.ceil(box[2])), min(height, math.ceil(box[3]))
    if x1 <= x0 or y1 <= y0:
        raise ShapeError(f"the rectangle ({box[0]:g},{box[1]:g} to {box[2]:g},{box[3]:g}) is "
                         f"outside the {width}x{height} canvas")
    return x0, y0, x1 - x0, y1 - y0


def _inset(shape: Shape, half: float) -> Shape:
    x0, y0, x1, y1 = shape.bbox
    d = min(half, (x1 - x0) / 4, (y1 - y0) / 4)
    x0, y0, x1, y1 = x0 + d, y0 + d, x1 - d, y1 - d
    return Shape(rings=(((x0, y0), (x1, y0), (x1, y1), (x0, y1)),), style=shape.style)


def _own_pixels(service: dict[str, Any] | None, bodies: list[dict[str, Any]], level: int,
                rect: tuple[int, int, int, int],
                own_image: OwnImage | None) -> npt.NDArray[np.uint8] | None:
    if service is None or own_image is None:
        return None
    image = next((b for b in bodies if b.get("type") == "Image" and isinstance(b.get("id"), str)),
                 None)
    rgba = own_image(image["id"]) if image is not None else None
    x0, y0, x1, y1 = destination(Patch(level, *rect, order=0, info="", file=""))
    if rgba is None or rgba.shape[:2] != (y1 - y0, x1 - x0):
        return None
    return rgba
