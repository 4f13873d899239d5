"""Relight's ``colorspace: "ycc"`` for ``ptm``, ``hsh`` and ``sh``, converted exactly into ``rgb``.

Relight ``Rti::render`` (case ``YCC``) relights such a folder as: luma
``Y = Σ_t w_t(l)·r[3t]`` (the term-``t`` weight of the basis, ``r[p]`` plane ``p`` dequantised,
``(t − bias)·scale``), chroma ``Cb = r[1]``, ``Cr = r[2]`` independent of the light, then
``Color3::YCbCrToRgb`` (``src/color.h``)::

    R = Y + 1.402·(Cr − ½)
    G = Y − 0.344136·(Cb − ½) − 0.714136·(Cr − ½)
    B = Y + 1.772·(Cb − ½)

(planes ``3t + 1``, ``3t + 2`` of ``t ≥ 1`` are not used). So every colour channel has Y's terms
and a constant ``k_c`` (the chroma part above). The equivalent ``rgb`` folder has, for every
channel ``c``, term ``t ≥ 1`` = plane ``3t`` (bytes, scale and bias unchanged) and term 0 =
``r[0] + k_c / w_0`` with ``w_0`` the basis's constant weight (PTM's ``1``, HSH's
``1/√(2π)``, SH's ``0.282095``): only those three term-0 planes are requantised (8 bits over
their own range), so a render differs from Relight's by at most half a step of that range.
"""

from __future__ import annotations

import math

import numpy as np
import numpy.typing as npt

from .sh_model import C0 as SH_C0

#: The weight of term 0 of each basis (the constant one).
CONSTANT_WEIGHT = {"ptm": 1.0, "hsh": 1.0 / math.sqrt(2.0 * math.pi), "sh": SH_C0}
#: ``YCbCrToRgb`` of Relight's ``src/color.h``: rows R, G, B; columns Cb − ½, Cr − ½.
CHROMA_TO_RGB = np.array([[0.0, 1.402], [-0.344136, -0.714136], [1.772, 0.0]], np.float64)

Planes = npt.NDArray[np.uint8]


def ycc_as_rgb(rtype: str, planes: Planes, scale: list[float],
               bias: list[float]) -> tuple[Planes, list[float], list[float]]:
    """The ``rgb`` planes ``(n, H, W)`` and per-plane scale/bias equivalent to ``ycc`` ones."""
    n = planes.shape[0]
    out = np.empty_like(planes)
    new_scale, new_bias = [0.0] * n, [0.0] * n
    for t in range(1, n // 3):
        for c in range(3):
            out[3 * t + c] = planes[3 * t]
            new_scale[3 * t + c], new_bias[3 * t + c] = scale[3 * t], bias[3 * t]

    def value(p: int) -> npt.NDArray[np.float64]:
        out: npt.NDArray[np.float64] = (planes[p] / 255.0 - bias[p]) * scale[p]
        return out

    chroma = np.stack([value(1) - 0.5, value(2) - 0.5], axis=-1)
    y0 = value(0)
    for c in range(3):
        v = y0 + (chroma @ CHROMA_TO_RGB[c]) / CONSTANT_WEIGHT[rtype]
        out[c], new_scale[c], new_bias[c] = requantise(v)
    return out, new_scale, new_bias


def requantise(v: npt.NDArray[np.float64]) -> tuple[Planes, float, float]:
    """8-bit ``t`` with ``(t/255 − bias)·scale ≈ v`` over ``v``'s own range (exact if constant)."""
    lo, hi = float(v.min()), float(v.max())
    span = hi - lo
    if span <= 0.0 or not math.isfinite(span):
        return np.zeros(v.shape, np.uint8), 1.0, -lo
    t = np.rint((v - lo) / span * 255.0).clip(0, 255).astype(np.uint8)
    return t, span, -lo / span
