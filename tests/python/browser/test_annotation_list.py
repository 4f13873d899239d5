"""Real Chromium: a layer's individual annotations in the advanced viewer (docs/annotations.md,
"Individual annotations in the viewer"): the panel's list, the hover highlight, focusing a patch,
hiding one (the overlay is then the composite of the others) and refreshing after a rebuild.

The dataset is the lens fixture's PTM ``base`` (1024×768, 128-px tiles) and image ``second``, with
translucent patches at level 0 (three of them overlapping), published with their W3C annotation page
(tests/python/fixtures/annotation_pages.py). With an overlay at level 0 only, every view shows
level 0; fitted at 1:1, one device pixel is one level-0 pixel (docs/annotations.md, "Levels").
"""

from __future__ import annotations

import json
import subprocess
import threading
from collections.abc import Mapping
from pathlib import Path
from typing import Any

import numpy as np
import numpy.typing as npt
import pytest
import pyvips
from flask import request

from lanterna.tiler.dataset.layers import add_image_layer, add_ptm_layer
from lanterna.tiler.dataset.writer import DatasetWriter
from lanterna.tiler.iiif.pyramid import vips_from_array
from lanterna.tiler.overlays import geometry as og
from lanterna.tiler.overlays.build import build_overlays
from lanterna.tiler.overlays.composite import composite, load_rgba
from lanterna.tiler.render import level_image
from tests.python.fixtures.annotation_pages import write_annotation_page
from tests.python.fixtures.lens import TILE, VIEW, base_ptm, smooth
from tests.python.fixtures.lens import H as HEIGHT
from tests.python.fixtures.lens import W as WIDTH
from tests.python.fixtures.overlays import patch
from tests.python.fixtures.page_script import FRAME, evaluate, frame, run_page
from tests.python.fixtures.servers import LANTERNA, LiveServer

pytestmark = pytest.mark.browser

#: Fitted at 1:1 in the 256×192 view of the refresh test: one device pixel per level-0 pixel.
REGION = (120, 100, 256, 192)
LIGHT = (0.3, 0.4)
#: patch id → (colour, alpha): three overlapping translucent patches at level 0, one apart, and
#: one at level 1 (the refresh test's first overlay).
PATCHES: dict[str, tuple[tuple[int, int, int], int]] = {
    "0_130_110_120_90_0_wash": ((220, 40, 30), 150),
    "0_200_150_110_100_1_mark": ((30, 200, 60), 210),
    "0_260_180_90_80_2_dot": ((40, 60, 230), 130),
    "0_700_500_200_150_3_corner": ((250, 250, 250), 90),
    "0_600_200_80_60_4_dropped": ((200, 120, 250), 220),
    "0_-20_-10_60_40_5_edge": ((250, 140, 20), 230),  # over the top-left corner: clipped
    "1_480_360_320_240_0_region": ((240, 220, 40), 160),
}
#: A file dropped into the store at half its destination size, of one colour (so any resampling
#: keeps it): the viewer resizes it to its rectangle, as the tiler does.
DROPPED = {"0_600_200_80_60_4_dropped": (40, 30)}
LEVEL0 = [i for i in PATCHES if i.startswith("0_")]
LEVEL1 = "1_480_360_320_240_0_region"
#: What the store's records would hold (texts, author, the render state the patch was drawn under).
RECORDS: dict[str, dict[str, Any]] = {
    "0_130_110_120_90_0_wash": {
        "short": "Red wash", "long": "<p>A <b>wash</b>.</p>", "author": "Ada",
        "state": {"layer": "base", "mode": "specular",
                  "params": {"specExponent": 40, "specKs": 0.6}, "light": [0.5, -0.25]}},
    "0_200_150_110_100_1_mark": {"short": "Green mark", "author": "Bo", "motivation": "tagging"},
    "0_260_180_90_80_2_dot": {"short": "", "author": ""},
    "0_700_500_200_150_3_corner": {"short": "Corner", "author": "Ada"},
    "1_480_360_320_240_0_region": {"short": "Region", "author": "Ada"},
}
HIDDEN = "0_200_150_110_100_1_mark"
#: Each channel may differ by 1/255: the viewer blends each patch into the 8-bit frame in turn,
#: the reference blends the once-rounded 8-bit composite.
TOLERANCE = 1


