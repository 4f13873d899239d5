"""The manifest's thumbnail, metadata, rights, attribution, provider, links (portal panels)."""

from __future__ import annotations

import copy
import json
from pathlib import Path
from typing import Any

import pytest

from lanterna.errors import LanternaInputError
from lanterna.manifests import metadata as md
from lanterna.manifests.build import build_manifest
from lanterna.manifests.validate import validate_manifest
from lanterna.tiler.dataset.writer import image_infos
from tests.python.fixtures.dataset_kinds import build_kinds

PUBLICATION = {
    "rights": "http://creativecommons.org/licenses/by/4.0/",
    "attribution": "Photographs: Example Museum",
    "provider": {"label": "Example Museum", "homepage": "https://museum.example/",
                 "logo": "https://museum.example/logo.png"},
    "homepage": "https://museum.example/objects/42",
    "seeAlso": ["https://museum.example/objects/42.json", "https://museum.example/42.html"],
    "metadata": [{"label": "Object", "value": "Tablet"}, {"label": "Date", "value": "2nd c."}],
}
SCHEMA = Path(__file__).parents[3] / "tiler" / "schemas" / "description.schema.json"


@pytest.fixture(scope="module")
def kinds(tmp_path_factory: pytest.TempPathFactory) -> dict[str, Path]:
    return build_kinds(tmp_path_factory.mktemp("kinds") / "root")


def described(folder: Path, publication: dict[str, Any] | None) -> tuple[dict[str, Any], Any]:
    desc = json.loads((folder / "lanterna.json").read_text())
    if publication is not None:
        desc["publication"] = copy.deepcopy(publication)
    return desc, image_infos(folder, desc, folder)


@pytest.mark.parametrize("uri", [
    "http://creativecommons.org/licenses/by/4.0/", "http://creativecommons.org/licenses/by-nc-sa/3.0/",
    "http://creativecommons.org/licenses/by/3.0/de/", "http://creativecommons.org/publicdomain/zero/1.0/",
    "http://creativecommons.org/publicdomain/mark/1.0/", "http://rightsstatements.org/vocab/InC/1.0/",
    "http://rightsstatements.org/vocab/NoC-NC/1.0/"])
def test_accepted_rights_are_what_the_presentation_schema_accepts(
        kinds: dict[str, Path], uri: str) -> None:
    desc, infos = described(kinds["images"], {"rights": uri})
    doc = build_manifest(desc, infos)
    assert doc["rights"] == uri and validate_manifest(doc) == []


@pytest.mark.parametrize(("uri", "hint"), [
    ("https://creativecommons.org/licenses/by/4.0/", "http://creativecommons.org/licenses/by/4.0/"),
    ("http://creativecommons.org/licenses/by/4.0", "http://creativecommons.org/licenses/by/4.0/"),
    ("http://creativecommons.org/licenses/by-xx/4.0/", None),
    ("http://rightsstatements.org/vocab/InC/2.0/", None),
    ("All rights reserved", None)])
def test_other_rights_are_refused_with_a_hint(uri: str, hint: str | None) -> None:
    with pytest.raises(ValueError, match="Creative Commons or RightsStatements.org") as err:
        md.check_rights(uri)
    assert (f"did you mean {hint}?" in str(err.value)) == (hint is not None)


def test_the_description_schema_uses_the_same_rights_and_url_rules() -> None:
    schema = json.loads(SCHEMA.read_text())
    assert schema["properties"]["rights"]["pattern"] == md.RIGHTS_PATTERN
    assert schema["$defs"]["url"]["pattern"] == md.URL_PATTERN
    assert set(md.PUBLICATION_KEYS) <= set(schema["properties"])


