"""Real Chromium, real Mirador 4 (the ready bundle, /viewer/mirador.html): the window's Lanterna
controls and Mirador's annotation panel driving our view (docs/mirador.md).

A two-layer PTM dataset whose rgb layer has an overlay built as ``lanterna annotate build``
builds it (the manifest lists its level motivated ``commenting``, targeting its drawing's bounding
box), and whose canvas also carries a page with a plain note on a region, as another tool would
add it. The top bar's
"Lanterna controls" button opens the companion window with our panel; its mode menu and light
buttons change our pixels (the light's frame matches the numpy relight within 2/255); selecting an
annotation in Mirador's own annotation panel fits our view to its region (``getImageRegion``),
switching to the overlay's layer and showing the overlays; a patch of the layer's W3C page is
focused with the render state it was drawn under, and pointing at it in Mirador's list outlines it.
A plain IIIF manifest gets no button.
"""

from __future__ import annotations

import json
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import numpy.typing as npt
import pytest
import pyvips

from lanterna.tiler.overlays.build import build_overlays
from tests.python.fixtures.mirador import check_ptm_frame, write_plain_manifest, write_two_ptms
from tests.python.fixtures.page_script import evaluate, frame, run_page
from tests.python.fixtures.ptm_relight import H, W
from tests.python.fixtures.servers import LiveServer

pytestmark = pytest.mark.browser

BASE = "http://127.0.0.1:8000/datasets/obj"  # the dataset's recorded URL (the server rewrites it)
CANVAS = f"{BASE}/canvas/1"
ORIGIN = (40, 30)  # image pixel at the view's top left corner, one image pixel per screen pixel
PAGE = (1280, 800)
#: The overlay level's drawing's bounding box (layer rgb, level 0) and the note's region, canvas px.
OVERLAY_BOX = (120, 80, 300, 200)
NOTE_BOX = (600, 450, 200, 150)
OVERLAY_ID = f"{CANVAS}/overlays/rgb/level/0"
NOTE_ID = f"{CANVAS}/notes/1"
#: A patch of layer lrgb (its W3C page, referenced by the canvas) and the state it was drawn under.
PATCH = "0_500_100_200_120_0_mark"
PATCH_BOX = (500, 100, 200, 120)
PATCH_ID = f"{BASE}/annotations/lrgb/{PATCH}.json"
PATCH_STATE = {"layer": "lrgb", "mode": "specular", "params": {"specExponent": 40, "specKs": 0.6},
               "light": [0.5, -0.25]}
BUTTON = 'button[aria-label="Lanterna controls"]'
PANEL = ".lanterna-mirador-panel"

#: Helpers the steps use: the window's viewer, and a frame read back at 1:1 from ORIGIN.
HELPERS = evaluate("""() => {
  const store = window.miradorInstance.store;
  const t = {
    store,
    windowId: () => Object.keys(store.getState().windows)[0],
    lv: () => Mirador.lanternaWindowViewer(t.windowId()),
    async until(f) {
      while (!f()) {
        await new Promise((r) => setTimeout(r, 50));
      }
    },
    async shot() {
      const l = t.lv();
      const { width, height } = l.readPixels();
      l.showImageRegion(ORIGIN, width, height);
      await l.whenFullyLoaded();
      const { data } = l.readPixels();
      let s = '';
      for (let k = 0; k < data.length; k += 0x8000) {
        s += String.fromCharCode.apply(null, data.subarray(k, k + 0x8000));
      }
      return { width, height, base64: btoa(s), light: l.getLight(), mode: l.getRenderMode() };
    },
    async settled() {
      await new Promise((r) => setTimeout(r, 300));  // let the view's animation start
      await t.lv().whenFullyLoaded();
      return { region: t.lv().getImageRegion(), layer: t.lv().getActiveLayer(),
               overlays: t.lv().getOverlaysVisible(),
               selected: store.getState().windows[t.windowId()].selectedAnnotationId };
    },
  };
  window.t = t;
  return true;
}""".replace("ORIGIN", f"{ORIGIN[0]}, {ORIGIN[1]}"))


@dataclass
class Site:
    """The served dataset's folder, its layer blocks, the Mirador page and the manifests' URLs."""

    url: str
    manifest: str
    plain: str
    ds: Path
    blocks: dict[str, dict[str, Any]]


