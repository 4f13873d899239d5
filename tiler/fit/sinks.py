"""Where the streamed fit's per-band outputs go, and the layers made from them at the end.

Per-pixel encodings (normal maps, Ward maps, the LRGB colour plane) are written straight to
file-backed planes (:class:`~lanterna.tiler.formats.strip_tiff.StripTiffWriter`); PTM/HSH
coefficients need their global range before they can be quantised, so they are appended to a
:class:`Spill` as 16-bit codes over each image row's range (:mod:`.spill_codes`; in memory up to
:data:`SPILL_MEMORY`, then 2 bytes per coefficient per pixel on disk) with the running min/max, and
:meth:`Sinks.finish` makes a second, sequential pass over it that writes the 8-bit planes.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from concurrent.futures import Future, ThreadPoolExecutor
from pathlib import Path
from typing import Any, BinaryIO

import numpy as np
import numpy.typing as npt

from lanterna.tiler.formats.layouts import (
    SVBRDF_MAPS,
    encode_normals,
    hsh_plane_layer,
    ptm_plane_layer,
)
from lanterna.tiler.formats.planes import PlaneGroup, PlaneLayer
from lanterna.tiler.formats.strip_tiff import BandImage, StripTiffWriter
from lanterna.tiler.progress import Progress

from . import bands as fb
from .hsh import hsh_quantisation
from .ptm import ptm_quantisation
from .quantise_kernel import quantise_planes, unit_bytes
from .spill_codes import encode_rows
from .ward import GLOSS_LIMITS

#: Bytes of coefficient codes a run may keep in memory instead of scratch files.
SPILL_MEMORY = 512 << 20
_EMPTY = np.zeros((0, 0, 0), np.uint16)


class Spill:
    """Coefficients appended band by band, with their running range, held as 16-bit codes per
    image row (:mod:`~.spill_codes`: 2 bytes per coefficient).

    A spill whose whole image (``height`` rows) fits what is left of the run's ``budget``
    (a one-item list shared by its spills, :data:`SPILL_MEMORY`) keeps its codes in memory; any
    other writes them to a scratch file.
    """

    def __init__(self, path: Path, height: int, budget: list[int] | None = None) -> None:
        self.path, self.height = path, height
        self.budget = budget if budget is not None else [SPILL_MEMORY]
        self.file: BinaryIO | None = None
        self.held: list[npt.NDArray[np.uint16]] | None = None
        self.lo: npt.NDArray[np.float64] | None = None
        self.hi: npt.NDArray[np.float64] | None = None
        self.shapes: list[tuple[int, ...]] = []
        self.ranges: list[tuple[npt.NDArray[np.float32], npt.NDArray[np.float32]]] = []

    def append(self, values: npt.NDArray[np.float32]) -> None:
        """Append a band ``(b, …, K)``; stored coefficient-major (``(K, b, …)``)."""
        km = np.ascontiguousarray(np.moveaxis(values, -1, 0), np.float32)
        flat = km.reshape(km.shape[0], -1)
        self.append_by_term(km, flat.min(axis=1), flat.max(axis=1))

    def append_by_term(self, km: npt.NDArray[np.float32], band_lo: npt.NDArray[np.generic],
                       band_hi: npt.NDArray[np.generic]) -> None:
        """Append a coefficient-major band ``(K, b, …)`` whose per-term min and max are
        ``band_lo``, ``band_hi``; its rows are coded here (:func:`~.spill_codes.encode_rows`)."""
        self.append_codes(*encode_rows(km.reshape(km.shape[0], km.shape[1], -1)), band_lo,
                          band_hi)

    def append_codes(self, codes: npt.NDArray[np.uint16], row_lo: npt.NDArray[np.float32],
                     row_hi: npt.NDArray[np.float32], band_lo: npt.NDArray[np.generic],
                     band_hi: npt.NDArray[np.generic]) -> None:
        """Append a band's codes ``(K, b, R)`` and its rows' ranges ``(K, b)``
        (:func:`~.spill_codes.encode_rows`: kept, not copied) with its per-term min and max."""
        lo = np.asarray(band_lo, np.float64)
        hi = np.asarray(band_hi, np.float64)
        if not (np.all(np.isfinite(lo)) and np.all(np.isfinite(hi))):
            raise ValueError("the fit produced non-finite coefficients")
        self.lo = lo if self.lo is None else np.minimum(self.lo, lo)
        self.hi = hi if self.hi is None else np.maximum(self.hi, hi)
        if self.held is None and self.file is None:  # the first band decides
            total = codes.nbytes // max(1, codes.shape[1]) * self.height
            if total <= self.budget[0]:
                self.budget[0] -= total
                self.held = []
            else:
                self.file = open(self.path, "wb")  # noqa: SIM115 - closed in bands()
        self.shapes.append(codes.shape)
        self.ranges.append((row_lo, row_hi))
        if self.held is not None:
            self.held.append(codes)
        else:
            assert self.file is not None
            self.file.write(np.ascontiguousarray(codes).data)

    def bands(self) -> Any:
        """Yield the bands back in order: their codes ``(K, b, R)`` and rows' ranges ``(K, b)``
        (each band freed once it is yielded, or the file deleted at the end)."""
        if self.held is None and self.file is None:
            return
        if self.held is not None:
            for i in range(len(self.held)):
                codes, self.held[i] = self.held[i], _EMPTY
                yield (codes, *self.ranges[i])
                del codes
            return
        assert self.file is not None
        self.file.close()
        with open(self.path, "rb") as f:
            for shape, (row_lo, row_hi) in zip(self.shapes, self.ranges, strict=True):
                yield np.fromfile(f, np.uint16, math.prod(shape)).reshape(shape), row_lo, row_hi
        self.path.unlink()


class Sinks:
    """Where each band's outputs go: plane files, or a spill for the globally quantised ones."""

    def __init__(self, scratch: Path, width: int, height: int) -> None:
        self.scratch, self.width, self.height = Path(scratch), width, height
        self.writers: dict[str, StripTiffWriter] = {}
        self.spills: dict[str, Spill] = {}
        self.budget = [SPILL_MEMORY]  # shared by the run's spills

    def _write(self, name: str, rows: npt.NDArray[np.uint8]) -> None:
        if name not in self.writers:
            bands = 3 if rows.ndim == 3 else 1
            self.writers[name] = StripTiffWriter(self.scratch / f"{name}.tif", self.width,
                                                 self.height, bands)
        self.writers[name].write(rows)

    def _spill(self, name: str) -> Spill:
        if name not in self.spills:
            self.spills[name] = Spill(self.scratch / f"{name}.u16", self.height, self.budget)
        return self.spills[name]

    def take(self, outs: dict[str, fb.Out], keys: Sequence[str]) -> None:
        """Store one part of a band: the outputs of the models of ``keys`` that it holds."""
        keys = [k for k in keys if k in outs]
        for k in ("ptm", "ptm-lrgb", "hsh"):
            if k in keys and "codes" in outs[k]:  # a compiled pass's, coded where solved
                o = outs[k]
                self._spill(k).append_codes(np.asarray(o["codes"], np.uint16),
                                            np.asarray(o["rowLo"], np.float32),
                                            np.asarray(o["rowHi"], np.float32), o["lo"], o["hi"])
            elif k in keys:
                self._spill(k).append(np.asarray(outs[k]["coeffs"], np.float32))
        if "ptm-lrgb" in keys:
            self._write("ptm-lrgb-color", np.asarray(outs["ptm-lrgb"]["rgb"], np.uint8))
        if {"normals", "ward"} & set(keys):  # a part with either holds the normals
            self._write("normals", encode_normals(np.asarray(outs["normals"]["normals"],
                                                             np.float32)))
        if "normals" in keys:
            self._write("albedo", unit_bytes(outs["normals"]["albedo"]))
        if "ward" in keys:
            for m in ("kd", "ks", "gloss"):
                self._write(f"ward-{m}", np.asarray(outs["ward"][m], np.uint8))

    def finish(self, keys: Sequence[str], terms: int, space: str,
               progress: Callable[[str, int], Progress] | None) -> dict[str, PlaneLayer]:
        files = {name: wr.close() for name, wr in self.writers.items()}
        layers: dict[str, PlaneLayer] = {}
        for k in ("ptm", "ptm-lrgb", "hsh"):
            if k in keys:
                layers[k] = self._quantise(k, terms, files, progress)
        if "normals" in keys:
            layers["normals"] = _svbrdf([("normals", files["normals"]), ("kd", files["albedo"])],
                                        space)
        if "ward" in keys:
            layers["ward"] = _svbrdf([("normals", files["normals"]), ("kd", files["ward-kd"]),
                                      ("ks", files["ward-ks"]), ("gloss", files["ward-gloss"])],
                                     space)
        return layers

    def _quantise(self, key: str, terms: int, files: dict[str, BandImage],
                  progress: Callable[[str, int], Progress] | None) -> PlaneLayer:
        """Second pass over a spill: the 8-bit planes of a PTM or HSH layer."""
        spill = self.spills[key]
        assert spill.lo is not None and spill.hi is not None
        scale: Any
        bias: Any
        # group name -> its three bytes' (term, channel) in the coefficient-major bands:
        # an HSH term holds its R, G, B; a PTM group three terms of one channel
        parts: dict[str, list[tuple[int, int]]]
        if key == "hsh":
            scale, bias = hsh_quantisation(spill.lo, spill.hi)
            parts = {f"t{t}": [(t, c) for c in range(3)] for t in range(terms)}
        else:
            scale, bias = ptm_quantisation(spill.lo, spill.hi)
            parts = ({f"c{g}": [(3 * g + j, 0) for j in range(3)] for g in range(2)}
                     if key == "ptm-lrgb" else
                     {f"{c}{g}": [(3 * g + j, ci) for j in range(3)]
                      for ci, c in enumerate("rgb") for g in range(2)})
        plan = np.array(list(parts.values()), np.intp)
        writers = {g: StripTiffWriter(self.scratch / f"{key}-{g}.tif", self.width, self.height,
                                      3) for g in parts}
        bar = progress(f"quantising {key}", self.height) if progress else None
        done = 0
        channels = 1 if key == "ptm-lrgb" else 3

        def write(q: npt.NDArray[np.uint8]) -> None:
            for g, rows in zip(parts, q, strict=True):
                writers[g].write(rows.reshape(-1, self.width, 3))

        # each band's planes written by a thread of their own while the next band is quantised
        # (the kernel and the files' writes release the GIL): one band in flight
        with ThreadPoolExecutor(max_workers=1, thread_name_prefix="lanterna-planes") as pool:
            written: Future[None] | None = None
            for codes, row_lo, row_hi in spill.bands():  # (K, b, W · channels), (K, b) twice
                q = quantise_planes(codes, row_lo, row_hi, scale, bias, plan,
                                    hsh=key == "hsh", channels=channels)
                if written is not None:
                    written.result()
                written = pool.submit(write, q)
                done += codes.shape[1]
                if bar:
                    bar.update(done)
            if written is not None:
                written.result()
        planes = {g: wr.close() for g, wr in writers.items()}
        if key == "hsh":
            return hsh_plane_layer([float(s) for s in scale],
                                   [-float(b) / float(s) for s, b in zip(scale, bias, strict=True)],
                                   lambda t: planes[f"t{t}"])
        colorspace = "lrgb" if key == "ptm-lrgb" else "rgb"
        return ptm_plane_layer(
            colorspace, scale, bias,
            lambda c, k: planes[f"c{k.start // 3}" if c is None else f"{'rgb'[c]}{k.start // 3}"],
            files.get("ptm-lrgb-color"))


def _svbrdf(maps: list[tuple[str, BandImage]], space: str) -> PlaneLayer:
    """A shape + material layer from fitted maps (as :func:`~.layers.add_svbrdf_layer`)."""
    groups = []
    for name, data in maps:
        channels, scale, bias = SVBRDF_MAPS[name]
        groups.append(PlaneGroup(channels, data, scale, bias))
    return PlaneLayer("svbrdf", groups, group_names=[name for name, _ in maps],
                      extra={"glossLimits": list(GLOSS_LIMITS), "inputColorSpace": space})
