"""A Lanterna manifest describes a shape + material layer's albedo and normal map the ARCHiOx way
(LightingMapExtension services on extra Choice items): valid Presentation 3, found where ARCHiOx's
viewer looks, pointing at images whose pixels are the layer's maps, and importable back."""

from __future__ import annotations

import json
import urllib.request
from pathlib import Path
from typing import Any

import numpy as np
import numpy.typing as npt
import pytest
import pyvips

from lanterna.cli import main
from lanterna.manifests.lightingmap import LIGHTINGMAP_CONTEXT, LIGHTINGMAP_PROFILE
from lanterna.manifests.validate import validate_manifest
from lanterna.tiler.dataset.layers import add_image_layer, add_svbrdf_layer
from lanterna.tiler.dataset.writer import DatasetWriter
from lanterna.tiler.iiif.pyramid import vips_from_array
from tests.python.fixtures.archiox import H, W, maps
from tests.python.fixtures.servers import lanterna_serve

PRESENTATION = "http://iiif.io/api/presentation/3/context.json"
ANNEX_PROFILE = "http://iiif.io/api/annex/services/lightingmap"


def write_dataset(root: Path, *, with_kd: bool = True) -> dict[str, npt.NDArray[np.uint8]]:
    """A dataset: a plain image, a shape-only layer, then a shape + material layer, then another."""
    albedo, normal = maps(8)
    other_albedo, _ = maps(9)
    with DatasetWriter(root / "obj", name="obj", label="Tablet", width=W, height=H) as ds:
        add_image_layer(ds, vips_from_array(albedo), layer_id="photo")
        add_svbrdf_layer(ds, normals=normal, layer_id="shape")
        if with_kd:
            add_svbrdf_layer(ds, normals=normal, kd=albedo, input_colorspace="srgb",
                             share={"normals": "n"}, layer_id="sv", label="Shape and colour")
            add_svbrdf_layer(ds, normals=normal, kd=other_albedo, input_colorspace="srgb",
                             share={"normals": "n"}, layer_id="sv2")
    return {"albedo": albedo, "normal": normal}


def manifest_of(root: Path) -> dict[str, Any]:
    doc: dict[str, Any] = json.loads((root / "obj" / "manifest.json").read_text())
    return doc


def choice_items(doc: dict[str, Any]) -> list[dict[str, Any]]:
    items: list[dict[str, Any]] = doc["items"][0]["items"][0]["items"][0]["body"]["items"]
    return items


def archiox_maps(doc: dict[str, Any]) -> dict[str, str]:
    """What ARCHiOx's getMap finds: per mapType, the ImageService3 id of the Choice item whose
    services include one of its lighting-map profiles (the annex one first)."""
    found = {}
    for item in choice_items(doc):
        services = item.get("service", [])
        mark = next((s for p in (ANNEX_PROFILE, LIGHTINGMAP_PROFILE) for s in services
                     if s.get("profile") == p), None)
        if mark is not None:
            found[mark["mapType"]] = next(s["id"] for s in services
                                          if s.get("type") == "ImageService3")
    return found


def test_the_maps_are_extra_choice_items_of_a_valid_manifest(tmp_path: Path) -> None:
    write_dataset(tmp_path)
    doc = manifest_of(tmp_path)
    assert validate_manifest(doc) == []
    assert doc["@context"] == [LIGHTINGMAP_CONTEXT, PRESENTATION], "Presentation 3 last"
    items = choice_items(doc)
    desc = json.loads((tmp_path / "obj" / "lanterna.json").read_text())
    layers = {layer["id"]: layer for layer in desc["layers"]}
    assert len(items) == len(layers) + 2, "one albedo + normal pair, after the layers"
    assert [i["label"]["en"][0] for i in items[:4]] == [x["label"] for x in layers.values()]
    albedo, normal = items[4:]
    for item, map_type in ((albedo, "albedo"), (normal, "normal")):
        assert item["type"] == "Image"
        assert all(s["type"] != "LanternaRelight" for s in item["service"]), \
            "our viewer lists only images with a relight service as layers"
        mark = item["service"][1]
        assert {k: mark[k] for k in ("type", "profile", "mapType")} == {
            "type": "LightingMapExtension", "profile": LIGHTINGMAP_PROFILE, "mapType": map_type}
        assert item["service"][0]["type"] == "ImageService3"
        assert (item["width"], item["height"]) == (W, H)
    planes = {p["channels"][0]: p["service"]["id"] for p in layers["sv"]["service"]["planes"]}
    assert archiox_maps(doc) == {"albedo": planes["KD_R"], "normal": planes["NX"]}, \
        "the first layer with both maps (sv), not the shape-only one nor sv2"
    fmt = desc["images"][planes["KD_R"].rsplit("/", 1)[1]]["format"]
    assert albedo["id"] == f"{planes['KD_R']}/full/max/0/default.{fmt}"
    assert albedo["format"] == {"webp": "image/webp", "png": "image/png"}[fmt]


