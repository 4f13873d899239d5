"""Fit relightable layers (PTM, HSH, normals, Lambert + Ward) to a multi-light collection.

One load of the images serves every requested model.  Each model is a row of :data:`MODELS`:
how to fit it and how to predict an image under a new light, so the leave-one-out quality
report (:func:`leave_one_out`) treats them alike.  See ``docs/fitting.md``.
"""

from __future__ import annotations

import hashlib
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import numpy.typing as npt

from .dataset import DEFAULT_BASE_URL
from .errors import LanternaInputError
from .fit_bands import RANK_WINDOW, SHADOW_FRACTION, normals_band, ptm_rgb_band
from .hsh_basis import hsh_weights
from .hsh_fit import fit_hsh
from .hsh_model import HSH_TERMS, Hsh
from .layers import add_hsh_layer, add_ptm_layer, add_svbrdf_layer, encode_normals
from .lp import read_lp
from .plans import LayerPlan, build_dataset
from .ptm_fit import fit_ptm_lrgb, ptm_design_matrix, quantize_coefficients
from .ptm_model import Ptm
from .stack import StackReader
from .ward_fit import Ward, fit_ward, predict_ward, quantize_ward

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
                shadow: float = SHADOW_FRACTION, band_rows: int = 64) -> Normals:
    """Estimate normals by robust photometric stereo (Woodham with per-pixel sample selection).

    Per pixel, on the luminance ``Y`` of the ``N`` samples: keep the samples whose rank lies in
    ``[lo·N, hi·N)`` (``rank_window``; drops the darkest quarter — shadows, grazing light —
    and the brightest tenth — highlights) and that are brighter than ``shadow`` × the pixel's
    maximum; solve ``g = argmin Σ (Y_i − g·l_i)²`` over them; ``n = g/|g|``, flipped so
    ``n_z ≥ 0``.  Pixels with fewer than 3 kept samples use every non-shadowed sample.  The
    albedo is the per-channel least-squares factor ``Σ I·s / Σ s²`` with ``s = max(0, n·l)``
    over the same samples.

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
    if n < 3 or np.linalg.matrix_rank(lights) < 3:
        raise ValueError("photometric stereo needs at least 3 non-coplanar lights")
    normals = np.empty((h, w, 3), np.float32)
    albedo = np.empty((h, w, 3), np.float32)
    for y0 in range(0, h, band_rows):
        out = normals_band(images[:, y0:y0 + band_rows], lights, rank_window=rank_window,
                           shadow=shadow)
        normals[y0:y0 + band_rows] = out["normals"]
        albedo[y0:y0 + band_rows] = out["albedo"]
    return Normals(normals, albedo)


def fit_ptm_rgb(images: Images, lights: Lights, *, band_rows: int = 64) -> Ptm:
    """Fit an RGB PTM (six coefficients per channel) by least squares, pseudo-inverse once.

    Coefficients are in 0–255 units and quantised by
    :func:`~lanterna.tiler.ptm_fit.quantize_coefficients` (one scale/bias per term).
    """
    basis = ptm_design_matrix(lights)
    n, h, w, _ = images.shape
    if basis.shape[0] != n:
        raise ValueError(f"{n} images but {basis.shape[0]} lights")
    if n < 6 or np.linalg.matrix_rank(basis) < 6:
        raise ValueError("the light directions do not determine the 6 PTM terms")
    pinv = (np.linalg.pinv(basis) * 255.0).astype(np.float32)  # (6, N)
    coeffs = np.empty((h, w, 3, 6), np.float32)
    for y0 in range(0, h, band_rows):
        coeffs[y0:y0 + band_rows] = ptm_rgb_band(images[:, y0:y0 + band_rows], pinv)["coeffs"]
    q, scale, bias = quantize_coefficients(coeffs)
    return Ptm(colorspace="rgb", coefficients=q, scale=scale, bias=bias)


def predict_normals(model: Normals, light: npt.NDArray[np.float64]) -> Stack:
    """Return the Lambert image ``albedo · max(0, n·l)`` under unit ``light``, clipped to 0–1."""
    shade = np.maximum(model.normals @ light.astype(np.float32), 0.0)
    out: Stack = np.clip(model.albedo * shade[..., None], 0.0, 1.0)
    return out


def predict_ptm(model: Ptm, light: npt.NDArray[np.float64]) -> Stack:
    """Return the (quantised) PTM relit under unit ``light``, 0–1."""
    return model.relight(float(light[0]), float(light[1]))


def predict_hsh(model: Hsh, light: npt.NDArray[np.float64]) -> Stack:
    """Return the (quantised) HSH relit under unit ``light``, clipped to 0–1."""
    wts = hsh_weights(float(light[0]), float(light[1]), model.terms)
    out: Stack = np.clip(model.dequantized() @ wts, 0.0, 1.0).astype(np.float32)
    return out


@dataclass(frozen=True)
class Model:
    """One fittable model: its layer id, label, fit and predict functions, and its layer."""

    id: str
    label: str
    fit: Callable[[Images, Lights], Any]
    predict: Callable[[Any, npt.NDArray[np.float64]], Stack]
    plan: Callable[[Any, str, str, str], LayerPlan]


def _ptm_plan(ptm: Ptm, lid: str, label: str, source: str) -> LayerPlan:
    return LayerPlan(lid, label, ptm.width, ptm.height, source,
                     lambda ds: add_ptm_layer(ds, ptm, layer_id=lid, label=label))


def _hsh_plan(hsh: Hsh, lid: str, label: str, source: str) -> LayerPlan:
    return LayerPlan(lid, label, hsh.width, hsh.height, source,
                     lambda ds: add_hsh_layer(ds, hsh, layer_id=lid, label=label))


def _normals_key(encoded: npt.NDArray[np.uint8]) -> dict[str, str]:
    # identical encoded normal maps (normals + ward layers of one run) are stored once
    return {"normals": "fitted-normals-" + hashlib.sha1(encoded.tobytes()).hexdigest()}


def _normals_plan(model: Normals, lid: str, label: str, source: str) -> LayerPlan:
    encoded = encode_normals(model.normals)
    h, w = encoded.shape[:2]
    share = _normals_key(encoded)
    return LayerPlan(lid, label, w, h, source,
                     lambda ds: add_svbrdf_layer(ds, normals=encoded, share=share,
                                                 layer_id=lid, label=label))


def _ward_plan(model: Ward, lid: str, label: str, source: str) -> LayerPlan:
    encoded = encode_normals(model.normals)
    h, w = encoded.shape[:2]
    share = _normals_key(encoded)
    return LayerPlan(lid, label, w, h, source,
                     lambda ds: add_svbrdf_layer(ds, normals=encoded, kd=model.kd, ks=model.ks,
                                                 gloss=model.gloss,
                                                 gloss_limits=model.gloss_limits,
                                                 input_colorspace="linear", share=share,
                                                 layer_id=lid, label=label))


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


def model_table(terms: int = 9, band_rows: int | None = None) -> dict[str, Model]:
    """Return the fittable models by CLI name (``hsh`` with ``terms`` terms).

    ``band_rows`` (default: each fitter's own) is the number of image rows every fitter
    reads and solves at once, so with a :class:`StackReader` the rows held in memory.
    """
    if terms not in HSH_TERMS:
        raise LanternaInputError(None, f"--terms must be 4, 9 or 16, got {terms}")
    if band_rows is not None and band_rows < 1:
        raise LanternaInputError(None, f"band rows must be at least 1, got {band_rows}")
    kw: dict[str, Any] = {} if band_rows is None else {"band_rows": band_rows}
    normals = _NormalsOnce(**kw)
    return {
        "ptm": Model("ptm", "PTM RGB (fitted)", lambda s, lt: fit_ptm_rgb(s, lt, **kw),
                     predict_ptm, _ptm_plan),
        "ptm-lrgb": Model("ptm_lrgb", "PTM LRGB (fitted)",
                          lambda s, lt: fit_ptm_lrgb(s, lt, **kw), predict_ptm, _ptm_plan),
        "hsh": Model(f"hsh{terms}", f"HSH {terms} terms (fitted)",
                     lambda s, lt: fit_hsh(s, lt, terms, **kw), predict_hsh, _hsh_plan),
        "normals": Model("normals", "Normals (robust photometric stereo)", normals,
                         predict_normals, _normals_plan),
        "ward": Model("ward", "Lambert + Ward (fitted)",
                      lambda s, lt: _fit_ward_model(normals, s, lt, **kw), predict_ward,
                      _ward_plan),
    }


def psnr(predicted: Stack, actual: Stack) -> float:
    """Return the PSNR in dB of ``predicted`` against ``actual`` (both 0–1)."""
    mse = float(np.mean((predicted.astype(np.float64) - actual.astype(np.float64)) ** 2))
    return float("inf") if mse == 0.0 else 10.0 * float(np.log10(1.0 / mse))


def leave_one_out(images: Images, lights: Lights, model: Model,
                  every: int = HOLDOUT_EVERY) -> dict[str, Any]:
    """Fit ``model`` without every ``every``-th light and return the PSNR on the held-out ones.

    This is a second full fit (on a :class:`StackReader`, a second streamed pass over the
    training images) plus one whole held-out image and its prediction in memory at a time
    (``H·W·3`` float32 each): on huge images budget for those, or skip the report.

    Returns ``{"heldOut": [indices], "psnr": [dB per held-out light], "meanPsnr", "medianPsnr"}``.
    """
    held = np.arange(0, images.shape[0], every)
    train = np.setdiff1d(np.arange(images.shape[0]), held)
    fitted = model.fit(images[train], lights[train])
    scores = [psnr(model.predict(fitted, lights[i]), images[i]) for i in held]
    return {"heldOut": [int(i) for i in held], "psnr": [round(s, 3) for s in scores],
            "meanPsnr": round(float(np.mean(scores)), 3),
            "medianPsnr": round(float(np.median(scores)), 3)}


def fit_collection(images_dir: Path, lp: Path, models: Sequence[str], out: Path, *,
                   terms: int = 9, name: str | None = None, label: str | None = None,
                   base_url: str = DEFAULT_BASE_URL, tile_size: int = 256, force: bool = False,
                   band_rows: int | None = None,
                   report: Callable[[str], None] = lambda _: None) -> dict[str, Any]:
    """Fit ``models`` to the collection and write them as the layers of dataset ``out``.

    The images are streamed: a :class:`StackReader` checks their headers, then every fit
    reads them in bands of ``band_rows`` rows (default: each fitter's own, 32–64), so the
    input held in memory is ``O(N · band_rows · W)`` whatever the image height; the fitted
    float coefficients of the whole image are kept until the global quantisation.
    Everything is read and fitted before the dataset is written (atomically, by
    :func:`build_dataset`), so bad input leaves nothing behind.  Returns the quality report
    (also stored as ``quality`` in ``lanterna.json``).
    """
    table = model_table(terms, band_rows)
    unknown = [m for m in models if m not in table]
    if unknown or not models:
        raise LanternaInputError(None, f"unknown model(s) {', '.join(unknown) or '(none)'}; "
                                 f"expected {', '.join(table)}")
    files, lights = read_lp(lp, images_dir)
    report(f"streaming {len(files)} images from {images_dir}")
    stack = StackReader(files)
    source = f"{Path(images_dir).name} + {Path(lp).name}"
    held_every = HOLDOUT_EVERY if len(files) >= 2 * HOLDOUT_EVERY else 0
    quality: dict[str, Any] = {"protocol": f"fit without every {HOLDOUT_EVERY}th light "
                               "(from the first), PSNR of the prediction on those, RGB 0-1",
                               "models": {}}
    plans = []
    for key in dict.fromkeys(models):
        model = table[key]
        try:
            if held_every:
                q = leave_one_out(stack, lights, model, held_every)
                quality["models"][model.id] = q
                report(f"{model.id}: leave-one-out PSNR mean {q['meanPsnr']:.2f} dB, "
                       f"median {q['medianPsnr']:.2f} dB over {len(q['heldOut'])} lights")
            fitted = model.fit(stack, lights)
        except ValueError as err:
            raise LanternaInputError(lp, f"cannot fit {key}: {err}") from None
        plans.append(model.plan(fitted, model.id, model.label, source))
    build_dataset(plans, out, name=name or Path(out).name, label=label or Path(images_dir).name,
                  base_url=base_url, tile_size=tile_size, force=force, quality=quality)
    return quality
