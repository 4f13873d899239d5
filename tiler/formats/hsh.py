"""Read and write HSH ``.rti`` files ("universal RTI" from hshfitter / RTIBuilder / Relight).

Layout (``/work/shared/notes/rti-formats.md`` §2.1)::

    #HSH1.2                    any number of '#' comment lines (before the type line only)
    3                          RTI type: 3 = HSH (1 PTM, 2 SH, 4 adaptive basis are not supported)
    320 470 3                  width height colours (3)
    9 2 1                      basis terms (4, 9, 16; legacy 1 → 4, 2 → 9), basis type, element size
    float32 scale[terms]       little-endian
    float32 bias[terms]
    payload                    rows TOP-DOWN; per pixel R[terms], G[terms], B[terms]

Header lines end in CRLF (hshfitter) or LF (Relight). With byte elements a coefficient is
``a = byte/255·scale + bias``. With float32 elements (``element size 4``, which hshfitter writes
with scale 1 and bias 0) it is ``a = value·scale + bias``; the reader then quantises each term to
bytes with one scale/bias shared by R, G and B over the whole image:
``scale = max − min``, ``bias = min``, ``byte = round((a − min)/(max − min)·255)``.

Every problem with the input raises :class:`~lanterna.errors.LanternaInputError` with a
one-line message.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import numpy.typing as npt

from lanterna.errors import LanternaInputError
from lanterna.tiler.fileio import read_input
from lanterna.tiler.limits import check_pixels, check_quantisation

from .hsh_model import HSH_TERMS, Hsh
from .layouts import hsh_plane_quantisation

#: RTI type codes of the universal header, for error messages.
RTI_TYPES = {0: "reserved", 1: "PTM", 2: "SH", 3: "HSH", 4: "adaptive basis"}
#: Legacy basis-term codes that RTIViewer (``universalrti.cpp``) maps to term counts.
_LEGACY_TERMS = {1: 4, 2: 9}
_MAX_LINE = 4096


class _Header:
    """Hand out the ASCII header lines one by one, tracking the byte offset."""

    def __init__(self, data: bytes, source: Path) -> None:
        self.data = data
        self.source = source
        self.offset = 0

    def line(self, what: str) -> str:
        end = self.data.find(b"\n", self.offset, self.offset + _MAX_LINE)
        if end < 0:
            raise LanternaInputError(self.source, f"header ends before the {what} line")
        raw = self.data[self.offset : end]
        self.offset = end + 1
        try:
            return raw.decode("ascii").strip()
        except UnicodeDecodeError:
            raise LanternaInputError(self.source, f"header {what} line is not ASCII text") from None

    def ints(self, what: str, count: int, first: str | None = None) -> tuple[int, ...]:
        line = self.line(what) if first is None else first
        tokens = line.split()
        if len(tokens) != count:
            raise LanternaInputError(
                self.source, f"header {what} line has {len(tokens)} values, expected {count}"
            )
        try:
            return tuple(int(t) for t in tokens)
        except ValueError:
            raise LanternaInputError(
                self.source, f"header {what} line must hold integers: {_clip(line)!r}"
            ) from None


def _clip(text: str, n: int = 40) -> str:
    return text if len(text) <= n else text[:n] + "…"


def read_rti(path: str | Path) -> Hsh:
    """Read an HSH ``.rti`` file.

    Parameters
    ----------
    path:
        The file to read.

    Returns
    -------
    Hsh
        Coefficients as ``uint8`` ``(H, W, 3, K)``, rows top-down, with the per-term scale and
        bias of the file (byte elements) or of the quantisation described in the module
        docstring (float elements).

    Raises
    ------
    LanternaInputError
        If the file is missing, is not an HSH ``.rti``, or its header and payload disagree.
    """
    src = Path(path)
    data = read_input(src, "an .rti file")
    if data.startswith(b"PTM_"):
        raise LanternaInputError(src, "is a PTM file, not an .rti file (use the PTM reader)")
    header = _Header(data, src)
    line = header.line("RTI type")
    while line.startswith("#"):
        line = header.line("RTI type")
    (rti_type,) = header.ints("RTI type", 1, first=line)
    if rti_type != 3:
        name = RTI_TYPES.get(rti_type, "unknown")
        raise LanternaInputError(
            src, f"unsupported RTI type {rti_type} ({name}); only type 3 (HSH) is supported"
        )
    width, height, colours = header.ints("size", 3)
    if width <= 0 or height <= 0:
        raise LanternaInputError(src, f"image size must be positive, got {width}x{height}")
    if colours != 3:
        raise LanternaInputError(src, f"unsupported colour count {colours}; expected 3 (RGB)")
    check_pixels(src, width, height, "the .rti image")
    terms, basis_type, element_size = header.ints("basis", 3)
    terms = _LEGACY_TERMS.get(terms, terms)
    if terms not in HSH_TERMS:
        raise LanternaInputError(src, f"unsupported HSH term count {terms}; expected 4, 9 or 16")
    if basis_type not in (1, 2):
        raise LanternaInputError(src, f"unknown basis type {basis_type}; expected 1 or 2")
    if element_size not in (1, 4):
        raise LanternaInputError(
            src, f"unsupported element size {element_size}; expected 1 (bytes) or 4 (float32)"
        )
    start = header.offset
    table_end = start + 8 * terms
    if len(data) < table_end:
        raise LanternaInputError(src, "file ends inside the scale/bias table")
    table = np.frombuffer(data[start:table_end], dtype="<f4").astype(np.float32)
    scale, bias = table[:terms].copy(), table[terms:].copy()
    if not (np.isfinite(scale).all() and np.isfinite(bias).all()):
        raise LanternaInputError(src, "scale/bias table holds a non-finite value")
    payload = data[table_end:]
    expected = width * height * 3 * terms * element_size
    if len(payload) != expected:
        side = "short" if len(payload) < expected else "long"
        raise LanternaInputError(
            src,
            f"payload is too {side}: {len(payload)} bytes, the header implies {expected}"
            f" ({width}x{height}, {terms} terms, element size {element_size})",
        )
    if element_size == 1:
        coeffs = np.frombuffer(payload, dtype=np.uint8).reshape(height, width, 3, terms).copy()
        hsh = Hsh(coeffs, scale, bias)
        check_quantisation(src, *hsh_plane_quantisation(hsh), "scale/bias table")
        return hsh
    values = np.frombuffer(payload, dtype="<f4").reshape(height, width, 3, terms)
    if not np.isfinite(values).all():
        raise LanternaInputError(src, "payload holds a non-finite float value")
    a = values.astype(np.float64) * scale.astype(np.float64) + bias.astype(np.float64)
    try:
        hsh = quantize_hsh(a)
    except ValueError as err:
        raise LanternaInputError(src, str(err)) from None
    check_quantisation(src, *hsh_plane_quantisation(hsh), "float coefficients")
    return hsh


def quantize_hsh(coefficients: npt.ArrayLike) -> Hsh:
    """Quantise float HSH coefficients ``(H, W, 3, K)`` (0–1 units) to an :class:`Hsh`.

    Each term gets one scale and bias shared by R, G and B over the whole image:
    ``scale = max − min``, ``bias = min``, ``byte = round((a − min)/scale·255)``. A constant
    term gets ``scale = 0`` and bytes 0. Raises ``ValueError`` if a term's range does not fit
    float32 (the scale and bias are stored, and served, as float32).
    """
    a = np.asarray(coefficients, dtype=np.float64)
    lo = a.min(axis=(0, 1, 2))
    hi = a.max(axis=(0, 1, 2))
    span = hi - lo
    safe = np.where(span > 0, span, 1.0)
    t = np.where(span > 0, (a - lo) / safe * 255.0, 0.0)
    coeffs = np.clip(np.rint(t), 0, 255).astype(np.uint8)
    scale, bias = span.astype(np.float32), lo.astype(np.float32)
    if not (np.isfinite(scale).all() and np.isfinite(bias).all()):
        raise ValueError("coefficient values span more than float32 can hold")
    return Hsh(coeffs, scale, bias)
