"""The fit's file-backed planes (:mod:`~lanterna.tiler.formats.strip_tiff`): rows appended in
any chunks come back as written, through the reader and through libvips, whatever the size's
remainder by the 256-pixel tile; a writer that is not given its rows makes no file."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import pyvips

from lanterna.tiler.formats.strip_tiff import TILE, StripTiffWriter


@pytest.mark.parametrize(("width", "height", "bands", "chunk"),
                         [(600, 530, 3, 37), (256, 256, 3, 256), (1, 300, 1, 7),
                          (513, 1, 1, 1), (300, 700, 3, 300)])
def test_rows_come_back_as_written(tmp_path: Path, width: int, height: int, bands: int,
                                   chunk: int) -> None:
    rng = np.random.default_rng(width * height + bands)
    shape = (height, width, 3) if bands == 3 else (height, width)
    image = rng.integers(0, 256, shape, np.uint8)
    with StripTiffWriter(tmp_path / "p.tif", width, height, bands) as writer:
        for y0 in range(0, height, chunk):
            writer.write(image[y0:y0 + chunk])
        stored = writer.close()
    assert stored.shape == shape
    assert np.array_equal(np.asarray(stored), image)
    assert np.array_equal(stored[height // 3:height // 3 + 5], image[height // 3:height // 3 + 5])
    vips = stored.vips()
    assert (vips.width, vips.height, vips.bands) == (width, height, bands)
    assert np.array_equal(vips.numpy().reshape(shape), image)
    assert not (tmp_path / ".p.tif.part").exists()


def test_edge_tiles_are_padded_with_zeros(tmp_path: Path) -> None:
    """The tiles past the right and bottom edges hold zeros, not the bytes of earlier rows."""
    width, height = 300, 260
    with StripTiffWriter(tmp_path / "p.tif", width, height, 3) as writer:
        writer.write(np.full((height, width, 3), 200, np.uint8))
        writer.close()
    tiled = pyvips.Image.new_from_file(str(tmp_path / "p.tif"))
    assert tiled.get("tile-width") == TILE and tiled.get("tile-height") == TILE
    # libtiff hands out whole tiles: the padding is what the file stores past the edges
    raw = (tmp_path / "p.tif").read_bytes()
    size = TILE * TILE * 3
    tiles = [np.frombuffer(raw, np.uint8, size, 16 + i * size).reshape(TILE, TILE, 3)
             for i in range(4)]
    assert (tiles[0] == 200).all()
    assert (tiles[1][:, :width - TILE] == 200).all() and (tiles[1][:, width - TILE:] == 0).all()
    assert (tiles[2][:height - TILE] == 200).all() and (tiles[2][height - TILE:] == 0).all()
    assert (tiles[3][height - TILE:] == 0).all() and (tiles[3][:, width - TILE:] == 0).all()


def test_too_many_or_too_few_rows_make_no_file(tmp_path: Path) -> None:
    writer = StripTiffWriter(tmp_path / "p.tif", 10, 4, 3)
    writer.write(np.zeros((3, 10, 3), np.uint8))
    with pytest.raises(ValueError, match="more than 4 rows"):
        writer.write(np.zeros((2, 10, 3), np.uint8))
    with pytest.raises(ValueError, match="3 of 4 rows"):
        writer.close()
    assert list(tmp_path.iterdir()) == []


def test_an_error_inside_the_block_leaves_nothing(tmp_path: Path) -> None:
    with pytest.raises(RuntimeError), StripTiffWriter(tmp_path / "p.tif", 10, 4, 1) as writer:
        writer.write(np.zeros((2, 10), np.uint8))
        raise RuntimeError("the fit failed")
    assert list(tmp_path.iterdir()) == []


def test_rows_of_the_wrong_shape_are_refused(tmp_path: Path) -> None:
    with StripTiffWriter(tmp_path / "p.tif", 10, 4, 3) as writer:
        with pytest.raises(ValueError, match="uint8"):
            writer.write(np.zeros((2, 11, 3), np.uint8))
        with pytest.raises(ValueError, match="uint8"):
            writer.write(np.zeros((2, 10, 3), np.float32))
        writer.abort()
