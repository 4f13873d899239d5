"""Shared data and helpers of the real-Chromium overlay, lens and gesture tests.

One dataset: a PTM layer ``base`` (with an overlay at levels 0 and 1, none at level 2) and an RGB
image layer ``second``. The viewer fits regions so that at zoom 1/f one device pixel is one pixel
of level log2(f); frames are compared with :func:`lanterna.tiler.render.render` over the stored
tiles of that level, composited with the stored overlay level image where one is expected.
"""

from __future__ import annotations

import json
import re
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
import numpy.typing as npt
import pytest
import pyvips

from lanterna.tiler.dataset.layers import add_image_layer, add_ptm_layer
from lanterna.tiler.dataset.writer import DatasetWriter
from lanterna.tiler.formats.ptm_model import Ptm
from lanterna.tiler.iiif.pyramid import vips_from_array
from lanterna.tiler.overlays.build import build_overlays
from lanterna.tiler.render import level_channels, level_image, render

from . import browser
from .conftest import LiveServer

W, H = 1024, 768
TILE = 128
VIEW = (256, 192)
LIGHT = (0.3, 0.4)
TOLERANCE = 2  # out of 255
RED, GREEN = (230, 20, 20), (20, 210, 40)
# Overlay patches (full-resolution rectangles): level 0 red, level 1 green; nothing at level 2.
PATCHES = {0: (RED, (160, 140, 120, 90)), 1: (GREEN, (220, 160, 240, 200))}
TEXTS = {"0": {"short": "Glyph detail", "long": "<p>A <b>glyph</b>.<script>bad()</script></p>"},
         "1": {"short": "Whole panel", "long": "<p>The panel.</p>"}}
ORIGIN = {1: (120, 100), 2: (60, 50), 4: (0, 0)}  # zoom factor → region origin in level px
TILE_URL = re.compile(r"/iiif/(?P<image>[A-Za-z0-9_-]+)/(?P<region>full|\d+,\d+,\d+,\d+)/")


