"""PCA light bases (Relight's ``rbf`` and ``bilinear`` types, colour spaces ``mrgb`` and ``mycc``).

Pure maths, the single statement of the semantics that the reader, the fit, the numpy reference
renderer and (in TypeScript) the plugin follow (docs/dataset-format.md, docs/rendering.md). Facts
from Relight's ``src/rti.cpp`` (``Rti::load``, ``Rti::render``, ``lightWeightsRbf``,
``lightWeightsBilinear``) and ``src/color.h`` (``toRgb``); written here from those facts.

A pixel holds ``N`` coefficients ``r_q = (t_q − bias_q)·scale_q`` (display units). The basis has
``N + 1`` rows (row 0 the mean) sampled at ``D`` light directions, 3 channels each; its bytes
``b[p, d, k]`` decode as ``b/255`` (p = 0) and ``(b − 127)/range[p − 1]`` (p ≥ 1). For a light
``l`` the sample weights ``w_d(l)`` (RBF or bilinear, below) give ``E[p, k] = Σ_d w_d·B[p, d, k]``
and the colour

- ``mrgb``: ``c_k = E[0, k] + Σ_q r_q·E[q + 1, k]``;
- ``mycc``: with ``yccplanes = [ny, nc, nc]``, plane ``q < 3·nc`` belongs to YCC channel ``q % 3``,
  later planes to channel 0 (Y); ``y_k = E[0, k] + Σ_{q of channel k} r_q·E[q + 1, k]`` and
  ``c = M·y`` with ``M`` Relight's YCoCg→RGB (:data:`YCC_TO_RGB`).

Both are linear in ``r``, so :func:`rgb_plane_weights` folds the channel selection and ``M`` into
per-plane RGB weights ``W[p]`` (``c = W[0] + Σ_q r_q·W[q + 1]``), the form the plugin uploads.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
import numpy.typing as npt

F64 = npt.NDArray[np.float64]

#: Basis types and colour spaces of this module.
PCA_TYPES = ("rbf", "bilinear")
PCA_COLORSPACES = ("mrgb", "mycc")
#: Normalised RBF weights at or below this are dropped, the rest renormalised (Relight).
RBF_DROP = 0.001
#: Most coefficient planes a PCA layer may have (16 plane groups of 3, the plugin's texture limit).
MAX_PCA_PLANES = 48

#: Relight's ``Color3::toRgb``: RGB = M · (Y, Co, Cg) (rows R, G, B).
YCC_TO_RGB: F64 = np.array([[1.0, 0.5, -0.5],
                            [1.0, 0.0, 0.5],
                            [1.0, -0.5, -0.5]], np.float64)


def light_direction(lu: float, lv: float) -> F64:
    """The unit light ``(lu, lv, lz)``; a projection outside the unit disk is moved onto it."""
    r = math.hypot(lu, lv)
    if r > 1.0:
        lu, lv = lu / r, lv / r
    return np.array([lu, lv, math.sqrt(max(0.0, 1.0 - lu * lu - lv * lv))], np.float64)


def rbf_weights(lights: npt.ArrayLike, sigma: float, lu: float, lv: float) -> F64:
    """Relight's RBF sample weights ``(D,)`` for the light projected at ``(lu, lv)``.

    ``g_d = exp(−‖l − l_d‖²/σ²)``, ``w = g/Σg``; weights ``≤`` :data:`RBF_DROP` become 0 and the
    rest are renormalised to sum 1 (:func:`rbf_direction_weights` of :func:`light_direction`).
    """
    return rbf_direction_weights(lights, sigma, light_direction(lu, lv))


def rbf_direction_weights(lights: npt.ArrayLike, sigma: float, direction: npt.ArrayLike,
                          drop: float = RBF_DROP) -> F64:
    """The RBF weights ``(D,)`` of a unit ``direction``; weights ``≤ drop`` are dropped (the
    fit's grid resampling has its own ``drop``). The exponent is shifted by its minimum before
    ``exp``, which leaves the normalised weights unchanged and keeps them finite for any light.
    """
    dirs = np.asarray(lights, np.float64).reshape(-1, 3)
    d2 = np.sum((dirs - np.asarray(direction, np.float64)) ** 2, axis=1)
    g = np.exp(-(d2 - d2.min()) / (float(sigma) ** 2))
    w = g / g.sum()
    keep = w > drop
    if not keep.any():  # cannot happen for D < 1000; keep the nearest light
        keep = w == w.max()
    w = np.where(keep, w, 0.0)
    out: F64 = w / w.sum()
    return out


def bilinear_weights(resolution: int, lu: float, lv: float) -> F64:
    """Relight's bilinear sample weights ``(R·R,)`` (sample ``x + y·R``) for ``(lu, lv)``.

    The light is mapped onto the octahedral square rotated by 45°: ``s = |lx| + |ly| + |lz|``,
    ``x = ((lx + ly)/s + 1)/2·(R − 1)``, ``y = ((ly − lx)/s + 1)/2·(R − 1)``; the cell corner is
    ``(sx, sy) = clamp(floor(x, y), 0, R − 2)`` and the four corners get the bilinear weights of
    ``(x − sx, y − sy)``.
    """
    res = int(resolution)
    lx, ly, lz = light_direction(lu, lv)
    s = abs(lx) + abs(ly) + abs(lz)
    x = ((lx + ly) / s + 1.0) / 2.0 * (res - 1)
    y = ((ly - lx) / s + 1.0) / 2.0 * (res - 1)
    sx = min(res - 2, max(0, math.floor(x)))
    sy = min(res - 2, max(0, math.floor(y)))
    dx, dy = x - sx, y - sy
    w = np.zeros(res * res, np.float64)
    for (ox, oy), v in (((0, 0), (1 - dx) * (1 - dy)), ((1, 0), dx * (1 - dy)),
                        ((0, 1), (1 - dx) * dy), ((1, 1), dx * dy)):
        w[(sx + ox) + (sy + oy) * res] += v
    return w


def decode_basis(basis: npt.ArrayLike, ranges: Sequence[float], ndimensions: int) -> F64:
    """Relight's basis bytes (flat, ``((p·D + d)·3 + k)``) as values ``(N + 1, D, 3)``."""
    b = np.asarray(basis, np.float64).reshape(len(ranges) + 1, int(ndimensions), 3)
    out = np.empty_like(b)
    out[0] = b[0] / 255.0
    out[1:] = (b[1:] - 127.0) / np.asarray(ranges, np.float64)[:, None, None]
    return out


def plane_channels(colorspace: str, nplanes: int, yccplanes: Sequence[int] | None) -> list[int]:
    """The YCC channel of each plane (``mycc``), or ``-1`` for every plane (``mrgb``: all three)."""
    if colorspace == "mrgb":
        return [-1] * nplanes
    nc = int(yccplanes[1]) if yccplanes else 0
    return [q % 3 if q < 3 * nc else 0 for q in range(nplanes)]


def rgb_plane_weights(e: npt.ArrayLike, colorspace: str,
                      yccplanes: Sequence[int] | None = None) -> F64:
    """Fold ``E`` ``(N + 1, 3)`` into RGB weights ``W`` with ``c = W[0] + Σ_q r_q·W[q + 1]``."""
    ev = np.asarray(e, np.float64)
    if colorspace == "mrgb":
        return ev.copy()
    if colorspace != "mycc":
        raise ValueError(f"unknown PCA colour space {colorspace!r}")
    out = np.empty_like(ev)
    out[0] = YCC_TO_RGB @ ev[0]
    for q, k in enumerate(plane_channels(colorspace, ev.shape[0] - 1, yccplanes)):
        out[q + 1] = YCC_TO_RGB[:, k] * ev[q + 1, k]
    return out


@dataclass(frozen=True)
class PcaBasis:
    """A layer's PCA basis, as its relight service block states it (docs/dataset-format.md)."""

    layer_type: str
    colorspace: str
    basis: npt.NDArray[np.uint8]  # flat, (N + 1)·D·3 bytes
    ranges: tuple[float, ...]  # N
    lights: tuple[float, ...] | None = None  # rbf: D·3
    sigma: float | None = None  # rbf
    resolution: int | None = None  # bilinear
    yccplanes: tuple[int, int, int] | None = None  # mycc

    @property
    def nplanes(self) -> int:
        return len(self.ranges)

    @property
    def ndimensions(self) -> int:
        if self.layer_type == "bilinear":
            return int(self.resolution or 0) ** 2
        return len(self.lights or ()) // 3

    def values(self) -> F64:
        """The decoded basis ``(N + 1, D, 3)``."""
        return decode_basis(self.basis, self.ranges, self.ndimensions)

    def sample_weights(self, lu: float, lv: float) -> F64:
        """``w_d(l)``, ``(D,)``."""
        if self.layer_type == "rbf":
            return rbf_weights(self.lights or (), float(self.sigma or 0.0), lu, lv)
        return bilinear_weights(int(self.resolution or 0), lu, lv)

    def weights(self, lu: float, lv: float) -> F64:
        """RGB plane weights ``W`` ``(N + 1, 3)`` for the light at ``(lu, lv)``."""
        e = np.einsum("d,pdk->pk", self.sample_weights(lu, lv), self.values())
        return rgb_plane_weights(e, self.colorspace, self.yccplanes)

    def fields(self) -> dict[str, object]:
        """The type-specific fields of the relight service block."""
        out: dict[str, object] = {"colorspace": self.colorspace, "nplanes": self.nplanes,
                                  "basis": [int(v) for v in self.basis],
                                  "range": [float(v) for v in self.ranges]}
        if self.yccplanes is not None:
            out["yccplanes"] = list(self.yccplanes)
        if self.layer_type == "rbf":
            out["lights"] = [float(v) for v in self.lights or ()]
            out["sigma"] = float(self.sigma or 0.0)
        else:
            out["resolution"] = int(self.resolution or 0)
        return out

    @classmethod
    def from_block(cls, block: Mapping[str, Any]) -> PcaBasis:
        """The basis of a (validated) relight service block of type ``rbf`` or ``bilinear``."""
        ycc = block.get("yccplanes")
        lights = block.get("lights")
        return cls(str(block["layerType"]), str(block["colorspace"]),
                   np.asarray(block["basis"], np.uint8).reshape(-1),
                   tuple(float(v) for v in block["range"]),
                   tuple(float(v) for v in lights) if lights is not None else None,
                   float(block["sigma"]) if "sigma" in block else None,
                   int(block["resolution"]) if "resolution" in block else None,
                   (int(ycc[0]), int(ycc[1]), int(ycc[2])) if ycc is not None else None)


def plane_channel_names(nplanes: int) -> list[list[str]]:
    """The channel names of a PCA layer's groups: ``P0, P1, P2`` …; padding ``X{k}`` (scale 0)."""
    groups = []
    for g in range(0, nplanes, 3):
        groups.append([f"P{q}" if q < nplanes else f"X{q}" for q in range(g, g + 3)])
    return groups
