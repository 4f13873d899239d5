"""docs/nginx/lanterna.conf, as documented, serving an exported tree (skipped without nginx).

Only ``listen`` and ``root`` are changed (a free loopback port, a temporary folder); nginx runs
in the foreground as one process. Checks: ``nginx -t``, the IIIF Image API validator at level 0,
and the headers docs/deploy.md promises (CORS, media types, caching, gzip, 303, preflight).
"""

from __future__ import annotations

import http.client
import re
import shutil
import socket
import subprocess
import sys
import time
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path

import pytest

from lanterna.tiler.dataset.export import export
from lanterna.tiler.dataset.layers import add_image_layer
from lanterna.tiler.dataset.writer import DatasetWriter
from lanterna.tiler.inputs.images import load_rgb_image
from tests.python.fixtures.dataset_kinds import build_kinds
from tests.python.fixtures.paths import REPO, SHARED, shared_file
from tests.python.fixtures.stored import stored_format

CONF = REPO / "docs" / "nginx" / "lanterna.conf"
IDENT = "67352ccc-d1b0-11e1-89ae-279075081939"
NGINX = shutil.which("nginx") or ("/usr/sbin/nginx" if Path("/usr/sbin/nginx").is_file() else None)
pytestmark = pytest.mark.skipif(NGINX is None, reason="nginx not installed (apt-get install nginx)")


@dataclass
class Nginx:
    port: int
    www: Path

    def request(self, method: str, path: str,
                headers: dict[str, str] | None = None) -> tuple[int, dict[str, str], bytes]:
        conn = http.client.HTTPConnection("127.0.0.1", self.port, timeout=10)
        conn.request(method, path, headers=headers or {})
        resp = conn.getresponse()
        body = resp.read()
        conn.close()
        return resp.status, {k.lower(): v for k, v in resp.getheaders()}, body


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        port: int = s.getsockname()[1]
        return port


def site_conf(port: int, www: Path) -> str:
    text = CONF.read_text()
    text = text.replace("    listen [::]:80;\n", "")
    text, n_listen = re.subn(r"listen 80;", f"listen 127.0.0.1:{port};", text)
    text, n_root = re.subn(r"root /srv/lanterna/www;", f"root {www};", text)
    assert n_listen == 1 and n_root == 1, "the documented config changed shape"
    return text


def main_conf(tmp: Path, site: Path) -> str:
    temp = "\n".join(f"    {kind}_temp_path {tmp}/{kind};"
                     for kind in ("client_body", "proxy", "fastcgi", "uwsgi", "scgi"))
    return (f"daemon off;\nmaster_process off;\npid {tmp}/nginx.pid;\n"
            f"error_log {tmp}/error.log;\nevents {{}}\n"
            f"http {{\n    include /etc/nginx/mime.types;\n"
            f"    default_type application/octet-stream;\n    access_log off;\n{temp}\n"
            f"    include {site};\n}}\n")


