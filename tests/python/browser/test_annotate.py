"""Real Chromium on a real ``lanterna serve`` with a token: the Annotate toolbox (docs/viewer.md
"Annotating", docs/annotations.md "Drawing in the viewer").

Strokes drawn with an emulated mouse, finger and pen change the drawing canvas; undo and redo
(buttons and keys) give back exactly the earlier pixels; Download saves ``L_X_Y_W_H_O_INFO.png``
whose pixels are the canvas's; a wrong token stores nothing; Upload sends the patch, and once the
status says the new build is served, the level image read through IIIF from the server holds the
canvas pixels exactly in the patch's rectangle (a single patch is composited without resampling)
and nothing elsewhere, and the viewer shows it without a reload.
"""

from __future__ import annotations

import base64
import io
import json
import urllib.request
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import numpy as np
import numpy.typing as npt
import pytest
from PIL import Image

from lanterna.cli import main
from lanterna.tiler.dataset.layers import add_ptm_layer
from lanterna.tiler.dataset.plane_format import parse_plane_format
from lanterna.tiler.dataset.writer import DatasetWriter
from tests.python.fixtures.page_script import (
    FRAME,
    NO_AUTHORING,
    READY,
    evaluate,
    frame,
    run_page,
)
from tests.python.fixtures.ptm import random_ptm_of_size
from tests.python.fixtures.servers import lanterna_serve

pytestmark = pytest.mark.browser

W, H = 700, 500
VIEW = (1000, 700)
TOKEN = "annotate-token-0123456789abcdef"

#: The drawing canvas's pixels (RGBA, base64), size and place.
CANVAS = evaluate("""() => {
  const c = document.querySelector('.lanterna-draw-surface');
  const data = c.getContext('2d').getImageData(0, 0, c.width, c.height).data;
  let s = '';
  for (let i = 0; i < data.length; i += 0x8000) {
    s += String.fromCharCode.apply(null, data.subarray(i, i + 0x8000));
  }
  const r = c.getBoundingClientRect();
  return { width: c.width, height: c.height, base64: btoa(s),
           rect: [r.left, r.top, r.width, r.height] };
}""")
#: What the viewer shows: the level, the region in view, the canvas size.
VIEWED = evaluate("""() => {
  const l = window.lanterna;
  const v = l.viewer.element.getBoundingClientRect();
  return { level: l.getOverlayState().level, available: l.getOverlayState().available,
           region: l.getImageRegion(), view: l.getState().view,
           element: [v.left, v.top, v.width, v.height] };
}""")
#: The rows (CSS px of the canvas) of the light and the hard pen stroke.
PEN_Y = (450, 560)
TOKEN_ROW = ".lanterna-annotate .lanterna-token-row"
#: Once the view has stopped moving: the region in view and where the drawing canvas is.
PLACED = evaluate("""async () => {
  const l = window.lanterna;
  const nextFrame = () => new Promise((r) => { requestAnimationFrame(r); });
  let last = '';
  for (let k = 0; k < 600 && JSON.stringify(l.getState().view) !== last; k++) {
    last = JSON.stringify(l.getState().view);
    await nextFrame();
    await nextFrame();
  }
  const r = document.querySelector('.lanterna-draw-surface').getBoundingClientRect();
  return { view: l.getState().view, rect: [r.left, r.top, r.width, r.height] };
}""")
STATUS = "document.querySelector('.lanterna-annotate-status').textContent"