def test_the_manifest_carries_every_given_property_and_stays_valid(
        kinds: dict[str, Path]) -> None:
    desc, infos = described(kinds["images"], PUBLICATION)
    doc = build_manifest(desc, infos)
    assert validate_manifest(doc) == []
    ds_url = doc["id"].removesuffix("/manifest.json")
    assert doc["rights"] == PUBLICATION["rights"]
    assert doc["requiredStatement"] == {"label": {"en": ["Attribution"]},
                                        "value": {"en": ["Photographs: Example Museum"]}}
    assert doc["provider"] == [{
        "id": f"{ds_url}/manifest.json#provider", "type": "Agent",
        "label": {"en": ["Example Museum"]},
        "homepage": [{"id": "https://museum.example/", "type": "Text",
                      "label": {"en": ["Example Museum"]}, "format": "text/html"}],
        "logo": [{"id": "https://museum.example/logo.png", "type": "Image",
                  "format": "image/png"}]}]
    assert doc["homepage"] == [{"id": "https://museum.example/objects/42", "type": "Text",
                                "label": {"en": [desc["label"]]}, "format": "text/html"}]
    assert doc["seeAlso"] == [
        {"id": "https://museum.example/objects/42.json", "type": "Dataset",
         "format": "application/json"},
        {"id": "https://museum.example/42.html", "type": "Text", "format": "text/html"}]
    assert doc["metadata"] == [{"label": {"en": ["Object"]}, "value": {"en": ["Tablet"]}},
                               {"label": {"en": ["Date"]}, "value": {"en": ["2nd c."]}}]
    keys = list(doc)
    assert keys.index("metadata") < keys.index("thumbnail") < keys.index("items")


def test_without_publication_there_is_only_the_thumbnail(kinds: dict[str, Path]) -> None:
    desc, infos = described(kinds["images"], None)
    doc = build_manifest(desc, infos)
    given = {"metadata", "rights", "requiredStatement", "provider", "homepage", "seeAlso"}
    assert given.isdisjoint(doc) and len(doc["thumbnail"]) == 1


def test_wavelengths_come_before_the_given_metadata(kinds: dict[str, Path]) -> None:
    desc, infos = described(kinds["images"], {"metadata": [{"label": "A", "value": "b"}]})
    desc["layers"][1]["service"]["wavelength"] = 850
    doc = build_manifest(desc, infos)
    assert [m["label"]["en"][0] for m in doc["metadata"]] == ["Wavelengths", "A"]
    assert doc["metadata"][0]["value"] == {"en": ["850 nm"]}


@pytest.mark.parametrize(("publication", "message"), [
    ({"rights": "CC-BY"}, "publication.rights: not a Creative Commons"),
    ({"homepage": "museum.example"}, "publication.homepage: not an http(s) URL"),
    ({"seeAlso": "https://x.example/"}, "publication.seeAlso: not a list"),
    ({"provider": {"homepage": "https://x.example/"}}, "publication.provider: not a text"),
    ({"metadata": [{"label": "A"}]}, "publication.metadata: wants {label, value}"),
    ({"licence": "x"}, "publication.licence: unknown field"),
    ({"attribution": "x" * 1001}, "publication.attribution: not a text of 1 to 1000")])
def test_a_bad_publication_field_is_a_one_line_error_naming_it(
        publication: dict[str, Any], message: str) -> None:
    with pytest.raises(LanternaInputError) as err:
        md.check_publication(publication)
    assert message in str(err.value) and "\n" not in str(err.value)


@pytest.mark.parametrize(("text", "expected"), [
    ("Example Museum", {"label": "Example Museum"}),
    ("Museum, Oxford,https://m.example/", {"label": "Museum, Oxford",
                                           "homepage": "https://m.example/"}),
    ("M,https://m.example/,https://m.example/l.svg", {
        "label": "M", "homepage": "https://m.example/", "logo": "https://m.example/l.svg"})])
def test_provider_option_forms(text: str, expected: dict[str, str]) -> None:
    assert md.parse_provider(text) == expected


def test_metadata_option_form() -> None:
    assert md.parse_metadata("Find spot = Oxyrhynchus, Egypt") == {
        "label": "Find spot", "value": "Oxyrhynchus, Egypt"}
    with pytest.raises(ValueError, match="LABEL=VALUE"):
        md.parse_metadata("no pair")


def test_a_bad_stored_publication_names_lanterna_json(kinds: dict[str, Path]) -> None:
    desc, infos = described(kinds["images"], {"rights": "CC-BY"})
    with pytest.raises(LanternaInputError, match=r"lanterna.json: publication.rights: not a"):
        build_manifest(desc, infos)
