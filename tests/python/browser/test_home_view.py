"""Real Chromium: what a visitor sees at the home view and when the screen changes.

The demo dataset (1536×1152, annotated at levels 0–3) shows its overview annotation at home on a
desktop and on a phone, and finer ones as one zooms in (docs/annotations.md, "Levels"); a tiny
image is not blown up at home (docs/rendering.md, "Home view"); the lens stays inside the viewer
when a phone turns to landscape.
"""

from __future__ import annotations

import json
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from lanterna.tiler.dataset.layers import add_image_layer
from lanterna.tiler.dataset.writer import DatasetWriter
from lanterna.tiler.demo.dataset import DEMO_TEXTS, build_demo
from lanterna.tiler.iiif.pyramid import vips_from_array
from tests.python.fixtures import browser, page_script
from tests.python.fixtures.servers import LiveServer

pytestmark = pytest.mark.browser

DEMO_W, DEMO_H = 1536, 1152
TINY_W, TINY_H = 64, 43
LIGHT = (0.3, 0.4)


@dataclass
class Served:
    root: Path
    url: str

    def viewer(self, dataset: str) -> str:
        return f"{self.url}/viewer/?manifest={self.url}/datasets/{dataset}/manifest.json"


@pytest.fixture(scope="module")
def served(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Served]:
    root = tmp_path_factory.mktemp("home")
    build_demo(root / "demo")
    rng = np.random.default_rng(3)
    tiny = rng.integers(60, 200, (TINY_H, TINY_W, 3), dtype=np.uint8)
    with DatasetWriter(root / "tiny", name="tiny", label="A tiny image", width=TINY_W,
                       height=TINY_H) as ds:
        add_image_layer(ds, vips_from_array(tiny), layer_id="img", label="Tiny", fmt="png")
    server = LiveServer(root)
    try:
        yield Served(root, server.url)
    finally:
        server.close()


def home_shot(out: Path, **extra: Any) -> browser.Shot:
    return browser.Shot(LIGHT, (0, 0, 1, 1), out, extra={"home": True, **extra})


def zoomed(k: int) -> tuple[int, int, int, int]:
    """The demo's central region 1/k of its size: fitted, it is k times the home zoom."""
    w, h = DEMO_W // k, DEMO_H // k
    return ((DEMO_W - w) // 2, (DEMO_H - h) // 2, w, h)


@pytest.mark.parametrize("viewport", [(1280, 720), (390, 844)], ids=["desktop", "phone"])
def test_the_home_view_shows_the_overview_annotation(served: Served, tmp_path: Path,
                                                     viewport: tuple[int, int]) -> None:
    shots = [home_shot(tmp_path / "home.rgba")]
    shots += [browser.Shot(LIGHT, zoomed(k), tmp_path / f"zoom{k}.rgba") for k in (2, 4, 8)]
    browser.render(served.viewer("demo"), shots, viewport=viewport)
    states = [s.meta()["overlayState"] for s in shots]
    assert [s["level"] for s in states] == [3, 2, 1, 0]
    assert [s["short"] for s in states] == [DEMO_TEXTS[str(lv)]["short"] for lv in (3, 2, 1, 0)]
    assert all(s["available"] for s in states)
    home = shots[0].meta()
    assert home["hypertext"] == DEMO_TEXTS["3"]["short"] == "An inscribed limestone tablet"
    requests = [s.meta()["requests"] for s in shots]
    assert [any("/ptm_ov0/" in u for u in r) for r in requests] == [False, False, False, True], \
        "the finest level's image loads only when zoomed in 8×"


def test_a_tiny_image_is_not_blown_up_at_home(served: Served, tmp_path: Path) -> None:
    shot = home_shot(tmp_path / "tiny.rgba")
    (frame,) = browser.render(served.viewer("tiny"), [shot], viewport=(1280, 720))
    rows, cols = np.nonzero(frame[..., 3])
    width, height = cols.max() - cols.min() + 1, rows.max() - rows.min() + 1
    # 2 CSS px per image px (DPR 1), centred; OpenSeadragon's own fit would be 16.7×
    assert (width, height) == (pytest.approx(2 * TINY_W, abs=1), pytest.approx(2 * TINY_H, abs=1))
    centre = ((cols.min() + cols.max() + 1) / 2, (rows.min() + rows.max() + 1) / 2)
    assert centre == (pytest.approx(640, abs=1), pytest.approx(360, abs=1))
    # around the image the canvas is transparent: the page's background shows there
    around = frame.copy()
    around[rows.min(): rows.max() + 1, cols.min(): cols.max() + 1] = 0
    assert not around.any()
    assert (frame[rows.min() + 1: rows.max(), cols.min() + 1: cols.max(), 3] == 255).all()


def test_the_lens_stays_inside_the_viewer_when_the_phone_turns(served: Served,
                                                               tmp_path: Path) -> None:
    lens = {"enabled": True, "center": [195, 700], "radius": 80}
    shot = browser.Shot(LIGHT, (0, 0, TINY_W, TINY_H), tmp_path / "turned.rgba",
                        extra={"lens": lens,
                               "gestures": [{"type": "viewport", "size": [844, 390]}]})
    (frame,) = browser.render(served.viewer("tiny"), [shot], viewport=(390, 844),
                              options={"mobile": True})
    meta = shot.meta()
    assert frame.shape[:2] == (390, 844)
    (x, y), r = meta["lens"]["center"], meta["lens"]["radius"]
    assert r == 80
    assert 0 <= x - r and x + r <= 844 and 0 <= y - r and y + r <= 390, meta["lens"]
    # it kept its offset from the centre along x (the viewer's centre moved by 227 px)
    assert x == pytest.approx(195 + (844 - 390) / 2)


def test_each_demo_preset_gives_the_pixels_of_its_values(served: Served, tmp_path: Path) -> None:
    """The demo's own library (tiler/demo/presets.py), entry by entry, against the same calls."""
    library = json.loads((served.root / "demo" / "presets.json").read_text())
    steps: list[dict[str, Any]] = [page_script.READY]
    for target in ("base", "lens"):
        for k, entry in enumerate(library[target]):
            preset = library["presets"][entry["preset"]]
            steps += [page_script.evaluate(f"() => window.lanterna.applyPreset('{target}', {k})"),
                      page_script.FRAME,
                      page_script.by_hand(target, preset, entry.get("opacity", 1)),
                      page_script.FRAME]
    values = page_script.run_page(served.viewer("demo") + "&minPixelRatio=0.75", steps, tmp_path,
                                  (800, 600), timeout=600)["values"]
    frames = [page_script.frame(v) for v in values if isinstance(v, dict) and "base64" in v]
    assert len(frames) == 2 * (len(library["base"]) + len(library["lens"])) >= 8
    for k in range(0, len(frames), 2):
        assert np.array_equal(frames[k], frames[k + 1]), f"entry {k // 2}"
    assert len({frames[k].tobytes() for k in range(0, len(frames), 2)}) == len(frames) // 2
