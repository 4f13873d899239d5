"""What ``lanterna serve`` and ``lanterna demo`` print: a busy port in one line before anything
else, no Werkzeug banner, request lines only with ``--verbose`` (5xx always), a missing viewer.
"""

from __future__ import annotations

import re
import select
import shutil
import signal
import socket
import subprocess
import sys
import urllib.error
import urllib.request
from collections.abc import Iterator
from pathlib import Path

import pytest

from lanterna.cli import main
from lanterna.tiler.dataset.layers import add_ptm_layer
from lanterna.tiler.dataset.writer import DatasetWriter
from tests.python.fixtures.ptm import random_ptm_of_size

LANTERNA = Path(sys.executable).parent / "lanterna"
#: Deadline for the server to print its first line (not a performance bound).
START_DEADLINE_S = 60
INFO = "/datasets/obj/iiif/ptm_c0/info.json"
BROKEN = "/iiif/3/obj/ptm_c1/info.json"  # its TIFF is garbage: a 500
GUNICORN = ["--workers", "1"]


@pytest.fixture(scope="module")
def root(tmp_path_factory: pytest.TempPathFactory) -> Path:
    root = tmp_path_factory.mktemp("root")
    with DatasetWriter(root / "obj", name="obj", label="Object", width=300, height=200,
                       tiff=True) as ds:
        add_ptm_layer(ds, random_ptm_of_size(300, 200))
    (root / "obj/tiff/ptm_c1.tif").write_bytes(b"not a TIFF")
    return root


@pytest.fixture
def busy_port() -> Iterator[int]:
    with socket.create_server(("127.0.0.1", 0)) as sock:
        yield sock.getsockname()[1]


def _status(url: str) -> int:
    try:
        with urllib.request.urlopen(url, timeout=30) as resp:
            resp.read()
            return int(resp.status)
    except urllib.error.HTTPError as err:
        err.close()
        return err.code


