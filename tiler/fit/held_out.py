"""The leave-one-out report of a fit: which pixels its twin is fitted on, the linear models'
fused held-out rows, the predictions of the others, and the PSNR per held-out light.

:func:`~lanterna.tiler.fit.engine.fit_stream` fits each model a second time without every k-th
light (the twin) and predicts those lights: PTM and HSH by the rows of :func:`fused_rows` in the
layer's own pass, the photometric models by a second fit (:data:`PREDICT`) on every pixel or, in
an image of more than :data:`REPORT_PIXELS`, on the pseudo-random sample of
:func:`report_sample`.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from typing import Any

import numpy as np
import numpy.typing as npt

from lanterna.tiler.formats.hsh_basis import hsh_weights
from lanterna.tiler.formats.ptm_model import ptm_weights

from . import bands as fb

#: Pixels the leave-one-out twin of the photometric models (a second nonlinear fit: for Ward as
#: costly as the layer's) is fitted on, about: a fixed pseudo-random subset of the image
#: beyond that (:func:`report_sample`); the linear models' reports are exact at any size.
REPORT_PIXELS = 1 << 16

PREDICT: dict[str, Callable[[fb.Out, npt.NDArray[np.float64]], fb.Band]] = {
    "ptm": fb.predict_ptm_band, "ptm-lrgb": fb.predict_ptm_band, "hsh": fb.predict_hsh_band,
    "normals": fb.predict_normals_band, "ward": fb.predict_ward_band,
}


#: SplitMix64's increment γ and its two mixing multipliers (Steele, Lea & Flood 2014), the
#: hash of :func:`report_sample` and of its compiled twin (:mod:`.sample_kernel`).
SPLITMIX_GAMMA, SPLITMIX_MUL1, SPLITMIX_MUL2 = (0x9E3779B97F4A7C15, 0xBF58476D1CE4E5B9,
                                                0x94D049BB133111EB)


def sample_threshold(share: float) -> int:
    """The bound below which a pixel's 53-bit hash puts it in a sample of ``share``."""
    return int(share * (1 << 53))


def report_sample(y0: int, rows: int, width: int, share: float) -> npt.NDArray[np.bool_]:
    """The pixels of rows ``y0 … y0 + rows`` (``(rows, width)`` mask) in the leave-one-out
    twin's sample: those whose index ``i = y·width + x`` gives a SplitMix64 output (the mix of
    ``(i + 1)·γ``) in the lowest ``share`` of its range.  Fixed by the pixel alone, so the same
    whatever the band heights or the machine; pseudo-random, so it cannot alias with a
    periodic pattern of the object, as a regular lattice can (measured on the 1024² grainy
    bench stack: every 8th row and column, 1/64 of the pixels, put the Ward report 0.43 dB
    low; this sample of 1/64, 0.01 dB)."""
    idx = (np.arange(y0, y0 + rows, dtype=np.uint64)[:, None] * np.uint64(width)
           + np.arange(width, dtype=np.uint64)[None, :])
    z = (idx + np.uint64(1)) * np.uint64(SPLITMIX_GAMMA)
    z = (z ^ (z >> np.uint64(30))) * np.uint64(SPLITMIX_MUL1)
    z = (z ^ (z >> np.uint64(27))) * np.uint64(SPLITMIX_MUL2)
    z ^= z >> np.uint64(31)
    mask: npt.NDArray[np.bool_] = (z >> np.uint64(11)) < np.uint64(sample_threshold(share))
    return mask


def fused_rows(keys: Sequence[str], pinv: dict[str, npt.NDArray[np.float32]], terms: int,
               lights: npt.NDArray[np.float64], held: npt.NDArray[np.intp],
               train: npt.NDArray[np.intp]) -> dict[str, npt.NDArray[np.float32]]:
    """Per linear model of ``keys``, ``(h, N)`` = the held-out lights' basis rows × the
    leave-one-out pseudo-inverse ``pinv`` of the training lights (zero on the held-out columns):
    the held-out predictions in one product."""
    rows: dict[str, npt.NDArray[np.float32]] = {}
    bases: dict[str, Callable[[float, float], npt.NDArray[np.floating]]] = {
        "ptm": ptm_weights, "hsh": lambda u, v: hsh_weights(u, v, terms)}
    pinvs = {"ptm": pinv.get("ptm-lrgb"), "hsh": pinv.get("hsh")}
    for k in ("ptm", "hsh"):
        rows_k = pinvs[k]
        if k not in keys or rows_k is None:
            continue
        basis = np.stack([bases[k](float(lt[0]), float(lt[1])) for lt in lights[held]])
        full = np.zeros((len(held), len(lights)))
        full[:, train] = basis.astype(np.float64) @ rows_k.astype(np.float64)
        rows[k] = full.astype(np.float32)
    return rows


def report(held: npt.NDArray[np.intp], sse: npt.NDArray[np.float64], pixels: int
           ) -> dict[str, Any]:
    """One model's report from its squared errors per held-out light over ``pixels`` pixels
    (RGB): ``heldOut``, ``psnr`` per light, ``meanPsnr``, ``medianPsnr`` and ``pixels``."""
    scores = [10.0 * math.log10(pixels * 3 / s) if s > 0 else math.inf for s in sse]
    return {"heldOut": [int(i) for i in held], "psnr": [round(s, 3) for s in scores],
            "meanPsnr": round(float(np.mean(scores)), 3),
            "medianPsnr": round(float(np.median(scores)), 3), "pixels": pixels}


class TwinStore:
    """The sampled twin's pixels kept between bands until a batch of them is fitted: one
    ``(N, room, 3)`` block filled in order (``pixels`` the filled part, ``pixels / div`` in
    0–1: as decoded, or float32 with ``div`` 1), made once for the pass instead of a small
    array per band held among the bands' temporaries. Those had the allocator fragment its
    heap and take fresh pages from the kernel for every band (a 2048² Ward fit's report took
    ~80,000 more page faults than the fit without it, 0.2 s of system time: docs/fitting.md
    "Speed, thirteenth pass")."""

    def __init__(self) -> None:
        self._block: npt.NDArray[np.generic] | None = None
        self.count = 0
        self.div = 1.0

    @property
    def pixels(self) -> npt.NDArray[np.generic]:
        """The pixels kept, ``(N, count, 3)`` (a view, valid until the next :meth:`add`)."""
        assert self._block is not None
        return self._block[:, :self.count]

    def add(self, twin: npt.NDArray[np.generic], room: int, div: float = 1.0) -> None:
        """Keep ``twin`` ``(N, k, 3)`` (``twin / div`` in 0–1, the sample format and ``div``
        of the pixels kept) after the pixels kept; the block is made with room for ``room``
        pixels (or as many as needed), and doubled when it is full."""
        n, k, c = twin.shape
        if self.count and (twin.dtype != self.pixels.dtype or div != self.div):
            raise ValueError(f"twin pixels of {twin.dtype} / {div} after "
                             f"{self.pixels.dtype} / {self.div}")
        self.div = div
        need = self.count + k
        if self._block is None or self._block.shape[1] < need or \
                self._block.dtype != twin.dtype:
            size = need if self._block is None else max(need, 2 * self._block.shape[1])
            block = np.empty((n, max(size, room), c), twin.dtype)
            if self._block is not None:
                block[:, :self.count] = self._block[:, :self.count]
            self._block = block
        self._block[:, self.count:need] = twin
        self.count = need
