"""The authoring API: GET /api/, GET/PUT /api/datasets/<name>/presets (docs/serving.md)."""

from __future__ import annotations

import json
import os
import threading
from pathlib import Path
from typing import Any

import pytest
from flask.testing import FlaskClient

from lanterna.manifests.validate import validate_manifest
from lanterna.server.api import MAX_BODY
from lanterna.server.app import create_app
from tests.python.fixtures.presets import read_json, small_dataset, small_library

TOKEN = "s3cret-token-of-20ch"
AUTH = {"Authorization": f"Bearer {TOKEN}"}
URL = "/api/datasets/obj/presets"


@pytest.fixture
def root(tmp_path: Path) -> Path:
    small_dataset(tmp_path / "root" / "obj")
    return tmp_path / "root"


def _client(root: Path, token: str | None = TOKEN) -> FlaskClient:
    return create_app({"DATA_ROOT": root, "AUTHORING_TOKEN": token}).test_client()


def _state(root: Path) -> tuple[str, bytes]:
    return os.readlink(root / "obj"), (root / "obj" / "lanterna.json").read_bytes()


def _error(resp: Any) -> str:
    body = resp.get_data(as_text=True)
    assert resp.mimetype == "application/json" and body.count("\n") == 1, body
    message: str = json.loads(body)["error"]
    return message


def test_the_index_says_whether_authoring_is_on(root: Path) -> None:
    assert _client(root).get("/api/").get_json() == {"authoring": True, "annotations": True}
    assert _client(root, None).get("/api/").get_json() == {"authoring": False,
                                                         "annotations": True}


def test_get_gives_an_empty_library_then_the_stored_one(root: Path) -> None:
    client = _client(root, None)
    assert client.get(URL).get_json() == {"type": "LanternaPresets", "version": 1,
                                          "presets": {}, "base": [], "lens": []}
    assert _client(root).put(URL, json=small_library(), headers=AUTH).status_code == 200
    resp = client.get(URL)
    assert resp.get_json() == small_library()
    assert resp.headers["Access-Control-Allow-Origin"] == "*"  # reads as before
    assert client.get("/api/datasets/none/presets").status_code == 404


def test_a_valid_put_rewrites_the_dataset(root: Path) -> None:
    resp = _client(root).put(URL, json=small_library(), headers=AUTH)
    assert resp.status_code == 200 and resp.get_json() == {"presets": 2}
    assert "Access-Control-Allow-Origin" not in resp.headers
    ds = root / "obj"
    assert read_json(ds / "lanterna.json")["presets"] == small_library()
    assert read_json(ds / "presets.json") == small_library()
    manifest = read_json(ds / "manifest.json")
    assert validate_manifest(manifest) == [] and manifest["service"][0]["presets"] == \
        small_library()["presets"]
    # the manifest as served names the library at the server's own URL
    served = _client(root).get("/datasets/obj/manifest.json").get_json()
    assert served["service"][0]["id"] == "http://localhost/datasets/obj/presets.json"


def test_no_token_configured_is_403_and_writes_nothing(root: Path) -> None:
    before = _state(root)
    resp = _client(root, None).put(URL, json=small_library(), headers=AUTH)
    assert resp.status_code == 403 and "authoring is off" in _error(resp)
    assert _state(root) == before


@pytest.mark.parametrize("headers", [{}, {"Authorization": "Bearer wrong-token-of-20chr"},
                                     {"Authorization": f"Basic {TOKEN}"},
                                     {"Authorization": f"Bearer {TOKEN[:-1]}"},
                                     {"Authorization": "Bearer"}],
                         ids=["missing", "wrong", "not-bearer", "prefix", "empty"])
def test_a_missing_or_wrong_token_is_401_and_writes_nothing(root: Path,
                                                           headers: dict[str, str]) -> None:
    before = _state(root)
    resp = _client(root).put(URL, json=small_library(), headers=headers)
    assert resp.status_code == 401 and resp.headers["WWW-Authenticate"].startswith("Bearer")
    assert "authoring token" in _error(resp)
    assert _state(root) == before