def _session(root: Path, *options: str, fetch: tuple[str, ...] = (INFO,)
             ) -> tuple[list[int], str]:
    """Run ``lanterna serve ROOT --port 0 OPTIONS``, GET each path, stop it; return the statuses
    and everything it printed (stdout and stderr, ANSI colours removed)."""
    proc = subprocess.Popen([str(LANTERNA), "serve", str(root), "--port", "0", *options],
                            stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    assert proc.stdout is not None
    ready, _, _ = select.select([proc.stdout], [], [], START_DEADLINE_S)
    first = proc.stdout.readline() if ready else ""
    found = re.search(r"at (http://127\.0\.0\.1:\d+)/", first)
    try:
        statuses = [_status(found[1] + path) for path in fetch] if found else []
    finally:
        proc.send_signal(signal.SIGTERM)
        proc.wait(timeout=60)
        output = first + proc.stdout.read()  # the rest, from the same buffered reader
        proc.stdout.close()
    assert found, output
    return statuses, re.sub(r"\x1b\[[0-9;]*m", "", output)


@pytest.mark.parametrize("argv", [["serve", "ROOT"], ["serve", "ROOT", *GUNICORN],
                                  ["demo", "--root", "ROOT/new"]])
def test_a_busy_port_is_one_line_and_nothing_else(
        argv: list[str], root: Path, busy_port: int, capsys: pytest.CaptureFixture[str]) -> None:
    argv = [arg.replace("ROOT", str(root)) for arg in argv]
    assert main([*argv, "--port", str(busy_port)]) == 1
    out, err = capsys.readouterr()
    assert out == ""
    assert re.fullmatch(rf"lanterna {argv[0]}: error: port {busy_port} is in use "
                        r"\(try --port \d+\)\n", err), err
    assert not (root / "new").exists()  # the demo is not built for a server that cannot start


def test_the_suggested_port_is_free(root: Path, busy_port: int,
                                    capsys: pytest.CaptureFixture[str]) -> None:
    main(["serve", str(root), "--port", str(busy_port)])
    suggested = int(re.findall(r"--port (\d+)", capsys.readouterr().err)[0])
    assert suggested != busy_port
    socket.create_server(("127.0.0.1", suggested)).close()


@pytest.mark.parametrize("engine", [[], GUNICORN], ids=["werkzeug", "gunicorn"])
def test_requests_are_logged_only_with_verbose(root: Path, engine: list[str]) -> None:
    request_line = re.compile(rf'"GET {re.escape(INFO)} HTTP/1\.1" 200')
    statuses, quiet = _session(root, *engine)
    assert statuses == [200]
    assert not request_line.search(quiet), quiet
    statuses, verbose = _session(root, *engine, "--verbose")
    assert statuses == [200]
    assert request_line.search(verbose), verbose


@pytest.mark.parametrize("engine", [[], GUNICORN], ids=["werkzeug", "gunicorn"])
def test_errors_are_logged_without_verbose(root: Path, engine: list[str]) -> None:
    statuses, output = _session(root, *engine, fetch=(INFO, BROKEN))
    assert statuses == [200, 500]
    assert "unhandled error" in output and "Traceback" in output  # the app's log
    if not engine:  # Werkzeug's request line (gunicorn's access log is off: nothing to log it)
        assert f'"GET {BROKEN} HTTP/1.1" 500' in output
    assert INFO not in output


def test_the_built_in_server_says_what_it_is_without_the_werkzeug_banner(root: Path) -> None:
    _, output = _session(root)
    lines = output.splitlines()
    assert lines[0].startswith(f"Lanterna serving {root} at http://127.0.0.1:")
    assert lines[1].startswith("  obj: http://127.0.0.1:") and "/viewer/?manifest=" in lines[1]
    assert lines[2] == lines[1].replace("  obj: ", "  obj (in Mirador): ").replace(
        "/viewer/?manifest=", "/viewer/mirador.html?manifest=")
    assert lines[3].startswith("Local server for this machine (127.0.0.1)")
    assert "--workers N" in lines[3]
    for banner in ("development server", "WSGI server", "Running on", "CTRL+C", "Debug mode"):
        assert banner not in output


def test_a_dataset_with_presets_also_gets_its_simplified_viewer_url(tmp_path: Path) -> None:
    with DatasetWriter(tmp_path / "obj", name="obj", label="Object", width=64, height=48) as ds:
        add_ptm_layer(ds, random_ptm_of_size(64, 48))
    (tmp_path / "obj").resolve().joinpath("presets.json").write_text(
        '{"type": "LanternaPresets", "version": 1, "presets": {}, "base": [], "lens": []}')
    lines = _session(tmp_path)[1].splitlines()
    assert lines[1].startswith("  obj: http://127.0.0.1:") and "/viewer/?manifest=" in lines[1]
    assert lines[2].startswith("  obj (simplified viewer): http://127.0.0.1:")
    assert lines[2].endswith("/viewer/simple.html?manifest=" + lines[1].split("manifest=")[1])
    assert lines[3].endswith("/viewer/mirador.html?manifest=" + lines[1].split("manifest=")[1])


def test_hidden_copies_of_a_dataset_are_not_listed(tmp_path: Path) -> None:
    root = tmp_path / "root"
    with DatasetWriter(root / "obj", name="obj", label="Object", width=30, height=20) as ds:
        add_ptm_layer(ds, random_ptm_of_size(30, 20))
    for stale in (".obj.old-20250101T000000_abcdef", ".obj.tmp-a1b2c3"):
        shutil.copytree(root / "obj", root / stale)  # a half-deleted or killed writer's folder
    _, output = _session(root)
    assert [line.split(":")[0] for line in output.splitlines() if line.startswith("  ")] == [
        "  obj", "  obj (in Mirador)"]


def test_a_missing_viewer_is_one_warning(root: Path, tmp_path: Path,
                                         monkeypatch: pytest.MonkeyPatch,
                                         capsys: pytest.CaptureFixture[str]) -> None:
    served: list[socket.socket] = []

    def run_threaded(app: object, listener: socket.socket, access_log: bool) -> None:
        served.append(listener)
        listener.close()

    monkeypatch.setattr("lanterna.server.app.default_viewer", lambda: tmp_path / "no-viewer")
    monkeypatch.setattr("lanterna.server.local.run_threaded", run_threaded)
    assert main(["serve", str(root), "--port", "0"]) == 0
    out, err = capsys.readouterr()
    assert len(served) == 1 and "obj: http://127.0.0.1:" in out
    assert err == ("lanterna serve: warning: the viewer is not built, /viewer/ answers 404 "
                   "(run `make build` in the Lanterna checkout)\n")


def test_the_viewer_route_says_how_to_build_a_missing_viewer(root: Path, tmp_path: Path) -> None:
    from lanterna.server.app import create_app

    client = create_app({"DATA_ROOT": root, "VIEWER_DIR": tmp_path}).test_client()
    resp = client.get("/viewer/")
    assert resp.status_code == 404 and b"make build" in resp.data


def test_a_bad_port_is_refused_by_the_parser(root: Path,
                                             capsys: pytest.CaptureFixture[str]) -> None:
    with pytest.raises(SystemExit) as exit_:
        main(["serve", str(root), "--port", "70000"])
    assert exit_.value.code == 2
    assert "not a port number" in capsys.readouterr().err
