"""The seed paper's scene ``overlay`` entry: level images become overlay levels with their texts."""

from __future__ import annotations

import json
import logging
from pathlib import Path

import numpy as np
import pytest

from lanterna.cli import main
from tests.python.fixtures.overlays import read_image
from tests.python.fixtures.sources import png

W, H = 520, 300  # tile 256 → levels 0–2


def scene(tmp_path: Path, overlay: dict[str, object]) -> Path:
    """Write a one-layer SVBRDF scene (a flat normal map) with ``overlay``."""
    (tmp_path / "maps").mkdir()
    normals = np.zeros((H, W, 3), np.uint8)
    normals[...] = (128, 128, 255)
    png(tmp_path / "maps/N00.png", normals)
    doc = {"name": "Scene", "width": W, "height": H,
           "layers": [{"id": "VIS", "name": "Visible",
                       "obj": {"shader": {"type": "SVBRDF"}, "maps": {"N": "maps/N.png"}},
                       "overlay": overlay}]}
    path = tmp_path / "scene.json"
    path.write_text(json.dumps(doc))
    return path


def test_scene_overlay_levels_become_overlay_images(tmp_path: Path,
                                                    caplog: pytest.LogCaptureFixture) -> None:
    (tmp_path / "ov").mkdir()
    level1 = np.zeros((150, 260, 4), np.uint8)
    level1[10:20, 30:60] = (255, 0, 0, 200)
    png(tmp_path / "ov/overlay01.png", level1)
    path = scene(tmp_path, {"img": "ov/overlay.png", "range": [1, 3],
                            "shortInfo": ["one", "two", "three"],
                            "longInfo": ["<p>1</p>", "<p>2</p>", "<p>3</p>"]})
    out = tmp_path / "out"
    with caplog.at_level(logging.WARNING, logger="lanterna.overlays"):
        assert main(["import", str(path), "-o", str(out)]) == 0
    warnings = [r.getMessage() for r in caplog.records]
    assert any("overlay02.png: missing: this overlay level has texts only" in w for w in warnings)
    assert any("overlay range [1, 3] is clamped to the pyramid's levels 0–2" in w
               for w in warnings)
    desc = json.loads((out / "lanterna.json").read_text())
    overlay = desc["layers"][0]["overlay"]
    assert overlay["levels"] == [{"level": 1, "image": "VIS_ov1", "width": 260, "height": 150,
                                  "short": "one", "long": "<p>1</p>",
                                  "box": [60, 20, 60, 20]}]  # level-1 pixels 30:60, 10:20
    assert overlay["shortInfo"] == ["one", "two", "three"]  # the scene's texts are all kept
    assert overlay["range"] == [1, 3] and overlay["source"] == "scene"
    np.testing.assert_array_equal(read_image(out, "VIS_ov1"), level1)
    m = json.loads((out / "manifest.json").read_text())
    (page,) = m["items"][0]["annotations"]
    (anno,) = page["items"]
    assert anno["label"] == {"en": ["one"]}
    assert anno["target"]["selector"]["value"] == "xywh=60,20,60,20"
    assert anno["body"][0]["service"][1]["level"] == 1
    assert [b["value"] for b in anno["body"][1:]] == ["one", "<p>1</p>"]  # short, long


def test_scene_without_overlay_images_still_imports(tmp_path: Path,
                                                    caplog: pytest.LogCaptureFixture) -> None:
    path = scene(tmp_path, {"img": "ov/overlay.png", "range": [0, 1], "shortInfo": ["a", "b"]})
    out = tmp_path / "out"
    with caplog.at_level(logging.WARNING, logger="lanterna.overlays"):
        assert main(["import", str(path), "-o", str(out)]) == 0
    assert len(caplog.records) == 2
    desc = json.loads((out / "lanterna.json").read_text())
    overlay = desc["layers"][0]["overlay"]
    assert overlay["levels"] == [] and overlay["shortInfo"] == ["a", "b"]
    assert "annotations" not in json.loads((out / "manifest.json").read_text())["items"][0]


def test_a_huge_range_is_clamped_to_the_pyramid_levels(tmp_path: Path,
                                                       caplog: pytest.LogCaptureFixture) -> None:
    """``range: [0, 1e9]`` tries the pyramid's levels only (it used to loop a billion times)."""
    path = scene(tmp_path, {"img": "ov/overlay.png", "range": [0, 1_000_000_000]})
    out = tmp_path / "ds"
    with caplog.at_level(logging.WARNING, logger="lanterna.overlays"):
        assert main(["import", str(path), "-o", str(out)]) == 0
    warnings = [r.getMessage() for r in caplog.records]
    assert len(warnings) <= 4, warnings  # the clamp, and one per missing level 0-2
    assert any("clamped to the pyramid's levels 0–2" in w for w in warnings)
