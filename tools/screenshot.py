"""Retake docs/screenshot.png: the demo dataset in the viewer, in headless Chromium.

Usage: ``.venv/bin/python tools/screenshot.py [--root datasets] [--out docs/screenshot.png]``
(``make screenshot``). Builds the demo dataset if it is missing.
"""

from __future__ import annotations

import argparse
import json
import subprocess
import tempfile
import threading
from pathlib import Path

from werkzeug.serving import make_server

from lanterna.server.app import create_app
from lanterna.tiler.demo.dataset import build_demo

REPO = Path(__file__).resolve().parents[1]


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--root", type=Path, default=REPO / "datasets")
    parser.add_argument("--out", type=Path, default=REPO / "docs" / "screenshot.png")
    parser.add_argument("--light", type=float, nargs=2, default=(-0.55, 0.45))
    parser.add_argument("--lens-layer", default="band_ir",
                        help="layer shown in the lens ('' for no lens; default the IR band)")
    args = parser.parse_args()
    if not (args.root / "demo" / "lanterna.json").is_file():
        build_demo(args.root / "demo", force=True)
    server = make_server("127.0.0.1", 0, create_app({"DATA_ROOT": args.root.resolve()}),
                         threaded=True)
    thread = threading.Thread(target=server.serve_forever, daemon=True)
    thread.start()
    try:
        base = f"http://127.0.0.1:{server.server_port}"
        desc = json.loads((args.root / "demo" / "lanterna.json").read_text())
        with tempfile.TemporaryDirectory() as tmp:
            spec = {
                "url": f"{base}/viewer/?manifest={base}/datasets/demo/manifest.json",
                "viewport": {"width": 1200, "height": 800},
                "shots": [{"light": list(args.light),
                           "region": [0, 0, desc["width"], desc["height"]],
                           "out": str(Path(tmp) / "shot.rgba"), "overlays": True,
                           **({"lens": {"enabled": True, "center": [470, 585], "radius": 150,
                                        "layer": args.lens_layer, "annotations": "outside"}}
                              if args.lens_layer else {})}],
                "screenshot": str(args.out.resolve()),
            }
            (Path(tmp) / "spec.json").write_text(json.dumps(spec))
            subprocess.run(["node", str(REPO / "tests/browser/render.mjs"),
                            str(Path(tmp) / "spec.json")], check=True, cwd=REPO)
    finally:
        server.shutdown()
    print(f"wrote {args.out}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