def test_no_pair_no_maps(tmp_path: Path) -> None:
    write_dataset(tmp_path, with_kd=False)
    doc = manifest_of(tmp_path)
    assert doc["@context"] == PRESENTATION
    assert archiox_maps(doc) == {}
    assert len(choice_items(doc)) == 2


def get(url: str) -> bytes:
    with urllib.request.urlopen(url, timeout=30) as response:  # noqa: S310
        data: bytes = response.read()
    return data


def decode(data: bytes) -> npt.NDArray[np.uint8]:
    image = pyvips.Image.new_from_buffer(data, "")
    return np.ndarray((image.height, image.width, image.bands), np.uint8, image.write_to_memory())


def test_served_maps_are_the_layers_maps_and_import_back(tmp_path: Path) -> None:
    source = write_dataset(tmp_path / "root")
    with lanterna_serve(tmp_path / "root") as (url, _):
        doc = json.loads(get(f"{url}/datasets/obj/manifest.json"))
        found = archiox_maps(doc)
        assert set(found) == {"albedo", "normal"}
        assert all(s.startswith(f"{url}/") for s in found.values()), "ids follow the request"
        albedo_info = json.loads(get(f"{found['albedo']}/info.json"))
        fmt = albedo_info["preferredFormats"][0]
        tile = albedo_info["tiles"][0]["width"]
        for map_type, service in found.items():
            full = decode(get(f"{service}/full/max/0/default.{fmt}"))
            np.testing.assert_array_equal(full, source[map_type])
            # ARCHiOx builds both maps' tile URLs from the albedo's info.json (scale factor 1:
            # the region clipped to the image, the size the region's)
            tw, th = min(tile, W), min(tile, H)
            first = decode(get(f"{service}/0,0,{tw},{th}/{tw},{th}/0/default.{fmt}"))
            np.testing.assert_array_equal(first, source[map_type][:th, :tw])
        out = tmp_path / "back"
        assert main(["import", f"{url}/datasets/obj/manifest.json", "-o", str(out)]) == 0
    desc = json.loads((out / "lanterna.json").read_text())
    assert [layer["service"]["layerType"] for layer in desc["layers"]] == ["svbrdf"]
    assert desc["label"] == "Tablet"
    for image, map_type in (("NX", "normal"), ("KD_R", "albedo")):
        plane = next(p for p in desc["layers"][0]["service"]["planes"]
                     if p["channels"][0] == image)
        name = plane["service"]["id"].rsplit("/", 1)[1]
        ext = desc["images"][name]["format"]
        got = pyvips.Image.new_from_file(str(out / "iiif" / name / "full/max/0" /
                                             f"default.{ext}"))
        np.testing.assert_array_equal(
            np.ndarray((got.height, got.width, got.bands), np.uint8, got.write_to_memory()),
            source[map_type])


@pytest.mark.parametrize("profile", [ANNEX_PROFILE, LIGHTINGMAP_PROFILE])
def test_import_accepts_both_profiles(tmp_path: Path, profile: str) -> None:
    source = write_dataset(tmp_path / "root")
    with lanterna_serve(tmp_path / "root") as (url, _):
        doc = json.loads(get(f"{url}/datasets/obj/manifest.json"))
        for item in choice_items(doc):
            for service in item["service"]:
                if service.get("type") == "LightingMapExtension":
                    service["profile"] = profile
        local = tmp_path / "m.json"
        local.write_text(json.dumps(doc))
        assert main(["import", str(local), "-o", str(tmp_path / "x")]) == 0
    desc = json.loads((tmp_path / "x" / "lanterna.json").read_text())
    plane = desc["layers"][0]["service"]["planes"][0]
    assert plane["channels"][0] == "NX"
    name = plane["service"]["id"].rsplit("/", 1)[1]
    ext = desc["images"][name]["format"]
    got = pyvips.Image.new_from_file(str(tmp_path / "x" / "iiif" / name / "full/max/0" /
                                         f"default.{ext}"))
    np.testing.assert_array_equal(
        np.ndarray((got.height, got.width, got.bands), np.uint8, got.write_to_memory()),
        source["normal"])
