"""Tile encodings: one table of formats and settings, checked on construction."""

from __future__ import annotations

import numpy as np
import pytest
import pyvips

from lanterna.tiler.iiif.encoding import JPG, PNG, WEBP, TileFormat, encode, tile_format
from lanterna.tiler.iiif.pyramid import vips_from_array


def _decode(data: bytes) -> np.ndarray:
    return np.asarray(pyvips.Image.new_from_buffer(data, "").numpy())


def test_names_become_default_formats() -> None:
    assert tile_format("png") == PNG and tile_format("webp") == WEBP and tile_format("jpg") == JPG
    assert tile_format(TileFormat("jpg", 70)).quality == 70
    assert [f.label() for f in (PNG, WEBP, JPG, TileFormat("jpg", 70), TileFormat("webp", 60))] \
        == ["png", "webp", "jpg:90", "jpg:70", "webp:near60"]
    assert PNG.lossless and WEBP.lossless
    assert not JPG.lossless and not TileFormat("webp", 80).lossless


@pytest.mark.parametrize(("ext", "quality"), [("gif", None), ("png", 5), ("jpg", 0),
                                              ("jpg", 101), ("webp", 50)])
def test_bad_formats_are_refused(ext: str, quality: int | None) -> None:
    with pytest.raises(ValueError):
        TileFormat(ext, quality)


def test_dz_suffix_carries_the_save_options() -> None:
    assert PNG.dz_suffix() == ".png[compression=3]"
    assert TileFormat("jpg", 80).dz_suffix() == ".jpg[Q=80,subsample_mode=off]"
    assert TileFormat("webp", 40).dz_suffix().startswith(".webp[lossless=true,")
    assert "near_lossless=true,Q=40" in TileFormat("webp", 40).dz_suffix()


def test_lossless_formats_decode_to_the_same_pixels() -> None:
    px = np.random.default_rng(1).integers(0, 256, (40, 50, 3), dtype=np.uint8)
    for fmt in (PNG, WEBP):
        np.testing.assert_array_equal(_decode(encode(vips_from_array(px), fmt)), px)
    lossy = _decode(encode(vips_from_array(px), TileFormat("jpg", 50))).astype(int)
    assert np.abs(lossy - px).max() > 0
