"""Real Chromium: the advanced viewer page (docs/viewer.md) on the lens dataset (fixtures/lens.py).

The lens's parameter sliders, saving the view as a preset and applying it, export and import of the
library, a broken import, saving to the dataset (against a fake authoring API), the Annotations
button, the URL's layer/mode fallback, the loading bar and the hidden rows of a single-layer
dataset.
"""

from __future__ import annotations

import json
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import numpy as np
import numpy.typing as npt
import pytest

from lanterna.tiler.dataset.layers import add_ptm_layer
from lanterna.tiler.dataset.writer import DatasetWriter
from tests.python.fixtures.lens import Dataset
from tests.python.fixtures.page_script import FRAME, NOTICES, READY, evaluate, frame, run_page
from tests.python.fixtures.ptm import random_ptm_of_size
from tests.python.fixtures.servers import LiveServer

pytestmark = pytest.mark.browser

VIEW = (640, 480)
#: A region of the lens dataset (1024×768) with the view's aspect, well inside the image.
REGION = (200, 150, 480, 360)


@pytest.fixture(scope="module")
def page_url(lens_dataset: Dataset) -> Iterator[str]:
    server = LiveServer(lens_dataset.root)
    try:
        manifest = f"{server.url}/datasets/lens/manifest.json"
        yield f"{server.url}/viewer/?manifest={manifest}&minPixelRatio=0.75"
    finally:
        server.close()


def slide(name: str, value: float) -> dict[str, str]:
    """Move the slider named ``name`` to ``value`` as a user would (an input event)."""
    return evaluate(f"""() => {{
      const s = document.querySelector('input[name="{name}"]');
      s.value = String({value});
      s.dispatchEvent(new Event('input', {{ bubbles: true }}));
      return Number(s.value);
    }}""")


def differs(a: npt.NDArray[np.uint8], b: npt.NDArray[np.uint8]) -> int:
    """How many pixels differ by more than 2 levels."""
    return int((np.abs(a.astype(int) - b.astype(int)).max(axis=-1) > 2).sum())


def test_lens_sliders_change_the_lens_pixels_as_set_lens_does(page_url: str,
                                                              tmp_path: Path) -> None:
    steps = [
        READY,
        evaluate(f"() => window.lanterna.showImageRegion({', '.join(map(str, REGION))})"),
        {"click": "#lens"},
        {"select": "select[name=lens-mode]", "value": "specular"},
        evaluate("() => [...document.querySelectorAll('.lanterna-lens-controls input[type=range]')]"
                 ".map((i) => i.name)"),
        slide("lens-specExponent", 20),
        slide("lens-lightIntensity", 1.7),
        FRAME,
        evaluate("() => window.lanterna.getLens().params"),
        evaluate("() => window.lanterna.setLens({ params: "
                 "{ specExponent: 75, lightIntensity: 1 } })"),
        FRAME,
        evaluate("() => window.lanterna.setLens({ params: "
                 "{ specExponent: 20, lightIntensity: 1.7 } })"),
        FRAME,
        evaluate("() => [document.querySelector('input[name=lens-specExponent]').value, "
                 "document.querySelector('.lanterna-lens-controls output').textContent]"),
    ]
    values = run_page(page_url, steps, tmp_path, VIEW)["values"]
    names = values[4]
    assert {"lens-lightIntensity", "lens-specKd", "lens-specKs", "lens-specExponent", "lens-gamma",
            "lens-brightness", "lens-opacity"} <= set(names), names
    by_slider, params = frame(values[7]), values[8]
    assert params["specExponent"] == 20 and params["lightIntensity"] == pytest.approx(1.7)
    default, by_api = frame(values[10]), frame(values[12])
    assert differs(by_slider, default) > 1000, "the sliders must change the lens"
    assert differs(by_slider, by_api) == 0
    assert values[13][0] == "20", "the slider follows setLens"


