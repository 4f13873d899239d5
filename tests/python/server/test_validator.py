"""The official IIIF Image API validator against the Flask app.

Level 0 on the static trees (``/datasets/…/iiif``); level 1, level 2 and the optional tests of
every extra feature the ``/iiif/3`` image server claims, on the pyramidal TIFFs.
"""

from __future__ import annotations

import re
import shutil
import subprocess
import sys
from collections.abc import Iterator
from pathlib import Path

import pytest

from lanterna.tiler.dataset.layers import add_image_layer
from lanterna.tiler.dataset.writer import DatasetWriter
from lanterna.tiler.inputs.images import load_rgb_image
from tests.python.fixtures.paths import shared_file
from tests.python.fixtures.servers import LiveServer

IDENT = "67352ccc-d1b0-11e1-89ae-279075081939"
#: Optional ("level 3") validator tests of the extras the image server claims in info.json:
#: mirroring, canonicalLinkHeader, profileLinkHeader and the tif format. (The validator's
#: format_webp test is Python-2 code that cannot run; webp is tested in test_image_api.py.)
CLAIMED_EXTRAS = ["rot_mirror", "rot_mirror_180", "linkheader_canonical", "linkheader_profile",
                  "format_tif"]


@pytest.fixture(scope="module")
def server(tmp_path_factory: pytest.TempPathFactory) -> Iterator[LiveServer]:
    png = shared_file(f"iiif-validator/{IDENT}.png")
    img = load_rgb_image(png)
    root = tmp_path_factory.mktemp("validator") / "root"
    with DatasetWriter(root / "validator", name="validator", label="validator", width=img.width,
                       height=img.height, tiff=True) as ds:
        add_image_layer(ds, img, layer_id=IDENT, label="IIIF validator test image")
    live = LiveServer(root)
    yield live
    live.close()


def _validate(server: LiveServer, prefix: str, *options: str) -> tuple[int, str]:
    """Run iiif-validate.py; return the number of tests run (all of which passed) and the log."""
    validate = shutil.which("iiif-validate.py", path=str(Path(sys.executable).parent))
    if validate is None:
        pytest.fail("iiif-validate.py missing: install the dev extras (pip install -e '.[dev]')")
    proc = subprocess.run(
        [sys.executable, validate, "-s", f"127.0.0.1:{server.port}", "-p", prefix, "-i", IDENT,
         "--version=3.0", "-v", *options],
        capture_output=True, text=True, timeout=300,
    )
    report = proc.stdout + proc.stderr
    assert proc.returncode == 0, report  # the exit code is the number of failures
    done = re.search(r"Done \((\d+) tests, (\d+) failures\)", report)
    assert done is not None, report
    assert int(done.group(2)) == 0, report
    assert report.count(" PASS") == int(done.group(1)), report
    return int(done.group(1)), report


def test_level0_validator_passes_on_the_static_tree(server: LiveServer) -> None:
    count, _ = _validate(server, "datasets/validator/iiif", "--level", "0")
    assert count >= 5


def test_level1_validator_passes_on_the_image_server(server: LiveServer) -> None:
    count, report = _validate(server, "iiif/3/validator", "--level", "1")
    assert count >= 24
    for name in ("cors", "jsonld", "baseurl_redirect", "id_error_escapedslash", "size_noup",
                 "region_square"):
        assert f"test {name} PASS" in report


def test_level2_validator_passes_on_the_image_server(server: LiveServer) -> None:
    # info.json says level1; the level-2 tests check the extras it lists (regionByPct,
    # sizeByPct, sizeByConfinedWh, rotationBy90s, png, color/gray/bitonal).
    count, report = _validate(server, "iiif/3/validator", "--level", "2")
    assert count >= 33
    for name in ("region_percent", "size_percent", "size_bwh", "rot_full_basic",
                 "rot_region_basic", "format_png", "quality_grey", "quality_bitonal"):
        assert f"test {name} PASS" in report


def test_claimed_optional_features_pass(server: LiveServer) -> None:
    options = [arg for name in CLAIMED_EXTRAS for arg in ("--test", name)]
    count, _ = _validate(server, "iiif/3/validator", *options)
    assert count == len(CLAIMED_EXTRAS)
