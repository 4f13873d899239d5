"""The in-memory model of a Polynomial Texture Map (PTM), independent of its file format."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

#: Coefficient order of every PTM: L(lu, lv) = a0 lu² + a1 lv² + a2 lu lv + a3 lu + a4 lv + a5.
PTM_BASIS = ("lu2", "lv2", "lulv", "lu", "lv", "1")


def ptm_weights(lu: float, lv: float) -> npt.NDArray[np.float64]:
    """Return the six PTM basis weights for the projected light direction (lu, lv)."""
    return np.array([lu * lu, lv * lv, lu * lv, lu, lv, 1.0])


@dataclass(frozen=True)
class Ptm:
    """A PTM held as its quantised bytes, rows top-down (row 0 is the top of the image).

    Attributes
    ----------
    colorspace:
        ``"lrgb"`` (6 luminance coefficients + an RGB colour per pixel) or ``"rgb"``
        (6 coefficients per colour channel).
    coefficients:
        ``uint8`` array, shape ``(H, W, 6)`` for lrgb, ``(H, W, 3, 6)`` for rgb.
    scale, bias:
        The file's per-coefficient quantisation, shape ``(6,)``: ``a = (byte - bias) * scale``
        in 0–255 units (the HP PTM convention); :meth:`dequantized` gives ``a/255``.
    rgb:
        ``uint8`` array ``(H, W, 3)`` for lrgb; ``None`` for rgb.
    lossy:
        True when the bytes are a lossy decode (the JPEG streams of ``PTM_FORMAT_JPEG_*``).
    """

    colorspace: str
    coefficients: npt.NDArray[np.uint8]
    scale: npt.NDArray[np.float32]
    bias: npt.NDArray[np.int32]
    rgb: npt.NDArray[np.uint8] | None = None
    lossy: bool = False

    def __post_init__(self) -> None:
        c = self.coefficients
        if self.colorspace == "lrgb":
            if c.ndim != 3 or c.shape[2] != 6:
                raise ValueError(f"lrgb coefficients must be (H, W, 6), got {c.shape}")
            if self.rgb is None or self.rgb.shape != c.shape[:2] + (3,):
                raise ValueError("lrgb PTM needs an (H, W, 3) rgb array")
        elif self.colorspace == "rgb":
            if c.ndim != 4 or c.shape[2:] != (3, 6):
                raise ValueError(f"rgb coefficients must be (H, W, 3, 6), got {c.shape}")
        else:
            raise ValueError(f"unknown PTM colorspace {self.colorspace!r}")
        if c.dtype != np.uint8:
            raise ValueError("coefficients must be uint8")
        if np.shape(self.scale) != (6,) or np.shape(self.bias) != (6,):
            raise ValueError("scale and bias must have 6 entries")

    @property
    def width(self) -> int:
        return int(self.coefficients.shape[1])

    @property
    def height(self) -> int:
        return int(self.coefficients.shape[0])

    def dequantized(self) -> npt.NDArray[np.float32]:
        """Return the coefficients in display units, ``a/255`` (as every dequantised value in
        Lanterna: the planes' ``(t − bias)·scale``, HSH terms), float32, shaped as ``coefficients``.
        """
        a = self.coefficients.astype(np.float32) - self.bias.astype(np.float32)
        return a * (self.scale.astype(np.float32) / np.float32(255.0))

    def relight(self, lu: float, lv: float) -> npt.NDArray[np.float32]:
        """Relight for light (lu, lv); return ``(H, W, 3)`` float32 in 0–1, clamped.

        lrgb: ``rgb/255 · L``; rgb: ``L_c`` per channel, ``L`` the polynomial of the dequantised
        coefficients (the RTIViewer convention).
        """
        w = ptm_weights(lu, lv).astype(np.float32)
        lum = self.dequantized() @ w
        if self.colorspace == "lrgb":
            assert self.rgb is not None
            out = self.rgb.astype(np.float32) / 255.0 * lum[..., None]
        else:
            out = lum
        return np.clip(out, 0.0, 1.0).astype(np.float32)
