"""Load a multi-light image collection (one photograph per light) as one float stack."""

from __future__ import annotations

import os
from collections.abc import Callable, Sequence
from concurrent.futures import Executor
from pathlib import Path
from typing import Any, TypeVar

import numpy as np
import numpy.typing as npt
import pyvips

from lanterna.errors import LanternaInputError
from lanterna.tiler.fileio import check_regular_file
from lanterna.tiler.limits import check_pixels

_T = TypeVar("_T")

#: Divisor turning each libvips band format into 0–1.
_FULL_SCALE = {"uchar": 255.0, "ushort": 65535.0}


def load_image(path: Path) -> npt.NDArray[np.float32]:
    """Return one image as ``(H, W, 3)`` float32 in 0–1, values as stored (no gamma change).

    JPEG, PNG and TIFF, 8 or 16 bit; grey images are repeated to RGB and alpha is dropped.
    Float TIFFs are taken as already in 0–1.
    """
    img = _open_rgb(path)
    try:
        array = img.numpy()
    except pyvips.Error as err:
        first = str(err).strip().splitlines()[0] if str(err).strip() else "unreadable image"
        raise LanternaInputError(path, f"cannot read image ({first})") from None
    out: npt.NDArray[np.float32] = np.asarray(array, np.float32).reshape(img.height, img.width, 3)
    if img.format in _FULL_SCALE:
        return out / np.float32(_FULL_SCALE[img.format])
    return out  # float or double (_open_rgb refuses other formats)


def load_stack(files: Sequence[Path]) -> npt.NDArray[np.float32]:
    """Load the images of ``files`` as ``(N, H, W, 3)`` float32 in 0–1.

    Raises
    ------
    LanternaInputError
        Naming the file that cannot be read, or whose size differs from the first image's.
    """
    if not files:
        raise LanternaInputError(None, "no images to load")
    first = load_image(files[0])
    h, w = first.shape[:2]
    stack = np.empty((len(files), h, w, 3), np.float32)
    stack[0] = first
    for i, path in enumerate(files[1:], 1):
        img = load_image(path)
        if img.shape[:2] != (h, w):
            raise LanternaInputError(path, f"is {img.shape[1]}x{img.shape[0]}, but "
                                     f"{Path(files[0]).name} is {w}x{h}: all images of a "
                                     "collection must have the same size")
        stack[i] = img
    return stack


#: Threads decoding the files of a band at once (each file's decoder runs serially, and
#: libvips decodes without the GIL, so a band is decoded on every core instead of one).
DECODE_THREADS = max(1, min(8, os.cpu_count() or 1))
#: Bytes libvips holds per image column for an open sequential decode (~1,500 lines of RGB:
#: measured 145 MB for a 32,768-px-wide JPEG, 36 MB at 8,192 px).
DECODER_BYTES_PER_COLUMN = 4608
#: Rows of an image fetched from libvips at once in a sequential pass.  A fetch makes libvips
#: allocate (and zero) buffers of the rows asked for at several steps of its pipeline, afresh at
#: every fetch: for a band of 85 rows, 0.5 MB each, above the allocator's threshold for fresh
#: pages from the kernel, so every fetch page-faulted them in.  Eight rows at a time (a JPEG's
#: MCU row, or half of one) keep those buffers small and reused: one thread reading a 2048²
#: 24-light stack in 85-row bands took 1.0 s (0.4 s of it in the kernel, 210,000 page faults),
#: 0.67 s in 8-row strips (0.09 s, 55,000): docs/fitting.md "Speed, thirteenth pass".
FETCH_ROWS = 8


def to_tiled_tiff(path: Path, out: Path) -> Path:
    """Re-encode ``path`` losslessly as a tiled TIFF (deflate) at ``out``, streaming.

    A wide collection read through its JPEG/PNG decoders would hold
    :data:`DECODER_BYTES_PER_COLUMN` × width per image; tiles can be read at any row, so a
    reader can open each file for one band and keep nothing between bands.
    """
    img = _open_rgb(path)
    tmp = out.with_name(f".{out.name}.part")
    try:
        img.tiffsave(str(tmp), tile=True, tile_width=256, tile_height=256,
                     compression="deflate", predictor="horizontal", bigtiff=True)
    except pyvips.Error as err:
        tmp.unlink(missing_ok=True)
        first = str(err).strip().splitlines()[0] if str(err).strip() else "unreadable image"
        raise LanternaInputError(path, f"cannot read image ({first})") from None
    tmp.rename(out)
    return out


#: numpy dtype of each libvips sample format a stack may hold.
_NUMPY_FORMAT = {"uchar": np.uint8, "ushort": np.uint16, "float": np.float32,
                 "double": np.float64}