SAVE_STEPS: list[dict[str, Any]] = [
    READY,
    {"select": "select[name=mode]", "value": "specular"},
    slide("specKs", 0.3),
    {"click": "button[name=light-east]"},
    evaluate(f"() => window.lanterna.showImageRegion({', '.join(map(str, REGION))})"),
    {"fill": "input[name=preset-name]", "value": "Raking east"},
    {"click": "button[name=preset-save]"},
    FRAME,
    # Change everything the preset holds, then apply it from its list.
    evaluate("""async () => {
      const l = window.lanterna;
      l.setRenderMode('color'); l.resetRenderParams(); l.setLight(0, 0);
      l.showImageRegion(0, 0, 1024, 768);
      await l.whenFullyLoaded();
      return l.getPresetLibrary();
    }"""),
    FRAME,
    {"click": ".lanterna-preset-list[data-target=base] .lanterna-preset-apply"},
    FRAME,
    evaluate("() => [window.lanterna.getRenderMode(), window.lanterna.getRenderParams().specKs, "
             "document.querySelector('.lanterna-presets-status').textContent]"),
]


def test_save_as_preset_applies_with_the_pixels_set_by_hand(page_url: str, tmp_path: Path) -> None:
    values = run_page(page_url, SAVE_STEPS, tmp_path, VIEW)["values"]
    by_hand, changed, applied = frame(values[7]), frame(values[9]), frame(values[11])
    library = values[8]
    assert [e["label"] for e in library["base"]] == ["Raking east"]
    preset = library["presets"][library["base"][0]["preset"]]
    assert preset["mode"] == "specular" and preset["params"]["specKs"] == 0.3
    assert preset["view"] == pytest.approx(list(REGION), abs=0.01)
    assert preset["light"][0] > 0.9, "raking from the east"
    assert differs(by_hand, changed) > 1000
    assert differs(by_hand, applied) == 0
    assert values[12][:2] == ["specular", 0.3]
    assert "Raking east" in values[12][2]


def test_export_then_import_gives_the_same_library(page_url: str, tmp_path: Path) -> None:
    exported = tmp_path / "exported.json"
    steps = [
        *SAVE_STEPS[:7],
        {"download": "button[name=presets-export]", "path": str(exported)},
        evaluate("() => window.lanterna.getPresetLibrary()"),
        evaluate("() => { window.lanterna.setPresetLibrary({ type: 'LanternaPresets', version: 1, "
                 "presets: {}, base: [], lens: [] }); "
                 "return document.querySelectorAll('.lanterna-preset-apply').length; }"),
        {"files": "input[name=presets-file]", "path": str(exported)},
        {"waitFor": "() => document.querySelectorAll('.lanterna-preset-apply').length === 1"},
        evaluate("() => window.lanterna.getPresetLibrary()"),
    ]
    values = run_page(page_url, steps, tmp_path, VIEW)["values"]
    assert values[7] == "presets.json"
    before, emptied, after = values[8], values[9], values[12]
    assert emptied == 0
    doc = json.loads(exported.read_text())
    assert doc["type"] == "LanternaPresets" and doc["base"] == before["base"]
    assert after == before


BROKEN = {"type": "LanternaPresets", "version": 1,
          "presets": {"p": {"label": "P", "layer": "nope", "mode": "color"}},
          "base": [{"label": "P", "preset": "p"}], "lens": []}