def write_patches(folder: Path, ids: list[str]) -> None:
    """Each patch at exactly its destination size at its level (as the browser draws them)."""
    folder.mkdir(parents=True, exist_ok=True)
    for k, ident in enumerate(ids):
        p = og.parse_patch_name(f"{ident}.png")
        x0, y0, x1, y1 = og.destination(p)
        rgb, alpha = PATCHES[ident]
        if ident in DROPPED:
            w, h = DROPPED[ident]
            px = np.zeros((h, w, 4), np.uint8)
            px[...] = (*rgb, alpha)
        else:
            px = patch(y1 - y0, x1 - x0, rgb, alpha, seed=k)
        pyvips.Image.new_from_array(px).copy(interpretation="srgb").write_to_file(
            str(folder / f"{ident}.png"))


def make_notes(root: Path, name: str, ids: list[str]) -> Path:
    """The dataset ``root/name`` with an overlay built from the patches ``ids`` and their page."""
    rng = np.random.default_rng(11)
    with DatasetWriter(root / name, name=name, label="Notes", width=WIDTH, height=HEIGHT,
                       tile_size=TILE) as ds:
        add_ptm_layer(ds, base_ptm(rng), layer_id="base", label="Base")
        second = np.round(smooth(rng, 0.1, 0.9, (3,)) * 255).astype(np.uint8)
        add_image_layer(ds, vips_from_array(second), layer_id="second", label="Second", fmt="png")
    folder = root / f"{name}-patches"
    write_patches(folder, ids)
    report = build_overlays(root / name, "base", patches_dir=folder)
    assert not report.errors
    write_annotation_page(root / name, "base", folder, RECORDS)
    return root / name


def level_image_of(dataset: Path, level: int) -> npt.NDArray[np.uint8]:
    """Layer ``base``'s published overlay image of ``level``, read back from its tiles."""
    desc = json.loads((dataset / "lanterna.json").read_text())
    layer = next(x for x in desc["layers"] if x["id"] == "base")
    ident = next(e["image"] for e in layer["overlay"]["levels"] if e["level"] == level)
    return level_image(dataset / "iiif" / ident, 1)


def composite_of(folder: Path, ids: list[str], level: int) -> npt.NDArray[np.uint8]:
    """The tiler's composite (tiler/overlays/composite.py) of the patches ``ids`` at ``level``."""
    lw, lh = og.level_size(WIDTH, HEIGHT, level)
    items = []
    for ident in sorted(ids, key=lambda i: og.parse_patch_name(f"{i}.png").order):
        p = og.parse_patch_name(f"{ident}.png")
        placement = og.place(p, WIDTH, HEIGHT)
        assert placement is not None
        items.append((load_rgba(folder / f"{ident}.png"), placement))
    out: npt.NDArray[np.uint8] = composite(lw, lh, items)
    return out


def in_view(level0: npt.NDArray[np.uint8]) -> npt.NDArray[np.float32]:
    """A level-0 overlay image cropped to :data:`REGION`, RGBA 0–1."""
    x, y, w, h = REGION
    return (level0[y:y + h, x:x + w] / 255).astype(np.float32)


def over(base: npt.NDArray[np.uint8], ov: npt.NDArray[np.float32]) -> npt.NDArray[np.int16]:
    """Premultiplied source-over of an overlay (RGBA 0–1) on a frame read back (RGB bytes)."""
    a = ov[..., 3:4]
    out = ov[..., :3] * a * 255 + base[..., :3].astype(np.float32) * (1 - a)
    return np.round(out).astype(np.int16)


def assert_frame(got: npt.NDArray[np.uint8], expected: npt.NDArray[np.int16], what: str) -> None:
    diff = np.abs(got[..., :3].astype(np.int16) - expected).max(axis=-1)
    bad = np.argwhere(diff > TOLERANCE)
    assert bad.size == 0, (
        f"{what}: {len(bad)} pixels off by up to {diff.max()}/255, first at (row, col) "
        f"{tuple(bad[0])}: got {got[tuple(bad[0])][:3]}, expected {expected[tuple(bad[0])]}")


def page_url(server: LiveServer, name: str) -> str:
    return (f"{server.url}/viewer/?manifest={server.url}/datasets/{name}/manifest.json&layer=base"
            "&minPixelRatio=0.75&wholeLevelMaxSide=0")


#: Wait for the viewer and the list; then fit the region at 1:1 under a fixed light.
OPEN = [
    {"waitFor": "() => window.lanterna && document.querySelector('.lanterna-annotations')"},
    evaluate(f"""async () => {{
      const l = window.lanterna;
      await l.ready;
      l.setLight({LIGHT[0]}, {LIGHT[1]});
      l.showImageRegion({', '.join(map(str, REGION))});
      await l.whenFullyLoaded();
    }}"""),
]


