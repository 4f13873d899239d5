"""Lanterna in a page's own OpenSeadragon 6 viewer (``attachLanterna``, docs/embedding.md).

The example page ``/viewer/embed.html``, served by ``lanterna serve``, makes a plain OpenSeadragon
viewer with its own navigation buttons, navigator and image, and attaches Lanterna to it. In real
Chromium: the page's viewer gets the manifest's layer and relights it within 2/255 of the numpy
reference at two lights; the page's own zoom button zooms the Lanterna view; ``destroy()`` leaves
the page's viewer drawing its own image with a standard drawer, without Lanterna's items, widgets or
handlers; attaching again works the same.
"""

from __future__ import annotations

import base64
from collections.abc import Iterator
from pathlib import Path
from typing import Any
from urllib.parse import quote

import numpy as np
import numpy.typing as npt
import pytest
import pyvips

from lanterna.tiler.dataset.layers import add_ptm_layer
from lanterna.tiler.dataset.writer import DatasetWriter
from tests.python.fixtures.page_script import FRAME, evaluate, frame, run_page
from tests.python.fixtures.pixels import assert_pixels_close
from tests.python.fixtures.ptm_relight import TOLERANCE, H, W, numpy_relight, smooth_random_ptm
from tests.python.fixtures.servers import lanterna_serve

pytestmark = pytest.mark.browser

VIEW = (640, 480)
#: Two lights, each read back over the same image region (zoom 1: one image px per screen px).
LIGHTS = [(-0.7, 0.2), (0.5, -0.6)]
REGION = (130, 100, *VIEW)
#: The page's own image: one flat colour, so that what its standard drawer draws can be checked.
HOST_RGB = (40, 170, 220)

#: What the page's viewer holds, and what of Lanterna is in it (drawer, items, widgets, handlers).
STATE = """() => {
  const v = window.hostViewer;
  const counts = (source) => Object.fromEntries(
    Object.entries(source.events).map(([k, e]) => [k, e.length]));
  const items = [];
  for (let i = 0; i < v.world.getItemCount(); i++) {
    const item = v.world.getItemAt(i);
    const name = item.source.constructor.name;
    const lanterna = name === 'BundleTileSource' || name === 'PatchTileSource';
    items.push([lanterna ? name : 'page', item.getOpacity()]);
  }
  return {
    drawer: v.drawer.getType(),
    items,
    navigatorItems: v.navigator.world.getItemCount(),
    lanternaElements: v.element.querySelectorAll('[class*="lanterna"]').length,
    canvases: v.canvas.querySelectorAll('canvas').length,
    viewerHandlers: counts(v),
    worldHandlers: counts(v.world),
    zoomButtons: v.element.querySelectorAll('[title="Zoom in"]').length,
  };
}"""

#: Once the page's own image is fully loaded: the colour its drawer drew at the view's centre.
HOST_PIXEL = """async () => {
  const v = window.hostViewer;
  const item = v.world.getItemAt(0);
  if (!item.getFullyLoaded()) {
    await new Promise((resolve) => { item.addOnceHandler('fully-loaded-change', resolve); });
  }
  v.forceRedraw();
  for (let i = 0; i < 3; i++) {
    await new Promise((resolve) => { requestAnimationFrame(resolve); });
  }
  const source = v.drawer.canvas;
  const copy = document.createElement('canvas');
  copy.width = source.width;
  copy.height = source.height;
  const ctx = copy.getContext('2d');
  ctx.drawImage(source, 0, 0);
  const [x, y] = [Math.floor(source.width / 2), Math.floor(source.height / 2)];
  return [...ctx.getImageData(x, y, 1, 1).data];
}"""

READY = evaluate(
    "async () => { await window.lanterna.ready; await window.lanterna.whenFullyLoaded(); }")


def shot(light: tuple[float, float]) -> dict[str, str]:
    """A step setting the light and fitting :data:`REGION` to the view."""
    return evaluate(f"""async () => {{
      const l = window.lanterna;
      l.setLight({light[0]}, {light[1]});
      l.showImageRegion({", ".join(map(str, REGION))});
    }}""")


