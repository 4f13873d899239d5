"""The /iiif/3 image server: info.json, pixels against numpy, levels read, caching, statuses."""

from __future__ import annotations

import os
from pathlib import Path
from typing import Any

import numpy as np
import numpy.typing as npt
import pytest
import pyvips
from flask.testing import FlaskClient

from lanterna.server.app import create_app
from lanterna.tiler.dataset.layers import add_image_layer
from lanterna.tiler.dataset.writer import DatasetWriter
from lanterna.tiler.iiif import geometry as geo
from lanterna.tiler.iiif.pyramid import vips_from_array

W, H = 1100, 700
BASE = "/iiif/3/obj/pic"


def _source() -> npt.NDArray[np.uint8]:
    """A smooth colour image (resampling errors stay small) with a sharp block for alignment."""
    yy, xx = np.mgrid[0:H, 0:W].astype(np.float64)
    img = np.stack([xx / W * 255, yy / H * 255, 128 + 100 * np.sin(xx / 90 + yy / 70)], axis=-1)
    img[300:340, 500:560] = (255, 0, 40)
    return np.clip(np.round(img), 0, 255).astype(np.uint8)


SOURCE = _source()


@pytest.fixture(scope="module")
def root(tmp_path_factory: pytest.TempPathFactory) -> Path:
    root = tmp_path_factory.mktemp("api") / "root"
    with DatasetWriter(root / "obj", name="obj", label="O", width=W, height=H, tiff=True) as ds:
        add_image_layer(ds, vips_from_array(SOURCE), layer_id="pic", fmt="png")
        add_image_layer(ds, vips_from_array(SOURCE), layer_id="photo", fmt="jpg")
    with DatasetWriter(root / "plain", name="plain", label="P", width=40, height=30) as ds:
        add_image_layer(ds, vips_from_array(SOURCE[:30, :40]), layer_id="pic", fmt="png")
    return root


def _client(root: Path, **config: Any) -> FlaskClient:
    return create_app({"DATA_ROOT": root, **config}).test_client()


@pytest.fixture
def client(root: Path) -> FlaskClient:
    return _client(root)


def _pixels(data: bytes) -> npt.NDArray[np.uint8]:
    return np.asarray(pyvips.Image.new_from_buffer(data, "").numpy())


def _area_resize(a: npt.NDArray[np.uint8], w: int, h: int) -> npt.NDArray[np.float64]:
    """Resize by averaging: each output pixel is the mean of the source pixels it covers."""
    ys = np.linspace(0, a.shape[0], h + 1).round().astype(int)
    xs = np.linspace(0, a.shape[1], w + 1).round().astype(int)
    f = a.astype(np.float64)
    rows = np.add.reduceat(f, ys[:-1], axis=0) / np.diff(ys)[:, None, None]
    return np.add.reduceat(rows, xs[:-1], axis=1) / np.diff(xs)[None, :, None]


def test_info_json(client: FlaskClient) -> None:
    resp = client.get(f"{BASE}/info.json")
    assert resp.status_code == 200 and resp.mimetype == "application/json"
    info = resp.get_json()
    assert info["id"] == f"http://localhost{BASE}"
    assert (info["type"], info["profile"], info["width"], info["height"]) == (
        "ImageService3", "level1", W, H)
    assert (info["maxWidth"], info["maxHeight"], info["maxArea"]) == (16383, 16383, 16777216)
    assert info["tiles"] == [{"width": 256, "height": 256, "scaleFactors": [1, 2, 4, 8]}]
    assert info["sizes"][-1] == {"width": W, "height": H} and info["sizes"][0]["width"] == 138
    assert info["preferredFormats"] == ["png"]
    assert set(info["extraFeatures"]) >= {"regionByPct", "sizeByConfinedWh", "mirroring"}
    assert "sizeUpscaling" not in info["extraFeatures"]
    assert resp.headers["Link"] == '<http://iiif.io/api/image/3/level1.json>;rel="profile"'
    assert resp.headers["Access-Control-Allow-Origin"] == "*"
    assert "preferredFormats" not in client.get("/iiif/3/obj/photo/info.json").get_json()


def test_info_json_ld_and_base_redirect(client: FlaskClient) -> None:
    resp = client.get(f"{BASE}/info.json", headers={"Accept": "application/ld+json"})
    assert resp.headers["Content-Type"] == (
        'application/ld+json;profile="http://iiif.io/api/image/3/context.json"')
    redirect = client.get(BASE)
    assert redirect.status_code == 303 and redirect.headers["Location"].endswith(
        f"{BASE}/info.json")


