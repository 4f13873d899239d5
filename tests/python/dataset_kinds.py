"""One small dataset of every kind the package writes, in one data root (schema and export tests).

Kinds: PTM (LRGB and RGB), HSH, shape + material (svbrdf), plain images (RGB JPEG and a grey
band), a multi-layer dataset mixing them, and an image dataset with an annotation overlay
(supplementing AnnotationPage) built from patches with ``lanterna annotate build``.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pyvips

from lanterna.cli import main
from lanterna.tiler.dataset.layers import (
    add_hsh_layer,
    add_image_layer,
    add_ptm_layer,
    add_svbrdf_layer,
)
from lanterna.tiler.dataset.writer import DatasetWriter
from lanterna.tiler.formats.hsh_model import Hsh
from lanterna.tiler.formats.layouts import encode_normals

from .conftest import random_ptm

W, H = 96, 64
TILE = 64  # several tiles and levels even at this size
BASE = "https://old.example.org/published"
KINDS = ("ptm_lrgb", "ptm_rgb", "hsh", "svbrdf", "images", "multi", "overlay")


def _hsh(seed: int) -> Hsh:
    rng = np.random.default_rng(seed)
    coef = rng.integers(0, 256, (H, W, 3, 9), dtype=np.uint8)
    scale = rng.uniform(0.3, 2.0, 9).astype(np.float32)
    scale[4] = 0.0  # a constant term is stored differently (docs/dataset-format.md)
    return Hsh(coef, scale, rng.uniform(-1.0, 0.2, 9).astype(np.float32))


def _maps(seed: int) -> dict[str, np.ndarray]:
    rng = np.random.default_rng(seed)
    n = rng.normal(0, 0.3, (H, W, 3))
    n[..., 2] = 1.0
    n /= np.linalg.norm(n, axis=-1, keepdims=True)
    return {"normals": encode_normals(n),
            "kd": rng.integers(0, 256, (H, W, 3), dtype=np.uint8),
            "ks": rng.integers(0, 256, (H, W, 3), dtype=np.uint8),
            "gloss": rng.integers(0, 256, (H, W), dtype=np.uint8),
            "depth": rng.integers(0, 256, (H, W), dtype=np.uint8)}


def _rgb(seed: int) -> pyvips.Image:
    px = np.random.default_rng(seed).integers(0, 256, (H, W, 3), dtype=np.uint8)
    return pyvips.Image.new_from_array(px).copy(interpretation="srgb")


def _grey(seed: int) -> pyvips.Image:
    px = np.random.default_rng(seed).integers(0, 256, (H, W), dtype=np.uint8)
    return pyvips.Image.new_from_array(px).copy(interpretation="b-w")


def _writer(root: Path, name: str) -> DatasetWriter:
    return DatasetWriter(root / name, name=name, label=f"The {name} object", width=W, height=H,
                         base_url=BASE, tile_size=TILE, summary=f"A synthetic {name} dataset")


def _overlay_patches(folder: Path) -> Path:
    """Two patches (level 0 and 1) named L_X_Y_W_H_O_INFO.png, and their texts."""
    folder.mkdir()
    for level, w, h, colour, name in ((0, 30, 20, (255, 0, 0), "0_10_8_30_20_0_box.png"),
                                      (1, 40, 30, (0, 0, 255), "1_40_20_40_30_0_wide.png")):
        px = np.zeros((h >> level, w >> level, 4), np.uint8)
        px[..., :3] = colour
        px[..., 3] = 200
        pyvips.Image.new_from_array(px).pngsave(str(folder / name))
    texts = folder.parent / "texts.json"
    texts.write_text(json.dumps({"0": {"short": "Box", "long": "<p>A <b>box</b></p>"},
                                 "1": {"short": "Wide"}}))
    return texts


def build_kinds(root: Path) -> dict[str, Path]:
    """Write every kind of dataset under ``root``; return ``{kind: dataset folder}``."""
    root.mkdir(parents=True, exist_ok=True)
    with _writer(root, "ptm_lrgb") as ds:
        add_ptm_layer(ds, random_ptm(W, H, "lrgb", seed=1), label="LRGB PTM")
    with _writer(root, "ptm_rgb") as ds:
        add_ptm_layer(ds, random_ptm(W, H, "rgb", seed=2), label="RGB PTM")
    with _writer(root, "hsh") as ds:
        add_hsh_layer(ds, _hsh(3))
    with _writer(root, "svbrdf") as ds:
        add_svbrdf_layer(ds, **_maps(4), depth_range=(-1.5, 2.0))
    with _writer(root, "images") as ds:
        add_image_layer(ds, _rgb(5), layer_id="vis", label="Visible")
        add_image_layer(ds, _grey(6), layer_id="ir", label="Infrared band", fmt="png")
    with _writer(root, "multi") as ds:
        add_ptm_layer(ds, random_ptm(W, H, "lrgb", seed=7))
        add_hsh_layer(ds, _hsh(8))
        maps = _maps(9)
        add_svbrdf_layer(ds, normals=maps["normals"], share={"normals": "n"})
        add_svbrdf_layer(ds, normals=maps["normals"], kd=maps["kd"], share={"normals": "n"},
                         layer_id="material", label="Material")
        add_image_layer(ds, _rgb(10), layer_id="uv", label="UV", fmt="png")
    with _writer(root, "overlay") as ds:
        add_image_layer(ds, _rgb(11), layer_id="vis", label="Visible", fmt="png")
        add_image_layer(ds, _rgb(12), layer_id="raking", label="Raking")
    patches = root.parent / "overlay_patches"
    texts = _overlay_patches(patches)
    assert main(["annotate", "build", str(root / "overlay"), "--layer", "vis",
                 "--patches", str(patches), "--texts", str(texts)]) == 0
    return {kind: root / kind for kind in KINDS}
