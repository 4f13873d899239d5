"""The annotation routes of the authoring API (server/annotations_api.py), through Flask's client.

Rebuilds run in the request (``REBUILD_INLINE``) except in the last test, which waits for the
background thread.
"""

from __future__ import annotations

import io
import json
import os
import time
from pathlib import Path
from typing import Any

import numpy as np
import pytest
import pyvips
from flask.testing import FlaskClient
from werkzeug.test import encode_multipart

from lanterna.server.annotations_api import MAX_TEXTS, MAX_UPLOAD
from lanterna.server.app import create_app
from lanterna.tiler.overlays import store
from tests.python.fixtures.overlays import W, make_dataset

TOKEN = "annotation-token-0123"
AUTH = {"Authorization": f"Bearer {TOKEN}"}
URL = "/api/datasets/obj/layers/vis"
#: Deadline for a background rebuild (not a performance bound).
REBUILD_DEADLINE_S = 120


@pytest.fixture
def root(tmp_path: Path) -> Path:
    make_dataset(tmp_path / "root")
    return tmp_path / "root"


def client(root: Path, token: str | None = TOKEN, inline: bool = True) -> FlaskClient:
    return create_app({"DATA_ROOT": root, "AUTHORING_TOKEN": token,
                       "REBUILD_INLINE": inline}).test_client()


def square(size: int, rgb: tuple[int, int, int], alpha: int = 255) -> bytes:
    out = np.zeros((size, size, 4), np.uint8)
    out[..., :3], out[..., 3] = rgb, alpha
    data: bytes = pyvips.Image.new_from_array(out).copy(interpretation="srgb").pngsave_buffer()
    return data


def upload(meta: dict[str, Any] | None, image: bytes | None) -> dict[str, Any]:
    data: dict[str, Any] = {}
    if meta is not None:
        data["meta"] = json.dumps(meta)
    if image is not None:
        data["image"] = (io.BytesIO(image), "patch.png", "image/png")
    return {"data": data, "content_type": "multipart/form-data"}


META = {"level": 0, "x": 10, "y": 20, "w": 10, "h": 10}


def state(root: Path) -> tuple[str, bool]:
    """The dataset's current version and whether it has a patch store."""
    return os.readlink(root / "obj"), (root / "obj.annotations").exists()


def error(resp: Any) -> str:
    body = resp.get_data(as_text=True)
    assert resp.mimetype == "application/json" and body.count("\n") == 1, body
    message: str = json.loads(body)["error"]
    return message


def test_the_index_says_annotations_are_served(root: Path) -> None:
    assert client(root).get("/api/").get_json() == {"authoring": True, "annotations": True}


@pytest.mark.parametrize(("token", "headers", "code", "message"), [
    (None, AUTH, 403, "authoring is off"),
    (TOKEN, {}, 401, "a valid authoring token is needed"),
    (TOKEN, {"Authorization": "Bearer wrong-token-000000"}, 401, "a valid authoring token"),
    (TOKEN, {**AUTH, "Origin": "https://evil.example"}, 403, "cross-origin write refused"),
])
def test_unauthorised_writes_change_nothing(root: Path, token: str | None,
                                            headers: dict[str, str], code: int,
                                            message: str) -> None:
    before = state(root)
    c = client(root, token)
    answers = [
        c.post(f"{URL}/patches", headers=headers, **upload(META, square(10, (255, 0, 0)))),
        c.put(f"{URL}/patches/0_10_20_10_10_0_patch", headers=headers,
              **upload({"short": "x"}, None)),
        c.delete(f"{URL}/patches/0_10_20_10_10_0_patch", headers=headers),
        c.put(f"{URL}/levels/0", headers=headers, json={"short": "x"}),
    ]
    for resp in answers:
        assert resp.status_code == code and message in error(resp)
        assert (resp.headers.get("WWW-Authenticate") == 'Bearer realm="lanterna"') == (code == 401)
        assert "Access-Control-Allow-Origin" not in resp.headers
    assert state(root) == before == (before[0], False)


def huge_header() -> bytes:
    data = square(2, (1, 2, 3))
    return data[:16] + (20000).to_bytes(4, "big") + (20000).to_bytes(4, "big") + data[24:]


