"""Retake the README's screenshots from the demo dataset, in headless Chromium.

Usage: ``.venv/bin/python tools/screenshot.py [--root datasets] [--out-dir docs]``
(``make screenshot``).
Builds the demo dataset if it is missing. Writes, in ``--out-dir``:

- ``screenshot.png``: the advanced viewer (1280×800): the demo's first base preset (raking light),
  its infrared lens preset over the inscription, the panel open at its presets;
- ``screenshot-simple.png``: the simplified viewer at a kiosk's 1920×1080, the lens on;
- ``screenshot-phone.png``: the advanced viewer on a 390×844 touch screen, the panel collapsed.
"""

from __future__ import annotations

import argparse
import json
import logging
import subprocess
import tempfile
import threading
from pathlib import Path
from typing import Any

from werkzeug.serving import make_server

from lanterna.server.app import create_app
from lanterna.tiler.demo.dataset import build_demo

REPO = Path(__file__).resolve().parents[1]
DRIVER = REPO / "tests" / "browser" / "page-script.mjs"
READY = "() => window.lanterna !== undefined && window.lanterna.manifest !== null"
SETTLE = "async () => { await window.lanterna.whenFullyLoaded(); return true; }"


def _shoot(spec: dict[str, Any], tmp: Path) -> None:
    path = tmp / "spec.json"
    path.write_text(json.dumps({"result": str(tmp / "result.json"), "timeoutMs": 120000, **spec}))
    subprocess.run(["node", str(DRIVER), str(path)], check=True, cwd=REPO)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--root", type=Path, default=REPO / "datasets")
    parser.add_argument("--out-dir", type=Path, default=REPO / "docs")
    args = parser.parse_args()
    if not (args.root / "demo" / "presets.json").is_file():
        build_demo(args.root / "demo", force=True)
    logging.getLogger("werkzeug").setLevel(logging.ERROR)  # no request lines
    server = make_server("127.0.0.1", 0, create_app({"DATA_ROOT": args.root.resolve()}),
                         threaded=True)
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
    finally:
        server.shutdown()
    for name in ("screenshot.png", "screenshot-simple.png", "screenshot-phone.png"):
        print(f"wrote {out / name}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
