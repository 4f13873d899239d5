"""Add layers of every type to a dataset: PTM, HSH, shape + material (SVBRDF) and plain images.

Each ``add_*_layer`` tiles the layer's plane groups (three channels per IIIF image, the layer's own
bytes where it has them), writes a preview image for the manifest body and registers the layer
(schema: docs/dataset-format.md, maths: docs/rendering.md).
"""

from __future__ import annotations

from typing import Any

import numpy as np
import numpy.typing as npt
import pyvips

from .dataset import DatasetWriter
from .hsh_basis import hsh_weights
from .hsh_model import Hsh
from .planes import PlaneLayer
from .ptm_model import PTM_BASIS, Ptm, ptm_weights

#: Default BRDF of a shape layer without material (docs/rendering.md, svbrdf).
DEFAULT_KD, DEFAULT_KS, DEFAULT_ALPHA = 0.7, 0.15, 0.25


def _plane(svc: dict[str, Any], fmt: str, channels: list[str], scale: list[float],
           bias: list[float]) -> dict[str, Any]:
    return {"service": svc, "format": fmt, "channels": channels, "scale": scale, "bias": bias}


def _to_bytes(display: npt.NDArray[np.floating]) -> npt.NDArray[np.uint8]:
    out: npt.NDArray[np.uint8] = np.round(np.clip(display, 0.0, 1.0) * 255.0).astype(np.uint8)
    return out


def add_ptm_layer(ds: DatasetWriter, ptm: Ptm, *, layer_id: str = "ptm",
                  label: str = "PTM") -> dict[str, Any]:
    """Tile the planes of ``ptm`` (3 per image, the PTM's own bytes) and add it as a layer.

    The file's ``a = (byte − b)·s`` in 0–255 units becomes ``(t − b/255)·s`` with ``t`` in
    0–1 (docs/dataset-format.md), so the stored texels are exactly the PTM's bytes.
    """
    scale = [float(s) for s in ptm.scale]
    bias = [float(b) / 255.0 for b in ptm.bias]
    planes: list[dict[str, Any]] = []

    def group(ident: str, data: npt.NDArray[np.uint8], channels: list[str], sc: list[float],
              bi: list[float]) -> None:
        svc = ds.add_image(ident, np.ascontiguousarray(data), fmt="png")
        planes.append(_plane(svc, "png", channels, sc, bi))

    if ptm.colorspace == "lrgb":
        assert ptm.rgb is not None
        for g in range(2):
            k = slice(3 * g, 3 * g + 3)
            group(f"{layer_id}_c{g}", ptm.coefficients[..., k],
                  [f"L{i}" for i in range(3 * g, 3 * g + 3)], scale[k], bias[k])
        group(f"{layer_id}_color", ptm.rgb, ["R", "G", "B"], [1.0] * 3, [0.0] * 3)
    else:
        for c, name in enumerate("RGB"):
            for g in range(2):
                k = slice(3 * g, 3 * g + 3)
                group(f"{layer_id}_{name.lower()}{g}", ptm.coefficients[:, :, c, k],
                      [f"{name}{i}" for i in range(3 * g, 3 * g + 3)], scale[k], bias[k])
    ds.add_image(f"{layer_id}_preview", _to_bytes(ptm.relight(0.0, 0.0)), fmt="jpg")
    layer = {"id": layer_id, "label": label, "body": f"{layer_id}_preview", "layerType": "ptm",
             "colorspace": ptm.colorspace, "basis": list(PTM_BASIS), "planes": planes}
    ds.add_layer(layer)
    return layer


def hsh_plane_quantisation(hsh: Hsh) -> tuple[list[float], list[float]]:
    """Map the ``.rti`` ``byte/255·scale + bias`` to our ``(t − bias')·scale'`` per term.

    ``scale' = scale`` and ``bias' = −bias/scale``; a term with ``scale = 0`` (constant) keeps
    ``scale' = bias`` and ``bias' = 0``, and its texels are stored as 255.
    """
    scales, biases = [], []
    for s, b in zip(hsh.scale.tolist(), hsh.bias.tolist(), strict=True):
        if s == 0.0:
            scales.append(float(b))
            biases.append(0.0)
        else:
            scales.append(float(s))
            biases.append(float(-b / s))
    return scales, biases


