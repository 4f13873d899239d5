"""Add layers of every type to a dataset: PTM, HSH, shape + material (SVBRDF) and plain images.

Every ``add_*_layer`` turns its input into :class:`~lanterna.tiler.formats.planes.PlaneGroup` s
(three channels per IIIF image, the source's own bytes where it has them; the layouts are
:mod:`lanterna.tiler.formats.layouts`), and :func:`add_planes_layer`
tiles them (each group in the format :mod:`.plane_format` chooses for its source), renders
the manifest's preview image with the reference renderer
(:mod:`lanterna.tiler.render`, colour mode, overhead light) and registers the layer
(schema: docs/dataset-format.md, maths: docs/rendering.md).
"""

from __future__ import annotations

from typing import Any

import numpy as np
import numpy.typing as npt
import pyvips

from lanterna.tiler.formats.hsh_model import Hsh
from lanterna.tiler.formats.layouts import (
    SVBRDF_MAPS,
    hsh_plane_layer,
    hsh_plane_quantisation,
    ptm_plane_layer,
    range_quantisation,
    to_bytes,
)
from lanterna.tiler.formats.planes import PlaneData, PlaneGroup, PlaneLayer
from lanterna.tiler.formats.ptm_model import Ptm
from lanterna.tiler.formats.strip_tiff import BandImage, StripTiffWriter
from lanterna.tiler.render import render

from .plane_format import AUTO, PlaneFormat, choose_format
from .writer import DatasetWriter

#: Pixels rendered at once for the preview of a file-backed layer (whole rows, at least one).
PREVIEW_PIXELS = 1 << 22


