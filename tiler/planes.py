"""A format-neutral relightable layer: named channels packed in 8-bit groups with scale/bias.

Readers of web formats (e.g. Relight's ``info.json`` + ``plane_k.jpg``) return a
:class:`PlaneLayer` already in Lanterna's channel names, order and ``(t − bias)·scale``
convention (docs/dataset-format.md), and :func:`lanterna.tiler.layers.add_planes_layer` tiles it.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import numpy.typing as npt


@dataclass(frozen=True)
class PlaneGroup:
    """One stored image: 1 or 3 channels, ``data`` uint8 ``(H, W, n)`` or ``(H, W)``."""

    channels: list[str]
    data: npt.NDArray[np.uint8]
    scale: list[float]
    bias: list[float]

    def __post_init__(self) -> None:
        n = len(self.channels)
        if n not in (1, 3) or len(self.scale) != n or len(self.bias) != n:
            raise ValueError(f"a plane group has 1 or 3 channels with a scale and bias each: "
                             f"{self.channels}")
        shape = self.data.shape
        ok = shape[2:] == (3,) if n == 3 else self.data.ndim == 2
        if self.data.dtype != np.uint8 or not ok or self.data.ndim not in (2, 3):
            want = "(H, W, 3)" if n == 3 else "(H, W)"
            raise ValueError(f"group {self.channels} data must be uint8 {want}, "
                             f"got {self.data.dtype} {shape}")

    def values(self) -> npt.NDArray[np.float32]:
        """Dequantised channel values ``(H, W, n)``."""
        t = self.data.astype(np.float32).reshape(self.data.shape[:2] + (-1,)) / np.float32(255)
        return (t - np.array(self.bias, np.float32)) * np.array(self.scale, np.float32)


@dataclass(frozen=True)
class PlaneLayer:
    """A relightable layer as plane groups (``layer_type`` ``ptm`` or ``hsh``)."""

    layer_type: str
    groups: list[PlaneGroup]
    colorspace: str | None = None
    terms: int | None = None
    extra: dict[str, object] = field(default_factory=dict)

    @property
    def height(self) -> int:
        return int(self.groups[0].data.shape[0])

    @property
    def width(self) -> int:
        return int(self.groups[0].data.shape[1])

    def channels(self) -> dict[str, npt.NDArray[np.float32]]:
        """Every channel's dequantised ``(H, W)`` values by name."""
        out: dict[str, npt.NDArray[np.float32]] = {}
        for g in self.groups:
            v = g.values()
            for k, name in enumerate(g.channels):
                out[name] = v[..., k]
        return out
