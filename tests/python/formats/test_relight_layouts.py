"""Relight/OpenLIME tiled layouts (tiler/formats/relight_layouts.py): deepzoom, tarzoom and
itarzoom folders, written here the way Relight writes them (tests/python/fixtures/
relight_layouts.py), read back to exactly the planes of the ``image`` layout."""

from __future__ import annotations

import json
import os
import re
from pathlib import Path
from typing import Any

import numpy as np
import numpy.typing as npt
import pytest
import pyvips

from lanterna.cli import main
from lanterna.errors import LanternaInputError
from lanterna.tiler.formats.relight_layouts import open_tiled_plane
from lanterna.tiler.formats.relight_web import read_relight
from tests.python.fixtures.paths import shared_file
from tests.python.fixtures.relight_layouts import write_deepzoom, write_itarzoom, write_tarzoom

W, H = 37, 23  # three levels of 16 px tiles (37 → 18 → 9), partial last column and row
NPLANES = 18
U8 = npt.NDArray[np.uint8]


def planes_rgb(seed: int = 0) -> list[U8]:
    """Six smooth-plus-noise RGB plane images (a PTM rgb's 18 planes)."""
    rng = np.random.default_rng(seed)
    y, x = np.mgrid[0:H, 0:W]
    out = []
    for i in range(NPLANES // 3):
        base = np.stack([(x * (3 + i) + y * (5 - i) + 40 * c) % 256 for c in range(3)], -1)
        noise = rng.integers(0, 30, (H, W, 3))
        out.append(np.clip(base + noise, 0, 255).astype(np.uint8))
    return out


def info(fmt: str = "png") -> dict[str, Any]:
    rng = np.random.default_rng(1)
    return {"width": W, "height": H, "format": fmt, "type": "ptm", "colorspace": "rgb",
            "nplanes": NPLANES, "lights": [0.0, 0.0, 1.0],
            "materials": [{"scale": [round(float(v), 3) for v in rng.uniform(0.5, 2, NPLANES)],
                           "bias": [round(float(v), 3) for v in rng.uniform(0, 0.8, NPLANES)]}]}


def write_layout(folder: Path, layout: str, planes: list[U8], *, overlap: int = 1,
                 fmt: str = "png") -> Path:
    folder.mkdir(parents=True, exist_ok=True)
    (folder / "info.json").write_text(json.dumps(info(fmt)))
    if layout == "image":
        for k, rgb in enumerate(planes):
            pyvips.Image.new_from_array(rgb).copy(interpretation="srgb").pngsave(
                str(folder / f"plane_{k}.png"))
    elif layout == "itarzoom":
        write_itarzoom(folder, planes, overlap=overlap, fmt=fmt)
    else:
        writer = write_deepzoom if layout == "deepzoom" else write_tarzoom
        for k, rgb in enumerate(planes):
            writer(folder, f"plane_{k}", rgb, overlap=overlap, fmt=fmt)
    return folder


@pytest.mark.parametrize("layout", ["deepzoom", "tarzoom", "itarzoom"])
@pytest.mark.parametrize("overlap", [0, 1, 3])
def test_tiled_layouts_round_trip_to_the_image_layout(tmp_path: Path, layout: str,
                                                      overlap: int) -> None:
    planes = planes_rgb()
    flat = read_relight(write_layout(tmp_path / "image", "image", planes))
    tiled = read_relight(write_layout(tmp_path / layout, layout, planes, overlap=overlap))
    assert tiled.layer_type == flat.layer_type == "ptm"
    assert [g.channels for g in tiled.groups] == [g.channels for g in flat.groups]
    for a, b in zip(tiled.groups, flat.groups, strict=True):
        np.testing.assert_array_equal(np.asarray(a.data), np.asarray(b.data))
        assert (a.scale, a.bias) == (b.scale, b.bias)
    # and the bytes are the source's: group R0, R1, R2 (lu², lv², lu·lv) holds Relight's red
    # terms 3, 5, 4, i.e. planes 9, 15, 12: channel 0 of images 3, 5 and 4
    r0 = np.asarray(tiled.groups[0].data)
    for k, image in enumerate((3, 5, 4)):
        np.testing.assert_array_equal(r0[..., k], planes[image][..., 0])


def test_jpeg_tiles_decode_close_to_their_source(tmp_path: Path) -> None:
    planes = planes_rgb(2)
    folder = write_layout(tmp_path / "dz", "deepzoom", planes, fmt="jpg")
    image = open_tiled_plane(folder, 2, 6, W, H)
    assert image is not None
    got = np.asarray(image.numpy(), np.float64)
    assert got.shape == (H, W, 3)
    src = planes[2].astype(np.float64)
    err = np.abs(got - src).mean()  # JPEG Q95 4:4:4 of noisy tiles: a few code values
    shifted = np.abs(got[:, 1:] - src[:, :-1]).mean()  # what a misplaced tile would cost
    assert err < 5.0 and err < 0.3 * shifted, (err, shifted)


@pytest.mark.parametrize("depth", ["onepixel", "onetile"])
def test_libvips_dzsave_pyramids_are_read(tmp_path: Path, depth: str) -> None:
    """Relight's older GUI tiled with libvips ``dzsave`` (depth onetile); a standard Deep Zoom
    pyramid goes down to 1 px. Either way the deepest level is found and read."""
    rgb = planes_rgb(3)[0]
    pyvips.Image.new_from_array(rgb).copy(interpretation="srgb").dzsave(
        str(tmp_path / "plane_0"), layout="dz", tile_size=16, overlap=2, depth=depth,
        suffix=".png")
    image = open_tiled_plane(tmp_path, 0, 1, W, H)
    assert image is not None
    np.testing.assert_array_equal(image.numpy(), rgb)


def test_no_tiled_layout_is_none(tmp_path: Path) -> None:
    assert open_tiled_plane(tmp_path, 0, 6, W, H) is None


def test_multispectral_names(tmp_path: Path) -> None:
    """OpenLIME's multispectral planes: ``{basename}_NN`` per image, itarzoom ``{basename}``."""
    planes = planes_rgb(4)[:2]
    write_itarzoom(tmp_path, planes, stem="ms", overlap=0)
    image = open_tiled_plane(tmp_path, 1, 2, W, H, name="ms_01", interleaved="ms")
    assert image is not None
    np.testing.assert_array_equal(image.numpy(), planes[1])


# --- bad input: one line naming the file ---------------------------------------------------


def one_line_error(folder: Path) -> LanternaInputError:
    with pytest.raises(LanternaInputError) as err:
        read_relight(folder)
    assert "\n" not in str(err.value)
    return err.value


def test_truncated_blob(tmp_path: Path) -> None:
    folder = write_layout(tmp_path, "tarzoom", planes_rgb())
    blob = folder / "plane_3.tzb"
    blob.write_bytes(blob.read_bytes()[:-10])
    err = one_line_error(folder)
    assert str(err).startswith(f"{blob}: is truncated or badly indexed: plane_3.tzi offsets[")
    assert f"the blob has {blob.stat().st_size} bytes" in str(err)


def test_index_entry_past_the_blob(tmp_path: Path) -> None:
    folder = write_layout(tmp_path, "itarzoom", planes_rgb())
    index = json.loads((folder / "planes.tzi").read_text())
    index["offsets"][-1] += 5000
    (folder / "planes.tzi").write_text(json.dumps(index))
    err = one_line_error(folder)
    n = len(index["offsets"]) - 1
    assert f"planes.tzi offsets[{n}] is {index['offsets'][-1]}" in str(err)


@pytest.mark.parametrize(("edit", "message"), [
    (lambda d: d.update(offsets=d["offsets"][:-1]), r"offsets must list \d+ byte offsets"),
    (lambda d: d["offsets"].__setitem__(3, 1.5), r"offsets\[3\] = 1.5: offsets must be whole"),
    (lambda d: d["offsets"].__setitem__(2, 0), r"offsets\[2\] = 0: .*non-decreasing"),
    (lambda d: d.update(width=W + 1), rf"width/height are {W + 1}x{H}, info.json says {W}x{H}"),
    (lambda d: d.update(tilesize=2), r"tilesize must be an integer in 16..8192, got 2"),
    (lambda d: d.update(nlevels=2), r"offsets must list \d+ byte offsets"),
    (lambda d: d.update(stride=5), r"stride must be an integer in 6..4096, got 5"),
])
def test_bad_itarzoom_index(tmp_path: Path, edit: Any, message: str) -> None:
    folder = write_layout(tmp_path, "itarzoom", planes_rgb())
    index = json.loads((folder / "planes.tzi").read_text())
    edit(index)
    (folder / "planes.tzi").write_text(json.dumps(index))
    err = str(one_line_error(folder))
    assert err.startswith(f"{folder / 'planes.tzi'}: ")
    assert re.search(message, err), err


def test_missing_and_wrong_size_tiles(tmp_path: Path) -> None:
    folder = write_layout(tmp_path, "deepzoom", planes_rgb())
    tile = folder / "plane_1_files" / "2" / "1_0.png"
    tile.unlink()
    err = one_line_error(folder)
    assert str(err) == f"{tile}: tile 1_0 of level 2 is missing"
    pyvips.Image.black(20, 17, bands=3).cast("uchar").pngsave(str(tile))
    err = one_line_error(folder)
    assert str(err) == f"{tile}: tile 1_0 is 20x17; the layout needs 18x17"
    pyvips.Image.black(18, 17).cast("uchar").pngsave(str(tile))
    assert "tile 1_0 has 1 band(s) of uchar; expected 8-bit RGB" in str(one_line_error(folder))
    tile.write_bytes(b"\x89PNG\r\n\x1a\n garbage")
    assert str(one_line_error(folder)).startswith(f"{tile}: cannot decode tile 1_0 (")


def test_wrong_size_tile_in_a_blob(tmp_path: Path) -> None:
    folder = write_layout(tmp_path, "tarzoom", planes_rgb(), overlap=0)
    index = json.loads((folder / "plane_0.tzi").read_text())
    index["overlap"] = 1  # the tiles no longer have the sizes the grid needs
    (folder / "plane_0.tzi").write_text(json.dumps(index))
    err = one_line_error(folder)
    assert str(err).startswith(f"{folder / 'plane_0.tzb'}: tile 0_0 (entry ")
    assert "is 16x16; the layout needs 17x17" in str(err)


@pytest.mark.parametrize(("text", "message"), [
    ("<Image", "not valid Deep Zoom XML"),
    ('<Image Format="jpg" TileSize="16" Overlap="1"/>', "Image has no <Size> element"),
    ('<Foo/>', "root element is <Foo>; expected <Image>"),
    (f'<Image Format="gif" TileSize="16" Overlap="1"><Size Width="{W}" Height="{H}"/></Image>',
     "Image Format 'gif': expected jpg, jpeg or png"),
    (f'<Image Format="png" TileSize="16" Overlap="1"><Size Width="{W}" Height="9"/></Image>',
     f"Size is {W}x9, info.json says {W}x{H}"),
    (f'<Image Format="png" TileSize="16" Overlap="16"><Size Width="{W}" Height="{H}"/></Image>',
     "Image Overlap must be an integer in 0..15, got '16'"),
    ('<!DOCTYPE x [<!ENTITY a "b">]><Image/>', "declares a DOCTYPE or entities; refused"),
])
def test_bad_dzi(tmp_path: Path, text: str, message: str) -> None:
    folder = write_layout(tmp_path, "deepzoom", planes_rgb())
    (folder / "plane_2.dzi").write_text(text)
    err = str(one_line_error(folder))
    assert err.startswith(f"{folder / 'plane_2.dzi'}: ") and message in err, err


def test_no_full_resolution_level(tmp_path: Path) -> None:
    folder = write_layout(tmp_path, "deepzoom", planes_rgb())
    for level in (folder / "plane_0_files").iterdir():
        for f in level.iterdir():
            f.unlink()
        level.rmdir()
    assert "has no full-resolution level (expected one of 6, 2)" in str(one_line_error(folder))


def test_fifo_index_is_refused(tmp_path: Path) -> None:
    folder = write_layout(tmp_path, "tarzoom", planes_rgb())
    (folder / "plane_4.tzi").unlink()
    os.mkfifo(folder / "plane_4.tzi")
    err = str(one_line_error(folder))
    assert err.startswith(f"{folder / 'plane_4.tzi'}: ") and "regular file" in err, err


@pytest.mark.parametrize("layout", ["deepzoom", "tarzoom", "itarzoom"])
def test_import_of_a_tiled_folder(tmp_path: Path, layout: str,
                                  capsys: pytest.CaptureFixture[str]) -> None:
    """``lanterna import`` tiles the reassembled planes; a bad layout writes nothing."""
    planes = planes_rgb(5)
    folder = write_layout(tmp_path / "coin", layout, planes)
    out = tmp_path / "ds"
    assert main(["import", str(folder), "-o", str(out), "--plane-format", "png"]) == 0
    stored = pyvips.Image.new_from_file(str(out / "iiif/coin_p0/full/max/0/default.png"))
    np.testing.assert_array_equal(stored.numpy()[..., 1], planes[5][..., 0])  # R1: term 5
    blob = folder / ("planes.tzb" if layout == "itarzoom" else "plane_5.tzb")
    if layout == "deepzoom":
        blob = folder / "plane_5_files" / "2" / "2_1.png"
    blob.write_bytes(blob.read_bytes()[:-40])
    assert main(["import", str(folder), "-o", str(tmp_path / "bad")]) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith(f"lanterna: error: {blob}: ") and "\n" not in err, err
    assert not (tmp_path / "bad").exists()


@pytest.mark.realdata
def test_real_relight_planes_tiled_by_libvips(tmp_path: Path) -> None:
    """A real Relight plane (../shared/realdata/relight-coin), tiled the way Relight's GUI tiled
    (libvips ``dzsave``, 256 px, overlap 1; PNG tiles so the check is exact), and in Relight's own
    tarzoom layout, reassembles to the plane's decode."""
    plane = shared_file("realdata/relight-coin/rbf27/plane_0.jpg")
    rgb = np.asarray(pyvips.Image.new_from_file(str(plane)).numpy())
    h, w = rgb.shape[:2]
    pyvips.Image.new_from_array(rgb).copy(interpretation="srgb").dzsave(
        str(tmp_path / "plane_0"), layout="dz", tile_size=256, overlap=1, depth="onetile",
        suffix=".png")
    write_tarzoom(tmp_path, "plane_1", rgb, tile=256, overlap=1)
    for k in (0, 1):
        image = open_tiled_plane(tmp_path, k, 2, w, h)
        assert image is not None
        np.testing.assert_array_equal(image.numpy(), rgb)
