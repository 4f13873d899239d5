"""A format-neutral relightable layer: named channels packed in 8-bit groups with scale/bias.

Readers of web formats (e.g. Relight's ``info.json`` + ``plane_k.jpg``) return a
:class:`PlaneLayer` already in Lanterna's channel names, order and ``(t − bias)·scale``
convention (docs/dataset-format.md); the dataset writer tiles it
(:func:`lanterna.tiler.dataset.layers.add_planes_layer`).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import numpy.typing as npt

from .pca_model import PCA_TYPES, PcaBasis, plane_channel_names
from .ptm_model import PTM_BASIS
from .strip_tiff import BandImage

#: A group's texels: in memory, or file-backed rows written by a streamed fit.
PlaneData = npt.NDArray[np.uint8] | BandImage


@dataclass(frozen=True)
class PlaneGroup:
    """One stored image: 1 or 3 channels, ``data`` uint8 ``(H, W, n)`` or ``(H, W)``.

    ``lossy`` says the bytes are the decode of a lossy source (a JPEG stream or file), so its
    tiles may be lossy within a bound (:mod:`lanterna.tiler.dataset.plane_format`).
    """

    channels: list[str]
    data: PlaneData
    scale: list[float]
    bias: list[float]
    lossy: bool = False

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

    def values(self, y0: int = 0, y1: int | None = None) -> npt.NDArray[np.float32]:
        """Dequantised channel values ``(y1 − y0, W, n)`` of rows ``y0:y1`` (default all)."""
        rows = np.asarray(self.data[y0:y1 if y1 is not None else self.data.shape[0]])
        t = rows.astype(np.float32).reshape(rows.shape[:2] + (-1,)) / np.float32(255)
        return (t - np.array(self.bias, np.float32)) * np.array(self.scale, np.float32)


@dataclass(frozen=True)
class PlaneLayer:
    """A layer as plane groups (``layer_type`` ptm, hsh, sh, svbrdf, rbf or bilinear).

    ``group_names`` name the stored images (``{layer_id}_{name}``; default ``p0, p1, …``);
    ``extra`` carries svbrdf's ``glossLimits``/``inputColorSpace`` and readers' provenance notes;
    ``pca`` is the basis of an ``rbf`` / ``bilinear`` layer (its groups ``P0 P1 P2``, …).
    """

    layer_type: str
    groups: list[PlaneGroup]
    colorspace: str | None = None
    terms: int | None = None
    extra: dict[str, object] = field(default_factory=dict)
    group_names: list[str] = field(default_factory=list)
    pca: PcaBasis | None = None

    def __post_init__(self) -> None:
        if not self.groups:
            raise ValueError("a plane layer needs at least one group")
        if (self.layer_type in PCA_TYPES) != (self.pca is not None):
            raise ValueError(f"a {self.layer_type} layer needs a PCA basis exactly when it is "
                             f"of type {' or '.join(PCA_TYPES)}")
        if self.pca is not None:
            _check_pca(self.pca, self.groups)
        if not self.group_names:
            object.__setattr__(self, "group_names", [f"p{i}" for i in range(len(self.groups))])
        if len(self.group_names) != len(self.groups):
            raise ValueError("one name per plane group")

    def fields(self) -> dict[str, object]:
        """The type-specific fields of the layer's relight service block."""
        if self.layer_type == "ptm":
            return {"colorspace": self.colorspace, "basis": list(PTM_BASIS)}
        if self.layer_type in ("hsh", "sh"):
            return {"terms": self.terms}
        if self.layer_type == "svbrdf":
            return {k: self.extra[k] for k in ("glossLimits", "inputColorSpace") if k in self.extra}
        if self.pca is not None:
            return self.pca.fields()
        raise ValueError(f"unsupported plane layer type {self.layer_type!r}")

    @property
    def height(self) -> int:
        return int(self.groups[0].data.shape[0])

    @property
    def width(self) -> int:
        return int(self.groups[0].data.shape[1])

    def channels(self, y0: int = 0, y1: int | None = None) -> dict[str, npt.NDArray[np.float32]]:
        """Every channel's dequantised ``(H, W)`` values (rows ``y0:y1``) by name."""
        out: dict[str, npt.NDArray[np.float32]] = {}
        for g in self.groups:
            v = g.values(y0, y1)
            for k, name in enumerate(g.channels):
                out[name] = v[..., k]
        return out


def _check_pca(pca: PcaBasis, groups: list[PlaneGroup]) -> None:
    """A PCA layer's groups are ``P0 P1 P2``, … (padding ``X{q}`` of scale 0) and its basis is
    ``(N + 1)·D·3`` bytes (what every reader of its block relies on: docs/dataset-format.md)."""
    n = pca.nplanes
    want = plane_channel_names(n)
    if [g.channels for g in groups] != want:
        raise ValueError(f"a PCA layer of {n} planes has the groups {want}")
    if any(g.scale[k] != 0.0 for g in groups for k, c in enumerate(g.channels) if c[0] == "X"):
        raise ValueError("the padding channels of a PCA layer have scale 0")
    if pca.basis.dtype != np.uint8 or pca.basis.size != (n + 1) * pca.ndimensions * 3 or \
            pca.ndimensions < 1:
        raise ValueError(f"the basis of {n} planes has (N + 1)·D·3 bytes, got {pca.basis.size}")
    if pca.colorspace == "mycc" and (pca.yccplanes is None or sum(pca.yccplanes) != n):
        raise ValueError(f"a mycc basis of {n} planes needs yccplanes summing to {n}")
