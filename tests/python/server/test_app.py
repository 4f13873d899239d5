"""The Flask app: static IIIF trees, JSON with rewritten ids, CORS, HEAD/OPTIONS, 404s."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from flask.testing import FlaskClient

from lanterna.server.app import create_app
from lanterna.tiler.dataset.layers import add_ptm_layer
from lanterna.tiler.dataset.plane_format import PlaneFormat
from lanterna.tiler.dataset.writer import DatasetWriter
from lanterna.tiler.iiif.encoding import TileFormat
from tests.python.fixtures.ptm import random_ptm_of_size


@pytest.fixture(scope="module")
def root(tmp_path_factory: pytest.TempPathFactory) -> Path:
    root = tmp_path_factory.mktemp("root")
    ptm = random_ptm_of_size(300, 200)
    with DatasetWriter(root / "obj", name="obj", label="Object", width=300, height=200,
                       base_url="https://example.org/pub") as ds:
        add_ptm_layer(ds, ptm, plane_format=PlaneFormat(TileFormat("png")))  # PNG tiles below
    (root.parent / "secret.json").write_text('{"secret": 1}')
    return root


@pytest.fixture
def client(root: Path, tmp_path: Path) -> FlaskClient:
    viewer = tmp_path / "viewer"
    viewer.mkdir()
    (viewer / "index.html").write_text("<!doctype html><title>viewer</title>")
    return create_app({"DATA_ROOT": root, "VIEWER_DIR": viewer}).test_client()


def test_info_json_id_matches_the_served_url(client: FlaskClient) -> None:
    resp = client.get("/datasets/obj/iiif/ptm_c0/info.json")
    assert resp.status_code == 200
    assert resp.headers["Access-Control-Allow-Origin"] == "*"
    assert resp.mimetype == "application/json"
    assert resp.get_json()["id"] == "http://localhost/datasets/obj/iiif/ptm_c0"


def test_json_ld_when_asked(client: FlaskClient) -> None:
    resp = client.get("/datasets/obj/iiif/ptm_c0/info.json",
                      headers={"Accept": "application/ld+json"})
    assert resp.headers["Content-Type"] == (
        'application/ld+json;profile="http://iiif.io/api/image/3/context.json"')


def test_manifest_ids_are_rewritten_everywhere(client: FlaskClient) -> None:
    text = client.get("/datasets/obj/manifest.json").get_data(as_text=True)
    assert "https://example.org/pub" not in text
    doc = json.loads(text)
    assert doc["id"] == "http://localhost/datasets/obj/manifest.json"
    body = doc["items"][0]["items"][0]["items"][0]["body"]["items"][0]
    relight = body["service"][1]
    assert relight["planes"][0]["service"]["id"] == "http://localhost/datasets/obj/iiif/ptm_c0"


def test_tiles_have_image_types_cors_and_head(client: FlaskClient) -> None:
    with client.get("/datasets/obj/iiif/ptm_c0/0,0,256,200/256,200/0/default.png") as resp:
        assert resp.status_code == 200 and resp.mimetype == "image/png"
        assert resp.headers["Access-Control-Allow-Origin"] == "*"
        assert resp.data[:8] == b"\x89PNG\r\n\x1a\n"
    with client.head("/datasets/obj/iiif/ptm_c0/full/max/0/default.jpg") as head:
        assert head.status_code == 200 and head.mimetype == "image/jpeg" and head.data == b""
        assert int(head.headers["Content-Length"]) > 0


def test_options_preflight(client: FlaskClient) -> None:
    resp = client.options("/datasets/obj/iiif/ptm_c0/info.json")
    assert resp.status_code == 200
    assert resp.headers["Access-Control-Allow-Origin"] == "*"
    assert "GET" in resp.headers["Access-Control-Allow-Methods"]


def test_base_uri_redirects_to_info_json(client: FlaskClient) -> None:
    resp = client.get("/datasets/obj/iiif/ptm_c0")
    assert resp.status_code == 303
    assert resp.headers["Location"].endswith("/datasets/obj/iiif/ptm_c0/info.json")


@pytest.mark.parametrize("path", [
    "/datasets/obj/iiif/nope/info.json",
    "/datasets/nope/manifest.json",
    "/datasets/obj/iiif/ptm_c0/0,0,1,1/1,1/0/default.png",
    "/datasets/../secret.json",
    "/datasets/obj/../../secret.json",
    "/datasets/%2e%2e/secret.json",
    "/datasets/obj",
])
def test_unknown_paths_are_404(client: FlaskClient, path: str) -> None:
    resp = client.get(path)
    assert resp.status_code == 404
    assert b"secret" not in resp.data


def test_index_lists_datasets_and_viewer_is_served(client: FlaskClient) -> None:
    index = client.get("/").get_data(as_text=True)
    assert "Object" in index and "viewer/?manifest=" in index
    with client.get("/viewer/") as resp:
        assert resp.status_code == 200 and b"<title>viewer" in resp.data


def test_create_app_needs_a_data_root() -> None:
    with pytest.raises(ValueError):
        create_app({})


def test_every_tile_url_openseadragon_requests_is_served(root: Path, client: FlaskClient) -> None:
    from lanterna.tiler.iiif import geometry as geo

    for image in ("ptm_c0", "ptm_c1", "ptm_color", "ptm_preview"):
        info = client.get(f"/datasets/obj/iiif/{image}/info.json").get_json()
        fmt = info.get("preferredFormats", ["jpg"])[0]
        tiles = info["tiles"][0]
        paths = list(geo.osd_tile_paths(info["width"], info["height"], tiles["width"],
                                        tiles["scaleFactors"]))
        assert len(paths) >= 3
        for path in paths:
            with client.head(f"/datasets/obj/iiif/{image}/{path}/0/default.{fmt}") as resp:
                assert resp.status_code == 200, (image, path)


def test_static_tiles_are_cacheable_and_conditional(client: FlaskClient) -> None:
    # send_from_directory gives a strong ETag, Last-Modified and max-age, and answers 304.
    url = "/datasets/obj/iiif/ptm_c0/0,0,256,200/256,200/0/default.png"
    with client.get(url) as first:
        etag, modified = first.headers["ETag"], first.headers["Last-Modified"]
        assert etag.startswith('"') and first.headers["Cache-Control"] == "public, max-age=3600"
    with client.get(url, headers={"If-None-Match": etag}) as again:
        assert again.status_code == 304 and again.data == b""
    with client.get(url, headers={"If-Modified-Since": modified}) as since:
        assert since.status_code == 304
    with client.get(url, headers={"If-None-Match": '"nope"'}) as other:
        assert other.status_code == 200


def test_json_documents_are_conditional_per_url(client: FlaskClient) -> None:
    url = "/datasets/obj/iiif/ptm_c0/info.json"
    first = client.get(url)
    assert first.headers["Last-Modified"] and first.headers["ETag"]
    assert client.get(url, headers={"If-None-Match": first.headers["ETag"]}).status_code == 304
    # The body depends on the host (rewritten ids), so the ETag does too.
    other = client.get(url, base_url="http://example.net")
    assert other.get_json()["id"].startswith("http://example.net/")
    assert other.headers["ETag"] != first.headers["ETag"]


def test_a_changed_base_url_is_read_again(tmp_path: Path) -> None:
    """The recorded base is cached per version of lanterna.json: a rewrite (new base) is seen."""
    root = tmp_path / "root"
    with DatasetWriter(root / "obj", name="obj", label="Object", width=64, height=48,
                       base_url="https://example.org/pub") as ds:
        add_ptm_layer(ds, random_ptm_of_size(64, 48), plane_format=PlaneFormat(TileFormat("png")))
    app = create_app({"DATA_ROOT": root, "VIEWER_DIR": tmp_path}).test_client()
    served = "http://localhost/datasets/obj/"
    assert served in app.get("/datasets/obj/manifest.json").get_data(as_text=True)
    # Another tool rewrites the description and the manifest with another base.
    for name in ("lanterna.json", "manifest.json"):
        path = next(p for p in (root / "obj").rglob(name) if p.is_file())
        path.write_text(path.read_text().replace("https://example.org/pub", "https://other.example/x"))
    text = app.get("/datasets/obj/manifest.json").get_data(as_text=True)
    assert "https://other.example/x" not in text
    assert served in text
