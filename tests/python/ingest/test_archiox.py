"""``lanterna import`` of lighting maps: an ARCHiOx-style manifest (URL or file) and a local
albedo + normal pair make one Lambert shape + material layer; bad inputs are one-line errors,
nothing written."""

from __future__ import annotations

import json
import os
import shutil
import threading
from collections.abc import Iterator
from http.server import BaseHTTPRequestHandler, ThreadingHTTPServer
from pathlib import Path
from typing import Any

import numpy as np
import numpy.typing as npt
import pytest
import pyvips

from lanterna.cli import main
from tests.python.fixtures.archiox import Site, maps, write_png, write_site
from tests.python.fixtures.servers import StaticServer


@pytest.fixture
def site(tmp_path: Path) -> Iterator[tuple[Site, StaticServer]]:
    with StaticServer(tmp_path / "site") as server:
        yield write_site(tmp_path / "site", server.url), server


def stored(out: Path) -> tuple[dict[str, Any], dict[str, npt.NDArray[np.uint8]]]:
    """The dataset's one layer and its stored plane images by map name (decoded full/max)."""
    desc = json.loads((out / "lanterna.json").read_text())
    assert len(desc["layers"]) == 1
    layer = desc["layers"][0]
    planes = {}
    for plane in layer["service"]["planes"]:
        image = plane["service"]["id"].rsplit("/", 1)[1]
        fmt = desc["images"][image]["format"]
        assert fmt in ("png", "webp"), "a lossless source stays lossless"
        vimg = pyvips.Image.new_from_file(str(out / "iiif" / image / "full" / "max" / "0" /
                                              f"default.{fmt}"))
        planes[plane["channels"][0]] = np.ndarray(
            (vimg.height, vimg.width, vimg.bands), np.uint8, vimg.write_to_memory())
    return layer, planes


def assert_lambert_layer(out: Path, site_maps: dict[str, npt.NDArray[np.uint8]]) -> dict[str, Any]:
    layer, planes = stored(out)
    service = layer["service"]
    assert service["layerType"] == "svbrdf"
    assert service["inputColorSpace"] == "srgb"
    assert [p["channels"] for p in service["planes"]] == [["NX", "NY", "NZ"],
                                                        ["KD_R", "KD_G", "KD_B"]]
    np.testing.assert_array_equal(planes["NX"], site_maps["normal"])
    np.testing.assert_array_equal(planes["KD_R"], site_maps["albedo"])
    return layer


def test_a_manifest_url_imports_its_albedo_and_normal_map(site: tuple[Site, StaticServer],
                                                         tmp_path: Path) -> None:
    s, server = site
    out = tmp_path / "out" / "tablet"
    assert main(["import", f"{s.url}/manifest.json", "-o", str(out)]) == 0
    layer = assert_lambert_layer(out, s.maps)
    assert layer["label"] == "ARCHiOx tablet (albedo + normal map)"
    desc = json.loads((out / "lanterna.json").read_text())
    assert (desc["label"], desc["summary"]) == ("ARCHiOx tablet", "A relightable tablet")
    fetched = [p for p in server.requests if not p.endswith("manifest.json")]
    infos = [i for i, p in enumerate(fetched) if p.endswith("/info.json")]
    images = [i for i, p in enumerate(fetched) if p.endswith("/default.png")]
    assert len(infos) == 2 and len(images) == 2
    assert max(infos) < min(images), "both sizes are checked before any image is downloaded"
    assert not any("/composite/" in p for p in fetched), "only the two maps are fetched"


def test_a_local_manifest_file_imports_the_same_layer(site: tuple[Site, StaticServer],
                                                     tmp_path: Path) -> None:
    s, _ = site
    local = tmp_path / "archiox.json"
    shutil.copy(s.manifest, local)
    out = tmp_path / "out" / "local"
    assert main(["import", str(local), "-o", str(out)]) == 0
    assert_lambert_layer(out, s.maps)


def test_a_local_albedo_and_normal_pair(tmp_path: Path) -> None:
    albedo, normal = maps(3)
    a, n = write_png(tmp_path / "tablet.png", albedo), write_png(tmp_path / "n.png", normal)
    out = tmp_path / "out" / "pair"
    assert main(["import", "--albedo", str(a), "--normal", str(n), "-o", str(out)]) == 0
    layer = assert_lambert_layer(out, {"albedo": albedo, "normal": normal})
    assert layer["id"] == "tablet"


