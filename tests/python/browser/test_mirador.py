"""Real Chromium, real Mirador 4 (the ready bundle, /viewer/mirador.html): Lanterna in its windows.

A two-layer PTM dataset opens in a Mirador window; our viewer (the plugin's, reached through
``Mirador.lanternaWindowViewer``) relights it within 2/255 of the numpy relight of the served tiles
at two lights; Mirador's layers panel (its "Show layer" button; the opacity as its slider dispatches
``updateLayers`` to the store ``Mirador.viewer`` returns) picks our layer and its opacity, and
our layer change moves Mirador's; Mirador's zoom-in button zooms our view and our zoom reaches
Mirador's viewport state; a plain IIIF manifest stays in Mirador's own OpenSeadragon; two windows
relight independently.
"""

from __future__ import annotations

import json
import re
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import numpy.typing as npt
import pytest

from tests.python.fixtures.mirador import check_ptm_frame, write_plain_manifest, write_two_ptms
from tests.python.fixtures.page_script import evaluate, frame, run_page
from tests.python.fixtures.ptm_relight import H, W
from tests.python.fixtures.servers import LiveServer

pytestmark = pytest.mark.browser

ORIGIN = (40, 30)  # image pixel at the view's top left corner, one image pixel per screen pixel
LIGHTS = [(-0.5, 0.3), (0.45, -0.6)]
PAGE = (1000, 760)

#: Helpers the steps use: window ids, their viewers, a frame read back at 1:1 from ORIGIN.
HELPERS = evaluate("""() => {
  const store = window.miradorInstance.store;
  const t = {
    store,
    windows: () => Object.keys(store.getState().windows),
    lv: (i) => Mirador.lanternaWindowViewer(t.windows()[i]),
    async readyViewers(n) {
      while (t.windows().length < n || t.windows().slice(0, n).some((w, i) => !t.lv(i))) {
        await new Promise((r) => setTimeout(r, 50));
      }
    },
    async shot(i, light) {
      const l = t.lv(i);
      const { width, height } = l.readPixels();
      l.showImageRegion(ORIGIN_X, ORIGIN_Y, width, height);
      l.setLight(light[0], light[1]);
      await l.whenFullyLoaded();
      const { data } = l.readPixels();
      let s = '';
      for (let k = 0; k < data.length; k += 0x8000) {
        s += String.fromCharCode.apply(null, data.subarray(k, k + 0x8000));
      }
      return { width, height, base64: btoa(s) };
    },
    async until(f) {
      while (!f()) {
        await new Promise((r) => setTimeout(r, 50));
      }
    },
  };
  window.t = t;
  return t.windows().length;
}""".replace("ORIGIN_X", str(ORIGIN[0])).replace("ORIGIN_Y", str(ORIGIN[1])))


@dataclass
class Site:
    """The served dataset, its layer blocks and painting image ids, the Mirador page's URL."""

    url: str
    manifest: str
    doc: dict[str, Any]
    plain: str
    ds: Path
    blocks: dict[str, dict[str, Any]]
    images: dict[str, str]
    canvas: str


@pytest.fixture(scope="module")
def site(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Site]:
    root = tmp_path_factory.mktemp("mirador") / "root"
    blocks = write_two_ptms(root / "obj")
    server = LiveServer(root)
    try:
        base = f"{server.url}/datasets/obj"
        got = json.loads((root / "obj" / "manifest.json").read_text())
        canvas = got["items"][0]
        items = canvas["items"][0]["items"][0]["body"]["items"]
        images = {svc["id"].rsplit("/", 1)[1].removesuffix(".json"): it["id"].replace(
            "http://127.0.0.1:8000", server.url) for it in items for svc in it["service"]
            if svc["type"] == "LanternaRelight"}
        assert sorted(images) == ["lrgb", "rgb"], images
        write_plain_manifest(root / "plain" / "manifest.json", f"{server.url}/datasets/plain",
                             f"{base}/iiif/lrgb_preview")
        yield Site(f"{server.url}/viewer/mirador.html", f"{base}/manifest.json", got,
                   f"{server.url}/datasets/plain/manifest.json", root / "obj", blocks, images,
                   canvas["id"].replace("http://127.0.0.1:8000", server.url))
    finally:
        server.close()


