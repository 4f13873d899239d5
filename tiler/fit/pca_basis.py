"""PCA bases, learnt: the sample's moments, the eigenvectors as Relight's bytes, the projection.

The maths of :mod:`.pca` (which says what is fitted) on arrays: :class:`Moments` of a pixel
sample, :func:`learn_basis` (one PCA, or one per YCoCg channel), :func:`quantise_basis`
(Relight's ``127 + range·e``) and :func:`fit_basis`, whose :class:`PcaFit` projects light
samples onto the stored basis and quantises the coefficients.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from lanterna.tiler.formats.pca_model import PcaBasis, plane_channels

from .pca import RANGE_QUANTILE, PcaSpec, resample_matrix, sample_transform

F64 = npt.NDArray[np.float64]
F32 = npt.NDArray[np.float32]


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

    def quantisation(self) -> tuple[F32, F32]:
        """The float32 ``lo`` and ``gain`` per plane of :meth:`quantise`."""
        lo = self.lo.astype(np.float32)
        gain: F32 = np.float32(255.0) / (self.hi - self.lo).astype(np.float32)
        return lo, gain

    def quantise(self, coefficients: F32) -> npt.NDArray[np.uint8]:
        """8-bit plane values ``t`` ``(P, N)`` of coefficients ``(N, P)``:
        ``r = (t/255 − bias)·scale`` (the numpy reference of the compiled
        :func:`~lanterna.tiler.fit.pca_kernel.quantise_planes`)."""
        lo, gain = (a[:, None] for a in self.quantisation())
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