# -- refreshing after a rebuild ------------------------------------------------------------------
def test_refresh_shows_the_rebuilt_overlay_without_a_reload(tmp_path: Path) -> None:
    """The page opens with an overlay at level 1 only; ``lanterna annotate build`` then adds the
    level-0 patches on disk; after ``refreshAnnotations()`` the same page draws the new level 0
    and lists the new patches, and told its ``onChange`` listeners."""
    level1 = [LEVEL1]
    dataset = make_notes(tmp_path, "refresh", level1)
    server = LiveServer(tmp_path)
    asked = threading.Event()
    done = threading.Event()
    failure: list[str] = []

    @server.app.before_request
    def watch() -> None:  # the page asks for the rebuild by fetching ?rebuild=now
        if request.args.get("rebuild") == "now":
            asked.set()

    def rebuild() -> None:
        if not asked.wait(300):
            return
        folder = tmp_path / "refresh-patches"
        write_patches(folder, list(PATCHES))
        proc = subprocess.run([str(LANTERNA), "annotate", "build", str(dataset), "--layer", "base",
                               "--patches", str(folder)], capture_output=True, text=True)
        if proc.returncode != 0:
            failure.append(proc.stdout + proc.stderr)
        write_annotation_page(dataset, "base", folder, RECORDS)
        done.set()

    worker = threading.Thread(target=rebuild, daemon=True)
    worker.start()
    try:
        manifest = f"{server.url}/datasets/refresh/manifest.json"
        result = run_page(page_url(server, "refresh"), [
            *OPEN,
            evaluate("""() => {
              window.__changes = 0;
              window.lanterna.onChange(() => { window.__changes++; });
              return window.lanterna.getAnnotations().map((a) => a.id);
            }"""),
            FRAME,
            evaluate(f"() => fetch('{manifest}?rebuild=now').then(() => 1)"),  # the rebuild starts
            evaluate(f"""async () => {{  // until the rebuilt manifest references the new page
              for (;;) {{
                const text = await (await fetch('{manifest}', {{ cache: 'no-store' }})).text();
                if (text.includes('base_ov0') && text.includes('/annotations/base.json')) {{
                  return true;
                }}
                await new Promise((resolve) => {{ setTimeout(resolve, 100); }});
              }}
            }}"""),
            evaluate("""async () => {
              const l = window.lanterna;
              const before = window.__changes;
              await l.refreshAnnotations();
              const base = l.manifest.layers.find((x) => x.id === 'base');
              return { changes: window.__changes - before, ids: l.getAnnotations().map((a) => a.id),
                       rows: document.querySelectorAll('.lanterna-annotation-row').length,
                       state: l.getOverlayState(), items: l.viewer.world.getItemCount(),
                       levels: base.overlays.map((o) => o.serviceId.split('/').pop()) };
            }"""),
            FRAME,
            evaluate("() => window.lanterna.setOverlaysVisible(false)"),
            FRAME,
        ], tmp_path / "page", VIEW)
    finally:
        server.close()
        worker.join(60)
    assert done.is_set() and not failure, failure
    values = result["values"]
    assert values[2] == level1
    before, after, plain = frame(values[3]), frame(values[7]), frame(values[9])
    refreshed = values[6]
    assert refreshed["changes"] >= 1
    assert refreshed["ids"] == [*LEVEL0, *level1]
    assert refreshed["rows"] == len(PATCHES)
    assert refreshed["state"]["level"] == 0 and refreshed["state"]["available"] is True
    desc = json.loads((dataset / "lanterna.json").read_text())
    levels = next(x for x in desc["layers"] if x["id"] == "base")["overlay"]["levels"]
    assert refreshed["levels"] == [e["image"] for e in levels], "the rebuilt levels, by image id"
    # the base layer and the new level 0; the level-1 item of the first build is removed
    assert refreshed["items"] == 2
    assert np.array_equal(before, plain), "before the refresh, level 0 had no overlay"
    new_level = level_image_of(dataset, 0)
    assert_frame(after, over(plain, in_view(new_level)), "the rebuilt level 0 after the refresh")
    assert np.abs(after.astype(int) - before.astype(int)).max() > 60, "the new overlay shows"


# -- the list, the highlight, focusing and hiding patches ----------------------------------------
#: The advanced page at 1280×800 with the view fitted at 1:1, the image's (0, 0) at ORIGIN.
PAGE_VIEW = (1280, 800)
ORIGIN = (128, 16)
WASH = "0_130_110_120_90_0_wash"


def row(ident: str, part: str = "") -> str:
    """The CSS selector of a patch's row in the list (or of a ``part`` of it)."""
    return f'.lanterna-annotation-row[data-id="{ident}"] {part}'.strip()


