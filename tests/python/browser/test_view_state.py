"""Real Chromium: the view state in the URL hash (links), restored pixel-equal in a new page; the
hash follows the view without history entries; a bad link opens with a notice; the canvas keys.

Data: the lens and overlays dataset (:mod:`tests.python.fixtures.lens`, 1024×768, layers ``base``
(PTM, overlays) and ``second`` (image)). Sessions: :mod:`tests.python.fixtures.view_tools`.
"""

from __future__ import annotations

import json
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from tests.python.fixtures.lens import Dataset
from tests.python.fixtures.servers import LiveServer
from tests.python.fixtures.view_tools import frame, run_session

pytestmark = pytest.mark.browser

#: Wait until the hash has been written for the state shown (the page shows exactly the link).
SETTLED = ("window.lanterna.viewer.element.dataset.lanternaLink !== undefined"
           " && window.lanterna.viewer.element.dataset.lanternaLink === location.hash")
STATE = "return window.lanterna.getState();"


@pytest.fixture(scope="module")
def page_url(lens_dataset: Dataset) -> Iterator[str]:
    server = LiveServer(lens_dataset.root)
    yield f"{server.url}/viewer/?manifest={server.url}/datasets/lens/manifest.json&layer=base"
    server.close()


#: A state set through the API with unrounded numbers: lens, parameters, light and a zoomed view.
SETUP = """
const l = window.lanterna;
l.setRenderMode('specular');
l.setRenderParams({ specKs: 0.81234, specExponent: 40.55, gamma: 1.234567, lightIntensity: 1.3 });
l.setLight(0.31234567, 0.45678912);
l.setOverlaysVisible(false);
l.showImageRegion(301.37, 207.73, 333.33, 250.01);
await l.setLens({ enabled: true, center: [203.456, 151.987], radius: 71.234, layer: 'second',
                  opacity: 0.734567, annotations: 'inside' });
"""


def test_a_link_reproduces_the_view_pixel_equal(page_url: str, tmp_path: Path) -> None:
    out = tmp_path / "link"
    saved = run_session([
        {"url": page_url, "steps": [
            {"frame": "home"},
            {"eval": SETUP},
            {"waitFor": SETTLED + " && location.hash.includes('lens=')"},
            {"frame": "shared"},
            {"eval": "return location.hash;", "save": "hash"},
            {"eval": STATE, "save": "state1"},
        ]},
        {"url": page_url + "{hash}", "steps": [
            {"waitFor": SETTLED},
            {"frame": "opened"},
            {"eval": "return location.hash;", "save": "hash2"},
            {"eval": STATE, "save": "state2"},
        ]},
        # Another screen size: the same region in view, the lens over the same detail.
        {"url": page_url + "{hash}", "viewport": {"width": 900, "height": 420}, "steps": [
            {"waitFor": SETTLED},
            {"eval": STATE, "save": "state3"},
            {"eval": "return window.lanterna.getLens();", "save": "lens3"},
        ]},
    ], out)
    hash_ = saved["hash"]
    assert hash_.startswith("#v=1&layer=base&mode=specular&light=0.312,0.457&p="), hash_
    for part in ("lightIntensity:1.3", "gamma:1.235", "specKs:0.812", "specExponent:40.6", "ov=0",
                 "lensLayer=second", "lensOpacity=0.735", "lensAnn=inside"):
        assert part in hash_, (part, hash_)
    shared, opened, home = frame(out, "shared"), frame(out, "opened"), frame(out, "home")
    assert not np.array_equal(shared, home), "the state must change the picture"
    assert shared[..., :3].std() > 5, "a real picture, not a blank frame"
    diff = np.abs(shared.astype(int) - opened.astype(int))
    assert diff.max() == 0, f"{(diff.max(axis=-1) > 0).sum()} pixels differ, by up to {diff.max()}"
    assert saved["hash2"] == hash_, "opening a link leaves its hash as it is"
    s1, s2, s3 = saved["state1"], saved["state2"], saved["state3"]
    for key in ("layer", "mode", "params", "light", "overlays"):
        assert s1[key] == s2[key] == s3[key], key
    assert s1["light"] == [0.312, 0.457]  # the rounded state is what the first page shows too
    assert s1["params"]["gamma"] == 1.235 and s1["params"]["specExponent"] == 40.6
    assert s1["lens"]["opacity"] == 0.735 and s1["lens"]["layer"] == "second"
    # lens in image pixels: the same detail on the wider screen
    assert np.allclose(s3["lens"]["center"], s1["lens"]["center"], atol=0.05)
    assert s3["lens"]["radius"] == pytest.approx(s1["lens"]["radius"], abs=0.05)
    assert saved["lens3"]["radius"] != pytest.approx(71.234, abs=0.5), "CSS radius follows the zoom"
    x, y, w, h = s1["view"]
    x3, y3, w3, h3 = s3["view"]
    assert x3 <= x + 0.05 and y3 <= y + 0.05 and x3 + w3 >= x + w - 0.05 and y3 + h3 >= y + h - 0.05
    assert min(w3 - w, h3 - h) == pytest.approx(0, abs=0.05), "the region just fits"


