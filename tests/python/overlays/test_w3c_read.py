"""Reading W3C AnnotationPages into patches: shapes, levels, texts, and one-line errors."""

from __future__ import annotations

import copy
import json
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from lanterna.errors import LanternaInputError
from lanterna.tiler.overlays.geometry import Patch, destination
from lanterna.tiler.overlays.shape_raster import DEFAULT_STROKE, SAMPLES
from lanterna.tiler.overlays.w3c_read import read_page

from . import raster_reference as ref
from .w3c_pages import NOTCH, SHERD, annotorious_page, mirador_annotation

W, H, DEEPEST = 320, 200, 2
YELLOW = (255, 204, 0)


def _write(tmp_path: Path, doc: Any, name: str = "page.json") -> Path:
    path = tmp_path / name
    path.write_text(doc if isinstance(doc, str) else json.dumps(doc))
    return path


def test_an_annotorious_page_becomes_one_patch_per_annotation(tmp_path: Path) -> None:
    sherd, notch, rect = read_page(_write(tmp_path, annotorious_page()), width=W, height=H,
                                   deepest=DEEPEST)
    assert (sherd.short, sherd.motivation, sherd.author, sherd.created) == (
        "Flaking paint along the rim; flaking", "commenting", "Ada Conservator",
        "2026-11-30T09:12:40.001Z")
    assert (notch.short, notch.motivation, notch.author, notch.created) == (
        "gilding", "tagging", "", None)
    assert (rect.short, rect.author) == ("Restored in 1962", "https://example.org/users/7")
    assert sherd.long == notch.long == ""
    # small shapes: level 0; the polygon's box grown by half the 2 px outline, outward
    assert (sherd.level, sherd.rect) == (0, (39, 21, 144, 121))
    assert notch.rect == (199, 34, 107, 119)
    # a rectangle is its own patch rectangle
    assert (rect.level, rect.rect) == (0, (20, 160, 90, 30))
    assert sherd.where == "items[0]"


@pytest.mark.parametrize("index", [0, 1])
def test_imported_polygons_match_an_independent_rasterisation(tmp_path: Path,
                                                              index: int) -> None:
    patch = read_page(_write(tmp_path, annotorious_page()), width=W, height=H,
                      deepest=DEEPEST)[index]
    points = [SHERD, NOTCH][index]
    dest = destination(Patch(patch.level, *patch.rect, order=0, info="", file=""))
    half = DEFAULT_STROKE * (1 << patch.level) / 2
    expected = ref.composite([
        (ref.crossing_fill(points, patch.level, dest, SAMPLES) * 0.3, YELLOW),
        (ref.distance_outline(points, True, half, patch.level, dest, SAMPLES), YELLOW)])
    assert patch.rgba.shape == expected.shape
    diff = np.abs(patch.rgba.astype(float) - expected)
    # alpha within one sample of 16 (round joins are 16-gons) and the rounding; colour exact
    assert diff[..., 3].max() <= 255 / SAMPLES**2 + 0.5
    assert diff[..., 3].mean() < 0.5
    assert diff[..., :3][patch.rgba[..., 3] > 0].max() <= 0.5
    pillow = ref.pillow_fill(points, patch.level, dest, SAMPLES)
    fill = ref.crossing_fill(points, patch.level, dest, SAMPLES)
    assert np.abs(fill - pillow).mean() < 0.02


def test_a_mirador_annotation_uses_its_svg_and_colours(tmp_path: Path) -> None:
    page = {"type": "AnnotationPage", "items": [mirador_annotation("https://x.org/canvas/1")]}
    (patch,) = read_page(_write(tmp_path, page), width=W, height=H, deepest=DEEPEST)
    assert patch.long == "<p>Under <b>UV</b>: retouching</p>" and patch.short == ""
    # the SVG's loop (x 100–180, y 70–130), grown by its 2 px outline's half
    assert patch.rect == (99, 69, 82, 62)
    alpha, colour = patch.rgba[..., 3], patch.rgba[..., :3]
    assert alpha[31, 41] == 0  # fill-opacity 0: the inside stays clear
    assert alpha.max() == 255 and tuple(colour[alpha == 255][0]) == (255, 0, 0)


