"""Every kind of manifest we write validates against the official IIIF Presentation 3.0 schema."""

from __future__ import annotations

import copy
import json
from collections.abc import Callable
from pathlib import Path
from typing import Any

import pytest

from lanterna.manifests.build import build_manifest
from lanterna.manifests.validate import SCHEMA_PATH, validate_manifest
from tests.python.fixtures.dataset_kinds import KINDS, build_kinds


@pytest.fixture(scope="module")
def kinds(tmp_path_factory: pytest.TempPathFactory) -> dict[str, Path]:
    return build_kinds(tmp_path_factory.mktemp("kinds") / "root")


def manifest(folder: Path) -> dict[str, Any]:
    doc: dict[str, Any] = json.loads((folder / "manifest.json").read_text())
    return doc


@pytest.mark.parametrize("kind", KINDS)
def test_written_manifest_is_valid(kinds: dict[str, Path], kind: str) -> None:
    assert validate_manifest(manifest(kinds[kind])) == []


def _image_services(node: Any) -> list[dict[str, Any]]:
    if isinstance(node, list):
        return [s for item in node for s in _image_services(item)]
    if not isinstance(node, dict):
        return []
    found = [node] if node.get("type") == "ImageService3" else []
    return found + [s for value in node.values() for s in _image_services(value)]


@pytest.mark.parametrize("kind", KINDS)
def test_every_image_service_embeds_its_info_json_description(kinds: dict[str, Path],
                                                               kind: str) -> None:
    # painting images, relight plane groups and overlay levels (written by a rewrite) alike
    services = _image_services(manifest(kinds[kind]))
    assert len(services) >= 2
    for service in services:
        ident = service["id"].rsplit("/", 1)[1]
        info = json.loads((kinds[kind] / "iiif" / ident / "info.json").read_text())
        assert service == {"type": "ImageService3", **{
            k: v for k, v in info.items() if k not in ("@context", "protocol")}}


def test_the_kinds_cover_every_layer_type_and_an_overlay(kinds: dict[str, Path]) -> None:
    types = set()
    for folder in kinds.values():
        desc = json.loads((folder / "lanterna.json").read_text())
        types |= {layer["service"]["layerType"] for layer in desc["layers"]}
    assert types == {"ptm", "hsh", "svbrdf", "image"}
    pages = manifest(kinds["overlay"])["items"][0]["annotations"]
    assert [a["motivation"] for a in pages[0]["items"]] == ["commenting"] * 2
    items = manifest(kinds["multi"])["items"][0]["items"][0]["items"][0]["body"]["items"]
    layers = [i for i in items if any(s["type"] == "LanternaRelight" for s in i["service"])]
    assert len(layers) == 5  # (and ARCHiOx's albedo + normal items, test_lightingmap.py)


def test_manifest_without_summary_or_overlay_is_valid(kinds: dict[str, Path]) -> None:
    desc = json.loads((kinds["multi"] / "lanterna.json").read_text())
    del desc["summary"]
    assert validate_manifest(build_manifest(desc)) == []


def test_the_vendored_schema_is_the_official_one() -> None:
    schema = json.loads(SCHEMA_PATH.read_text())
    assert schema["$id"] == "http://iiif.io/api/presentation/3/schema.json"
    assert {"manifest", "canvas", "annotationPage", "annotation", "choice"} <= set(
        schema["classes"])
    notice = (SCHEMA_PATH.parent / "NOTICE.md").read_text()
    assert "IIIF/presentation-validator" in notice and "60bc2bde" in notice


def _body(doc: dict[str, Any]) -> dict[str, Any]:
    item: dict[str, Any] = doc["items"][0]["items"][0]["items"][0]["body"]["items"][0]
    return item


Breakage = Callable[[dict[str, Any]], object]
BREAKAGES: dict[str, tuple[Breakage, str]] = {
    "no label": (lambda m: m.pop("label"), "(root): 'label' is a required property"),
    "label not a language map": (lambda m: m.update(label="Object"), "label: 'Object' is not"),
    "unknown manifest key": (lambda m: m.update(layers=[]), "'layers' was unexpected"),
    "negative canvas width": (lambda m: m["items"][0].update(width=-1), "items/0/width: -1"),
    "canvas without items": (lambda m: m["items"][0].pop("items"),
                             "items/0: 'items' is a required property"),
    "relative id": (lambda m: m.update(id="manifest.json"), "id: 'manifest.json' does not match"),
    "service without id": (lambda m: _body(m)["service"][0].pop("id"),
                           "body/items/0/service/0: 'id' is a required property"),
    "bad media type": (lambda m: _body(m).update(format="jpeg"),
                       "body/items/0/format: 'jpeg' does not match"),
    "target not a URI": (lambda m: m["items"][0]["items"][0]["items"][0].update(target="c1"),
                         "items/0/items/0/items/0/target: 'c1'"),
    "overlay page with an unknown key": (
        lambda m: m["items"][0]["annotations"][0].update(behavior=["hidden"]),
        "items/0/annotations/0: Additional properties are not allowed ('behavior'"),
}


@pytest.mark.parametrize("name", BREAKAGES)
def test_a_broken_manifest_is_reported(kinds: dict[str, Path], name: str) -> None:
    breaking, expected = BREAKAGES[name]
    doc = copy.deepcopy(manifest(kinds["overlay"]))
    breaking(doc)
    errors = validate_manifest(doc)
    assert errors, f"{name}: not reported"
    assert any(expected in e for e in errors), errors


@pytest.mark.parametrize("kind", KINDS)
def test_the_thumbnail_is_a_file_the_first_layers_pyramid_holds(kinds: dict[str, Path],
                                                                 kind: str) -> None:
    doc = manifest(kinds[kind])
    (thumb,) = doc["thumbnail"]
    first = doc["items"][0]["items"][0]["items"][0]["body"]["items"][0]
    service = first["service"][0]
    assert thumb["service"] == [service]  # the first layer's image, with its service
    w, h = thumb["width"], thumb["height"]
    assert {"width": w, "height": h} in service["sizes"] and max(w, h) <= 400
    assert thumb["id"] == f"{service['id']}/full/{w},{h}/0/default.{thumb['id'][-3:]}"
    file = kinds[kind] / "iiif" / thumb["id"].split("/iiif/", 1)[1]
    assert file.is_file()  # no new file: an existing sizes entry
    assert thumb["format"] == {"jpg": "image/jpeg", "png": "image/png"}[file.suffix[1:]]
