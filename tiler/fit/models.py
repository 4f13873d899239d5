"""Fit relightable layers (PTM, HSH, normals, Lambert + Ward) to a multi-light collection.

The library API on a whole stack (in memory, or a :class:`StackReader` read in bands): one
function per model returning its model object, the table of models (:func:`model_table`) and
the leave-one-out report (:func:`leave_one_out`).  ``lanterna fit`` runs them through the
streaming engine (:mod:`~lanterna.tiler.fit.engine`, :mod:`~lanterna.tiler.fit.run`), built on
the same per-band solvers (:mod:`~lanterna.tiler.fit.bands`).  See ``docs/fitting.md``.
"""

from __future__ import annotations

import tempfile
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import numpy.typing as npt

from lanterna.errors import LanternaInputError
from lanterna.tiler.formats.hsh_model import HSH_TERMS
from lanterna.tiler.formats.ptm_model import Ptm
from lanterna.tiler.inputs.stack import StackReader

from .bands import normals_band, ptm_rgb_band
from .engine import fit_stream
from .hsh import fit_hsh
from .normals import RANK_WINDOW, SHADOW_FRACTION, check_lights
from .pca import PCA_LABELS, PcaSpec, parse_spec
from .pca_band import fit_pca, pca_models
from .ptm import fit_ptm_lrgb, ptm_design_matrix, ptm_pinv, quantize_coefficients
from .row_bands import auto_band_rows
from .spill_codes import round_trip
from .ward import Ward, fit_ward, quantize_ward

Stack = npt.NDArray[np.float32]
#: An in-memory stack or one read from disk in row bands.
Images = Stack | StackReader
Lights = npt.NDArray[np.float64]

#: Every ``HOLDOUT_EVERY``-th light (starting with the first) is held out for the report.
HOLDOUT_EVERY = 10


@dataclass(frozen=True)
class Normals:
    """Unit normals ``(H, W, 3)`` (x right, y up, z toward the camera) and Lambert albedo."""

    normals: npt.NDArray[np.float32]
    albedo: npt.NDArray[np.float32]


def fit_normals(images: Images, lights: Lights, *, rank_window: tuple[float, float] = RANK_WINDOW,
                shadow: float = SHADOW_FRACTION, iterations: int = 0,
                band_rows: int = 64) -> Normals:
    """Estimate normals by robust photometric stereo (Woodham with per-pixel sample selection).

    Per pixel, on the luminance ``Y`` of the ``N`` samples: keep the samples whose rank lies in
    ``[lo·N, hi·N)`` (``rank_window``; drops the darkest quarter — shadows, grazing light —
    and the brightest tenth — highlights) and that are brighter than ``shadow`` × the pixel's
    maximum; solve ``g = argmin Σ (Y_i − g·l_i)²`` over them; ``n = g/|g|``, flipped so
    ``n_z ≥ 0``.  Pixels with fewer than 3 kept samples use every non-shadowed sample.  The
    albedo is the per-channel least-squares factor ``Σ I·s / Σ s²`` with ``s = max(0, n·l)``
    over the same samples.  ``iterations > 0`` then refines every pixel by Tukey IRLS over the
    kept samples (:func:`~lanterna.tiler.fit.normals.solve_normals_band`; for linear light).

    Parameters
    ----------
    images : ndarray, shape (N, H, W, 3)
        Float in 0–1.
    lights : ndarray, shape (N, 3)
        Unit light directions; at least 3, not coplanar.
    """
    n, h, w, _ = images.shape
    if lights.shape != (n, 3):
        raise ValueError(f"{n} images but lights of shape {lights.shape}")
    check_lights(lights)
    normals = np.empty((h, w, 3), np.float32)
    albedo = np.empty((h, w, 3), np.float32)
    for y0 in range(0, h, band_rows):
        out = normals_band(images[:, y0:y0 + band_rows], lights, rank_window=rank_window,
                           shadow=shadow, iterations=iterations)
        normals[y0:y0 + band_rows] = out["normals"]
        albedo[y0:y0 + band_rows] = out["albedo"]
    return Normals(normals, albedo)


def fit_ptm_rgb(images: Images, lights: Lights, *, band_rows: int = 64) -> Ptm:
    """Fit an RGB PTM (six coefficients per channel) by least squares, pseudo-inverse once.

    Coefficients are in 0–255 units and quantised by
    :func:`~lanterna.tiler.fit.ptm.quantize_coefficients` (one scale/bias per term).
    """
    basis = ptm_design_matrix(lights)
    n, h, w, _ = images.shape
    if basis.shape[0] != n:
        raise ValueError(f"{n} images but {basis.shape[0]} lights")
    pinv = (ptm_pinv(basis) * 255.0).astype(np.float32)  # (6, N)
    coeffs = np.empty((h, w, 3, 6), np.float32)
    for y0 in range(0, h, band_rows):
        coeffs[y0:y0 + band_rows] = ptm_rgb_band(images[:, y0:y0 + band_rows], pinv)["coeffs"]
    q, scale, bias = quantize_coefficients(coeffs, held=round_trip(coeffs))
    return Ptm(colorspace="rgb", coefficients=q, scale=scale, bias=bias)


@dataclass(frozen=True)
class Model:
    """One fittable model: its CLI name, layer id, label and in-memory fit function.

    ``key`` is its CLI name (a :data:`~lanterna.tiler.fit.engine.MODEL_KEYS` entry, or
    ``rbf``/``bilinear`` with their ``pca`` spec), ``terms`` the HSH term count.
    """

    key: str
    terms: int
    id: str
    label: str
    fit: Callable[[Images, Lights], Any]
    pca: PcaSpec | None = None