BAD = [
    ("not a PNG", META, b"\xff\xd8\xff\xe0 a jpeg, say", 400, "the image is not a PNG"),
    ("no alpha", META, pyvips.Image.black(10, 10, bands=3).pngsave_buffer(), 400,
     "has no alpha channel"),
    ("outside", {**META, "x": W + 5}, square(10, (1, 1, 1)), 400, "outside the 600x400 canvas"),
    ("level too high", {**META, "level": 3}, square(10, (1, 1, 1)), 400,
     "level 3 is beyond the pyramid (levels 0–2)"),
    ("wrong size", {**META, "level": 1}, square(10, (1, 1, 1)), 400,
     "the image is 10x10; rectangle 10,20,10,10 at level 1 is 5x5"),
    ("oversize IHDR", META, huge_header(), 413, "20000x20000; patch images are at most 8192"),
    ("no image", META, None, 400, "expected a multipart body"),
    ("bad meta", None, square(10, (1, 1, 1)), 400, "expected a multipart body"),
    ("truncated", META, square(10, (1, 1, 1))[:60], 400, "cannot read image"),
]


@pytest.mark.parametrize(("meta", "image", "code", "message"), [b[1:] for b in BAD],
                         ids=[b[0] for b in BAD])
def test_bad_uploads_are_refused_with_one_line_and_nothing_stored(
        root: Path, meta: dict[str, Any] | None, image: bytes | None, code: int,
        message: str) -> None:
    before = state(root)
    resp = client(root).post(f"{URL}/patches", headers=AUTH, **upload(meta, image))
    assert resp.status_code == code and message in error(resp), error(resp)
    assert state(root) == before


def test_a_body_over_the_limit_is_413_before_it_is_read(root: Path) -> None:
    before = state(root)
    resp = client(root).post(f"{URL}/patches", headers=AUTH, data=b"",
                             content_type="multipart/form-data; boundary=x",
                             environ_overrides={"CONTENT_LENGTH": str(MAX_UPLOAD + 1)})
    assert resp.status_code == 413 and "the body is over" in error(resp)
    boundary, body = encode_multipart({"meta": json.dumps(META)})
    resp = client(root).post(f"{URL}/patches", headers=AUTH, data=body + b"\0" * MAX_UPLOAD,
                             content_type=f"multipart/form-data; boundary={boundary}")
    assert resp.status_code == 413 and state(root) == before


def test_oversize_level_texts_are_413_naming_their_own_limit(root: Path) -> None:
    before = state(root)
    body = json.dumps({"short": "x", "long": "y" * MAX_TEXTS}).encode()
    resp = client(root).put(f"{URL}/levels/0", headers=AUTH, data=body,
                            content_type="application/json")
    assert resp.status_code == 413 and f"over {MAX_TEXTS} bytes" in error(resp)
    assert state(root) == before


def test_unknown_dataset_layer_or_patch_is_404(root: Path) -> None:
    c = client(root)
    assert c.get("/api/datasets/nope/layers/vis/patches").status_code == 404
    resp = c.get("/api/datasets/obj/layers/nope/status")
    assert resp.status_code == 404 and "no layer 'nope'" in error(resp)
    assert c.get(f"{URL}/patches/0_0_0_1_1_0_x").status_code == 404
    assert c.get(f"{URL}/patches/0_0_0_1_1_0_x/image").status_code == 404
    assert c.delete(f"{URL}/patches/0_0_0_1_1_0_x", headers=AUTH).status_code == 404
    assert c.post("/api/datasets/.obj/layers/vis/patches", headers=AUTH).status_code == 404


