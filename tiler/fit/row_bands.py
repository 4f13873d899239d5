"""The row bands one fit pass reads: their heights, their spans, and the reader that decodes
them ahead of the solver (:func:`~lanterna.tiler.fit.engine.fit_stream`'s input side).

A band is what is decoded at once (:data:`BAND_BUDGET` of float input, kept 8-bit as decoded);
the solvers split it into float sub-bands (:data:`SUB_BAND_BUDGET`, cache-sized) except the
Ward fit, which solves whole bands (:data:`WARD_BAND_BUDGET`).
"""

from __future__ import annotations

from collections import deque
from collections.abc import Iterator, Sequence
from concurrent.futures import ThreadPoolExecutor

import numpy as np
import numpy.typing as npt

from lanterna.tiler.inputs.stack import DECODE_THREADS, StackReader

Images = npt.NDArray[np.float32] | StackReader

#: Bytes of input (N × rows × W × 3 float32) solved at once when the band height is automatic.
BAND_BUDGET = 48 << 20
#: Bytes of float input (N × rows × W × 3 float32) solved at once: read bands are split into
#: sub-bands this size, which stay in the CPU caches with their solvers' temporaries.
SUB_BAND_BUDGET = 4 << 20
#: Bytes of float input the Ward fit solves at once (with the normals it needs): a whole band of
#: :data:`BAND_BUDGET`.  Its compiled kernel is bound by arithmetic, not memory, and is parallel
#: over the pixels of a call: on two cores a 1024² fit took 0.67 s so against 0.78 s in
#: cache-sized sub-bands, whose calls are short enough for their overheads, and the other
#: thread's waits for the slower half, to count.
WARD_BAND_BUDGET = BAND_BUDGET
#: Bands read ahead of the one being solved (each a buffer of the band as decoded).
READ_AHEAD = 2


def auto_band_rows(n: int, width: int, budget: int = BAND_BUDGET) -> int:
    """Rows per band so that the float input band ``(n, rows, width, 3)`` fits ``budget``."""
    return max(1, min(256, budget // max(1, n * width * 12)))


def band_spans(height: int, rows: int, first: int) -> list[tuple[int, int]]:
    """The row spans ``(y0, y1)`` the pass reads: the first ``first`` rows (at most ``rows``),
    then ``rows`` at a time.  A short first band lets the solver start once the rows of one
    sub-band are decoded instead of a whole band's (the one decode no solve overlaps)."""
    if height <= 0:
        return []
    head = max(1, min(first, rows, height))
    return [(0, head), *((y0, min(height, y0 + rows)) for y0 in range(head, height, rows))]


def sub_band_rows(n: int, width: int, budget: int = SUB_BAND_BUDGET) -> int:
    """Rows solved at once so that the float sub-band ``(n, rows, width, 3)`` fits ``budget``."""
    return max(1, budget // max(1, n * width * 12))


def read_bands(images: Images, spans: Sequence[tuple[int, int]]
               ) -> Iterator[tuple[int, npt.NDArray[np.generic], float]]:
    """Yield ``(y1, band, div)`` for each span, in order: ``band / div`` is ``images[:, y0:y1]``.

    A :class:`StackReader` whose images share a sample format yields its bands as decoded
    (8-bit: a quarter of the float band), :data:`READ_AHEAD` bands read ahead in a thread (two
    rather than one took ~5 % off PTM and HSH fits at 2048²: fewer waits for a slow band), each
    band's files decoded in parallel (:data:`DECODE_THREADS`; libvips runs without the GIL)
    while the solver waits, into one of ``READ_AHEAD + 1`` reused buffers; a band is valid until
    the next one is asked for.  Other stacks yield float32 bands.
    """
    dtype = images.native_dtype() if isinstance(images, StackReader) else None
    n, width = images.shape[0], images.shape[2]
    tallest = max((y1 - y0 for y0, y1 in spans), default=0)
    buffers = [np.empty(n * tallest * width * 3 if dtype is not None else 0, dtype or np.uint8)
               for _ in range(READ_AHEAD + 1)]
    with ThreadPoolExecutor(max_workers=DECODE_THREADS,
                            thread_name_prefix="lanterna-decode") as decoders, \
            ThreadPoolExecutor(max_workers=1, thread_name_prefix="lanterna-read") as pool:

        def read(i: int, parallel: bool) -> tuple[npt.NDArray[np.generic], float]:
            y0, y1 = spans[i]
            if dtype is None or not isinstance(images, StackReader):
                return np.asarray(images[:, y0:y1], np.float32), 1.0
            band = buffers[i % len(buffers)][:n * (y1 - y0) * width * 3].reshape(
                n, y1 - y0, width, 3)
            return band, images.band_into(y0, y1, band, decoders if parallel else None)

        # the bands ahead are decoded on every core only while the solver waits for the decode;
        # when a band is ready before it is asked for, the solver is the slower side and one
        # decoding thread leaves it the other core (measured: the normals' 2048² fit 1.35–1.38 s
        # with the decode always parallel, 1.20 s so)
        ahead = deque(pool.submit(read, i, True) for i in range(min(READ_AHEAD, len(spans))))
        for i, (_, y1) in enumerate(spans):
            parallel = not ahead[0].done()
            band, div = ahead.popleft().result()
            if i + READ_AHEAD < len(spans):
                ahead.append(pool.submit(read, i + READ_AHEAD, parallel))
            yield y1, band, div