def add_hsh_layer(ds: DatasetWriter, hsh: Hsh, *, layer_id: str = "hsh",
                  label: str = "HSH") -> dict[str, Any]:
    """Tile an HSH field: one IIIF image per term holding its R, G, B coefficients."""
    scales, biases = hsh_plane_quantisation(hsh)
    planes = []
    for k in range(hsh.terms):
        data = hsh.coefficients[:, :, :, k]
        if hsh.scale[k] == 0.0:
            data = np.full_like(data, 255)
        svc = ds.add_image(f"{layer_id}_t{k}", np.ascontiguousarray(data), fmt="png")
        planes.append(_plane(svc, "png", [f"R{k}", f"G{k}", f"B{k}"], [scales[k]] * 3,
                             [biases[k]] * 3))
    preview = hsh.dequantized() @ hsh_weights(0.0, 0.0, hsh.terms)
    ds.add_image(f"{layer_id}_preview", _to_bytes(preview), fmt="jpg")
    layer = {"id": layer_id, "label": label, "body": f"{layer_id}_preview", "layerType": "hsh",
             "terms": hsh.terms, "planes": planes}
    ds.add_layer(layer)
    return layer


def encode_normals(normals: npt.NDArray[np.floating]) -> npt.NDArray[np.uint8]:
    """Encode ``(H, W, 3)`` unit normals (OpenGL convention) as ``round((n + 1)/2·255)``."""
    if normals.ndim != 3 or normals.shape[2] != 3:
        raise ValueError(f"normals must be (H, W, 3), got {normals.shape}")
    return _to_bytes((np.asarray(normals, np.float32) + 1.0) * 0.5)


def linear_to_srgb(x: npt.NDArray[np.floating]) -> npt.NDArray[np.float32]:
    """The sRGB transfer function (docs/rendering.md)."""
    x = np.clip(np.asarray(x, np.float32), 0.0, 1.0)
    return np.where(x <= 0.0031308, 12.92 * x, 1.055 * np.power(x, 1 / 2.4) - 0.055).astype(
        np.float32)


def add_svbrdf_layer(
    ds: DatasetWriter,
    *,
    normals: npt.NDArray[np.uint8] | None = None,
    kd: npt.NDArray[np.uint8] | None = None,
    ks: npt.NDArray[np.uint8] | None = None,
    gloss: npt.NDArray[np.uint8] | None = None,
    depth: npt.NDArray[np.uint8] | None = None,
    depth_range: tuple[float, float] = (0.0, 1.0),
    gloss_limits: tuple[float, float] = (0.01, 0.5),
    input_colorspace: str = "linear",
    share: dict[str, str] | None = None,
    layer_id: str = "svbrdf",
    label: str = "Shape and material",
) -> dict[str, Any]:
    """Add a shape (normal map, depth) + material (kd, ks, gloss) layer; any subset of maps.

    Parameters
    ----------
    normals:
        ``(H, W, 3)`` uint8, encoded ``(n + 1)/2`` in the OpenGL convention (see
        :func:`encode_normals`).
    kd, ks:
        ``(H, W, 3)`` uint8 in ``input_colorspace`` (``"linear"`` or ``"srgb"``).
    gloss, depth:
        ``(H, W)`` uint8; gloss maps to ``α = αmin + t·(αmax − αmin)`` with ``gloss_limits``;
        depth to ``low + t·(high − low)`` with ``depth_range = (low, high)`` (the source's units).
    share:
        Optional map name → share key (e.g. the normal map's resolved path): maps with the same key
        across layers are stored once.
    """
    if input_colorspace not in ("linear", "srgb"):
        raise ValueError(f"inputColorSpace must be linear or srgb, not {input_colorspace!r}")
    lo, hi = (float(v) for v in gloss_limits)
    if not 0.0 < lo <= hi:
        raise ValueError(f"glossLimits must satisfy 0 < min <= max, got {gloss_limits}")
    maps: list[tuple[str, npt.NDArray[np.uint8] | None, list[str], list[float], list[float]]] = [
        ("normals", normals, ["NX", "NY", "NZ"], [2.0] * 3, [0.5] * 3),
        ("kd", kd, ["KD_R", "KD_G", "KD_B"], [1.0] * 3, [0.0] * 3),
        ("ks", ks, ["KS_R", "KS_G", "KS_B"], [1.0] * 3, [0.0] * 3),
        ("gloss", gloss, ["GLOSS"], [1.0], [0.0]),
        ("depth", depth, ["DEPTH"], *_range_quantisation(depth_range)),
    ]
    planes = []
    for name, data, channels, sc, bi in maps:
        if data is None:
            continue
        expected = (ds.height, ds.width) + ((3,) if len(channels) == 3 else ())
        if data.dtype != np.uint8 or data.shape != expected:
            raise ValueError(f"{name} map must be uint8 {expected}, got {data.dtype} {data.shape}")
        key = (share or {}).get(name)
        svc = ds.add_image(f"{layer_id}_{name}", np.ascontiguousarray(data), fmt="png",
                           share_key=key)
        planes.append(_plane(svc, "png", channels, sc, bi))
    if not planes:
        raise ValueError("a shape + material layer needs at least one map")
    preview = _svbrdf_preview(normals, kd, input_colorspace)
    ds.add_image(f"{layer_id}_preview", _to_bytes(preview), fmt="jpg")
    layer = {"id": layer_id, "label": label, "body": f"{layer_id}_preview", "layerType": "svbrdf",
             "glossLimits": [lo, hi], "inputColorSpace": input_colorspace, "planes": planes}
    ds.add_layer(layer)
    return layer


