"""Make a multi-layer benchmark/demo dataset: every layer type over the same demo tablet.

    .venv/bin/python bench/make_datasets.py ROOT [--width 4096 --height 3072]

Writes ROOT/bench with layers (in order) ``ptm_lrgb``, ``ptm_rgb``, ``hsh9``, ``hsh16``,
``svbrdf``, ``rbf27`` and ``bilinear18`` (PCA mrgb, shaped like Relight's defaults: 27 planes over
116 acquisition lights, 18 planes on a 9 × 9 grid), ``image`` (RGB JPEG), ``mono`` (single-band
``Y``) and ``plain`` (the colour image as PNG, the benchmark's reference). Coefficients are analytic
fits of a Lambertian tablet (not camera captures): good enough to look plausible and to measure
speed.
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
    add_planes_layer,
    add_ptm_layer,
    add_svbrdf_layer,
)
from lanterna.tiler.dataset.writer import DatasetWriter
from lanterna.tiler.demo.tablet import make_demo_object
from lanterna.tiler.formats.hsh_basis import hsh_weights
from lanterna.tiler.formats.hsh_model import Hsh
from lanterna.tiler.formats.layouts import encode_normals
from lanterna.tiler.formats.pca_model import PcaBasis, plane_channel_names
from lanterna.tiler.formats.planes import PlaneGroup, PlaneLayer
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


def dome_lights(count: int) -> np.ndarray:
    """``count`` unit lights spread over the hemisphere (a golden-angle spiral, z ≥ 0.15)."""
    i = np.arange(count) + 0.5
    z = 0.15 + 0.85 * (1 - i / count)
    phi = i * math.pi * (3 - math.sqrt(5))
    r = np.sqrt(1 - z * z)
    return np.stack([r * np.cos(phi), r * np.sin(phi), z], axis=-1)


def octahedral_samples(res: int) -> np.ndarray:
    """The directions of Relight's bilinear grid samples (``x + y·R``), the inverse of its map."""
    y, x = np.mgrid[0:res, 0:res] / (res - 1) * 2 - 1
    u, v = (x - y) / 2, (x + y) / 2
    d = np.stack([u, v, np.maximum(1 - np.abs(u) - np.abs(v), 0)], -1).reshape(-1, 3)
    out: np.ndarray = d / np.maximum(np.linalg.norm(d, axis=1, keepdims=True), 1e-9)
    return out


def pca_lambert_layer(layer_type: str, nplanes: int, n: np.ndarray, albedo: np.ndarray
                      ) -> PlaneLayer:
    """A PCA mrgb layer of ``albedo_k·(n·l)``: plane ``3·axis + k`` holds ``albedo_k·n_axis`` and
    its basis row ``l_axis`` in channel ``k``; the remaining planes are zero (fetched all the same).
    """
    rbf = layer_type == "rbf"
    samples = dome_lights(116) if rbf else octahedral_samples(9)
    rows = np.zeros((nplanes + 1, len(samples), 3))
    for axis in range(3):
        for k in range(3):
            rows[1 + 3 * axis + k, :, k] = samples[:, axis]
    ranges = tuple([127.0] * nplanes)
    basis = np.concatenate([rows[:1] * 255, 127 + rows[1:] * 127]).round().astype(np.uint8)
    groups = []
    for g, names in enumerate(plane_channel_names(nplanes)):
        q = np.arange(3 * g, 3 * g + 3)
        coef = np.zeros(n.shape[:2] + (3,), np.float32)
        for c, plane in enumerate(q):
            if plane < 9:
                coef[..., c] = albedo[..., plane % 3] * n[..., plane // 3]
        t = np.round((coef / 2 + 0.5) * 255).clip(0, 255).astype(np.uint8)
        groups.append(PlaneGroup(list(names), t, [2.0, 2.0, 2.0], [0.5, 0.5, 0.5]))
    pca = PcaBasis(layer_type, "mrgb", basis.ravel(), ranges,
                   lights=tuple(float(v) for v in samples.ravel()) if rbf else None,
                   sigma=0.125 if rbf else None, resolution=None if rbf else 9)
    return PlaneLayer(layer_type, groups, pca=pca)


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
        for layer_id, layer_type, nplanes in (("rbf27", "rbf", 27), ("bilinear18", "bilinear", 18)):
            add_planes_layer(ds, pca_lambert_layer(layer_type, nplanes, n, albedo),
                             layer_id=layer_id, label=f"{layer_type} {nplanes} (PCA mrgb)")
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
