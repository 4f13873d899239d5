"""Checks on an uploaded patch PNG made from its header alone, before anything decodes it.

A PNG starts with its 8-byte signature and an ``IHDR`` chunk (width, height, bit depth, colour
type: RFC 2083 §4.1.1). From those 33 bytes we refuse what is not a PNG, what is too large to
decode safely (:data:`MAX_SIDE`, :data:`MAX_PIXELS`) and what cannot have an alpha channel
(colour types 4 and 6 have one; 0, 2 and 3 only with a ``tRNS`` chunk, looked for before
``IDAT``). Pure: bytes in, a one-line problem out.
"""

from __future__ import annotations

import struct
from dataclasses import dataclass

SIGNATURE = b"\x89PNG\r\n\x1a\n"
#: Largest side of a patch PNG, in pixels.
MAX_SIDE = 8192
#: Largest area of a patch PNG, in pixels (16.8 Mpx, as the image server's default).
MAX_PIXELS = 16_800_000
#: Colour types with an alpha channel of their own; the others need a ``tRNS`` chunk.
_ALPHA_TYPES = {4, 6}
_COLOUR_TYPES = {0: "grey", 2: "RGB", 3: "palette", 4: "grey + alpha", 6: "RGBA"}


class PngHeaderError(ValueError):
    """A PNG refused from its header; ``too_large`` tells a 413 from a 400."""

    def __init__(self, problem: str, *, too_large: bool = False) -> None:
        super().__init__(problem)
        self.too_large = too_large


@dataclass(frozen=True)
class PngHeader:
    """The facts of a PNG's ``IHDR``: size, bit depth, colour type."""

    width: int
    height: int
    bit_depth: int
    colour_type: int


def read_header(data: bytes) -> PngHeader:
    """Check the signature and ``IHDR`` of ``data``; return them or raise :class:`PngHeaderError`.

    Refuses: not a PNG, a malformed header, a side over :data:`MAX_SIDE` or an area over
    :data:`MAX_PIXELS` (``too_large``), and an image without alpha (no alpha colour type and no
    ``tRNS`` chunk before the first ``IDAT``).
    """
    if not data.startswith(SIGNATURE):
        raise PngHeaderError("the image is not a PNG (no PNG signature)")
    if len(data) < 33 or data[12:16] != b"IHDR" or struct.unpack(">I", data[8:12])[0] != 13:
        raise PngHeaderError("the image is not a valid PNG (no IHDR header)")
    width, height, depth, colour = struct.unpack(">IIBB", data[16:26])
    if width < 1 or height < 1 or colour not in _COLOUR_TYPES:
        raise PngHeaderError(f"the image is not a valid PNG (IHDR {width}x{height}, colour "
                             f"type {colour})")
    if max(width, height) > MAX_SIDE or width * height > MAX_PIXELS:
        raise PngHeaderError(f"the image is {width}x{height}; patch images are at most "
                             f"{MAX_SIDE} px a side and {MAX_PIXELS / 1e6:.1f} Mpx",
                             too_large=True)
    if colour not in _ALPHA_TYPES and not has_trns(data):
        raise PngHeaderError(f"the image has no alpha channel ({_COLOUR_TYPES[colour]} PNG "
                             "without transparency); patches must be RGBA")
    return PngHeader(width, height, depth, colour)


def has_trns(data: bytes) -> bool:
    """Whether a ``tRNS`` chunk comes before the first ``IDAT`` (walking the chunk list)."""
    pos = len(SIGNATURE)
    while pos + 8 <= len(data):
        length, kind = struct.unpack(">I4s", data[pos:pos + 8])
        if kind == b"tRNS":
            return True
        if kind in (b"IDAT", b"IEND"):
            return False
        pos += 12 + length
    return False