def test_create_list_get_replace_texts_delete_round_trip(root: Path) -> None:
    c = client(root)
    assert c.get(f"{URL}/status").get_json() == {
        "layer": "vis", "state": "done", "served": {"build": 0, "fingerprint": None},
        "patches": 0, "error": None}
    meta = {**META, "short": "Crack", "long": "<p>a <b>crack</b></p>", "author": "Ada",
            "state": {"layer": "vis", "mode": "color", "params": {}, "light": [0.2, 0.3]}}
    resp = c.post(f"{URL}/patches", headers=AUTH, **upload(meta, square(10, (255, 0, 0))))
    assert resp.status_code == 201, resp.get_data(as_text=True)
    body = resp.get_json()
    record = body["patch"]
    assert record["id"] == "0_10_20_10_10_0_Crack" and record["author"] == "Ada"
    assert body["status"]["state"] == "done" and body["status"]["served"]["build"] == 1
    assert body["status"]["served"]["fingerprint"] == store.fingerprint(root / "obj", "vis")
    second = c.post(f"{URL}/patches", headers=AUTH,
                    **upload({"level": 1, "x": 0, "y": 0, "w": 8, "h": 8, "motivation": "tagging"},
                             square(4, (0, 0, 255)))).get_json()["patch"]
    listing = c.get(f"{URL}/patches").get_json()
    assert [p["id"] for p in listing["patches"]] == [record["id"], second["id"]]
    assert listing["status"]["served"]["build"] == 2 and listing["levels"] == {}
    assert c.get(f"{URL}/patches/{record['id']}").get_json() == record
    with c.get(f"{URL}/patches/{record['id']}/image") as image:
        assert image.mimetype == "image/png" and image.data == square(10, (255, 0, 0))
    # the served pyramid has it
    with c.get("/datasets/obj/iiif/vis_ov0_b2/0,0,256,256/256,256/0/default.png") as tile:
        pixels = pyvips.Image.new_from_buffer(tile.data, "").numpy()
    assert pixels[25, 15].tolist() == [255, 0, 0, 255]

    resp = c.put(f"{URL}/patches/{record['id']}", headers=AUTH,
                 **upload({"short": "Crack (new)"}, square(10, (0, 255, 0))))
    assert resp.status_code == 200 and resp.get_json()["patch"]["short"] == "Crack (new)"
    with c.get(f"{URL}/patches/{record['id']}/image") as image:
        assert image.data == square(10, (0, 255, 0))
    resp = c.put(f"{URL}/patches/{record['id']}", headers=AUTH, **upload({"w": 99}, None))
    assert resp.status_code == 400 and "w cannot change" in error(resp)

    resp = c.put(f"{URL}/levels/0", headers=AUTH, json={"short": "Fine", "long": "<p>f</p>"})
    assert resp.status_code == 200
    assert {k: v for k, v in resp.get_json().items() if k != "status"} == {
        "level": 0, "short": "Fine", "long": "<p>f</p>"}
    assert c.put(f"{URL}/levels/9", headers=AUTH, json={"short": "x"}).status_code == 400
    assert c.put(f"{URL}/levels/0", headers=AUTH, json={"short": 3}).status_code == 400
    desc = json.loads((root / "obj/lanterna.json").read_text())
    level0 = desc["layers"][0]["overlay"]["levels"][0]
    assert (level0["short"], level0["image"]) == ("Fine", "vis_ov0_b4")

    resp = c.delete(f"{URL}/patches/{second['id']}", headers=AUTH)
    assert resp.status_code == 200 and resp.get_json()["deleted"] == second["id"]
    status = c.get(f"{URL}/status").get_json()
    assert status["patches"] == 1 and status["served"]["build"] == 5 and status["state"] == "done"


def test_a_stale_layer_is_rebuilt_when_its_status_is_read(root: Path) -> None:
    store.add_patch(root / "obj", "vis", square(10, (255, 0, 0)), META)  # e.g. a dropped file
    status = client(root).get(f"{URL}/status").get_json()
    assert status["state"] == "done" and status["served"]["build"] == 1


def test_background_rebuilds_end_done_with_every_patch(root: Path) -> None:
    c = client(root, inline=False)
    for i in range(5):
        resp = c.post(f"{URL}/patches", headers=AUTH,
                      **upload({**META, "x": 20 * i}, square(10, (50 * i, 0, 0))))
        assert resp.status_code == 201
        assert resp.get_json()["status"]["state"] in ("queued", "building", "done")
    deadline = time.monotonic() + REBUILD_DEADLINE_S
    while (status := c.get(f"{URL}/status").get_json())["state"] != "done":
        assert time.monotonic() < deadline, status
        time.sleep(0.05)
    assert status["served"]["fingerprint"] == store.fingerprint(root / "obj", "vis")
    desc = json.loads((root / "obj/lanterna.json").read_text())
    assert len(desc["layers"][0]["overlay"]["patches"]) == 5


def test_a_failed_rebuild_is_reported_and_not_retried_until_the_store_changes(
        tmp_path: Path) -> None:
    root = tmp_path / "clash"
    make_dataset(root, layers=("vis", "vis_ov0"))  # layer vis_ov0's image has the id of vis's
    c = client(root)
    resp = c.post(f"{URL}/patches", headers=AUTH, **upload(META, square(10, (255, 0, 0))))
    assert resp.status_code == 201  # stored; its rebuild fails
    status = resp.get_json()["status"]
    assert status["state"] == "done" and status["served"]["build"] == 0
    assert status["error"] == ("obj: image id(s) vis_ov0 already used by something other than "
                               "this layer's overlay")  # named within the data root
    marker = root / "obj.annotations/vis/.error"
    stamp = marker.stat().st_mtime_ns
    assert c.get(f"{URL}/status").get_json() == status
    assert marker.stat().st_mtime_ns == stamp  # not tried again on the same store
    resp = c.delete(f"{URL}/patches/{resp.get_json()['patch']['id']}", headers=AUTH)
    assert resp.get_json()["status"]["error"] is None and not marker.exists()
