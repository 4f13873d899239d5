"""The demo dataset's preset library and pixel size, and what its presets show."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np
import pytest

from lanterna.manifests.validate import validate_manifest
from lanterna.tiler.demo.dataset import build_demo
from lanterna.tiler.demo.presets import DEMO_PIXEL_MM, demo_presets
from lanterna.tiler.presets.library import check_library
from lanterna.tiler.render import level_channels, luma, render
from tests.python.fixtures.presets import read_json

SIZE = (384, 288)


@pytest.fixture(scope="module")
def demo(tmp_path_factory: pytest.TempPathFactory) -> Path:
    return build_demo(tmp_path_factory.mktemp("demo") / "demo", size=SIZE, force=True)


def _render(demo: Path, preset: dict[str, Any]) -> np.ndarray:
    desc = read_json(demo / "lanterna.json")
    layer = next(la["service"] for la in desc["layers"] if la["id"] == preset["layer"])
    rgb = render(layer, level_channels(demo, layer, 1), tuple(preset.get("light", (0, 0))),
                 preset["mode"], preset.get("params"))
    return np.asarray(luma(rgb))


def test_the_demo_ships_its_library_and_pixel_size(demo: Path) -> None:
    desc = read_json(demo / "lanterna.json")
    assert desc["presets"] == demo_presets(*SIZE) == read_json(demo / "presets.json")
    assert check_library(desc["presets"], desc) == desc["presets"]
    assert desc["pixelSizeMM"] == DEMO_PIXEL_MM
    manifest = read_json(demo / "manifest.json")
    assert validate_manifest(manifest) == []
    assert manifest["items"][0]["service"][0]["physicalScale"] == DEMO_PIXEL_MM
    assert len(manifest["service"][0]["base"]) >= 5 and len(manifest["service"][0]["lens"]) >= 3


def test_the_demo_manifest_says_what_a_portal_shows(demo: Path) -> None:
    manifest = read_json(demo / "manifest.json")
    assert manifest["rights"] == "http://creativecommons.org/publicdomain/zero/1.0/"
    attribution = manifest["requiredStatement"]["value"]["en"][0]
    assert "Synthetic" in attribution and "Lanterna" in attribution
    assert manifest["provider"][0]["label"] == {"en": ["The Lanterna project"]}
    assert any("not a real object" in m["value"]["en"][0] for m in manifest["metadata"])
    assert (demo / "iiif" / manifest["thumbnail"][0]["id"].split("/iiif/", 1)[1]).is_file()
    width, height = SIZE
    for anno in manifest["items"][0]["annotations"][0]["items"]:  # the overlay levels
        assert anno["motivation"] == "commenting"
        assert anno["target"]["selector"]["value"] != f"xywh=0,0,{width},{height}"


def test_every_preset_renders_and_its_views_scale_with_the_size() -> None:
    small, large = demo_presets(384, 288), demo_presets(1536, 1152)
    for pid, preset in large["presets"].items():
        if "view" in preset:
            assert [4 * v for v in small["presets"][pid]["view"]] == \
                pytest.approx(preset["view"], abs=4)


def test_raking_light_brings_out_the_inscription(demo: Path) -> None:
    lib = demo_presets(*SIZE)
    raking = lib["presets"]["raking-west"]
    x, y, w, h = raking["view"]
    overhead = {**raking, "light": [0.0, 0.0], "params": {}}

    def relief(img: np.ndarray) -> float:  # mean horizontal gradient in the view
        return float(np.abs(np.diff(img[y:y + h, x:x + w], axis=1)).mean())

    assert relief(_render(demo, raking)) > 1.5 * relief(_render(demo, overhead))


def test_the_infrared_lens_shows_what_the_visible_bands_do_not(demo: Path) -> None:
    lib = demo_presets(*SIZE)
    ir = _render(demo, lib["presets"]["infrared"])
    red = _render(demo, {"layer": "band_R", "mode": "color"})
    # the underdrawing's ruling lines: rows where IR dips below its neighbours but R does not
    row = int(0.55 * SIZE[1])
    cols = slice(int(0.3 * SIZE[0]), int(0.4 * SIZE[0]))

    def dip(img: np.ndarray) -> float:
        return float((img[row - 3, cols] + img[row + 3, cols]).mean() / 2 -
                     img[row, cols].mean())
    assert dip(ir) > 0.03 and abs(dip(red)) < 0.5 * dip(ir)
