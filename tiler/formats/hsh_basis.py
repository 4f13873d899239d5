"""Hemispherical Harmonics basis weights (Gautron et al. 2004; RTIViewer's ``getHSH``).

The formulas are normative in docs/rendering.md (``hsh``); the plugin implements the same in GLSL.
"""

from __future__ import annotations

import math

import numpy as np
import numpy.typing as npt

#: Largest elevation angle used: lights closer to the horizon are clamped (RTIViewer's π/2 − 0.04).
MAX_THETA = math.pi / 2 - 0.04


def hsh_weights(lu: float, lv: float, terms: int) -> npt.NDArray[np.float32]:
    """Return the ``terms`` (4, 9 or 16) HSH weights for the light projected at (lu, lv)."""
    if terms not in (4, 9, 16):
        raise ValueError(f"HSH has 4, 9 or 16 terms, not {terms}")
    r = math.hypot(lu, lv)
    lz = math.sqrt(max(0.0, 1.0 - min(r, 1.0) ** 2))
    theta = min(math.acos(min(max(lz, 0.0), 1.0)), MAX_THETA)
    x = math.cos(theta)
    s = math.sqrt(max(x - x * x, 0.0))
    cp, sp = (lu / r, lv / r) if r >= 1e-6 else (1.0, 0.0)
    c2, s2 = cp * cp - sp * sp, 2 * sp * cp
    c3, s3 = 4 * cp**3 - 3 * cp, 3 * sp - 4 * sp**3
    pi = math.pi
    w = [
        1 / math.sqrt(2 * pi),
        math.sqrt(6 / pi) * cp * s,
        math.sqrt(3 / (2 * pi)) * (2 * x - 1),
        math.sqrt(6 / pi) * sp * s,
        math.sqrt(30 / pi) * c2 * (x * x - x),
        math.sqrt(30 / pi) * cp * (2 * x - 1) * s,
        math.sqrt(5 / (2 * pi)) * (6 * x * x - 6 * x + 1),
        math.sqrt(30 / pi) * sp * (2 * x - 1) * s,
        math.sqrt(30 / pi) * s2 * (x * x - x),
        2 * math.sqrt(35 / pi) * c3 * s**3,
        math.sqrt(210 / pi) * c2 * (2 * x - 1) * (x * x - x),
        2 * math.sqrt(21 / pi) * cp * s * (1 - 5 * x + 5 * x * x),
        math.sqrt(7 / (2 * pi)) * (20 * x**3 - 30 * x * x + 12 * x - 1),
        2 * math.sqrt(21 / pi) * sp * s * (1 - 5 * x + 5 * x * x),
        math.sqrt(210 / pi) * s2 * (2 * x - 1) * (x * x - x),
        2 * math.sqrt(35 / pi) * s3 * s**3,
    ]
    return np.array(w[:terms], dtype=np.float32)
