"""A band's pieces for the solvers, in reused buffers: float32 0–1 sub-bands (:meth:`SubBands.
floats`), or pieces kept as decoded for the kernels that divide where they read
(:meth:`SubBands.as_decoded`).  Each piece is valid until the next is asked for: a fresh
array each time would cost a page fault per 4 KB page, as much as the conversion itself, and no
solver keeps a view of its input."""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from .unit_kernel import to_unit_compiled


@dataclass
class SubBands:
    """The reused buffers of one solver (made where it runs; a new one is empty)."""

    _unit: npt.NDArray[np.float32] | None = None
    _raw: npt.NDArray[np.generic] | None = None

    def floats(self, band: npt.NDArray[np.generic], div: float, rows: int
               ) -> Iterator[tuple[int, npt.NDArray[np.float32]]]:
        """``band`` (``band / div`` in 0–1) as float32 0–1 sub-bands of ``rows`` rows, with
        their first row in ``band``: views of a float band, or converted into one buffer."""
        n, b, w, c = band.shape
        rows = max(1, min(rows, b))
        native = band.dtype != np.float32 or div != 1.0
        if native and (self._unit is None or self._unit.size < n * rows * w * c):
            self._unit = np.empty(n * rows * w * c, np.float32)
        for r0 in range(0, b, rows):
            r1 = min(b, r0 + rows)
            if not native:
                yield r0, np.asarray(band[:, r0:r1], np.float32)
                continue
            assert self._unit is not None
            piece = self._unit[:n * (r1 - r0) * w * c].reshape(n, r1 - r0, w, c)
            for i in range(n):
                to_unit_compiled(band[i, r0:r1], None if div == 1.0 else div, piece[i])
            yield r0, piece

    def as_decoded(self, band: npt.NDArray[np.generic], div: float, rows: int
                   ) -> Iterator[tuple[int, npt.NDArray[np.generic], float]]:
        """``band`` as decoded in pieces of ``rows`` rows, ``(r0, piece, div)``: the band itself
        when it is one contiguous piece, else its rows copied into one contiguous buffer (a
        quarter of the float buffer's bytes at 8 bits)."""
        n, b, w, c = band.shape
        if rows >= b and band.flags.c_contiguous:
            yield 0, band, div
            return
        rows = max(1, min(rows, b))
        size = n * rows * w * c
        if self._raw is None or self._raw.dtype != band.dtype or self._raw.size < size:
            self._raw = np.empty(size, band.dtype)
        for r0 in range(0, b, rows):
            r1 = min(b, r0 + rows)
            piece = self._raw[:n * (r1 - r0) * w * c].reshape(n, r1 - r0, w, c)
            piece[...] = band[:, r0:r1]
            yield r0, piece, div