class _NormalsOnce:
    """:func:`fit_normals`, remembering the last few results by (stack, lights) object identity.

    So the ``normals`` and ``ward`` models of one table fit the normals once and write one
    normal map.  Holds its inputs, so an identity match cannot be a recycled ``id``.
    """

    def __init__(self, keep: int = 3, **fit_options: Any) -> None:
        self._keep = keep
        self._options = fit_options
        self._recent: list[tuple[Images, Lights, Normals]] = []

    def __call__(self, images: Images, lights: Lights) -> Normals:
        for seen_images, seen_lights, fitted in self._recent:
            if seen_images is images and seen_lights is lights:
                return fitted
        fitted = fit_normals(images, lights, **self._options)
        self._recent = [(images, lights, fitted), *self._recent][: self._keep]
        return fitted


def _fit_ward_model(normals: Callable[[Images, Lights], Normals], images: Images,
                    lights: Lights, **fit_options: Any) -> Ward:
    nrm = normals(images, lights).normals
    kd, ks, alpha = fit_ward(images, lights, nrm, **fit_options)
    return quantize_ward(nrm, kd, ks, alpha)


def model_table(terms: int = 9, band_rows: int | None = None, *, planes: object = None,
                colorspace: object = None) -> dict[str, Model]:
    """Return the fittable models by CLI name (``hsh`` with ``terms`` terms).

    ``band_rows`` (default: each fitter's own) is the number of image rows every fitter
    reads and solves at once, so with a :class:`StackReader` the rows held in memory.
    ``planes`` and ``colorspace`` (``--planes``, ``--colorspace``) shape the PCA bases
    ``rbf`` and ``bilinear`` (:func:`~lanterna.tiler.fit.pca.parse_spec`).
    """
    if terms not in HSH_TERMS:
        raise LanternaInputError(None, f"--terms must be 4, 9 or 16, got {terms}")
    if band_rows is not None and band_rows < 1:
        raise LanternaInputError(None, f"band rows must be at least 1, got {band_rows}")
    kw: dict[str, Any] = {} if band_rows is None else {"band_rows": band_rows}
    normals = _NormalsOnce(**kw)
    return {
        "ptm": Model("ptm", terms, "ptm", "PTM RGB (fitted)",
                     lambda s, lt: fit_ptm_rgb(s, lt, **kw)),
        "ptm-lrgb": Model("ptm-lrgb", terms, "ptm_lrgb", "PTM LRGB (fitted)",
                          lambda s, lt: fit_ptm_lrgb(s, lt, **kw)),
        "hsh": Model("hsh", terms, f"hsh{terms}", f"HSH {terms} terms (fitted)",
                     lambda s, lt: fit_hsh(s, lt, terms, **kw)),
        "normals": Model("normals", terms, "normals", "Normals + albedo (photometric stereo)",
                         normals),
        "ward": Model("ward", terms, "ward", "Lambert + Ward (fitted)",
                      lambda s, lt: _fit_ward_model(normals, s, lt, **kw)),
        **{key: _pca_model(parse_spec(key, planes, colorspace), terms, kw)
           for key in PCA_LABELS},
    }


def _pca_model(spec: PcaSpec, terms: int, kw: dict[str, Any]) -> Model:
    label = (f"{PCA_LABELS[spec.layer_type]} {spec.nplanes} planes, {spec.colorspace} "
             "(fitted)")
    return Model(spec.layer_type, terms, spec.layer_type, label,
                 lambda s, lt: fit_pca(s, lt, spec, **kw), spec)


def _held(n: int, every: int) -> npt.NDArray[np.intp]:
    """The held-out lights of :func:`~lanterna.tiler.fit.engine.fit_stream`'s report."""
    return np.arange(0, n, every) if every else np.zeros(0, np.intp)


def psnr(predicted: Stack, actual: Stack) -> float:
    """Return the PSNR in dB of ``predicted`` against ``actual`` (both 0–1)."""
    mse = float(np.mean((predicted.astype(np.float64) - actual.astype(np.float64)) ** 2))
    return float("inf") if mse == 0.0 else 10.0 * float(np.log10(1.0 / mse))


def leave_one_out(images: Images, lights: Lights, model: Model,
                  every: int = HOLDOUT_EVERY, band_rows: int | None = None) -> dict[str, Any]:
    """Fit ``model`` without every ``every``-th light and return the PSNR on the held-out ones.

    The report of :func:`~lanterna.tiler.fit.engine.fit_stream` (what ``lanterna fit``
    stores) without writing the layer: one streamed pass, predictions from the float fit.
    Returns ``{"heldOut": [indices], "psnr": [dB per held-out light], "meanPsnr",
    "medianPsnr"}``.
    """
    with tempfile.TemporaryDirectory(prefix="lanterna-loo-") as scratch:
        keys, extra = [model.key], []
        if model.pca is not None:
            n, _, w, _ = images.shape
            keys, extra = [], pca_models(images, lights, [model.pca], _held(n, every),
                                         Path(scratch), band_rows=band_rows or
                                         auto_band_rows(n, w), layers=False)
        result = fit_stream(images, lights, keys, Path(scratch), terms=model.terms,
                            band_rows=band_rows, holdout_every=every, layers=False,
                            extra=extra)
    return result.quality[model.key]
