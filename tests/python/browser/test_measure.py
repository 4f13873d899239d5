"""Real Chromium: the measurement mode's values and plots equal the numpy model, and its input.

One dataset with lossless (PNG) planes holds a layer of every type (PTM lrgb and rgb, HSH, shape +
material with linear and sRGB maps, RGB and grey images). The page measures three pixels per layer
(``window.lanternaMeasure.measure``, tests/browser/measure.mjs); each pixel's dequantised values
must equal what :func:`lanterna.tiler.render.level_channels` reads from the stored tiles, and its
plot what :mod:`lanterna.tiler.render.measure` computes from those values. Then a one-finger drag
in measure mode must leave the light and the view alone and show the widget.
"""

from __future__ import annotations

import json
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import numpy as np
import numpy.typing as npt
import pytest

from lanterna.tiler.dataset.layers import (
    add_hsh_layer,
    add_image_layer,
    add_ptm_layer,
    add_svbrdf_layer,
)
from lanterna.tiler.dataset.plane_format import parse_plane_format
from lanterna.tiler.dataset.writer import DatasetWriter
from lanterna.tiler.formats.hsh_model import Hsh
from lanterna.tiler.formats.layouts import encode_normals
from lanterna.tiler.iiif.pyramid import vips_from_array
from lanterna.tiler.render import level_channels
from lanterna.tiler.render.measure import (
    DISK_SIZE,
    SLICE_SIZE,
    material_slice,
    reflectance_disk,
    swatch,
)
from tests.python.fixtures import browser
from tests.python.fixtures.paths import REPO
from tests.python.fixtures.ptm import random_ptm_of_size
from tests.python.fixtures.servers import LiveServer

pytestmark = pytest.mark.browser

W, H, TILE = 96, 64, 64  # two tiles across
VIEW = (400, 300)
SCALE = VIEW[0] / W  # the whole image fitted: 1 image px = 4.17 CSS px, centred vertically
TOP = (VIEW[1] - H * SCALE) / 2
PIXELS = [(5, 7), (70, 30), (95, 63)]  # both tiles, the last pixel
LIGHT = (0.3, 0.2)
PNG = parse_plane_format("png")


def build(out: Path) -> dict[str, dict[str, Any]]:
    """Write the dataset; return each layer's relight service block by id."""
    rng = np.random.default_rng(13)
    n = rng.normal(0, 0.4, (H, W, 3))
    n[..., 2] = 1
    n /= np.linalg.norm(n, axis=-1, keepdims=True)
    maps = {"normals": encode_normals(n), "kd": rng.integers(0, 256, (H, W, 3), dtype=np.uint8),
            "ks": rng.integers(0, 256, (H, W, 3), dtype=np.uint8),
            "gloss": rng.integers(0, 256, (H, W), dtype=np.uint8)}
    hsh = Hsh(rng.integers(0, 256, (H, W, 3, 9), dtype=np.uint8),
              rng.uniform(0.3, 2.0, 9).astype(np.float32),
              rng.uniform(-1, 0.2, 9).astype(np.float32))
    blocks: dict[str, dict[str, Any]] = {}
    with DatasetWriter(out, name="measure", label="Measure", width=W, height=H,
                       tile_size=TILE) as ds:
        for cs in ("lrgb", "rgb"):
            blocks[f"ptm_{cs}"] = add_ptm_layer(ds, random_ptm_of_size(W, H, cs, seed=len(cs)),
                                                layer_id=f"ptm_{cs}", plane_format=PNG)
        blocks["hsh"] = add_hsh_layer(ds, hsh, layer_id="hsh", plane_format=PNG)
        for space in ("linear", "srgb"):
            blocks[f"sv_{space}"] = add_svbrdf_layer(
                ds, **maps, gloss_limits=(0.05, 0.45), input_colorspace=space,
                layer_id=f"sv_{space}", plane_format=PNG, share={"normals": "n"})
        rgb = vips_from_array(rng.integers(0, 256, (H, W, 3), dtype=np.uint8))
        grey = vips_from_array(rng.integers(0, 256, (H, W), dtype=np.uint8))
        blocks["rgb"] = add_image_layer(ds, rgb.copy(interpretation="srgb"), layer_id="rgb",
                                        fmt="png")
        blocks["grey"] = add_image_layer(ds, grey.copy(interpretation="b-w"), layer_id="grey",
                                         fmt="png")
    return blocks


def css_of(px: int, py: int) -> list[float]:
    """The CSS point at the centre of image pixel (px, py) with the whole image fitted."""
    return [(px + 0.5) * SCALE, TOP + (py + 0.5) * SCALE]


PARAMS = {"ptm_lrgb": {"lightIntensity": 1.5}}
# left of the page's panel (x > 142 at this width), not on a pixel edge
GESTURE = {"type": "touch", "from": [[20, 150]], "to": [[130, 122]]}
HOVER = [100, 200]


