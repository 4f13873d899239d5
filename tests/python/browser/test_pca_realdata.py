"""Relight's own coin outputs (``../shared/realdata/relight-coin``: ``rbf27``, rbf mrgb with 27
planes; ``bilinear18``, bilinear mrgb with 18 planes on a 9 × 9 grid) imported with
``lanterna import`` and relit in real Chromium, within 2/255 of the numpy reference
(:func:`lanterna.tiler.render.render` over the stored tiles) at three lights, in colour, normals,
albedo and specular. Skipped with a message when ../shared is absent.
"""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

import numpy as np
import numpy.typing as npt
import pytest

from lanterna.cli import main
from lanterna.tiler.dataset.writer import read_description
from lanterna.tiler.render import PARAMETERS, level_channels, render
from tests.python.fixtures.browser import Shot
from tests.python.fixtures.browser import render as render_in_chromium
from tests.python.fixtures.paths import shared_file
from tests.python.fixtures.servers import LiveServer

pytestmark = [pytest.mark.browser, pytest.mark.realdata]

VIEW = (320, 240)
REGION = (120, 150) + VIEW  # the coin's face, across the tile seams x = 256 and y = 256
LIGHTS = [(-0.6, 0.3), (0.0, 0.0), (0.45, -0.5)]
MODES = ["color", "normals", "albedo", "specular"]
TOLERANCE = 2  # out of 255


@pytest.mark.parametrize("name, layer_type, planes", [("rbf27", "rbf", 27),
                                                      ("bilinear18", "bilinear", 18)])
def test_relight_coin_renders_as_the_reference(
        tmp_path: Path, live_server: Callable[[Path], LiveServer], name: str, layer_type: str,
        planes: int) -> None:
    src = shared_file(f"realdata/relight-coin/{name}/info.json").parent
    root = tmp_path / "root"
    assert main(["import", str(src), "-o", str(root / name)]) == 0
    layers = read_description(root / name)["layers"]
    assert len(layers) == 1
    block = layers[0]["service"]
    assert (block["layerType"], block["colorspace"], block["nplanes"]) == (layer_type, "mrgb",
                                                                          planes)
    server = live_server(root)
    url = f"{server.url}/viewer/?manifest={server.url}/datasets/{name}/manifest.json"
    defaults = {p: spec[0] for p, spec in PARAMETERS.items()}
    keys = [(mode, light) for mode in MODES for light in LIGHTS]
    shots = [Shot(light, REGION, tmp_path / f"s{i:02d}.rgba", layers[0]["id"], mode, defaults)
             for i, (mode, light) in enumerate(keys)]
    frames = render_in_chromium(url, shots, viewport=VIEW)
    channels = level_channels(root / name, block, 1, REGION)
    shown: dict[tuple[str, tuple[float, float]], npt.NDArray[np.float64]] = {}
    for (mode, light), frame in zip(keys, frames, strict=True):
        expected = np.round(render(block, channels, light, mode) * 255).astype(np.int16)
        got = frame[..., :3].astype(np.int16)
        diff = np.abs(got - expected)
        bad = np.argwhere(diff.max(axis=-1) > TOLERANCE)
        assert bad.size == 0, (
            f"{name} {mode} light={light}: {len(bad)} pixels off by up to {diff.max()}/255, "
            f"first at (row, col) {tuple(bad[0])}: got {got[tuple(bad[0])]}, "
            f"expected {expected[tuple(bad[0])]}")
        assert expected.std() > 5, f"{name} {mode}: the coin must not render flat"
        if mode in ("color", "normals"):
            shown[(mode, light)] = got.astype(np.float64)
    # relit from the side the light comes from: where the model's normal faces left (n_x < 0) the
    # coin is brighter under the light from the left than under the light from the right
    nx = shown[("normals", LIGHTS[1])][..., 0] / 127.5 - 1
    change = shown[("color", LIGHTS[0])].mean(axis=-1) - shown[("color", LIGHTS[2])].mean(axis=-1)
    corr = float(np.corrcoef(nx.ravel(), change.ravel())[0, 1])
    print(f"{name}: correlation {corr:.2f}")
    assert corr < -0.3, f"{name}: brightening under the left light vs n_x: correlation {corr:.2f}"
