"""Nothing outside DATA_ROOT is ever read; no listings; errors never leak stack traces.

A secret file (and a whole dataset with a TIFF) sits beside the data root, reachable only by
traversal or through symlinks planted inside the root. Every attempt must answer 400/404 without
the sentinel in the body, and an audit hook (Python ``open``) plus a spy on pyvips' loader must
show that no file outside the root was opened.
"""

from __future__ import annotations

import http.client
import os
import sys
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import numpy as np
import pytest
import pyvips

from lanterna.server.app import create_app
from lanterna.tiler.dataset.layers import add_image_layer
from lanterna.tiler.dataset.writer import DatasetWriter
from lanterna.tiler.iiif.pyramid import vips_from_array
from tests.python.fixtures.servers import LiveServer

SENTINEL = "SENTINEL-7f3a9c"
_OPENED: list[str] = []
_RECORDING = [False]


def _audit(event: str, args: tuple[Any, ...]) -> None:
    if _RECORDING[0] and event in ("open", "os.listdir", "os.scandir") and args:
        if isinstance(args[0], (str, bytes, os.PathLike)):
            _OPENED.append(os.fsdecode(args[0]))


sys.addaudithook(_audit)  # audit hooks cannot be removed; this one records only when asked


def _dataset(out: Path, name: str) -> None:
    img = vips_from_array(np.full((40, 60, 3), 77, np.uint8))
    with DatasetWriter(out, name=name, label=name, width=60, height=40, tiff=True) as ds:
        add_image_layer(ds, img, layer_id="pic", fmt="png")


@pytest.fixture(scope="module")
def base(tmp_path_factory: pytest.TempPathFactory) -> Path:
    base = tmp_path_factory.mktemp("sec")
    root = base / "root"
    _dataset(root / "obj", "obj")
    _dataset(base / "outside", "outside")            # a complete dataset outside the root
    (base / "secret.txt").write_text(SENTINEL)
    (base / "secret.json").write_text(f'{{"s": "{SENTINEL}"}}')
    (base / "outside" / "secret.json").write_text(f'{{"s": "{SENTINEL}"}}')
    # Symlinks inside the root that lead out of it.
    (root / "evil").symlink_to(base / "outside")                        # a dataset folder
    (root / "obj" / "evil.json").symlink_to(base / "secret.json")       # a file
    (root / "obj" / "tiff" / "evil.tif").symlink_to(base / "outside/tiff/pic.tif")
    (root / "linkdir").symlink_to(base)                                 # a folder above
    (root / ".hidden").mkdir()
    (root / ".hidden" / "lanterna.json").write_text(f'{{"s": "{SENTINEL}"}}')
    return base


@pytest.fixture
def recording(base: Path, monkeypatch: pytest.MonkeyPatch) -> Iterator[list[str]]:
    real = pyvips.Image.new_from_file

    def spy(path: str, **kwargs: Any) -> pyvips.Image:
        _OPENED.append(str(path))
        return real(path, **kwargs)

    monkeypatch.setattr(pyvips.Image, "new_from_file", spy)
    _OPENED.clear()
    _RECORDING[0] = True
    yield _OPENED
    _RECORDING[0] = False


def _outside_reads(base: Path, opened: list[str]) -> list[str]:
    """Return the recorded paths inside ``base`` that resolve outside ``base/root``."""
    root = (base / "root").resolve()
    bad = []
    for path in opened:
        resolved = Path(path).resolve()
        if resolved.is_relative_to(base.resolve()) and not resolved.is_relative_to(root):
            bad.append(path)
    return bad


ATTACKS = [
    "/datasets/../secret.txt",
    "/datasets/%2e%2e/secret.txt",
    "/datasets/%2E%2E/secret.json",
    "/datasets/obj/%2e%2e/%2e%2e/secret.json",
    "/datasets/obj%2F..%2F..%2Fsecret.json",
    "/datasets/..%2fsecret.json",
    "/datasets/obj/..%5C..%5Csecret.json",
    "/datasets/obj\\..\\..\\secret.json",
    "/datasets/%2Fetc%2Fpasswd",
    "/datasets//etc/passwd",
    "/datasets/obj/%00.json",
    "/datasets/obj/lanterna.json%00.png",
    "/datasets/evil/secret.json",
    "/datasets/evil/lanterna.json",
    "/datasets/obj/evil.json",
    "/datasets/linkdir/secret.json",
    "/datasets/.hidden/lanterna.json",
    "/iiif/3/evil/pic/info.json",
    "/iiif/3/evil/pic/full/max/0/default.png",
    "/iiif/3/obj/evil/info.json",
    "/iiif/3/obj/evil/full/max/0/default.png",
    "/iiif/3/obj/..%2F..%2Foutside%2Ftiff%2Fpic/info.json",
    "/iiif/3/%2e%2e/outside/pic/info.json",
    "/iiif/3/obj/%2e%2e/info.json",
    "/iiif/3/obj/pic%00/info.json",
    "/iiif/3/obj/pic\\..\\evil/info.json",
    "/iiif/3/linkdir/outside/info.json",
]