def notes_page() -> dict[str, Any]:
    """A page of one plain note (a region and a text), as another tool would add it."""
    note = {
        "id": NOTE_ID, "type": "Annotation", "motivation": "commenting",
        "body": {"type": "TextualBody", "value": "A chip in the rim", "format": "text/plain"},
        "target": f"{CANVAS}#xywh=" + ",".join(map(str, NOTE_BOX))}
    return {"id": f"{CANVAS}/notes", "type": "AnnotationPage", "items": [note]}


def build_overlay(ds: Path, scratch: Path) -> None:
    """Layer rgb's overlay, built as `lanterna annotate build` does: one level-0 drawing covering
    OVERLAY_BOX, short text "Underdrawing" (the manifest then lists it, motivated ``commenting``,
    targeting the drawing's own box: docs/annotations.md)."""
    x, y, w, h = OVERLAY_BOX
    scratch.mkdir(parents=True)
    drawing = np.zeros((h, w, 4), np.uint8)
    drawing[..., 0], drawing[..., 3] = 220, 180
    pyvips.Image.new_from_array(drawing).copy(interpretation="srgb").write_to_file(
        str(scratch / f"0_{x}_{y}_{w}_{h}_0_underdrawing.png"))
    report = build_overlays(ds, "rgb", patches_dir=scratch,
                            texts={"0": {"short": "Underdrawing"}})
    assert not report.errors, report.errors


def write_patch_page(version: Path) -> dict[str, Any]:
    """Layer lrgb's W3C annotation page with one patch (docs/annotations.md); its reference."""
    folder = version / "annotations" / "lrgb"
    folder.mkdir(parents=True)
    x, y, w, h = PATCH_BOX
    pyvips.Image.black(w, h, bands=4).write_to_file(str(folder / f"{PATCH}.png"))
    patch = {
        "id": PATCH_ID, "type": "Annotation", "motivation": ["highlighting", "commenting"],
        "target": {"type": "SpecificResource", "source": {"id": CANVAS, "type": "Canvas"},
                   "selector": {"type": "FragmentSelector", "value": f"xywh={x},{y},{w},{h}"}},
        "body": [
            {"id": f"{BASE}/annotations/lrgb/{PATCH}.png", "type": "Image", "format": "image/png",
             "width": w, "height": h,
             "service": [{"id": f"{PATCH_ID}#lanterna", "type": "LanternaPatch",
                          "profile": "urn:lanterna:patch:1", "layer": "lrgb", "level": 0,
                          "order": 0, "x": x, "y": y, "w": w, "h": h, "state": PATCH_STATE}]},
            {"type": "TextualBody", "value": "Tool mark", "format": "text/plain",
             "purpose": "commenting"}]}
    page_id = f"{BASE}/annotations/lrgb.json"
    (version / "annotations" / "lrgb.json").write_text(json.dumps({
        "@context": "http://iiif.io/api/presentation/3/context.json", "id": page_id,
        "type": "AnnotationPage", "items": [patch]}))
    return {"id": page_id, "type": "AnnotationPage"}


@pytest.fixture(scope="module")
def site(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Site]:
    root = tmp_path_factory.mktemp("mirador-ui") / "root"
    blocks = write_two_ptms(root / "obj")
    build_overlay(root / "obj", root.parent / "patches")
    version = (root / "obj").resolve()
    manifest_path = version / "manifest.json"
    manifest = json.loads(manifest_path.read_text())
    canvas = manifest["items"][0]
    assert canvas["id"] == CANVAS and (canvas["width"], canvas["height"]) == (W, H)
    pages = [notes_page(), write_patch_page(version)]
    canvas["annotations"] = [*canvas.get("annotations", []), *pages]
    manifest_path.write_text(json.dumps(manifest))
    server = LiveServer(root)
    try:
        write_plain_manifest(root / "plain" / "manifest.json", f"{server.url}/datasets/plain",
                             f"{server.url}/datasets/obj/iiif/lrgb_preview")
        yield Site(f"{server.url}/viewer/mirador.html", f"{server.url}/datasets/obj/manifest.json",
                   f"{server.url}/datasets/plain/manifest.json", root / "obj", blocks)
    finally:
        server.close()


def served(url: str, site: Site) -> str:
    """An id of the manifest as the server answers it (its recorded base rewritten)."""
    return url.replace("http://127.0.0.1:8000", site.url.split("/viewer/")[0])


