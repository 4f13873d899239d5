"""Fitting PCA light bases (Relight's ``rbf`` and ``bilinear``, colour spaces ``mrgb``/``mycc``).

Pure maths on arrays; the semantics of what is fitted are those of
:mod:`lanterna.tiler.formats.pca_model` (docs/dataset-format.md).  A pixel's light samples
``x`` (``(n, 3)`` in 0–1, one row per acquisition light) become the basis's ``D`` samples: the
lights themselves (``rbf``, ``D = n``) or resampled onto the ``R × R`` octahedral grid
(``bilinear``, :func:`resample_matrix`), in YCoCg for ``mycc`` (:data:`RGB_TO_YCC`).  A PCA of
a bounded sample of pixels (:mod:`.pca_sample`) gives the mean and ``N`` eigenvectors, stored
as Relight's bytes (:mod:`.pca_basis`); every pixel is then projected onto the stored basis
(:meth:`~.pca_basis.PcaFit.coefficients`) and its coefficients quantised per plane by the sample's
central :data:`RANGE_QUANTILE` (Relight's ``minmaxMaterial``).  Facts from Relight's
``rtibuilder.cpp`` (``pickBasePCA``, ``minmaxMaterial``, ``buildResampleMap``), written here.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from lanterna.errors import LanternaInputError
from lanterna.tiler.formats.pca_model import (
    MAX_PCA_PLANES,
    PCA_COLORSPACES,
    PCA_TYPES,
    YCC_TO_RGB,
    bilinear_weights,
    rbf_direction_weights,
)

F64 = npt.NDArray[np.float64]
F32 = npt.NDArray[np.float32]

#: Coefficient planes by default (Relight's default is 9; 18 beats HSH9 on real data, docs).
DEFAULT_PLANES = 18
#: Relight's defaults: RBF σ (for ~100 lights), bilinear grid side and its regularisation.
DEFAULT_SIGMA = 0.125
DEFAULT_RESOLUTION = 8
REGULARIZATION = 0.1
#: RBF weights of a grid direction at or below this are dropped (Relight's ``buildResampleMap``).
RESAMPLE_DROP = 0.005
#: Coefficients are quantised over this central fraction of the sample's values (Relight).
RANGE_QUANTILE = 0.995
#: The PCA bases' CLI names and labels.
PCA_LABELS = {"rbf": "RBF", "bilinear": "Bilinear"}
#: Relight's ``Color3::toYcc`` (YCoCg): the inverse of :data:`YCC_TO_RGB`.
RGB_TO_YCC: F64 = np.asarray(np.linalg.inv(YCC_TO_RGB), np.float64)


@dataclass(frozen=True)
class PcaSpec:
    """What to fit: ``layer_type`` ``rbf``/``bilinear``, colour space, planes, σ, resolution."""

    layer_type: str
    colorspace: str = "mrgb"
    nplanes: int = DEFAULT_PLANES
    sigma: float = DEFAULT_SIGMA
    resolution: int = DEFAULT_RESOLUTION

    @property
    def yccplanes(self) -> tuple[int, int, int] | None:
        """``mycc``: ``[ny, nc, nc]`` with ``nc = N // 4`` (so ``ny ≥ N/2``), else ``None``."""
        if self.colorspace != "mycc":
            return None
        nc = self.nplanes // 4
        return (self.nplanes - 2 * nc, nc, nc)


def parse_spec(model: str, planes: object = None, colorspace: object = None) -> PcaSpec:
    """The :class:`PcaSpec` of ``--model`` with ``--planes``/``--colorspace`` (CLI strings ok).

    Raises
    ------
    LanternaInputError
        One line naming the option and its value.
    """
    if model not in PCA_TYPES:
        raise LanternaInputError(None, f"--model {model} is not a PCA basis "
                                 f"({', '.join(PCA_TYPES)})")
    n = DEFAULT_PLANES
    if planes is not None:
        text = str(planes).strip()
        if not text.lstrip("+").isdigit():
            raise LanternaInputError(None, f"--planes must be an integer from 1 to "
                                     f"{MAX_PCA_PLANES}, got {planes!r}")
        n = int(text)
        if not 1 <= n <= MAX_PCA_PLANES:
            raise LanternaInputError(None, f"--planes must be from 1 to {MAX_PCA_PLANES}, "
                                     f"got {n}")
    space = "mrgb" if colorspace is None else str(colorspace)
    if space not in PCA_COLORSPACES:
        raise LanternaInputError(None, f"--colorspace must be {' or '.join(PCA_COLORSPACES)}, "
                                 f"got {space!r}")
    return PcaSpec(model, space, n)


def resample_matrix(lights: npt.ArrayLike, resolution: int, sigma: float = DEFAULT_SIGMA,
                    regularization: float = REGULARIZATION) -> F64:
    """Relight's ``buildResampleMap``: ``(R², n)`` weights from light samples to grid samples.

    ``B`` interpolates each grid direction (``fromOcta``) from the lights by normalised
    Gaussian weights ``exp(−‖n − l‖²/σ²)`` (≤ :data:`RESAMPLE_DROP` dropped, renormalised);
    ``A`` ``(n, R²)`` is the bilinear reading of the grid at each light; the grid is the
    regularised least-squares solution near ``B·b``:
    ``M = B + (AᵀA + kI)⁻¹·Aᵀ·(I − A·B)``.  Relight then drops the entries ``|m| ≤ 0.005``
    to save work per pixel; here ``M`` is folded into one matrix product and kept whole, so
    its rows sum to 1 (a constant stays constant; the drop shifts it by up to 4 %).
    """
    dirs = np.asarray(lights, np.float64).reshape(-1, 3)
    dirs = dirs / np.linalg.norm(dirs, axis=1, keepdims=True)
    res = int(resolution)
    b = np.zeros((res * res, len(dirs)))
    for y in range(res):
        for x in range(res):
            ox, oy = 2.0 * x / (res - 1) - 1.0, 2.0 * y / (res - 1) - 1.0
            gx, gy = (ox - oy) / 2.0, (ox + oy) / 2.0
            g = np.array([gx, gy, max(0.0, 1.0 - abs(gx) - abs(gy))])
            g /= np.linalg.norm(g)
            b[x + y * res] = rbf_direction_weights(dirs, sigma, g, RESAMPLE_DROP)
    a = np.stack([bilinear_weights(res, float(lx), float(ly)) for lx, ly, _ in dirs])
    inv = np.linalg.inv(a.T @ a + regularization * np.eye(res * res))
    out: F64 = b + inv @ (a.T @ (np.eye(len(dirs)) - a @ b))
    return out


def sample_transform(spec: PcaSpec, nlights: int, resample: F64 | None) -> F64:
    """The basis samples of a pixel as one matrix ``(D·3, n·3)`` on its flattened light samples
    (index ``light·3 + channel``): the resampling onto the grid (bilinear), then YCoCg (mycc)."""
    t: F64 = np.asarray(np.kron(resample, np.eye(3)) if resample is not None
                        else np.eye(3 * nlights), np.float64)
    if spec.colorspace == "mycc":
        t = np.kron(np.eye(t.shape[0] // 3), RGB_TO_YCC) @ t
    return t
