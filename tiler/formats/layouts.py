"""Plane layouts: how each layer type's values are grouped, three channels per IIIF image.

Pure functions from a model's bytes and quantisation to :class:`~.planes.PlaneLayer` s, shared by
the importers (:mod:`lanterna.tiler.dataset.layers`) and the fitting engine
(:mod:`lanterna.tiler.fit.engine`) (schema: docs/dataset-format.md).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence

import numpy as np
import numpy.typing as npt

from .hsh_model import Hsh
from .planes import PlaneData, PlaneGroup, PlaneLayer


def to_bytes(display: npt.NDArray[np.floating]) -> npt.NDArray[np.uint8]:
    """Round display values in 0–1 (clamped) to bytes."""
    out: npt.NDArray[np.uint8] = np.round(np.clip(display, 0.0, 1.0) * 255.0).astype(np.uint8)
    return out


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


def ptm_plane_layer(colorspace: str, scale: npt.ArrayLike, bias: npt.ArrayLike,
                    coefficients: Callable[[int | None, slice], PlaneData],
                    rgb: PlaneData | None, *, lossy: bool = False) -> PlaneLayer:
    """The plane groups of a PTM: ``c0, c1, color`` (lrgb) or ``r0, r1, g0, … b1`` (rgb).

    ``lossy``: the bytes are a lossy decode (a JPEG PTM), marked on every group.
    ``scale``/``bias`` are the file's per-coefficient values (``a = (byte − b)·s`` in 0–255
    units), stored as ``(t − b/255)·s`` with ``t`` in 0–1 (docs/dataset-format.md);
    ``coefficients(c, k)`` returns the bytes of channel ``c`` (``None`` for lrgb), terms ``k``.
    """
    sc = [float(v) for v in np.asarray(scale).reshape(-1)]
    bi = [float(v) / 255.0 for v in np.asarray(bias).reshape(-1)]
    groups, names = [], []
    if colorspace == "lrgb":
        if rgb is None:
            raise ValueError("an LRGB PTM needs its RGB plane")
        for g in range(2):
            k = slice(3 * g, 3 * g + 3)
            groups.append(PlaneGroup([f"L{i}" for i in range(3 * g, 3 * g + 3)],
                                     coefficients(None, k), sc[k], bi[k], lossy))
            names.append(f"c{g}")
        groups.append(PlaneGroup(["R", "G", "B"], rgb, [1.0] * 3, [0.0] * 3, lossy))
        names.append("color")
    else:
        for c, name in enumerate("RGB"):
            for g in range(2):
                k = slice(3 * g, 3 * g + 3)
                groups.append(PlaneGroup([f"{name}{i}" for i in range(3 * g, 3 * g + 3)],
                                         coefficients(c, k), sc[k], bi[k], lossy))
                names.append(f"{name.lower()}{g}")
    return PlaneLayer("ptm", groups, colorspace=colorspace, group_names=names)


def hsh_plane_layer(scales: Sequence[float], biases: Sequence[float],
                    term: Callable[[int], PlaneData]) -> PlaneLayer:
    """The plane groups of an HSH field: ``t0 … t{K−1}``, term k's R, G, B in one image.

    ``scales``/``biases`` are the stored ``(t − bias)·scale`` values per term;
    ``term(k)`` returns term k's ``(H, W, 3)`` bytes.
    """
    groups = [PlaneGroup([f"R{k}", f"G{k}", f"B{k}"], term(k), [scales[k]] * 3, [biases[k]] * 3)
              for k in range(len(scales))]
    return PlaneLayer("hsh", groups, terms=len(scales),
                      group_names=[f"t{k}" for k in range(len(scales))])


def encode_normals(normals: npt.NDArray[np.floating]) -> npt.NDArray[np.uint8]:
    """Encode ``(H, W, 3)`` unit normals (OpenGL convention) as ``round((n + 1)/2·255)``."""
    if normals.ndim != 3 or normals.shape[2] != 3:
        raise ValueError(f"normals must be (H, W, 3), got {normals.shape}")
    return to_bytes((np.asarray(normals, np.float32) + 1.0) * 0.5)


#: The svbrdf maps in storage order: channels, scale and bias of each (docs/dataset-format.md).
#: A depth map's scale and bias come from its value range (:func:`range_quantisation`).
SVBRDF_MAPS: dict[str, tuple[list[str], list[float], list[float]]] = {
    "normals": (["NX", "NY", "NZ"], [2.0] * 3, [0.5] * 3),
    "kd": (["KD_R", "KD_G", "KD_B"], [1.0] * 3, [0.0] * 3),
    "ks": (["KS_R", "KS_G", "KS_B"], [1.0] * 3, [0.0] * 3),
    "gloss": (["GLOSS"], [1.0], [0.0]),
    "depth": (["DEPTH"], [1.0], [0.0]),
}


def range_quantisation(value_range: tuple[float, float]) -> tuple[list[float], list[float]]:
    """``(scale, bias)`` so that ``(t − bias)·scale`` spans ``value_range`` for t in 0–1."""
    low, high = (float(v) for v in value_range)
    span = high - low
    return ([span], [-low / span]) if span != 0 else ([low], [0.0])
