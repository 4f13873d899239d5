"""Relight's PCA bases in a web-format folder: types ``rbf`` and ``bilinear``, ``mrgb`` / ``mycc``.

Facts from Relight's ``src/rti.cpp`` (``Rti::load``) and ``src/cli/rtibuilder.cpp``
(``saveJSON``, ``save``); the semantics are :mod:`.pca_model`'s. ``info.json`` holds:

- ``nplanes`` N (``mrgb``), or instead ``yccplanes: [ny, nc, nc]`` (``mycc``: Relight writes
  ``yccplanes`` *instead of* ``nplanes``, and N = ny + 2·nc);
- ``materials[0].range`` (N numbers > 0) beside the usual per-plane ``scale`` / ``bias``;
- ``rbf``: ``lights`` (D·3 numbers, the acquisition lights) and ``sigma`` > 0;
  ``bilinear``: ``resolution`` R ≥ 2 (D = R²; its ``lights`` are not used);
- the basis, (N + 1)·D·3 bytes, as the ``basis`` array (current Relight), or — older outputs,
  e.g. Relight's own ``test/rbf27`` — in the file ``materials.bin`` beside ``info.json``, the
  same bytes in the same order.

Plane ``q`` of the folder (channel ``q % 3`` of ``plane_{q // 3}``) is the coefficient ``P{q}``
of the layer, kept byte for byte with its scale and bias (docs/dataset-format.md, ``rbf``).
"""

from __future__ import annotations

import math
import os
import stat
from pathlib import Path
from typing import Any

import numpy as np
import numpy.typing as npt

from lanterna.errors import LanternaInputError
from lanterna.tiler.fileio import read_input

from .pca_model import MAX_PCA_PLANES, PcaBasis, plane_channel_names
from .planes import PlaneGroup

#: Most light samples D a basis may have (acquisition lights of an rbf, R² of a bilinear grid).
MAX_PCA_DIMENSIONS = 1024
#: The file older Relight outputs keep the basis in.
MATERIALS_BIN = "materials.bin"


def pca_nplanes(info: dict[str, Any], path: Path, colorspace: str) -> int:
    """N of a PCA folder: ``nplanes``, or ``sum(yccplanes)`` for ``mycc`` (checked)."""
    if colorspace == "mycc":
        ycc = info.get("yccplanes")
        if ycc is None:
            raise LanternaInputError(path, "mycc needs 'yccplanes' [ny, nc, nc]")
        ny, nc, nc2 = ycc  # the schema makes it three integers ≥ 0
        if nc != nc2 or ny < nc or ny + 2 * nc < 1:
            raise LanternaInputError(path, f"'yccplanes' must be [ny, nc, nc] with ny ≥ nc and "
                                     f"ny + 2·nc ≥ 1, got {list(ycc)}")
        n = int(ny + 2 * nc)
        if "nplanes" in info and as_int(info["nplanes"], "nplanes", path) != n:
            raise LanternaInputError(path, f"'nplanes' {info['nplanes']!r} disagrees with "
                                     f"'yccplanes' {list(ycc)} (ny + 2·nc = {n})")
    else:
        if "nplanes" not in info:
            raise LanternaInputError(path, f"{colorspace} needs 'nplanes'")
        n = as_int(info["nplanes"], "nplanes", path)
    if not 1 <= n <= MAX_PCA_PLANES:
        raise LanternaInputError(path, f"'nplanes' must be 1 to {MAX_PCA_PLANES} for a PCA basis, "
                                 f"got {n}")
    return n


def read_pca_basis(info: dict[str, Any], path: Path, rtype: str, colorspace: str,
                   nplanes: int) -> PcaBasis:
    """The folder's :class:`~.pca_model.PcaBasis`, every field checked (one-line errors)."""
    ranges = _ranges(info, path, nplanes)
    lights: tuple[float, ...] | None = None
    sigma: float | None = None
    resolution: int | None = None
    if rtype == "rbf":
        lights = _lights(info, path)
        sigma = info.get("sigma")
        if not isinstance(sigma, int | float) or isinstance(sigma, bool) or not (
                math.isfinite(sigma) and sigma > 0):
            raise LanternaInputError(path, f"rbf needs 'sigma' > 0, got {sigma!r}")
        sigma = float(sigma)
        ndim = len(lights) // 3
    else:
        resolution = as_int(info.get("resolution"), "resolution", path)
        top = math.isqrt(MAX_PCA_DIMENSIONS)
        if not 2 <= resolution <= top:
            raise LanternaInputError(path, f"bilinear needs 'resolution' 2 to {top}, got "
                                     f"{resolution}")
        ndim = resolution * resolution
    basis = _basis(info, path, (nplanes + 1) * ndim * 3, nplanes, ndim)
    ycc = info.get("yccplanes") if colorspace == "mycc" else None
    return PcaBasis(rtype, colorspace, basis, ranges, lights, sigma, resolution,
                    (int(ycc[0]), int(ycc[1]), int(ycc[2])) if ycc is not None else None)


