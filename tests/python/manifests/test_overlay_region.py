"""An overlay level annotation targets its drawing's region, or the whole canvas when unknown."""

from __future__ import annotations

from typing import Any

import pytest

from lanterna.manifests.overlays import drawn_region, overlay_pages

DESC: dict[str, Any] = {"baseUrl": "https://example.org/pub", "name": "obj", "width": 600,
                        "height": 400}


@pytest.mark.parametrize(("box", "region"), [
    ([90, 45, 510, 355], (90, 45, 510, 355)),
    (None, (0, 0, 600, 400)),  # a record written before the box was kept
    ([0, 0, 0, 10], (0, 0, 600, 400)),  # empty
    ([500, 300, 101, 10], (0, 0, 600, 400)),  # past the canvas
    ([1, 2, 3], (0, 0, 600, 400)),
    ([1.5, 2, 3, 4], (0, 0, 600, 400)),
    ("0,0,5,5", (0, 0, 600, 400))])
def test_the_region_is_the_box_when_it_is_a_rectangle_on_the_canvas(
        box: Any, region: tuple[int, int, int, int]) -> None:
    entry = {"level": 0, "image": "vis_ov0", "width": 600, "height": 400}
    if box is not None:
        entry["box"] = box
    assert drawn_region(entry, DESC) == region


def test_a_level_without_texts_has_no_textual_bodies() -> None:
    layer = {"id": "vis", "label": "VIS", "overlay": {"levels": [
        {"level": 1, "image": "vis_ov1", "width": 300, "height": 200, "box": [2, 4, 6, 8]}]}}
    (page,) = overlay_pages({**DESC, "layers": [layer]})
    (anno,) = page["items"]
    assert [b["type"] for b in anno["body"]] == ["Image"]
    assert anno["label"] == {"en": ["Level 1"]} and anno["motivation"] == "commenting"
    assert anno["target"]["selector"]["value"] == "xywh=2,4,6,8"