def test_a_broken_import_names_the_file_and_path_and_changes_nothing(page_url: str,
                                                                    tmp_path: Path) -> None:
    broken = tmp_path / "broken-library.json"
    broken.write_text(json.dumps(BROKEN))
    garbage = tmp_path / "garbage.json"
    garbage.write_text("{not json")
    steps = [
        *SAVE_STEPS[:7],
        evaluate("() => window.lanterna.getPresetLibrary()"),
        {"drop": str(broken)},
        {"waitFor": "() => window.lanterna.getNotices().length > 0"},
        NOTICES,
        evaluate("() => window.lanterna.getPresetLibrary()"),
        {"click": ".lanterna-notice-action"},
        {"files": "input[name=presets-file]", "path": str(garbage)},
        {"waitFor": "() => window.lanterna.getNotices().length > 0"},
        NOTICES,
        evaluate("() => window.lanterna.getPresetLibrary()"),
    ]
    values = run_page(page_url, steps, tmp_path, VIEW)["values"]
    before = values[7]
    (dropped,) = values[10]["texts"]
    assert "broken-library.json" in dropped and "presets.p.layer" in dropped, dropped
    assert values[11] == before
    picked = values[15]["texts"]
    assert len(picked) == 1, "the first notice was dismissed"
    assert "garbage.json" in picked[0] and "JSON" in picked[0], picked
    assert values[16] == before


#: The presets section's status line.
STATUS = "document.querySelector('.lanterna-presets-status').textContent"


def authoring_routes() -> list[dict[str, object]]:
    put = r"/api/datasets/lens/presets$"
    return [
        {"match": r"/api/$", "body": '{"authoring": true}', "contentType": "application/json"},
        {"match": put, "status": 401, "times": 1, "contentType": "application/json",
         "headers": {"WWW-Authenticate": "Bearer"}, "body": '{"error": "wrong token"}'},
        {"match": put, "status": 200, "contentType": "application/json", "body": '{"presets": 1}'},
    ]


def test_save_to_dataset_sends_the_token_and_handles_401(page_url: str, tmp_path: Path) -> None:
    status = evaluate(f"() => [{STATUS}, "
                      "document.querySelector('.lanterna-token-row').hidden, "
                      "sessionStorage.getItem('lanterna.authoringToken')]")
    steps = [
        *SAVE_STEPS[:7],
        {"waitFor": "() => !document.querySelector('.lanterna-dataset-save').hidden"},
        {"click": "button[name=presets-save-dataset]"},
        {"fill": "input[name=authoring-token]", "value": "wrong"},
        {"click": "button[name=presets-send-token]"},
        {"waitFor": f"() => {STATUS}.includes('401')"},
        status,
        {"fill": "input[name=authoring-token]", "value": "s3cret"},
        {"key": "Enter"},
        {"waitFor": f"() => {STATUS}.startsWith('Saved')"},
        status,
        evaluate("() => { document.querySelector('.lanterna-presets-status').textContent = ''; }"),
        {"click": "button[name=presets-save-dataset]"},
        {"waitFor": f"() => {STATUS}.startsWith('Saved')"},
        status,
        evaluate("() => window.lanterna.getPresetLibrary()"),
    ]
    found = run_page(page_url, steps, tmp_path, VIEW, routes=authoring_routes(),
                     record=r"/api/datasets/[^/]+/presets",
                     allow_console_errors=["401"])
    values, requests = found["values"], found["requests"]
    assert "wrong token" in values[12][0] and values[12][1] is False and values[12][2] is None
    assert values[16][0] == 'Saved to the dataset "lens" (1 presets).' and values[16][2] == "s3cret"
    assert values[16][1] is True
    assert values[20][1] is True, "the token is not asked again"
    assert [(r["method"], r["headers"].get("authorization")) for r in requests] == [
        ("PUT", "Bearer wrong"), ("PUT", "Bearer s3cret"), ("PUT", "Bearer s3cret")]
    body = json.loads(requests[-1]["body"])
    library = values[21]
    assert body["base"] == library["base"] and body["presets"] == library["presets"]


def test_no_save_to_dataset_without_authoring(page_url: str, tmp_path: Path) -> None:
    asked = "() => document.querySelector('.lanterna-dataset-save').dataset.checked === 'true'"
    steps = [READY, evaluate(asked), *SAVE_STEPS[1:7], {"waitFor": asked},
             evaluate("() => document.querySelector('.lanterna-dataset-save').hidden")]
    found = run_page(page_url, steps, tmp_path, VIEW, record=r"/api/")
    assert found["values"][1] is False, "not asked before the library is edited"
    assert found["values"][-1] is True
    assert [r["url"].split("/", 3)[-1] for r in found["requests"]] == ["api/"]