def pca_groups(planes: npt.NDArray[np.uint8], scale: list[float], bias: list[float],
               lossy: bool) -> list[PlaneGroup]:
    """The layer's groups ``P0 P1 P2``, …: the folder's images as they are (padding scale 0)."""
    n = len(scale)
    groups = []
    for g, names in enumerate(plane_channel_names(n)):
        idx = list(range(3 * g, 3 * g + 3))
        data = np.zeros(planes.shape[1:] + (3,), np.uint8)
        for k, q in enumerate(idx):
            if q < n:
                data[..., k] = planes[q]
        groups.append(PlaneGroup(names, data, [scale[q] if q < n else 0.0 for q in idx],
                                 [bias[q] if q < n else 0.0 for q in idx], lossy))
    return groups


def as_int(value: Any, key: str = "nplanes", path: Path | None = None) -> int:
    """``value`` as an integer (or its decimal text), else a one-line error naming ``key``."""
    if isinstance(value, str) and value.strip().isdigit():
        value = int(value)
    if isinstance(value, bool) or not isinstance(value, int):
        raise LanternaInputError(path, f"{key!r} must be an integer, got {value!r}")
    return value


def _ranges(info: dict[str, Any], path: Path, nplanes: int) -> tuple[float, ...]:
    materials = info.get("materials")
    holder = materials[0] if isinstance(materials, list) and materials else {}
    values = holder.get("range") if isinstance(holder, dict) else None
    if not isinstance(values, list) or len(values) != nplanes:
        got = f"{len(values)} values" if isinstance(values, list) else repr(values)
        raise LanternaInputError(path, f"materials[0].range must list {nplanes} numbers > 0 "
                                 f"(one per plane), got {got}")
    for i, v in enumerate(values):
        if not isinstance(v, int | float) or isinstance(v, bool) or not (
                math.isfinite(v) and v > 0):
            raise LanternaInputError(path, f"materials[0].range[{i}] must be a finite number "
                                     f"> 0, got {v!r}")
    return tuple(float(v) for v in values)


def _lights(info: dict[str, Any], path: Path) -> tuple[float, ...]:
    values = info.get("lights")
    if not isinstance(values, list) or not values or len(values) % 3:
        got = f"{len(values)} numbers" if isinstance(values, list) else repr(values)
        raise LanternaInputError(path, f"rbf needs 'lights': D·3 numbers (x, y, z per "
                                 f"acquisition light), got {got}")
    if len(values) // 3 > MAX_PCA_DIMENSIONS:
        raise LanternaInputError(path, f"'lights' lists {len(values) // 3} lights; at most "
                                 f"{MAX_PCA_DIMENSIONS} are supported")
    for i, v in enumerate(values):
        if not isinstance(v, int | float) or isinstance(v, bool) or not math.isfinite(v):
            raise LanternaInputError(path, f"lights[{i}] must be a finite number, got {v!r}")
    return tuple(float(v) for v in values)


def _basis(info: dict[str, Any], path: Path, size: int, nplanes: int,
           ndim: int) -> npt.NDArray[np.uint8]:
    """The basis bytes from ``info.json``'s ``basis`` or, without it, ``materials.bin``."""
    shape = f"(nplanes + 1)·ndimensions·3 = ({nplanes} + 1)·{ndim}·3 = {size}"
    values = info.get("basis")
    if values is None:
        return _materials_bin(path.parent / MATERIALS_BIN, size, shape)
    if not isinstance(values, list) or len(values) != size:
        got = f"{len(values)} values" if isinstance(values, list) else repr(values)
        raise LanternaInputError(path, f"'basis' must list {shape} integers 0–255, got {got}")
    arr = np.asarray(values, dtype=object)
    for i, v in enumerate(arr):
        if isinstance(v, bool) or not isinstance(v, int | float) or v != int(v) or not (
                0 <= v <= 255):
            raise LanternaInputError(path, f"basis[{i}] must be an integer 0–255, got {v!r}")
    return np.asarray(values, np.float64).astype(np.uint8)


def _materials_bin(src: Path, size: int, shape: str) -> npt.NDArray[np.uint8]:
    try:
        info = os.stat(src)
    except FileNotFoundError:
        raise LanternaInputError(src.with_name("info.json"), f"no 'basis' and no {MATERIALS_BIN} "
                                 "beside info.json: the PCA basis is missing") from None
    except OSError as exc:
        raise LanternaInputError(src, f"cannot read file ({exc.strerror})") from None
    if stat.S_ISREG(info.st_mode) and info.st_size != size:
        raise LanternaInputError(src, f"is {info.st_size:,} bytes; the basis is {shape} bytes")
    data = read_input(src, "a Relight basis (materials.bin)", max_bytes=size)
    if len(data) != size:  # changed while read
        raise LanternaInputError(src, f"is {len(data):,} bytes; the basis is {shape} bytes")
    return np.frombuffer(data, np.uint8).copy()
