"""Relight's plain real spherical harmonics (``type: "sh"``): the light basis and its term counts.

The basis is Relight's ``Rti::lightWeightsSh`` (``src/rti.cpp``), the real spherical harmonics
of bands 0–2 without the Condon–Shortley phase, for the light ``l = (lu, lv, lz)``,
``lz = √(1 − lu² − lv²)``, with Relight's rounded constants::

    Y0 = 0.282095            Y4 = 1.092548·lu·lv
    Y1 = 0.488603·lv         Y5 = 1.092548·lv·lz
    Y2 = 0.488603·lz         Y6 = 0.315392·(3·lz² − 1)
    Y3 = 0.488603·lu         Y7 = 1.092548·lu·lz
                             Y8 = 0.546274·(lu² − lv²)

A layer of order 1 has the first 4 terms (``nplanes`` 12), of order 2 all 9 (``nplanes`` 27):
Relight's builder fits only those two (``RtiBuilder::pickBaseHSH`` asserts 12 or 27 planes), in
``rgb`` (or ``ycc``) only — it refuses ``mrgb``/``mycc`` for sh, so there is no PCA sh.
OpenLIME 1.2.6's ``SH.lightWeights`` differs (band 1 ``x, z, y``, terms 5 and 7 swapped, term 6
doubled, term 8 negated); Relight's builder fits the coefficients against ``lightWeightsSh``, so
that is the basis that relights them as they were made.

The formulas are normative in docs/rendering.md (``sh``); the plugin's ``math/sh-basis.ts`` is
the same in TypeScript and GLSL. This is not an HSH (whose terms hold ``√(cos θ − cos² θ)``) nor a
PTM (polynomials of ``lu, lv`` only): a layer type of its own.
"""

from __future__ import annotations

import numpy as np
import numpy.typing as npt

#: Term counts of an sh layer: order 1 and order 2.
SH_TERMS = (4, 9)
#: Relight's constants: ``Y0``; band 1; ``lu·lv``, ``lv·lz``, ``lu·lz``; ``3lz² − 1``; ``lu² − lv²``
C0, C1, C2, C3, C4 = 0.282095, 0.488603, 1.092548, 0.315392, 0.546274

F32 = npt.NDArray[np.float32]


def sh_basis(lu: npt.ArrayLike, lv: npt.ArrayLike, terms: int) -> F32:
    """SH weights for (arrays of) projected light directions: ``broadcast(lu, lv) + (terms,)``.

    ``lz = √(max(0, 1 − lu² − lv²))`` (a light on or past the rim is at the horizon).
    """
    if terms not in SH_TERMS:
        raise ValueError(f"sh has 4 or 9 terms, not {terms}")
    u, v = np.broadcast_arrays(np.asarray(lu, np.float32), np.asarray(lv, np.float32))
    z = np.sqrt(np.maximum(np.float32(0), np.float32(1) - u * u - v * v))

    def k(c: float) -> np.float32:
        return np.float32(c)

    w = [np.full_like(u, k(C0)), k(C1) * v, k(C1) * z, k(C1) * u,
         k(C2) * u * v, k(C2) * v * z, k(C3) * (3 * z * z - 1), k(C2) * u * z,
         k(C4) * (u * u - v * v)]
    out: F32 = np.stack(w[:terms], axis=-1).astype(np.float32)
    return out


def sh_weights(lu: float, lv: float, terms: int) -> F32:
    """The ``terms`` (4 or 9) SH weights of one light projected at ``(lu, lv)``."""
    return sh_basis(lu, lv, terms)
