"""Plan one layer from one source: a ``.ptm``, an ``.rti``, a Relight folder, an image, map files
(shape + material) or spectral bands. Each plan reads and checks its input; nothing is written.
"""

from __future__ import annotations

import re
from collections.abc import Sequence
from pathlib import Path

import numpy as np
import numpy.typing as npt

from lanterna.errors import LanternaInputError
from lanterna.tiler.dataset.layers import (
    add_hsh_layer,
    add_image_layer,
    add_planes_layer,
    add_ptm_layer,
    add_svbrdf_layer,
)
from lanterna.tiler.dataset.plan import LayerPlan
from lanterna.tiler.dataset.plane_format import AUTO, PlaneFormat
from lanterna.tiler.dataset.writer import DatasetWriter, check_identifier
from lanterna.tiler.formats.hsh import read_rti
from lanterna.tiler.formats.layouts import SVBRDF_MAPS
from lanterna.tiler.formats.ptm import read_ptm
from lanterna.tiler.formats.relight_multispectral import is_multispectral
from lanterna.tiler.formats.relight_web import read_relight
from lanterna.tiler.iiif.pyramid import vips_from_array
from lanterna.tiler.inputs.images import load_rgb_image
from lanterna.tiler.inputs.maps import (
    is_lossy_file,
    load_band,
    load_color_map,
    load_depth_map,
    load_normal_map,
    load_scalar_map,
)

IMAGE_SUFFIXES = {".png", ".jpg", ".jpeg", ".tif", ".tiff", ".webp"}


def layer_id_from(stem: str) -> str:
    """Turn a file name stem into a layer id (``[A-Za-z0-9_-]``)."""
    cleaned = re.sub(r"[^A-Za-z0-9_-]+", "_", stem).strip("_")
    return cleaned or "layer"


def plan_source(path: Path, *, layer_id: str | None = None, label: str | None = None,
                plane_format: PlaneFormat = AUTO) -> LayerPlan:
    """Plan a layer from one source: ``.ptm``, ``.rti``, a Relight folder or an image.

    ``plane_format`` (``--plane-format``) is the tile format of the planes of relightable layers;
    plain images keep their own format.
    """
    path = Path(path)
    lid = check_identifier(layer_id or layer_id_from(path.stem), "layer id")
    if path.is_dir():
        if not (path / "info.json").is_file():
            raise LanternaInputError(path, "a folder source must be a Relight web-format folder "
                                     "(info.json + plane_k.jpg)")
        if is_multispectral(path):
            raise LanternaInputError(path, "an OpenLIME multispectral folder makes several "
                                     "layers: give it to lanterna import as a source of its own")
        planes = read_relight(path)
        kind = f"{planes.layer_type.upper()} {(planes.colorspace or '').upper()}".strip()
        lbl = label or f"{path.name} ({kind}, Relight)"
        size = planes.extra.get("pixelSizeMM")
        return LayerPlan(lid, lbl, planes.width, planes.height, path.name,
                         lambda ds: add_planes_layer(ds, planes, layer_id=lid, label=lbl,
                                                     plane_format=plane_format),
                         pixel_size_mm=float(size) if isinstance(size, int | float) else None)
    if not path.is_file():
        if path.exists():
            raise LanternaInputError(path, "is not a regular file (a device, FIFO or socket)")
        raise LanternaInputError(path, "no such file")
    suffix = path.suffix.lower()
    if suffix == ".ptm":
        ptm = read_ptm(path)
        lbl = label or f"{path.stem} (PTM {ptm.colorspace.upper()})"
        return LayerPlan(lid, lbl, ptm.width, ptm.height, path.name,
                         lambda ds: add_ptm_layer(ds, ptm, layer_id=lid, label=lbl,
                                                  plane_format=plane_format))
    if suffix == ".rti":
        hsh = read_rti(path)
        lbl = label or f"{path.stem} (HSH {hsh.terms} terms)"
        return LayerPlan(lid, lbl, hsh.width, hsh.height, path.name,
                         lambda ds: add_hsh_layer(ds, hsh, layer_id=lid, label=lbl,
                                                  plane_format=plane_format))
    if suffix in IMAGE_SUFFIXES:
        img = load_rgb_image(path)
        lbl = label or path.stem
        return LayerPlan(lid, lbl, img.width, img.height, path.name,
                         lambda ds: add_image_layer(ds, img, layer_id=lid, label=lbl,
                                                    share_key=str(path.resolve())))
    raise LanternaInputError(path, f"unknown source type {suffix or '(no suffix)'}; expected "
                             ".ptm, .rti, a Relight folder or an image (.png, .jpg, .tif, .webp)")


