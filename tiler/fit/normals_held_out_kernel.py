"""The rank-window photometric stereo and its leave-one-out twin in one compiled pass (Numba).

The report refits the normals on the training lights and predicts the held-out ones.  Done
apart, that is a copy of the training images and a second fit from scratch; here each chunk of
pixels is read once.  The training lights' stable ranks among themselves are the full ranks
less the held-out samples that rank below (earlier held-out ones when equal), so the
``N²`` comparisons are made once.  Both fits are :mod:`.normals_kernel`'s steps (the twin's
bit for bit those of a fit of the training images alone); the held-out prediction is
:func:`~lanterna.tiler.fit.bands.predict_normals_band`'s, in float32 (Lambert
``clip(albedo · max(0, n·l), 0, 1)``), its squared errors summed in float64 per chunk, then
over the chunks in order.
"""

from __future__ import annotations

import numba
import numpy as np
import numpy.typing as npt

from .compiled import unit
from .normals_kernel import MAX_COUNTED, chunk_rows, fit_chunk, fit_rows, kernel_rows, window

_CHUNK = 512  # pixels per parallel task
#: The most lights the pass takes (its ranks are counted, as :mod:`.normals_kernel`'s).
MAX_LIGHTS = MAX_COUNTED


@numba.njit(cache=True, parallel=True, nogil=True, error_model="numpy")
def _fused(lum: npt.NDArray[np.floating], colour: npt.NDArray[np.generic],
           lights: npt.NDArray[np.float64], lo: int, hi: int, shadow: float,
           train: npt.NDArray[np.intp], held: npt.NDArray[np.intp], lo_t: int, hi_t: int,
           normals: npt.NDArray[np.float32], albedo: npt.NDArray[np.float32],
           sse: npt.NDArray[np.float64], d: np.float32, weights: npt.NDArray[np.float32],
           from_colour: bool) -> None:
    p = colour.shape[1]
    nt, h = train.shape[0], held.shape[0]
    for chunk in numba.prange((p + _CHUNK - 1) // _CHUNK):
        q0, q1 = chunk * _CHUNK, min(p, (chunk + 1) * _CHUNK)
        m = q1 - q0
        y = chunk_rows(lum, colour, weights, from_colour, q0, q1, d)
        rank = fit_chunk(y, colour, lights, lo, hi, shadow, normals, albedo, q0, d)
        rank_t = np.empty((nt, m), np.int32)
        for j in range(nt):
            i = train[j]
            yi, rt = y[i], rank_t[j]
            rt[:] = rank[i]
            for hh in held:
                yh = y[hh]
                if hh < i:
                    for q in range(m):
                        rt[q] -= np.int32(yh[q] <= yi[q])
                else:
                    for q in range(m):
                        rt[q] -= np.int32(yh[q] < yi[q])
        keep_t = window(y, rank_t, train, lo_t, hi_t, shadow)
        nrm_t, alb_t = fit_rows(y, keep_t, train, lights, colour, q0, d, True)
        for jh in range(h):
            i = held[jh]
            lx, ly = np.float32(lights[i, 0]), np.float32(lights[i, 1])
            lz = np.float32(lights[i, 2])
            src = colour[i, q0:q1]
            acc = 0.0
            for q in range(m):
                shade = max(np.float32(nrm_t[0, q]) * lx + np.float32(nrm_t[1, q]) * ly
                            + np.float32(nrm_t[2, q]) * lz, np.float32(0.0))
                for c in range(3):
                    pred = min(max(np.float32(alb_t[c, q]) * shade, np.float32(0.0)),
                               np.float32(1.0))
                    e = float(pred - np.float32(unit(src[q, c], d)))
                    acc += e * e
            sse[chunk, jh] = acc


def rank_window_normals_held_out(lum: npt.NDArray[np.floating] | None,
                                 colour: npt.NDArray[np.generic],
                                 lights: npt.NDArray[np.float64], window_lo_hi: tuple[int, int],
                                 shadow: float, train: npt.NDArray[np.intp],
                                 held: npt.NDArray[np.intp], train_lo_hi: tuple[int, int],
                                 div: float = 1.0,
                                 weights: npt.NDArray[np.float32] | None = None
                                 ) -> tuple[npt.NDArray[np.float32], npt.NDArray[np.float32],
                                            npt.NDArray[np.float64]]:
    """Normals and albedo ``(P, 3)`` float32 of ``lum (N, P)``, ``colour (N, P, 3)`` 0–1 under
    ``lights (N, 3)`` (ranks ``window_lo_hi``), and the squared errors ``(h,)`` on the
    ``held`` lights of the fit of the ``train`` lights (ranks ``train_lo_hi`` among them);
    ``train`` and ``held`` ascending, at most :data:`MAX_LIGHTS` lights; ``colour`` may be 8-/16-bit
    as decoded, with ``div`` 255/65535 (the results of the float ``colour / div``); ``lum``
    None: the luminance of ``colour`` with ``weights``, chunk by chunk in the pass
    (:func:`~.normals_kernel.rank_window_normals`)."""
    n, p = colour.shape[:2]
    if n > MAX_LIGHTS:
        raise ValueError(f"the fused pass takes at most {MAX_LIGHTS} lights, not {n}")
    normals = np.empty((p, 3), np.float32)
    albedo = np.empty((p, 3), np.float32)
    sse = np.zeros(((p + _CHUNK - 1) // _CHUNK, len(held)))
    rows, w = kernel_rows(lum, colour, weights)
    _fused(rows, np.ascontiguousarray(colour),
           np.ascontiguousarray(lights, np.float64), window_lo_hi[0], window_lo_hi[1],
           float(shadow), np.ascontiguousarray(train, np.intp),
           np.ascontiguousarray(held, np.intp), train_lo_hi[0], train_lo_hi[1], normals, albedo,
           sse, np.float32(div), w, lum is None)
    out: npt.NDArray[np.float64] = sse.sum(axis=0)
    return normals, albedo, out
