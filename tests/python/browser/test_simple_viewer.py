"""Real Chromium: the simplified viewer page (plugin/simple.html, docs/simple-viewer.md).

Data and driver: :mod:`tests.python.fixtures.simple_page`. The page shows only the preset library's
two menus, the lens and measurement toggles and a fullscreen button; a preset gives the pixels of
its values set through the API; only the presets' layers are fetched; a kiosk returns to its start
after the idle time and never shows a dialog.
"""

from __future__ import annotations

import json
import re
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from tests.python.fixtures.servers import LiveServer
from tests.python.fixtures.simple_page import (
    LIBRARY,
    UNUSED_LAYER,
    USED_LAYERS,
    Read,
    build_objects,
    drive,
)

pytestmark = pytest.mark.browser

#: A plane request: ``…/iiif/{image}/{region}/{size}/0/default.{fmt}``.
PLANE_URL = re.compile(r"/iiif/(?P<image>[A-Za-z0-9_-]+)/[^/]+/[^/]+/0/default\.\w+$")
CONTROL_IDS = {"lens-toggle", "measure-toggle", "fullscreen"}
BASE_LABELS = [e["label"] for e in LIBRARY["base"]]
LENS_LABELS = [e["label"] for e in LIBRARY["lens"]]


@pytest.fixture(scope="module")
def site(tmp_path_factory: pytest.TempPathFactory) -> Iterator[tuple[LiveServer, Path]]:
    root = tmp_path_factory.mktemp("simple") / "root"
    build_objects(root)
    server = LiveServer(root)
    yield server, root
    server.close()


def page_url(server: LiveServer, dataset: str, query: str = "") -> str:
    return (f"{server.url}/viewer/simple.html?manifest={server.url}/datasets/{dataset}/"
            f"manifest.json{query}")


def layer_images(root: Path, dataset: str) -> dict[str, set[str]]:
    """The image ids of each layer (its planes and its preview), from the dataset's manifest."""
    manifest = json.loads((root / dataset / "manifest.json").read_text())
    out: dict[str, set[str]] = {}
    for canvas in manifest["items"]:
        for page in canvas["items"]:
            for anno in page["items"]:
                body = anno["body"]
                for item in body["items"] if body["type"] == "Choice" else [body]:
                    services = item.get("service", [])
                    relight = [s for s in services if s.get("type") == "LanternaRelight"]
                    for service in relight:
                        layer = service["id"].rsplit("/", 1)[1].removesuffix(".json")
                        out[layer] = {p["service"]["id"].rsplit("/", 1)[1]
                                      for p in service["planes"]}
                        out[layer] |= {s["id"].rsplit("/", 1)[1] for s in services
                                       if s.get("type") == "ImageService3"}
    return out


def fetched_images(requests: list[str]) -> set[str]:
    return {m["image"] for m in (PLANE_URL.search(u) for u in requests) if m}


def controls(read: Read | dict[str, Any]) -> list[dict[str, Any]]:
    ui = read.ui if isinstance(read, Read) else read["ui"]
    found: list[dict[str, Any]] = ui["controls"]
    return found


def menu_texts(read: Read, menu: str) -> list[str]:
    return [c["text"] for c in controls(read) if c["menu"] == menu]


def pressed(read: Read, menu: str) -> list[str]:
    return [c["text"] for c in controls(read) if c["menu"] == menu and c["pressed"] == "true"]


def api_calls(preset: dict[str, Any]) -> list[list[Any]]:
    """The API calls that set a base preset's values by hand."""
    calls: list[list[Any]] = [["setActiveLayer", preset["layer"]],
                              ["setRenderMode", preset["mode"]], ["resetRenderParams"],
                              ["setRenderParams", preset.get("params", {})]]
    if "light" in preset:
        calls.append(["setLight", *preset["light"]])
    return calls


