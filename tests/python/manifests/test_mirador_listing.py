"""The overlay levels and patches are listed by stock Mirador 4, each with its texts and region.

Mirador is not imported: its rules are restated here from its source (Mirador 4.0.0,
``src/lib/AnnotationItem.js``, ``src/state/selectors/annotations.js``,
``src/state/sagas/annotations.js``, ``src/config/settings.js``):

1. The canvas's ``annotations`` entries of type ``AnnotationPage`` are its pages: one with
   ``items`` is used as embedded, one without is fetched by its ``id``.
2. An annotation's motivations are ``flatten(compact([motivation]))``: a string is a list of one.
3. The annotation panel lists an annotation when **some** of its motivations is in
   ``annotations.filteredMotivations``, by default
   ``['oa:commenting', 'oa:tagging', 'sc:painting', 'commenting', 'tagging']``.
4. The text shown is the ``value``s of the bodies whose ``purpose`` is not ``tagging``, joined by
   a space (a body without ``value`` adds an empty string), unless the only motivation is
   ``tagging``; ``tagging`` bodies are shown as tags.
5. The region drawn and zoomed to is the ``xywh=`` of the first target's ``FragmentSelector``.
"""

from __future__ import annotations

import json
import re
from pathlib import Path
from typing import Any

import pytest

from lanterna.manifests.annotation_page import patch_annotation
from tests.python.fixtures.dataset_kinds import build_kinds

#: Rule 3's default (Mirador 4.0.0 src/config/settings.js, annotations.filteredMotivations).
DEFAULT_MOTIVATIONS = ["oa:commenting", "oa:tagging", "sc:painting", "commenting", "tagging"]


def motivations(anno: dict[str, Any]) -> list[str]:
    """Rule 2."""
    value = anno.get("motivation")
    return [] if value is None else list(value) if isinstance(value, list) else [value]


def listed(anno: dict[str, Any]) -> bool:
    """Rule 3."""
    return any(m in DEFAULT_MOTIVATIONS for m in motivations(anno))


def shown_text(anno: dict[str, Any]) -> str | None:
    """Rule 4 (``chars``)."""
    if motivations(anno) == ["tagging"]:
        return None
    bodies = anno["body"] if isinstance(anno["body"], list) else [anno["body"]]
    return " ".join(str(b.get("value", "")) for b in bodies if b.get("purpose") != "tagging")


def region(anno: dict[str, Any]) -> list[int]:
    """Rule 5."""
    target = anno["target"][0] if isinstance(anno["target"], list) else anno["target"]
    selectors = target["selector"] if isinstance(target["selector"], list) else [
        target["selector"]]
    fragment = next(s for s in selectors if s.get("type") == "FragmentSelector")
    match = re.search(r"xywh=(.*)$", fragment["value"])
    assert match is not None
    return [int(v) for v in match.group(1).split(",")]


@pytest.fixture(scope="module")
def overlay(tmp_path_factory: pytest.TempPathFactory) -> Path:
    return build_kinds(tmp_path_factory.mktemp("mirador") / "root")["overlay"]


def pages(dataset: Path) -> list[dict[str, Any]]:
    """Rule 1, with the fetch of a referenced page read from the dataset's files."""
    manifest = json.loads((dataset / "manifest.json").read_text())
    ds_url = manifest["id"].removesuffix("/manifest.json")
    out = []
    for page in manifest["items"][0]["annotations"]:
        assert page["type"] == "AnnotationPage"
        if "items" not in page:
            page = json.loads((dataset / page["id"].removeprefix(f"{ds_url}/")).read_text())
        out.append(page)
    return out


def test_every_overlay_level_is_listed_with_its_texts_and_its_drawings_region(
        overlay: Path) -> None:
    desc = json.loads((overlay / "lanterna.json").read_text())
    levels = {e["level"]: e for e in desc["layers"][0]["overlay"]["levels"]}
    level_page = pages(overlay)[0]
    assert len(level_page["items"]) == len(levels) == 2
    for anno in level_page["items"]:
        entry = levels[int(anno["id"].rsplit("/", 1)[1])]
        assert listed(anno)
        text = shown_text(anno)
        assert text is not None and entry["short"] in text and entry["long"] in text
        assert region(anno) == entry["box"] != [0, 0, desc["width"], desc["height"]]


def test_the_level_boxes_are_the_patches_rectangles(overlay: Path) -> None:
    # dataset_kinds draws one opaque patch per level: 0_10_8_30_20 and 1_40_20_40_30
    level_page = pages(overlay)[0]
    assert [region(a) for a in level_page["items"]] == [[10, 8, 30, 20], [40, 20, 40, 30]]


def test_every_patch_is_listed_with_its_texts_and_its_own_region(overlay: Path) -> None:
    desc = json.loads((overlay / "lanterna.json").read_text())
    records = {r["id"]: r for r in desc["layers"][0]["overlay"]["patches"]}
    patch_page = pages(overlay)[1]
    assert len(patch_page["items"]) == len(records) == 2
    for anno in patch_page["items"]:
        record = records[anno["id"].rsplit("/", 1)[1].removesuffix(".json")]
        assert listed(anno)
        assert region(anno) == [record["x"], record["y"], record["w"], record["h"]]
        assert (shown_text(anno) or "").strip() == " ".join(
            t for t in (record["short"], record["long"]) if t)


def test_the_rules_refuse_what_mirador_would_not_list() -> None:
    # the encoding before this one: supplementing, over the whole canvas
    earlier = {"motivation": "supplementing", "body": [{"type": "TextualBody", "value": "x"}],
               "target": {"selector": {"type": "FragmentSelector", "value": "xywh=0,0,8,8"}}}
    assert not listed(earlier)
    assert listed({**earlier, "motivation": ["highlighting", "tagging"]})
    assert shown_text({**earlier, "motivation": "tagging"}) is None


@pytest.mark.parametrize("motivation", ["commenting", "tagging"])
def test_a_patch_with_texts_shows_them_as_mirador_does(motivation: str) -> None:
    desc = {"baseUrl": "https://example.org/pub", "name": "obj"}
    record = {"id": "0_5_6_7_8_0_a", "layer": "vis", "level": 0, "x": 5, "y": 6, "w": 7, "h": 8,
              "order": 0, "width": 7, "height": 8, "short": "Seal", "long": "<p>A seal</p>",
              "motivation": motivation}
    anno = patch_annotation(desc, "vis", record)
    assert listed(anno) and region(anno) == [5, 6, 7, 8]
    bodies = anno["body"]
    tags = [b["value"] for b in bodies if b.get("purpose") == "tagging"]  # rule 4's tags
    if motivation == "tagging":
        assert tags == ["Seal"] and (shown_text(anno) or "").strip() == "<p>A seal</p>"
    else:
        assert tags == [] and (shown_text(anno) or "").strip() == "Seal <p>A seal</p>"