@pytest.fixture(scope="module")
def run(site: Site, tmp_path_factory: pytest.TempPathFactory) -> list[Any]:
    """One Mirador window on the dataset: the controls opened and used, two annotations selected."""
    overlay, note, patch = (served(i, site) for i in (OVERLAY_ID, NOTE_ID, PATCH_ID))
    steps: list[dict[str, Any]] = [
        {"waitFor": "() => window.miradorInstance && window.Mirador?.lanternaWindowViewer"},
        HELPERS,
        evaluate("async () => { await t.until(() => t.lv()); await t.lv().ready; "
                 "return t.lv().getActiveLayer(); }"),
        # 3: the button opens the companion window with our panel
        {"waitFor": f"() => document.querySelector('{BUTTON}')"},
        {"click": BUTTON},
        {"waitFor": f"() => document.querySelector('{PANEL} select[name=mode]')"},
        evaluate(f"""() => ({{
          sections: [...document.querySelectorAll('{PANEL} legend, {PANEL} h2')]
            .map((e) => e.textContent),
          modes: [...document.querySelectorAll('{PANEL} select[name=mode] option')]
            .map((o) => o.value),
          apiModes: t.lv().getLayers().find((l) => l.id === t.lv().getActiveLayer()).modes,
          title: document.querySelector('.lanterna-companion-window h3')?.textContent,
          layerMenuShown: document.querySelector('{PANEL} select[name=layer]').checkVisibility(),
          contents: Object.values(t.store.getState().companionWindows).map((w) => w.content),
        }})"""),
        # 7: a colour frame, then the mode menu
        evaluate("() => t.shot()"),
        {"select": f"{PANEL} select[name=mode]", "value": "normals"},
        evaluate("() => t.shot()"),
        {"select": f"{PANEL} select[name=mode]", "value": "color"},
        # 11: the raking light from the west
        {"click": f"{PANEL} button[name=light-west]"},
        evaluate("() => t.shot()"),
        evaluate(f"() => document.querySelector('{PANEL} .lanterna-light-readout').textContent"),
        # 14: the button again closes it
        {"click": BUTTON},
        evaluate(f"""async () => {{
          await t.until(() => !document.querySelector('{PANEL}'));
          return Object.values(t.store.getState().companionWindows).map((w) => w.content);
        }}"""),
        # 16: Mirador's annotation panel, opened from its side bar, lists both annotations
        {"click": 'button[aria-label="Toggle sidebar"]'},
        {"click": '[aria-label="Annotations"]'},
        {"waitFor": "() => document.querySelectorAll('li[annotationid]').length === 4"},
        evaluate("() => [...document.querySelectorAll('li[annotationid]')].map((li) => "
                 "[li.getAttribute('annotationid'), li.textContent.trim()])"),
        # 20: select the overlay level, then the note
        {"click": f'li[annotationid="{overlay}"]'},
        evaluate("() => t.settled()"),
        {"click": f'li[annotationid="{note}"]'},
        evaluate("() => t.settled()"),
        # 24: pointing at the patch outlines it; selecting it focuses it
        {"hover": f'li[annotationid="{patch}"]'},
        evaluate("() => document.querySelectorAll('.lanterna-annotation-highlight').length"),
        {"click": f'li[annotationid="{patch}"]'},
        evaluate("""async () => ({ ...await t.settled(), mode: t.lv().getRenderMode(),
                                   light: t.lv().getLight(),
                                   params: t.lv().getRenderParams() })"""),
    ]
    folder = tmp_path_factory.mktemp("mirador-ui-run")
    result = run_page(f"{site.url}?manifest={site.manifest}", steps, folder, PAGE, routes=(),
                      settle=False)
    values: list[Any] = result["values"]
    return values


def relit(site: Site, layer: str, value: dict[str, Any]) -> npt.NDArray[np.int16]:
    """Check the frame (1:1 from ORIGIN) against the numpy relight at its light; return its RGB."""
    light = (value["light"]["lu"], value["light"]["lv"])
    return check_ptm_frame(site.ds, site.blocks[layer], light, frame(value), ORIGIN)


def test_the_top_bar_button_opens_the_controls(run: list[Any]) -> None:
    assert run[2] == "lrgb"
    shown = run[6]
    assert shown["title"] == "Lanterna"
    assert shown["sections"] == ["View", "Base layer", "Light", "Lens", "Presets"], shown
    assert shown["modes"] == shown["apiModes"] and "normals" in shown["modes"], shown
    assert not shown["layerMenuShown"], "Mirador's layers panel chooses the layer"
    assert "lanterna" in shown["contents"], shown
    assert "lanterna" not in run[15], "the button closes it again"


