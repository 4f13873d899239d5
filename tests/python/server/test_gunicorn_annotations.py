"""The annotation API under ``lanterna serve --workers 2`` (gunicorn): concurrent uploads, pyramid
reads during rebuilds, a worker killed while rebuilding, and ``annotate build`` at the same time.

Waits have generous deadlines (:data:`DEADLINE_S`); nothing here measures time.
"""

from __future__ import annotations

import json
import os
import re
import secrets
import signal
import subprocess
import threading
import time
import urllib.error
import urllib.request
from collections.abc import Iterator
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path
from typing import Any

import numpy as np
import pytest
import pyvips

from lanterna.tiler.dataset.layers import add_image_layer
from lanterna.tiler.dataset.writer import DatasetWriter
from lanterna.tiler.overlays import store
from tests.python.fixtures.overlays import make_dataset
from tests.python.fixtures.servers import LANTERNA, lanterna_serve
from tests.python.fixtures.sources import png

TOKEN = "gunicorn-annotations-0123"
AUTH = {"Authorization": f"Bearer {TOKEN}"}
#: Deadline for rebuilds to finish and markers to appear (not a performance bound).
DEADLINE_S = 240
#: The first full-resolution tile of a level image.
TILE = "0,0,256,256/256,256"


@pytest.fixture(scope="module")
def served(tmp_path_factory: pytest.TempPathFactory) -> Iterator[tuple[str, Path]]:
    """``(url, root)`` of a 2-worker server over ``obj`` (layers vis, uv, ir) and ``big``."""
    scratch = tmp_path_factory.mktemp("gunicorn-annotations")
    root = scratch / "root"
    make_dataset(root, layers=("vis", "uv", "ir"))
    w, h = 3000, 2000  # a level-0 overlay of it takes a while to tile: time to kill a worker
    rng = np.random.default_rng(3)
    with DatasetWriter(root / "big", name="big", label="Big", width=w, height=h) as ds:
        img = pyvips.Image.new_from_array(rng.integers(0, 256, (h, w, 3), dtype=np.uint8))
        add_image_layer(ds, img.copy(interpretation="srgb"), layer_id="vis", label="VIS",
                        fmt="jpg")
    token_file = scratch / "token"
    token_file.write_text(TOKEN + "\n")
    with lanterna_serve(root, "--workers", "2", "--authoring-token-file",
                        str(token_file)) as (url, _):
        yield url, root


def request(method: str, url: str, body: bytes | None = None,
            headers: dict[str, str] | None = None) -> tuple[int, bytes]:
    req = urllib.request.Request(url, data=body, method=method, headers=headers or {})
    try:
        with urllib.request.urlopen(req, timeout=120) as resp:
            return resp.status, resp.read()
    except urllib.error.HTTPError as err:
        with err:
            return err.code, err.read()


def get_json(url: str) -> Any:
    code, body = request("GET", url)
    assert code == 200, (url, code, body)
    return json.loads(body)


def square(size: int, rgb: tuple[int, int, int]) -> bytes:
    out = np.full((size, size, 4), 255, np.uint8)
    out[..., :3] = rgb
    data: bytes = pyvips.Image.new_from_array(out).copy(interpretation="srgb").pngsave_buffer()
    return data


def post_patch(url: str, ds: str, layer: str, meta: dict[str, Any], image: bytes) -> Any:
    boundary = secrets.token_hex(12)
    body = (f"--{boundary}\r\nContent-Disposition: form-data; name=\"meta\"\r\n\r\n"
            f"{json.dumps(meta)}\r\n--{boundary}\r\nContent-Disposition: form-data; "
            "name=\"image\"; filename=\"p.png\"\r\nContent-Type: image/png\r\n\r\n").encode() \
        + image + f"\r\n--{boundary}--\r\n".encode()
    code, answer = request("POST", f"{url}/api/datasets/{ds}/layers/{layer}/patches", body,
                           {**AUTH, "Content-Type": f"multipart/form-data; boundary={boundary}"})
    assert code == 201, answer
    return json.loads(answer)