#: The region shown before and after a click on the page's own zoom-in button (two steps).
REGION_NOW = evaluate("""async () => {
  const l = window.lanterna;
  await l.whenFullyLoaded();
  return { region: l.getImageRegion(), zoom: l.viewer.viewport.getZoom(true),
           target: l.viewer.viewport.getZoom(false) };
}""")


def host_image_url() -> str:
    """A flat :data:`HOST_RGB` PNG as a data URL (the page's own image)."""
    png = (pyvips.Image.black(64, 48) + list(HOST_RGB)).cast("uchar").pngsave_buffer()
    return "data:image/png;base64," + base64.b64encode(png).decode()


@pytest.fixture(scope="module")
def run(tmp_path_factory: pytest.TempPathFactory) -> Iterator[dict[str, Any]]:
    """The example page's steps, run once: attached, relit, zoomed, destroyed, attached again."""
    tmp = tmp_path_factory.mktemp("embed")
    root = tmp / "root"
    with DatasetWriter(root / "obj", name="obj", label="Random PTM", width=W, height=H) as ds:
        layer = add_ptm_layer(ds, smooth_random_ptm("lrgb", seed=11))
    steps: list[dict[str, str]] = [
        {"waitFor": "() => window.lanterna && window.hostViewer"},
        READY, evaluate(STATE)]
    for light in LIGHTS:
        steps += [shot(light), FRAME]
    steps += [shot(LIGHTS[0]), REGION_NOW, {"click": '[title="Zoom in"]'}, REGION_NOW,
              {"click": "#toggle"}, evaluate(STATE), evaluate(HOST_PIXEL),
              {"click": "#toggle"}, READY, evaluate(STATE), shot(LIGHTS[1]), FRAME,
              {"click": "#toggle"}, evaluate(STATE), evaluate(HOST_PIXEL)]
    with lanterna_serve(root) as (url, _):
        page = (f"{url}/viewer/embed.html?manifest={quote(url + '/datasets/obj/manifest.json')}"
                f"&image={quote(host_image_url(), safe='')}")
        found = run_page(page, steps, tmp / "page", viewport=VIEW, routes=(), settle=False)
    values = found["values"]
    names = ["wait", "ready", "attached", "shot0", "frame0", "shot1", "frame1", "shot", "before",
             "click", "after", "off", "detached", "host", "on", "ready2", "reattached", "shot2",
             "frame2", "off2", "detached2", "host2"]
    yield {"layer": layer, "root": root, **dict(zip(names, values, strict=True))}


def reference(run: dict[str, Any], light: tuple[float, float]) -> npt.NDArray[np.int16]:
    """The numpy relight of :data:`REGION` at zoom 1, in 0–255."""
    ref = numpy_relight(run["root"] / "obj", run["layer"], 1, light)
    x, y, w, h = REGION
    return np.round(ref[y: y + h, x: x + w] * 255.0).astype(np.int16)


def assert_matches(got: npt.NDArray[np.uint8], expected: npt.NDArray[np.int16], what: str) -> None:
    """The frame equals the reference within :data:`TOLERANCE`, and is opaque."""
    assert got.shape[:2] == expected.shape[:2]
    assert (got[..., 3] == 255).all(), f"{what}: the image area must be opaque"
    assert_pixels_close(got, expected, TOLERANCE, what)


def test_the_pages_own_viewer_gets_the_lanterna_drawer_and_layer(run: dict[str, Any]) -> None:
    state = run["attached"]
    assert state["drawer"] == "lanterna"
    # the page's image stays in the world, hidden; the layer is Lanterna's bundle item
    assert state["items"] == [["page", 0], ["BundleTileSource", 1]]
    assert state["navigatorItems"] == 2
    assert state["zoomButtons"] == 1
    assert state["lanternaElements"] > 0  # the light widget and notices


@pytest.mark.parametrize("index", [0, 1])
def test_it_is_relit_like_the_numpy_reference(run: dict[str, Any], index: int) -> None:
    expected = reference(run, LIGHTS[index])
    assert expected.std() > 10  # not a flat picture
    assert_matches(frame(run[f"frame{index}"]), expected, f"light {LIGHTS[index]}")


def test_the_two_lights_differ(run: dict[str, Any]) -> None:
    a, b = (frame(run[f"frame{i}"])[..., :3].astype(np.int16) for i in (0, 1))
    assert np.abs(a - b).mean() > 5