def _range_quantisation(value_range: tuple[float, float]) -> tuple[list[float], list[float]]:
    """``(scale, bias)`` so that ``(t − bias)·scale`` spans ``value_range`` for t in 0–1."""
    low, high = (float(v) for v in value_range)
    span = high - low
    return ([span], [-low / span]) if span != 0 else ([low], [0.0])


def _svbrdf_preview(normals: npt.NDArray[np.uint8] | None, kd: npt.NDArray[np.uint8] | None,
                    colorspace: str) -> npt.NDArray[np.float32]:
    """A Lambertian preview lit from overhead: ``srgb(kd · n.z)`` (or the unshaded kd)."""
    if kd is None:
        assert normals is not None
        albedo = np.full(normals.shape, DEFAULT_KD, np.float32)
    else:
        albedo = kd.astype(np.float32) / 255.0
        if colorspace == "srgb":
            albedo = np.where(albedo <= 0.04045, albedo / 12.92,
                              ((albedo + 0.055) / 1.055) ** 2.4).astype(np.float32)
    if normals is None:
        return linear_to_srgb(albedo)
    n = normals.astype(np.float32) / 255.0 * 2.0 - 1.0
    nz = n[..., 2:3] / np.maximum(np.linalg.norm(n, axis=-1, keepdims=True), 1e-6)
    return linear_to_srgb(albedo * np.clip(nz, 0.0, 1.0))


def add_image_layer(ds: DatasetWriter, image: pyvips.Image, *, layer_id: str = "image",
                    label: str = "Image", fmt: str = "jpg",
                    share_key: str | None = None) -> dict[str, Any]:
    """Add a plain (unshaded) image layer; a single-band image is a grey ``Y`` layer."""
    mono = image.bands == 1
    svc = ds.add_image(layer_id, image, fmt=fmt, share_key=share_key)
    body = svc["id"].rsplit("/", 1)[1]
    layer = {"id": layer_id, "label": label, "body": body, "layerType": "image",
             "planes": [_plane(svc, fmt, ["Y"] if mono else ["R", "G", "B"],
                               [1.0] * (1 if mono else 3), [0.0] * (1 if mono else 3))]}
    ds.add_layer(layer)
    return layer


def add_planes_layer(ds: DatasetWriter, layer: PlaneLayer, *, layer_id: str,
                     label: str) -> dict[str, Any]:
    """Tile a format-neutral :class:`~lanterna.tiler.planes.PlaneLayer` (ptm or hsh) as a layer."""
    planes = []
    for i, g in enumerate(layer.groups):
        svc = ds.add_image(f"{layer_id}_p{i}", np.ascontiguousarray(g.data), fmt="png")
        planes.append(_plane(svc, "png", list(g.channels), list(g.scale), list(g.bias)))
    ch = layer.channels()
    if layer.layer_type == "ptm":
        w = ptm_weights(0.0, 0.0)  # overhead light
        if layer.colorspace == "lrgb":
            lum = sum(ch[f"L{k}"] * w[k] for k in range(6))
            preview = np.stack([ch[c] * lum for c in "RGB"], axis=-1)
        else:
            preview = np.stack([sum(ch[f"{c}{k}"] * w[k] for k in range(6)) for c in "RGB"], -1)
        fields: dict[str, Any] = {"colorspace": layer.colorspace, "basis": list(PTM_BASIS)}
    elif layer.layer_type == "hsh":
        assert layer.terms is not None
        hw = hsh_weights(0.0, 0.0, layer.terms)
        preview = np.stack([sum(ch[f"{c}{k}"] * hw[k] for k in range(layer.terms)) for c in "RGB"],
                           axis=-1)
        fields = {"terms": layer.terms}
    else:
        raise ValueError(f"unsupported plane layer type {layer.layer_type!r}")
    ds.add_image(f"{layer_id}_preview", _to_bytes(preview), fmt="jpg")
    out = {"id": layer_id, "label": label, "body": f"{layer_id}_preview",
           "layerType": layer.layer_type, **fields, "planes": planes}
    ds.add_layer(out)
    return out
