"""Tests for the map and band loaders (tiler/inputs/maps.py)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import numpy.typing as npt
import pytest
import pyvips

from lanterna.errors import LanternaInputError
from lanterna.tiler.inputs.maps import (
    load_band,
    load_color_map,
    load_depth_map,
    load_normal_map,
    load_scalar_map,
)

W, H = 40, 24


def save(path: Path, array: npt.NDArray[np.generic]) -> Path:
    """Save ``(H, W[, bands])`` uint8/uint16/float32 as PNG or TIFF (by suffix)."""
    image = pyvips.Image.new_from_array(np.ascontiguousarray(array))
    bands = image.bands
    if array.dtype == np.uint16:
        image = image.copy(interpretation="rgb16" if bands >= 3 else "grey16")
    elif array.dtype == np.uint8:
        image = image.copy(interpretation="srgb" if bands >= 3 else "b-w")
    image.write_to_file(str(path))
    return path


def bump_normals(seed: int = 0) -> npt.NDArray[np.float64]:
    """Unit normals of a smooth random height field (x right, y up, z to the viewer)."""
    rng = np.random.default_rng(seed)
    y, x = np.mgrid[0:H, 0:W].astype(np.float64)
    height = sum(rng.uniform(2, 6) * np.sin(rng.uniform(0.1, 0.4) * x + rng.uniform(0.1, 0.4) * y
                                            + rng.uniform(0, 6)) for _ in range(3))
    dzdx = np.gradient(height, axis=1)
    dzdy = -np.gradient(height, axis=0)  # rows go down, y goes up
    n = np.stack([-dzdx, -dzdy, np.ones_like(height)], axis=-1)
    out: npt.NDArray[np.float64] = n / np.linalg.norm(n, axis=-1, keepdims=True)
    return out


def encode(n: npt.NDArray[np.float64], bits: int = 8) -> npt.NDArray[np.generic]:
    top = 255 if bits == 8 else 65535
    dtype = np.uint8 if bits == 8 else np.uint16
    return np.rint((n + 1.0) / 2.0 * top).astype(dtype)


def diff(a: npt.NDArray[np.generic], b: npt.NDArray[np.generic]) -> npt.NDArray[np.int32]:
    return np.abs(a.astype(np.int32) - b.astype(np.int32))


# --- normal maps --------------------------------------------------------------------------------


def test_opengl_map_round_trips_and_directx_flips_green(tmp_path: Path) -> None:
    n = bump_normals()
    assert np.abs(n[..., 1]).max() > 0.3  # the green channel really carries signal
    gl = encode(n)
    dx = gl.copy()
    dx[..., 1] = 255 - dx[..., 1]
    gl_path, dx_path = save(tmp_path / "gl.png", gl), save(tmp_path / "dx.png", dx)
    out = load_normal_map(gl_path)
    assert out.dtype == np.uint8 and out.shape == (H, W, 3)
    np.testing.assert_array_equal(out, gl)  # unit to 8-bit precision: the bytes are kept
    np.testing.assert_array_equal(load_normal_map(dx_path, convention="directx"), out)
    # Read with the wrong convention, the green channel comes out mirrored.
    wrong = load_normal_map(dx_path, convention="opengl")
    assert diff(wrong[..., 1], 255 - gl[..., 1]).max() <= 1
    assert diff(wrong[..., 1], gl[..., 1]).max() > 60


def test_sixteen_bit_input_keeps_its_precision(tmp_path: Path) -> None:
    n = bump_normals(seed=3)
    path = save(tmp_path / "n16.png", encode(n, bits=16))
    assert pyvips.Image.new_from_file(str(path)).format == "ushort"
    out = load_normal_map(path)
    best = encode(n)  # the 8-bit encoding of the true normals
    assert diff(out, best).max() <= 1
    assert (out == best).mean() > 0.995
    # Dropping the low byte (v >> 8) would be off by one in a large share of samples.
    assert ((encode(n, bits=16).astype(np.uint16) // 256).astype(np.uint8) != best).mean() > 0.2


@pytest.mark.parametrize("bits", [8, 16])
def test_vectors_are_renormalised(tmp_path: Path, bits: int) -> None:
    n = bump_normals(seed=5)
    factor = np.where(np.arange(W) % 2 == 0, 0.7, 0.9)[None, :, None]
    path = save(tmp_path / "scaled.png", encode(n * factor, bits=bits))
    out = load_normal_map(path)
    assert diff(out, encode(n)).max() <= (1 if bits == 16 else 2)
    decoded = out.astype(np.float64) / 255 * 2 - 1
    np.testing.assert_allclose(np.linalg.norm(decoded, axis=-1), 1.0, atol=0.01)


def test_black_background_is_kept_and_grey_pixels_become_flat(tmp_path: Path) -> None:
    gl = encode(bump_normals(seed=6))
    gl[:5] = 0  # masked background rows (more than half of the image would still be fine)
    gl[10, 10] = 128  # one (nearly) zero-length vector
    out = load_normal_map(save(tmp_path / "masked.png", gl))
    assert not out[:5].any()
    assert out[10, 10].tolist() == [128, 128, 255]


def _normal_cases() -> dict[str, tuple[npt.NDArray[np.generic], str]]:
    rng = np.random.default_rng(1)
    photo = rng.integers(0, 256, (H, W, 3), dtype=np.uint8)
    photo[..., 2] //= 3  # warm photograph: little blue
    inverted = encode(bump_normals())
    inverted[..., 2] = 255 - inverted[..., 2]
    return {
        "grey": (np.full((H, W, 3), 128, np.uint8), "near-zero vectors (a grey image?)"),
        "white": (np.full((H, W, 3), 255, np.uint8), "far from unit length"),
        "photo": (photo, "not a normal map"),
        "inverted z": (inverted, "blue (z) channel is below 0.5 on average"),
        "black": (np.zeros((H, W, 3), np.uint8), "entirely black"),
        "single band": (np.full((H, W), 200, np.uint8), "has 1 colour band(s); expected 3"),
    }


@pytest.mark.parametrize("case", sorted(_normal_cases()))
def test_implausible_normal_maps_are_rejected(tmp_path: Path, case: str) -> None:
    array, expected = _normal_cases()[case]
    path = save(tmp_path / "bad.png", array)
    with pytest.raises(LanternaInputError) as err:
        load_normal_map(path)
    message = str(err.value)
    assert expected in message and message.startswith(f"{path}: ") and "\n" not in message


def test_normal_map_with_alpha_and_unknown_convention(tmp_path: Path) -> None:
    gl = encode(bump_normals())
    rgba = np.concatenate([gl, np.full((H, W, 1), 255, np.uint8)], axis=-1)
    out = load_normal_map(save(tmp_path / "rgba.png", rgba))
    assert diff(out, gl).max() <= 1
    with pytest.raises(LanternaInputError, match="unknown normal-map convention 'vulkan'"):
        load_normal_map(tmp_path / "rgba.png", convention="vulkan")


# --- colour, scalar, band, depth ----------------------------------------------------------------


def test_color_map_8bit_exact_16bit_rounded_grey_expanded(tmp_path: Path) -> None:
    rng = np.random.default_rng(2)
    rgb = rng.integers(0, 256, (H, W, 3), dtype=np.uint8)
    np.testing.assert_array_equal(load_color_map(save(tmp_path / "c.png", rgb)), rgb)
    wide = np.zeros((H, W, 3), np.uint16)
    wide[0, :4, 0] = [386, 32767, 32768, 65535]  # 1.50→2, 127.50→127, 127.50→128, 255
    out = load_color_map(save(tmp_path / "c16.png", wide))
    assert out[0, :4, 0].tolist() == [2, 127, 128, 255]
    grey = rng.integers(0, 256, (H, W), dtype=np.uint8)
    out = load_color_map(save(tmp_path / "g.png", grey))
    assert out.shape == (H, W, 3) and all((out[..., c] == grey).all() for c in range(3))


def test_color_map_rejects_odd_band_counts_and_bad_files(tmp_path: Path) -> None:
    five = pyvips.Image.black(W, H, bands=5).cast("uchar")
    five.tiffsave(str(tmp_path / "five.tif"))
    with pytest.raises(LanternaInputError, match="has 5 colour bands; expected grey or RGB"):
        load_color_map(tmp_path / "five.tif")
    (tmp_path / "text.png").write_text("not an image")
    with pytest.raises(LanternaInputError, match=r"text.png: cannot read image \("):
        load_color_map(tmp_path / "text.png")
    with pytest.raises(LanternaInputError, match="file not found"):
        load_color_map(tmp_path / "missing.png")
    save(tmp_path / "f.tif", np.zeros((H, W, 3), np.float32))
    with pytest.raises(LanternaInputError, match="unsupported sample format float"):
        load_color_map(tmp_path / "f.tif")


def test_scalar_map_and_band(tmp_path: Path) -> None:
    rng = np.random.default_rng(4)
    grey = rng.integers(0, 256, (H, W), dtype=np.uint8)
    np.testing.assert_array_equal(load_scalar_map(save(tmp_path / "g.png", grey)), grey)
    wide = (grey.astype(np.uint32) * 257 + np.where(grey < 255, 100, 0)).astype(np.uint16)
    np.testing.assert_array_equal(load_band(save(tmp_path / "b16.png", wide)), grey)
    rgb_grey = np.repeat(grey[..., None], 3, axis=2)
    np.testing.assert_array_equal(load_band(save(tmp_path / "rgbgrey.png", rgb_grey)), grey)
    colour = rng.integers(0, 256, (H, W, 3), dtype=np.uint8)
    with pytest.raises(LanternaInputError, match="band has 3 different colour bands"):
        load_band(save(tmp_path / "colour.png", colour))
    with pytest.raises(LanternaInputError, match="map has 3 different colour bands"):
        load_scalar_map(tmp_path / "colour.png")


def test_depth_map_is_stretched_with_its_range(tmp_path: Path) -> None:
    y, x = np.mgrid[0:H, 0:W].astype(np.float32)
    depth = (2.5 + 0.1 * x - 0.05 * y).astype(np.float32)
    depth[3, 3] = np.nan
    data, (low, high) = load_depth_map(save(tmp_path / "d.tif", depth))
    finite = np.isfinite(depth)
    assert low == pytest.approx(float(depth[finite].min()))
    assert high == pytest.approx(float(depth[finite].max()))
    expected = np.rint((np.nan_to_num(depth, nan=low) - low) / (high - low) * 255)
    expected[3, 3] = 0
    np.testing.assert_array_equal(data, expected.astype(np.uint8))
    assert data.min() == 0 and data.max() == 255
    flat, rng = load_depth_map(save(tmp_path / "flat.png", np.full((H, W), 9, np.uint8)))
    assert rng == (9.0, 9.0) and not flat.any()
    with pytest.raises(LanternaInputError, match="unsupported sample format float"):
        load_scalar_map(tmp_path / "d.tif")
