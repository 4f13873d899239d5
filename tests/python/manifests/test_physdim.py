"""The physical scale: ``--pixel-size`` (or Relight's ``pixelSizeInMM``) → ``pixelSizeMM`` →
a physdim service on the canvas, accepted by the Presentation 3 schema."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from PIL import Image

from lanterna.cli import main
from lanterna.manifests.build import build_manifest
from lanterna.manifests.extensions import PHYSDIM_PROFILE
from lanterna.manifests.validate import validate_manifest
from tests.python.fixtures.photos import (
    bumpy_normals,
    render_bumpy,
    spiral_lights,
    write_collection,
)
from tests.python.fixtures.presets import read_json
from tests.python.formats.test_relight_web import info_json, random_planes, write_folder


@pytest.fixture
def image(tmp_path: Path) -> Path:
    path = tmp_path / "vis.png"
    Image.fromarray(np.random.default_rng(1).integers(0, 256, (30, 40, 3), np.uint8)).save(path)
    return path


def _physdim(dataset: Path) -> list[dict[str, object]]:
    manifest = read_json(dataset / "manifest.json")
    assert validate_manifest(manifest) == []
    services: list[dict[str, object]] = manifest["items"][0].get("service", [])
    return services


def test_import_with_a_pixel_size_gives_the_canvas_a_physdim_service(image: Path,
                                                                      tmp_path: Path) -> None:
    out = tmp_path / "obj"
    assert main(["import", str(image), "--pixel-size", "0.0254", "-o", str(out)]) == 0
    assert read_json(out / "lanterna.json")["pixelSizeMM"] == 0.0254
    assert _physdim(out) == [{
        "@context": "http://iiif.io/api/annex/services/physdim/1/context.json",
        "id": "http://127.0.0.1:8000/datasets/obj/canvas/1/physdim",
        "type": "PhysicalDimensions", "profile": PHYSDIM_PROFILE,
        "physicalScale": 0.0254, "physicalUnits": "mm"}]


def test_without_a_pixel_size_there_is_no_physdim_service(image: Path, tmp_path: Path) -> None:
    out = tmp_path / "obj"
    assert main(["import", str(image), "-o", str(out)]) == 0
    assert "pixelSizeMM" not in read_json(out / "lanterna.json")
    assert _physdim(out) == []


@pytest.mark.parametrize("value", ["0", "-0.1", "nan", "inf", "mm"])
def test_a_bad_pixel_size_is_refused(image: Path, tmp_path: Path, value: str,
                                     capsys: pytest.CaptureFixture[str]) -> None:
    with pytest.raises(SystemExit) as exit_:
        main(["import", str(image), f"--pixel-size={value}", "-o", str(tmp_path / "obj")])
    assert exit_.value.code == 2
    assert "not a positive number of millimetres" in capsys.readouterr().err
    assert not (tmp_path / "obj").exists()


def _relight(folder: Path, pixel_mm: float | None) -> Path:
    planes, scale, bias = random_planes(9)
    info = info_json("ptm", "lrgb", 9, scale, bias)
    if pixel_mm is not None:
        info["pixelSizeInMM"] = pixel_mm
    write_folder(folder, info, planes)
    return folder


def test_a_relight_pixel_size_is_used_unless_one_is_given(tmp_path: Path) -> None:
    source = _relight(tmp_path / "rti", 0.08)
    assert main(["import", str(source), "-o", str(tmp_path / "a")]) == 0
    assert read_json(tmp_path / "a" / "lanterna.json")["pixelSizeMM"] == 0.08
    assert _physdim(tmp_path / "a")[0]["physicalScale"] == 0.08
    assert main(["import", str(source), "--pixel-size", "0.1", "-o", str(tmp_path / "b")]) == 0
    assert _physdim(tmp_path / "b")[0]["physicalScale"] == 0.1


def test_a_bad_relight_pixel_size_names_the_file(tmp_path: Path,
                                                 capsys: pytest.CaptureFixture[str]) -> None:
    source = _relight(tmp_path / "rti", None)
    info = json.loads((source / "info.json").read_text())
    (source / "info.json").write_text(json.dumps({**info, "pixelSizeInMM": -1}))
    assert main(["import", str(source), "-o", str(tmp_path / "a")]) == 2
    err = capsys.readouterr().err
    assert err.startswith(f"lanterna: error: {source / 'info.json'}: pixelSizeInMM: expected a "
                          "positive number of millimetres")


def test_the_service_passes_the_schema_beside_presets_and_overlays() -> None:
    desc = {"baseUrl": "https://example.org/d", "name": "x", "label": "X", "width": 10,
            "height": 8, "pixelSizeMM": 0.5,
            "images": {"i": {"width": 10, "height": 8}},
            "layers": [{"id": "i", "label": "I", "body": "i",
                        "service": {"id": "https://example.org/d/x/layers/i.json",
                                    "type": "LanternaRelight", "layerType": "image",
                                    "planes": []}}],
            "presets": {"type": "LanternaPresets", "version": 1, "label": "Mine",
                        "presets": {"p": {"label": "P", "layer": "i", "mode": "color"}},
                        "base": [{"label": "P", "preset": "p"}], "lens": []}}
    manifest = build_manifest(desc)  # raises if the schema refuses it
    assert manifest["items"][0]["service"][0]["physicalScale"] == 0.5
    assert manifest["service"][0]["id"] == "https://example.org/d/x/presets.json"


def test_fit_takes_a_pixel_size_too(tmp_path: Path) -> None:
    lights = spiral_lights()
    lp = write_collection(tmp_path / "shots", render_bumpy(bumpy_normals(), lights), lights,
                          depth=8)
    out = tmp_path / "ds"
    assert main(["fit", str(tmp_path / "shots"), "--lp", str(lp), "--model", "ptm", "--quiet",
                 "--pixel-size", "0.2", "-o", str(out)]) == 0
    assert read_json(out / "lanterna.json")["pixelSizeMM"] == 0.2
    assert _physdim(out)[0]["physicalScale"] == 0.2