def check_relit(site: Site, layer: str, light: tuple[float, float], value: dict[str, Any]) -> None:
    """The frame (1:1 from ORIGIN) matches the numpy relight where it shows the image."""
    got = frame(value)
    opaque = got[:H - ORIGIN[1], :W - ORIGIN[0], 3] == 255
    assert opaque.all(), f"{layer}: the image must be opaque"
    check_ptm_frame(site.ds, site.blocks[layer], light, got, ORIGIN)


def centre(view: list[float]) -> tuple[float, float]:
    return view[0] + view[2] / 2, view[1] + view[3] / 2


def rgb(value: dict[str, Any]) -> npt.NDArray[np.int16]:
    return frame(value)[..., :3].astype(np.int16)


@pytest.fixture(scope="module")
def one_window(site: Site, tmp_path_factory: pytest.TempPathFactory) -> dict[str, Any]:
    """One Mirador window on the dataset: frames, layer switches both ways, zooms both ways."""
    lrgb, rgb_image = site.images["lrgb"], site.images["rgb"]
    named: list[tuple[str, dict[str, Any]]] = [
        ("", {"waitFor": "() => window.miradorInstance && Mirador.lanternaWindowViewer"}),
        ("windows", HELPERS),
        ("first layer", evaluate(
            "async () => { await t.readyViewers(1); return t.lv(0).getActiveLayer(); }")),
        ("widgets", evaluate("""() => {
          const rect = (q) => document.querySelector(q)?.getBoundingClientRect().toJSON();
          return { disc: rect('.lanterna-mirador-canvas .lanterna-light-widget'),
                   zoom: rect('button[aria-label="Zoom in"]') };
        }""")),
        ("lrgb 0", evaluate(f"() => t.shot(0, {list(LIGHTS[0])})")),
        ("lrgb 1", evaluate(f"() => t.shot(0, {list(LIGHTS[1])})")),
        # Mirador's layers panel (side bar): show rgb, above lrgb in Mirador's order
        ("", {"click": 'button[aria-label="Toggle sidebar"]'}),
        ("", {"click": 'button[aria-label="Layers"]'}),
        ("", {"click": 'button[aria-label="Show layer"]'}),
        ("switched", evaluate("""async () => {
          await t.until(() => t.lv(0).getActiveLayer() === 'rgb' && t.lv(0).layer?.id === 'rgb');
          return t.lv(0).getActiveLayer();
        }""")),
        ("rgb 0", evaluate(f"() => t.shot(0, {list(LIGHTS[0])})")),
        # what the layers panel's opacity slider dispatches
        ("opacity", evaluate(f"""async () => {{
          t.store.dispatch(Mirador.updateLayers(t.windows()[0], '{site.canvas}',
            {{ '{rgb_image}': {{ opacity: 0.4 }} }}));
          const canvas = document.querySelector('.lanterna-mirador-canvas');
          await t.until(() => canvas.style.opacity === '0.4');
          return canvas.style.opacity;
        }}""")),
        # our layer change: Mirador's top visible layer follows
        ("mirador layers", evaluate(f"""async () => {{
          const w = t.windows()[0];
          await t.lv(0).setActiveLayer('lrgb');
          const layers = () => t.store.getState().layers[w]['{site.canvas}'];
          await t.until(() => layers()['{lrgb}']?.index === 1);
          return layers();
        }}""")),
        # Mirador's zoom-in button, then our own zoom
        ("before zoom", evaluate("() => { t.before = t.lv(0).getState().view; return t.before; }")),
        ("", {"click": 'button[aria-label="Zoom in"]'}),
        ("after zoom", evaluate("""async () => {
          await t.until(() => t.lv(0).getState().view[2] < t.before[2] * 0.75);
          await t.lv(0).whenFullyLoaded();
          return t.lv(0).getState().view;
        }""")),
        ("", {"click": 'button[aria-label="Zoom out"]'}),
        ("after zoom out", evaluate("""async () => {
          await t.until(() => t.lv(0).getState().view[2] > t.before[2] * 0.75);
          return t.lv(0).getState().view;
        }""")),
        ("", {"click": 'button[aria-label="Reset zoom"]'}),
        ("after reset", evaluate("""async () => {
          const [w, h] = [WIDTH, HEIGHT];
          await t.until(() => {
            const [x0, y0, vw, vh] = t.lv(0).getState().view;
            return x0 <= 0.5 && y0 <= 0.5 && x0 + vw >= w - 0.5 && y0 + vh >= h - 0.5;
          });
          return t.lv(0).getState().view;
        }""".replace("WIDTH", str(W)).replace("HEIGHT", str(H)))),
        ("our zoom", evaluate("""async () => {
          const w = t.windows()[0];
          t.lv(0).showImageRegion(100, 100, 200, 150);
          const wanted = 1 / t.lv(0).getState().view[2];
          const zoom = () => t.store.getState().viewers[w]?.zoom;
          await t.until(() => Math.abs(zoom() - wanted) < wanted * 0.01);
          return { viewer: t.store.getState().viewers[w], view: t.lv(0).getState().view };
        }""")),
    ]
    folder = tmp_path_factory.mktemp("mirador-one")
    result = run_page(f"{site.url}?manifest={site.manifest}", [step for _, step in named], folder,
                      PAGE, routes=())
    return {name: value for (name, _), value in zip(named, result["values"], strict=True) if name}