def steps_for_every_preset() -> list[dict[str, Any]]:
    """Each base preset by its button, then moved away, then by the API; the same for the lens."""
    steps: list[dict[str, Any]] = [{"type": "read", "name": "start"}]
    for i, entry in enumerate(LIBRARY["base"]):
        preset = LIBRARY["presets"][entry["preset"]]
        steps += [{"type": "click", "selector": f"#base-list button[data-index='{i}']"},
                  {"type": "read", "name": f"base{i}"},
                  {"type": "api", "calls": [["setLight", 0.5, 0.5]]},
                  {"type": "read", "name": f"base{i}-moved"},
                  {"type": "api", "calls": api_calls(preset)},
                  {"type": "read", "name": f"base{i}-api"}]
    for i, entry in enumerate(LIBRARY["lens"]):
        preset = LIBRARY["presets"][entry["preset"]]
        lens = {"enabled": True, "layer": preset["layer"], "mode": preset["mode"],
                "opacity": entry.get("opacity", 1)}
        steps += [{"type": "click", "selector": f"#lens-list button[data-index='{i}']"},
                  {"type": "read", "name": f"lens{i}"},
                  {"type": "api", "calls": [["setLens", {"enabled": False}]]},
                  {"type": "read", "name": f"lens{i}-off"},
                  {"type": "api", "calls": [["setLens", lens]]},
                  {"type": "read", "name": f"lens{i}-api"}]
    return steps


@pytest.fixture(scope="module")
def desktop(site: tuple[LiveServer, Path], tmp_path_factory: pytest.TempPathFactory,
            ) -> tuple[dict[str, Any], dict[str, Read]]:
    server, _ = site
    return drive(page_url(server, "obj"), steps_for_every_preset(),
                 tmp_path_factory.mktemp("desktop"), viewport=(1920, 1080))


def test_the_page_shows_the_two_menus_and_two_toggles_and_nothing_else(
        desktop: tuple[dict[str, Any], dict[str, Read]]) -> None:
    _, reads = desktop
    start = reads["start"]
    found = controls(start)
    assert menu_texts(start, "base-menu") == BASE_LABELS
    assert menu_texts(start, "lens-menu") == LENS_LABELS
    assert {c["id"] for c in found if c["menu"] is None} == CONTROL_IDS
    assert len(found) == len(BASE_LABELS) + len(LENS_LABELS) + len(CONTROL_IDS)
    assert {c["tag"] for c in found} == {"button"}  # no select, no slider, no input
    assert start.ui["dialogs"] == [] and start.ui["note"] is None
    # large touch targets, text readable from 2 m on a 1080p screen, no sideways scroll
    assert min(min(c["rect"][2], c["rect"][3]) for c in found) >= 48
    assert min(c["fontSize"] for c in found) >= 20
    assert start.ui["scroll"][0] <= start.ui["scroll"][1]
    # the first base preset applied at start, the lens off
    assert pressed(start, "base-menu") == [BASE_LABELS[0]]
    assert pressed(start, "lens-menu") == []
    assert start.state["layer"] == "ptm" and start.state["light"]["lu"] == pytest.approx(-0.9)
    assert not start.state["lens"]["enabled"]
    toggles = {c["id"]: c["pressed"] for c in found if c["menu"] is None}
    assert toggles["lens-toggle"] == "false" and toggles["measure-toggle"] == "false"


@pytest.mark.parametrize("i", range(len(LIBRARY["base"])))
def test_a_base_preset_gives_the_pixels_of_its_values_set_through_the_api(
        desktop: tuple[dict[str, Any], dict[str, Read]], i: int) -> None:
    _, reads = desktop
    chosen, moved, by_hand = reads[f"base{i}"], reads[f"base{i}-moved"], reads[f"base{i}-api"]
    preset = LIBRARY["presets"][LIBRARY["base"][i]["preset"]]
    assert chosen.state["layer"] == preset["layer"] and chosen.state["mode"] == preset["mode"]
    assert pressed(chosen, "base-menu") == [BASE_LABELS[i]]
    assert not np.array_equal(chosen.frame, moved.frame), "moving the light must change the frame"
    assert np.array_equal(chosen.frame, by_hand.frame)
    assert chosen.frame[..., :3].std() > 5, "the frame must not be flat"


