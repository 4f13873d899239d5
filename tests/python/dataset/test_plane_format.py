"""``--plane-format``: parsing, and each plane group's format chosen by its source."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
import pyvips

from lanterna.errors import LanternaInputError
from lanterna.tiler.dataset.layers import add_ptm_layer
from lanterna.tiler.dataset.plane_format import (
    AUTO,
    PlaneFormat,
    choose_format,
    parse_plane_format,
    sample_tiles,
)
from lanterna.tiler.dataset.writer import DatasetWriter
from lanterna.tiler.formats.planes import PlaneGroup
from lanterna.tiler.formats.ptm import read_ptm
from lanterna.tiler.formats.ptm_model import Ptm
from lanterna.tiler.iiif import geometry as geo
from lanterna.tiler.iiif.encoding import TileFormat
from tests.python.fixtures.plane_bound import assert_within_bound
from tests.python.fixtures.ptm import smooth_ptm
from tests.python.fixtures.ptm_writer import write_ptm

W, H = 600, 520


def _source_groups(ptm: Ptm) -> list[np.ndarray]:
    assert ptm.rgb is not None
    return [ptm.coefficients[..., 0:3], ptm.coefficients[..., 3:6], ptm.rgb]


def _write(tmp_path: Path, ptm: Ptm, spec: PlaneFormat, name: str) -> tuple[Path, dict]:
    out = tmp_path / name
    with DatasetWriter(out, name=name, label=name, width=ptm.width, height=ptm.height) as ds:
        layer = add_ptm_layer(ds, ptm, plane_format=spec)
    return out, layer


def _level0(out: Path, plane: dict, w: int, h: int) -> tuple[np.ndarray, int]:
    """Level 0 assembled from the stored tiles, and the tiles' bytes."""
    folder = out / "iiif" / plane["service"]["id"].rsplit("/", 1)[1]
    level = np.zeros((h, w, 3), np.uint8)
    size = 0
    for t in geo.spec_tiles(w, h, 256, 1):
        path = folder / geo.canonical_path(w, h, t) / "0" / f"default.{plane['format']}"
        size += path.stat().st_size
        level[t.y:t.y + t.h, t.x:t.x + t.w] = pyvips.Image.new_from_file(str(path)).numpy()
    return level, size


@pytest.mark.parametrize(("text", "expected"), [
    ("auto", AUTO), ("png", PlaneFormat(TileFormat("png"))),
    ("WebP", PlaneFormat(TileFormat("webp"))), ("jpg", PlaneFormat(TileFormat("jpg"))),
    ("jpg:72", PlaneFormat(TileFormat("jpg", 72))),
    ("jpeg:100", PlaneFormat(TileFormat("jpg", 100)))])
def test_plane_formats_parse(text: str, expected: PlaneFormat) -> None:
    assert parse_plane_format(text) == expected


@pytest.mark.parametrize("text", ["", "gif", "jpg:", "jpg:0", "jpg:101", "jpg:x", "png:9",
                                  "webp:60", "auto:1"])
def test_bad_plane_formats_are_a_one_line_usage_error(text: str) -> None:
    with pytest.raises(LanternaInputError) as err:
        parse_plane_format(text)
    message = str(err.value)
    assert "\n" not in message and "auto, png, webp or jpg[:Q]" in message and repr(text) in message


def test_a_fixed_format_is_used_for_every_group() -> None:
    group = PlaneGroup(["R", "G", "B"], np.zeros((8, 8, 3), np.uint8), [1.0] * 3, [0.0] * 3)
    assert choose_format(group, PlaneFormat(TileFormat("jpg", 60))) == TileFormat("jpg", 60)


def test_the_sample_is_a_few_central_tiles_on_the_pyramid_grid() -> None:
    data = np.arange(1100 * 900 * 3, dtype=np.uint32).astype(np.uint8).reshape(900, 1100, 3)
    group = PlaneGroup(["R", "G", "B"], data, [1.0] * 3, [0.0] * 3)
    tiles = sample_tiles(group, 256)
    assert len(tiles) == 4 and all(t.shape == (256, 256, 3) for t in tiles)
    np.testing.assert_array_equal(tiles[0], data[256:512, 256:512])  # 5x4 tiles: 2nd row, col
    small = PlaneGroup(["R", "G", "B"], data[:100, :70], [1.0] * 3, [0.0] * 3)
    assert [t.shape for t in sample_tiles(small, 256)] == [(100, 70, 3)]