BUTTON = evaluate("""() => {
  const b = document.getElementById('overlays');
  return { hidden: b.hidden, disabled: b.disabled, pressed: b.getAttribute('aria-pressed'),
           title: b.title,
           hypertext: document.querySelector('.lanterna-hypertext')?.textContent ?? null };
}""")


def test_annotations_button_is_disabled_on_layers_without_overlays(page_url: str,
                                                                   tmp_path: Path) -> None:
    steps = [
        READY, FRAME, BUTTON,
        {"select": "select[name=layer]", "value": "second"},
        {"waitFor": "() => window.lanterna.getActiveLayer() === 'second'"},
        BUTTON,
    ]
    values = run_page(page_url, steps, tmp_path, VIEW)["values"]
    on_base, on_second = values[2], values[5]
    assert on_base["hidden"] is False and on_base["disabled"] is False
    assert on_base["pressed"] == "true"
    assert "level" not in on_base["hypertext"].lower(), on_base["hypertext"]
    assert on_second["disabled"] is True and on_second["pressed"] == "false"
    assert "Base" in on_second["title"]


STATE = evaluate("""() => ({
  layer: window.lanterna.getActiveLayer(), mode: window.lanterna.getRenderMode(),
  panel: document.querySelectorAll('#panel select').length,
  notices: [...document.querySelectorAll('.lanterna-notice')].map((n) => n.textContent),
})""")


@pytest.mark.parametrize(("query", "word"), [("&layer=nope", "nope"), ("&mode=glossy", "glossy"),
                                             ("&layer=second&mode=specular", "specular")])
def test_an_unknown_layer_or_mode_in_the_url_falls_back_with_a_notice(
        page_url: str, tmp_path: Path, query: str, word: str) -> None:
    steps = [
        {"waitFor": "() => document.querySelector('.lanterna-presets') "
                    "&& window.lanterna.getNotices().length > 0"},
        STATE, {"click": ".lanterna-notice-action"}, STATE,
    ]
    values = run_page(page_url + query, steps, tmp_path, VIEW)["values"]
    shown, dismissed = values[1], values[3]
    assert shown["panel"] >= 4, "the panel is built"
    assert shown["mode"] == "color"
    assert shown["layer"] == ("second" if "second" in query else "base")
    (text,) = shown["notices"]
    assert word in text, text
    assert dismissed["notices"] == []


PROGRESS = evaluate("() => document.getElementById('progress').hidden")


def test_the_loading_bar_shows_while_tiles_load_and_failures_show_a_notice(
        page_url: str, tmp_path: Path) -> None:
    routes = [{"match": r"/iiif/second[^/]*/", "hang": True}]
    steps = [
        READY, FRAME, PROGRESS,
        {"select": "select[name=layer]", "value": "second"},
        {"waitFor": "() => window.lanterna.getActiveLayer() === 'second'"},
        evaluate("() => new Promise((r) => requestAnimationFrame(() => requestAnimationFrame(r)))"),
        PROGRESS,
        # The hung tiles time out: the viewer's notice says so and the bar goes.
        evaluate("() => { window.lanterna.viewer.imageLoader.timeout = 500; "
                 "window.lanterna.viewer.forceRedraw(); }"),
        {"select": "select[name=layer]", "value": "base"},
        {"select": "select[name=layer]", "value": "second"},
        {"waitFor": "() => window.lanterna.getNotices().some((n) => n.kind === 'tiles-failed')"},
        NOTICES,
    ]
    values = run_page(page_url, steps, tmp_path, VIEW, routes=[*routes, {
        "match": r"/api/$", "body": '{"authoring": false}', "contentType": "application/json"}],
        allow_console_errors=["."], settle=False)["values"]
    assert values[2] is True, "loaded: no bar"
    assert values[6] is False, "the bar shows while the new layer's tiles load"
    assert any("could not be loaded" in t for t in values[11]["texts"]), values[11]