@pytest.fixture(scope="module")
def run(tmp_path_factory: pytest.TempPathFactory) -> Iterator[tuple[Path, dict[str, Any],
                                                                     dict[str, Any]]]:
    """Build, measure in Chromium; yield (dataset, layer blocks, result)."""
    tmp = tmp_path_factory.mktemp("measure")
    blocks = build(tmp / "measure")
    server = LiveServer(tmp)
    try:
        url = f"{server.url}/viewer/?manifest={server.url}/datasets/measure/manifest.json"
        whole = [0, 0, W, H]
        cases = [{"layer": layer, "light": list(LIGHT), "region": whole,
                  "params": PARAMS.get(layer), "points": [css_of(*p) for p in PIXELS]}
                 for layer in blocks]
        cases.append({"layer": "sv_linear", "light": list(LIGHT), "region": whole,
                      "gestures": [GESTURE]})
        hover = [{"layer": "ptm_rgb", "light": list(LIGHT), "region": whole, "hover": HOVER}]
        spec = {"pages": [{"url": f"{url}&measure=1", "touch": True, "cases": cases},
                          {"url": f"{url}&measure=1", "cases": hover},
                          {"url": url, "cases": hover}],
                "viewport": {"width": VIEW[0], "height": VIEW[1]}, "out": str(tmp / "out.json")}
        browser.run_driver(REPO / "tests/browser/measure.mjs", spec, tmp / "spec.json", 600)
        yield tmp / "measure", blocks, json.loads((tmp / "out.json").read_text())
    finally:
        server.close()


def reference(kind: str, block: dict[str, Any], values: dict[str, float],
              intensity: float) -> npt.NDArray[np.float32]:
    """The numpy plot of a measurement kind, from the pixel's values."""
    if kind == "brdf-slice":
        return material_slice(block, values, SLICE_SIZE)
    if kind == "reflectance-disk":
        return reflectance_disk(block, values, DISK_SIZE, intensity)
    return swatch(block, values)[None, None]


KINDS = {"ptm_lrgb": "reflectance-disk", "ptm_rgb": "reflectance-disk", "hsh": "reflectance-disk",
         "sv_linear": "brdf-slice", "sv_srgb": "brdf-slice", "rgb": "swatch", "grey": "swatch"}


@pytest.mark.parametrize("index, layer", list(enumerate(KINDS)))
def test_values_and_plots_equal_the_numpy_model(
        run: tuple[Path, dict[str, Any], dict[str, Any]], index: int, layer: str) -> None:
    dataset, blocks, result = run
    block = blocks[layer]
    assert {p["format"] for p in block["planes"]} == {"png"}
    measurements = result["pages"][0]["cases"][index]["measurements"]
    for (px, py), m in zip(PIXELS, measurements, strict=True):
        assert (m["imageX"], m["imageY"], m["layer"], m["kind"]) == (px, py, layer, KINDS[layer])
        channels = level_channels(dataset, block, 1, region=(px, py, 1, 1))
        want = {name: float(v[0, 0]) for name, v in channels.items()}
        assert set(m["values"]) == set(want)
        for name, v in want.items():
            assert abs(m["values"][name] - v) <= 1e-6, (layer, (px, py), name)
        ref = reference(m["kind"], block, want, PARAMS.get(layer, {}).get("lightIntensity", 1.0))
        got = np.array(m["plot"]["data"], np.float64).reshape(m["plot"]["height"],
                                                              m["plot"]["width"], 3)
        assert got.shape == ref.shape
        scale = max(1.0, float(np.abs(ref).max()))
        assert float(np.abs(got - ref).max()) <= 1e-4 * scale, (layer, (px, py))
        assert float(np.abs(ref).max()) > 0  # not an empty plot
    # three different pixels give three different plots
    datas = [tuple(m["plot"]["data"]) for m in measurements]
    assert len(set(datas)) == 3


def test_a_one_finger_drag_measures_and_leaves_light_and_view(
        run: tuple[Path, dict[str, Any], dict[str, Any]]) -> None:
    case = run[2]["pages"][0]["cases"][len(KINDS)]
    before, after = case["before"], case["after"]
    assert before["mode"] == "measure" and before["enabled"]
    assert (after["light"]["lu"], after["light"]["lv"]) == pytest.approx(LIGHT, abs=1e-9)
    assert after["view"] == before["view"]
    assert before["widget"]["hidden"] and not after["widget"]["hidden"]
    end = GESTURE["to"][0]
    assert (after["current"]["imageX"], after["current"]["imageY"]) == (
        int(end[0] / SCALE), int((end[1] - TOP) / SCALE))
    assert after["current"]["kind"] == "brdf-slice"
    assert after["widget"]["caption"].startswith("kd ")
    x, y, w, h = after["widget"]["rect"]
    assert 0 <= x and 0 <= y and x + w <= after["widget"]["host"][0] + 0.5
    assert y + h <= after["widget"]["host"][1] + 0.5
    assert x > end[0] or x + w < end[0]  # beside the finger, not under it
    assert after["widget"]["centerPixel"][3] == 255  # the plot is drawn


def test_a_hover_shows_the_disk_only_in_measure_mode(
        run: tuple[Path, dict[str, Any], dict[str, Any]]) -> None:
    on = run[2]["pages"][1]["cases"][0]["after"]
    off = run[2]["pages"][2]["cases"][0]["after"]
    assert not on["widget"]["hidden"] and on["current"]["kind"] == "reflectance-disk"
    assert (on["current"]["imageX"], on["current"]["imageY"]) == (
        int(HOVER[0] / SCALE), int((HOVER[1] - TOP) / SCALE))
    assert on["widget"]["caption"].startswith(f"light {LIGHT[0]:.2f} {LIGHT[1]:.2f}")
    assert off["widget"]["hidden"] and off["current"] is None and off["mode"] == "light"