ROWS = evaluate("""() => ({
  rows: [...document.querySelectorAll('.lanterna-annotation-row')].map((r) => ({
    id: r.dataset.id, text: r.querySelector('.lanterna-annotation-text').textContent,
    meta: r.querySelector('.lanterna-annotation-meta').textContent,
    shown: r.querySelector('.lanterna-annotation-shown').checked })),
  hidden: document.querySelector('.lanterna-annotations').hidden,
  ids: window.lanterna.getAnnotations().map((a) => a.id),
  second: window.lanterna.getAnnotations('second').length,
})""")
#: The highlight boxes, their rectangles in CSS px of the viewer element.
BOXES = evaluate("""() => {
  const v = window.lanterna.viewer.element.getBoundingClientRect();
  return [...document.querySelectorAll('.lanterna-annotation-highlight')].map((b) => {
    const r = b.getBoundingClientRect();
    return [r.left - v.left, r.top - v.top, r.width, r.height];
  });
}""")


@pytest.fixture(scope="module")
def session(tmp_path_factory: pytest.TempPathFactory) -> dict[str, Any]:
    """One page through the list's uses; the values of its steps by name, and the dataset."""
    root = tmp_path_factory.mktemp("notes")
    dataset = make_notes(root, "notes", LEVEL0)
    server = LiveServer(root)
    x, y = -ORIGIN[0], -ORIGIN[1]
    named: list[tuple[str, Mapping[str, object]]] = [
        ("", OPEN[0]),
        ("", evaluate(f"""async () => {{
          const l = window.lanterna;
          await l.ready;
          l.setLight({LIGHT[0]}, {LIGHT[1]});
          l.showImageRegion({x}, {y}, {PAGE_VIEW[0]}, {PAGE_VIEW[1]});
          await l.whenFullyLoaded();
          return l.getOverlayState().level;
        }}""")),
        ("rows", ROWS),
        ("all", FRAME),
        ("", evaluate("() => window.lanterna.setOverlaysVisible(false)")),
        ("base", FRAME),
        ("", evaluate("() => window.lanterna.setOverlaysVisible(true)")),
        ("", {"click": row(HIDDEN, ".lanterna-annotation-shown")}),
        ("after-hide", ROWS),
        ("is-hidden", evaluate(f"() => window.lanterna.isAnnotationHidden('{HIDDEN}')")),
        ("hidden", FRAME),
        ("", {"click": row(HIDDEN, ".lanterna-annotation-shown")}),
        ("again", FRAME),
        ("", {"hover": row(WASH)}),
        ("hover", BOXES),
        ("", {"screenshot": str(root / "list.png")}),
        ("", {"hover": ".lanterna-annotations legend"}),
        ("left", BOXES),
        ("", evaluate("""async () => {
          const l = window.lanterna;
          await l.setActiveLayer('second');
          l.setLight(0, 0);
          return l.getAnnotations().length;
        }""")),
        ("other-layer", ROWS),
        ("", evaluate("""async () => {
          const l = window.lanterna;
          await l.setActiveLayer('base');
          l.setRenderMode('color');
          l.resetRenderParams();
          l.setLight(0, 0);
        }""")),
        ("", evaluate(f"() => document.querySelector('{row(WASH, 'button')}').focus()")),
        ("focused-box", BOXES),
        ("", {"key": "Enter"}),
        ("", {"waitFor": "() => window.lanterna.getRenderMode() === 'specular'"}),
        ("state", evaluate("""async () => {
          const l = window.lanterna;
          await l.whenFullyLoaded();
          return { state: l.getState(), focused: document.activeElement.className };
        }""")),
        ("from-other-layer", evaluate(f"""async () => {{
          const l = window.lanterna;
          await l.setActiveLayer('second');
          l.setLight(0, 0);
          await l.focusAnnotation('{WASH}');
          return {{ layer: l.getActiveLayer(), mode: l.getRenderMode(), light: l.getLight() }};
        }}""")),
    ]
    try:
        result = run_page(page_url(server, "notes"), [step for _, step in named], root / "page",
                          PAGE_VIEW)
    finally:
        server.close()
    values = {name: value for (name, _), value in zip(named, result["values"], strict=True)
              if name}
    return {"values": values, "dataset": dataset, "root": root}