def test_large_shapes_get_coarser_levels(tmp_path: Path) -> None:
    page = {"type": "AnnotationPage", "items": [
        {"type": "Annotation", "target": "https://x.org/canvas/1#xywh=0,0,3000,1200"},
        {"type": "Annotation", "target": {"selector": {
            "type": "SvgSelector",
            "value": "<svg><circle cx='2000' cy='1500' r='1400'/></svg>"}}}]}
    big, circle = read_page(_write(tmp_path, page), width=4000, height=3000, deepest=4)
    assert (big.level, big.rect, big.rgba.shape) == (2, (0, 0, 3000, 1200), (300, 750, 4))
    assert circle.level == 2 and max(circle.rgba.shape[:2]) <= 1024
    # the rectangle's outline lies inside the patch: opaque on its edge, translucent inside
    assert big.rgba[0, 375, 3] == 255 and big.rgba[150, 375, 3] == round(0.3 * 255)


def _broken(change: str) -> Any:
    page = annotorious_page()
    items = page["items"]
    if change == "wrong type":
        items[1]["body"] = 42
    elif change == "unknown selector":
        items[1]["target"]["selector"] = {"type": "PointSelector", "value": "x=1,y=2"}
    elif change == "outside":
        items[2]["target"]["selector"]["value"] = "xywh=pixel:400,10,30,30"
    elif change == "arcs":
        items[1]["target"]["selector"]["value"] = "<svg><path d='M 10 10 A 5 5 0 0 1 30 30'/></svg>"
    elif change == "not svg":
        items[0]["target"]["selector"]["value"] = "<svg><polygon points='1,2 3,4"
    elif change == "long author":
        items[0]["creator"] = {"name": "x" * 201}
    elif change == "short too long":
        items[2]["body"][0]["value"] = "y" * 1001
    elif change == "long too long":  # each body within the schema, the two together not
        items[2]["body"] += [{"type": "TextualBody", "format": "text/html",
                              "value": "<p>" + "z" * 60000 + "</p>"}] * 2
    elif change == "too deep":
        items[1]["body"].append({"id": "https://x.org/p.png", "type": "Image",
                                 "service": [{"type": "LanternaPatch", "level": 7}]})
    elif change == "no items":
        del page["items"]
    return page


@pytest.mark.parametrize(("change", "where", "message"), [
    ("wrong type", "items[1].body", "expected a body or a list of bodies"),
    ("unknown selector", "items[1].target", "a FragmentSelector or an SvgSelector"),
    ("outside", "items[2].target.selector.value", "outside the 320x200 canvas"),
    ("arcs", "items[1].target.selector.value", "arcs (A) are not supported"),
    ("not svg", "items[0].target.selector.value", "not well-formed XML"),
    ("long author", "items[0].creator", "a creator"),
    ("short too long", "items[2].body", "at most 1000"),
    ("long too long", "items[2].body", "long text (the HTML TextualBodies) is 120015"),
    ("too deep", "items[1].body", "level 7 is beyond the pyramid (levels 0–2)"),
    ("no items", "", 'needs "items"'),
])
def test_a_bad_page_is_one_line_naming_the_file_and_json_path(
        tmp_path: Path, change: str, where: str, message: str) -> None:
    path = _write(tmp_path, _broken(change))
    with pytest.raises(LanternaInputError) as err:
        read_page(path, width=W, height=H, deepest=DEEPEST)
    text = str(err.value)
    assert "\n" not in text
    assert text.startswith(f"{path}: {where}")
    assert message in text


@pytest.mark.parametrize(("text", "message"), [
    ("{not json", "not valid JSON"),
    ("[1, 2]", "expected an AnnotationPage"),
    ('{"type": "AnnotationCollection", "items": []}', 'type: expected "AnnotationPage"'),
])
def test_not_a_page(tmp_path: Path, text: str, message: str) -> None:
    path = _write(tmp_path, text)
    with pytest.raises(LanternaInputError, match=message) as err:
        read_page(path, width=W, height=H, deepest=DEEPEST)
    assert str(err.value).startswith(str(path))


def test_the_first_of_several_targets_and_a_string_target(tmp_path: Path) -> None:
    page = copy.deepcopy(annotorious_page())
    first = page["items"][2]["target"]
    page["items"][2]["target"] = [first, "https://x.org/canvas/1#xywh=0,0,5,5"]
    page["items"].append({"type": "Annotation",
                          "target": "https://x.org/canvas/1#xywh=pixel:300,180,50,50"})
    patches = read_page(_write(tmp_path, page), width=W, height=H, deepest=DEEPEST)
    assert patches[2].rect == (20, 160, 90, 30)
    assert patches[3].rect == (300, 180, 20, 20)  # clipped to the canvas
