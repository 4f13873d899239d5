"""The official IIIF Image API validator, level 0, against a dataset served by the Flask app."""

from __future__ import annotations

import re
import shutil
import subprocess
import sys
from collections.abc import Callable
from pathlib import Path

import pytest

from lanterna.tiler.dataset import DatasetWriter
from lanterna.tiler.importers import load_rgb_image
from lanterna.tiler.layers import add_image_layer

from .conftest import LiveServer, shared_file

IDENT = "67352ccc-d1b0-11e1-89ae-279075081939"


def test_level0_validator_passes(tmp_path: Path,
                                 live_server: Callable[[Path], LiveServer]) -> None:
    png = shared_file(f"iiif-validator/{IDENT}.png")
    validate = shutil.which("iiif-validate.py", path=str(Path(sys.executable).parent))
    if validate is None:
        pytest.fail("iiif-validate.py missing: install the dev extras (pip install -e '.[dev]')")
    img = load_rgb_image(png)
    root = tmp_path / "root"
    with DatasetWriter(root / "validator", name="validator", label="validator", width=img.width,
                       height=img.height) as ds:
        add_image_layer(ds, img, layer_id=IDENT, label="IIIF validator test image")
    server = live_server(root)
    proc = subprocess.run(
        [sys.executable, validate, "-s", f"127.0.0.1:{server.port}",
         "-p", "datasets/validator/iiif", "-i", IDENT, "--version=3.0", "--level", "0", "-v"],
        capture_output=True, text=True, timeout=120,
    )
    report = proc.stdout + proc.stderr
    assert proc.returncode == 0, report
    done = re.search(r"Done \((\d+) tests, (\d+) failures\)", report)
    assert done is not None, report
    assert int(done.group(1)) >= 5 and int(done.group(2)) == 0, report
    assert report.count(" PASS") == int(done.group(1)), report