def smooth(rng: np.random.Generator, lo: float, hi: float, shape: tuple[int, ...] = (),
           cell: int = 32) -> npt.NDArray[np.float64]:
    """A smooth random field (bilinear over a coarse grid)."""
    coarse = rng.uniform(lo, hi, (H // cell + 2, W // cell + 2) + shape)
    y, x = np.arange(H) / cell, np.arange(W) / cell
    y0, x0 = y.astype(int), x.astype(int)
    fy = (y - y0).reshape((H, 1) + (1,) * len(shape))
    fx = (x - x0).reshape((1, W) + (1,) * len(shape))
    top = coarse[y0][:, x0] * (1 - fx) + coarse[y0][:, x0 + 1] * fx
    bottom = coarse[y0 + 1][:, x0] * (1 - fx) + coarse[y0 + 1][:, x0 + 1] * fx
    out: npt.NDArray[np.float64] = top * (1 - fy) + bottom * fy
    return out


def base_ptm(rng: np.random.Generator) -> Ptm:
    """An LRGB PTM with an interior maximum, in range for every light."""
    a0, a1 = smooth(rng, -0.45, -0.2), smooth(rng, -0.45, -0.2)
    u0, v0 = smooth(rng, -0.4, 0.4), smooth(rng, -0.4, 0.4)
    a = np.stack([a0, a1, np.zeros_like(a0), -2 * a0 * u0, -2 * a1 * v0,
                  smooth(rng, 0.5, 0.8) + a0 * u0**2 + a1 * v0**2], -1)
    scale = np.array([2, 2, 2, 2, 2, 1], np.float32)
    bias = np.array([128, 128, 128, 128, 128, 0], np.int32)
    coef = np.clip(np.round(a * 255 / scale + bias), 0, 255).astype(np.uint8)
    rgb = np.round(smooth(rng, 0.3, 1.0, (3,)) * 255).astype(np.uint8)
    return Ptm("lrgb", coef, scale, bias, rgb)


def write_patches(folder: Path) -> None:
    """One opaque rectangle per level, with a soft 6-px alpha ramp on its left side."""
    folder.mkdir()
    for level, (colour, (x, y, w, h)) in PATCHES.items():
        px = np.zeros((h, w, 4), np.uint8)
        px[..., :3] = colour
        px[..., 3] = 255
        px[:, :6, 3] = np.linspace(40, 220, 6).astype(np.uint8)
        pyvips.Image.new_from_array(px).copy(interpretation="srgb").write_to_file(
            str(folder / f"{level}_{x}_{y}_{w}_{h}_0_patch{level}.png"))


@dataclass
class Dataset:
    root: Path
    blocks: dict[str, dict[str, Any]]

    @property
    def dir(self) -> Path:
        return self.root / "lens"


def make_lens_dataset(tmp_path_factory: pytest.TempPathFactory) -> Dataset:
    """Build the dataset (the ``lens_dataset`` fixture of conftest.py)."""
    tmp = tmp_path_factory.mktemp("lens")
    rng = np.random.default_rng(11)
    with DatasetWriter(tmp / "lens", name="lens", label="Lens and overlays", width=W, height=H,
                       tile_size=TILE) as ds:
        add_ptm_layer(ds, base_ptm(rng), layer_id="base", label="Base")
        second = np.round(smooth(rng, 0.1, 0.9, (3,)) * 255).astype(np.uint8)
        add_image_layer(ds, vips_from_array(second), layer_id="second", label="Second", fmt="png")
        blocks = {layer["id"]: ds.layer_service(layer) for layer in ds.layers}
    write_patches(tmp / "patches")
    report = build_overlays(tmp / "lens", "base", patches_dir=tmp / "patches", texts=TEXTS)
    assert report.levels == [0, 1] and not report.errors
    return Dataset(tmp, blocks)


@dataclass
class LensShot(browser.Shot):
    """A browser shot with the lens, overlay and gesture fields of render.mjs."""

    lens: dict[str, Any] | None = None
    overlays: bool | None = None
    gestures: list[dict[str, Any]] = field(default_factory=list)

    def spec(self) -> dict[str, object]:
        out = super().spec()
        if self.lens is not None:
            out["lens"] = self.lens
        if self.overlays is not None:
            out["overlays"] = self.overlays
        if self.gestures:
            out["gestures"] = self.gestures
        return out

    def meta(self) -> dict[str, Any]:
        """What render.mjs wrote beside the frame (state after the shot, requests)."""
        result: dict[str, Any] = json.loads(Path(str(self.out) + ".json").read_text())
        return result


def region(factor: int) -> tuple[int, int, int, int]:
    x, y = ORIGIN[factor]
    return (x * factor, y * factor, VIEW[0] * factor, VIEW[1] * factor)


def shots_and_frames(dataset: Dataset, shots: list[LensShot],
                     viewport: tuple[int, int] = VIEW) -> list[npt.NDArray[np.uint8]]:
    server = LiveServer(dataset.root)
    try:
        url = f"{server.url}/viewer/?manifest={server.url}/datasets/lens/manifest.json&layer=base"
        return browser.render(url, list(shots), viewport=viewport)
    finally:
        server.close()


def reference(dataset: Dataset, layer: str, factor: int, mode: str = "color",
              light: tuple[float, float] = LIGHT) -> npt.NDArray[np.float32]:
    """The layer rendered at zoom 1/factor over the shot's view, display values 0–1."""
    x, y = ORIGIN[factor]
    ch = level_channels(dataset.dir, dataset.blocks[layer], factor, (x, y) + VIEW)
    out: npt.NDArray[np.float32] = render(dataset.blocks[layer], ch, light, mode)
    return out


def overlay_at(dataset: Dataset, level: int, factor: int) -> npt.NDArray[np.float32]:
    """The stored level image over the shot's view (RGBA 0–1; transparent outside the image)."""
    img = level_image(dataset.dir / "iiif" / f"base_ov{level}", 1).astype(np.float32) / 255
    x, y = ORIGIN[factor]
    out = np.zeros((VIEW[1], VIEW[0], 4), np.float32)
    crop = img[y: y + VIEW[1], x: x + VIEW[0]]
    out[: crop.shape[0], : crop.shape[1]] = crop
    return out


def over(ref: npt.NDArray[np.float32], ov: npt.NDArray[np.float32]) -> npt.NDArray[np.int16]:
    """Premultiplied source-over of the overlay on the reference, in bytes."""
    a = ov[..., 3:4]
    return np.round((ov[..., :3] * a + ref * (1 - a)) * 255).astype(np.int16)


def assert_close(got: npt.NDArray[np.uint8], expected: npt.NDArray[np.int16],
                 mask: npt.NDArray[np.bool_], what: str) -> None:
    diff = np.abs(got[..., :3].astype(np.int16) - expected).max(axis=-1)
    diff = np.where(mask, diff, 0)
    bad = np.argwhere(diff > TOLERANCE)
    assert mask.sum() > 100, f"{what}: too few pixels checked ({mask.sum()})"
    assert bad.size == 0, (
        f"{what}: {len(bad)} of {mask.sum()} pixels off by up to {diff.max()}/255, first at "
        f"(row, col) {tuple(bad[0])}: got {got[tuple(bad[0])][:3]}, expected "
        f"{expected[tuple(bad[0])]}")


def disk(cx: float, cy: float, r: float) -> npt.NDArray[np.bool_]:
    """Pixels whose centres lie within r of (cx, cy) (CSS px = device px here)."""
    y, x = np.mgrid[0: VIEW[1], 0: VIEW[0]] + 0.5
    inside: npt.NDArray[np.bool_] = (x - cx) ** 2 + (y - cy) ** 2 <= r * r
    return inside


# -- overlays and hypertext ----------------------------------------------------------------------