def plan_svbrdf(maps: dict[str, Path], *, layer_id: str, label: str | None = None,
                gloss_limits: tuple[float, float] = (0.01, 0.5), input_colorspace: str = "linear",
                normal_convention: str = "opengl",
                plane_format: PlaneFormat = AUTO) -> LayerPlan:
    """Plan a shape + material layer from map files (any subset of :data:`SVBRDF_MAPS`)."""
    unknown = sorted(set(maps) - set(SVBRDF_MAPS))
    if unknown:
        raise LanternaInputError(None, f"layer {layer_id}: unknown map(s) {', '.join(unknown)}; "
                                 f"expected {', '.join(SVBRDF_MAPS)}")
    if not maps:
        raise LanternaInputError(None, f"layer {layer_id}: a shape + material layer needs a map")
    data: dict[str, npt.NDArray[np.uint8]] = {}
    depth_range = (0.0, 1.0)
    for name, path in maps.items():
        if name == "normals":
            data[name] = load_normal_map(path, convention=normal_convention)
        elif name in ("kd", "ks"):
            data[name] = load_color_map(path)
        elif name == "depth":
            data[name], depth_range = load_depth_map(path)  # stretched to 0–255 over min..max
        else:
            data[name] = load_scalar_map(path)
    sizes = {name: (int(a.shape[1]), int(a.shape[0])) for name, a in data.items()}
    first = next(iter(maps))
    for name, size in sizes.items():
        if size != sizes[first]:
            raise LanternaInputError(maps[name], f"map {name} is {size[0]}x{size[1]}, map {first} "
                                     f"is {sizes[first][0]}x{sizes[first][1]}")
    share = {name: str(Path(p).resolve()) for name, p in maps.items()}
    lossy = frozenset(name for name, p in maps.items() if is_lossy_file(p))
    kind = "shape + material" if "normals" in data and "kd" in data else (
        "shape" if "normals" in data else "material")
    lbl = label or f"{layer_id} ({kind})"
    w, h = sizes[first]

    def add(ds: DatasetWriter) -> object:
        return add_svbrdf_layer(ds, normals=data.get("normals"), kd=data.get("kd"),
                                ks=data.get("ks"), gloss=data.get("gloss"),
                                depth=data.get("depth"), depth_range=depth_range,
                                gloss_limits=gloss_limits,
                                input_colorspace=input_colorspace, share=share,
                                lossy=lossy, layer_id=layer_id, label=lbl,
                                plane_format=plane_format)

    return LayerPlan(layer_id, lbl, w, h, ", ".join(str(p) for p in maps.values()), add)


def plan_bands(bands: dict[str, Path], fusions: Sequence[Sequence[str]] = ()) -> list[LayerPlan]:
    """Plan one grey layer per spectral band and one false-colour layer per band→RGB triple."""
    loaded = {name: load_band(path) for name, path in bands.items()}
    plans = []
    shapes = {name: a.shape for name, a in loaded.items()}
    for name, array in loaded.items():
        lid = check_identifier(layer_id_from(name), "band name")
        if array.shape != next(iter(shapes.values())):
            raise LanternaInputError(bands[name], f"band {name} is {array.shape[1]}x"
                                     f"{array.shape[0]}, other bands differ")
        plans.append(_array_plan(lid, f"{name} band", array, str(bands[name])))
    for triple in fusions:
        if len(triple) != 3:
            raise LanternaInputError(None, f"a false-colour fusion maps three bands to R,G,B: "
                                     f"got {','.join(triple)}")
        missing = [b for b in triple if b not in loaded]
        if missing:
            raise LanternaInputError(None, f"fusion {','.join(triple)}: unknown band(s) "
                                     f"{', '.join(missing)} (have {', '.join(loaded)})")
        rgb = np.stack([loaded[b] for b in triple], axis=-1)
        lid = check_identifier(layer_id_from("fc_" + "_".join(triple)), "layer id")
        plans.append(_array_plan(lid, f"False colour R={triple[0]} G={triple[1]} B={triple[2]}",
                                 rgb, "+".join(triple)))
    return plans


def _array_plan(lid: str, label: str, array: npt.NDArray[np.uint8], source: str) -> LayerPlan:
    img = vips_from_array(array)
    return LayerPlan(lid, label, img.width, img.height, source,
                     lambda ds: add_image_layer(ds, img, layer_id=lid, label=label, fmt="png"))