def test_a_jpeg_ptm_gets_lossy_tiles_within_the_bound_of_its_decode(tmp_path: Path) -> None:
    src = tmp_path / "s.ptm"
    write_ptm(src, smooth_ptm("lrgb", W, H, seed=3), "PTM_FORMAT_JPEG_LRGB", jpeg_quality=90)
    ptm = read_ptm(src)
    assert ptm.lossy
    out, layer = _write(tmp_path, ptm, AUTO, "auto")
    png_out, png_layer = _write(tmp_path, ptm, PlaneFormat(TileFormat("png")), "png")
    desc = json.loads((out / "lanterna.json").read_text())
    for plane, png_plane, source in zip(layer["planes"], png_layer["planes"],
                                        _source_groups(ptm), strict=True):
        image = desc["images"][plane["service"]["id"].rsplit("/", 1)[1]]
        assert plane["format"] in ("jpg", "webp") and "quality" in image  # lossy, not exact
        stored, size = _level0(out, plane, W, H)
        err = stored.astype(np.int16) - source  # against the reader's decode
        assert_within_bound(err)
        assert 0 < np.abs(err).max()  # lossy indeed
        assert size < _level0(png_out, png_plane, W, H)[1] / 2


def test_a_lossless_source_gets_the_smaller_of_png_and_webp(tmp_path: Path) -> None:
    rng = np.random.default_rng(5)
    smooth = smooth_ptm("lrgb", W, H, seed=4)
    assert not smooth.lossy
    noisy = Ptm("lrgb", rng.integers(0, 256, (H, W, 6), dtype=np.uint8), smooth.scale,
                smooth.bias, smooth.rgb)
    clear = 0
    for tag, ptm in (("smooth", smooth), ("noisy", noisy)):
        auto, layer = _write(tmp_path, ptm, AUTO, f"{tag}-auto")
        sizes = {}
        for ext in ("png", "webp"):
            out, fixed = _write(tmp_path, ptm, PlaneFormat(TileFormat(ext)), f"{tag}-{ext}")
            sizes[ext] = [_level0(out, p, W, H)[1] for p in fixed["planes"]]
        for i, (plane, source) in enumerate(zip(layer["planes"], _source_groups(ptm),
                                                strict=True)):
            stored, _ = _level0(auto, plane, W, H)
            np.testing.assert_array_equal(stored, source)  # exact whatever the format
            png, webp = sizes["png"][i], sizes["webp"][i]
            if max(png, webp) > 1.05 * min(png, webp):  # a clear winner on the whole level
                assert plane["format"] == ("png" if png < webp else "webp")
                clear += 1
    assert clear >= 3


def test_a_jpeg_source_re_encoded_at_its_own_quality_is_kept_as_jpeg(tmp_path: Path) -> None:
    """A Q90 JPEG plane (a Relight folder's plane_k.jpg) re-encoded at Q90 moves a few values in
    10⁵ by 3–4 and the rest by 0–1: within the bound, and about the source's bytes, where
    near-lossless WebP (every value within 2) would take twice the bytes."""
    rng = np.random.default_rng(11)
    smooth = smooth_ptm("lrgb", W, H, seed=8).coefficients[..., 0:3]
    noisy = np.clip(smooth.astype(np.int16) + rng.integers(-6, 7, smooth.shape), 0, 255)
    source_file = tmp_path / "plane_0.jpg"
    pyvips.Image.new_from_array(noisy.astype(np.uint8)).copy(interpretation="srgb").jpegsave(
        str(source_file), Q=90, subsample_mode="off")
    decoded = pyvips.Image.new_from_file(str(source_file)).numpy()
    group = PlaneGroup(["R", "G", "B"], decoded, [1.0] * 3, [0.0] * 3, lossy=True)
    chosen = choose_format(group)
    assert chosen.ext == "jpg" and chosen.quality is not None and chosen.quality <= 90
    stored = pyvips.Image.new_from_buffer(
        pyvips.Image.new_from_array(decoded).copy(interpretation="srgb").jpegsave_buffer(
            Q=chosen.quality, subsample_mode="off"), "").numpy()
    assert_within_bound(stored.astype(np.int16) - decoded)
