"""Pyramidal TIFFs: lossless for coefficient planes, one per image, recorded, written atomically."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
import pyvips

from lanterna.cli import main
from lanterna.tiler.dataset.layers import add_image_layer, add_ptm_layer
from lanterna.tiler.dataset.writer import DatasetWriter
from lanterna.tiler.iiif.encoding import TileFormat
from lanterna.tiler.iiif.pyramid import vips_from_array
from lanterna.tiler.iiif.tiff import tiff_options, write_tiff
from tests.python.fixtures.ptm import random_ptm_of_size
from tests.python.fixtures.ptm_writer import write_ptm


def _pages(path: Path) -> list[tuple[int, int]]:
    first = pyvips.Image.new_from_file(str(path))
    n = first.get("n-pages")
    return [(p.width, p.height) for p in
            (pyvips.Image.new_from_file(str(path), page=k) for k in range(n))]


def test_png_type_tiff_is_lossless_tiled_and_pyramidal(tmp_path: Path) -> None:
    data = np.random.default_rng(3).integers(0, 256, (700, 1100, 3), dtype=np.uint8)
    path = write_tiff(vips_from_array(data), tmp_path / "a.tif", fmt="png")
    img = pyvips.Image.new_from_file(str(path))
    assert np.array_equal(img.numpy(), data)
    assert (img.get("tile-width"), img.get("tile-height")) == (256, 256)
    assert _pages(path) == [(1100, 700), (550, 350), (275, 175), (137, 87)]
    assert [p.name for p in tmp_path.iterdir()] == ["a.tif"]


def test_jpg_type_tiff_is_close(tmp_path: Path) -> None:
    blocks = np.random.default_rng(4).integers(0, 256, (30, 40, 3), dtype=np.uint8)
    data = np.kron(blocks, np.ones((10, 10, 1), np.uint8))
    path = write_tiff(vips_from_array(data), tmp_path / "b.tif", fmt="jpg")
    err = np.abs(pyvips.Image.new_from_file(str(path)).numpy().astype(int) - data).mean()
    assert 0 < err < 3  # lossy, but Q90


def test_tiff_options_follow_the_tile_format() -> None:
    """WebP trees' TIFFs are lossless deflate (what every TIFF reader reads); JPEG keeps its Q."""
    assert tiff_options("webp")["compression"] == "deflate"
    assert tiff_options(TileFormat("webp", 60))["compression"] == "deflate"
    assert tiff_options("jpg")["Q"] == 90
    assert tiff_options(TileFormat("jpg", 75)) | {"Q": 0} == tiff_options("jpg") | {"Q": 0}
    assert tiff_options(TileFormat("jpg", 75))["Q"] == 75


def test_failed_write_leaves_no_file(tmp_path: Path) -> None:
    with pytest.raises(ValueError):
        write_tiff(vips_from_array(np.zeros((4, 4, 3), np.uint8)), tmp_path / "c.tif", fmt="gif")
    assert list(tmp_path.iterdir()) == []


def test_dataset_writer_writes_and_records_one_tiff_per_image(tmp_path: Path) -> None:
    ptm = random_ptm_of_size(300, 200)
    rgb = vips_from_array(np.full((200, 300, 3), 90, np.uint8))
    with DatasetWriter(tmp_path / "obj", name="obj", label="O", width=300, height=200,
                       tiff=True) as ds:
        add_ptm_layer(ds, ptm)
        add_image_layer(ds, rgb, layer_id="photo", share_key="same")
        add_image_layer(ds, rgb, layer_id="photo2", share_key="same")
    desc = json.loads((tmp_path / "obj/lanterna.json").read_text())
    tiffs = sorted(p.name for p in (tmp_path / "obj/tiff").iterdir())
    assert tiffs == sorted(f"{ident}.tif" for ident in desc["images"])
    assert "photo.tif" in tiffs and "photo2.tif" not in tiffs
    for ident, image in desc["images"].items():
        assert image["tiff"] == f"tiff/{ident}.tif"
    # The coefficient planes are stored bit for bit: same pixels as the lossless pyramid's
    # full/max (PNG or lossless WebP, whichever --plane-format auto found smaller).
    for ident in ("ptm_c0", "ptm_c1"):
        ext = desc["images"][ident]["format"]
        assert ext in ("png", "webp") and "quality" not in desc["images"][ident]
        tree = pyvips.Image.new_from_file(
            str(tmp_path / f"obj/iiif/{ident}/full/max/0/default.{ext}")).numpy()
        tif = pyvips.Image.new_from_file(str(tmp_path / f"obj/tiff/{ident}.tif")).numpy()
        assert np.array_equal(tree, tif)


def test_dataset_without_tiff_flag_has_none(tmp_path: Path) -> None:
    with DatasetWriter(tmp_path / "obj", name="obj", label="O", width=30, height=20) as ds:
        add_ptm_layer(ds, random_ptm_of_size(30, 20))
    assert not (tmp_path / "obj/tiff").exists()
    desc = json.loads((tmp_path / "obj/lanterna.json").read_text())
    assert all("tiff" not in image for image in desc["images"].values())


def test_import_tiff_flag(tmp_path: Path) -> None:
    src = tmp_path / "x.ptm"
    write_ptm(src, random_ptm_of_size(64, 48), "PTM_FORMAT_LRGB")
    assert main(["import", str(src), "-o", str(tmp_path / "x"), "--tiff"]) == 0
    desc = json.loads((tmp_path / "x/lanterna.json").read_text())
    assert desc["images"] and all((tmp_path / "x" / image["tiff"]).is_file()
                                  for image in desc["images"].values())