@pytest.fixture(scope="module")
def single_layer(tmp_path_factory: pytest.TempPathFactory) -> Iterator[str]:
    root = tmp_path_factory.mktemp("single")
    label = "One layer, a long title that has to be cut short on a phone because it is far too long"
    with DatasetWriter(root / "one", name="one", label=label, width=300, height=200,
                       tile_size=256) as ds:
        add_ptm_layer(ds, random_ptm_of_size(300, 200, seed=3), layer_id="ptm", label="Tablet")
    manifest = root / "one" / "manifest.json"
    doc = json.loads(manifest.read_text())
    doc["summary"] = {"en": ["<p>A <b>tablet</b>.<script>window.bad = 1</script></p>"]}
    doc["metadata"] = [{"label": {"en": ["Material"]}, "value": {"en": ["Limestone"]}}]
    doc["requiredStatement"] = {"label": {"en": ["Attribution"]}, "value": {"en": ["Museum X"]}}
    doc["rights"] = "http://creativecommons.org/licenses/by/4.0/"
    manifest.write_text(json.dumps(doc))
    server = LiveServer(root)
    try:
        yield f"{server.url}/viewer/?manifest={server.url}/datasets/one/manifest.json"
    finally:
        server.close()


def test_a_single_layer_dataset_hides_the_layer_and_annotation_rows(single_layer: str,
                                                                    tmp_path: Path) -> None:
    shown = evaluate("""() => {
      const visible = (el) => el !== null && el.getClientRects().length > 0;
      const row = (name) => document.querySelector(`select[name="${name}"]`).closest('label');
      return {
        layer: visible(row('layer')), lensLayer: visible(row('lens-layer')),
        lensAnnotations: visible(row('lens-annotations')),
        overlays: visible(document.getElementById('overlays')),
        mode: visible(row('mode')),
        about: document.querySelector('.lanterna-about').textContent, bad: window.bad ?? null,
        bold: document.querySelector('.lanterna-about-summary b')?.textContent ?? null,
      };
    }""")
    values = run_page(single_layer, [READY, shown, FRAME], tmp_path, VIEW)["values"]
    got = values[1]
    assert got["mode"] is True
    assert (got["layer"], got["lensLayer"], got["lensAnnotations"], got["overlays"]) == (False,) * 4
    for text in ("Limestone", "Museum X", "creativecommons.org", "tablet"):
        assert text in got["about"]
    assert got["bold"] == "tablet" and got["bad"] is None and "window.bad" not in got["about"]


def test_every_control_is_reached_by_tab_with_a_focus_ring(page_url: str, tmp_path: Path) -> None:
    tab = evaluate("""() => {
      const el = document.activeElement;
      const style = getComputedStyle(el);
      return [el.id || el.getAttribute('name') || el.className || el.outerHTML.slice(0, 12),
        style.outlineStyle !== 'none'
        && parseFloat(style.outlineWidth) >= 2];
    }""")
    steps: list[dict[str, Any]] = [READY, {"click": "#lens"},
                                   evaluate("() => document.body.focus()")]
    for _ in range(60):
        steps += [{"key": "Tab"}, tab]
    values = run_page(page_url, steps, tmp_path, VIEW)["values"][4::2]
    reached = {name for name, _ in values}
    for name in ("panel-toggle", "mode", "home", "zoom-in", "zoom-out", "lens", "overlays", "layer",
                 "gamma", "light-north", "lens-mode", "lens-opacity",
                 "preset-name", "preset-save", "presets-export", "presets-import"):
        assert name in reached, (name, reached)
    # (after the last control the focus leaves the page: the body)
    unringed = [name for name, ring in values if not ring and not name.startswith("<body")]
    assert unringed == []