def test_the_canvas_opens_in_our_viewer_and_is_relit(site: Site,
                                                     one_window: dict[str, Any]) -> None:
    assert one_window["windows"] == 1
    assert one_window["first layer"] == "lrgb"
    check_relit(site, "lrgb", LIGHTS[0], one_window["lrgb 0"])
    check_relit(site, "lrgb", LIGHTS[1], one_window["lrgb 1"])
    moved = np.abs(rgb(one_window["lrgb 0"]) - rgb(one_window["lrgb 1"])).mean()
    assert moved > 5, "the light must matter"


def test_the_light_disc_sits_above_miradors_canvas_controls(one_window: dict[str, Any]) -> None:
    disc, zoom = one_window["widgets"]["disc"], one_window["widgets"]["zoom"]
    assert disc is not None and zoom is not None, one_window["widgets"]
    assert disc["bottom"] <= zoom["top"] + 0.5, f"the light disc overlaps the controls: {disc}"


def test_miradors_layers_panel_picks_our_layer_and_opacity(site: Site,
                                                          one_window: dict[str, Any]) -> None:
    assert one_window["switched"] == "rgb"
    check_relit(site, "rgb", LIGHTS[0], one_window["rgb 0"])
    assert one_window["opacity"] == "0.4"


def test_our_layer_change_moves_miradors_layers(site: Site, one_window: dict[str, Any]) -> None:
    layers = one_window["mirador layers"]
    assert layers[site.images["lrgb"]] == {"index": 1, "visibility": True}, layers
    assert layers[site.images["rgb"]]["index"] == 0, layers


def test_miradors_zoom_button_zooms_our_view(one_window: dict[str, Any]) -> None:
    before, after = one_window["before zoom"], one_window["after zoom"]
    assert after[2] == pytest.approx(before[2] / 2, rel=0.02), (before, after)
    assert centre(after) == pytest.approx(centre(before), abs=2), (before, after)


def test_miradors_zoom_out_and_reset_buttons_work_too(one_window: dict[str, Any]) -> None:
    before, out = one_window["before zoom"], one_window["after zoom out"]
    assert out[2] == pytest.approx(before[2], rel=0.02), (before, out)
    x, y, w, h = one_window["after reset"]  # the whole image fits, centred
    assert x <= 0.5 and y <= 0.5 and x + w >= W - 0.5 and y + h >= H - 0.5, (x, y, w, h)
    assert min(w - W, h - H) == pytest.approx(0, abs=1), (x, y, w, h)


def test_our_zoom_reaches_miradors_viewport(one_window: dict[str, Any]) -> None:
    viewer, view = one_window["our zoom"]["viewer"], one_window["our zoom"]["view"]
    assert viewer["zoom"] == pytest.approx(1 / view[2], rel=0.01)
    assert viewer["x"] == pytest.approx(view[0] + view[2] / 2, abs=1)
    assert viewer["y"] == pytest.approx(view[1] + view[3] / 2, abs=1)


