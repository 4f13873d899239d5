"""Reference renderer: the mode table, parameters, the post step and reading stored levels."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import numpy.typing as npt
import pytest

from lanterna.tiler.dataset.layers import add_svbrdf_layer
from lanterna.tiler.dataset.writer import DatasetWriter
from lanterna.tiler.formats.layouts import encode_normals
from lanterna.tiler.render import (
    MODES,
    applicable_modes,
    level_channels,
    post,
    render,
    resolve_params,
)

F32 = npt.NDArray[np.float32]

# docs/rendering.md, "Modes and where they apply": one row per mode, columns ptm lrgb, ptm rgb,
# hsh, svbrdf with shape, svbrdf without shape / image.
TABLE = {
    "color": "11111", "normals": "11110", "albedo": "11111", "diffuse": "11110",
    "achromatic": "11111", "specular": "11110", "diffuseGain": "11000",
    "unsharpNormals": "11110", "unsharpCoefficients": "11100", "unsharpLuminance": "10000",
    "unsharpImage": "11111",
}
N_PLANE = {"channels": ["NX", "NY", "NZ"]}
KD_PLANE = {"channels": ["KD_R", "KD_G", "KD_B"]}
COLUMNS = [
    {"layerType": "ptm", "colorspace": "lrgb", "planes": []},
    {"layerType": "ptm", "colorspace": "rgb", "planes": []},
    {"layerType": "hsh", "terms": 9, "planes": []},
    {"layerType": "svbrdf", "planes": [N_PLANE, KD_PLANE]},
    {"layerType": "svbrdf", "planes": [KD_PLANE]},
    {"layerType": "image", "planes": [{"channels": ["R", "G", "B"]}]},
]


def test_mode_table_is_the_documented_one() -> None:
    assert tuple(TABLE) == MODES
    for col, layer in enumerate(COLUMNS):
        expected = tuple(m for m in MODES if TABLE[m][min(col, 4)] == "1")
        assert applicable_modes(layer) == expected, layer


def channels_for(layer: dict[str, object], h: int = 6, w: int = 7) -> dict[str, F32]:
    rng = np.random.default_rng(0)
    kind = layer["layerType"]
    names: list[str]
    if kind == "ptm":
        names = ([f"L{k}" for k in range(6)] + list("RGB") if layer["colorspace"] == "lrgb"
                 else [f"{c}{k}" for c in "RGB" for k in range(6)])
    elif kind == "hsh":
        names = [f"{c}{k}" for c in "RGB" for k in range(9)]
    else:
        names = [c for p in layer["planes"] for c in p["channels"]]
    out = {n: rng.uniform(0.2, 0.6, (h, w)).astype(np.float32) for n in names}
    for c in ("NZ",):
        if c in out:
            out[c] += 0.5
    return out


@pytest.mark.parametrize("col", range(len(COLUMNS)))
def test_every_mode_renders_or_is_refused(col: int) -> None:
    layer = COLUMNS[col]
    ch = channels_for(layer)
    ok = applicable_modes(layer)
    for mode in MODES:
        if mode in ok:
            out = render(layer, ch, (0.3, -0.2), mode)
            assert out.shape == (6, 7, 3) and out.dtype == np.float32
            assert np.isfinite(out).all() and out.min() >= 0 and out.max() <= 1
        else:
            with pytest.raises(ValueError, match="does not apply"):
                render(layer, ch, (0.3, -0.2), mode)


def test_parameters_are_checked() -> None:
    assert resolve_params(None)["specExponent"] == 75
    assert resolve_params({"umGain": 3})["umGain"] == 3
    with pytest.raises(ValueError, match="unknown"):
        resolve_params({"gain": 1})
    with pytest.raises(ValueError, match="outside"):
        resolve_params({"gamma": 0.1})
    with pytest.raises(ValueError, match="unit disk"):
        render(COLUMNS[5], channels_for(COLUMNS[5]), (0.9, 0.9))
    with pytest.raises(ValueError, match="layerType"):
        applicable_modes({"layerType": "neural"})


def test_post_step_gamma_then_brightness() -> None:
    c = np.array([[[-0.5, 0.25, 2.0]]], np.float32)
    np.testing.assert_allclose(post(c), [[[0, 0.25, 1]]])
    np.testing.assert_allclose(post(c, gamma=2.0), [[[0, 0.5, 1]]], atol=1e-7)
    np.testing.assert_allclose(post(c, gamma=2.0, brightness=0.3), [[[0.3, 0.8, 1]]], atol=1e-7)
    np.testing.assert_allclose(post(c, brightness=-0.5), [[[0, 0, 0.5]]], atol=1e-7)
    img = COLUMNS[5]
    ch = {"R": np.full((2, 2), 0.25, np.float32), "G": np.zeros((2, 2), np.float32),
          "B": np.ones((2, 2), np.float32)}
    out = render(img, ch, params={"gamma": 2.0, "brightness": 0.1})
    np.testing.assert_allclose(out[0, 0], [0.6, 0.1, 1.0], atol=1e-6)


def test_level_channels_reads_what_was_stored(tmp_path: Path) -> None:
    h, w = 300, 520  # two tile columns, two rows at level 0; one tile at level 1
    rng = np.random.default_rng(1)
    n = rng.normal(size=(h, w, 3))
    n[..., 2] = np.abs(n[..., 2]) + 1
    n /= np.linalg.norm(n, axis=-1, keepdims=True)
    gloss = rng.integers(0, 256, (h, w), dtype=np.uint8)
    with DatasetWriter(tmp_path / "d", name="d", label="d", width=w, height=h) as ds:
        layer = ds.layer_service(add_svbrdf_layer(ds, normals=encode_normals(n), gloss=gloss))
    full = level_channels(tmp_path / "d", layer, 1)
    enc = encode_normals(n).astype(np.float32) / 255
    np.testing.assert_allclose(full["NX"], (enc[..., 0] - 0.5) * 2, atol=1e-6)
    np.testing.assert_allclose(full["GLOSS"], gloss / 255, atol=1e-6)
    crop = level_channels(tmp_path / "d", layer, 1, region=(250, 200, 20, 30))
    np.testing.assert_array_equal(crop["NY"], full["NY"][200:230, 250:270])
    half = level_channels(tmp_path / "d", layer, 2)
    assert half["GLOSS"].shape == (150, 260)
    assert abs(float(half["GLOSS"].mean()) - float(full["GLOSS"].mean())) < 0.01
    with pytest.raises(ValueError):
        level_channels(tmp_path / "d", layer, 2, region=(250, 140, 20, 30))
