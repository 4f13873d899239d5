"""write_pyramid's extra files: ``sizes`` joined from level tiles, ``full/max`` from a thread."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import pyvips

from lanterna.tiler.iiif import geometry as geo
from lanterna.tiler.iiif import pyramid
from lanterna.tiler.iiif.encoding import TileFormat
from lanterna.tiler.iiif.pyramid import FULL_MAX_LIMIT, vips_from_array, write_pyramid


def _image(w: int, h: int) -> np.ndarray:
    return np.random.default_rng(7).integers(0, 256, (h, w, 3), dtype=np.uint8)


def _pixels(path: Path) -> np.ndarray:
    return np.asarray(pyvips.Image.new_from_file(str(path)).numpy())


@pytest.mark.parametrize(("w", "h"), [(1001, 777), (600, 300), (513, 2)])
def test_sizes_are_the_level_tiles_joined(tmp_path: Path, w: int, h: int) -> None:
    info = write_pyramid(vips_from_array(_image(w, h)), tmp_path / "p", "http://h/p", fmt="png")
    ts = info["tiles"][0]["width"]
    for factor in info["tiles"][0]["scaleFactors"]:
        sw, sh = geo.level_size(w, h, factor)
        if factor == 1 or {"width": sw, "height": sh} not in info["sizes"]:
            continue
        level = np.zeros((sh, sw, 3), np.uint8)
        for t in geo.spec_tiles(w, h, ts, factor):
            tile = _pixels(tmp_path / "p" / geo.canonical_path(w, h, t) / "0/default.png")
            x, y = t.x // factor, t.y // factor
            level[y:y + t.sh, x:x + t.sw] = tile
        np.testing.assert_array_equal(_pixels(tmp_path / f"p/full/{sw},{sh}/0/default.png"),
                                      level)


@pytest.mark.parametrize("fmt", ["png", "webp"])
def test_full_max_is_the_whole_image_in_both_formats(tmp_path: Path, fmt: str) -> None:
    img = _image(700, 500)
    write_pyramid(vips_from_array(img), tmp_path / "p", "http://h/p", fmt=fmt)
    np.testing.assert_array_equal(_pixels(tmp_path / f"p/full/max/0/default.{fmt}"), img)
    jpg = _pixels(tmp_path / "p/full/max/0/default.jpg")
    assert jpg.shape == img.shape
    # the size entry equal to the whole image is the same file as full/max
    assert (tmp_path / f"p/full/700,500/0/default.{fmt}").samefile(
        tmp_path / f"p/full/max/0/default.{fmt}")


def test_a_failed_full_max_leaves_nothing(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    real_render = pyramid._render

    def failing(image: pyvips.Image, req: geo.TileRequest, target: Path,
                fmt: TileFormat) -> None:
        if target.name.startswith("full-max"):
            raise OSError("disk full")
        real_render(image, req, target, fmt)

    monkeypatch.setattr(pyramid, "_render", failing)
    with pytest.raises(OSError, match="disk full"):
        write_pyramid(vips_from_array(_image(300, 200)), tmp_path / "p", "http://h/p")
    assert list(tmp_path.iterdir()) == []  # no output, no scratch folder


@pytest.mark.parametrize("fmt", ["jpg", "png", "webp"])
def test_full_max_of_a_large_image_is_its_first_level_within_the_limit(tmp_path: Path,
                                                                       fmt: str) -> None:
    """Past FULL_MAX_LIMIT, ``max`` is a reduced pyramid level, declared by maxWidth/maxHeight."""
    w, h = FULL_MAX_LIMIT * 2 + 300, 700  # factor 2 is still too wide: factor 4
    rng = np.random.default_rng(3)
    img = rng.integers(0, 256, (h // 4 + 1, w // 4 + 1, 3), np.uint8).repeat(4, 0).repeat(4, 1)
    img = np.ascontiguousarray(img[:h, :w])
    info = write_pyramid(vips_from_array(img), tmp_path / "p", "http://x/p", fmt=fmt)
    mw, mh = -(-w // 4), -(-h // 4)
    assert (info["maxWidth"], info["maxHeight"]) == (mw, mh) and max(mw, mh) <= FULL_MAX_LIMIT
    for ext in sorted({"jpg", fmt}):
        full = _pixels(tmp_path / f"p/full/max/0/default.{ext}")
        assert full.shape == (mh, mw, 3), ext
    if fmt != "jpg":  # the level's own tiles, losslessly: equal to the 4x4 block values
        np.testing.assert_array_equal(_pixels(tmp_path / f"p/full/max/0/default.{fmt}"),
                                      img[::4, ::4][:mh, :mw])
    # every tile a client asks for is still there
    assert (tmp_path / f"p/0,0,256,256/256,256/0/default.{fmt}").is_file()
