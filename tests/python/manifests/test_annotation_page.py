"""The layers' published patches as W3C Web Annotations in an AnnotationPage (contract §4)."""

from __future__ import annotations

import copy
from typing import Any

import pytest

from lanterna.errors import LanternaInputError
from lanterna.manifests.annotation_page import (
    annotation_documents,
    annotation_page,
    patch_annotation,
)
from lanterna.manifests.build import build_manifest
from lanterna.manifests.validate import validate_annotation_page, validate_manifest

from .w3c_rules import w3c_errors

DS = "https://example.org/data/tablet"
STATE = {"layer": "ptm", "mode": "specular", "params": {"gloss": 40}, "light": [0.3, -0.5]}


def record(stem: str, level: int, x: int, y: int, w: int, h: int, order: int,
           **extra: Any) -> dict[str, Any]:
    """A published patch record (contract §1, §2): the store's record + file, width, height."""
    f = 1 << level
    rec: dict[str, Any] = {
        "type": "LanternaPatch", "version": 1, "id": stem, "layer": "vis", "level": level,
        "x": x, "y": y, "w": w, "h": h, "order": order, "info": stem.split("_", 6)[-1],
        "author": "", "created": "2026-12-01T10:00:00Z", "modified": "2026-12-01T10:00:00Z",
        "short": "", "long": "", "motivation": "commenting", "state": None,
        "file": f"{stem}.png", "width": -(-(x + w) // f) - x // f,
        "height": -(-(y + h) // f) - y // f}
    rec.update(extra)
    return rec


def description() -> dict[str, Any]:
    """A dataset description: layer vis with two patches, layer ptm with a pre-store overlay."""
    level = {"level": 1, "image": "vis_ov1", "width": 150, "height": 100, "short": "Overview",
             "long": ""}
    return {
        "lanterna": 1, "name": "tablet", "label": "Tablet", "width": 300, "height": 200,
        "baseUrl": "https://example.org/data/", "source": None,
        "images": {"vis_c": {"format": "jpg", "width": 300, "height": 200, "bands": 3},
                   "ptm_c": {"format": "jpg", "width": 300, "height": 200, "bands": 3},
                   "vis_ov1": {"format": "png", "width": 150, "height": 100, "bands": 4}},
        "layers": [
            {"id": "vis", "label": "Visible", "body": "vis_c",
             "service": {"id": f"{DS}/layers/vis.json", "type": "LanternaRelight",
                         "profile": "urn:lanterna:relight:1", "layerType": "image"},
             "overlay": {"source": "store", "build": 3, "fingerprint": "ab" * 32,
                         "levels": [level], "patches": [
                             record("0_10_20_30_40_0_cracks", 0, 10, 20, 30, 40, 0,
                                    author="Ada Conservator", short="Cracks",
                                    long="<p>Cracks in the <b>glaze</b></p>", state=STATE),
                             record("1_101_0_99_51_1_gilding", 1, 101, 0, 99, 51, 1,
                                    short="gilding", motivation="tagging"),
                         ]}},
            {"id": "ptm", "label": "PTM", "body": "ptm_c",
             "service": {"id": f"{DS}/layers/ptm.json", "type": "LanternaRelight",
                         "profile": "urn:lanterna:relight:1", "layerType": "image"},
             "overlay": {"source": "patches", "levels": [], "patches": [
                 {"level": 0, "x": 0, "y": 0, "w": 5, "h": 5, "order": 0, "info": "old",
                  "file": "0_0_0_5_5_0_old.png"}]}},
        ],
    }


def test_the_page_and_each_annotation_validate_against_presentation_3_and_the_w3c_model() -> None:
    docs = annotation_documents(description())
    assert sorted(docs) == ["annotations/vis.json",
                            "annotations/vis/0_10_20_30_40_0_cracks.json",
                            "annotations/vis/1_101_0_99_51_1_gilding.json"]
    page = docs["annotations/vis.json"]
    assert validate_annotation_page(page) == []
    assert w3c_errors(page) == []
    for name, doc in docs.items():
        assert w3c_errors(doc) == [], name
        # an Annotation alone is checked as the one item of a page (the schema has no root class
        # for it), with its @context moved to the page
        alone = {k: v for k, v in doc.items() if k != "@context"}
        wrapper = {"id": f"{DS}/x.json", "type": "AnnotationPage", "items": [alone]}
        assert validate_annotation_page(wrapper if doc["type"] == "Annotation" else doc) == []


def test_an_annotation_carries_rectangle_texts_author_state_and_image() -> None:
    page = annotation_page(description(), description()["layers"][0])
    assert page is not None
    assert page["id"] == f"{DS}/annotations/vis.json"
    assert page["label"] == {"en": ["Notes: Visible"]}
    assert page["@context"][-1] == "http://iiif.io/api/presentation/3/context.json"
    first, second = page["items"]
    assert first["id"] == f"{DS}/annotations/vis/0_10_20_30_40_0_cracks.json"
    assert first["motivation"] == ["highlighting", "commenting"]
    assert second["motivation"] == ["highlighting", "tagging"]
    assert first["target"] == {
        "type": "SpecificResource", "source": {"id": f"{DS}/canvas/1", "type": "Canvas"},
        "selector": {"type": "FragmentSelector", "conformsTo": "http://www.w3.org/TR/media-frags/",
                     "value": "xywh=10,20,30,40"}}
    assert second["target"]["selector"]["value"] == "xywh=101,0,99,51"
    image, short, long = first["body"]
    assert (image["id"], image["width"], image["height"]) == (
        f"{DS}/annotations/vis/0_10_20_30_40_0_cracks.png", 30, 40)
    assert image["service"] == [{
        "id": f"{first['id']}#lanterna", "type": "LanternaPatch", "profile": "urn:lanterna:patch:1",
        "layer": "vis", "level": 0, "order": 0, "x": 10, "y": 20, "w": 30, "h": 40,
        "state": STATE}]
    assert short == {"id": f"{first['id']}#short", "type": "TextualBody", "value": "Cracks",
                     "format": "text/plain", "purpose": "commenting"}
    assert (long["value"], long["format"], long["purpose"]) == (
        "<p>Cracks in the <b>glaze</b></p>", "text/html", "describing")
    assert first["creator"] == {"type": "Person", "name": "Ada Conservator"}
    assert first["created"] == "2026-12-01T10:00:00Z"
    # level 1: x 101..200 → 50..100, y 0..51 → 0..26; no long text, no author, tagging
    assert (second["body"][0]["width"], second["body"][0]["height"]) == (50, 26)
    assert [b["type"] for b in second["body"]] == ["Image", "TextualBody"]
    assert second["body"][1]["purpose"] == "tagging"
    assert "creator" not in second
    assert "@context" not in first  # inside the page; the file of its own has it
    alone = patch_annotation(description(), "vis", description()["layers"][0]["overlay"][
        "patches"][0], standalone=True)
    assert alone == {"@context": page["@context"], **first}


def test_the_page_lists_patches_in_application_order() -> None:
    desc = description()
    patches = desc["layers"][0]["overlay"]["patches"]
    patches.reverse()  # the records' order is the application order; the page keeps it
    page = annotation_page(desc, desc["layers"][0])
    assert page is not None
    assert [a["id"].rsplit("/", 1)[1] for a in page["items"]] == [
        "1_101_0_99_51_1_gilding.json", "0_10_20_30_40_0_cracks.json"]


def test_the_manifest_still_validates_and_links_the_page_after_the_overlay_pages() -> None:
    manifest = build_manifest(description())
    assert validate_manifest(manifest) == []
    pages = manifest["items"][0]["annotations"]
    assert [p["id"] for p in pages] == [f"{DS}/canvas/1/overlays/vis",
                                        f"{DS}/annotations/vis.json"]
    assert pages[1] == {"id": f"{DS}/annotations/vis.json", "type": "AnnotationPage",
                        "label": {"en": ["Notes: Visible"]}}


def test_layers_without_published_patch_images_have_no_page() -> None:
    desc = description()
    assert annotation_page(desc, desc["layers"][1]) is None  # records from before the store
    desc["layers"][0]["overlay"]["patches"] = []
    assert annotation_documents(desc) == {}
    manifest = build_manifest(desc)
    assert [p["id"] for p in manifest["items"][0]["annotations"]] == [
        f"{DS}/canvas/1/overlays/vis"]


def test_ids_with_unsafe_characters_are_percent_encoded_in_urls_not_in_file_names() -> None:
    desc = description()
    desc["layers"][0]["overlay"]["patches"][0]["id"] = "0_10_20_30_40_0_two words"
    docs = annotation_documents(desc)
    assert "annotations/vis/0_10_20_30_40_0_two words.json" in docs
    assert docs["annotations/vis.json"]["items"][0]["id"] == (
        f"{DS}/annotations/vis/0_10_20_30_40_0_two%20words.json")


def test_a_page_the_schema_refuses_is_a_one_line_error() -> None:
    desc = description()
    desc["baseUrl"] = "file:///srv/data"  # Presentation 3 ids must be http(s) URLs
    with pytest.raises(LanternaInputError) as err:
        annotation_documents(desc)
    assert "annotation page of layer vis" in str(err.value)
    assert "\n" not in str(err.value)


@pytest.mark.parametrize(("where", "value"), [
    (("motivation",), ["highlighting", "painting-over"]),
    (("target", "selector", "conformsTo"), "http://example.org/frags"),
    (("body", 1, "purpose"), "scribbling"),
    (("created",), "1 December 2026"),
    (("@context",), "http://iiif.io/api/presentation/3/context.json"),
])
def test_the_w3c_rules_catch_what_the_model_forbids(where: tuple[Any, ...], value: Any) -> None:
    doc = copy.deepcopy(annotation_documents(description())[
        "annotations/vis/0_10_20_30_40_0_cracks.json"])
    node = doc
    for key in where[:-1]:
        node = node[key]
    node[where[-1]] = value
    assert w3c_errors(doc) != []