def test_the_list_shows_the_active_layers_patches(session: dict[str, Any]) -> None:
    rows = session["values"]["rows"]
    assert rows["hidden"] is False and rows["ids"] == LEVEL0 and rows["second"] == 0
    assert [r["id"] for r in rows["rows"]] == LEVEL0, "in application order"
    assert [r["text"] for r in rows["rows"]] == [
        "Red wash", "Green mark", "0_260_180_90_80_2_dot", "Corner", "0_600_200_80_60_4_dropped",
        "0_-20_-10_60_40_5_edge"], "the short text, else the id"
    assert [r["meta"] for r in rows["rows"]] == ["Level 0 · Ada", "Level 0 · Bo", "Level 0",
                                                 "Level 0 · Ada", "Level 0", "Level 0"]
    assert all(r["shown"] for r in rows["rows"])
    other = session["values"]["other-layer"]
    assert other["rows"] == [] and other["ids"] == [], "a layer without patches lists none"
    assert other["hidden"] is False, "the section stays while some layer has annotations"


def test_hover_outlines_the_patch_on_screen(session: dict[str, Any]) -> None:
    p = og.parse_patch_name(f"{WASH}.png")
    expected = [p.x + ORIGIN[0], p.y + ORIGIN[1], p.w, p.h]  # 1:1, the image's (0, 0) at ORIGIN
    boxes = session["values"]["hover"]
    assert len(boxes) == 1
    assert np.allclose(boxes[0], expected, atol=2), (boxes[0], expected)
    assert session["values"]["left"] == [], "leaving the row removes the outline"
    assert len(session["values"]["focused-box"]) == 1, "focusing the row outlines it too"


def test_selecting_fits_the_patch_and_restores_its_render_state(session: dict[str, Any]) -> None:
    got = session["values"]["state"]
    state = got["state"]
    recorded = RECORDS[WASH]["state"]
    assert state["layer"] == "base" and state["mode"] == "specular"
    assert state["light"] == pytest.approx(recorded["light"], abs=1e-6)
    assert state["params"]["specExponent"] == 40 and state["params"]["specKs"] == pytest.approx(0.6)
    p = og.parse_patch_name(f"{WASH}.png")
    x, y, w, h = state["view"]
    # the rectangle fits the 1280×800 view: its height fills it, centred across
    assert h == pytest.approx(p.h, abs=0.5) and w == pytest.approx(p.h * 1.6, abs=0.5)
    assert x + w / 2 == pytest.approx(p.x + p.w / 2, abs=0.5)
    assert y == pytest.approx(p.y, abs=0.5)
    assert got["focused"] == "lanterna-annotation-focus", "the keyboard focus stays on the row"
    other = session["values"]["from-other-layer"]
    assert other["layer"] == "base" and other["mode"] == "specular", "the layer it was drawn on"
    assert [other["light"]["lu"], other["light"]["lv"]] == pytest.approx(recorded["light"])


def test_hiding_a_patch_draws_the_composite_of_the_others(session: dict[str, Any]) -> None:
    values, dataset = session["values"], session["dataset"]
    assert values["is-hidden"] is True
    assert [r["shown"] for r in values["after-hide"]["rows"]] == [r != HIDDEN for r in LEVEL0]
    base, hidden, again, shown = (frame(values[k]) for k in ("base", "hidden", "again", "all"))
    folder = session["root"] / "notes-patches"
    others = composite_of(folder, [i for i in LEVEL0 if i != HIDDEN], 0)
    assert_frame(hidden, over(base, placed(others, hidden.shape)), "with the mark hidden")
    p = og.parse_patch_name(f"{HIDDEN}.png")
    x0, y0 = p.x + ORIGIN[0], p.y + ORIGIN[1]
    diff = np.abs(hidden[y0:y0 + p.h, x0:x0 + p.w].astype(int) - shown[y0:y0 + p.h, x0:x0 + p.w])
    assert diff.max() > 100, "the hidden patch is gone"
    pyramid = level_image_of(dataset, 0)
    assert_frame(again, over(base, placed(pyramid, again.shape)), "shown again: the pyramid")
    assert np.array_equal(again, shown)


def placed(level0: npt.NDArray[np.uint8], shape: tuple[int, ...]) -> npt.NDArray[np.float32]:
    """A level-0 overlay image where the 1:1 view draws it (the image's (0, 0) at ORIGIN), 0–1."""
    out = np.zeros((shape[0], shape[1], 4), np.float32)
    h = min(level0.shape[0], shape[0] - ORIGIN[1])
    w = min(level0.shape[1], shape[1] - ORIGIN[0])
    out[ORIGIN[1]:ORIGIN[1] + h, ORIGIN[0]:ORIGIN[0] + w] = level0[:h, :w] / 255
    return out
