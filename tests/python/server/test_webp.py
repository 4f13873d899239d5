"""WebP-stored planes: static tiles as image/webp; the IIIF image server serves them losslessly."""

from __future__ import annotations

import json

import numpy as np
import pytest
import pyvips
from flask.testing import FlaskClient

from lanterna.server.app import create_app
from lanterna.tiler.dataset.layers import add_ptm_layer
from lanterna.tiler.dataset.plane_format import PlaneFormat
from lanterna.tiler.dataset.writer import DatasetWriter
from lanterna.tiler.iiif.encoding import TileFormat
from tests.python.fixtures.ptm import smooth_ptm

W, H = 300, 200
PTM = smooth_ptm("lrgb", W, H, seed=2)


@pytest.fixture(scope="module")
def client(tmp_path_factory: pytest.TempPathFactory) -> FlaskClient:
    root = tmp_path_factory.mktemp("webp") / "root"
    with DatasetWriter(root / "obj", name="obj", label="O", width=W, height=H, tiff=True) as ds:
        add_ptm_layer(ds, PTM, plane_format=PlaneFormat(TileFormat("webp", 60)))
    desc = json.loads((root / "obj" / "lanterna.json").read_text())
    assert desc["images"]["ptm_c0"]["format"] == "webp"
    return create_app({"DATA_ROOT": root}).test_client()


def test_static_webp_tiles_have_their_media_type(client: FlaskClient) -> None:
    info = client.get("/datasets/obj/iiif/ptm_c0/info.json").get_json()
    assert info["preferredFormats"] == ["webp"] and info["extraFormats"] == ["webp"]
    with client.get("/datasets/obj/iiif/ptm_c0/0,0,256,200/256,200/0/default.webp") as resp:
        assert resp.status_code == 200 and resp.mimetype == "image/webp"
        assert resp.data[:4] == b"RIFF" and resp.data[8:12] == b"WEBP"
        tile = np.asarray(pyvips.Image.new_from_buffer(resp.data, "").numpy())
    err = np.abs(tile.astype(int) - PTM.coefficients[:200, :256, 0:3])
    assert err.max() <= 2  # near-lossless level 60
    with client.get("/datasets/obj/iiif/ptm_c0/full/max/0/default.jpg") as jpg:
        assert jpg.status_code == 200 and jpg.mimetype == "image/jpeg"  # level 0 needs it


def test_iiif_server_serves_a_webp_image_losslessly(client: FlaskClient) -> None:
    info = client.get("/iiif/3/obj/ptm_c0/info.json").get_json()
    assert info["preferredFormats"] == ["webp"]
    with client.get("/iiif/3/obj/ptm_c0/0,0,256,200/max/0/default.webp") as resp:
        assert resp.status_code == 200 and resp.mimetype == "image/webp"
        got = np.asarray(pyvips.Image.new_from_buffer(resp.data, "").numpy())
    # the TIFF holds the source decode losslessly, and lossless WebP carries it out exactly
    np.testing.assert_array_equal(got, PTM.coefficients[:200, :256, 0:3])