def test_a_plain_manifest_stays_in_miradors_own_viewer(site: Site, tmp_path: Path) -> None:
    steps: list[dict[str, Any]] = [
        {"waitFor": "() => window.miradorInstance && Mirador.lanternaWindowViewer"},
        HELPERS,
        # Mirador's OpenSeadragon (its OSDReferences) has the image, fully loaded
        evaluate("""async () => {
          await t.until(() => t.windows().length === 1);
          const w = t.windows()[0];
          await t.until(() => {
            const osd = Mirador.OSDReferences.get(w)?.current;
            return osd && osd.world.getItemCount() === 1 && osd.world.getItemAt(0).getFullyLoaded();
          });
          const osd = Mirador.OSDReferences.get(w).current;
          return { items: osd.world.getItemCount(),
                   lanterna: Mirador.lanternaWindowViewer(w) === null,
                   ours: document.querySelectorAll('.lanterna-mirador-view').length,
                   canvases: document.querySelectorAll('.mirador-osd-container canvas').length,
                   drawer: osd.drawer.getType() };
        }"""),
    ]
    url = f"{site.url}?manifest={site.plain}"
    got = run_page(url, steps, tmp_path, PAGE, routes=())["values"][2]
    assert got["items"] == 1 and got["lanterna"] is True and got["ours"] == 0, got
    assert got["canvases"] >= 1, got
    assert got["drawer"] != "lanterna", got  # not our drawer: Mirador's OpenSeadragon 5


def test_two_windows_relight_independently(site: Site, tmp_path: Path) -> None:
    steps: list[dict[str, Any]] = [
        {"waitFor": "() => window.miradorInstance && Mirador.lanternaWindowViewer"},
        HELPERS,
        evaluate("""async () => {
          await t.readyViewers(2);
          return [t.lv(0) !== t.lv(1), t.lv(0).viewer !== t.lv(1).viewer];
        }"""),
        evaluate(f"() => t.shot(0, {list(LIGHTS[0])})"),
        evaluate(f"() => t.shot(1, {list(LIGHTS[1])})"),
        evaluate("() => [t.lv(0).getLight(), t.lv(1).getLight()]"),
    ]
    url = f"{site.url}?manifest={site.manifest}&manifest={site.manifest}"
    values = run_page(url, steps, tmp_path, PAGE, routes=())["values"]
    assert values[2] == [True, True]
    check_relit(site, "lrgb", LIGHTS[0], values[3])
    check_relit(site, "lrgb", LIGHTS[1], values[4])
    a, b = rgb(values[3]), rgb(values[4])
    rows, cols = min(a.shape[0], b.shape[0]), min(a.shape[1], b.shape[1])
    assert np.abs(a[:rows, :cols] - b[:rows, :cols]).mean() > 5, "different lights: other pixels"
    (lu0, lv0), (lu1, lv1) = ([v["lu"], v["lv"]] for v in values[5])
    assert (lu0, lv0) == pytest.approx(LIGHTS[0]) and (lu1, lv1) == pytest.approx(LIGHTS[1])


def test_a_broken_relight_block_is_one_line_in_the_window(site: Site, tmp_path: Path) -> None:
    doc = json.loads(json.dumps(site.doc))
    items = doc["items"][0]["items"][0]["items"][0]["body"]["items"]
    block = next(s for s in items[0]["service"] if s["type"] == "LanternaRelight")
    block["planes"] = block["planes"][:1]  # an lrgb PTM needs three plane groups
    served = json.dumps(doc).replace("http://127.0.0.1:8000", site.url.split("/viewer/")[0])
    routes = [{"match": f"^{re.escape(site.manifest)}$", "status": 200, "body": served,
               "contentType": "application/json"}]
    steps: list[dict[str, Any]] = [
        {"waitFor": "() => document.querySelector('.lanterna-mirador-error')"},
        evaluate("() => document.querySelector('.lanterna-mirador-error').textContent"),
        evaluate("() => Mirador.lanternaWindowViewer(Object.keys("
                 "window.miradorInstance.store.getState().windows)[0])"),
    ]
    result = run_page(f"{site.url}?manifest={site.manifest}", steps, tmp_path, PAGE,
                      routes=routes, allow_console_errors=[r"^\[lanterna\]"])
    text, viewer = result["values"][1], result["values"][2]
    assert text.startswith("Lanterna: ") and "3 plane groups, got 1" in text, text
    assert "\n" not in text, text
    assert viewer is None
    assert result["pageErrors"] == []