def add_planes_layer(ds: DatasetWriter, layer: PlaneLayer, *, layer_id: str, label: str,
                     share: dict[int, str] | None = None,
                     plane_format: PlaneFormat = AUTO) -> dict[str, Any]:
    """Tile the plane groups of ``layer`` and add it, with a preview, to the dataset.

    ``share`` maps a group index to a share key: groups with the same key across layers are
    stored once (e.g. one normal map used by several material layers). ``plane_format`` is
    ``--plane-format``: ``auto`` chooses each group's tile format by its source.
    """
    planes = []
    for i, group in enumerate(layer.groups):
        data = group.data
        image = data.vips() if isinstance(data, BandImage) else np.ascontiguousarray(data)
        key = (share or {}).get(i)
        first = ds.shared_image(key)  # a shared group is stored once, in its first format
        fmt = (ds.images[first]["format"] if first is not None
               else choose_format(group, plane_format, tile_size=ds.tile_size))
        svc = ds.add_image(f"{layer_id}_{layer.group_names[i]}", image, fmt=fmt, share_key=key)
        stored = ds.images[svc["id"].rsplit("/", 1)[1]]
        planes.append({"service": svc, "format": stored["format"],
                       "channels": list(group.channels),
                       "scale": list(group.scale), "bias": list(group.bias)})
    block = {"layerType": layer.layer_type, **layer.fields(), "planes": planes}
    banded = [g.data for g in layer.groups if isinstance(g.data, BandImage)]
    if banded:
        # file-backed (streamed) planes: render the preview a band of rows at a time
        # (colour mode is per pixel, so this equals the whole-image render)
        target = banded[0].path.with_name(f"{banded[0].path.stem}-preview.tif")
        with StripTiffWriter(target, layer.width, layer.height, 3) as writer:
            rows = max(1, PREVIEW_PIXELS // layer.width)
            for y0 in range(0, layer.height, rows):
                channels = layer.channels(y0, y0 + rows)
                writer.write(to_bytes(render(block, channels, (0.0, 0.0), "color")))
            preview: npt.NDArray[np.uint8] | pyvips.Image = writer.close().vips()
    else:
        preview = to_bytes(render(block, layer.channels(), (0.0, 0.0), "color"))
    ds.add_image(f"{layer_id}_preview", preview, fmt="jpg")
    out = {"id": layer_id, "label": label, "body": f"{layer_id}_preview", **block}
    ds.add_layer(out)
    return out


def add_ptm_layer(ds: DatasetWriter, ptm: Ptm, *, layer_id: str = "ptm",
                  label: str = "PTM", plane_format: PlaneFormat = AUTO) -> dict[str, Any]:
    """Add a PTM layer whose stored texels are exactly the PTM's bytes.

    The file's ``a = (byte − b)·s`` in 0–255 units becomes ``(t − b/255)·s`` with ``t`` in
    0–1 (docs/dataset-format.md).
    """
    def coefficients(c: int | None, k: slice) -> PlaneData:
        return ptm.coefficients[..., k] if c is None else ptm.coefficients[:, :, c, k]

    planes = ptm_plane_layer(ptm.colorspace, ptm.scale, ptm.bias, coefficients, ptm.rgb,
                             lossy=ptm.lossy)
    return add_planes_layer(ds, planes, layer_id=layer_id, label=label,
                            plane_format=plane_format)


def add_hsh_layer(ds: DatasetWriter, hsh: Hsh, *, layer_id: str = "hsh",
                  label: str = "HSH", plane_format: PlaneFormat = AUTO) -> dict[str, Any]:
    """Add an HSH field: one IIIF image per term holding its R, G, B coefficients."""
    scales, biases = hsh_plane_quantisation(hsh)

    def term(k: int) -> PlaneData:
        data = hsh.coefficients[:, :, :, k]
        return np.full_like(data, 255) if hsh.scale[k] == 0.0 else data

    planes = hsh_plane_layer(scales, biases, term)
    return add_planes_layer(ds, planes, layer_id=layer_id, label=label,
                            plane_format=plane_format)


def add_svbrdf_layer(
    ds: DatasetWriter,
    *,
    normals: npt.NDArray[np.uint8] | None = None,
    kd: npt.NDArray[np.uint8] | None = None,
    ks: npt.NDArray[np.uint8] | None = None,
    gloss: npt.NDArray[np.uint8] | None = None,
    depth: npt.NDArray[np.uint8] | None = None,
    depth_range: tuple[float, float] = (0.0, 1.0),
    gloss_limits: tuple[float, float] = (0.01, 0.5),
    input_colorspace: str = "linear",
    share: dict[str, str] | None = None,
    lossy: frozenset[str] = frozenset(),
    layer_id: str = "svbrdf",
    label: str = "Shape and material",
    plane_format: PlaneFormat = AUTO,
) -> dict[str, Any]:
    """Add a shape (normal map, depth) + material (kd, ks, gloss) layer; any subset of maps.

    Parameters
    ----------
    normals:
        ``(H, W, 3)`` uint8, encoded ``(n + 1)/2`` in the OpenGL convention (see
        :func:`encode_normals`).
    kd, ks:
        ``(H, W, 3)`` uint8 in ``input_colorspace``: ``"linear"``, ``"srgb"`` (decoded to linear
        by the viewer) or ``"display"`` (display values, shaded as stored; docs/rendering.md).
    gloss, depth:
        ``(H, W)`` uint8; gloss maps to ``α = αmin + t·(αmax − αmin)`` with ``gloss_limits``;
        depth to ``low + t·(high − low)`` with ``depth_range = (low, high)`` (the source's units).
    share:
        Optional map name → share key (e.g. the normal map's resolved path): maps with the same key
        across layers are stored once.
    lossy:
        The names of the maps read from lossy (JPEG) files.
    plane_format:
        ``--plane-format`` (:mod:`.plane_format`).
    """
    if input_colorspace not in ("linear", "srgb", "display"):
        raise ValueError("inputColorSpace must be linear, srgb or display, not "
                         f"{input_colorspace!r}")
    lo, hi = (float(v) for v in gloss_limits)
    if not 0.0 < lo <= hi:
        raise ValueError(f"glossLimits must satisfy 0 < min <= max, got {gloss_limits}")
    given = {"normals": normals, "kd": kd, "ks": ks, "gloss": gloss, "depth": depth}
    groups: list[PlaneGroup] = []
    names: list[str] = []
    shared: dict[int, str] = {}
    for name, (channels, sc, bi) in SVBRDF_MAPS.items():
        data = given[name]
        if data is None:
            continue
        if name == "depth":
            sc, bi = range_quantisation(depth_range)
        expected = (ds.height, ds.width) + ((3,) if len(channels) == 3 else ())
        if data.dtype != np.uint8 or data.shape != expected:
            raise ValueError(f"{name} map must be uint8 {expected}, got {data.dtype} {data.shape}")
        if share and name in share:
            shared[len(groups)] = share[name]
        groups.append(PlaneGroup(channels, data, sc, bi, name in lossy))
        names.append(name)
    if not groups:
        raise ValueError("a shape + material layer needs at least one map")
    planes = PlaneLayer("svbrdf", groups, group_names=names,
                        extra={"glossLimits": [lo, hi], "inputColorSpace": input_colorspace})
    return add_planes_layer(ds, planes, layer_id=layer_id, label=label, share=shared,
                            plane_format=plane_format)


def add_image_layer(ds: DatasetWriter, image: pyvips.Image, *, layer_id: str = "image",
                    label: str = "Image", fmt: str = "jpg",
                    share_key: str | None = None) -> dict[str, Any]:
    """Add a plain (unshaded) image layer; a single-band image is a grey ``Y`` layer.

    The image is its own manifest body (no preview), so a JPEG layer stays one JPEG pyramid.
    """
    mono = image.bands == 1
    svc = ds.add_image(layer_id, image, fmt=fmt, share_key=share_key)
    n = 1 if mono else 3
    channels = ["Y"] if mono else ["R", "G", "B"]
    layer = {"id": layer_id, "label": label, "body": svc["id"].rsplit("/", 1)[1],
             "layerType": "image",
             "planes": [{"service": svc, "format": fmt, "channels": channels,
                         "scale": [1.0] * n, "bias": [0.0] * n}]}
    ds.add_layer(layer)
    return layer