def test_limits_come_from_the_config(root: Path) -> None:
    client = _client(root, IIIF_MAX_WIDTH=600, IIIF_MAX_HEIGHT=600, IIIF_MAX_AREA=200_000,
                     IIIF_UPSCALING=True, IIIF_TILE_SIZE=512)
    info = client.get(f"{BASE}/info.json").get_json()
    assert (info["maxWidth"], info["maxHeight"], info["maxArea"]) == (600, 600, 200_000)
    assert info["tiles"][0]["width"] == 512 and "sizeUpscaling" in info["extraFeatures"]
    assert all(s["width"] * s["height"] <= 200_000 for s in info["sizes"])
    img = _pixels(client.get(f"{BASE}/full/max/0/default.png").data)
    assert img.shape[1] <= 600 and img.shape[0] * img.shape[1] <= 200_000
    assert client.get(f"{BASE}/full/600,/0/default.png").status_code == 400
    up = client.get(f"{BASE}/0,0,100,50/^pct:200/0/default.png")
    assert up.status_code == 200 and _pixels(up.data).shape == (100, 200, 3)


@pytest.mark.parametrize("region", ["0,0,256,256", "500,300,60,40", "1024,512,300,300",
                                    "full", "pct:50,50,10,10", "square"])
def test_regions_at_full_resolution_are_exact(client: FlaskClient, region: str) -> None:
    resp = client.get(f"{BASE}/{region}/max/0/default.png")
    assert resp.status_code == 200 and resp.mimetype == "image/png"
    named = {"full": (0, 0, W, H), "pct:50,50,10,10": (550, 350, 110, 70),
             "square": (200, 0, 700, 700)}
    x, y, w, h = named[region] if region in named else (int(v) for v in region.split(","))
    assert np.array_equal(_pixels(resp.data), SOURCE[y:y + h, x:x + w])


@pytest.mark.parametrize("path, box, size, mean_tol, max_tol", [
    # Pyramid tiles at scale factors 2 and 4 are the level's pixels: a 2x2 / 4x4 box mean,
    # rounded (measured: mean 0.15 / 0.40, max 0 / 1).
    ("0,0,512,512/256,256", (0, 0, 512, 512), (256, 256), 0.5, 1),
    ("512,512,512,188/128,47", (512, 512, 512, 188), (128, 47), 0.5, 1),
    # Other sizes: a level read, then a lanczos resize, against numpy's area mean (measured:
    # mean 0.30-0.31, max 13-24 at the edges of the sharp red block, where filters differ).
    ("full/300,", (0, 0, W, H), (300, 191), 0.6, 32),
    ("100,50,700,500/!210,210", (100, 50, 700, 500), (210, 150), 0.6, 32),
    ("full/pct:37", (0, 0, W, H), (407, 259), 0.6, 32),
])
def test_resized_requests_match_numpy(client: FlaskClient, path: str,
                                      box: tuple[int, int, int, int], size: tuple[int, int],
                                      mean_tol: float, max_tol: int) -> None:
    resp = client.get(f"{BASE}/{path}/0/default.png")
    out = _pixels(resp.data).astype(np.float64)
    x, y, w, h = box
    expected = _area_resize(SOURCE[y:y + h, x:x + w], *size)
    assert out.shape == expected.shape
    err = np.abs(out - expected)  # in grey levels
    assert err.mean() <= mean_tol and err.max() <= max_tol


def test_small_outputs_read_a_small_level(client: FlaskClient,
                                          monkeypatch: pytest.MonkeyPatch) -> None:
    pages: list[int] = []
    real = pyvips.Image.new_from_file

    def spy(path: str, **kwargs: Any) -> pyvips.Image:
        if "revalidate" in kwargs:  # the pixel read (not the header scan)
            pages.append(kwargs.get("page", 0))
        return real(path, **kwargs)

    monkeypatch.setattr(pyvips.Image, "new_from_file", spy)
    for path, page in [("full/137,", 3), ("full/275,", 2), ("full/276,", 1), ("full/max", 0),
                       ("0,0,2048,2048/256,", 2), ("0,0,1024,1024/128,", 3),
                       ("0,0,256,256/256,", 0), ("0,0,256,256/128,", 1)]:
        pages.clear()
        assert client.get(f"{BASE}/{path}/0/default.jpg").status_code == 200
        assert pages == [page], path


def test_every_advertised_tile_is_served(client: FlaskClient) -> None:
    info = client.get(f"{BASE}/info.json").get_json()
    tiles = info["tiles"][0]
    paths = set(geo.osd_tile_paths(W, H, tiles["width"], tiles["scaleFactors"]))
    paths |= {geo.canonical_path(W, H, t) for f in tiles["scaleFactors"]
              for t in geo.spec_tiles(W, H, tiles["width"], f)}
    paths |= {f"full/{s['width']},{s['height']}" for s in info["sizes"]}
    assert len(paths) > 20
    for path in sorted(paths):
        resp = client.get(f"{BASE}/{path}/0/default.jpg")
        assert resp.status_code == 200, path
        req = geo.parse_region_size(W, H, path)
        assert _pixels(resp.data).shape[:2] == (req.sh, req.sw), path