def _open_rgb(path: Path, access: str = "sequential") -> pyvips.Image:
    """Open ``path`` as 3 bands (alpha dropped, grey repeated), by default for one top-to-bottom
    pass; ``access="random"`` opens it afresh (not from libvips' cache) for a few rows."""
    check_regular_file(path, "an image")
    try:
        img = (pyvips.Image.new_from_file(str(path), access="sequential") if access == "sequential"
               else pyvips.Image.new_from_file(str(path), access=access, revalidate=True))
        check_pixels(path, img.width, img.height)
        if img.hasalpha():
            img = img.extract_band(0, n=img.bands - 1)
        if img.bands == 1:
            img = img.bandjoin([img, img])
        elif img.bands > 3:
            img = img.extract_band(0, n=3)
    except pyvips.Error as err:
        first = str(err).strip().splitlines()[0] if str(err).strip() else "unreadable image"
        raise LanternaInputError(path, f"cannot read image ({first})") from None
    if img.bands != 3:
        raise LanternaInputError(path, f"expected an RGB or grey image, got {img.bands} bands")
    if img.format not in _NUMPY_FORMAT:
        raise LanternaInputError(path, f"unsupported sample format {img.format} "
                                 "(expected 8 or 16 bit, or float)")
    return img


def to_unit(band: npt.NDArray[np.generic], full_scale: float | None,
            out: npt.NDArray[np.float32]) -> None:
    """Write ``band`` (as stored) into ``out`` as float32 in 0–1, the values of
    :func:`load_image` (one division, no temporary)."""
    if full_scale is None:
        out[...] = band
    else:
        np.divide(band, np.float32(full_scale), out=out)


