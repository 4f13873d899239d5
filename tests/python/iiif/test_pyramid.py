"""IIIF level-0 pyramids written by dzsave, with its gaps fixed."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
import pyvips

from lanterna.tiler.iiif import geometry as geo
from lanterna.tiler.iiif.encoding import TileFormat
from lanterna.tiler.iiif.pyramid import vips_from_array, write_pyramid


def _image(w: int, h: int, seed: int = 0) -> np.ndarray:
    return np.random.default_rng(seed).integers(0, 256, (h, w, 3), dtype=np.uint8)


@pytest.mark.parametrize(("w", "h"), [(200, 150), (256, 256), (300, 1000), (1001, 777), (513, 2)])
@pytest.mark.parametrize("fmt", ["png", "jpg", "webp"])
def test_every_tile_openseadragon_or_the_spec_asks_for_exists(tmp_path: Path, w: int, h: int,
                                                              fmt: str) -> None:
    out = tmp_path / "img"
    info = write_pyramid(vips_from_array(_image(w, h)), out, "http://h/iiif/img", fmt=fmt)
    assert json.loads((out / "info.json").read_text()) == info
    factors = info["tiles"][0]["scaleFactors"]
    ts = info["tiles"][0]["width"]
    wanted = set(geo.osd_tile_paths(w, h, ts, factors))
    wanted |= {geo.canonical_path(w, h, t) for f in factors for t in geo.spec_tiles(w, h, ts, f)}
    wanted |= {f"full/{s['width']},{s['height']}" for s in info["sizes"]}
    missing = [p for p in sorted(wanted) if not (out / p / "0" / f"default.{fmt}").is_file()]
    assert missing == []
    # level 0 requires full/max in jpg whatever the tile format
    assert (out / "full/max/0/default.jpg").is_file()
    for p in wanted:  # each file has the pixel size its URL says
        req = geo.parse_region_size(w, h, p)
        tile = pyvips.Image.new_from_file(str(out / p / "0" / f"default.{fmt}"))
        assert (tile.width, tile.height) == (req.sw, req.sh), p


def test_info_json_fixes_dzsave_gaps(tmp_path: Path) -> None:
    info = write_pyramid(vips_from_array(_image(1001, 777)), tmp_path / "a", "http://h/p/a",
                         fmt="png")
    assert info["@context"] == "http://iiif.io/api/image/3/context.json"
    assert info["id"] == "http://h/p/a"
    assert info["type"] == "ImageService3" and info["profile"] == "level0"
    assert (info["width"], info["height"]) == (1001, 777)
    assert info["sizes"] == [{"width": 251, "height": 195}, {"width": 501, "height": 389},
                             {"width": 1001, "height": 777}]
    assert info["preferredFormats"] == ["png"] and info["extraFormats"] == ["png"]
    assert "maxWidth" not in info
    jpg = write_pyramid(vips_from_array(_image(64, 64)), tmp_path / "b", "http://h/p/b", fmt="jpg")
    assert "preferredFormats" not in jpg and "extraFormats" not in jpg
    webp = write_pyramid(vips_from_array(_image(64, 64)), tmp_path / "c", "http://h/p/c",
                         fmt=TileFormat("webp", 60))
    assert webp["preferredFormats"] == ["webp"] and webp["extraFormats"] == ["webp"]


def test_webp_tiles_are_lossless_and_near_lossless_within_its_level(tmp_path: Path) -> None:
    img = _image(600, 300, seed=3)
    smooth = np.repeat(np.repeat(img[::8, ::8], 8, 0), 8, 1)[:300, :600]  # near-lossless acts
    write_pyramid(vips_from_array(img), tmp_path / "w", "http://h/w", fmt="webp")
    write_pyramid(vips_from_array(smooth), tmp_path / "n", "http://h/n", fmt=TileFormat("webp", 40))
    tile = "256,0,256,256/256,256/0/default.webp"
    exact = pyvips.Image.new_from_file(str(tmp_path / "w" / tile)).numpy()
    np.testing.assert_array_equal(exact, img[0:256, 256:512])
    near = pyvips.Image.new_from_file(str(tmp_path / "n" / tile)).numpy().astype(int)
    err = np.abs(near - smooth[0:256, 256:512])
    assert 0 < err.max() <= 8  # lossy, by at most libwebp's level-40 step


def test_jpg_quality_is_the_one_asked_for_and_4_4_4(tmp_path: Path) -> None:
    img = _image(256, 256, seed=5)
    sizes = {}
    for q in (50, 95):
        write_pyramid(vips_from_array(img), tmp_path / f"q{q}", "http://h/q",
                      fmt=TileFormat("jpg", q))
        tile = tmp_path / f"q{q}/full/max/0/default.jpg"
        sizes[q] = tile.stat().st_size
        # libvips reads back the chroma subsampling: none (4:4:4) at any quality
        assert pyvips.Image.new_from_file(str(tile)).get("jpeg-chroma-subsample") == "4:4:4"
    assert sizes[50] < sizes[95] / 1.5


def test_png_tiles_are_lossless_at_full_resolution(tmp_path: Path) -> None:
    img = _image(600, 300, seed=3)
    write_pyramid(vips_from_array(img), tmp_path / "p", "http://h/p", fmt="png")
    tile = pyvips.Image.new_from_file(str(tmp_path / "p/256,0,256,256/256,256/0/default.png"))
    np.testing.assert_array_equal(tile.numpy(), img[0:256, 256:512])
    edge = pyvips.Image.new_from_file(str(tmp_path / "p/512,256,88,44/88,44/0/default.png"))
    np.testing.assert_array_equal(edge.numpy(), img[256:300, 512:600])


def test_existing_output_is_refused(tmp_path: Path) -> None:
    (tmp_path / "x").mkdir()
    with pytest.raises(FileExistsError):
        write_pyramid(vips_from_array(_image(10, 10)), tmp_path / "x", "http://h/x")


def test_rejects_non_uint8_arrays() -> None:
    with pytest.raises(ValueError, match="uint8"):
        vips_from_array(np.zeros((4, 4, 3), np.float32))  # type: ignore[arg-type]
