"""Bounds on the work one input may cause (docs/reliability.md).

Every reader that decodes an image whole checks the pixel count its header declares against
:func:`max_pixels` before it allocates or decodes anything, so a small file declaring a huge image
(a decompression bomb, a corrupt header) is a one-line error, not gigabytes of memory. The limit
is :data:`DEFAULT_MAX_PIXELS` (2³⁰ px: 32768 × 32768); ``--max-pixels N`` on the command line,
or ``LANTERNA_MAX_PIXELS``, raises or lowers it.
"""

from __future__ import annotations

import math
import os
from collections.abc import Iterable
from pathlib import Path

from lanterna.errors import LanternaInputError

#: Largest image, in pixels (width × height), decoded whole unless raised.
DEFAULT_MAX_PIXELS = 1 << 30
#: Environment variable that sets the limit (a positive integer).
ENVIRONMENT = "LANTERNA_MAX_PIXELS"

_limit: int | None = None


def max_pixels() -> int:
    """The pixel limit: set by :func:`set_max_pixels`, else ``LANTERNA_MAX_PIXELS``, else the
    default."""
    if _limit is not None:
        return _limit
    raw = os.environ.get(ENVIRONMENT, "").strip()
    if raw:
        if not raw.isdigit() or int(raw) < 1:
            raise LanternaInputError(None, f"{ENVIRONMENT} must be a positive integer, "
                                     f"not {raw!r}")
        return int(raw)
    return DEFAULT_MAX_PIXELS


def set_max_pixels(limit: int | None) -> None:
    """Set the pixel limit for this process (``None``: back to the environment or default)."""
    global _limit
    if limit is not None and limit < 1:
        raise LanternaInputError(None, "--max-pixels must be at least 1")
    _limit = limit


def check_pixels(source: str | Path | None, width: int, height: int, what: str = "image") -> None:
    """Raise a one-line error if a ``width`` × ``height`` image is over the pixel limit."""
    limit = max_pixels()
    if width * height > limit:
        raise LanternaInputError(source, f"{what} is {width}x{height} ({_mpx(width * height)}); "
                                 f"images over {_mpx(limit)} are refused (--max-pixels raises "
                                 "the limit)")


def _mpx(pixels: int) -> str:
    return f"{pixels / 1e6:,.1f} Mpx" if pixels < 10**9 else f"{pixels / 1e9:,.2f} Gpx"


#: Largest magnitude of a stored plane's scale or bias (``(t − bias)·scale``): beyond it the
#: float32 shading (products of coefficients, in the browser and the reference renderer)
#: overflows. Real files stay far below (PTM scales ~0.1–10, HSH and Relight ~±10).
MAX_QUANTISATION = 1e6


def check_quantisation(source: str | Path | None, scale: Iterable[float], bias: Iterable[float],
                       what: str = "scale/bias") -> None:
    """Raise a one-line error unless every scale and bias is finite and within
    :data:`MAX_QUANTISATION` (both in the stored ``(t − bias)·scale`` convention)."""
    for name, values in (("scale", scale), ("bias", bias)):
        for v in values:
            if not math.isfinite(v) or abs(v) > MAX_QUANTISATION:
                raise LanternaInputError(source, f"{what}: {name} {v:g} is out of range (at most "
                                         f"{MAX_QUANTISATION:g} in magnitude)")