class StackReader:
    """A multi-light collection on disk, read lazily in row bands.

    Looks like the ``(N, H, W, 3)`` float32 array :func:`load_stack` would return, for the
    indexing the fitters use: ``reader[:, y0:y1]`` reads rows ``y0:y1`` of every image
    (``(N, y1 − y0, W, 3)`` float32 in 0–1, bit-identical to the same slice of
    :func:`load_stack`), ``reader[indices]`` is a reader over a subset of the images, and
    ``reader[i]`` loads image ``i`` whole.  Band reads go through one libvips region per file
    opened with ``access="sequential"``, so a pass from top to bottom decodes each file once
    and holds only ``O(N · band · W)``; a read above the current position (a new pass)
    reopens the files.  Sizes are checked from the headers when the reader is made.
    """

    dtype = np.dtype(np.float32)
    ndim = 4

    def __init__(self, files: Sequence[Path], *, reopen: bool = False) -> None:
        if not files:
            raise LanternaInputError(None, "no images to load")
        self.files = [Path(f) for f in files]
        first = _open_rgb(self.files[0])
        h, w = first.height, first.width
        formats = {first.format}
        for path in self.files[1:]:
            img = _open_rgb(path)
            formats.add(img.format)
            if (img.height, img.width) != (h, w):
                raise LanternaInputError(path, f"is {img.width}x{img.height}, but "
                                         f"{self.files[0].name} is {w}x{h}: all images of a "
                                         "collection must have the same size")
        self.shape = (len(self.files), h, w, 3)
        self.format = first.format if len(formats) == 1 else None
        self.reopen = reopen
        self._regions: list[tuple[pyvips.Image, pyvips.Region]] = []
        self._next_row = 0

    def __len__(self) -> int:
        return self.shape[0]

    def close(self) -> None:
        """Release the decoders of the current pass (a later read starts a new pass)."""
        self._regions = []

    def decoder_bytes(self) -> int:
        """Memory libvips holds for the open decoders of one pass (0 when reopening per band)."""
        return 0 if self.reopen else len(self.files) * self.shape[2] * DECODER_BYTES_PER_COLUMN

    def __getstate__(self) -> dict[str, Any]:
        """Pickle the file list and shape only (libvips regions stay behind; reopened lazily)."""
        return {"files": self.files, "shape": self.shape, "reopen": self.reopen,
                "format": self.format}

    def __setstate__(self, state: dict[str, Any]) -> None:
        self.files, self.shape = state["files"], state["shape"]
        self.reopen = state.get("reopen", False)
        self.format = state.get("format")
        self._regions = []
        self._next_row = 0

    def rows(self, y0: int, y1: int) -> npt.NDArray[np.float32]:
        """Return rows ``y0:y1`` of every image as ``(N, y1 − y0, W, 3)`` float32 in 0–1."""
        n, h, w, _ = self.shape
        y0, y1 = max(0, y0), min(h, y1)
        out = np.empty((n, max(0, y1 - y0), w, 3), np.float32)
        for i, (band, full_scale) in enumerate(self.native_rows(y0, y1)):
            to_unit(band, full_scale, out[i])
        return out

    def band_into(self, y0: int, y1: int, out: npt.NDArray[np.generic],
                  pool: Executor | None = None) -> float:
        """Copy rows ``y0:y1`` of every image as stored into ``out`` ``(N, y1 − y0, W, 3)``
        (the images' sample format: :meth:`native_dtype`) and return the divisor to 0–1
        (1.0 for float).  ``pool`` decodes the files in its threads (libvips runs without the
        GIL), so a band is decoded on every core instead of one."""
        n = self.shape[0]
        self._open_pass(y0)

        def copy(i: int) -> float | None:
            return self._fetch(i, y0, y1, out[i])[1]
        scales = _in_runs(copy, n, pool)
        self._next_row = y1
        return (scales[0] or 1.0) if scales else 1.0

    def native_dtype(self) -> np.dtype[Any] | None:
        """The numpy dtype of the images' samples as stored, ``None`` if they differ (such a
        collection is read as float, by :meth:`rows`)."""
        return None if self.format is None else np.dtype(_NUMPY_FORMAT[self.format])

    def _open_pass(self, y0: int) -> None:
        if not self.reopen and (not self._regions or y0 < self._next_row):
            self._regions = []
            for path in self.files:
                img = _open_rgb(path)
                self._regions.append((img, pyvips.Region.new(img)))

    def _fetch(self, i: int, y0: int, y1: int, out: npt.NDArray[np.generic] | None = None
               ) -> tuple[npt.NDArray[np.generic], float | None]:
        """Rows ``y0:y1`` of image ``i`` as stored, into ``out`` ``(y1 − y0, W, 3)`` if given;
        a sequential pass fetches them :data:`FETCH_ROWS` at a time."""
        path, w, regions = self.files[i], self.shape[2], self._regions
        # reopen: tiled files, each opened for these rows only (no decoder state kept) and
        # fetched at once (in strips, each strip would decode its tiles again)
        img = _open_rgb(path, "random") if self.reopen else regions[i][0]
        region = pyvips.Region.new(img) if self.reopen else regions[i][1]
        dtype = _NUMPY_FORMAT[img.format]
        band = np.empty((y1 - y0, w, 3), dtype) if out is None else out
        step = max(1, y1 - y0) if self.reopen else FETCH_ROWS
        try:
            for s0 in range(y0, y1, step):
                s1 = min(y1, s0 + step)
                raw = region.fetch(0, s0, w, s1 - s0)
                band[s0 - y0:s1 - y0] = np.frombuffer(raw, dtype).reshape(s1 - s0, w, 3)
        except pyvips.Error as err:
            self._regions = []
            first = str(err).strip().splitlines()[0] if str(err).strip() else "read error"
            raise LanternaInputError(path, f"cannot read image ({first})") from None
        return band, _FULL_SCALE.get(img.format)

    def native_rows(self, y0: int, y1: int, pool: Executor | None = None
                    ) -> list[tuple[npt.NDArray[np.generic], float | None]]:
        """Rows ``y0:y1`` of every image as stored: per image ``(rows, W, 3)`` in its sample
        format (a copy of the decoded bytes) and the divisor to 0–1 (``None`` for float).

        A quarter of the float32 band's memory for 8-bit images; :func:`to_unit` of each gives
        exactly :meth:`rows`.  ``pool`` decodes the files in its threads (as :meth:`band_into`).
        """
        n, h, w, _ = self.shape
        y0, y1 = max(0, y0), min(h, y1)
        if y1 <= y0:
            return [(np.empty((0, w, 3), np.uint8), 255.0) for _ in self.files]
        self._open_pass(y0)
        bands = _in_runs(lambda i: self._fetch(i, y0, y1), n, pool)
        self._next_row = y1
        return bands

    def subset(self, indices: Sequence[int] | npt.NDArray[np.integer]) -> StackReader:
        """Return a reader over the images ``indices`` (in that order)."""
        sub = object.__new__(StackReader)
        sub.files = [self.files[int(i)] for i in indices]
        sub.shape = (len(sub.files), *self.shape[1:])
        sub.reopen = self.reopen
        sub.format = self.format
        sub._regions = []
        sub._next_row = 0
        return sub

    def __getitem__(self, key: Any) -> Any:
        if isinstance(key, (int, np.integer)):
            return load_image(self.files[int(key)])
        if isinstance(key, tuple) and len(key) == 2 and key[0] == slice(None) \
                and isinstance(key[1], slice) and key[1].step in (None, 1):
            start, stop, _ = key[1].indices(self.shape[1])
            return self.rows(start, stop)
        if isinstance(key, (list, np.ndarray)):
            return self.subset(np.asarray(key, np.intp).reshape(-1))
        raise TypeError(f"StackReader supports [i], [indices] and [:, y0:y1], not {key!r}")


def _in_runs(task: Callable[[int], _T], n: int, pool: Executor | None) -> list[_T]:
    """``[task(i) for i in range(n)]``, in :data:`DECODE_THREADS` runs of consecutive ``i`` on
    ``pool`` (one task per file costs more CPU in handoffs and cache misses than it gains:
    0.53 s against 0.44 s of CPU to decode 24 2048² JPEGs on two threads)."""
    if pool is None or n < 2 or DECODE_THREADS < 2:
        return [task(i) for i in range(n)]
    runs = min(n, DECODE_THREADS)
    cuts = [n * r // runs for r in range(runs + 1)]
    done = pool.map(lambda a, b: [task(i) for i in range(a, b)], cuts[:-1], cuts[1:])
    return [x for run in done for x in run]