@pytest.fixture(scope="module")
def served(tmp_path_factory: pytest.TempPathFactory) -> Iterator[tuple[str, Path]]:
    scratch = tmp_path_factory.mktemp("annotate")
    root = scratch / "root"
    with DatasetWriter(root / "obj", name="obj", label="Object", width=W, height=H) as ds:
        add_ptm_layer(ds, random_ptm_of_size(W, H), layer_id="ptm",
                      plane_format=parse_plane_format("png"))
    # An overview annotation at the home level (2), as a GIMP user makes it: the toolbox's patch
    # is drawn one level finer, whose image it then is alone.
    gimp = scratch / "gimp"
    gimp.mkdir()
    overview = np.zeros((-(-H // 4), -(-W // 4), 4), np.uint8)
    overview[10:30, 10:60] = (255, 255, 0, 200)
    Image.fromarray(overview, "RGBA").save(gimp / "level_2.png")
    assert main(["annotate", "build", str(root / "obj"), "--layer", "ptm", "--gimp",
                 str(gimp)]) == 0
    token = scratch / "token"
    token.write_text(TOKEN + "\n")
    with lanterna_serve(root, "--authoring-token-file", str(token)) as (url, _):
        yield url, root


def page(url: str) -> str:
    return f"{url}/viewer/?manifest={url}/datasets/obj/manifest.json&minPixelRatio=0.75"


def rgba(value: dict[str, Any]) -> npt.NDArray[np.uint8]:
    raw = np.frombuffer(base64.b64decode(value["base64"]), np.uint8)
    return raw.reshape(int(value["height"]), int(value["width"]), 4)


def expected_frame(region: list[float], level: int) -> tuple[int, int, int, int, int, int]:
    """The patch for the region in view at ``level``, computed here from docs/annotations.md:
    grown to whole level pixels, clipped to the canvas; (X, Y, W, H, width, height)."""
    s = 2 ** level
    x = max(0, int(np.floor(region[0] / s)) * s)
    y = max(0, int(np.floor(region[1] / s)) * s)
    x1 = min(W, int(np.ceil((region[0] + region[2]) / s)) * s)
    y1 = min(H, int(np.ceil((region[1] + region[3]) / s)) * s)
    width = int(np.ceil(x1 / s)) - x // s
    height = int(np.ceil(y1 / s)) - y // s
    return x, y, x1 - x, y1 - y, width, height


def screen_rect(image_rect: list[int], view: list[float]) -> list[float]:
    """``image_rect`` (full-resolution px) in CSS px of the page's viewer (at 0, 0, VIEW) showing
    the image region ``view``."""
    sx, sy = VIEW[0] / view[2], VIEW[1] / view[3]
    return [(image_rect[0] - view[0]) * sx, (image_rect[1] - view[1]) * sy,
            image_rect[2] * sx, image_rect[3] * sy]


def drag(kind: str, a: tuple[float, float], b: tuple[float, float], **extra: Any) -> dict[str, Any]:
    """A drag on the drawing canvas from ``a`` to ``b`` (CSS px from its top left corner)."""
    if kind == "touch":
        extra = {"from": [list(a)], "to": [list(b)], **extra}
    return {"gesture": {"type": kind, "from": list(a), "to": list(b), "steps": 10, **extra},
            "on": ".lanterna-draw-surface"}


def click(name: str) -> dict[str, str]:
    return {"click": f".lanterna-annotate button[name={name}]"}


#: The region shown before annotating: about twice the home zoom, so one level finer than home.
REGION = (200, 150, 300, 210)


def overlay_image(url: str, level: int) -> npt.NDArray[np.uint8]:
    """Level ``level`` of layer ptm's overlay, read through IIIF from the server (``full/max``)."""
    with urllib.request.urlopen(f"{url}/datasets/obj/manifest.json", timeout=60) as resp:
        manifest = json.loads(resp.read())
    pages = manifest["items"][0]["annotations"]
    bodies = [body for p in pages for a in p.get("items", []) for body in (
        a["body"] if isinstance(a["body"], list) else [a["body"]])
        if body.get("type") == "Image" and any(
            s.get("type") == "LanternaOverlayLevel" and s.get("level") == level
            for s in body.get("service", []))]
    assert len(bodies) == 1, f"one level-{level} image in the manifest"
    with urllib.request.urlopen(bodies[0]["id"], timeout=60) as resp:
        with Image.open(io.BytesIO(resp.read())) as img:
            assert img.mode == "RGBA"
            return np.asarray(img).copy()


def test_strokes_undo_redo_download_and_upload_give_the_served_overlay(
        served: tuple[str, Path], tmp_path: Path) -> None:
    url, root = served
    png = tmp_path / "download.png"
    steps: list[dict[str, Any]] = [
        READY,
        {"waitFor": "() => document.getElementById('annotate').dataset.checked === 'true'"},
        evaluate("() => !document.getElementById('annotate').hidden"),   # 2
        evaluate(f"() => window.lanterna.showImageRegion({', '.join(map(str, REGION))})"),
        FRAME,                                                            # 4: before
        VIEWED,                                                           # 5
        {"click": "#annotate"},
        CANVAS,                                                           # 7: empty
        drag("mouse", (300, 100), (600, 250)),
        CANVAS,                                                           # 9: mouse
        {"select": ".lanterna-annotate select[name=annotate-size]", "value": "16"},
        {"click": ".lanterna-annotate button[name=annotate-color][value='#0a84ff']"},
        drag("touch", (320, 400), (640, 150)),
        CANVAS,                                                           # 13: + touch
        {"click": ".lanterna-annotate button[name=annotate-color][value='#34c759']"},
        {"select": ".lanterna-annotate select[name=annotate-size]", "value": "4"},
        drag("pen", (300, PEN_Y[0]), (640, PEN_Y[0]), pressure=0.2),
        drag("pen", (300, PEN_Y[1]), (640, PEN_Y[1]), pressure=1),
        CANVAS,                                                           # 18: + 2 pen strokes
        click("annotate-undo"), click("annotate-undo"),
        CANVAS,                                                           # 21 = 13
        {"key": "Control+z"},
        CANVAS,                                                           # 23 = 9
        click("annotate-redo"),
        CANVAS,                                                           # 25 = 13
        {"key": "Control+Shift+z"}, {"key": "Control+y"},
        CANVAS,                                                           # 28 = 18
        {"key": "Control+y"},
        CANVAS,                                                           # 30 = 18 (no more)
        {"click": ".lanterna-annotate summary"},
        {"fill": ".lanterna-annotate input[name=annotate-short]", "value": "Crack, upper left"},
        {"download": ".lanterna-annotate button[name=annotate-download]", "path": str(png)},  # 33
        VIEWED,                                                           # 34: while annotating
        click("annotate-upload"),
        {"waitFor": f"() => !document.querySelector('{TOKEN_ROW}').hidden"},
        {"fill": ".lanterna-annotate input[name=authoring-token]", "value": "not-the-token-at-all"},
        click("annotate-send-token"),
        {"waitFor": f"() => {STATUS}.includes('401')"},
        evaluate(f"() => {STATUS}"),                                      # 40
        {"fill": ".lanterna-annotate input[name=authoring-token]", "value": TOKEN},
        click("annotate-send-token"),
        {"waitFor": f"() => {STATUS}.includes('is shown')"},
        evaluate(f"() => {STATUS}"),                                      # 44
        VIEWED,                                                           # 45
        FRAME,                                                            # 46: after
        {"click": "#zoom-in"},
        PLACED,                                                           # 48
        evaluate("() => [window.lanterna.getLight(), window.lanterna.getRenderMode()]"),  # 49
        {"click": "button[name=light-west]"},
        {"select": "select[name=mode]", "value": "specular"},
        evaluate("() => [window.lanterna.getLight(), window.lanterna.getRenderMode(), "
                 "!!document.querySelector('.lanterna-draw-surface')]"),  # 52
    ]
    found = run_page(page(url), steps, tmp_path, VIEW, routes=(), allow_console_errors=["401"])
    v = found["values"]
    assert v[2] is True, "the server allows authoring: the button shows"
    viewed = v[5]
    level = viewed["level"]
    assert level == 1, "twice the home zoom: one level finer than the overview's"
    x, y, w, h, width, height = expected_frame(viewed["region"], level)
    assert (x, y) != (0, 0) and (x + w, y + h) != (W, H), "the patch is part of the canvas"
    canvases = {k: rgba(v[k]) for k in (7, 9, 13, 18, 21, 23, 25, 28, 30)}
    assert canvases[7].shape == (height, width, 4)
    assert not canvases[7].any(), "the canvas starts transparent"
    rect = v[7]["rect"]
    s = 2 ** level
    x0, y0 = x // s, y // s
    on_screen = [x0 * s, y0 * s, width * s, height * s]
    assert rect == pytest.approx(screen_rect(on_screen, viewed["view"]), abs=0.01)
    assert rect[2] > 650 and rect[3] > 600, "the strokes fall on the canvas, clear of the toolbox"
    # each stroke changed the drawing
    assert canvases[9][..., 3].any()
    assert not np.array_equal(canvases[9], canvases[13])
    assert not np.array_equal(canvases[13], canvases[18])
    # undo and redo give back exactly the earlier pixels
    assert np.array_equal(canvases[21], canvases[13])
    assert np.array_equal(canvases[23], canvases[9])
    assert np.array_equal(canvases[25], canvases[13])
    assert np.array_equal(canvases[28], canvases[18])
    assert np.array_equal(canvases[30], canvases[18])
    drawing = canvases[18]
    # the pen's pressure: the light stroke is thinner than the hard one
    pen = drawing.astype(int) - canvases[13].astype(int)
    to_x = width / rect[2]
    cols = slice(int(450 * to_x), int(550 * to_x))
    split = int(sum(PEN_Y) / 2 * height / rect[3])
    thickness = [int((np.abs(pen[:, cols]).sum(axis=2) > 0)[rows].sum(axis=0).max())
                 for rows in (slice(0, split), slice(split, None))]
    assert 0 < thickness[0] < thickness[1], thickness
    # the download: its name and pixels
    name = f"{level}_{x}_{y}_{w}_{h}_1_Crack-upper-left.png"  # on top of the overview's order 0
    assert v[33] == name
    with Image.open(png) as img:
        assert img.mode == "RGBA"
        assert np.array_equal(np.asarray(img), drawing)
    # while annotating, the view stays where it was
    assert v[34]["view"] == pytest.approx(viewed["view"], abs=1e-6)
    # the wrong token: refused, nothing stored
    assert "401" in v[40]
    # the upload: the served level image is the drawing in the patch's rectangle, clear elsewhere
    assert "is shown" in v[44]
    store = sorted(p.name for p in (root / "obj.annotations" / "ptm").glob("*.png"))
    assert store == sorted([name, f"2_0_0_{W}_{H}_0_level.png"])
    served_level = overlay_image(url, level)
    assert served_level.shape == (-(-H // s), -(-W // s), 4)
    assert np.array_equal(served_level[y0:y0 + height, x0:x0 + width], drawing)
    outside = served_level.copy()
    outside[y0:y0 + height, x0:x0 + width] = 0
    assert not outside.any()
    # the viewer shows it without a reload: the pixels change where the strokes are, only there
    assert v[5]["available"] is False, "no level-1 overlay before the upload"
    assert v[45]["available"] is True and v[45]["level"] == level
    before, after = frame(v[4]).astype(int), frame(v[46]).astype(int)
    changed = np.abs(after - before).sum(axis=2) > 0
    ox, oy = int(rect[0]), int(rect[1])
    assert changed[oy + 175, ox + 450], "the middle of the mouse stroke"
    assert changed[oy + PEN_Y[1], ox + 470], "the hard pen stroke"
    assert not changed[:, ox + 700:].any(), "nothing drawn right of the strokes"
    # the canvas follows the view: zoomed in with the toolbar, it lies on the same image pixels
    placed = v[48]
    assert placed["view"] != viewed["view"]
    assert placed["rect"] == pytest.approx(screen_rect(on_screen, placed["view"]), abs=0.01)
    assert placed["rect"][2] == pytest.approx(rect[2] * 1.5, rel=1e-3)
    # the panel's light and mode still work while annotating
    assert v[52][0] != v[49][0] and v[49][1] == "color" and v[52][1:] == ["specular", True]


def test_without_authoring_there_is_no_annotate_button_and_no_status_reads(
        served: tuple[str, Path], tmp_path: Path) -> None:
    url, _ = served
    steps: list[dict[str, Any]] = [
        READY,
        {"waitFor": "() => document.getElementById('annotate').dataset.checked === 'true'"},
        evaluate("() => document.getElementById('annotate').hidden"),
    ]
    found = run_page(page(url), steps, tmp_path, VIEW, routes=(NO_AUTHORING,), record=r"/api/")
    assert found["values"][-1] is True
    assert [r["url"] for r in found["requests"]] == [f"{url}/api/"]
