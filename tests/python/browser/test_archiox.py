"""Real Chromium: a layer imported from an ARCHiOx-style manifest (served by a plain static IIIF
host, written from the published convention) is relit by the plugin within 2/255 of the numpy
reference, at two lights and two zooms."""

from __future__ import annotations

import json
from collections.abc import Callable
from pathlib import Path

import numpy as np
import pytest

from lanterna.cli import main
from lanterna.tiler.render import PARAMETERS, level_channels, render
from tests.python.fixtures import browser
from tests.python.fixtures.archiox import write_site
from tests.python.fixtures.pixels import assert_pixels_close
from tests.python.fixtures.servers import LiveServer, StaticServer

pytestmark = pytest.mark.browser

VIEW = (160, 120)
#: zoom factor → the fitted region in full-resolution pixels (one level pixel per screen pixel)
REGIONS = {1: (80, 60, 160, 120), 2: (0, 0, 320, 240)}
LIGHTS = [(-0.55, 0.35), (0.45, -0.6)]
TOLERANCE = 2  # out of 255
DEFAULTS = {name: spec[0] for name, spec in PARAMETERS.items()}


def test_an_imported_archiox_layer_is_relit_like_the_reference(
        tmp_path: Path, live_server: Callable[[Path], LiveServer]) -> None:
    root = tmp_path / "root"
    with StaticServer(tmp_path / "site") as host:
        write_site(tmp_path / "site", host.url)
        assert main(["import", f"{host.url}/manifest.json", "-o", str(root / "tablet")]) == 0
    desc = json.loads((root / "tablet" / "lanterna.json").read_text())
    (layer,) = desc["layers"]
    block = layer["service"]
    assert block["layerType"] == "svbrdf"
    server = live_server(root)
    url = f"{server.url}/viewer/?manifest={server.url}/datasets/tablet/manifest.json"
    shots = [browser.Shot(light, REGIONS[f], tmp_path / f"z{f}_{i}.rgba", layer["id"], "color",
                          DEFAULTS)
             for f in REGIONS for i, light in enumerate(LIGHTS)]
    frames = browser.render(url, shots, viewport=VIEW)
    means, worst = [], 0
    for shot, frame in zip(shots, frames, strict=True):
        factor = 1 if shot.region[2] == VIEW[0] else 2
        x, y, _, _ = shot.region
        channels = level_channels(root / "tablet", block, factor,
                                  (x // factor, y // factor, *VIEW))
        expected = np.round(render(block, channels, shot.light, "color") * 255).astype(np.int16)
        assert frame.shape == (VIEW[1], VIEW[0], 4)
        assert (frame[..., 3] == 255).all(), "the view must be opaque"
        got = frame[..., :3].astype(np.int16)
        worst = max(worst, int(np.abs(got - expected).max()))
        assert_pixels_close(got, expected, TOLERANCE, f"light={shot.light} zoom 1/{factor}")
        assert expected.std() > 5, "not a flat picture"
        means.append(float(np.abs(got - frames[0][..., :3]).mean()) if means else 0.0)
    assert means[1] > 5, "the second light lights the tablet differently"
    print(f"ARCHiOx import: largest difference {worst}/255")  # reported with -s
