"""The official IIIF Image API validator, level 0, on an exported tree served by a plain static
server (Python's http.server: no Lanterna code answers the requests)."""

from __future__ import annotations

import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from lanterna.cli import main
from lanterna.tiler.dataset.layers import add_image_layer
from lanterna.tiler.dataset.writer import DatasetWriter
from lanterna.tiler.inputs.images import load_rgb_image
from tests.python.fixtures.paths import shared_file
from tests.python.fixtures.servers import StaticServer

IDENT = "67352ccc-d1b0-11e1-89ae-279075081939"


def test_level0_validator_passes_on_a_static_export(tmp_path: Path) -> None:
    png = shared_file(f"iiif-validator/{IDENT}.png")
    validate = shutil.which("iiif-validate.py", path=str(Path(sys.executable).parent))
    if validate is None:
        pytest.fail("iiif-validate.py missing: install the dev extras (pip install -e '.[dev]')")
    img = load_rgb_image(png)
    # written for one URL (the dev server default) ...
    with DatasetWriter(tmp_path / "validator", name="validator", label="validator",
                       width=img.width, height=img.height) as ds:
        add_image_layer(ds, img, layer_id=IDENT, label="IIIF validator test image")
    site = tmp_path / "site"
    with StaticServer(site) as server:
        # ... exported for another, under a prefix of a static host
        base = f"{server.url}/pub/iiif"
        assert main(["export", str(tmp_path / "validator"), "--base-url", base,
                     "-o", str(site / "pub" / "iiif")]) == 0
        proc = subprocess.run(
            [sys.executable, validate, "-s", f"127.0.0.1:{server.port}",
             "-p", "pub/iiif/validator/iiif", "-i", IDENT, "--version=3.0", "--level", "0", "-v"],
            capture_output=True, text=True, timeout=120,
        )
        requested = list(server.requests)
    report = proc.stdout + proc.stderr
    assert proc.returncode == 0, report
    done = re.search(r"Done \((\d+) tests, (\d+) failures\)", report)
    assert done is not None, report
    assert int(done.group(1)) >= 5 and int(done.group(2)) == 0, report
    assert report.count(" PASS") == int(done.group(1)), report
    assert f"/pub/iiif/validator/iiif/{IDENT}/info.json" in requested
