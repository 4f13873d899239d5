"""The in-memory model of a Hemispherical Harmonics (HSH) reflectance field."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

HSH_TERMS = (4, 9, 16)


@dataclass(frozen=True)
class Hsh:
    """An RGB HSH field, rows top-down.

    Attributes
    ----------
    coefficients:
        ``uint8`` array ``(H, W, 3, K)`` (channel R, G, B; term k), K in 4, 9, 16.
    scale, bias:
        Per-term dequantisation, shape ``(K,)``, shared by the three channels:
        ``a = byte/255 * scale + bias`` (the ``.rti`` convention; values in 0–1 display units).
    """

    coefficients: npt.NDArray[np.uint8]
    scale: npt.NDArray[np.float32]
    bias: npt.NDArray[np.float32]

    def __post_init__(self) -> None:
        c = self.coefficients
        if c.dtype != np.uint8 or c.ndim != 4 or c.shape[2] != 3 or c.shape[3] not in HSH_TERMS:
            raise ValueError(f"HSH coefficients must be uint8 (H, W, 3, 4|9|16), got {c.dtype} "
                             f"{c.shape}")
        k = c.shape[3]
        if np.shape(self.scale) != (k,) or np.shape(self.bias) != (k,):
            raise ValueError(f"scale and bias must have {k} entries")

    @property
    def terms(self) -> int:
        return int(self.coefficients.shape[3])

    @property
    def width(self) -> int:
        return int(self.coefficients.shape[1])

    @property
    def height(self) -> int:
        return int(self.coefficients.shape[0])

    def dequantized(self) -> npt.NDArray[np.float32]:
        """Return ``(H, W, 3, K)`` float32 coefficients in 0–1 units."""
        out = self.coefficients.astype(np.float32) / np.float32(255.0)
        return out * self.scale.astype(np.float32) + self.bias.astype(np.float32)
