"""An exported tree on plain static servers renders in real Chromium like the numpy relight.

The dataset is written for the dev-server URL, exported with ``--with-viewer`` for another base
URL under a prefix, and served by Python's http.server (tests/python/fixtures/servers.py). The
viewer comes either from the export itself (same origin) or from a second static server (another
origin: every manifest, info.json and tile fetch, and the WebGL texture uploads, rely on the CORS
header of the static host). Frames are compared with the numpy relight of fixtures/ptm_relight.py,
within the same tolerance.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from lanterna.cli import main
from lanterna.tiler.dataset.layers import add_ptm_layer
from lanterna.tiler.dataset.writer import DatasetWriter
from tests.python.fixtures.browser import Shot, render
from tests.python.fixtures.paths import REPO
from tests.python.fixtures.ptm_relight import (
    LIGHTS,
    TOLERANCE,
    H,
    W,
    numpy_relight,
    smooth_random_ptm,
)
from tests.python.fixtures.servers import StaticServer

pytestmark = pytest.mark.browser

VIEWPORT = (640, 480)
VIEWS = [(1, (130, 100, 640, 480)), (2, (100, 60, 1280, 960))]  # zoom 1 and 1/2, as there


@pytest.mark.parametrize("viewer_origin", ["same", "other"])
def test_exported_tree_renders_like_numpy(tmp_path: Path, viewer_origin: str) -> None:
    with DatasetWriter(tmp_path / "obj", name="obj", label="Random PTM", width=W,
                       height=H) as ds:
        layer = add_ptm_layer(ds, smooth_random_ptm("lrgb", seed=11))
    site = tmp_path / "site"
    with StaticServer(site) as data, StaticServer(REPO / "plugin/dist/viewer") as other:
        base = f"{data.url}/pub"
        assert main(["export", str(tmp_path / "obj"), "--base-url", base, "-o",
                     str(site / "pub"), "--with-viewer"]) == 0
        viewer = f"{base}/viewer/" if viewer_origin == "same" else f"{other.url}/"
        shots = [Shot(light, region, tmp_path / f"z{f}_{i}.rgba")
                 for f, region in VIEWS for i, light in enumerate(LIGHTS)]
        frames = render(f"{viewer}?manifest={base}/obj/manifest.json", shots, viewport=VIEWPORT)
        data_requests, viewer_requests = list(data.requests), list(other.requests)
    vw, vh = VIEWPORT
    for shot, frame in zip(shots, frames, strict=True):
        factor = 1 if shot.region[2] == vw else 2
        ref = numpy_relight(site / "pub" / "obj", layer, factor, shot.light)
        x0, y0 = shot.region[0] // factor, shot.region[1] // factor
        expected = np.round(ref[y0: y0 + vh, x0: x0 + vw] * 255.0).astype(np.int16)
        # at zoom 1/2 the view goes past the image's right and bottom edges: compare the image
        got = frame[: expected.shape[0], : expected.shape[1]]
        assert got.shape[:2] == expected.shape[:2] == ((vh, vw) if factor == 1 else (320, 400))
        assert (got[..., 3] == 255).all(), "the image area must be opaque"
        diff = np.abs(got[..., :3].astype(np.int16) - expected)
        bad = np.argwhere(diff.max(axis=-1) > TOLERANCE)
        assert bad.size == 0, (
            f"light={shot.light} zoom 1/{factor}: {len(bad)} pixels off by up to "
            f"{diff.max()} /255, first at (row, col) {tuple(bad[0])}")
        assert expected.std() > 10  # the light changes the picture: not a constant image
    # everything came from the static hosts: the manifest and tiles from the exported tree
    assert "/pub/obj/manifest.json" in data_requests
    ext = layer["planes"][0]["format"]
    assert any(r.startswith("/pub/obj/iiif/ptm_c0/") and r.endswith(f"/default.{ext}")
               for r in data_requests)
    if viewer_origin == "other":
        assert any(r.startswith("/?manifest=") for r in viewer_requests)
        assert any(r.startswith("/assets/") for r in viewer_requests)
        assert not any(r.startswith("/pub/viewer/") for r in data_requests)
    else:
        assert any(r.startswith("/pub/viewer/assets/") for r in data_requests)
