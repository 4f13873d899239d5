"""Real Chromium: presets from the command line to the viewer and back (docs/presets.md).

`lanterna presets add` writes a library into a dataset; the advanced viewer reads the same library
from the manifest, and each entry gives the pixels its values give when set through the API. Then a
preset saved in the viewer goes back into the dataset through the real authoring API: a wrong token
writes nothing, the right one rewrites the dataset, and a new page sees the preset.
"""

from __future__ import annotations

import json
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from lanterna.cli import main
from lanterna.tiler.dataset.layers import add_image_layer, add_ptm_layer
from lanterna.tiler.dataset.plane_format import parse_plane_format
from lanterna.tiler.dataset.writer import DatasetWriter
from lanterna.tiler.iiif.pyramid import vips_from_array
from tests.python.fixtures.page_script import FRAME, READY, by_hand, evaluate, frame, run_page
from tests.python.fixtures.ptm import random_ptm_of_size
from tests.python.fixtures.servers import LiveServer

pytestmark = pytest.mark.browser

W, H = 256, 192
VIEW = (640, 480)
TOKEN = "a-long-enough-authoring-token"
ADD = [
    ["--id", "raking", "--label", "Raking", "--layer", "ptm", "--mode", "color",
     "--light=-0.9,0.1", "--param", "lightIntensity=1.3", "--base", "Raking light"],
    ["--id", "spec", "--label", "Specular", "--layer", "ptm", "--mode", "specular",
     "--param", "specKs=0.9", "--param", "specExponent=30", "--light", "0.3,0.5",
     "--view", "32,24,128,96", "--base", "Specular, detail"],
    ["--id", "band", "--label", "Band", "--layer", "band", "--mode", "achromatic",
     "--param", "gamma=1.4", "--lens", "The band", "--opacity", "0.7"],
]


@pytest.fixture(scope="module")
def root(tmp_path_factory: pytest.TempPathFactory) -> Path:
    root = tmp_path_factory.mktemp("presets")
    rng = np.random.default_rng(3)
    with DatasetWriter(root / "obj", name="obj", label="Object", width=W, height=H) as ds:
        add_ptm_layer(ds, random_ptm_of_size(W, H), layer_id="ptm",
                      plane_format=parse_plane_format("png"))
        band = vips_from_array(rng.integers(0, 256, (H, W, 3), dtype=np.uint8))
        add_image_layer(ds, band.copy(interpretation="srgb"), layer_id="band", fmt="png")
    for args in ADD:
        assert main(["presets", "add", str(root / "obj"), *args]) == 0
    return root


@pytest.fixture(scope="module")
def server(root: Path) -> Iterator[LiveServer]:
    live = LiveServer(root, {"AUTHORING_TOKEN": TOKEN})
    try:
        yield live
    finally:
        live.close()


def page(server: LiveServer) -> str:
    manifest = f"{server.url}/datasets/obj/manifest.json"
    return f"{server.url}/viewer/?manifest={manifest}&minPixelRatio=0.75"


def test_the_cli_library_reaches_the_viewer_and_gives_the_pixels_of_its_values(
        root: Path, server: LiveServer, tmp_path: Path) -> None:
    library = json.loads((root / "obj" / "presets.json").read_text())
    manifest = json.loads((root / "obj" / "manifest.json").read_text())
    block = next(s for s in manifest["service"] if s["type"] == "LanternaPresets")
    assert {k: block[k] for k in ("presets", "base", "lens")} == {
        k: library[k] for k in ("presets", "base", "lens")}
    steps: list[dict[str, Any]] = [READY, evaluate("() => window.lanterna.getPresetLibrary()")]
    for target in ("base", "lens"):
        for k, entry in enumerate(library[target]):
            preset = library["presets"][entry["preset"]]
            steps += [evaluate(f"() => window.lanterna.applyPreset('{target}', {k})"), FRAME,
                      by_hand(target, preset, entry.get("opacity", 1)), FRAME]
    values = run_page(page(server), steps, tmp_path, VIEW)["values"]
    seen = values[1]
    assert {k: seen[k] for k in ("presets", "base", "lens")} == {
        k: library[k] for k in ("presets", "base", "lens")}
    frames = [frame(v) for v in values[2:] if isinstance(v, dict) and "base64" in v]
    assert len(frames) == 2 * (len(library["base"]) + len(library["lens"]))
    for k in range(0, len(frames), 2):
        assert np.array_equal(frames[k], frames[k + 1]), f"entry {k // 2}"
    assert not np.array_equal(frames[0], frames[2])  # the presets differ


STATUS = "document.querySelector('.lanterna-presets-status').textContent"


def test_a_preset_saved_in_the_viewer_goes_into_the_dataset_with_the_token_only(
        root: Path, server: LiveServer, tmp_path: Path) -> None:
    before = {name: (root / "obj" / name).read_bytes()
              for name in ("presets.json", "manifest.json", "lanterna.json")}
    steps: list[dict[str, Any]] = [
        READY,
        {"select": "select[name=mode]", "value": "specular"},
        {"click": "button[name=light-west]"},
        {"fill": "input[name=preset-name]", "value": "Saved in the viewer"},
        {"click": "button[name=preset-save]"},
        {"waitFor": "() => !document.querySelector('.lanterna-dataset-save').hidden"},
        {"click": "button[name=presets-save-dataset]"},
        {"fill": "input[name=authoring-token]", "value": "not-the-token-at-all"},
        {"click": "button[name=presets-send-token]"},
        {"waitFor": f"() => {STATUS}.includes('401')"},
        evaluate(f"() => {STATUS}"),
    ]
    found = run_page(page(server), steps, tmp_path / "wrong", VIEW, routes=(),
                     allow_console_errors=["401"])
    assert "401" in found["values"][-1]
    after = {name: (root / "obj" / name).read_bytes() for name in before}
    assert after == before, "a refused save wrote nothing"

    steps[7] = {"fill": "input[name=authoring-token]", "value": TOKEN}
    steps[9] = {"waitFor": f"() => {STATUS}.startsWith('Saved to the dataset')"}
    found = run_page(page(server), steps, tmp_path / "right", VIEW, routes=())
    assert found["values"][-1].startswith('Saved to the dataset "obj"')
    library = json.loads((root / "obj" / "presets.json").read_text())
    saved = [p for p in library["presets"].values() if p["label"] == "Saved in the viewer"]
    assert len(saved) == 1 and saved[0]["mode"] == "specular" and saved[0]["layer"] == "ptm"
    assert saved[0]["light"][0] < -0.9  # raking from the west
    assert {p for p in library["presets"]} >= {"raking", "spec", "band"}  # nothing lost
    manifest = json.loads((root / "obj" / "manifest.json").read_text())
    block = next(s for s in manifest["service"] if s["type"] == "LanternaPresets")
    assert block["presets"] == library["presets"]

    reopened = run_page(page(server), [READY, evaluate("() => window.lanterna.getPresetLibrary()")],
                        tmp_path / "reopened", VIEW)["values"][1]
    assert reopened["presets"] == library["presets"] and reopened["base"] == library["base"]