@pytest.fixture(scope="module")
def nginx(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Nginx]:
    assert NGINX is not None
    tmp = tmp_path_factory.mktemp("nginx")
    port, www = free_port(), tmp / "www"
    root = tmp / "root"
    build_kinds(root)
    png = SHARED / f"iiif-validator/{IDENT}.png"
    if png.is_file():
        img = load_rgb_image(png)
        with DatasetWriter(root / "validator", name="validator", label="validator",
                           width=img.width, height=img.height) as ds:
            add_image_layer(ds, img, layer_id=IDENT, label="IIIF validator test image")
    viewer = tmp / "viewer"
    (viewer / "assets").mkdir(parents=True)
    (viewer / "index.html").write_text("<!doctype html><title>viewer</title>")
    (viewer / "assets" / "index-abc123.js").write_text("export {};\n" * 50)
    export(root, www / "iiif", f"http://127.0.0.1:{port}/iiif", viewer=viewer)
    (www / ".iiif.old-x").mkdir()
    (www / ".iiif.old-x" / "secret.json").write_text("{}")
    (tmp / "lanterna.conf").write_text(site_conf(port, www))
    (tmp / "nginx.conf").write_text(main_conf(tmp, tmp / "lanterna.conf"))
    check = subprocess.run([NGINX, "-t", "-p", str(tmp), "-c", str(tmp / "nginx.conf")],
                           capture_output=True, text=True, timeout=30)
    assert check.returncode == 0, check.stderr
    proc = subprocess.Popen([NGINX, "-p", str(tmp), "-c", str(tmp / "nginx.conf")],
                            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    server = Nginx(port, www)
    try:
        for _ in range(100):
            try:
                server.request("HEAD", "/iiif/")
                break
            except OSError:
                time.sleep(0.05)
        yield server
    finally:
        proc.terminate()
        proc.wait(10)


def test_level0_validator_passes_through_nginx(nginx: Nginx) -> None:
    shared_file(f"iiif-validator/{IDENT}.png")
    validate = shutil.which("iiif-validate.py", path=str(Path(sys.executable).parent))
    assert validate is not None, "iiif-validate.py missing: pip install -e '.[dev]'"
    proc = subprocess.run(
        [sys.executable, validate, "-s", f"127.0.0.1:{nginx.port}", "-p",
         "iiif/validator/iiif", "-i", IDENT, "--version=3.0", "--level", "0", "-v"],
        capture_output=True, text=True, timeout=120)
    report = proc.stdout + proc.stderr
    done = re.search(r"Done \((\d+) tests, (\d+) failures\)", report)
    assert proc.returncode == 0 and done is not None, report
    assert int(done.group(1)) >= 5 and int(done.group(2)) == 0, report


def test_json_media_types_cors_caching_and_gzip(nginx: Nginx) -> None:
    status, h, body = nginx.request("GET", "/iiif/multi/manifest.json",
                                    {"Accept-Encoding": "gzip"})
    assert status == 200 and h["access-control-allow-origin"] == "*"
    assert h["content-type"] == "application/ld+json"
    assert h["content-encoding"] == "gzip" and h["cache-control"] == "no-cache"
    assert "etag" in h and "last-modified" in h
    status, h, _ = nginx.request("GET", "/iiif/multi/manifest.json",
                                 {"If-None-Match": h["etag"]})
    assert status == 304
    _, h, _ = nginx.request("GET", "/iiif/multi/iiif/ptm_c0/info.json", {"Accept-Encoding": "gzip"})
    assert h["content-type"] == "application/ld+json" and h["content-encoding"] == "gzip"
    _, h, _ = nginx.request("GET", "/iiif/multi/lanterna.json", {"Accept-Encoding": "gzip"})
    assert h["content-type"] == "application/json" and h["content-encoding"] == "gzip"
    assert h["access-control-allow-origin"] == "*"


#: How each plane tile format's files begin, and the media type nginx must send.
MAGIC = {"png": (b"\x89PNG", "image/png"), "webp": (b"RIFF", "image/webp"),
         "jpg": (b"\xff\xd8\xff", "image/jpeg")}


def test_tiles_and_viewer_assets(nginx: Nginx) -> None:
    # the plane's format is what --plane-format auto chose (png or lossless webp: the smaller)
    fmt = stored_format(nginx.www / "iiif" / "multi", "ptm_c0")
    status, h, body = nginx.request("GET", f"/iiif/multi/iiif/ptm_c0/full/max/0/default.{fmt}")
    magic, media_type = MAGIC[fmt]
    assert status == 200 and h["content-type"] == media_type and body.startswith(magic)
    assert h["access-control-allow-origin"] == "*"
    assert h["cache-control"] == "public, max-age=86400"
    _, h, _ = nginx.request("GET", "/iiif/multi/iiif/ptm_preview/full/max/0/default.jpg")
    assert h["content-type"] == "image/jpeg"
    _, h, _ = nginx.request("GET", "/iiif/viewer/assets/index-abc123.js")
    assert h["cache-control"] == "public, max-age=31536000, immutable"
    status, h, body = nginx.request("GET", "/iiif/")
    assert status == 200 and b"viewer/?manifest=" in body and h["cache-control"] == "no-cache"


def test_preflight_redirect_and_hidden_folders(nginx: Nginx) -> None:
    status, h, _ = nginx.request("OPTIONS", "/iiif/multi/manifest.json",
                                 {"Origin": "https://viewer.example", "Access-Control-"
                                  "Request-Method": "GET", "Access-Control-Request-Headers":
                                  "accept"})
    assert status == 204 and h["access-control-allow-origin"] == "*"
    assert "GET" in h["access-control-allow-methods"]
    assert "accept" in h["access-control-allow-headers"].lower()
    status, h, _ = nginx.request("GET", "/iiif/multi/iiif/ptm_c0")
    assert status == 303
    assert h["location"] == f"http://127.0.0.1:{nginx.port}/iiif/multi/iiif/ptm_c0/info.json"
    assert nginx.request("GET", "/iiif/multi/iiif/ptm_c0/")[0] == 303
    assert nginx.request("GET", "/.iiif.old-x/secret.json")[0] == 404
    assert nginx.request("GET", "/elsewhere")[0] == 404