def test_the_pages_own_zoom_button_zooms_the_lanterna_view(run: dict[str, Any]) -> None:
    before, after = run["before"], run["after"]
    assert before["region"] == [float(v) for v in REGION]
    assert after["zoom"] == pytest.approx(after["target"])  # settled
    # how far one press zooms depends on how long OpenSeadragon's button saw it pressed: only more
    ratio = after["zoom"] / before["zoom"]
    assert ratio > 1.05
    x, y, w, h = before["region"]
    ax, ay, aw, ah = after["region"]
    assert (aw, ah) == pytest.approx((w / ratio, h / ratio), abs=0.02)
    # about the same centre
    assert (ax + aw / 2, ay + ah / 2) == pytest.approx((x + w / 2, y + h / 2), abs=0.5)


@pytest.mark.parametrize("key", ["detached", "detached2"])
def test_destroy_gives_the_page_its_viewer_back(run: dict[str, Any], key: str) -> None:
    state = run[key]
    assert state["drawer"] in ("webgl", "canvas")
    assert state["items"] == [["page", 1]]  # its opacity back
    assert state["navigatorItems"] == 1
    assert state["lanternaElements"] == 0
    assert state["zoomButtons"] == 1


@pytest.mark.parametrize("key", ["host", "host2"])
def test_the_standard_drawer_draws_the_pages_own_image_again(run: dict[str, Any], key: str) -> None:
    r, g, b, a = run[key]
    assert a == 255
    assert np.abs(np.array([r, g, b]) - np.array(HOST_RGB)).max() <= TOLERANCE


def test_no_handler_is_left_behind_by_an_attach_and_destroy(run: dict[str, Any]) -> None:
    first, second = run["detached"], run["detached2"]
    assert second["viewerHandlers"] == first["viewerHandlers"]
    assert second["worldHandlers"] == first["worldHandlers"]


def test_attaching_again_relights_as_before(run: dict[str, Any]) -> None:
    assert run["reattached"]["drawer"] == "lanterna"
    assert run["reattached"]["items"] == [["page", 0], ["BundleTileSource", 1]]
    assert_matches(frame(run["frame2"]), reference(run, LIGHTS[1]), "attached again")


def test_destroy_before_ready_leaves_the_page_its_viewer(tmp_path: Path) -> None:
    """Attached and destroyed in one go (the manifest not fetched yet): ``ready`` says so in one
    line and the page's viewer is as before."""
    root = tmp_path / "root"
    with DatasetWriter(root / "obj", name="obj", label="Random PTM", width=W, height=H) as ds:
        add_ptm_layer(ds, smooth_random_ptm("lrgb", seed=3))
    # off, on and off again in one task: the new viewer is destroyed before anything could load
    toggle = """async () => {
      await window.lanterna.ready;
      const button = document.getElementById('toggle');
      button.click();
      button.click();
      const quick = window.lanterna;
      button.click();
      const error = await quick.ready.then(() => null, (e) => [e.name, e.message]);
      for (let i = 0; i < 3; i++) {
        await new Promise((resolve) => { requestAnimationFrame(resolve); });
      }
      return [error, document.getElementById('status').hidden];
    }"""
    with lanterna_serve(root) as (url, _):
        page = (f"{url}/viewer/embed.html?manifest={quote(url + '/datasets/obj/manifest.json')}"
                f"&image={quote(host_image_url(), safe='')}")
        values = run_page(page, [
            {"waitFor": "() => window.lanterna && window.hostViewer"},
            evaluate(toggle), evaluate(STATE), evaluate(HOST_PIXEL),
        ], tmp_path / "page", viewport=VIEW, routes=(), settle=False)["values"]
    error, status_hidden = values[1]
    assert error == ["LanternaError", "the viewer was destroyed before it was ready"]
    assert status_hidden is True  # the page does not report a viewer it destroyed itself
    state = values[2]
    assert state["items"] == [["page", 1]]
    assert state["navigatorItems"] == 1
    assert state["lanternaElements"] == 0
    assert state["drawer"] in ("webgl", "canvas")
    assert np.abs(np.array(values[3][:3]) - np.array(HOST_RGB)).max() <= TOLERANCE
