"""Property-based: IIIF Image API requests of any shape get an answer, never a 500.

Requests to the level-1 image server are generated from the URL grammar (regions, sizes,
rotations, qualities, formats — valid, edge and out-of-range values) and from arbitrary text;
each must answer 200 with the format's media type, or 303/400/404/501 with a one-line plain-text
body, within the case bounds of ``fixtures/fuzz.py``.
"""

from __future__ import annotations

import string
from collections import Counter
from urllib.parse import quote

import numpy as np
import pytest
from flask.testing import FlaskClient
from hypothesis import given, settings
from hypothesis import strategies as st

from lanterna.server.app import create_app
from lanterna.server.image_request import FORMATS
from lanterna.tiler.dataset.layers import add_image_layer
from lanterna.tiler.dataset.writer import DatasetWriter
from lanterna.tiler.iiif.pyramid import vips_from_array
from tests.python.fixtures.fuzz import OUTCOMES, bounded, examples

W, H = 300, 200
ints = st.one_of(st.integers(1, 120), st.integers(1, 120), st.integers(0, 400),
                 st.sampled_from([0, 1, 299, 300, 16383, 16384, 65535, 10**9, 10**10]))
nums = st.one_of(ints.map(str), st.floats(0, 200).map(lambda f: f"{f:.3f}"),
                 st.sampled_from(["0.0", ".5", "1e3", "-1", "nan", ""]))
garbage = st.text(string.printable, max_size=12)


def mostly(*valid: st.SearchStrategy[str]) -> st.SearchStrategy[str]:
    """Grammar-shaped values nine times in ten, arbitrary text otherwise."""
    return st.one_of(*(valid * 3), garbage) if len(valid) > 2 else st.one_of(
        *(valid * 9), garbage)


regions = mostly(
    st.sampled_from(["full", "square"]),
    st.builds(lambda *v: ",".join(map(str, v)), ints, ints, ints, ints),
    st.builds(lambda *v: "pct:" + ",".join(v), nums, nums, nums, nums))
sizes = mostly(
    st.sampled_from(["max", "^max"]),
    st.builds(lambda up, w: f"{up}{w},", st.sampled_from(["", "^"]), ints),
    st.builds(lambda up, h: f"{up},{h}", st.sampled_from(["", "^"]), ints),
    st.builds(lambda up, bang, w, h: f"{up}{bang}{w},{h}", st.sampled_from(["", "^"]),
              st.sampled_from(["", "!"]), ints, ints),
    st.builds(lambda up, n: f"{up}pct:{n}", st.sampled_from(["", "^"]), nums))
rotations = mostly(st.builds(lambda m, r: f"{m}{r}", st.sampled_from(["", "!"]),
                             st.sampled_from(["0", "0", "90", "180", "270", "360", "22.5", "-90",
                                              "1e9", "361"])))
formats = mostly(st.sampled_from([*FORMATS, *FORMATS, "gif", "jp2", "pdf", "bmp", ""]))
qualities = mostly(st.sampled_from(["default", "default", "color", "gray", "bitonal", "grey"]))


@pytest.fixture(scope="module")
def client(tmp_path_factory: pytest.TempPathFactory) -> FlaskClient:
    root = tmp_path_factory.mktemp("iiif") / "root"
    pixels = np.random.default_rng(0).integers(0, 256, (H, W, 3), dtype=np.uint8)
    with DatasetWriter(root / "obj", name="obj", label="O", width=W, height=H, tiff=True) as ds:
        add_image_layer(ds, vips_from_array(pixels), layer_id="pic", fmt="png")
    return create_app({"DATA_ROOT": root}).test_client()


@settings(max_examples=examples(600))
@given(region=regions, size=sizes, rotation=rotations, quality=qualities, fmt=formats)
def test_image_requests(client: FlaskClient, region: str, size: str, rotation: str,
                        quality: str, fmt: str) -> None:
    segments = [quote(s, safe="") or "%20" for s in (region, size, rotation, f"{quality}.{fmt}")]
    with bounded():
        resp = client.get("/iiif/3/obj/pic/" + "/".join(segments))
    OUTCOMES.setdefault("IIIF image requests", Counter())[f"status {resp.status_code}"] += 1
    assert resp.status_code in (200, 303, 400, 404, 501), resp.get_data(as_text=True)[:200]
    if resp.status_code == 200:
        assert resp.mimetype == FORMATS[fmt]
    elif resp.status_code != 303:
        body = resp.get_data(as_text=True)
        assert resp.mimetype == "text/plain" and body.count("\n") == 1, body[:200]
