"""The bounded pixel sample a PCA basis is learnt from: one streamed pass over the row bands.

The image size is known from the headers, so the sample is drawn up front: ``S`` distinct pixel
indices chosen uniformly at random (a fixed seed, so a fit is reproducible), sorted; one pass
top to bottom copies each band's chosen pixels (every light's sample of them).  The result is
the sample a reservoir over the bands would give, without its per-band bookkeeping, and is the
same whatever the band height or the reader (a stack in memory or read from disk; from disk
only the chosen pixels are converted to float).  Memory:
``S × n × 3`` float32, ``S`` = min(:data:`SAMPLE_PIXELS`, :data:`SAMPLE_BYTES` / (12·n),
pixels), plus one band.
"""

from __future__ import annotations

from collections.abc import Callable
from concurrent.futures import Executor, ThreadPoolExecutor
from typing import Any

import numpy as np
import numpy.typing as npt

from lanterna.tiler.inputs.stack import DECODE_THREADS, StackReader, to_unit
from lanterna.tiler.progress import Progress

#: Most pixels sampled (Relight's ``nsamples``, 2^16).
SAMPLE_PIXELS = 1 << 16
#: Most bytes the sample may hold (float32 light samples; 46,603 pixels of 240 lights).
SAMPLE_BYTES = 128 << 20
#: The sample's fixed seed.
SAMPLE_SEED = 15


def sample_count(n: int, pixels: int, budget: int = SAMPLE_BYTES,
                 cap: int = SAMPLE_PIXELS) -> int:
    """Pixels sampled from ``pixels`` of ``n`` lights within ``budget`` bytes and ``cap``."""
    return max(1, min(pixels, cap, budget // max(1, n * 3 * 4)))


def sample_pixels(images: Any, band_rows: int, *, budget: int = SAMPLE_BYTES,
                  cap: int = SAMPLE_PIXELS,
                  progress: Callable[[str, int], Progress] | None = None
                  ) -> npt.NDArray[np.float32]:
    """A uniform sample of pixels ``(S, n, 3)`` float32 of a stack ``(n, H, W, 3)``.

    ``images`` is anything indexable as ``images[:, y0:y1]`` (an array, a
    :class:`~lanterna.tiler.inputs.stack.StackReader`, a fusion stack); one pass in bands of
    ``band_rows`` rows.
    """
    n, h, w, _ = images.shape
    size = sample_count(n, h * w, budget, cap)
    chosen = np.sort(np.random.default_rng(SAMPLE_SEED).choice(h * w, size, replace=False))
    out = np.empty((size, n, 3), np.float32)
    bar = progress("sampling pixels for the PCA basis", h) if progress else None
    with ThreadPoolExecutor(max_workers=DECODE_THREADS,
                            thread_name_prefix="lanterna-decode") as pool:
        for y0 in range(0, h, band_rows):
            y1 = min(h, y0 + band_rows)
            a, b = np.searchsorted(chosen, [y0 * w, y1 * w])
            if b > a:
                rows, cols = np.divmod(chosen[a:b], w)
                _take(images, y0, y1, rows - y0, cols, out[a:b], pool)
            if bar:
                bar.update(y1)
    if hasattr(images, "close"):
        images.close()  # the next pass starts from the top again
    return out


def _take(images: Any, y0: int, y1: int, rows: npt.NDArray[np.intp],
          cols: npt.NDArray[np.intp], out: npt.NDArray[np.float32], pool: Executor) -> None:
    """``out (s, n, 3)`` = the pixels ``(rows, cols)`` of band ``y0:y1`` of every light.

    From a :class:`~lanterna.tiler.inputs.stack.StackReader` the band stays as decoded (its
    files decoded in ``pool``'s threads) and only the chosen pixels become float (``to_unit``:
    the values of ``images[:, y0:y1]``, a few hundred pixels of a band instead of all of it)."""
    if not isinstance(images, StackReader):
        out[...] = np.asarray(images[:, y0:y1], np.float32)[:, rows, cols].transpose(1, 0, 2)
        return
    for k, (band, full_scale) in enumerate(images.native_rows(y0, y1, pool)):
        to_unit(band[rows, cols], full_scale, out[:, k])