def test_a_cross_origin_write_is_403(root: Path) -> None:
    before = _state(root)
    client = _client(root)
    resp = client.put(URL, json=small_library(),
                      headers={**AUTH, "Origin": "http://evil.example"})
    assert resp.status_code == 403 and "cross-origin" in _error(resp)
    assert "Access-Control-Allow-Origin" not in resp.headers
    assert _state(root) == before
    same = client.put(URL, json=small_library(), headers={**AUTH, "Origin": "http://localhost"})
    assert same.status_code == 200


def test_a_preflight_for_a_write_gets_no_cors(root: Path) -> None:
    resp = _client(root).options(URL, headers={"Origin": "http://evil.example",
                                               "Access-Control-Request-Method": "PUT"})
    assert "Access-Control-Allow-Origin" not in resp.headers


def test_a_body_over_the_limit_is_413(root: Path) -> None:
    before = _state(root)
    lib = small_library()
    lib["label"] = "x" * 100
    body = json.dumps(lib).encode() + b" " * MAX_BODY
    resp = _client(root).put(URL, data=body, headers={**AUTH, "Content-Type":
                                                      "application/json"})
    assert resp.status_code == 413 and "over" in _error(resp)
    assert _state(root) == before
    # exactly at the limit is read (and then judged on its content)
    at = json.dumps(small_library()).encode()
    at += b" " * (MAX_BODY - len(at))
    assert _client(root).put(URL, data=at, headers=AUTH).status_code == 200


@pytest.mark.parametrize(("body", "message"), [
    (b'{"type": "LanternaPresets", "version": 1', "the body is not valid JSON"),
    (b'{"a": NaN}', "the body is not valid JSON"),
    (b"\xff\xfe", "the body is not valid JSON"),
    (json.dumps({**small_library(), "base": [{"label": "B", "preset": "raking",
                                              "layer": "ir"}]}).encode(),
     "presets.json: base[0].layer: no layer 'ir' in the dataset (layers: ptm, uv)"),
    (json.dumps({**small_library(), "version": 2}).encode(),
     "presets.json: version: expected the number 1 (got 2)"),
    (b"[]", "presets.json: expected an object"),
])
def test_an_invalid_library_is_400_naming_the_path(root: Path, body: bytes,
                                                   message: str) -> None:
    before = _state(root)
    resp = _client(root).put(URL, data=body, headers={**AUTH, "Content-Type":
                                                      "application/json"})
    assert resp.status_code == 400
    assert _error(resp).startswith(message)
    assert _state(root) == before


def test_an_unknown_dataset_is_404(root: Path) -> None:
    for name in ("ghost", ".obj.lock", "..", "%2e%2e"):
        resp = _client(root).put(f"/api/datasets/{name}/presets", json=small_library(),
                                 headers=AUTH)
        assert resp.status_code == 404, name


def test_two_concurrent_puts_leave_one_of_them_whole(root: Path) -> None:
    a = small_library()
    b = small_library()
    b["presets"] = {f"p{i}": {"label": f"P{i}", "layer": "uv", "mode": "color"}
                    for i in range(30)}
    b["base"] = [{"label": f"P{i}", "preset": f"p{i}"} for i in range(30)]
    b["lens"] = []
    app = create_app({"DATA_ROOT": root, "AUTHORING_TOKEN": TOKEN})
    statuses: list[int] = []
    start = threading.Barrier(2)

    def put(lib: dict[str, Any]) -> None:
        client = app.test_client()
        start.wait()
        statuses.append(client.put(URL, json=lib, headers=AUTH).status_code)

    threads = [threading.Thread(target=put, args=(lib,)) for lib in (a, b)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert statuses == [200, 200]
    ds = root / "obj"
    stored = read_json(ds / "presets.json")
    assert stored in (a, b)
    assert read_json(ds / "lanterna.json")["presets"] == stored
    manifest = read_json(ds / "manifest.json")
    assert validate_manifest(manifest) == []
    assert manifest["service"][0]["presets"] == stored["presets"]
    assert manifest["service"][0]["base"] == stored["base"]
