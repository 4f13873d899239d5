"""File-backed 8-bit images written row band by row band, read back through libvips.

Fitting a gigapixel collection produces its planes a few rows at a time; holding them whole in
memory (or in a ``np.memmap``, whose touched pages count as resident) would not fit the
memory budget.  :class:`StripTiffWriter` appends rows to an uncompressed, striped BigTIFF (a
plain ``write``, no mapping) and :class:`BandImage` reads it back — as numpy row bands or as a
pyvips image for the pyramid writer — through libtiff, whose reads are bounded by the strips in
use (measured: 53 MB peak RSS reading a 3 GB plane, against 2.9 GB through ``mmap``).
"""

from __future__ import annotations

import os
import struct
from pathlib import Path
from typing import Any

import numpy as np
import numpy.typing as npt
import pyvips

#: TIFF field types used here.
_SHORT, _LONG, _LONG8 = 3, 4, 16
_TYPE_CODE = {_SHORT: "H", _LONG: "I", _LONG8: "Q"}
#: Tile side: libvips reads a tiled TIFF tile by tile, for any region (a striped one it may
#: decode whole for random access).
TILE = 256
_HEADER = 16


class StripTiffWriter:
    """Write a ``height × width × bands`` uint8 image top to bottom as a tiled BigTIFF.

    ``write(rows)`` appends ``(b, width[, bands])`` rows (held until a row of 256² tiles is
    complete: ``256 × width × bands`` bytes); ``close()`` checks that every row came, writes the
    directory and renames the temporary file to ``path``.  On an exception inside a ``with``
    block the temporary file is removed and ``path`` is not created.
    """

    def __init__(self, path: Path, width: int, height: int, bands: int) -> None:
        if bands not in (1, 3) or width < 1 or height < 1:
            raise ValueError(f"need 1 or 3 bands and a positive size, got {width}x{height}x{bands}")
        self.path = Path(path)
        self.width, self.height, self.bands = width, height, bands
        self._tmp = self.path.with_name(f".{self.path.name}.part")
        self._file = open(self._tmp, "wb")  # noqa: SIM115 - closed in close()/abort()
        self._file.write(b"\0" * _HEADER)
        self._rows = 0
        # rows wait here until a whole row of tiles can be written: the width rounded up to
        # whole tiles, whose columns past the image stay zero
        self._across = -(-self.width // TILE)
        self._pending = np.zeros((TILE, self._across * TILE, bands), np.uint8)
        # a row of tiles in the file's order, made by one copy and written by one call
        self._tiles = np.empty((self._across, TILE, TILE, bands), np.uint8)
        self._filled = 0
        self._offsets: list[int] = []
        self._counts: list[int] = []

    def write(self, rows: npt.NDArray[np.uint8]) -> None:
        """Append rows: ``(b, width, bands)`` or, for one band, ``(b, width)``."""
        want = (self.width,) + ((self.bands,) if self.bands == 3 else ())
        arr = rows.reshape(rows.shape[0], self.width, self.bands) if (
            self.bands == 1 and rows.ndim == 3) else rows
        if arr.dtype != np.uint8 or arr.shape[1:] != want:
            raise ValueError(f"rows must be uint8 (b, {', '.join(map(str, want))}), "
                             f"got {rows.dtype} {rows.shape}")
        if self._rows + arr.shape[0] > self.height:
            raise ValueError(f"more than {self.height} rows written")
        rows3 = arr.reshape(arr.shape[0], self.width, self.bands)
        done = 0
        while done < len(rows3):
            take = min(TILE - self._filled, len(rows3) - done)
            self._pending[self._filled:self._filled + take, :self.width] = rows3[done:done + take]
            self._filled += take
            done += take
            if self._filled == TILE:
                self._flush()
        self._rows += arr.shape[0]

    def _flush(self) -> None:
        """Write the pending row of tiles (zero-padded at the right and bottom edges)."""
        if self._filled < TILE:
            self._pending[self._filled:] = 0
        grid = self._pending.reshape(TILE, self._across, TILE, self.bands)
        np.copyto(self._tiles, grid.transpose(1, 0, 2, 3))
        at, size = self._file.tell(), TILE * TILE * self.bands
        self._offsets.extend(range(at, at + self._across * size, size))
        self._counts.extend([size] * self._across)
        self._file.write(self._tiles.data)
        self._filled = 0

    def close(self) -> BandImage:
        """Finish the file and return it as a :class:`BandImage`."""
        if self._rows != self.height:
            self.abort()
            raise ValueError(f"{self._rows} of {self.height} rows written")
        if self._filled:
            self._flush()
        ifd_at = self._file.tell()
        entries: list[tuple[int, int, list[int]]] = [
            (256, _LONG, [self.width]), (257, _LONG, [self.height]),
            (258, _SHORT, [8] * self.bands), (259, _SHORT, [1]),
            (262, _SHORT, [2 if self.bands == 3 else 1]), (277, _SHORT, [self.bands]),
            (284, _SHORT, [1]), (322, _LONG, [TILE]), (323, _LONG, [TILE]),
            (324, _LONG8, self._offsets), (325, _LONG8, self._counts),
            (339, _SHORT, [1] * self.bands),
        ]
        self._file.write(_directory(entries, ifd_at))
        self._file.seek(0)
        self._file.write(struct.pack("<2sHHHQ", b"II", 43, 8, 0, ifd_at))
        self._file.close()
        os.replace(self._tmp, self.path)
        return BandImage(self.path, self.width, self.height, self.bands)

    def abort(self) -> None:
        """Close and delete the temporary file."""
        self._file.close()
        self._tmp.unlink(missing_ok=True)

    def __enter__(self) -> StripTiffWriter:
        return self

    def __exit__(self, exc_type: Any, exc: Any, tb: Any) -> None:
        if exc_type is not None:
            self.abort()


def _directory(entries: list[tuple[int, int, list[int]]], at: int) -> bytes:
    """One BigTIFF IFD at file offset ``at``, its out-of-line arrays after it."""
    head = struct.pack("<Q", len(entries))
    tail_at = at + 8 + 20 * len(entries) + 8
    body, tail = b"", b""
    for tag, kind, values in sorted(entries):
        data = struct.pack(f"<{len(values)}{_TYPE_CODE[kind]}", *values)
        if len(data) <= 8:
            field = data.ljust(8, b"\0")
        else:
            field = struct.pack("<Q", tail_at + len(tail))
            tail += data + (b"\0" if len(data) % 2 else b"")
        body += struct.pack("<HHQ", tag, kind, len(values)) + field
    return head + body + struct.pack("<Q", 0) + tail


class BandImage:
    """A striped TIFF written by :class:`StripTiffWriter`, looked at like a uint8 array.

    ``shape``/``dtype``/``ndim`` as the ``(H, W[, 3])`` array it holds; ``image[y0:y1]`` reads
    rows; :meth:`vips` opens it for libvips (random access, strip by strip).
    """

    dtype = np.dtype(np.uint8)

    def __init__(self, path: Path, width: int, height: int, bands: int) -> None:
        self.path = Path(path)
        self.width, self.height, self.bands = width, height, bands
        self.shape: tuple[int, ...] = (height, width, 3) if bands == 3 else (height, width)
        self.ndim = len(self.shape)

    def _image(self) -> pyvips.Image:
        # opened afresh for each use: caches libvips attaches while an image is read (the
        # pyramid writer's, the tiles of a long read) go when that use ends
        return pyvips.Image.new_from_file(str(self.path), revalidate=True)

    def vips(self) -> pyvips.Image:
        """The image for libvips, interpreted as sRGB (3 bands) or b-w (1 band)."""
        return self._image().copy(interpretation="srgb" if self.bands == 3 else "b-w")

    def rows(self, y0: int, y1: int) -> npt.NDArray[np.uint8]:
        """Rows ``y0:y1`` as ``(b, W, 3)`` or ``(b, W)`` uint8."""
        y0, y1 = max(0, y0), min(self.height, y1)
        if y1 <= y0:
            return np.empty((0, *self.shape[1:]), np.uint8)
        raw = pyvips.Region.new(self._image()).fetch(0, y0, self.width, y1 - y0)
        return np.frombuffer(raw, np.uint8).reshape((y1 - y0, *self.shape[1:])).copy()

    def __getitem__(self, key: Any) -> npt.NDArray[np.uint8]:
        if isinstance(key, slice) and key.step in (None, 1):
            start, stop, _ = key.indices(self.height)
            return self.rows(start, stop)
        raise TypeError(f"BandImage supports [y0:y1] only, not {key!r}")

    def __array__(self, dtype: Any = None, copy: Any = None) -> npt.NDArray[np.uint8]:
        """The whole image in memory (for small images and tests)."""
        out = self.rows(0, self.height)
        return out if dtype is None else out.astype(dtype)