def test_a_directx_pair_is_stored_in_the_opengl_convention(tmp_path: Path) -> None:
    albedo, normal = maps(4)
    directx = normal.copy()
    directx[..., 1] = 255 - directx[..., 1]
    a, n = write_png(tmp_path / "a.png", albedo), write_png(tmp_path / "n.png", directx)
    out = tmp_path / "out" / "dx"
    assert main(["import", "--albedo", str(a), "--normal", str(n), "--normal-convention",
                 "directx", "-o", str(out)]) == 0
    assert_lambert_layer(out, {"albedo": albedo, "normal": normal})


def _drop(map_type: str) -> Any:
    def edit(s: Site) -> None:
        doc = s.read()
        body = doc["items"][0]["items"][0]["items"][0]["body"]
        body["items"] = [i for i in body["items"]
                         if all(sv.get("mapType") != map_type for sv in i["service"])]
        s.write(doc)
    return edit


def _no_image_service(s: Site) -> None:
    doc = s.read()
    item = doc["items"][0]["items"][0]["items"][0]["body"]["items"][2]
    item["service"] = [sv for sv in item["service"] if "ImageService" not in
                       str(sv.get("type", sv.get("@type")))]
    s.write(doc)


def _smaller_albedo(s: Site) -> None:
    info = json.loads(s.info_path("albedo").read_text())
    s.info_path("albedo").write_text(json.dumps({**info, "width": 160, "height": 120}))


def _lying_info(s: Site) -> None:
    for name in ("albedo", "normal"):
        info = json.loads(s.info_path(name).read_text())
        s.info_path(name).write_text(json.dumps({**info, "width": 300}))


def _photo_as_normals(s: Site) -> None:
    write_png(s.root / "iiif/normal/full/max/0/default.png", s.maps["albedo"])


def _not_json(s: Site) -> None:
    s.manifest.write_text("<html>not a manifest</html>")


def _collection(s: Site) -> None:
    s.write({**s.read(), "type": "Collection"})


def _info_without_width(s: Site) -> None:
    info = json.loads(s.info_path("normal").read_text())
    del info["width"]
    s.info_path("normal").write_text(json.dumps(info))


def _missing_image(s: Site) -> None:
    (s.root / "iiif/albedo/full/max/0/default.png").unlink()


MAP_PATH = "items[0].items[0].items[0].body.items"
BAD = {
    "no normal map": (_drop("normal"), "no normal map: no painting Image with a "
                      "LightingMapExtension service of mapType normal (found mapType albedo)"),
    "no albedo map": (_drop("albedo"), "items[0]: a normal map but no albedo map"),
    "no image service": (_no_image_service, f"{MAP_PATH}[2].service: the normal map has no "
                         "ImageService3"),
    "maps of different sizes": (_smaller_albedo, f"{MAP_PATH}[1]: the albedo map is 160x120, the "
                                f"normal map ({MAP_PATH}[2]) 320x240"),
    "info.json lies": (_lying_info, "the image is 320x240, its info.json says 300x240"),
    "a photo as normal map": (_photo_as_normals, "not a normal map"),
    "not JSON": (_not_json, "not valid JSON"),
    "not a manifest": (_collection, 'type: expected "Manifest"'),
    "info.json without width": (_info_without_width, f'{MAP_PATH}[2]: '),
    "missing image": (_missing_image, "HTTP 404"),
}


@pytest.mark.parametrize("case", BAD)
def test_bad_manifests_are_one_line_errors(site: tuple[Site, StaticServer], tmp_path: Path,
                                           capsys: pytest.CaptureFixture[str], case: str) -> None:
    s, _ = site
    edit, problem = BAD[case]
    edit(s)
    out = tmp_path / "out"
    assert main(["import", f"{s.url}/manifest.json", "-o", str(out / "x")]) == 2
    err = capsys.readouterr().err.strip()
    assert "\n" not in err, err
    assert f"{s.url}/manifest.json" in err and problem in err, err
    if case == "info.json without width":
        assert 'needs "width"' in err
    assert not out.exists() or list(out.iterdir()) == [], "nothing written"


