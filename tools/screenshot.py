"""Retake the README's screenshots from the demo dataset, in headless Chromium.

Usage: ``.venv/bin/python tools/screenshot.py [--root datasets] [--out-dir docs]``
(``make screenshot``).
Builds the demo dataset if it is missing. Writes, in ``--out-dir``:

- ``screenshot.png``: the advanced viewer (1280×800): the demo's first base preset (raking light),
  its infrared lens preset over the inscription, the panel open at its presets;
- ``screenshot-simple.png``: the simplified viewer at a kiosk's 1920×1080, the lens on;
- ``screenshot-phone.png``: the advanced viewer on a 390×844 touch screen, the panel collapsed;
- ``screenshot-annotate.png``: the advanced viewer (1280×800) annotating the gold rosette under
  specular enhancement, zoomed in to level 0: a drawing in progress (not uploaded: the demo is
  left as it was), the toolbox, the layer's annotations in the panel. The server allows
  authoring for it (a throw-away token);
- ``screenshot-mirador.png``: Mirador 4 with the Lanterna plugins (1440×900), two windows of the
  demo side by side (a comparison): the left one under the first base preset with its Lanterna
  controls open, the right one on the infrared band with Mirador's annotation panel listing the
  overlay levels.
"""

from __future__ import annotations

import argparse
import json
import logging
import math
import secrets
import subprocess
import tempfile
import threading
from pathlib import Path
from typing import Any

from werkzeug.serving import make_server

from lanterna.server.app import create_app
from lanterna.tiler.demo.dataset import build_demo, demo_is_current

REPO = Path(__file__).resolve().parents[1]
DRIVER = REPO / "tests" / "browser" / "page-script.mjs"
READY = "() => window.lanterna !== undefined && window.lanterna.manifest !== null"
SETTLE = "async () => { await window.lanterna.whenFullyLoaded(); return true; }"


#: Both Mirador windows have their Lanterna viewer, ready.
MIRADOR_READY = """() => {
  const ids = Object.keys(window.miradorInstance?.store.getState().windows ?? {});
  return ids.length === 2 && ids.every((id) => window.Mirador.lanternaWindowViewer(id)?.manifest);
}"""
#: Left: the first base preset, the Lanterna controls; right: the infrared band, the annotations.
MIRADOR_SCENE = """async () => {
  const M = window.Mirador, store = window.miradorInstance.store;
  const [left, right] = Object.keys(store.getState().windows);
  const a = M.lanternaWindowViewer(left), b = M.lanternaWindowViewer(right);
  await a.applyPreset('base', 0);
  a.viewer.viewport.goHome(true);
  const ir = b.getLayers().find((l) => /infrared|IR/i.test(l.label)) ?? b.getLayers()[0];
  await b.setActiveLayer(ir.id);
  store.dispatch(M.addCompanionWindow(left, { content: 'lanterna', position: 'right' }));
  store.dispatch(M.updateWindow(right, { sideBarOpen: true }));
  let button;
  while (!(button = [...document.querySelectorAll('button[aria-label="Annotations"]')].at(-1))) {
    await new Promise((r) => setTimeout(r, 50));
  }
  button.click(); // the side bar's Annotations panel in place of "About this item"
  return true;
}"""
MIRADOR_SETTLE = """async () => {
  const store = window.miradorInstance.store;
  await new Promise((r) => setTimeout(r, 500));
  for (const id of Object.keys(store.getState().windows)) {
    await window.Mirador.lanternaWindowViewer(id).whenFullyLoaded();
  }
  return true;
}"""


def _shoot(spec: dict[str, Any], tmp: Path) -> None:
    path = tmp / "spec.json"
    path.write_text(json.dumps({"result": str(tmp / "result.json"), "timeoutMs": 120000, **spec}))
    subprocess.run(["node", str(DRIVER), str(path)], check=True, cwd=REPO)


