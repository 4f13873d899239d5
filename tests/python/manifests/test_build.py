"""The dataset manifest: IIIF Presentation 3 shape and the relight service block."""

from __future__ import annotations

import json
import os
from pathlib import Path

import pytest

from lanterna.tiler.dataset.layers import add_ptm_layer
from lanterna.tiler.dataset.writer import DatasetWriter
from tests.python.fixtures.ptm import random_ptm_of_size


@pytest.fixture(scope="module")
def dataset(tmp_path_factory: pytest.TempPathFactory) -> Path:
    out = tmp_path_factory.mktemp("m") / "obj"
    with DatasetWriter(out, name="obj", label="An object", width=120, height=80,
                       base_url="https://example.org/data/") as ds:
        add_ptm_layer(ds, random_ptm_of_size(120, 80, "rgb"), label="RGB PTM")
    return out


def test_manifest_shape(dataset: Path) -> None:
    m = json.loads((dataset / "manifest.json").read_text())
    assert m["@context"] == "http://iiif.io/api/presentation/3/context.json"
    assert m["type"] == "Manifest" and m["id"] == "https://example.org/data/obj/manifest.json"
    assert m["label"] == {"en": ["An object"]}
    canvas = m["items"][0]
    assert (canvas["type"], canvas["width"], canvas["height"]) == ("Canvas", 120, 80)
    anno = canvas["items"][0]["items"][0]
    assert anno["motivation"] == "painting" and anno["target"] == canvas["id"]
    choice = anno["body"]
    assert choice["type"] == "Choice" and len(choice["items"]) == 1
    body = choice["items"][0]
    assert body["type"] == "Image" and body["format"] == "image/jpeg"
    assert body["id"] == "https://example.org/data/obj/iiif/ptm_preview/full/max/0/default.jpg"
    assert (dataset / "iiif/ptm_preview/full/max/0/default.jpg").is_file()
    image_service, relight = body["service"]
    info = json.loads((dataset / "iiif/ptm_preview/info.json").read_text())
    assert image_service == {"id": "https://example.org/data/obj/iiif/ptm_preview",
                             "type": "ImageService3", "profile": "level0", "width": 120,
                             "height": 80, "sizes": info["sizes"], "tiles": info["tiles"]}
    assert relight["type"] == "LanternaRelight" and relight["profile"] == "urn:lanterna:relight:1"
    assert relight["layerType"] == "ptm" and relight["colorspace"] == "rgb"
    assert [p["channels"] for p in relight["planes"]] == [
        [f"{c}{k}" for k in range(g, g + 3)] for c in "RGB" for g in (0, 3)]


def test_every_service_in_the_manifest_exists_on_disk(dataset: Path) -> None:
    m = json.loads((dataset / "manifest.json").read_text())
    body = m["items"][0]["items"][0]["items"][0]["body"]["items"][0]
    relight = body["service"][1]
    for plane in relight["planes"]:
        ident = plane["service"]["id"].removeprefix("https://example.org/data/obj/iiif/")
        info = json.loads((dataset / "iiif" / ident / "info.json").read_text())
        assert info["id"] == plane["service"]["id"]
        assert (info["width"], info["height"]) == (120, 80)
        # the description the viewer needs is embedded: no info.json request before the tiles
        assert plane["service"] == {"type": "ImageService3", **{
            k: info[k] for k in ("id", "profile", "width", "height", "sizes", "tiles",
                                 "preferredFormats", "extraFormats")}}
    layer_doc = json.loads((dataset / "layers/ptm.json").read_text())
    assert layer_doc == relight
    assert relight["id"] == "https://example.org/data/obj/layers/ptm.json"


def test_large_image_body_has_the_size_of_its_reduced_full_max(tmp_path: Path) -> None:
    import pyvips

    from lanterna.tiler.dataset.layers import add_image_layer
    from lanterna.tiler.iiif.pyramid import FULL_MAX_LIMIT

    w, h = FULL_MAX_LIMIT + 200, 64
    img = pyvips.Image.black(w, h, bands=3).copy(interpretation="srgb") + 90
    with DatasetWriter(tmp_path / "big", name="big", label="big", width=w, height=h) as ds:
        add_image_layer(ds, img.cast("uchar"), layer_id="vis")
    desc = json.loads((tmp_path / "big" / "lanterna.json").read_text())
    assert (desc["images"]["vis"]["maxWidth"], desc["images"]["vis"]["maxHeight"]) == (
        -(-w // 2), h // 2)
    body = json.loads((tmp_path / "big" / "manifest.json").read_text())[
        "items"][0]["items"][0]["items"][0]["body"]["items"][0]
    assert body["id"].endswith("/vis/full/max/0/default.jpg")
    assert (body["width"], body["height"]) == (-(-w // 2), h // 2)
    full = pyvips.Image.new_from_file(str(tmp_path / "big/iiif/vis/full/max/0/default.jpg"))
    assert (full.width, full.height) == (body["width"], body["height"])
    service = body["service"][0]
    info = json.loads((tmp_path / "big/iiif/vis/info.json").read_text())
    assert (service["maxWidth"], service["maxHeight"]) == (info["maxWidth"], info["maxHeight"])
    assert service["tiles"] == info["tiles"] and service["sizes"] == info["sizes"]
    assert "preferredFormats" not in service  # a JPEG tree has none


def test_missing_info_json_leaves_a_bare_reference(tmp_path: Path) -> None:
    from lanterna.manifests.build import build_manifest
    from lanterna.tiler.dataset.writer import image_infos

    desc = json.loads((_small_dataset(tmp_path) / "lanterna.json").read_text())
    folder = _small_dataset_folder(tmp_path)
    (folder / "iiif/ptm_r0/info.json").unlink()
    infos = image_infos(folder, desc, folder)
    assert "ptm_r0" not in infos and "ptm_g0" in infos
    body = build_manifest(desc, infos)["items"][0]["items"][0]["items"][0]["body"]["items"][0]
    planes = {p["service"]["id"].rsplit("/", 1)[1]: p["service"]
              for p in body["service"][1]["planes"]}
    assert planes["ptm_r0"] == {"id": planes["ptm_r0"]["id"], "type": "ImageService3",
                                "profile": "level0"}
    assert planes["ptm_g0"]["tiles"][0]["scaleFactors"] == [1]


def test_an_info_json_that_is_not_json_is_a_one_line_error(tmp_path: Path) -> None:
    from lanterna.errors import LanternaInputError
    from lanterna.tiler.dataset.writer import image_infos

    folder = _small_dataset(tmp_path)
    desc = json.loads((folder / "lanterna.json").read_text())
    (folder / "iiif/ptm_g0/info.json").write_text("{not json")
    with pytest.raises(LanternaInputError, match=r"ptm_g0/info.json.*not valid JSON"):
        image_infos(folder, desc, folder)


def _small_dataset_folder(tmp_path: Path) -> Path:
    return Path(os.path.realpath(tmp_path / "obj"))


def _small_dataset(tmp_path: Path) -> Path:
    out = tmp_path / "obj"
    with DatasetWriter(out, name="obj", label="An object", width=120, height=80) as ds:
        add_ptm_layer(ds, random_ptm_of_size(120, 80, "rgb"), label="RGB PTM")
    return Path(os.path.realpath(out))