@pytest.mark.parametrize("path", ATTACKS)
def test_traversal_over_real_http_reads_nothing_outside(base: Path, path: str,
                                                        recording: list[str]) -> None:
    server = LiveServer(base / "root")
    try:
        conn = http.client.HTTPConnection("127.0.0.1", server.port, timeout=10)
        conn.request("GET", path)  # sent as is: no client-side normalisation of .. or %2e
        resp = conn.getresponse()
        body = resp.read()
        conn.close()
    finally:
        server.close()
    assert resp.status in (400, 404), (path, resp.status)
    assert SENTINEL.encode() not in body and b"Traceback" not in body
    assert _outside_reads(base, recording) == []


@pytest.mark.parametrize("path", ATTACKS)
def test_traversal_through_the_test_client(base: Path, path: str, recording: list[str]) -> None:
    client = create_app({"DATA_ROOT": base / "root"}).test_client()
    resp = client.get(path)
    assert resp.status_code in (400, 404), (path, resp.status_code)
    assert SENTINEL.encode() not in resp.data
    assert _outside_reads(base, recording) == []


def test_the_files_inside_the_root_still_work(base: Path, recording: list[str]) -> None:
    client = create_app({"DATA_ROOT": base / "root"}).test_client()
    assert client.get("/iiif/3/obj/pic/full/max/0/default.png").status_code == 200
    assert client.get("/datasets/obj/lanterna.json").status_code == 200
    with client.get("/datasets/obj/iiif/pic/full/max/0/default.png") as tile:
        assert tile.status_code == 200
    assert _outside_reads(base, recording) == []
    # the spy does see reads (of the dataset's current version, what its link points to)
    assert any(p.endswith("/tiff/pic.tif") and "/.obj.v-" in p for p in recording)


@pytest.mark.parametrize("path", ["/datasets/obj/", "/datasets/obj", "/datasets/obj/iiif/",
                                  "/datasets/obj/tiff", "/datasets/", "/iiif/3/obj/",
                                  "/iiif/3/", "/iiif/3/obj/pic/"])
def test_no_directory_listings(base: Path, path: str, recording: list[str]) -> None:
    client = create_app({"DATA_ROOT": base / "root"}).test_client()
    resp = client.get(path)
    assert resp.status_code == 404 and b"pic.tif" not in resp.data and b"iiif" not in resp.data
    assert not [p for p in recording if Path(p).resolve().is_relative_to(base.resolve())
                and Path(p).is_dir()]


def test_oversized_output_is_refused(base: Path) -> None:
    client = create_app({"DATA_ROOT": base / "root", "IIIF_MAX_AREA": 1000,
                         "IIIF_UPSCALING": True}).test_client()
    resp = client.get("/iiif/3/obj/pic/full/^6000,4000/0/default.jpg")
    assert resp.status_code == 400 and b"limits" in resp.data
    assert client.get("/iiif/3/obj/pic/full/max/0/default.jpg").status_code == 200


@pytest.mark.parametrize("path, target", [
    ("/iiif/3/obj/pic/full/max/0/default.jpg", "lanterna.server.image_response.compute_image"),
    ("/iiif/3/obj/pic/info.json", "lanterna.server.image_api.info_document"),
    ("/datasets/obj/lanterna.json", "lanterna.server.app._json_response"),
])
def test_an_internal_failure_is_a_short_500_without_traceback(
        base: Path, monkeypatch: pytest.MonkeyPatch, path: str, target: str) -> None:
    def fail(*args: object, **kwargs: object) -> None:
        raise RuntimeError(f"boom at {base}/secret.txt")

    monkeypatch.setattr(target, fail)
    client = create_app({"DATA_ROOT": base / "root"}).test_client()
    resp = client.get(path)
    assert resp.status_code == 500 and resp.mimetype == "text/plain"
    assert resp.data == b"500 Internal Server Error\n"
    assert b"Traceback" not in resp.data and b"boom" not in resp.data


def test_http_errors_are_plain_text(base: Path) -> None:
    client = create_app({"DATA_ROOT": base / "root"}).test_client()
    resp = client.post("/datasets/obj/lanterna.json")
    assert resp.status_code == 405 and resp.mimetype == "text/plain"
    assert "GET" in resp.headers["Allow"] and b"<" not in resp.data
    missing = client.get("/nope")
    assert missing.status_code == 404 and missing.data == b"404 Not Found\n"