@pytest.mark.parametrize("i", range(len(LIBRARY["lens"])))
def test_a_lens_preset_turns_the_lens_on_with_the_pixels_of_its_api_values(
        desktop: tuple[dict[str, Any], dict[str, Read]], i: int) -> None:
    _, reads = desktop
    chosen, off, by_hand = reads[f"lens{i}"], reads[f"lens{i}-off"], reads[f"lens{i}-api"]
    entry = LIBRARY["lens"][i]
    assert chosen.state["lens"]["enabled"]
    assert chosen.state["lens"]["layer"] == LIBRARY["presets"][entry["preset"]]["layer"]
    assert chosen.state["lens"]["opacity"] == pytest.approx(entry.get("opacity", 1))
    assert pressed(chosen, "lens-menu") == [LENS_LABELS[i]]
    toggles = {c["id"]: c["pressed"] for c in controls(chosen) if c["menu"] is None}
    assert toggles["lens-toggle"] == "true"
    assert not np.array_equal(chosen.frame, off.frame), "the lens must show something else"
    assert np.array_equal(chosen.frame, by_hand.frame)


def test_only_the_layers_of_the_presets_are_requested(
        desktop: tuple[dict[str, Any], dict[str, Read]], site: tuple[LiveServer, Path]) -> None:
    result, reads = desktop
    images = layer_images(site[1], "obj")
    assert reads["start"].state["layers"] == list(USED_LAYERS)
    fetched = fetched_images(result["requests"])
    used = set().union(*(images[layer] for layer in USED_LAYERS))
    assert images[UNUSED_LAYER] and not fetched & images[UNUSED_LAYER], fetched
    assert fetched <= used
    for layer in USED_LAYERS:  # every preset was applied: each of its layers was drawn
        assert fetched & images[layer], layer


def test_a_library_given_by_url_gives_the_same_menus(
        site: tuple[LiveServer, Path], tmp_path: Path) -> None:
    server, root = site
    library = f"{server.url}/datasets/bare/library.json"
    result, reads = drive(page_url(server, "bare", f"&presets={library}"),
                          [{"type": "read", "name": "start"}], tmp_path)
    start = reads["start"]
    assert menu_texts(start, "base-menu") == BASE_LABELS
    assert menu_texts(start, "lens-menu") == LENS_LABELS
    assert start.state["layers"] == list(USED_LAYERS)
    assert library in result["requests"]
    assert not fetched_images(result["requests"]) & layer_images(root, "bare")[UNUSED_LAYER]


def test_without_presets_the_object_shows_with_the_lens_toggle_only(
        site: tuple[LiveServer, Path], tmp_path: Path) -> None:
    server, _ = site
    _, reads = drive(page_url(server, "bare"), [{"type": "read", "name": "start"}], tmp_path)
    start = reads["start"]
    assert {c["id"] for c in controls(start)} == {"lens-toggle", "fullscreen"}
    assert start.ui["note"] and "default rendering" in start.ui["note"]
    assert start.state["layers"] == ["ptm", "hsh", "material", "ir", "uv"]
    assert start.state["layer"] == "ptm" and start.state["mode"] == "color"


def _state_key(read: Read) -> dict[str, Any]:
    s = read.state
    return {"layer": s["layer"], "mode": s["mode"], "params": s["params"],
            "light": [round(s["light"]["lu"], 6), round(s["light"]["lv"], 6)],
            "lens": [s["lens"]["enabled"], s["lens"]["center"], round(s["lens"]["radius"], 3)],
            "view": [round(v, 6) for v in [*s["view"]["center"], s["view"]["zoom"]]]}


