"""The demo manifest in real Mirador 4 (the ready bundle's /viewer/mirador.html): relit as the
reference renders it.

The demo (built small) opens in a Mirador window; for its PTM, HSH and RBF layers, at two lights,
the frame our viewer draws at one image pixel per screen pixel matches the numpy reference renderer
(``tiler/render``) on the served level-0 tiles within 2/255 (the PTM layer's annotation overlays
hidden). The demo's manifest carries what a
portal shows (thumbnail, rights, attribution) and the lighting-map items; they must not stop it.
"""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from lanterna.tiler.demo.dataset import build_demo
from lanterna.tiler.render import level_channels, render
from tests.python.fixtures.page_script import evaluate, frame, run_page
from tests.python.fixtures.pixels import assert_pixels_close
from tests.python.fixtures.presets import read_json
from tests.python.fixtures.servers import LiveServer

pytestmark = pytest.mark.browser

SIZE = (256, 192)
LAYERS = ("ptm", "hsh", "rbf")
LIGHTS = [(-0.55, 0.25), (0.3, -0.5)]
TOLERANCE = 2
PAGE = (900, 700)


@pytest.fixture(scope="module")
def served(tmp_path_factory: pytest.TempPathFactory) -> Iterator[tuple[Path, str]]:
    root = tmp_path_factory.mktemp("mirador-demo")
    demo = build_demo(root / "demo", size=SIZE, force=True)
    server = LiveServer(root)
    try:
        yield demo, server.url
    finally:
        server.close()


@pytest.fixture(scope="module")
def frames(served: tuple[Path, str], tmp_path_factory: pytest.TempPathFactory) -> dict[str, Any]:
    _, url = served
    manifest = f"{url}/datasets/demo/manifest.json"
    shots = []
    for layer in LAYERS:
        for lu, lv in LIGHTS:
            shots.append(evaluate(f"""async () => {{
              const l = window.lv;
              await l.setActiveLayer('{layer}');
              l.setRenderMode('color');
              l.setOverlaysVisible(false); // the PTM layer's annotation drawings
              const {{ width, height }} = l.readPixels();
              l.showImageRegion(0, 0, width, height);
              l.setLight({lu}, {lv});
              await l.whenFullyLoaded();
              const {{ data }} = l.readPixels();
              let s = '';
              for (let k = 0; k < data.length; k += 0x8000) {{
                s += String.fromCharCode.apply(null, data.subarray(k, k + 0x8000));
              }}
              return {{ width, height, base64: btoa(s) }};
            }}"""))
    steps = [
        {"waitFor": """() => {
          const ids = Object.keys(window.miradorInstance?.store.getState().windows ?? {});
          return ids.length === 1 && window.Mirador.lanternaWindowViewer(ids[0])?.manifest;
        }"""},
        evaluate("""() => {
          const id = Object.keys(window.miradorInstance.store.getState().windows)[0];
          window.lv = window.Mirador.lanternaWindowViewer(id);
          return window.lv.getLayers().map((l) => l.id);
        }"""),
        *shots,
    ]
    result = run_page(f"{url}/viewer/mirador.html?manifest={manifest}", steps,
                      tmp_path_factory.mktemp("mirador-demo-page"), PAGE, routes=())
    values = result["values"]  # one per step: the wait, the layer ids, the frames
    return {"layers": values[1], "frames": values[2:]}


def test_the_demo_opens_in_mirador_with_its_layers(frames: dict[str, Any]) -> None:
    assert set(LAYERS) <= set(frames["layers"]), frames["layers"]


@pytest.mark.parametrize("layer", LAYERS)
def test_the_demo_layer_is_relit_as_the_reference_renders_it(
        served: tuple[Path, str], frames: dict[str, Any], layer: str) -> None:
    demo, _ = served
    desc = read_json(demo / "lanterna.json")
    block = next(la["service"] for la in desc["layers"] if la["id"] == layer)
    channels = level_channels(demo, block, 1)  # scale factor 1: full resolution
    width, height = SIZE
    got_by_light = []
    for k, light in enumerate(LIGHTS):
        got = frame(frames["frames"][LAYERS.index(layer) * len(LIGHTS) + k])
        assert got.shape[0] >= height and got.shape[1] >= width, got.shape
        part = got[:height, :width, :3].astype(np.int16)
        assert (got[:height, :width, 3] == 255).all(), f"{layer}: the image must be opaque"
        expected = np.round(np.clip(render(block, channels, light, "color"), 0, 1) * 255)
        assert_pixels_close(part, expected, TOLERANCE, f"{layer} light={light}")
        assert float(expected.std()) > 5, "the picture must not be flat"
        got_by_light.append(part)
    assert np.abs(got_by_light[0] - got_by_light[1]).mean() > 3, "the light must matter"
