"""The authoring API under ``lanterna serve --workers 2``: the token reaches every worker, and
concurrent writes through several workers end in one whole library (the dataset lock)."""

from __future__ import annotations

import json
import threading
import urllib.error
import urllib.request
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest

from lanterna.manifests.validate import validate_manifest
from tests.python.fixtures.presets import read_json, small_dataset, small_library
from tests.python.fixtures.servers import lanterna_serve

TOKEN = "gunicorn-token-0123456789"


@pytest.fixture(scope="module")
def served(tmp_path_factory: pytest.TempPathFactory) -> Iterator[tuple[str, Path, str]]:
    """``(url, root, startup output)`` of a 2-worker server with a token file."""
    scratch = tmp_path_factory.mktemp("gunicorn-api")
    root = scratch / "root"
    small_dataset(root / "obj")
    token_file = scratch / "token"
    token_file.write_text(TOKEN + "\n")
    with lanterna_serve(root, "--workers", "2", "--authoring-token-file",
                        str(token_file)) as (url, lines):
        yield url, root, "".join(lines)


def _request(method: str, url: str, body: Any = None,
             headers: dict[str, str] | None = None) -> tuple[int, Any]:
    data = None if body is None else json.dumps(body).encode()
    req = urllib.request.Request(url, data=data, method=method, headers={
        "Content-Type": "application/json", **(headers or {})})
    try:
        with urllib.request.urlopen(req, timeout=60) as resp:
            return resp.status, json.loads(resp.read())
    except urllib.error.HTTPError as err:
        with err:
            return err.code, json.loads(err.read())


def test_the_startup_output_says_authoring_is_on_without_the_token(
        served: tuple[str, Path, str]) -> None:
    _, _, output = served
    assert "with gunicorn, 2 workers" in output
    assert "Authoring API: on (token from " in output
    assert TOKEN not in output


def test_every_worker_has_the_token(served: tuple[str, Path, str]) -> None:
    url, root, _ = served
    auth = {"Authorization": f"Bearer {TOKEN}"}
    # many requests over fresh connections: both workers answer some of them
    for _ in range(12):
        assert _request("GET", f"{url}/api/") == (200, {"authoring": True, "annotations": True})
    status, body = _request("PUT", f"{url}/api/datasets/obj/presets", small_library(),
                            {"Authorization": "Bearer not-the-token-at-all"})
    assert status == 401 and "authoring token" in body["error"]
    assert not (root / "obj" / "presets.json").exists()
    for _ in range(6):
        assert _request("PUT", f"{url}/api/datasets/obj/presets", small_library(), auth) == \
            (200, {"presets": 2})
    assert read_json(root / "obj" / "presets.json") == small_library()


def test_concurrent_puts_through_two_workers_leave_one_library_whole(
        served: tuple[str, Path, str]) -> None:
    url, root, _ = served
    auth = {"Authorization": f"Bearer {TOKEN}"}
    libraries = []
    for n in range(6):
        lib = small_library()
        lib["presets"] = {f"p{n}-{i}": {"label": f"P{i}", "layer": "uv", "mode": "color"}
                          for i in range(n + 1)}
        lib["base"] = [{"label": f"P{i}", "preset": f"p{n}-{i}"} for i in range(n + 1)]
        lib["lens"] = []
        libraries.append(lib)
    statuses: list[int] = []
    start = threading.Barrier(len(libraries))

    def put(lib: dict[str, Any]) -> None:
        start.wait()
        statuses.append(_request("PUT", f"{url}/api/datasets/obj/presets", lib, auth)[0])

    threads = [threading.Thread(target=put, args=(lib,)) for lib in libraries]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert statuses == [200] * len(libraries)
    ds = root / "obj"
    stored = read_json(ds / "presets.json")
    assert stored in libraries
    assert read_json(ds / "lanterna.json")["presets"] == stored
    manifest = read_json(ds / "manifest.json")
    assert validate_manifest(manifest) == [] and manifest["service"][0]["base"] == stored["base"]
    assert _request("GET", f"{url}/api/datasets/obj/presets") == (200, stored)
