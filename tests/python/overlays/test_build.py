"""End to end: a folder of RGBA PNG patches → overlay pyramids, lanterna.json, manifest, server."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
import pyvips
from flask.testing import FlaskClient

from lanterna.cli import main
from lanterna.server.app import create_app
from lanterna.tiler.overlays.build import build_overlays
from tests.python.fixtures.overlays import BASE, H, W, make_dataset, patch, read_image
from tests.python.fixtures.publishing import leftovers
from tests.python.fixtures.sources import png

PATCHES = {
    "0_100_50_40_30_1_red stroke.png": patch(30, 40, (255, 0, 0), 160, 1),
    "0_120_60_40_30_2_blue_box.png": patch(30, 40, (0, 0, 255), 200, 2),
    "0_90_45_20_20_0_under.png": patch(20, 20, (0, 255, 0), 255, 3),
    "0_580_380_40_40_3_corner.png": patch(40, 40, (255, 255, 0), 230, 4),  # clipped
    "2_300_200_64_64_0_tower.png": patch(16, 16, (10, 200, 30), 220, 5),
}
TEXTS = {"0": {"short": "Strokes", "long": "<p>Red <b>strokes</b></p>"},
         "2": {"short": "Tower", "long": "<p>The tower</p>"}}


def reference_level0() -> np.ndarray:
    """Composite the level-0 patches with the straight-alpha source-over formula."""
    colour = np.zeros((H, W, 3))
    alpha = np.zeros((H, W, 1))
    for name in ["0_90_45_20_20_0_under.png", "0_100_50_40_30_1_red stroke.png",
                 "0_120_60_40_30_2_blue_box.png", "0_580_380_40_40_3_corner.png"]:
        _, x, y, w, h = (int(v) for v in name.split("_")[:5])
        src = PATCHES[name][: H - y, : W - x].astype(np.float64) / 255
        ys, xs = slice(y, min(y + h, H)), slice(x, min(x + w, W))
        a_s, a_d = src[..., 3:], alpha[ys, xs]
        a_o = a_s + a_d * (1 - a_s)
        c_o = src[..., :3] * a_s + colour[ys, xs] * a_d * (1 - a_s)
        colour[ys, xs] = np.divide(c_o, a_o, out=np.zeros_like(c_o), where=a_o > 0)
        alpha[ys, xs] = a_o
    return np.rint(np.concatenate([colour, alpha], -1) * 255).astype(np.uint8)


@pytest.fixture(scope="module")
def built(tmp_path_factory: pytest.TempPathFactory) -> Path:
    root = tmp_path_factory.mktemp("ov")
    dataset = make_dataset(root / "root")
    folder = root / "patches"
    folder.mkdir()
    for name, array in PATCHES.items():
        png(folder / name, array)
    (root / "texts.json").write_text(json.dumps(TEXTS))
    assert main(["annotate", "build", str(dataset), "--layer", "vis", "--patches", str(folder),
                 "--texts", str(root / "texts.json")]) == 0
    return dataset


def test_level_images_equal_a_numpy_composite(built: Path) -> None:
    level0 = read_image(built, "vis_ov0")
    assert level0.shape == (H, W, 4)
    np.testing.assert_array_equal(level0, reference_level0())
    # the blue box (order 2) wins over the red stroke (order 1) where it is opaque enough
    assert level0[70, 130, 2] > level0[70, 130, 0]
    level2 = read_image(built, "vis_ov2")
    assert level2.shape == (100, 150, 4)  # ceil(600/4) × ceil(400/4)
    np.testing.assert_array_equal(level2[50:66, 75:91], PATCHES["2_300_200_64_64_0_tower.png"])
    assert level2[..., 3].sum() == PATCHES["2_300_200_64_64_0_tower.png"][..., 3].sum()


def test_levels_without_patches_have_no_image(built: Path) -> None:
    assert not (built / "iiif/vis_ov1").exists()
    desc = json.loads((built / "lanterna.json").read_text())
    assert [e["level"] for e in desc["layers"][0]["overlay"]["levels"]] == [0, 2]
    assert "overlay" not in desc["layers"][1]


def test_level_images_are_iiif_pyramids(built: Path) -> None:
    info = json.loads((built / "iiif/vis_ov0/info.json").read_text())
    assert info["id"] == f"{BASE}/obj/iiif/vis_ov0"
    assert (info["width"], info["height"]) == (W, H)
    assert info["tiles"][0]["scaleFactors"] == [1, 2, 4]
    assert info["preferredFormats"] == ["png"]
    tile = pyvips.Image.new_from_file(str(built / "iiif/vis_ov0/0,0,256,256/256,256/0/default.png"))
    assert tile.bands == 4  # alpha kept
    info2 = json.loads((built / "iiif/vis_ov2/info.json").read_text())
    assert (info2["width"], info2["height"]) == (150, 100)
    assert (built / "iiif/vis_ov2/full/max/0/default.jpg").is_file()


def test_lanterna_json_keeps_levels_texts_and_patches(built: Path) -> None:
    desc = json.loads((built / "lanterna.json").read_text())
    overlay = desc["layers"][0]["overlay"]
    assert overlay["source"] == "store" and overlay["build"] == 1
    assert len(overlay["fingerprint"]) == 64
    assert overlay["levels"] == [
        {"level": 0, "image": "vis_ov0", "width": W, "height": H, "short": "Strokes",
         "long": "<p>Red <b>strokes</b></p>", "box": drawn_extent(reference_level0())},
        {"level": 2, "image": "vis_ov2", "width": 150, "height": 100, "short": "Tower",
         "long": "<p>The tower</p>", "box": [300, 200, 64, 64]}]  # the tower patch's rectangle
    assert [p["file"] for p in overlay["patches"]] == [
        "0_90_45_20_20_0_under.png", "0_100_50_40_30_1_red stroke.png",
        "0_120_60_40_30_2_blue_box.png", "0_580_380_40_40_3_corner.png",
        "2_300_200_64_64_0_tower.png"]
    record = overlay["patches"][2]
    assert record == {"type": "LanternaPatch", "version": 1, "id": "0_120_60_40_30_2_blue_box",
                      "layer": "vis", "level": 0, "x": 120, "y": 60, "w": 40, "h": 30,
                      "order": 2, "info": "blue_box", "author": "", "created": record["created"],
                      "modified": record["created"], "short": "", "long": "",
                      "motivation": "commenting", "state": None,
                      "file": "0_120_60_40_30_2_blue_box.png", "width": 40, "height": 30}
    assert record["created"].endswith("Z")
    # the published patch files, one per record, equal to the patches
    for name, array in PATCHES.items():
        stored = pyvips.Image.new_from_file(str(built / "annotations/vis" / name)).numpy()
        np.testing.assert_array_equal(stored, array)
    assert desc["images"]["vis_ov2"] == {"format": "png", "width": 150, "height": 100, "bands": 4}
    # the layer's relight service document is not touched by the overlay
    assert "overlay" not in json.loads((built / "layers/vis.json").read_text())


def drawn_extent(rgba: np.ndarray) -> list[int]:
    """[x, y, w, h] of the pixels with some alpha (level 0: canvas pixels)."""
    ys, xs = np.nonzero(rgba[..., 3])
    return [int(xs.min()), int(ys.min()), int(xs.max() - xs.min() + 1),
            int(ys.max() - ys.min() + 1)]


def test_level_boxes_cover_the_patches_and_are_clipped_to_the_canvas() -> None:
    # the level-0 patches span x 90..620, y 45..420 on the 600x400 canvas (the corner is clipped)
    assert drawn_extent(reference_level0()) == [90, 45, W - 90, H - 45]


def test_manifest_has_one_commenting_page_per_annotated_layer(built: Path) -> None:
    m = json.loads((built / "manifest.json").read_text())
    canvas = m["items"][0]
    assert canvas["items"][0]["items"][0]["body"]["type"] == "Choice"  # painting unchanged
    page, notes = canvas["annotations"]  # the level overlay, then the patches' W3C page
    assert notes == {"id": f"{BASE}/obj/annotations/vis.json", "type": "AnnotationPage",
                     "label": {"en": ["Notes: VIS"]}}
    assert page["id"] == f"{BASE}/obj/canvas/1/overlays/vis"
    assert page["type"] == "AnnotationPage" and page["label"] == {"en": ["Annotations: VIS"]}
    first, second = page["items"]
    assert first["type"] == "Annotation" and first["motivation"] == "commenting"
    assert first["label"] == {"en": ["Strokes"]}
    assert first["target"] == {
        "type": "SpecificResource", "source": {"id": canvas["id"], "type": "Canvas"},
        "selector": {"type": "FragmentSelector", "conformsTo": "http://www.w3.org/TR/media-frags/",
                     "value": f"xywh=90,45,{W - 90},{H - 45}"}}  # the level's drawing
    assert second["target"]["selector"]["value"] == "xywh=300,200,64,64"
    image, short, text = first["body"]
    assert short == {"id": f"{first['id']}/short", "type": "TextualBody", "value": "Strokes",
                     "format": "text/plain", "purpose": "commenting"}
    info = json.loads((built / "iiif/vis_ov0/info.json").read_text())
    assert image == {
        "id": f"{BASE}/obj/iiif/vis_ov0/full/max/0/default.png", "type": "Image",
        "format": "image/png", "width": W, "height": H,
        "service": [
            {"id": f"{BASE}/obj/iiif/vis_ov0", "type": "ImageService3", "profile": "level0",
             "width": W, "height": H, "sizes": info["sizes"], "tiles": info["tiles"],
             "preferredFormats": ["png"], "extraFormats": ["png"]},
            {"id": f"{BASE}/obj/layers/vis.json#overlay-0", "type": "LanternaOverlayLevel",
             "profile": "urn:lanterna:overlay:1", "layer": "vis", "level": 0,
             "short": "Strokes", "long": "<p>Red <b>strokes</b></p>"}]}
    assert text["type"] == "TextualBody" and text["format"] == "text/html"
    assert text["purpose"] == "describing" and text["value"] == "<p>Red <b>strokes</b></p>"
    assert second["body"][0]["service"][1]["level"] == 2
    assert (second["body"][0]["width"], second["body"][0]["height"]) == (150, 100)


@pytest.fixture
def client(built: Path) -> FlaskClient:
    return create_app({"DATA_ROOT": built.parent}).test_client()


def test_server_serves_overlay_tiles_with_rewritten_ids(client: FlaskClient) -> None:
    info = client.get("/datasets/obj/iiif/vis_ov2/info.json").get_json()
    assert info["id"] == "http://localhost/datasets/obj/iiif/vis_ov2"
    text = client.get("/datasets/obj/manifest.json").get_data(as_text=True)
    assert BASE not in text
    anno = json.loads(text)["items"][0]["annotations"][0]["items"][1]
    image = anno["body"][0]
    assert image["service"][0]["id"] == "http://localhost/datasets/obj/iiif/vis_ov2"
    assert image["service"][1]["id"] == "http://localhost/datasets/obj/layers/vis.json#overlay-2"
    with client.get("/datasets/obj/iiif/vis_ov2/full/max/0/default.png") as resp:
        assert resp.status_code == 200 and resp.mimetype == "image/png"
        served = pyvips.Image.new_from_buffer(resp.data, "")
        assert (served.width, served.height, served.bands) == (150, 100, 4)


def test_annotate_list(built: Path, capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["annotate", "list", str(built)]) == 0
    out = capsys.readouterr().out.splitlines()
    assert out == ["vis: 2 level(s), 5 patch(es) (from store)",
                   "  level 0  600x400  Strokes (long text)",
                   "  level 2  150x100  Tower (long text)",
                   "uv: no overlay"]


def test_replace_empties_the_store_and_old_images_go_a_build_later(tmp_path: Path) -> None:
    dataset = make_dataset(tmp_path)
    first, second = tmp_path / "a", tmp_path / "b"
    first.mkdir()
    second.mkdir()
    png(first / "0_0_0_10_10_0_a.png", patch(10, 10, (255, 0, 0), 255))
    png(first / "2_0_0_40_40_0_b.png", patch(10, 10, (255, 0, 0), 255))
    png(second / "1_0_0_20_20_0_c.png", patch(10, 10, (0, 0, 255), 255))
    png(second / "2_0_0_8_8_0_d.png", patch(2, 2, (0, 0, 255), 255))
    tile = dataset / "iiif/vis/0,0,256,256/256,256/0/default.png"
    inode = tile.stat().st_ino
    build_overlays(dataset, "vis", patches_dir=first, texts={"2": {"short": "kept"}})
    report = build_overlays(dataset, "vis", patches_dir=second, replace=True)
    assert report.levels == [1, 2] and report.patches == 2 and report.errors == []
    assert report.build == 2
    assert (dataset / "iiif/vis_ov1_b2/info.json").is_file()
    desc = json.loads((dataset / "lanterna.json").read_text())
    assert {"vis_ov1_b2", "vis_ov2_b2"} <= set(desc["images"])
    assert not {"vis_ov0", "vis_ov2", "vis_ov1"} & set(desc["images"])
    levels = desc["layers"][0]["overlay"]["levels"]
    assert [(e["level"], e["image"], e["short"]) for e in levels] == [
        (1, "vis_ov1_b2", ""), (2, "vis_ov2_b2", "kept")]
    assert read_image(dataset, "vis_ov2_b2")[0, 0].tolist() == [0, 0, 255, 255]
    assert sorted(p.name for p in (dataset / "annotations/vis").glob("*.png")) == [
        "1_0_0_20_20_0_c.png", "2_0_0_8_8_0_d.png"]
    # the previous build's images stay (unlisted) for one more version, then go
    assert (dataset / "iiif/vis_ov0/info.json").is_file()
    assert build_overlays(dataset, "vis", patches_dir=first).build == 3  # adds: a, b, c, d
    assert not (dataset / "iiif/vis_ov0").exists() and not (dataset / "iiif/vis_ov2").exists()
    assert (dataset / "iiif/vis_ov2_b2").is_dir() and (dataset / "iiif/vis_ov2_b3").is_dir()
    overlay = json.loads((dataset / "lanterna.json").read_text())["layers"][0]["overlay"]
    assert [p["id"] for p in overlay["patches"]] == [
        "0_0_0_10_10_0_a", "1_0_0_20_20_0_c", "2_0_0_40_40_0_b", "2_0_0_8_8_0_d"]
    assert tile.stat().st_ino == inode  # unchanged tiles are hard-linked, not copied
    assert leftovers(tmp_path) == ["a", "b", "obj", "obj.annotations"]


def test_gimp_levels_are_used_as_drawn(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    dataset = make_dataset(tmp_path)
    folder = tmp_path / "gimp"
    folder.mkdir()
    level1 = patch(200, 300, (200, 100, 50), 120, 7)
    full = patch(H, W, (0, 0, 255), 255, 8)  # a level-2 drawing at canvas size: downscaled
    png(folder / "level_1.png", level1)
    png(folder / "2.png", full)
    png(folder / "level_02.png", full)  # level 2 twice
    png(folder / "0.png", patch(10, 10, (0, 0, 0), 255))  # wrong size
    (tmp_path / "t.json").write_text(json.dumps({"1": {"short": "one"}, "0": {"short": "x"}}))
    assert main(["annotate", "build", str(dataset), "--layer", "uv", "--gimp", str(folder),
                 "--texts", str(tmp_path / "t.json")]) == 1
    err = capsys.readouterr().err
    assert f"{folder}/0.png: is 10x10; level 0 of the 600x400 canvas is 600x400" in err
    assert f"{folder}/level_02.png: level 2 is also given by 2.png" in err
    assert "texts for level 0 ignored: no overlay image at that level" in err
    np.testing.assert_array_equal(read_image(dataset, "uv_ov1"), level1)
    level2 = read_image(dataset, "uv_ov2")
    assert level2.shape == (100, 150, 4) and np.all(level2[..., 2] == 255)
    desc = json.loads((dataset / "lanterna.json").read_text())
    overlay = desc["layers"][1]["overlay"]
    assert overlay["source"] == "store"
    assert [p["id"] for p in overlay["patches"]] == ["1_0_0_600_400_0_level",
                                                     "2_0_0_600_400_0_level"]
    assert [(e["level"], e["short"]) for e in overlay["levels"]] == [(1, "one"), (2, "")]
