"""A PCA basis (rbf, bilinear) as a model of the streamed fit: its per-band step and its planes.

:func:`prepare_pca` learns the layer's basis and, for the leave-one-out report, a second basis
without the held-out lights (learnt from the same pixel sample restricted to the training
lights: the PCA never sees a held-out image, and the RBF interpolates only the training
lights; bilinear resamples only them onto its grid).  The engine
(:func:`~lanterna.tiler.fit.engine.fit_stream`, ``extra=``) then runs :class:`PcaStep` on every
band — the projection onto the basis, 8-bit per plane — and hands the planes to
:class:`PcaModel`, which writes them to file-backed groups ``p0, p1, …`` of three planes.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import numpy.typing as npt
from threadpoolctl import threadpool_limits

from lanterna.tiler.formats.pca_model import plane_channel_names
from lanterna.tiler.formats.planes import PlaneGroup, PlaneLayer
from lanterna.tiler.formats.strip_tiff import StripTiffWriter
from lanterna.tiler.progress import Progress

from .pca import PcaSpec
from .pca_basis import Moments, PcaFit, fit_basis
from .pca_kernel import light_major, quantise_planes
from .pca_sample import sample_pixels
from .row_bands import sub_band_rows

Out = dict[str, npt.NDArray[np.generic]]


def band_planes(fit: PcaFit, x: npt.NDArray[np.float32], out: npt.NDArray[np.uint8],
                p0: int = 0) -> None:
    """Write the 8-bit planes of light samples ``x`` ``(n·3, P)`` into pixels ``p0:p0 + P`` of
    ``out`` ``(groups, pixels, 3)`` (the planes past ``N`` of the last group are 0):
    :meth:`PcaFit.quantise`'s bytes."""
    lo32, gain32 = fit.quantisation()
    quantise_planes(fit.coefficients(x), lo32, gain32, out, p0)