def test_a_kiosk_returns_to_its_first_preset_after_the_idle_time(
        site: tuple[LiveServer, Path], tmp_path: Path) -> None:
    server, _ = site
    steps = [{"type": "read", "name": "start"},
             {"type": "click", "selector": "#base-list button[data-index='2']"},
             {"type": "click", "selector": "#lens-list button[data-index='1']"},
             {"type": "read", "name": "chosen"},
             {"type": "wheel", "at": [300, 300], "deltaY": -300},
             {"type": "read", "name": "zoomed"},
             {"type": "mouse", "from": [150, 600], "to": [250, 650]},  # outside the lens
             {"type": "read", "name": "lit"},
             {"type": "mouse", "from": [150, 600], "to": [100, 650], "button": "right"},
             {"type": "click", "selector": "#measure-toggle"},
             {"type": "read", "name": "changed"},
             {"type": "waitForIdleReset"},
             {"type": "read", "name": "reset"}]
    result, reads = drive(page_url(server, "obj", "&kiosk=1&idle=3"), steps, tmp_path)
    start, changed, reset = reads["start"], reads["changed"], reads["reset"]
    chosen, zoomed, lit = reads["chosen"], reads["zoomed"], reads["lit"]
    assert chosen.state["layer"] == "material" and chosen.state["lens"]["enabled"]
    # the mouse: wheel zooms, a drag lights, a right-drag pans
    assert zoomed.state["view"]["zoom"] > chosen.state["view"]["zoom"] * 1.1
    assert lit.state["light"] != zoomed.state["light"] and lit.state["view"] == zoomed.state["view"]
    assert changed.state["view"]["center"] != lit.state["view"]["center"]
    assert changed.state["light"] == lit.state["light"]
    assert chosen.ui["fullscreen"], "the first gesture of a kiosk asks for fullscreen"
    toggles = {c["id"]: c["pressed"] for c in controls(changed) if c["menu"] is None}
    assert toggles["measure-toggle"] == "true" and changed.state["dragMode"] != "light"
    assert reset.ui["idleResets"] == changed.ui["idleResets"] + 1
    assert _state_key(reset) == _state_key(start)
    assert np.array_equal(reset.frame, start.frame)
    assert pressed(reset, "base-menu") == [BASE_LABELS[0]] and pressed(reset, "lens-menu") == []
    toggles = {c["id"]: c["pressed"] for c in controls(reset) if c["menu"] is None}
    assert toggles == {"lens-toggle": "false", "measure-toggle": "false"}  # measurement off
    assert reset.state["dragMode"] == "light"
    # locked down: no context menu, no selection, no page zoom, no button to leave fullscreen
    ui = start.ui
    assert ui["kiosk"] and ui["contextMenuBlocked"] and ui["userSelect"] == "none"
    assert "user-scalable=no" in ui["viewport"]
    assert "fullscreen" not in {c["id"] for c in controls(start)}
    assert result["dialogs"] == []


@pytest.fixture(scope="module")
def touch_reads(site: tuple[LiveServer, Path],
                tmp_path_factory: pytest.TempPathFactory) -> dict[str, Read]:
    """Emulated touch: one finger, a pinch outside the lens, the lens on, two fingers inside it."""
    server, _ = site
    steps = [{"type": "read", "name": "t0"},
             {"type": "touch", "from": [[200, 400]], "to": [[600, 200]]},
             {"type": "read", "name": "t1"},
             {"type": "touch", "from": [[300, 500], [340, 500]], "to": [[290, 490], [370, 510]]},
             {"type": "read", "name": "t2"},
             {"type": "click", "selector": "#lens-toggle"},
             {"type": "api", "calls": [["setLens", {"center": [300, 300], "radius": 60}]]},
             {"type": "read", "name": "t3"},
             {"type": "touch", "from": [[290, 300], [310, 300]], "to": [[310, 310], [350, 310]]},
             {"type": "read", "name": "t4"}]
    _, reads = drive(page_url(server, "obj"), steps, tmp_path_factory.mktemp("touch"),
                     options={"touch": True})
    return reads


def _light(r: Read) -> tuple[float, float]:
    return r.state["light"]["lu"], r.state["light"]["lv"]


def test_touch_one_finger_lights_two_fingers_zoom_or_move_the_lens(
        touch_reads: dict[str, Read]) -> None:
    t0, t1, t2, t3, t4 = (touch_reads[f"t{k}"] for k in range(5))
    assert _light(t1) != pytest.approx(_light(t0), abs=1e-3), "one finger moves the light"
    assert t1.state["view"] == t0.state["view"]
    assert t2.state["view"]["zoom"] > t1.state["view"]["zoom"] * 1.3  # fingers 40 → 80 px apart
    assert t3.state["lens"]["enabled"] and pressed(t3, "lens-menu") == [LENS_LABELS[0]]
    # two fingers inside the lens: midpoint (300, 300) → (330, 310), distance 20 → 40
    assert t4.state["lens"]["center"] == pytest.approx([330, 310], abs=0.5)
    assert t4.state["lens"]["radius"] == pytest.approx(120, rel=0.02)
    assert t4.state["view"] == t3.state["view"] and _light(t4) == pytest.approx(_light(t3))


def test_a_pinch_outside_the_lens_leaves_the_light(touch_reads: dict[str, Read]) -> None:
    assert _light(touch_reads["t2"]) == pytest.approx(_light(touch_reads["t1"]), abs=1e-6)


