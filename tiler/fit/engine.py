"""Fit every requested model in one streamed pass over a multi-light collection.

One pass reads the images top to bottom in bands of rows (:class:`~lanterna.tiler.inputs.stack.
StackReader`, kept 8-bit as decoded) and solves them in cache-sized float sub-bands, each
twice — on all lights (the layer) and without the held-out lights (the leave-one-out report,
accumulated as squared errors on the held-out images of the same rows; the linear models predict
them by one product, :func:`~.held_out.fused_rows`) — so the images are decoded once whatever
the number of models.

Memory is bounded by the band, not the image: each band's outputs go to file-backed planes or,
for the globally quantised PTM/HSH coefficients, to a spill of 16-bit codes per row quantised in
a second pass (:mod:`.sinks`, :mod:`.spill_codes`). The results are
:class:`~lanterna.tiler.formats.planes.PlaneLayer` s whose groups are those files.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterable, Iterator, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Protocol, cast

import numpy as np
import numpy.typing as npt
from threadpoolctl import threadpool_limits

from lanterna.tiler.formats.planes import PlaneLayer
from lanterna.tiler.formats.ptm_model import ptm_weights
from lanterna.tiler.inputs.stack import StackReader
from lanterna.tiler.progress import Progress
from lanterna.tiler.render.shading import linear_to_srgb

from . import bands as fb
from . import held_out as ho  # its REPORT_PIXELS read at call time (tests change it)
from .held_out import PREDICT, TwinStore, fused_rows, report
from .linear_kernel import linear_band_coded
from .lrgb_kernel import lrgb_band_held_out_compiled
from .normals_held_out_kernel import MAX_LIGHTS
from .row_bands import (
    BAND_BUDGET,
    SUB_BAND_BUDGET,
    WARD_BAND_BUDGET,
    Images,
    auto_band_rows,
    band_spans,
    read_bands,
    sub_band_rows,
)
from .sample_kernel import report_indices
from .sinks import Sinks
from .solver import Solver
from .sub_bands import SubBands
from .unit_kernel import to_unit_compiled

Lights = npt.NDArray[np.float64]

#: Models the engine fits, by CLI name.
MODEL_KEYS = ("ptm", "ptm-lrgb", "hsh", "normals", "ward")


#: Per band: the outputs of its parts in row order (the linear models' whole band first, then
#: each float sub-band's), or ``None`` without layers; the held-out squared errors per model; and
#: the pixels they were summed over per model.
_StepResult = tuple[list[dict[str, fb.Out]] | None, dict[str, npt.NDArray[np.float64]],
                    dict[str, int]]
#: Models solved by one compiled product over the band as stored (:mod:`.linear_kernel`).
LINEAR_KEYS = ("ptm", "hsh")
#: Models whose compiled kernels read a whole band as decoded (no float copy of it).
WHOLE_BAND_KEYS = (*LINEAR_KEYS, "ptm-lrgb")


@dataclass
class _Step:
    """Everything done to one band: the layer fit and the held-out squared errors.

    A picklable callable, so a Dask worker can run it on the band it reads.
    """

    full: Solver
    loo: Solver | None
    held: npt.NDArray[np.intp]
    train: npt.NDArray[np.intp]
    layers: bool
    #: key -> ``(h, N)`` rows predicting the held-out lights straight from the band's samples
    fused: dict[str, npt.NDArray[np.float32]] = field(default_factory=dict)
    extra: Sequence[Callable[[npt.NDArray[np.generic], float],
                             tuple[fb.Out | None, npt.NDArray[np.float64]]]] = ()
    extra_keys: Sequence[str] = ()
    #: the share of pixels the photometric models' twin is fitted on (held_out.report_sample)
    report_share: float = 1.0
    #: the sampled twin's pixels fitted together, up to this many (0: each band's alone, as a
    #: Dask worker must: its bands' results come back one by one); the rest by :meth:`flush`
    twin_batch: int = 0
    #: the sampled twin's pixels a pass is expected to keep at once (the first batch and a
    #: band's), the room :attr:`_kept` is made with (it grows if they are more)
    twin_room: int = 0
    #: the sub-band buffers, made where the step runs (never pickled)
    _buffers: SubBands = field(default_factory=SubBands, repr=False, compare=False)
    #: the sampled twin's pixels not fitted yet (with ``twin_batch``): ``_kept.pixels``
    _kept: TwinStore = field(default_factory=TwinStore, repr=False, compare=False)

    def __getstate__(self) -> dict[str, Any]:
        return {**self.__dict__, "_buffers": SubBands(), "_kept": TwinStore()}

    def __call__(self, band: npt.NDArray[np.generic], div: float = 1.0, y0: int = 0
                 ) -> _StepResult:
        """Solve ``band`` ``(N, b, W, 3)``, the image's rows from ``y0``: 0–1 float32
        (``div`` 1), or the samples as decoded (8/16-bit, ``div`` 255/65535)."""
        keys = self.full.keys
        _, b, w, _ = band.shape
        sse = {k: np.zeros(len(self.held)) for k in [*keys, *self.extra_keys]}
        pixels = {k: b * w for k in sse}
        parts: list[dict[str, fb.Out]] = []
        whole = [k for k in WHOLE_BAND_KEYS if k in keys]
        if whole or self.extra:
            outs = self._whole(band, div, whole, sse)
            for key, model in zip(self.extra_keys, self.extra, strict=True):
                out, sse[key] = model(band, div)
                if out is not None:
                    outs[key] = out
            parts.append(outs)
        rest = [k for k in keys if k not in WHOLE_BAND_KEYS]
        if rest:
            sampled = self.loo is not None and self.report_share < 1.0
            fused = self.loo is not None and rest == ["normals"] and not self.full.linear and \
                len(self.full.lights) <= MAX_LIGHTS and not sampled
            for r0, piece, d in self._pieces(band, div, rest, fused or sampled):
                if fused:  # the fit and its leave-one-out twin in one pass (the layer
                    # is made even for a report alone: it is a small part of the pass)
                    out, err = fb.normals_band_held_out(piece, self.full.lights, self.train,
                                                        self.held, d)
                    sse["normals"] += err
                    parts.append({"normals": out} if self.layers else {})
                    continue
                outs = self.full.solve(piece, rest, d) if self.layers else {}
                if sampled:  # the twin's pixels of these rows, fitted in batches
                    idx = report_indices(y0 + r0, piece.shape[1], w, self.report_share)
                    flat = np.ascontiguousarray(piece).reshape(piece.shape[0], -1, 3)
                    # kept as the piece is (as decoded: refitted so, by the kernels the layer's
                    # fit has loaded, with the same results as its floats)
                    self._kept.add(np.take(flat, idx, axis=1), self.twin_room, d)
                elif self.loo is not None:
                    floats = cast("npt.NDArray[np.float32]", piece)  # _pieces: floats here
                    for k, err in self._held_out(floats, self.loo, rest).items():
                        sse[k] += err
                parts.append(outs)
            if sampled and self.loo is not None:
                if self._kept.count >= self.twin_batch:
                    self._twin_errors(rest, sse, pixels)
                else:
                    pixels.update(dict.fromkeys(rest, 0))
        return (parts if self.layers else None), sse, pixels

    def flush(self) -> tuple[dict[str, npt.NDArray[np.float64]], dict[str, int]]:
        """The squared errors and pixels of the sampled twin's pixels not fitted yet."""
        rest = [k for k in self.full.keys if k not in WHOLE_BAND_KEYS]
        sse = {k: np.zeros(len(self.held)) for k in rest}
        pixels = dict.fromkeys(rest, 0)
        if self._kept.count and self.loo is not None:
            self._twin_errors(rest, sse, pixels)
        self._kept = TwinStore()  # the pass is over: its room freed
        return sse, pixels

    def _twin_errors(self, keys: Sequence[str], sse: dict[str, npt.NDArray[np.float64]],
                     pixels: dict[str, int]) -> None:
        """Fit the pending twin pixels as one ``(N, 1, pixels, 3)`` band: their squared errors
        added to ``sse``, their count set in ``pixels`` (fewer, longer calls than a band's
        few thousand pixels each: 25 bands of a 2048² Ward fit took 0.08 s so)."""
        twin = self._kept.pixels[:, None]
        assert self.loo is not None
        count = int(twin.shape[2])
        pixels.update(dict.fromkeys(keys, count))
        if count:
            for k, err in self._held_out(twin, self.loo, keys, self._kept.div).items():
                sse[k] += err
        self._kept.count = 0

    def _whole(self, band: npt.NDArray[np.generic], div: float, keys: Sequence[str],
               sse: dict[str, npt.NDArray[np.float64]]) -> dict[str, fb.Out]:
        """The models whose compiled kernels read the band as decoded, each in one pass over
        the whole band: PTM/HSH coefficients (coefficient-major, with their range, by
        :func:`~.linear_kernel.linear_band`), LRGB's, and their held-out errors."""
        n, b, w, c = band.shape
        flat = np.ascontiguousarray(band).reshape(n, -1)
        outs: dict[str, fb.Out] = {}
        if "ptm-lrgb" in keys:  # the layer and its report in one pass
            held_out = None
            if self.loo is not None:
                basis = np.stack([ptm_weights(float(lt[0]), float(lt[1])).astype(np.float32)
                                  for lt in self.full.lights[self.held]])
                held_out = (self.loo.pinv["ptm-lrgb"], self.train, self.held, basis)
            coeffs, rgb, err = lrgb_band_held_out_compiled(
                band, self.full.pinv["ptm-lrgb"] if self.layers else None,
                fb.LUMINANCE_WEIGHTS, div, held_out)
            if self.layers:
                outs["ptm-lrgb"] = {"coeffs": coeffs, "rgb": rgb}
            if held_out is not None:
                sse["ptm-lrgb"] = err
        for k in (k for k in keys if k in LINEAR_KEYS):
            rows = self.full.pinv[k] if self.layers else np.zeros((0, n), np.float32)
            held = self.fused.get(k) if self.loo is not None else None
            codes, row_lo, row_hi, err = linear_band_coded(flat, div, rows, w * c,
                                                           held_rows=held, held=self.held)
            if held is not None:
                sse[k] = err
            if self.layers:  # held until the global range is known: 16 bits a coefficient
                outs[k] = {"codes": codes, "rowLo": row_lo, "rowHi": row_hi,
                           "lo": row_lo.min(axis=1), "hi": row_hi.max(axis=1)}
        return outs

    def _pieces(self, band: npt.NDArray[np.generic], div: float, keys: Sequence[str],
                twin: bool) -> Iterator[tuple[int, npt.NDArray[np.generic], float]]:
        """The photometric models' pieces of ``band``: ``(r0, piece, d)`` with ``piece / d`` in
        0–1, each holding the budget's bytes of input as the kernel reads it.  An 8-/16-bit
        band's pieces stay as decoded (their kernels divide where they read, with the same
        results; a piece short of the whole band copied into one reused contiguous buffer) for
        a fit of the values as stored whose report, if any, is sampled (:meth:`_held_out`
        refits its sample as decoded); else they are float sub-bands
        (:class:`~.sub_bands.SubBands`; docs/fitting.md "Speed, thirteenth pass").  A piece
        as decoded holds 4 (8-bit) or 2 (16-bit) times a float sub-band's rows, the same
        bytes: at 8 bits a quarter of the calls, each with its Python steps and its threads'
        wake-ups ("Speed, sixteenth pass")."""
        n, _, w, _ = band.shape
        budget = WARD_BAND_BUDGET if "ward" in keys else SUB_BAND_BUDGET
        if not (band.dtype in (np.uint8, np.uint16) and div != 1.0 and not self.full.linear
                and (self.loo is None or twin)):
            for r0, piece in self._buffers.floats(band, div, sub_band_rows(n, w, budget)):
                yield r0, piece, 1.0
            return
        rows = sub_band_rows(n, w, budget * 4 // band.itemsize)  # it counts 4-byte samples
        yield from self._buffers.as_decoded(band, div, rows)

    def _held_out(self, band: npt.NDArray[np.generic], loo: Solver, keys: Sequence[str],
                  div: float = 1.0) -> dict[str, npt.NDArray[np.float64]]:
        """The squared errors on the held-out lights of ``band`` (``band / div`` in 0–1) of the
        leave-one-out fits of ``keys`` (the photometric models; :meth:`_whole` sums the
        others'): refitted on a copy of the training images, and predicted."""
        sse: dict[str, npt.NDArray[np.float64]] = {}
        n = band.shape[0]
        actual = np.ascontiguousarray(band).reshape(n, -1)[self.held]
        if div != 1.0:  # as decoded: the held-out images' floats
            floats = np.empty(actual.shape, np.float32)
            to_unit_compiled(actual, div, floats)
            actual = floats
        fitted = loo.solve(band[self.train], keys, div)
        for k in keys:
            sse[k] = np.zeros(len(self.held))
            for j, i in enumerate(self.held):
                pred = PREDICT[k](fitted[k], self.full.lights[i])
                if self.full.linear and k in ("normals", "ward"):
                    pred = linear_to_srgb(pred)
                diff = pred.reshape(-1) - actual[j]
                sse[k][j] = float(np.einsum("i,i->", diff, diff, dtype=np.float64))
        return sse


class ExtraModel(Protocol):
    """A model with its own per-band step (the PCA bases, :mod:`~lanterna.tiler.fit.pca_band`).

    ``step(band, div)`` (picklable, run where the band is solved; ``band / div`` is the band in
    0–1: float32 with ``div`` 1, or as decoded) returns the band's outputs (or ``None``
    without layers) and the squared errors on the held-out lights of ``fit_stream``; ``take``
    stores the outputs in order, ``finish`` makes the layer at the end.
    """

    key: str

    @property
    def step(self) -> Callable[[npt.NDArray[np.generic], float],
                               tuple[fb.Out | None, npt.NDArray[np.float64]]]: ...

    def take(self, out: fb.Out) -> None: ...

    def finish(self, progress: Callable[[str, int], Progress] | None) -> PlaneLayer: ...


class BandRunner(Protocol):
    """Runs :class:`_Step` on the row bands of a stack elsewhere (e.g. on a Dask cluster)."""

    def bands(self, images: Images, spans: Sequence[tuple[int, int]],
              step: Callable[[npt.NDArray[np.float32], float, int], _StepResult]
              ) -> Iterator[_StepResult]:
        """Yield ``step(images[:, y0:y1], 1.0, y0)`` for every span, in order."""
        ...


@dataclass
class FitResult:
    """The fitted layers (file-backed planes in the scratch folder) and the quality report."""

    layers: dict[str, PlaneLayer]
    quality: dict[str, dict[str, Any]]
    band_rows: int


def fit_stream(images: Images, lights: Lights, keys: Sequence[str], scratch: Path, *,
               terms: int = 9, band_rows: int | None = None, holdout_every: int = 0,
               linear: bool = False, layers: bool = True,
               progress: Callable[[str, int], Progress] | None = None,
               runner: BandRunner | None = None,
               extra: Sequence[ExtraModel] = (),
               report_pixels: int | None = None) -> FitResult:
    """Fit the models ``keys`` (of :data:`MODEL_KEYS`) in one pass; planes go to ``scratch``.

    ``holdout_every > 0`` also fits without every ``holdout_every``-th light (from the first)
    and reports the PSNR of each model on those lights (``{"heldOut", "psnr", "meanPsnr",
    "medianPsnr"}`` per model; predictions from the float coefficients, before 8-bit storage).
    The photometric models (``normals``, ``ward``) fit the values as stored (``linear=False``:
    their layers say ``inputColorSpace: "display"``, shaded as they are) or decoded from sRGB to
    linear light first (``linear=True``: ``"linear"`` layers, encoded for display by the
    viewer; their report compares the display encoding of the prediction).  PTM and HSH always
    fit the stored values, which the viewer shows as they are.
    The photometric models' report (a second nonlinear fit) is fitted on a fixed pseudo-random
    share of the pixels when the image has more than ``report_pixels`` (about that many,
    :func:`~.held_out.report_sample`; ``None``: :data:`~.held_out.REPORT_PIXELS`; 0: every
    pixel); each model's report says how many it used (``"pixels"``).  ``layers=False`` skips
    the layers (the report only).  ``runner`` solves the bands elsewhere
    (:class:`~lanterna.tiler.fit.cluster.DaskRunner`); results are consumed in order, so the
    output is the same as the local loop's.  ``progress(label, total)`` makes a progress
    reporter per stage.  ``extra`` are models with their own band step
    (:class:`ExtraModel`, e.g. the PCA bases), fitted in the same pass; their held-out lights
    must be this call's.

    Raises
    ------
    ValueError
        When the lights do not determine a model, or shapes disagree.
    """
    n, h, w, _ = images.shape
    if lights.shape != (n, 3):
        raise ValueError(f"{n} images but lights of shape {lights.shape}")
    unknown = [k for k in keys if k not in MODEL_KEYS]
    if unknown:
        raise ValueError(f"unknown model(s) {unknown}")
    rows = band_rows or auto_band_rows(n, w)
    full = Solver(lights, keys, terms, linear)
    held = np.arange(0, n, holdout_every) if holdout_every else np.zeros(0, np.intp)
    train = np.setdiff1d(np.arange(n), held)
    loo = Solver(lights[train], keys, terms, linear) if len(held) else None
    every = [*keys, *(m.key for m in extra)]
    sse = {k: np.zeros(len(held)) for k in every}
    sinks = Sinks(scratch, w, h)
    bar = progress("fitting " + ", ".join(every), h) if progress else None
    spans = band_spans(h, rows, sub_band_rows(n, w) if band_rows is None and runner is None
                       and isinstance(images, StackReader) else rows)
    limit = ho.REPORT_PIXELS if report_pixels is None else report_pixels
    share = 1.0 if limit <= 0 else min(1.0, limit / max(1, h * w))
    batch = _twin_batch(n, w) if runner is None else 0
    step = _Step(full, loo, held, train, layers,
                 fused_rows(loo.keys, loo.pinv, loo.terms, lights, held, train)
                 if loo is not None else {},
                 [m.step for m in extra], [m.key for m in extra], share,
                 batch, _twin_room(batch, share, h, w, max(y1 - y0 for y0, y1 in spans)))
    pixels = dict.fromkeys(every, 0)
    results: Iterable[tuple[int, _StepResult]]
    if runner is None:
        results = ((y1, step(band, div, y1 - band.shape[1]))
                   for y1, band, div in read_bands(images, spans))
    else:
        results = zip((y1 for _, y1 in spans), runner.bands(images, spans, step), strict=True)
    # one BLAS thread: the pass has its own (the read-ahead decode, the kernels'); idle BLAS
    # threads spin, which on a shared or busy machine costs more than the small products gain
    with threadpool_limits(limits=1, user_api="blas"):
        for y1, (parts, band_sse, band_pixels) in results:
            for outs in parts or ():
                sinks.take(outs, keys)
                for m in extra:
                    if m.key in outs:
                        m.take(outs[m.key])
            for k in every:
                sse[k] += band_sse[k]
                pixels[k] += band_pixels[k]
            if bar:
                bar.update(y1)
    last_sse, last_pixels = step.flush()  # the sampled twin's last batch
    for k, err in last_sse.items():
        sse[k] += err
        pixels[k] += last_pixels[k]
    if hasattr(images, "close"):
        images.close()  # the pass is over: free the decoders before quantising and tiling
    space = "linear" if linear else "display"
    fitted = sinks.finish(keys, terms, space, progress) if layers else {}
    if layers:
        fitted.update({m.key: m.finish(progress) for m in extra})
    quality = {k: report(held, sse[k], pixels[k]) for k in every} if len(held) else {}
    return FitResult(fitted, quality, rows)


def _twin_batch(n: int, width: int) -> int:
    """Pixels of the sampled twin fitted at once in a local pass: a float band's worth."""
    return max(width, BAND_BUDGET // max(1, n * 12))


def _twin_room(batch: int, share: float, height: int, width: int, rows: int) -> int:
    """The sampled twin's pixels a pass keeps at once, about: a batch (or the whole sample, if
    fewer) and the tallest band's share (twice it, for the sample's spread), at least a row."""
    if share >= 1.0:
        return 0  # no sample: the twin is fitted with each band
    return min(batch, math.ceil(share * height * width)) + math.ceil(2 * share * rows * width) \
        + width
