"""Real Chromium: the scale bar of a dataset with a physical scale (a IIIF physdim service on the
canvas) is as long on screen as the length it states, at two zooms; a dataset without one has none.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import pytest

from tests.python.fixtures.lens import Dataset
from tests.python.fixtures.servers import LiveServer
from tests.python.fixtures.view_tools import add_physdim, run_session

pytestmark = pytest.mark.browser

MM_PER_PX = 0.05
IMAGE_WIDTH = 1024
MM = {"mm": 1.0, "cm": 10.0, "m": 1000.0}

#: The bar as shown, and the viewport it is shown for.
MEASURE = """
const l = window.lanterna;
await l.whenFullyLoaded();
const bar = document.querySelector('.lanterna-scale-bar');
const line = bar.querySelector('.lanterna-scale-bar-line').getBoundingClientRect();
const widget = document.querySelector('.lanterna-light-widget').getBoundingClientRect();
const viewer = l.viewer.element.getBoundingClientRect();
return { hidden: bar.hidden, width: line.width, left: line.left, right: line.right,
         bottom: line.bottom,
         widgetRight: widget.right, viewerRight: viewer.right, viewerBottom: viewer.bottom,
         label: bar.textContent, length: Number(bar.dataset.length), unit: bar.dataset.unit,
         zoom: l.viewer.viewport.getZoom(true), container: l.viewer.viewport.getContainerSize().x };
"""


def session(root: Path, tmp: Path, regions: list[tuple[int, int, int, int]]) -> dict[str, Any]:
    server = LiveServer(root)
    try:
        steps: list[dict[str, Any]] = []
        for k, r in enumerate(regions):
            steps += [{"eval": f"window.lanterna.showImageRegion({', '.join(map(str, r))});"},
                      {"eval": MEASURE, "save": f"bar{k}"}]
        url = f"{server.url}/viewer/?manifest={server.url}/datasets/lens/manifest.json"
        return run_session([{"url": url, "steps": steps}], tmp)
    finally:
        server.close()


def test_the_bar_states_its_on_screen_length(lens_dataset: Dataset, tmp_path: Path) -> None:
    without = session(lens_dataset.root, tmp_path / "none", [(0, 0, 1024, 768)])
    assert without["bar0"]["hidden"] is True, "no physdim service: no scale bar"

    add_physdim(lens_dataset.dir, MM_PER_PX)
    saved = session(lens_dataset.root, tmp_path / "bar", [(0, 0, 1024, 768), (300, 200, 128, 96)])
    labels = []
    for key in ("bar0", "bar1"):
        bar = saved[key]
        assert bar["hidden"] is False
        # OSD's zoom 1 fits the image's width to the container's
        screen_per_image = bar["zoom"] * bar["container"] / IMAGE_WIDTH
        length_mm = bar["length"] * MM[bar["unit"]]
        expected = length_mm / MM_PER_PX * screen_per_image
        assert bar["width"] == pytest.approx(expected, abs=0.02), bar
        assert bar["label"] == f"{bar['length']:g} {bar['unit']}"
        assert bar["length"] in (1, 2, 5, 10, 20, 50, 100, 200, 500)
        assert 160 / 2.5 <= bar["width"] <= 160, "a round length between 64 and 160 px"
        assert bar["left"] >= bar["widgetRight"], "beside the light widget, not over it"
        assert bar["right"] <= bar["viewerRight"] and bar["bottom"] <= bar["viewerBottom"]
        labels.append(bar["label"])
    assert saved["bar1"]["zoom"] == pytest.approx(8 * saved["bar0"]["zoom"], rel=1e-6)
    assert labels == ["1 cm", "1 mm"]
