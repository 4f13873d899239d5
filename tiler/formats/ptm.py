"""Read HP Polynomial Texture Map (``.ptm``) files into a :class:`~.ptm_model.Ptm`.

Supported: ``PTM_1.1`` and ``PTM_1.2`` headers with the formats ``PTM_FORMAT_RGB``,
``PTM_FORMAT_LRGB``, ``PTM_FORMAT_JPEG_LRGB`` and ``PTM_FORMAT_JPEG_RGB``. Layouts follow
``/work/shared/notes/rti-formats.md`` §1: rows are stored bottom-up (also inside the JPEG
streams), JPEG planes may be predicted from an earlier plane, and 5-byte side-info records
overwrite single pixels after prediction.

Every problem with the input raises :class:`~lanterna.errors.LanternaInputError`
with a one-line message.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import numpy.typing as npt
import pyvips

from lanterna.errors import LanternaInputError
from lanterna.tiler.fileio import read_input
from lanterna.tiler.limits import check_pixels, check_quantisation

from .ptm_model import Ptm

#: Header versions we read.
PTM_VERSIONS = ("PTM_1.2", "PTM_1.1")
#: Formats we read, mapped to (colorspace, JPEG-compressed).
PTM_FORMATS = {
    "PTM_FORMAT_RGB": ("rgb", False),
    "PTM_FORMAT_LRGB": ("lrgb", False),
    "PTM_FORMAT_JPEG_RGB": ("rgb", True),
    "PTM_FORMAT_JPEG_LRGB": ("lrgb", True),
}
#: Formats that exist in the HP spec but that no reader supports.
_KNOWN_UNSUPPORTED = (
    "PTM_FORMAT_LUM",
    "PTM_FORMAT_PTM_LUT",
    "PTM_FORMAT_PTM_C_LUT",
    "PTM_FORMAT_JPEGLS_RGB",
    "PTM_FORMAT_JPEGLS_LRGB",
)
#: Largest width or height accepted (the JPEG limit).
MAX_SIDE = 65500
_SIDE_RECORD = 5


@dataclass(frozen=True)
class PtmHeader:
    """The fixed part of a PTM header (lines 1–6)."""

    version: str
    format: str
    width: int
    height: int
    scale: npt.NDArray[np.float32]
    bias: npt.NDArray[np.int32]


@dataclass(frozen=True)
class JpegInfo:
    """The JPEG-only header lines, one entry per stream (9 for LRGB, 18 for RGB)."""

    quality: int
    transform: tuple[int, ...]
    order: tuple[int, ...]
    reference: tuple[int, ...]
    sizes: tuple[int, ...]
    side_sizes: tuple[int, ...]


class _Lines:
    """Hand out the ASCII header lines of ``data`` one by one, tracking the byte offset."""

    def __init__(self, data: bytes, source: Path) -> None:
        self.data = data
        self.source = source
        self.offset = 0

    def next(self, what: str) -> str:
        end = self.data.find(b"\n", self.offset, self.offset + 4096)
        if end < 0:
            raise LanternaInputError(self.source, f"header ends before the {what} line")
        raw = self.data[self.offset : end]
        self.offset = end + 1
        try:
            return raw.decode("ascii").strip()
        except UnicodeDecodeError:
            raise LanternaInputError(self.source, f"header {what} line is not ASCII text") from None

    def ints(self, what: str, count: int) -> tuple[int, ...]:
        values = self.numbers(what, count)
        if any(not v.is_integer() for v in values):
            raise LanternaInputError(self.source, f"header {what} line must hold integers")
        return tuple(int(v) for v in values)

    def numbers(self, what: str, count: int) -> tuple[float, ...]:
        line = self.next(what)
        tokens = line.split()
        if len(tokens) != count:
            raise LanternaInputError(
                self.source, f"header {what} line has {len(tokens)} values, expected {count}"
            )
        try:
            values = tuple(float(t) for t in tokens)
        except ValueError:
            raise LanternaInputError(
                self.source, f"header {what} line is not numeric: {_clip(line)!r}"
            ) from None
        if not all(math.isfinite(v) for v in values):
            raise LanternaInputError(self.source, f"header {what} line has a non-finite value")
        return values


def _clip(text: str, n: int = 40) -> str:
    return text if len(text) <= n else text[:n] + "…"


def _parse_header(lines: _Lines) -> PtmHeader:
    src = lines.source
    version = lines.next("version")
    if not version.startswith("PTM_"):
        raise LanternaInputError(src, "not a PTM file (first line does not start with PTM_)")
    if version not in PTM_VERSIONS:
        raise LanternaInputError(src, f"unsupported PTM version {_clip(version)!r}")
    fmt = lines.next("format")
    if fmt in _KNOWN_UNSUPPORTED:
        raise LanternaInputError(src, f"unsupported PTM format {fmt}")
    if fmt not in PTM_FORMATS:
        raise LanternaInputError(src, f"unknown PTM format line {_clip(fmt)!r}")
    (width,) = lines.ints("width", 1)
    (height,) = lines.ints("height", 1)
    for name, value in (("width", width), ("height", height)):
        if value <= 0:
            raise LanternaInputError(src, f"{name} must be positive, got {value}")
        if value > MAX_SIDE:
            raise LanternaInputError(src, f"{name} {value} is too large (max {MAX_SIDE})")
    check_pixels(src, width, height, "the PTM")
    scale = np.array(lines.numbers("scale", 6), dtype=np.float32)
    if not np.isfinite(scale).all():
        raise LanternaInputError(src, "header scale value too large for float32")
    bias_values = lines.ints("bias", 6)
    if any(abs(b) > 2**31 - 1 for b in bias_values):
        raise LanternaInputError(src, "header bias value out of range")
    bias = np.array(bias_values, dtype=np.int32)
    # stored as (t − b/255)·s (docs/dataset-format.md): bounded for float32 shading
    check_quantisation(src, scale.tolist(), (bias / 255.0).tolist(), "header")
    return PtmHeader(version, fmt, width, height, scale, bias)


def _parse_jpeg_info(lines: _Lines, n: int) -> JpegInfo:
    src = lines.source
    (quality,) = lines.ints("JPEG quality", 1)
    transform = lines.ints("transform", n)
    motion_x = lines.ints("motion-x", n)
    motion_y = lines.ints("motion-y", n)
    order = lines.ints("order", n)
    reference = lines.ints("reference", n)
    sizes = lines.ints("compressed sizes", n)
    side_sizes = lines.ints("side-info sizes", n)
    if any(motion_x) or any(motion_y):
        raise LanternaInputError(src, "non-zero JPEG motion vectors are not supported")
    if any(t < 0 or t > 1 for t in transform):
        raise LanternaInputError(src, f"unsupported plane transform in {list(transform)}")
    if sorted(order) != list(range(n)):
        raise LanternaInputError(src, f"order line is not a permutation of 0..{n - 1}")
    for i, r in enumerate(reference):
        if r == -1:
            continue
        if not 0 <= r < n or r == i:
            raise LanternaInputError(src, f"plane {i} has an invalid reference plane {r}")
        if order[r] >= order[i]:
            raise LanternaInputError(src, f"plane {i} is decoded before its reference {r}")
    if any(s <= 0 for s in sizes):
        raise LanternaInputError(src, "JPEG compressed sizes must be positive")
    if any(s < 0 or s % _SIDE_RECORD for s in side_sizes):
        raise LanternaInputError(src, "side-info sizes must be non-negative multiples of 5")
    return JpegInfo(quality, transform, order, reference, sizes, side_sizes)


def read_ptm(path: str | Path) -> Ptm:
    """Read a ``.ptm`` file.

    Parameters
    ----------
    path:
        The file to read.

    Returns
    -------
    Ptm
        The coefficients as stored (``uint8``), rows top-down, with the header's
        per-coefficient scale and bias.

    Raises
    ------
    LanternaInputError
        If the file is missing, is not a PTM, uses an unsupported format, or its header and
        payload are inconsistent or corrupt.
    """
    src = Path(path)
    data = read_input(src, "a PTM file")
    if not data.startswith(b"PTM_"):
        raise LanternaInputError(src, "not a PTM file (does not start with PTM_)")
    lines = _Lines(data, src)
    header = _parse_header(lines)
    colorspace, compressed = PTM_FORMATS[header.format]
    if compressed:
        n = 9 if colorspace == "lrgb" else 18
        info = _parse_jpeg_info(lines, n)
        planes = _decode_jpeg_planes(data, lines.offset, header, info, src)
        return _ptm_from_planes(header, colorspace, planes)
    return _decode_raw(data[lines.offset :], header, colorspace, src)


def _decode_raw(payload: bytes, header: PtmHeader, colorspace: str, src: Path) -> Ptm:
    h, w = header.height, header.width
    per_texel = 18 if colorspace == "rgb" else 9
    expected = h * w * per_texel
    if len(payload) != expected:
        side = "short" if len(payload) < expected else "long"
        raise LanternaInputError(
            src,
            f"payload is too {side}: {len(payload)} bytes, the header implies {expected}"
            f" ({w}x{h} {header.format})",
        )
    buf = np.frombuffer(payload, dtype=np.uint8)
    if colorspace == "rgb":
        # Three blocks R, G, B; each block bottom-up with 6 bytes per texel.
        blocks = buf.reshape(3, h, w, 6)[:, ::-1]
        coeffs = np.ascontiguousarray(blocks.transpose(1, 2, 0, 3))
        return Ptm("rgb", coeffs, header.scale, header.bias)
    if header.version == "PTM_1.1":
        texels = buf.reshape(h, w, 9)[::-1]
        coeffs, rgb = texels[..., :6], texels[..., 6:]
    else:
        coeffs = buf[: h * w * 6].reshape(h, w, 6)[::-1]
        rgb = buf[h * w * 6 :].reshape(h, w, 3)[::-1]
    return Ptm(
        "lrgb",
        np.ascontiguousarray(coeffs),
        header.scale,
        header.bias,
        np.ascontiguousarray(rgb),
    )


def _check_jpeg_header(buf: bytes, header: PtmHeader, plane: int, src: Path) -> pyvips.Image:
    """Open one JPEG stream (its header only: nothing is decoded) and check it against the PTM
    header; return the lazy image."""
    if not buf.startswith(b"\xff\xd8"):
        raise LanternaInputError(src, f"JPEG stream {plane} does not start with a JPEG marker")
    try:
        image = pyvips.Image.jpegload_buffer(buf, fail_on="warning")
        bands, width, height = image.bands, image.width, image.height
        fmt = image.format
    except pyvips.Error as exc:
        reason = " ".join(str(exc.detail or exc.message).split())
        raise LanternaInputError(
            src, f"JPEG stream {plane} is corrupt or truncated ({_clip(reason, 80)})"
        ) from None
    if bands != 1 or width != header.width or height != header.height:
        raise LanternaInputError(
            src,
            f"JPEG stream {plane} is {width}x{height} with {bands} bands,"
            f" expected single-band {header.width}x{header.height}",
        )
    if fmt != "uchar":
        raise LanternaInputError(src, f"JPEG stream {plane} is not 8-bit")
    return image


def _decode_jpeg(image: pyvips.Image, header: PtmHeader, plane: int,
                 src: Path) -> npt.NDArray[np.uint8]:
    """Decode one opened JPEG stream (:func:`_check_jpeg_header`) to an ``(H, W)`` array in
    JPEG raster order."""
    try:
        pixels = image.write_to_memory()
    except pyvips.Error as exc:
        reason = " ".join(str(exc.detail or exc.message).split())
        raise LanternaInputError(
            src, f"JPEG stream {plane} is corrupt or truncated ({_clip(reason, 80)})"
        ) from None
    return np.frombuffer(pixels, dtype=np.uint8).reshape(header.height, header.width).copy()


def _decode_jpeg_planes(
    data: bytes, start: int, header: PtmHeader, info: JpegInfo, src: Path
) -> npt.NDArray[np.uint8]:
    """Decode all JPEG planes; return ``(n, H, W)`` uint8 with rows top-down."""
    n = len(info.sizes)
    offsets = [start]
    for size, side_size in zip(info.sizes, info.side_sizes, strict=True):
        offsets.append(offsets[-1] + size + side_size)
    if len(data) != offsets[-1]:
        which = "short" if len(data) < offsets[-1] else "long"
        raise LanternaInputError(
            src,
            f"payload is too {which}: {len(data) - start} bytes,"
            f" the header implies {offsets[-1] - start}",
        )
    # every stream's own header, before anything is allocated or decoded
    streams = [_check_jpeg_header(data[offsets[i]: offsets[i] + info.sizes[i]], header, i, src)
               for i in range(n)]
    h, w = header.height, header.width
    planes = np.zeros((n, h, w), dtype=np.uint8)
    for plane in sorted(range(n), key=lambda i: info.order[i]):
        begin = offsets[plane]
        jpeg_end = begin + info.sizes[plane]
        values = _decode_jpeg(streams[plane], header, plane, src)
        ref = info.reference[plane]
        if ref >= 0:
            base = planes[ref].astype(np.int16)
            if info.transform[plane] & 1:
                base = 255 - base
            values = ((base + values.astype(np.int16) - 128) % 256).astype(np.uint8)
        side = np.frombuffer(data[jpeg_end : offsets[plane + 1]], dtype=np.uint8)
        if side.size:
            records = side.reshape(-1, _SIDE_RECORD)
            index = records[:, :4].astype(np.int64) @ np.array([1 << 24, 1 << 16, 1 << 8, 1])
            if int(index.max()) >= h * w:
                raise LanternaInputError(
                    src,
                    f"side-info index {int(index.max())} of plane {plane} is out of range"
                    f" (plane has {h * w} pixels)",
                )
            values.reshape(-1)[index] = records[:, 4]
        planes[plane] = values
    # JPEG rows are bottom-up like the rest of the format; prediction and side info work in
    # stream order, so flip only at the end.
    return np.ascontiguousarray(planes[:, ::-1])


def _ptm_from_planes(header: PtmHeader, colorspace: str, planes: npt.NDArray[np.uint8]) -> Ptm:
    h, w = header.height, header.width
    if colorspace == "lrgb":
        coeffs = np.ascontiguousarray(planes[:6].transpose(1, 2, 0))
        rgb = np.ascontiguousarray(planes[6:].transpose(1, 2, 0))
        return Ptm("lrgb", coeffs, header.scale, header.bias, rgb, lossy=True)
    # Stream i is colour i // 6, coefficient i % 6.
    coeffs = np.ascontiguousarray(planes.reshape(3, 6, h, w).transpose(2, 3, 0, 1))
    return Ptm("rgb", coeffs, header.scale, header.bias, lossy=True)
