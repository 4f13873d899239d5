"""``lanterna import``/``fit`` options and description fields for what a portal shows, kept by
every rebuild of the manifest."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from lanterna.cli import main
from lanterna.manifests.validate import validate_manifest
from tests.python.fixtures.photos import (
    bumpy_normals,
    render_bumpy,
    spiral_lights,
    write_collection,
)
from tests.python.fixtures.sources import png, random_image

CC_BY = "http://creativecommons.org/licenses/by/4.0/"
CC0 = "http://creativecommons.org/publicdomain/zero/1.0/"
OPTIONS = ["--rights", CC_BY, "--attribution", "Photographs: Example Museum",
           "--provider", "Example Museum, Oxford,https://museum.example/",
           "--homepage", "https://museum.example/objects/42",
           "--see-also", "https://museum.example/objects/42.json",
           "--metadata", "Object=Tablet", "--metadata", "Date=2nd c.",
           "--summary", "<p>A tablet.</p>"]


def manifest(out: Path) -> dict[str, Any]:
    doc: dict[str, Any] = json.loads((out / "manifest.json").read_text())
    assert validate_manifest(doc) == []
    return doc


def assert_published(doc: dict[str, Any]) -> None:
    assert doc["rights"] == CC_BY
    assert doc["requiredStatement"]["value"] == {"en": ["Photographs: Example Museum"]}
    (provider,) = doc["provider"]
    assert provider["label"] == {"en": ["Example Museum, Oxford"]}
    assert provider["homepage"][0]["id"] == "https://museum.example/"
    assert doc["homepage"][0]["id"] == "https://museum.example/objects/42"
    assert [s["id"] for s in doc["seeAlso"]] == ["https://museum.example/objects/42.json"]
    assert [(m["label"]["en"][0], m["value"]["en"][0]) for m in doc["metadata"]] == [
        ("Object", "Tablet"), ("Date", "2nd c.")]
    assert doc["summary"] == {"en": ["<p>A tablet.</p>"]}


def test_import_options_reach_the_manifest_and_survive_a_rebuild(tmp_path: Path) -> None:
    src = png(tmp_path / "vis.png", random_image(1))
    out = tmp_path / "ds"
    assert main(["import", str(src), "-o", str(out), *OPTIONS]) == 0
    assert_published(manifest(out))
    stored = json.loads((out / "lanterna.json").read_text())["publication"]
    assert stored["rights"] == CC_BY and stored["provider"]["label"] == "Example Museum, Oxford"
    patches = tmp_path / "patches"
    patches.mkdir()
    rgba = np.zeros((10, 12, 4), np.uint8)
    rgba[..., 0], rgba[..., 3] = 255, 200
    png(patches / "0_20_10_12_10_0_mark.png", rgba)
    assert main(["annotate", "build", str(out), "--layer", "vis", "--patches",
                 str(patches)]) == 0
    rebuilt = manifest(out)
    assert_published(rebuilt)  # the overlay rebuild kept every property
    (level,) = rebuilt["items"][0]["annotations"][0]["items"]
    assert level["target"]["selector"]["value"] == "xywh=20,10,12,10"


def test_fit_options_reach_the_manifest(tmp_path: Path) -> None:
    lights = spiral_lights(12)
    lp = write_collection(tmp_path / "shots", render_bumpy(bumpy_normals(), lights), lights)
    out = tmp_path / "ds"
    assert main(["fit", str(tmp_path / "shots"), "--lp", str(lp), "--model", "ptm", "--quiet",
                 "-o", str(out), *OPTIONS]) == 0
    assert_published(manifest(out))


def test_description_fields_are_used_and_options_override_them(tmp_path: Path) -> None:
    png(tmp_path / "vis.png", random_image(2))
    doc = {"label": "Tablet", "rights": CC0, "attribution": "From the file",
           "provider": {"label": "File Museum", "logo": "https://f.example/logo.svg"},
           "metadata": [{"label": "Material", "value": "Limestone"}],
           "layers": [{"id": "vis", "source": "vis.png"}]}
    (tmp_path / "obj.json").write_text(json.dumps(doc))
    out = tmp_path / "ds"
    assert main(["import", str(tmp_path / "obj.json"), "-o", str(out), "--attribution",
                 "From the option"]) == 0
    m = manifest(out)
    assert m["rights"] == CC0
    assert m["requiredStatement"]["value"] == {"en": ["From the option"]}
    assert m["provider"][0]["logo"] == [{"id": "https://f.example/logo.svg", "type": "Image",
                                         "format": "image/svg+xml"}]
    assert m["metadata"] == [{"label": {"en": ["Material"]}, "value": {"en": ["Limestone"]}}]


@pytest.mark.parametrize(("field", "value", "message"), [
    ("rights", "https://creativecommons.org/licenses/by/4.0/", "rights"),
    ("homepage", "museum.example", "homepage"),
    ("metadata", [{"label": "A"}], "metadata[0]")])
def test_a_bad_description_field_is_one_line_naming_the_file_and_field(
        tmp_path: Path, capsys: pytest.CaptureFixture[str], field: str, value: Any,
        message: str) -> None:
    png(tmp_path / "vis.png", random_image(3))
    doc = {field: value, "layers": [{"id": "vis", "source": "vis.png"}]}
    (tmp_path / "obj.json").write_text(json.dumps(doc))
    out = tmp_path / "ds"
    assert main(["import", str(tmp_path / "obj.json"), "-o", str(out)]) != 0
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "obj.json" in err and message in err, err
    assert not out.exists()


@pytest.mark.parametrize(("option", "value", "message"), [
    ("--rights", "https://creativecommons.org/licenses/by/4.0/",
     "did you mean http://creativecommons.org/licenses/by/4.0/?"),
    ("--homepage", "www.museum.example", "not an http(s) URL"),
    ("--provider", "https://museum.example/", "with the name first"),
    ("--metadata", "Tablet", "wants LABEL=VALUE")])
def test_a_bad_option_is_one_line_naming_it(tmp_path: Path, capsys: pytest.CaptureFixture[str],
                                            option: str, value: str, message: str) -> None:
    src = png(tmp_path / "vis.png", random_image(4))
    with pytest.raises(SystemExit) as exit_:
        main(["import", str(src), "-o", str(tmp_path / "ds"), option, value])
    assert exit_.value.code == 2
    last = capsys.readouterr().err.strip().splitlines()[-1]
    assert f"argument {option}" in last and message in last, last
    assert not (tmp_path / "ds").exists()