@pytest.mark.parametrize("rotation, transform", [
    ("90", lambda a: np.rot90(a, -1)), ("180", lambda a: np.rot90(a, 2)),
    ("270", lambda a: np.rot90(a, 1)), ("!0", np.fliplr), ("!90", lambda a: np.rot90(
        np.fliplr(a), -1)), ("360", lambda a: a),
])
def test_rotation_and_mirroring(client: FlaskClient, rotation: str, transform: Any) -> None:
    resp = client.get(f"{BASE}/480,280,120,100/max/{rotation}/default.png")
    assert np.array_equal(_pixels(resp.data), transform(SOURCE[280:380, 480:600]))


def test_qualities(client: FlaskClient) -> None:
    crop = SOURCE[0:64, 0:64].astype(np.float64)
    gray = _pixels(client.get(f"{BASE}/0,0,64,64/max/0/gray.png").data)
    assert gray.ndim == 2 or gray.shape[2] == 1
    # libvips' b-w: the luminance of the linear-light colour, encoded back with the sRGB curve.
    lin = np.where(crop <= 10.31, crop / 255 / 12.92, ((crop / 255 + 0.055) / 1.055) ** 2.4)
    y = lin @ np.array([0.2126, 0.7152, 0.0722])
    luma = 255 * np.where(y <= 0.0031308, 12.92 * y, 1.055 * y ** (1 / 2.4) - 0.055)
    assert np.abs(gray.reshape(64, 64) - luma).mean() < 2
    bitonal = _pixels(client.get(f"{BASE}/full/200,/0/bitonal.png").data)
    assert set(np.unique(bitonal)) == {0, 255}
    color = _pixels(client.get(f"{BASE}/0,0,64,64/max/0/color.png").data)
    assert np.array_equal(color, SOURCE[0:64, 0:64])


@pytest.mark.parametrize("fmt, mimetype, magic", [
    ("jpg", "image/jpeg", b"\xff\xd8\xff"), ("png", "image/png", b"\x89PNG"),
    ("webp", "image/webp", b"RIFF"), ("tif", "image/tiff", b"II*\x00"),
])
def test_formats(client: FlaskClient, fmt: str, mimetype: str, magic: bytes) -> None:
    resp = client.get(f"{BASE}/0,0,100,80/max/0/default.{fmt}")
    assert resp.status_code == 200 and resp.mimetype == mimetype and resp.data.startswith(magic)
    out = _pixels(resp.data).astype(int)
    err = np.abs(out - SOURCE[0:80, 0:100]).mean()
    assert err == 0 if fmt != "jpg" else err < 3  # webp is lossless for png-type images


def test_jpg_type_image_is_served_from_its_jpeg_tiff(client: FlaskClient) -> None:
    out = _pixels(client.get("/iiif/3/obj/photo/0,0,200,200/max/0/default.png").data)
    assert 0 < np.abs(out.astype(int) - SOURCE[:200, :200]).mean() < 3


def test_caching_headers_and_conditional_requests(client: FlaskClient, root: Path) -> None:
    url = f"{BASE}/0,0,256,256/256,256/0/default.jpg"
    first = client.get(url)
    etag = first.headers["ETag"]
    assert etag.startswith('"') and not etag.startswith("W/")  # strong
    assert first.headers["Cache-Control"] == "public, max-age=86400"
    assert first.headers["Last-Modified"]
    assert f'<http://localhost{BASE}/0,0,256,256/max/0/default.jpg>;rel="canonical"' in (
        first.headers["Link"])
    # The same image asked for in another form has the same ETag.
    assert client.get(f"{BASE}/0,0,256,256/max/0/default.jpg").headers["ETag"] == etag
    assert client.get(f"{BASE}/0,0,256,256/128,/0/default.jpg").headers["ETag"] != etag
    again = client.get(url, headers={"If-None-Match": etag})
    assert again.status_code == 304 and again.data == b"" and again.headers["ETag"] == etag
    since = client.get(url, headers={"If-Modified-Since": first.headers["Last-Modified"]})
    assert since.status_code == 304
    assert client.get(url, headers={"If-None-Match": '"other"'}).status_code == 200
    info = client.get(f"{BASE}/info.json")
    assert client.get(f"{BASE}/info.json",
                      headers={"If-None-Match": info.headers["ETag"]}).status_code == 304
    # A rewritten file (new mtime) changes the ETag.
    tiff = root / "obj/tiff/pic.tif"
    st = tiff.stat()
    os.utime(tiff, ns=(st.st_atime_ns, st.st_mtime_ns + 5_000_000_000))
    try:
        assert client.get(url).headers["ETag"] != etag
        assert client.get(url, headers={"If-None-Match": etag}).status_code == 200
    finally:
        os.utime(tiff, ns=(st.st_atime_ns, st.st_mtime_ns))