def test_the_mode_menu_changes_our_pixels(site: Site, run: list[Any]) -> None:
    colour, normals = run[7], run[9]
    assert (colour["mode"], normals["mode"]) == ("color", "normals")
    part = relit(site, "lrgb", colour)
    other = frame(normals)[:part.shape[0], :part.shape[1], :3].astype(np.int16)
    assert np.abs(other - part).mean() > 10, "the normals must not look like the colour"


def test_the_light_buttons_relight_our_view(site: Site, run: list[Any]) -> None:
    before, west = run[7], run[12]
    assert west["mode"] == "color"
    lu, lv = west["light"]["lu"], west["light"]["lv"]
    assert lu < -0.9 and abs(lv) < 1e-6, west["light"]  # raking from the west (the left)
    assert run[13].startswith("Azimuth 270°"), run[13]
    part = relit(site, "lrgb", west)
    assert np.abs(part - relit(site, "lrgb", before)).mean() > 5, "the light must matter"


def test_miradors_panel_lists_our_annotations(site: Site, run: list[Any]) -> None:
    listed = dict(run[19])
    # the overlay's drawing is also the first patch of rgb's store: a W3C annotation without text
    drawing = served(f"{BASE}/annotations/rgb/0_{'_'.join(map(str, OVERLAY_BOX))}_0_underdrawing"
                     ".json", site)
    assert listed == {served(OVERLAY_ID, site): "Underdrawing",
                      served(NOTE_ID, site): "A chip in the rim",
                      served(PATCH_ID, site): "Tool mark", drawing: listed.get(drawing)}
    assert drawing in listed


def fits(region: list[float], box: tuple[int, int, int, int]) -> None:
    """The view shows all of ``box``, centred, and fits it along one side."""
    x, y, w, h = region
    bx, by, bw, bh = box
    assert x <= bx + 1 and y <= by + 1 and x + w >= bx + bw - 1 and y + h >= by + bh - 1, region
    assert x + w / 2 == pytest.approx(bx + bw / 2, abs=2) and y + h / 2 == pytest.approx(
        by + bh / 2, abs=2), region
    assert w == pytest.approx(bw, rel=0.02) or h == pytest.approx(bh, rel=0.02), region


def test_selecting_an_overlay_level_shows_it_on_its_layer(site: Site, run: list[Any]) -> None:
    got = run[21]
    assert got["selected"] == served(OVERLAY_ID, site)
    assert got["layer"] == "rgb" and got["overlays"] is True, got
    fits(got["region"], OVERLAY_BOX)


def test_selecting_a_note_moves_our_view_to_its_region(site: Site, run: list[Any]) -> None:
    got = run[23]
    assert got["selected"] == served(NOTE_ID, site)
    fits(got["region"], NOTE_BOX)


def test_no_lanterna_viewer_no_button(site: Site, tmp_path: Path) -> None:
    steps: list[dict[str, Any]] = [
        # Mirador's own viewer has drawn the plain image (its OpenSeadragon's tiles are in)
        {"waitFor": """() => {
          const w = Object.keys(window.miradorInstance.store.getState().windows)[0];
          const v = w && Mirador.OSDReferences.get(w)?.current;
          return v && v.world.getItemCount() > 0 && v.world.getItemAt(0).getFullyLoaded();
        }"""},
        evaluate(f"""() => ({{
          buttons: document.querySelectorAll('{BUTTON}').length,
          viewer: Mirador.lanternaWindowViewer(
            Object.keys(window.miradorInstance.store.getState().windows)[0]),
        }})"""),
    ]
    result = run_page(f"{site.url}?manifest={site.plain}", steps, tmp_path, PAGE, routes=(),
                      settle=False)
    assert result["values"][1] == {"buttons": 0, "viewer": None}


def test_selecting_a_patch_focuses_it_with_its_render_state(site: Site, run: list[Any]) -> None:
    assert run[25] == 1, "pointing at the patch in Mirador's list outlines it"
    got = run[27]
    assert got["selected"] == served(PATCH_ID, site)
    assert (got["layer"], got["mode"], got["overlays"]) == ("lrgb", "specular", True), got
    assert [got["light"]["lu"], got["light"]["lv"]] == pytest.approx(PATCH_STATE["light"])
    assert got["params"]["specExponent"] == 40 and got["params"]["specKs"] == pytest.approx(0.6)
    fits(got["region"], PATCH_BOX)