def test_the_hash_follows_the_view_without_history_entries(page_url: str, tmp_path: Path) -> None:
    steps: list[dict[str, Any]] = [{"eval": "return history.length;", "save": "before"}]
    for k, (lu, mode) in enumerate([(0.1, "diffuse"), (0.2, "normals"), (-0.4, "color")]):
        steps += [
            {"eval": f"const l = window.lanterna; l.setRenderMode('{mode}'); l.setLight({lu}, 0.3);"
                     f" l.showImageRegion({100 * k}, 50, 400, 300);"},
            {"waitFor": SETTLED + f" && location.hash.includes('mode={mode}')"},
            {"eval": "return location.hash;", "save": f"hash{k}"},
        ]
    steps.append({"eval": "return history.length;", "save": "after"})
    saved = run_session([{"url": page_url, "steps": steps}], tmp_path / "history")
    assert saved["after"] == saved["before"]
    last = saved["hash2"]
    assert "light=-0.4,0.3" in last and "view=200,50,400,300" in last, last
    assert len({saved[f"hash{k}"] for k in range(3)}) == 3


def test_a_pasted_link_is_restored(page_url: str, tmp_path: Path) -> None:
    link = "#v=1&layer=second&mode=color&light=-0.5,0.25&view=0,0,512,384"
    saved = run_session([{"url": page_url, "steps": [
        {"eval": f"location.hash = '{link}';"},
        {"waitFor": "window.lanterna.getActiveLayer() === 'second' && " + SETTLED},
        {"eval": STATE, "save": "state"},
        {"eval": "return location.hash;", "save": "hash"},
    ]}], tmp_path / "pasted")
    assert saved["state"]["light"] == [-0.5, 0.25]
    assert saved["state"]["view"] == pytest.approx([0, 0, 512, 384], abs=0.01)
    assert saved["hash"] == link


def test_a_bad_link_opens_with_a_notice(page_url: str, tmp_path: Path) -> None:
    link = ("#v=1&layer=nope&mode=shiny&p=gamma:2,bogus:1&light=0.2,0.1&lensLayer=second"
            "&lensMode=specular&junk=1")
    saved = run_session([{"url": page_url + link, "steps": [
        {"waitFor": SETTLED},
        {"eval": STATE, "save": "state"},
        {"eval": "return window.lanterna.getNotices();", "save": "notices"},
    ]}], tmp_path / "bad")
    state = saved["state"]
    assert state["layer"] == "base" and state["mode"] == "color"  # kept the viewer's own
    assert state["params"]["gamma"] == 2 and state["light"] == [0.2, 0.1]  # the valid fields apply
    errors = [n["message"] + n["detail"] for n in saved["notices"] if n["kind"] == "error"]
    assert len(errors) == 1, saved["notices"]
    for problem in ('mode: no render mode "shiny"', 'p: no render parameter "bogus"',
                    "junk: unknown key", 'layer: no layer "nope"',
                    "lensMode: specular does not apply to layer second"):
        assert problem in errors[0], (problem, errors[0])