def test_304_happens_before_any_pixel_work(client: FlaskClient,
                                           monkeypatch: pytest.MonkeyPatch) -> None:
    url = f"{BASE}/full/200,/0/default.jpg"
    etag = client.get(url).headers["ETag"]

    def boom(*args: object, **kwargs: object) -> None:
        raise AssertionError("rendered")

    monkeypatch.setattr("lanterna.server.image_response.compute_image", boom)
    assert client.get(url, headers={"If-None-Match": etag}).status_code == 304


def test_head_and_options(client: FlaskClient) -> None:
    url = f"{BASE}/full/100,/0/default.jpg"
    head = client.head(url)
    assert head.status_code == 200 and head.data == b""
    assert int(head.headers["Content-Length"]) == len(client.get(url).data)
    options = client.options(url)
    assert options.status_code == 200 and "GET" in options.headers["Allow"]
    assert options.headers["Access-Control-Allow-Origin"] == "*"


@pytest.mark.parametrize("path, status", [
    ("/iiif/3/obj/nope/info.json", 404),
    ("/iiif/3/nope/pic/info.json", 404),
    ("/iiif/3/plain/pic/info.json", 404),           # a dataset without --tiff
    ("/iiif/3/obj/nope/full/max/0/default.jpg", 404),
    ("/iiif/3/obj/nope", 404),
    (f"{BASE}/full/max/0/default.gif", 501),
    (f"{BASE}/full/max/45/default.jpg", 501),
    (f"{BASE}/full/^max/0/default.jpg", 501),
    (f"{BASE}/full/max/0/default.xyz", 400),
    (f"{BASE}/full/1101,/0/default.jpg", 400),       # upscaling without ^
    (f"{BASE}/1100,0,10,10/max/0/default.jpg", 400),  # outside the image
    (f"{BASE}/0,0,0,10/max/0/default.jpg", 400),
    (f"{BASE}/0,0,10,10/0,0/0/default.jpg", 400),
    (f"{BASE}/full/max/0/default.jpg/extra", 404),
])
def test_error_statuses_are_short_plain_text(client: FlaskClient, path: str, status: int) -> None:
    resp = client.get(path)
    assert resp.status_code == status
    assert resp.mimetype == "text/plain" and len(resp.data) < 300
    assert resp.headers["Access-Control-Allow-Origin"] == "*"


def test_oversized_output_is_refused_before_pixel_work(root: Path,
                                                       monkeypatch: pytest.MonkeyPatch) -> None:
    def boom(*args: object, **kwargs: object) -> None:
        raise AssertionError("rendered")

    monkeypatch.setattr("lanterna.server.image_response.compute_image", boom)
    client = _client(root, IIIF_MAX_AREA=10_000)
    for size in ("1000,", "pct:50", "101,100", "!500,500"):
        resp = client.get(f"{BASE}/full/{size}/0/default.jpg")
        assert resp.status_code == 400 and b"limits" in resp.data, size


def test_tiff_without_a_pyramid_is_not_decoded_for_a_thumbnail(
        root: Path, tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    flat = tmp_path / "root"
    (flat / "flat/tiff").mkdir(parents=True)
    vips_from_array(SOURCE).tiffsave(str(flat / "flat/tiff/pic.tif"), tile=True)
    client = _client(flat, IIIF_MAX_AREA=100_000)
    assert client.get("/iiif/3/flat/pic/full/100,/0/default.jpg").status_code == 400
    ok = client.get("/iiif/3/flat/pic/0,0,300,300/100,/0/default.png")
    assert ok.status_code == 200
    assert _pixels(ok.data).shape == (100, 100, 3)


def test_encode_accepts_every_band_layout() -> None:
    from lanterna.server.image_response import apply_quality, encode

    for bands in (1, 2, 3, 4):
        img = pyvips.Image.black(8, 6, bands=bands).cast("uchar") + 100
        img = img.copy(interpretation="b-w" if bands < 3 else "srgb")
        for quality in ("default", "color", "gray", "bitonal"):
            out = apply_quality(img, quality)
            for fmt in ("jpg", "png", "webp", "tif"):
                data = encode(out, fmt, lossless=True)
                back = pyvips.Image.new_from_buffer(data, "")
                assert (back.width, back.height) == (8, 6), (bands, quality, fmt)
