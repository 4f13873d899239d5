"""A dataset's library: stored in lanterna.json, presets.json and the manifest, atomically."""

from __future__ import annotations

import json
import os
from pathlib import Path

import pytest
from PIL import Image

from lanterna.errors import LanternaInputError
from lanterna.manifests.validate import validate_manifest
from lanterna.tiler.dataset import writer as writer_mod
from lanterna.tiler.dataset.export import export
from lanterna.tiler.overlays.build import build_overlays
from lanterna.tiler.presets.library import PresetError, empty_library
from lanterna.tiler.presets.store import dataset_library, store_library, update_library
from tests.python.fixtures.overlays import patch
from tests.python.fixtures.presets import read_json, small_dataset, small_library
from tests.python.fixtures.publishing import leftovers


@pytest.fixture
def dataset(tmp_path: Path) -> Path:
    return small_dataset(tmp_path / "root" / "obj")


def _files(dataset: Path) -> dict[str, bytes]:
    real = Path(os.path.realpath(dataset))
    return {str(p.relative_to(real)): p.read_bytes() for p in sorted(real.rglob("*"))
            if p.is_file()}


def test_a_dataset_without_presets_has_an_empty_library(dataset: Path) -> None:
    assert dataset_library(dataset) == empty_library()
    assert not (dataset / "presets.json").exists()
    assert "service" not in read_json(dataset / "manifest.json")


def test_storing_writes_lanterna_json_presets_json_and_the_manifest(dataset: Path) -> None:
    lib = small_library()
    assert store_library(dataset, lib) == lib
    assert read_json(dataset / "lanterna.json")["presets"] == lib
    assert read_json(dataset / "presets.json") == lib
    manifest = read_json(dataset / "manifest.json")
    assert validate_manifest(manifest) == []
    (service,) = manifest["service"]
    assert service == {"id": "http://127.0.0.1:8000/datasets/obj/presets.json",
                       "profile": "urn:lanterna:presets:1", **lib}
    assert dataset_library(dataset) == lib
    assert leftovers(dataset.parent) == ["obj"]


def test_a_library_label_stays_in_presets_json_but_out_of_the_manifest(dataset: Path) -> None:
    lib = {**small_library(), "label": "Conservator's presets"}
    store_library(dataset, lib)
    assert read_json(dataset / "presets.json")["label"] == "Conservator's presets"
    manifest = read_json(dataset / "manifest.json")
    assert validate_manifest(manifest) == [] and "label" not in manifest["service"][0]


def test_storing_an_empty_library_removes_it(dataset: Path) -> None:
    store_library(dataset, small_library())
    store_library(dataset, empty_library())
    assert "presets" not in read_json(dataset / "lanterna.json")
    assert not (dataset / "presets.json").exists()
    assert "service" not in read_json(dataset / "manifest.json")


def test_a_bad_library_changes_nothing(dataset: Path) -> None:
    store_library(dataset, small_library())
    before, version = _files(dataset), os.readlink(dataset)
    bad = small_library()
    bad["base"][0]["layer"] = "ir"
    with pytest.raises(PresetError, match=r"^presets\.json: base\[0\]\.layer: no layer 'ir'"):
        store_library(dataset, bad)
    assert os.readlink(dataset) == version and _files(dataset) == before
    assert leftovers(dataset.parent) == ["obj"]


def test_a_failure_half_way_leaves_the_previous_dataset(dataset: Path,
                                                        monkeypatch: pytest.MonkeyPatch) -> None:
    store_library(dataset, small_library())
    before, version = _files(dataset), os.readlink(dataset)
    half_written: list[object] = []

    def failing(desc: dict[str, object], infos: object = None) -> dict[str, object]:
        # lanterna.json and presets.json of the next version are written by now
        (tmp,) = dataset.parent.glob(".obj.tmp-*")
        half_written.append(read_json(tmp / "presets.json")["presets"]["raking"]["label"])
        raise OSError(28, "No space left on device")

    monkeypatch.setattr(writer_mod, "build_manifest", failing)
    new = small_library()
    new["presets"]["raking"]["label"] = "Raking, changed"
    with pytest.raises(LanternaInputError, match=r"cannot write \(No space left on device\); "
                                                 "nothing was changed"):
        store_library(dataset, new)
    assert half_written == ["Raking, changed"]
    assert os.readlink(dataset) == version and _files(dataset) == before
    assert leftovers(dataset.parent) == ["obj"]


def test_update_sees_the_current_library(dataset: Path) -> None:
    store_library(dataset, small_library())
    seen = []

    def change(lib: dict[str, object], desc: dict[str, object]) -> dict[str, object]:
        seen.append((lib, desc["name"]))
        return {**lib, "base": []}

    out = update_library(dataset, change)
    assert seen == [(small_library(), "obj")] and out["base"] == []


def test_an_overlay_build_keeps_the_presets(dataset: Path, tmp_path: Path) -> None:
    store_library(dataset, small_library())
    patches = tmp_path / "patches"
    patches.mkdir()
    Image.fromarray(patch(16, 16, (255, 0, 0), 200)).save(patches / "0_4_4_16_16_0_mark.png")
    build_overlays(dataset, "ptm", patches_dir=patches)
    assert read_json(dataset / "presets.json") == small_library()
    assert read_json(dataset / "manifest.json")["service"][0]["presets"] == \
        small_library()["presets"]


def test_a_static_export_keeps_the_presets(dataset: Path, tmp_path: Path) -> None:
    store_library(dataset, small_library())
    export(dataset, tmp_path / "site", "https://cdn.example.org/iiif")
    manifest = read_json(tmp_path / "site" / "obj" / "manifest.json")
    assert validate_manifest(manifest) == []
    (service,) = manifest["service"]
    assert service["id"] == "https://cdn.example.org/iiif/obj/presets.json"
    assert read_json(tmp_path / "site" / "obj" / "presets.json") == small_library()
    assert {k: service[k] for k in ("presets", "base", "lens")} == \
        {k: small_library()[k] for k in ("presets", "base", "lens")}


def test_storing_again_replaces_presets_json(dataset: Path) -> None:
    store_library(dataset, small_library())
    again = small_library()
    again["lens"] = []
    store_library(dataset, again)
    assert read_json(dataset / "presets.json") == again
    assert json.loads((dataset / "lanterna.json").read_text())["presets"] == again