def test_the_pixel_limit_is_checked_before_any_download(
        site: tuple[Site, StaticServer], tmp_path: Path, capsys: pytest.CaptureFixture[str],
        monkeypatch: pytest.MonkeyPatch) -> None:
    s, server = site
    monkeypatch.setenv("LANTERNA_MAX_PIXELS", "50000")
    assert main(["import", f"{s.url}/manifest.json", "-o", str(tmp_path / "out" / "x")]) == 2
    err = capsys.readouterr().err
    assert "320x240" in err and "refused" in err, err
    assert not any(p.endswith("default.png") for p in server.requests)
    assert not (tmp_path / "out").exists()


def test_a_manifest_that_is_not_a_regular_file(tmp_path: Path,
                                               capsys: pytest.CaptureFixture[str]) -> None:
    fifo = tmp_path / "manifest.json"
    os.mkfifo(fifo)
    assert main(["import", str(fifo), "-o", str(tmp_path / "out" / "x")]) == 2
    err = capsys.readouterr().err.strip()
    assert "\n" not in err and "manifest.json" in err and "not a regular file" in err, err
    assert not (tmp_path / "out").exists()


def test_an_unreachable_manifest(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    with StaticServer(tmp_path / "empty") as server:
        url = server.url
    assert main(["import", f"{url}/manifest.json", "-o", str(tmp_path / "out" / "x")]) == 2
    err = capsys.readouterr().err.strip()
    assert "\n" not in err and f"{url}/manifest.json: cannot fetch a IIIF manifest" in err, err


@pytest.mark.parametrize("given", [["--albedo", "a.png"], ["--normal", "n.png"]])
def test_albedo_and_normal_go_together(tmp_path: Path, capsys: pytest.CaptureFixture[str],
                                       given: list[str]) -> None:
    assert main(["import", *given, "-o", str(tmp_path / "x")]) == 2
    assert "--albedo and --normal go together" in capsys.readouterr().err


def test_a_pair_of_different_sizes(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    albedo, normal = maps(5)
    a = write_png(tmp_path / "a.png", albedo[:200])
    n = write_png(tmp_path / "n.png", normal)
    assert main(["import", "--albedo", str(a), "--normal", str(n), "-o",
                 str(tmp_path / "out" / "x")]) == 2
    err = capsys.readouterr().err.strip()
    assert "\n" not in err and "a.png: map kd is 320x200, map normals is 320x240" in err, err
    assert not (tmp_path / "out").exists()


class _Redirect(BaseHTTPRequestHandler):
    def do_GET(self) -> None:  # noqa: N802 (http.server's name)
        self.send_response(302)
        self.send_header("Location", "ftp://127.0.0.1:1/manifest.json")
        self.end_headers()

    def log_message(self, format: str, *args: Any) -> None:
        pass


def test_a_redirect_to_another_scheme_is_refused(tmp_path: Path,
                                                 capsys: pytest.CaptureFixture[str]) -> None:
    server = ThreadingHTTPServer(("127.0.0.1", 0), _Redirect)
    thread = threading.Thread(target=server.serve_forever, daemon=True)
    thread.start()
    try:
        url = f"http://127.0.0.1:{server.server_address[1]}/manifest.json"
        assert main(["import", url, "-o", str(tmp_path / "out" / "x")]) == 2
    finally:
        server.shutdown()
        server.server_close()
    err = capsys.readouterr().err.strip()
    assert "\n" not in err and f"{url}: HTTP 302" in err, err
    assert not (tmp_path / "out").exists()


def test_a_long_label_makes_a_valid_layer_id(site: tuple[Site, StaticServer],
                                             tmp_path: Path) -> None:
    s, _ = site
    s.write({**s.read(), "label": {"none": ["Tablet, obverse; " * 20]}})
    out = tmp_path / "out" / "long"
    assert main(["import", f"{s.url}/manifest.json", "-o", str(out)]) == 0
    layer, _ = stored(out)
    assert layer["id"].startswith("Tablet_obverse_Tablet") and len(layer["id"]) <= 64
