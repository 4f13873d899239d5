"""Make a multi-layer benchmark/demo dataset: every layer type over the same demo tablet.

    .venv/bin/python bench/make_datasets.py ROOT [--width 4096 --height 3072]

Writes ROOT/bench with layers (in order) ``ptm_lrgb``, ``ptm_rgb``, ``hsh9``, ``hsh16``,
``svbrdf``, ``image`` (RGB JPEG), ``mono`` (single-band ``Y``) and ``plain`` (the colour image as
PNG, the benchmark's reference). Coefficients are analytic fits of a Lambertian tablet (not camera
captures): good enough to look plausible and to measure speed.
"""

from __future__ import annotations

import argparse
import math
from pathlib import Path

import numpy as np
import pyvips

from lanterna.tiler.dataset.layers import (
    add_hsh_layer,
    add_image_layer,
    add_ptm_layer,
    add_svbrdf_layer,
)
from lanterna.tiler.dataset.writer import DatasetWriter
from lanterna.tiler.demo.tablet import make_demo_object
from lanterna.tiler.formats.hsh_basis import hsh_weights
from lanterna.tiler.formats.hsh_model import Hsh
from lanterna.tiler.formats.layouts import encode_normals
from lanterna.tiler.formats.ptm_model import Ptm


def lambert_ptm_coefficients(n: np.ndarray) -> np.ndarray:
    """PTM coefficients approximating n·l (lz ≈ 1 − (lu² + lv²)/2), shape (H, W, 6)."""
    nu, nv, nz = n[..., 0], n[..., 1], n[..., 2]
    z = np.zeros_like(nu)
    return np.stack([-nz / 2, -nz / 2, z, nu, nv, nz], axis=-1)


def quantise_ptm(coef: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Coefficients in 0–1 units → PTM bytes with a = (byte − bias)·scale in 0–255 units."""
    scale = np.array([2, 2, 2, 2, 2, 1], np.float32)
    bias = np.array([128, 128, 128, 128, 128, 0], np.int32)
    b = np.round(coef * 255.0 / scale + bias)
    return np.clip(b, 0, 255).astype(np.uint8), scale, bias


def hsh_coefficients(n: np.ndarray, albedo: np.ndarray, terms: int) -> np.ndarray:
    """HSH coefficients of albedo·max(0, n·l), least squares over a hemisphere of lights.

    Float32, shape (H, W, 3, terms) (colour, term), in 0–1 display units.
    """
    lights = []
    for ring, count in ((15, 8), (35, 12), (55, 16), (75, 20)):
        for i in range(count):
            t, p = math.radians(ring), 2 * math.pi * i / count
            lights.append((math.sin(t) * math.cos(p), math.sin(t) * math.sin(p), math.cos(t)))
    lmat = np.array(lights, np.float64)
    hmat = np.stack([hsh_weights(lu, lv, terms) for lu, lv, _ in lights]).astype(np.float64)
    h, w = n.shape[:2]
    coef = np.empty((h, w, 3, terms), np.float32)
    pinv = np.linalg.pinv(hmat)  # (terms, L)
    for y0 in range(0, h, 256):
        nn = n[y0 : y0 + 256].reshape(-1, 3).astype(np.float64)
        shade = np.maximum(nn @ lmat.T, 0.0)  # (P, L)
        k = shade @ pinv.T  # (P, terms)
        a = albedo[y0 : y0 + 256].reshape(-1, 3, 1) * k[:, None, :]
        coef[y0 : y0 + 256] = a.reshape(-1, w, 3, terms)
    return coef


def hsh_field(n: np.ndarray, albedo: np.ndarray, terms: int) -> Hsh:
    """:func:`hsh_coefficients` quantised to bytes, one scale and bias per term."""
    coef = hsh_coefficients(n, albedo, terms)
    lo = coef.min(axis=(0, 1, 2))
    hi = coef.max(axis=(0, 1, 2))
    span = np.where(hi > lo, hi - lo, 1.0)
    q = np.round((coef - lo) / span * 255.0).clip(0, 255).astype(np.uint8)
    return Hsh(q, span.astype(np.float32), lo.astype(np.float32))


def build(root: Path, width: int, height: int) -> None:
    obj = make_demo_object(width, height)
    n, albedo = obj.normals, obj.albedo
    colour = np.round(np.clip(albedo, 0, 1) * 255).astype(np.uint8)
    lum = lambert_ptm_coefficients(n)
    with DatasetWriter(
        root / "bench",
        name="bench",
        label="Demo tablet, every layer type",
        width=width,
        height=height,
        force=True,
    ) as ds:
        q, scale, bias = quantise_ptm(lum)
        add_ptm_layer(
            ds, Ptm("lrgb", q, scale, bias, colour), layer_id="ptm_lrgb", label="PTM LRGB"
        )
        q, scale, bias = quantise_ptm(albedo[..., :, None] * lum[..., None, :])
        add_ptm_layer(ds, Ptm("rgb", q, scale, bias), layer_id="ptm_rgb", label="PTM RGB")
        for terms in (9, 16):
            add_hsh_layer(
                ds, hsh_field(n, albedo, terms), layer_id=f"hsh{terms}", label=f"HSH {terms}"
            )
        lin = np.where(albedo <= 0.04045, albedo / 12.92, ((albedo + 0.055) / 1.055) ** 2.4)
        ks = (obj.specular[..., None] * obj.specular_color[None, None, :]).clip(0, 1)
        add_svbrdf_layer(
            ds,
            normals=encode_normals(n),
            kd=np.round(lin * 255).astype(np.uint8),
            ks=np.round(ks * 255).astype(np.uint8),
            gloss=np.round((1 - obj.specular) * 255).astype(np.uint8),
            layer_id="svbrdf",
            label="Shape and material",
        )
        add_image_layer(
            ds, pyvips.Image.new_from_array(colour), layer_id="image", label="Image (JPEG)"
        )
        grey = np.round(colour.astype(np.float32) @ np.array([0.2126, 0.7152, 0.0722])).astype(
            np.uint8
        )
        add_image_layer(
            ds, pyvips.Image.new_from_array(grey), layer_id="mono", label="Image (Y)", fmt="png"
        )
        add_image_layer(
            ds,
            pyvips.Image.new_from_array(colour),
            layer_id="plain",
            label="Plain (PNG)",
            fmt="png",
        )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("root", type=Path)
    parser.add_argument("--width", type=int, default=4096)
    parser.add_argument("--height", type=int, default=3072)
    args = parser.parse_args()
    build(args.root, args.width, args.height)


if __name__ == "__main__":
    main()
