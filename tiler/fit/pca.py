"""Fitting PCA light bases (Relight's ``rbf`` and ``bilinear``, colour spaces ``mrgb``/``mycc``).

Pure maths on arrays; the semantics of what is fitted are those of
:mod:`lanterna.tiler.formats.pca_model` (docs/dataset-format.md).  A pixel's light samples
``x`` (``(n, 3)`` in 0–1, one row per acquisition light) become the basis's ``D`` samples: the
lights themselves (``rbf``, ``D = n``) or resampled onto the ``R × R`` octahedral grid
(``bilinear``, :func:`resample_matrix`), in YCoCg for ``mycc`` (:data:`RGB_TO_YCC`).  A PCA of
a bounded sample of pixels (:mod:`.pca_sample`) gives the mean and ``N`` eigenvectors, stored
as Relight's bytes (:func:`quantise_basis`); every pixel is then projected onto the stored basis
(:meth:`PcaFit.coefficients`) and its coefficients quantised per plane by the sample's
central :data:`RANGE_QUANTILE` (Relight's ``minmaxMaterial``).  Facts from Relight's
``rtibuilder.cpp`` (``pickBasePCA``, ``minmaxMaterial``, ``buildResampleMap``), written here.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from lanterna.errors import LanternaInputError
from lanterna.tiler.formats.pca_model import (
    MAX_PCA_PLANES,
    PCA_COLORSPACES,
    PCA_TYPES,
    YCC_TO_RGB,
    PcaBasis,
    bilinear_weights,
    plane_channels,
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
            d2 = np.sum((dirs - g) ** 2, axis=1)
            w = np.exp(-(d2 - d2.min()) / sigma ** 2)
            w /= w.sum()
            w = np.where(w > RESAMPLE_DROP, w, 0.0)
            b[x + y * res] = w / w.sum()
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


@dataclass(frozen=True)
class Moments:
    """The mean ``(n·3,)`` and covariance ``(n·3, n·3)`` of a pixel sample's light samples.

    Every basis of a fit is learnt from these (computed once): the samples of a basis are a
    linear map ``T`` of the light samples, so their mean is ``T·m`` and covariance ``T·C·Tᵀ``;
    the leave-one-out basis takes the rows and columns of the training lights.
    """

    mean: F64
    cov: F64

    @classmethod
    def of(cls, pixels: npt.ArrayLike) -> Moments:
        """The moments of pixels ``(S, n, 3)`` (the product in float32, the result float64)."""
        x = np.asarray(pixels, np.float32)
        flat = x.reshape(len(x), -1)
        mean = flat.mean(axis=0, dtype=np.float64)
        centred = flat - mean.astype(np.float32)
        cov = (centred.T @ centred).astype(np.float64) / max(1, len(flat))
        return cls(mean, cov)

    def restrict(self, lights: npt.NDArray[np.intp]) -> Moments:
        """The moments of the light samples of ``lights`` only."""
        cols = (np.asarray(lights)[:, None] * 3 + np.arange(3)).reshape(-1)
        return Moments(self.mean[cols], self.cov[np.ix_(cols, cols)])


def _top_eigenvectors(cov: F64, count: int) -> F64:
    """The ``count`` leading unit eigenvectors ``(count, dim)`` of a covariance."""
    if count == 0:
        return np.zeros((0, cov.shape[0]))
    vals, vecs = np.linalg.eigh(cov)
    top = vecs[:, np.argsort(vals)[::-1][:count]].T
    # a deterministic sign: the largest-magnitude entry of each eigenvector positive
    signs = np.sign(top[np.arange(count), np.argmax(np.abs(top), axis=1)])
    out: F64 = top * np.where(signs == 0, 1.0, signs)[:, None]
    return out


def learn_basis(moments: Moments, transform: F64, spec: PcaSpec) -> tuple[F64, F64]:
    """PCA of the basis samples ``T·x``: the mean ``(D, 3)`` and eigenvectors ``(N, D, 3)``.

    ``mrgb``: one PCA over all ``3·D`` values.  ``mycc``: one per YCC channel with
    ``yccplanes`` planes each, placed as Relight interleaves them (:func:`plane_channels`).
    """
    d = transform.shape[0] // 3
    mean = (transform @ moments.mean).reshape(d, 3)
    cov = transform @ moments.cov @ transform.T
    if spec.colorspace == "mrgb":
        return mean, _top_eigenvectors(cov, spec.nplanes).reshape(-1, d, 3)
    channels = plane_channels("mycc", spec.nplanes, spec.yccplanes)
    eig = np.zeros((spec.nplanes, d, 3))
    for k in range(3):
        planes = [q for q, c in enumerate(channels) if c == k]
        idx = np.arange(d) * 3 + k
        for q, v in zip(planes, _top_eigenvectors(cov[np.ix_(idx, idx)], len(planes)),
                        strict=True):
            eig[q, :, k] = v
    return mean, eig


def quantise_basis(mean: F64, eig: F64) -> tuple[npt.NDArray[np.uint8], tuple[float, ...]]:
    """Relight's basis bytes (mean ``255·m``, planes ``127 + range·e``) and ``range`` per plane.

    ``range = 127/max|e|`` (a plane that is all zero keeps range 127).
    """
    peak = np.abs(eig).reshape(len(eig), -1).max(axis=1) if len(eig) else np.zeros(0)
    ranges = 127.0 / np.where(peak > 0, peak, 1.0)
    rows = [np.clip(np.rint(mean * 255.0), 0, 255)]
    rows += [np.clip(np.rint(127.0 + r * e), 0, 255) for r, e in zip(ranges, eig, strict=True)]
    return np.stack(rows).astype(np.uint8).reshape(-1), tuple(float(r) for r in ranges)


def light_major(pixels: npt.ArrayLike) -> F32:
    """Light samples ``(n, P, 3)`` (a band's layout) as ``(n·3, P)`` float32 (row ``i·3 + k``)."""
    x = np.asarray(pixels, np.float32)
    n, p, _ = x.shape
    return np.ascontiguousarray(np.swapaxes(x, 1, 2)).reshape(n * 3, p)


@dataclass(frozen=True)
class PcaFit:
    """A learnt basis: the stored :class:`PcaBasis`, the projection and coefficient ranges.

    ``kernel`` ``(N, n·3)`` and ``offset`` ``(N,)`` map a pixel's light samples ``x`` (all the
    collection's lights; a leave-one-out basis has zero columns for the held-out ones) straight
    to its coefficients ``r = kernel·x − offset``: the resampling, the colour transform and the
    projection onto the stored basis, composed once.
    """

    basis: PcaBasis
    kernel: F32
    offset: F32
    lo: F64  # (N,) quantisation range of each plane
    hi: F64

    def coefficients(self, x: F32) -> F32:
        """Float coefficients ``(N, P)`` of light samples ``x`` ``(n·3, P)`` (light_major)."""
        out: F32 = self.kernel @ x - self.offset[:, None]
        return out

    def quantise(self, coefficients: F32) -> npt.NDArray[np.uint8]:
        """8-bit plane values ``t`` ``(P, N)`` of coefficients ``(N, P)``:
        ``r = (t/255 − bias)·scale``."""
        lo = self.lo.astype(np.float32)[:, None]
        gain = (np.float32(255.0) / (self.hi - self.lo).astype(np.float32))[:, None]
        t = np.rint((coefficients - lo) * gain)
        out: npt.NDArray[np.uint8] = np.clip(t, 0, 255).astype(np.uint8).T
        return out

    def scale_bias(self) -> tuple[list[float], list[float]]:
        """Per-plane ``scale``, ``bias`` (``r = (t/255 − bias)·scale``)."""
        scale = self.hi - self.lo
        return ([float(s) for s in scale],
                [float(-lo / s) for lo, s in zip(self.lo, scale, strict=True)])

    def weights(self, light: Sequence[float]) -> F32:
        """The RGB plane weights ``(N + 1, 3)`` of the stored basis for ``light``."""
        return self.basis.weights(float(light[0]), float(light[1])).astype(np.float32)


def fit_basis(pixels: npt.ArrayLike, lights: npt.ArrayLike, spec: PcaSpec, *,
              use: npt.NDArray[np.intp] | None = None,
              moments: Moments | None = None) -> PcaFit:
    """Learn ``spec``'s basis from sampled pixels ``(S, n, 3)`` (0–1) lit by ``lights`` ``(n, 3)``.

    ``use`` restricts the basis to those lights (the leave-one-out basis: the others are
    neither in its PCA nor among its RBF lights or bilinear resampling); ``moments`` are the
    sample's, when already computed.  The coefficients are the least-squares projection onto
    the *stored* (quantised) basis and mean, so the bytes' rounding is compensated where it
    can be; their quantisation range is the central :data:`RANGE_QUANTILE` of the sample's.
    """
    x = np.asarray(pixels, np.float32)
    n = x.shape[1]
    use = np.arange(n) if use is None else np.asarray(use, np.intp)
    stats = (moments or Moments.of(x)).restrict(use)
    dirs = np.asarray(lights, np.float64).reshape(-1, 3)[use]
    dirs = dirs / np.linalg.norm(dirs, axis=1, keepdims=True)
    resample = (resample_matrix(dirs, spec.resolution, spec.sigma)
                if spec.layer_type == "bilinear" else None)
    transform = sample_transform(spec, len(dirs), resample)
    mean, eig = learn_basis(stats, transform, spec)
    data, ranges = quantise_basis(mean, eig)
    rbf = spec.layer_type == "rbf"
    basis = PcaBasis(spec.layer_type, spec.colorspace, data, ranges,
                     tuple(float(v) for v in dirs.reshape(-1)) if rbf else None,
                     spec.sigma if rbf else None, None if rbf else spec.resolution,
                     spec.yccplanes)
    values = basis.values()  # (N + 1, D, 3) as stored
    projection = np.linalg.pinv(values[1:].reshape(spec.nplanes, -1).T)  # (N, D·3)
    kernel = np.zeros((spec.nplanes, 3 * n))
    cols = (use[:, None] * 3 + np.arange(3)).reshape(-1)
    kernel[:, cols] = projection @ transform
    offset = projection @ values[0].reshape(-1)
    fit = PcaFit(basis, kernel.astype(np.float32), offset.astype(np.float32),
                 np.zeros(spec.nplanes), np.ones(spec.nplanes))
    coeffs = fit.coefficients(light_major(np.swapaxes(x, 0, 1))).astype(np.float64)
    tail = (1.0 - RANGE_QUANTILE) / 2.0
    lo = np.quantile(coeffs, tail, axis=1)
    hi = np.quantile(coeffs, 1.0 - tail, axis=1)
    hi = np.where(hi - lo > 1e-6, hi, lo + 1e-6)
    return PcaFit(basis, fit.kernel, fit.offset, lo, hi)