@dataclass
class PcaStep:
    """One band ``(n, b, W, 3)`` → its 8-bit planes and the held-out squared errors.

    Picklable (arrays and the fitted bases only), so a Dask worker can run it.  The held-out
    lights' plane weights of the leave-one-out basis are stacked once (``held_weights``
    ``(h·3, N + 1)``), so a band's predictions at every held-out light are one product.
    """

    key: str
    full: PcaFit
    loo: PcaFit | None
    held: npt.NDArray[np.intp]
    held_weights: npt.NDArray[np.float32]
    layers: bool = True

    def __call__(self, band: npt.NDArray[np.generic], div: float = 1.0
                 ) -> tuple[Out | None, npt.NDArray[np.float64]]:
        """Planes and held-out errors of ``band`` ``(n, b, W, 3)``: float32 in 0–1 (``div`` 1)
        or as decoded (``div`` 255/65535), projected in the engine's float sub-bands
        (:func:`~.row_bands.sub_band_rows`), made light-major in one reused buffer."""
        n, b, w, _ = band.shape
        pixels = np.ascontiguousarray(band).reshape(n, b * w, 3)
        groups = -(-self.full.basis.nplanes // 3)
        planes = np.empty((groups, b * w if self.layers else 0, 3), np.uint8)
        sse = np.zeros(len(self.held))
        step = w * sub_band_rows(n, w)
        buffer = np.empty(3 * n * min(step, b * w), np.float32)
        for p0 in range(0, b * w, step):
            p1 = min(b * w, p0 + step)
            x = light_major(pixels, div, slice(p0, p1), buffer[:3 * n * (p1 - p0)].reshape(
                3 * n, p1 - p0))
            if self.layers:
                band_planes(self.full, x, planes, p0)
            if self.loo is not None and len(self.held):
                coeffs = self.loo.coefficients(x)
                pred = self.held_weights[:, 1:] @ coeffs
                pred += self.held_weights[:, :1]
                np.clip(pred, 0.0, 1.0, out=pred)
                pred -= x[(self.held[:, None] * 3 + np.arange(3)).reshape(-1)]
                sse += np.einsum("ij,ij->i", pred, pred, dtype=np.float64).reshape(-1, 3).sum(1)
        return ({"planes": planes.reshape(groups, b, w, 3)} if self.layers else None), sse


class PcaModel:
    """The engine's handle on one PCA layer: the :class:`PcaStep` and where its planes go."""

    def __init__(self, step: PcaStep, scratch: Path, width: int, height: int) -> None:
        self.key, self.step = step.key, step
        self.groups = -(-step.full.basis.nplanes // 3)
        self.writers = [StripTiffWriter(Path(scratch) / f"{step.key}-p{g}.tif", width, height, 3)
                        for g in range(self.groups)] if step.layers else []

    def take(self, out: Out) -> None:
        """Write one band's planes ``(groups, b, W, 3)``."""
        for g, writer in enumerate(self.writers):
            writer.write(out["planes"][g])

    def finish(self, progress: Callable[[str, int], Progress] | None = None) -> PlaneLayer:
        """The fitted layer: ``p0, p1, …`` groups (padding channels of scale 0), the basis."""
        fit = self.step.full
        scale, bias = fit.scale_bias()
        n = fit.basis.nplanes
        groups = []
        for g, (names, writer) in enumerate(zip(plane_channel_names(n), self.writers,
                                                strict=True)):
            qs = range(3 * g, 3 * g + 3)
            groups.append(PlaneGroup(names, writer.close(),
                                     [scale[q] if q < n else 0.0 for q in qs],
                                     [bias[q] if q < n else 0.0 for q in qs]))
        return PlaneLayer(fit.basis.layer_type, groups, colorspace=fit.basis.colorspace,
                          pca=fit.basis,
                          group_names=[f"p{g}" for g in range(self.groups)])


def prepare_pca(spec: PcaSpec, sample: npt.NDArray[np.float32], lights: npt.NDArray[np.float64],
                held: npt.NDArray[np.intp], scratch: Path, width: int, height: int, *,
                layers: bool = True) -> PcaModel:
    """Learn ``spec``'s bases from the pixel ``sample`` ``(S, n, 3)`` and make its model.

    Raises
    ------
    ValueError
        When the lights cannot carry the basis (fewer lights than planes for ``rbf``).
    """
    n = len(lights)
    dims = n if spec.layer_type == "rbf" else spec.resolution ** 2
    if spec.nplanes > 3 * dims:
        raise ValueError(f"{spec.layer_type}: {spec.nplanes} planes need at least "
                         f"{-(-spec.nplanes // 3)} light samples, got {dims}")
    train = np.setdiff1d(np.arange(n), held)
    moments = Moments.of(sample)
    full = fit_basis(sample, lights, spec, moments=moments)
    loo = fit_basis(sample, lights, spec, use=train, moments=moments) if len(held) else None
    weights = (np.concatenate([loo.weights(lights[i]).T for i in held])
               if loo is not None and len(held) else np.zeros((0, spec.nplanes + 1), np.float32))
    step = PcaStep(spec.layer_type, full, loo, np.asarray(held, np.intp), weights, layers)
    return PcaModel(step, scratch, width, height)


def pca_models(images: Any, lights: npt.NDArray[np.float64], specs: Sequence[PcaSpec],
               held: npt.NDArray[np.intp], scratch: Path, *, band_rows: int,
               layers: bool = True, progress: Callable[[str, int], Progress] | None = None
               ) -> list[PcaModel]:
    """The models of ``specs`` for one stack: one sampling pass (:mod:`.pca_sample`) for all."""
    if not specs:
        return []
    _, h, w, _ = images.shape
    # one BLAS thread, as in the fit's pass: the basis's products are small, and OpenBLAS's
    # idle threads spin after a threaded call — measured 6 % of the CPU of a 2048² rbf fit,
    # taken from the decode of the pass that follows
    with threadpool_limits(limits=1, user_api="blas"):
        sample = sample_pixels(images, band_rows, progress=progress)
        return [prepare_pca(spec, sample, lights, held, scratch, w, h, layers=layers)
                for spec in specs]


def fit_pca(images: Any, lights: npt.NDArray[np.float64], spec: PcaSpec, *,
            band_rows: int = 64) -> tuple[PcaFit, npt.NDArray[np.uint8]]:
    """Fit ``spec`` to a whole stack in memory: the basis and the 8-bit planes ``(H, W, N)``.

    The library form of what ``lanterna fit --model rbf|bilinear`` streams (same sample, same
    basis, same bytes, whatever ``band_rows``).
    """
    n, h, w, _ = images.shape
    if lights.shape != (n, 3):
        raise ValueError(f"{n} images but lights of shape {lights.shape}")
    sample = sample_pixels(images, band_rows)
    full = fit_basis(sample, lights, spec)
    planes = np.empty((h, w, spec.nplanes), np.uint8)
    groups = np.empty((-(-spec.nplanes // 3), band_rows * w, 3), np.uint8)
    for y0 in range(0, h, band_rows):
        band = np.asarray(images[:, y0:y0 + band_rows], np.float32)
        rows = band.shape[1]
        band_planes(full, light_major(band.reshape(n, rows * w, 3)), groups)
        pixel_major = np.moveaxis(groups[:, :rows * w], 0, 1).reshape(rows * w, -1)
        planes[y0:y0 + rows] = pixel_major[:, :spec.nplanes].reshape(rows, w, -1)
    return full, planes
