"""``lanterna serve --workers N``: gunicorn serves the same app (info.json, tiles), stops
cleanly."""

from __future__ import annotations

import json
import os
import signal
import socket
import subprocess
import sys
import time
import urllib.error
import urllib.request
from collections.abc import Iterator
from pathlib import Path

import pytest
import pyvips

from lanterna.cli import main
from lanterna.server.wsgi import gunicorn_settings
from lanterna.tiler.dataset.layers import add_ptm_layer
from lanterna.tiler.dataset.writer import DatasetWriter
from tests.python.fixtures.ptm import random_ptm_of_size

#: Readiness deadline for the server to accept connections (not a performance bound).
START_DEADLINE_S = 60


@pytest.fixture(scope="module")
def root(tmp_path_factory: pytest.TempPathFactory) -> Path:
    root = tmp_path_factory.mktemp("root")
    with DatasetWriter(root / "obj", name="obj", label="Object", width=300, height=200,
                       base_url="https://example.org/pub", tiff=True) as ds:
        add_ptm_layer(ds, random_ptm_of_size(300, 200))
    return root


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        port: int = s.getsockname()[1]
        return port


def _children(pid: int) -> list[int]:
    """The child process ids of ``pid`` (Linux /proc)."""
    kids: list[int] = []
    for task in Path(f"/proc/{pid}/task").iterdir():
        kids += [int(k) for k in (task / "children").read_text().split()]
    return kids


def _get(url: str) -> tuple[int, dict[str, str], bytes]:
    with urllib.request.urlopen(url, timeout=30) as resp:
        return resp.status, dict(resp.headers.items()), resp.read()


@pytest.fixture(scope="module")
def server(root: Path) -> Iterator[tuple[subprocess.Popen[str], str]]:
    port = _free_port()
    lanterna = Path(sys.executable).parent / "lanterna"
    proc = subprocess.Popen([str(lanterna), "serve", str(root), "--workers", "2",
                             "--port", str(port), "--max-size", "150"],
                            stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    url = f"http://127.0.0.1:{port}"
    deadline = time.monotonic() + START_DEADLINE_S
    while True:
        try:
            with socket.create_connection(("127.0.0.1", port), timeout=1):
                break
        except OSError:
            if proc.poll() is not None or time.monotonic() > deadline:
                proc.kill()
                pytest.fail(f"server did not start: {proc.communicate()[0]}")
            time.sleep(0.1)
    yield proc, url
    if proc.poll() is None:
        proc.kill()
    proc.communicate()  # reap it and close its pipe


def test_gunicorn_serves_info_json_and_tiles(server: tuple[subprocess.Popen[str], str],
                                             root: Path) -> None:
    proc, url = server
    base = f"{url}/datasets/obj/iiif/ptm_c0"
    status, headers, body = _get(f"{base}/info.json")
    assert status == 200
    assert headers["Server"].startswith("gunicorn")
    assert headers["Access-Control-Allow-Origin"] == "*"
    info = json.loads(body)
    assert info["id"] == base  # ids rewritten to the served URL, as under the dev server
    assert (info["width"], info["height"]) == (300, 200)

    tile = next(p for p in sorted((root / "obj/iiif/ptm_c0").rglob("default.*")))
    path = tile.relative_to(root).as_posix()
    status, headers, body = _get(f"{url}/datasets/{path}")
    assert status == 200 and headers["Server"].startswith("gunicorn")
    assert body == tile.read_bytes()
    assert pyvips.Image.new_from_buffer(body, "").width > 0

    # one arbiter (the lanterna process itself) forks two worker processes (one after the other)
    deadline = time.monotonic() + START_DEADLINE_S
    while len(_children(proc.pid)) < 2 and time.monotonic() < deadline:
        time.sleep(0.1)
    assert len(_children(proc.pid)) == 2


def test_image_server_limits_from_the_command_line(
        server: tuple[subprocess.Popen[str], str]) -> None:
    """--max-size reaches the level-1 image server of every gunicorn worker."""
    _, url = server
    info = json.loads(_get(f"{url}/iiif/3/obj/ptm_c0/info.json")[2])
    assert (info["maxWidth"], info["maxHeight"]) == (150, 150)
    assert _get(f"{url}/iiif/3/obj/ptm_c0/full/120,/0/default.png")[0] == 200
    with pytest.raises(urllib.error.HTTPError) as err:
        _get(f"{url}/iiif/3/obj/ptm_c0/0,0,200,100/200,/0/default.png")
    err.value.close()
    assert err.value.code == 400


def test_gunicorn_stops_cleanly_on_sigterm(server: tuple[subprocess.Popen[str], str]) -> None:
    proc, url = server
    workers = _children(proc.pid)
    proc.send_signal(signal.SIGTERM)
    output, _ = proc.communicate(timeout=60)
    assert proc.returncode == 0, output
    assert "Lanterna serving" in output and "with gunicorn, 2 workers" in output
    assert "Traceback" not in output
    for pid in workers:
        assert not os.path.exists(f"/proc/{pid}") or "zombie" in Path(
            f"/proc/{pid}/status").read_text()
    with pytest.raises(OSError):
        socket.create_connection(("127.0.0.1", int(url.rsplit(":", 1)[1])), timeout=1).close()


@pytest.mark.parametrize("argv", [["--workers", "0"], ["--threads", "4"],
                                  ["--workers", "2", "--threads", "0"]])
def test_bad_worker_options_are_refused(root: Path, argv: list[str],
                                        capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["serve", str(root), *argv]) == 2
    assert "lanterna: error:" in capsys.readouterr().err


def test_gunicorn_settings_suit_static_tiles() -> None:
    s = gunicorn_settings("127.0.0.1", 8000, 4, 8)
    assert s["bind"] == ["127.0.0.1:8000"] and s["workers"] == 4
    assert s["worker_class"] == "gthread" and s["threads"] == 8
    assert s["keepalive"] > 0 and s["timeout"] > 0 and s["sendfile"] is True
    with pytest.raises(ValueError):
        gunicorn_settings("127.0.0.1", 8000, 0)