def test_a_kiosk_shows_no_dialog_when_a_tile_or_the_presets_fail(
        site: tuple[LiveServer, Path], tmp_path: Path) -> None:
    server, root = site
    ptm_images = "|".join(sorted(layer_images(root, "bare")["ptm"]))
    steps = [{"type": "read", "name": "start"},
             {"type": "waitFor", "selector": "#note[hidden]"},
             {"type": "read", "name": "later"}]
    routes = [{"match": r"/library\.json$", "status": 404},
              {"match": rf"/iiif/({ptm_images})/0,0,64,64/", "status": 404, "times": 1}]
    result, reads = drive(page_url(server, "bare", f"&kiosk=1&presets={server.url}/datasets/bare/"
                                                   "library.json"),
                          steps, tmp_path, options={"routes": routes, "allowConsoleErrors": [
                              "Failed to load resource", "404"]})
    assert result["routeHits"][0] == 1 and result["routeHits"][1] >= 1
    for read in (reads["start"], reads["later"]):
        assert read.ui["dialogs"] == []
        assert {c["id"] for c in controls(read)} == {"lens-toggle"}  # nothing to dismiss
    assert reads["start"].ui["note"] is not None and "http" not in reads["start"].ui["note"]
    assert reads["later"].ui["note"] is None  # the note cleared itself
    assert result["dialogs"] == []


def test_a_kiosk_that_cannot_open_the_object_says_so_calmly(
        site: tuple[LiveServer, Path], tmp_path: Path) -> None:
    server, _ = site
    result, _ = drive(page_url(server, "missing", "&kiosk=1"), [], tmp_path,
                      options={"expect": "unavailable", "allowConsoleErrors": [".*"]})
    ui = result["ui"]
    assert ui["unavailable"].startswith("This object is not available right now")
    assert "missing" not in ui["unavailable"]  # no URL, no error name for visitors
    assert controls(result) == [] and ui["dialogs"] == [] and result["dialogs"] == []


def test_a_kiosk_opens_the_object_when_it_comes_back(
        site: tuple[LiveServer, Path], tmp_path: Path) -> None:
    server, _ = site
    routes = [{"match": r"/datasets/obj/manifest\.json$", "status": 503, "times": 1}]
    result, reads = drive(page_url(server, "obj", "&kiosk=1&retry=1"),
                          [{"type": "read", "name": "start"}], tmp_path,
                          options={"routes": routes, "allowConsoleErrors": [".*"]})
    manifest = [u for u in result["requests"] if u.endswith("/datasets/obj/manifest.json")]
    assert result["routeHits"] == [1] and len(manifest) == 2  # failed, then tried again
    assert reads["start"].ui["unavailable"] is None
    assert pressed(reads["start"], "base-menu") == [BASE_LABELS[0]]


def test_the_phone_layout_keeps_the_object_in_view_and_the_targets_large(
        site: tuple[LiveServer, Path], tmp_path: Path) -> None:
    server, _ = site
    steps = [{"type": "read", "name": "start"}, {"type": "click", "selector": "#lens-toggle"},
             {"type": "read", "name": "lens"}]
    _, reads = drive(page_url(server, "obj"), steps, tmp_path, viewport=(390, 844),
                     options={"touch": True, "mobile": True})
    start = reads["start"]
    assert start.ui["scroll"][0] <= start.ui["scroll"][1]
    x, y, w, h = start.ui["viewer"]
    assert (x, y, w) == (0, 0, 390) and h >= 844 / 2
    found = controls(start)
    assert len(found) == len(BASE_LABELS) + len(LENS_LABELS) + len(CONTROL_IDS)
    assert min(min(c["rect"][2], c["rect"][3]) for c in found) >= 48
    assert all(c["rect"][1] >= h for c in found)  # below the image, none over it
    # the lens opens in the middle of the image's area, not of the page the menus share
    lens = reads["lens"].state["lens"]
    assert lens["enabled"] and lens["center"] == pytest.approx([w / 2, h / 2], abs=0.5)


def test_the_page_needs_a_manifest(live_server: Callable[[Path], LiveServer],
                                   tmp_path: Path) -> None:
    server = live_server(tmp_path)
    result, _ = drive(f"{server.url}/viewer/simple.html", [], tmp_path / "out",
                      options={"expect": "unavailable", "allowConsoleErrors": [".*"]})
    assert "no manifest given" in result["ui"]["unavailable"]