def wait_done(url: str, root: Path, ds: str, layer: str) -> Any:
    """Poll the status until ``done`` with the store's fingerprint served; return it."""
    deadline = time.monotonic() + DEADLINE_S
    while True:
        status = get_json(f"{url}/api/datasets/{ds}/layers/{layer}/status")
        if status["state"] == "done" and \
                status["served"]["fingerprint"] == store.fingerprint(root / ds, layer):
            return status
        assert time.monotonic() < deadline, status
        time.sleep(0.1)


def served_level(url: str, ds: str, layer: str, level: int,
                 region: str = "full/max") -> tuple[str, np.ndarray]:
    """The served level image id of ``layer`` and the pixels of one of its files (``full/max``
    by default: the whole level up to 2048 px a side)."""
    desc = get_json(f"{url}/datasets/{ds}/lanterna.json")
    entry = next(e for e in next(la for la in desc["layers"] if la["id"] == layer)["overlay"][
        "levels"] if e["level"] == level)
    code, data = request("GET", f"{url}/datasets/{ds}/iiif/{entry['image']}/{region}/0/"
                         "default.png")
    assert code == 200
    return entry["image"], np.asarray(pyvips.Image.new_from_buffer(data, "").numpy())


def test_fifty_concurrent_uploads_are_all_stored_and_all_in_the_final_pyramid(
        served: tuple[str, Path]) -> None:
    url, root = served
    squares = {i: ((20 + 55 * (i % 10), 20 + 70 * (i // 10)), (5 * i, 255 - 5 * i, (37 * i) % 256))
               for i in range(50)}

    def upload(i: int) -> Any:
        (x, y), rgb = squares[i]
        return post_patch(url, "obj", "vis", {"level": 0, "x": x, "y": y, "w": 10, "h": 10,
                                              "short": f"square {i}"}, square(10, rgb))

    with ThreadPoolExecutor(max_workers=16) as pool:
        records = [answer["patch"] for answer in pool.map(upload, range(50))]
    assert sorted(r["order"] for r in records) == list(range(50))  # none overwrote another
    assert len(store.list_patches(root / "obj", "vis")) == 50
    status = wait_done(url, root, "obj", "vis")
    assert status["patches"] == 50 and status["error"] is None
    _, level0 = served_level(url, "obj", "vis", 0)
    for (x, y), rgb in squares.values():
        assert level0[y + 5, x + 5].tolist() == [*rgb, 255]
    listing = get_json(f"{url}/api/datasets/obj/layers/vis/patches")
    assert len(listing["patches"]) == 50


def _build_of(image_id: str) -> int:
    m = re.search(r"_b(\d+)$", image_id)
    return int(m.group(1)) if m else 1


def test_pyramid_reads_during_rebuilds_see_whole_builds(served: tuple[str, Path]) -> None:
    url, root = served
    done = threading.Event()

    def uploads() -> None:
        try:
            for i in range(8):
                post_patch(url, "obj", "uv", {"level": 0, "x": 30 * i, "y": 40, "w": 20, "h": 20},
                           square(20, (200, 30 * i, 0)))
                time.sleep(0.3)  # spread the changes over several rebuilds
            wait_done(url, root, "obj", "uv")
        finally:
            done.set()

    writer = threading.Thread(target=uploads)
    writer.start()
    seen: dict[str, bytes] = {}  # URL → the body it gave the first time
    builds_seen: set[int] = set()
    reads = gone = 0
    while not done.is_set():
        manifest = get_json(f"{url}/datasets/obj/manifest.json")
        ids = sorted({m.group(1) for m in re.finditer(r"/iiif/(uv_ov\d+(?:_b\d+)?)\b",
                                                      json.dumps(manifest))})
        for ident in ids:
            builds_seen.add(_build_of(ident))
            base = f"{url}/datasets/obj/iiif/{ident}"
            urls = [f"{base}/info.json", f"{base}/0,0,256,256/256,256/0/default.png",
                    f"{base}/512,256,88,144/88,144/0/default.png", f"{base}/full/150,100/0/"
                    "default.png"]
            for tile_url in urls:
                code, body = request("GET", tile_url)
                if code == 404:
                    # allowed only once the build it belongs to is two publishes old
                    newest = max(_build_of(e["image"]) for e in get_json(
                        f"{url}/datasets/obj/lanterna.json")["layers"][1]["overlay"]["levels"])
                    assert newest >= _build_of(ident) + 2, (tile_url, newest)
                    gone += 1
                    break
                assert code == 200, tile_url
                reads += 1
                if tile_url.endswith(".json"):
                    body = json.dumps(json.loads(body)).encode()
                # an id's files never change: each belongs to one build only
                assert seen.setdefault(tile_url, body) == body, tile_url
    writer.join()
    assert reads > 0 and len(builds_seen) >= 2, (builds_seen, reads, gone)


def test_a_worker_killed_while_rebuilding_leaves_the_old_pyramid_and_the_next_completes(
        served: tuple[str, Path]) -> None:
    url, root = served
    big = np.zeros((2000, 3000, 4), np.uint8)
    big[..., 1], big[..., 3] = 180, 90
    data: bytes = pyvips.Image.new_from_array(big).copy(interpretation="srgb").pngsave_buffer()
    post_patch(url, "big", "vis", {"level": 0, "x": 0, "y": 0, "w": 3000, "h": 2000}, data)
    wait_done(url, root, "big", "vis")
    marker = store.store_dir(root / "big", "vis") / store.BUILDING
    killed = 0
    for attempt in range(5):  # until the kill lands while the new version is being written
        version = os.readlink(root / "big")
        old_id, old_pixels = served_level(url, "big", "vis", 0, TILE)
        post_patch(url, "big", "vis", {"level": 0, "x": 20 * attempt, "y": 0, "w": 10,
                                       "h": 10}, square(10, (255, 0, 255)))
        deadline = time.monotonic() + DEADLINE_S
        pid = None
        while pid is None and time.monotonic() < deadline:
            try:
                pid = int(json.loads(marker.read_text())["pid"])
            except (OSError, ValueError, KeyError):
                time.sleep(0.002)
        assert pid is not None
        try:
            os.kill(pid, signal.SIGKILL)
        except ProcessLookupError:
            continue
        if os.readlink(root / "big") != version:
            wait_done(url, root, "big", "vis")
            continue  # it had published already: try again
        killed += 1
        # the old pyramid is still the one served, whole
        ident, pixels = served_level(url, "big", "vis", 0, TILE)
        assert ident == old_id
        np.testing.assert_array_equal(pixels, old_pixels)
        break
    assert killed == 1
    # the next status read sees the dead marker and starts the rebuild again
    status = wait_done(url, root, "big", "vis")
    assert status["patches"] == len(store.list_patches(root / "big", "vis"))
    ident, pixels = served_level(url, "big", "vis", 0, TILE)
    assert ident != old_id and pixels[5, 20 * attempt + 5].tolist() == [255, 0, 255, 255]


def test_annotate_build_during_server_uploads_loses_nothing(served: tuple[str, Path],
                                                           tmp_path: Path) -> None:
    url, root = served
    folder = tmp_path / "patches"
    folder.mkdir()
    for i in range(5):
        png(folder / f"0_{40 * i}_300_20_20_{100 + i}_cli.png",
            np.full((20, 20, 4), (0, 0, 50 * i, 255), np.uint8))
    cli = subprocess.Popen([str(LANTERNA), "annotate", "build", str(root / "obj"), "--layer",
                            "ir", "--patches", str(folder)], stdout=subprocess.PIPE,
                           stderr=subprocess.STDOUT, text=True)
    with ThreadPoolExecutor(max_workers=4) as pool:
        ids = [a["patch"]["id"] for a in pool.map(lambda i: post_patch(
            url, "obj", "ir", {"level": 0, "x": 30 * i, "y": 50, "w": 10, "h": 10},
            square(10, (9, 9, 9 + i))), range(10))]
    out, _ = cli.communicate(timeout=DEADLINE_S)
    assert cli.returncode == 0, out
    wait_done(url, root, "obj", "ir")
    desc = get_json(f"{url}/datasets/obj/lanterna.json")
    published = {p["id"] for p in desc["layers"][2]["overlay"]["patches"]}
    assert published == set(ids) | {f"0_{40 * i}_300_20_20_{100 + i}_cli" for i in range(5)}