def test_canvas_keys(page_url: str, tmp_path: Path) -> None:
    out = tmp_path / "keys"
    setup = ("window.lanterna.viewer.canvas.focus(); window.lanterna.setLight(0, 0);"
             " window.lanterna.showImageRegion(100, 100, 200, 150);")
    help_hidden = "document.querySelector('.lanterna-help').hidden"
    active = "document.activeElement"
    # Wide enough that the panel leaves the toolbar free.
    saved = run_session([{"url": page_url, "viewport": {"width": 1100, "height": 600}, "steps": [
        {"eval": setup},
        {"eval": STATE, "save": "zoomed"},
        {"press": "ArrowRight"}, {"press": "ArrowUp"}, {"press": "ArrowUp"},
        {"eval": STATE, "save": "lit"},
        {"press": "Shift+ArrowRight"},
        {"eval": "await new Promise((r) => setTimeout(r, 100)); return window.lanterna.getState();",
         "save": "panned"},
        {"press": "l"}, {"eval": "return window.lanterna.getLens().enabled;", "save": "lensOn"},
        {"press": "l"}, {"eval": "return window.lanterna.getLens().enabled;", "save": "lensOff"},
        {"press": "a"},
        {"eval": "return window.lanterna.getOverlaysVisible();", "save": "overlaysAfterA"},
        {"press": "h"},
        {"eval": "const l = window.lanterna;"
                 " await new Promise((r) => l.viewer.addOnceHandler('animation-finish', r));"
                 " return l.getImageRegion();", "save": "home"},
        {"press": "?"},
        {"eval": f"return {active}.textContent;", "save": "helpFocus"},
        {"eval": f"return !{help_hidden};", "save": "helpOpen"},
        {"press": "Tab"}, {"press": "Tab"}, {"press": "Shift+Tab"},
        {"eval": f"return document.querySelector('.lanterna-help-dialog').contains({active});",
         "save": "trapped"},
        {"press": "Escape"},
        {"eval": f"return [{help_hidden}, {active} === window.lanterna.viewer.canvas];",
         "save": "closed"},
        {"click": "#toolbar button[aria-haspopup=dialog]"},
        {"eval": f"return {active}.textContent;", "save": "buttonHelp"},
        {"click": ".lanterna-help-close"},
        {"eval": f"return [{help_hidden}, {active}.textContent];", "save": "buttonClosed"},
    ]}], out)
    assert saved["lit"]["light"] == pytest.approx([0.05, 0.1], abs=1e-12)
    assert saved["lit"]["view"] == pytest.approx(saved["zoomed"]["view"], abs=1e-6), "light only"
    assert saved["panned"]["view"][0] > saved["zoomed"]["view"][0] + 1, "Shift+→ pans right"
    assert saved["panned"]["light"] == saved["lit"]["light"]
    assert saved["lensOn"] is True and saved["lensOff"] is False
    assert saved["overlaysAfterA"] is False
    assert saved["home"] == pytest.approx([0, 0, 1024, 768], abs=0.5)
    assert saved["helpOpen"] is True and saved["helpFocus"] == "Close"
    assert saved["trapped"] is True
    assert saved["closed"] == [True, True], "Esc closes and gives the focus back to the canvas"
    assert saved["buttonHelp"] == "Close"
    assert saved["buttonClosed"] == [True, "?"]
    assert json.dumps(saved)  # all values were JSON


def test_a_rotated_view_is_reproduced_pixel_equal(page_url: str, tmp_path: Path) -> None:
    out = tmp_path / "rotated"
    setup = ("const l = window.lanterna; l.viewer.viewport.setRotation(90, true);"
             " l.setLight(-0.41234, 0.2); l.showImageRegion(400.5, 300.25, 300, 225);"
             " await l.setLens({ enabled: true, center: [150.5, 120.25], radius: 60 });")
    saved = run_session([
        {"url": page_url, "steps": [
            {"eval": setup},
            {"waitFor": SETTLED + " && location.hash.includes('rot=90')"},
            {"frame": "shared"},
            {"eval": "return location.hash;", "save": "hash"},
        ]},
        {"url": page_url + "{hash}", "steps": [
            {"waitFor": SETTLED},
            {"frame": "opened"},
            {"eval": "return window.lanterna.viewer.viewport.getRotation(true);",
             "save": "rotation"},
        ]},
    ], out)
    assert saved["rotation"] == 90
    shared, opened = frame(out, "shared"), frame(out, "opened")
    assert shared[..., :3].std() > 5
    assert np.array_equal(shared, opened), f"{(shared != opened).any(axis=-1).sum()} pixels differ"