def _strokes() -> list[dict[str, Any]]:
    """A few strokes on the drawing canvas (fractions of its size → CSS px from its corner): a
    ring round a petal of the rosette and an arrow to it."""
    ring = [(0.52 + 0.12 * math.cos(t), 0.42 + 0.2 * math.sin(t))
            for t in (2 * math.pi * k / 16 for k in range(17))]
    lines = [ring, [(0.15, 0.85), (0.40, 0.58)], [(0.40, 0.58), (0.31, 0.60)],
             [(0.40, 0.58), (0.38, 0.68)]]
    steps: list[dict[str, Any]] = []
    for line in lines:
        for a, b in zip(line, line[1:], strict=False):
            steps.append({"gesture": {"type": "mouse", "from": list(a), "to": list(b),
                                      "steps": 6},
                          "on": ".lanterna-draw-surface", "fraction": True})
    return steps


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--root", type=Path, default=REPO / "datasets")
    parser.add_argument("--out-dir", type=Path, default=REPO / "docs")
    args = parser.parse_args()
    if not demo_is_current(args.root / "demo"):
        build_demo(args.root / "demo", force=True)
    logging.getLogger("werkzeug").setLevel(logging.ERROR)  # no request lines
    config = {"DATA_ROOT": args.root.resolve(), "AUTHORING_TOKEN": secrets.token_urlsafe(24)}
    server = make_server("127.0.0.1", 0, create_app(config), threaded=True)
    thread = threading.Thread(target=server.serve_forever, daemon=True)
    thread.start()
    out = args.out_dir.resolve()
    try:
        base = f"http://127.0.0.1:{server.server_port}"
        manifest = f"{base}/datasets/demo/manifest.json"
        with tempfile.TemporaryDirectory() as tmp:
            _shoot({
                "url": f"{base}/viewer/?manifest={manifest}",
                "viewport": {"width": 1280, "height": 800},
                "steps": [
                    {"waitFor": READY},
                    {"eval": "async () => { const l = window.lanterna;"
                             " await l.applyPreset('base', 0); await l.applyPreset('lens', 0);"
                             " document.getElementById('home')?.click();"
                             " await l.setLens({center: [420, 540], radius: 130}); return true; }"},
                    {"eval": "async () => { document.querySelector('.lanterna-presets')"
                             "?.scrollIntoView({block: 'start'}); return true; }"},
                    {"eval": SETTLE},
                    {"screenshot": str(out / "screenshot.png")},
                ],
            }, Path(tmp))
            _shoot({
                "url": f"{base}/viewer/simple.html?manifest={manifest}",
                "viewport": {"width": 1920, "height": 1080},
                "steps": [
                    {"waitFor": READY},
                    {"waitFor": "() => document.body.dataset.state === 'ready'"},
                    {"click": "#lens-list li:first-child button"},
                    {"eval": SETTLE},
                    {"screenshot": str(out / "screenshot-simple.png")},
                ],
            }, Path(tmp))
            _shoot({
                "url": f"{base}/viewer/?manifest={manifest}",
                "viewport": {"width": 390, "height": 844},
                "mobile": True,
                "steps": [
                    {"waitFor": READY},
                    {"eval": "async () => { await window.lanterna.applyPreset('base', 0);"
                             " document.getElementById('home')?.click(); return true; }"},
                    {"eval": SETTLE},
                    {"screenshot": str(out / "screenshot-phone.png")},
                ],
            }, Path(tmp))
            _shoot({
                "url": f"{base}/viewer/?manifest={manifest}",
                "viewport": {"width": 1280, "height": 800},
                "steps": [
                    {"waitFor": READY},
                    {"eval": "async () => { const l = window.lanterna;"
                             " await l.applyPreset('base', 1);"
                             " l.showImageRegion(0.43 * 1536, 0.23 * 1152, 0.12 * 1536,"
                             " 0.1 * 1152); return true; }"},
                    {"eval": SETTLE},
                    {"waitFor": "() => !document.getElementById('annotate')?.hidden"},
                    {"click": "#annotate"},
                    {"waitFor": "() => document.querySelector('.lanterna-draw-surface') !== null"},
                    *_strokes(),
                    {"click": ".lanterna-annotate-texts summary"},
                    {"fill": ".lanterna-annotate input[name=annotate-short]",
                     "value": "Burnishing marks on a petal"},
                    {"fill": ".lanterna-annotate input[name=annotate-author]",
                     "value": "A. Curator"},
                    {"eval": "async () => { document.querySelector('.lanterna-annotations')"
                             "?.scrollIntoView({block: 'start'}); return true; }"},
                    {"screenshot": str(out / "screenshot-annotate.png")},
                ],
            }, Path(tmp))
            _shoot({
                "url": f"{base}/viewer/mirador.html?manifest={manifest}&manifest={manifest}",
                "viewport": {"width": 1440, "height": 900},
                "steps": [
                    {"waitFor": MIRADOR_READY},
                    {"eval": MIRADOR_SCENE},
                    {"waitFor": "() => [...document.querySelectorAll('li[annotationid]')]"
                                " .some((li) => li.offsetParent !== null)"},
                    {"eval": MIRADOR_SETTLE},
                    {"screenshot": str(out / "screenshot-mirador.png")},
                ],
            }, Path(tmp))
    finally:
        server.shutdown()
    for name in ("screenshot.png", "screenshot-simple.png", "screenshot-phone.png",
                 "screenshot-annotate.png", "screenshot-mirador.png"):
        print(f"wrote {out / name}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
