"""Read Relight/OpenLIME web-format RTI folders (``info.json`` + ``plane_k.jpg``) as a PlaneLayer.

Format (Relight ``src/rti.cpp`` ``Rti::load``/``loadData``, ``src/cli/rtibuilder.cpp``
``saveJSON``; OpenLIME ``src/ShaderRTI.js``; notes §2.3):

- ``info.json`` holds ``width``, ``height``, ``type`` (``ptm``, ``hsh``, …), ``colorspace``
  (``rgb``, ``lrgb``, …), ``nplanes`` and ``materials[0].scale`` / ``.bias``: one value per plane.
- Plane ``p`` is channel ``p % 3`` of the RGB image ``plane_{p // 3}.jpg`` (``format: "png"``
  gives ``.png``); rows are top-down. A plane's value is ``(t − bias[p])·scale[p]`` with
  ``t = texel/255``, which is Lanterna's own convention, so the texels are kept unchanged.
- Light: x right, y up (Relight exports the same coefficients to ``.ptm`` with only a reorder).
- ``ptm``: the basis is ``1, u, v, u², uv, v²`` (degree 1 stops after ``v``).
  ``rgb``: planes ``3t + c`` are term ``t`` of colour ``c`` (9 or 18 planes).
  ``lrgb``: planes 0–2 are the base colour (scale 1, bias 0), planes ``3 + t`` luminance term
  ``t`` (6 or 9 planes); colour = base · L.
- ``hsh``: planes ``3k + c`` are term ``k`` of colour ``c`` (``rgb`` only; 4, 9 or 16 terms).
- ``sh``: plain real spherical harmonics (:mod:`.sh_model`), laid out as ``hsh`` (4 or 9 terms).

The reader regroups the planes into Lanterna's channel names and order (docs/dataset-format.md):
PTM ``L0…L5`` / ``R0…R5, G0…G5, B0…B5`` in the basis ``lu², lv², lu·lv, lu, lv, 1`` (a degree-1
PTM gets zero quadratic channels), HSH and SH one group ``R{k}, G{k}, B{k}`` per term.

- ``ycc`` (``ptm``, ``hsh``, ``sh``): converted exactly into ``rgb`` planes (:mod:`.relight_ycc`).
- ``rbf`` / ``bilinear`` with ``mrgb`` / ``mycc``: a PCA basis (:mod:`.relight_pca`); the planes
  are kept as they are, groups ``P0 P1 P2``, … (``nplanes`` need not be a multiple of 3).
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import numpy as np
import numpy.typing as npt
import pyvips

from lanterna.errors import LanternaInputError
from lanterna.tiler.documents import read_document
from lanterna.tiler.fileio import read_input
from lanterna.tiler.limits import check_pixels, check_quantisation

from .pca_model import PCA_TYPES
from .planes import PlaneGroup, PlaneLayer
from .relight_layouts import open_rgb_plane, open_tiled_plane, tiled_plane_source, vips_reason
from .relight_pca import as_int, pca_groups, pca_nplanes, read_pca_basis
from .relight_ycc import ycc_as_rgb

#: Relight's PTM term for each Lanterna PTM coefficient (``lu², lv², lu·lv, lu, lv, 1``).
PTM_TERM_OF = (3, 5, 4, 1, 2, 0)
#: Accepted ``nplanes`` per (type, colorspace) of the fixed bases (PCA bases: 1 to 48).
NPLANES = {("ptm", "lrgb"): (6, 9), ("ptm", "rgb"): (9, 18), ("ptm", "ycc"): (9, 18),
           ("hsh", "rgb"): (12, 27, 48), ("hsh", "ycc"): (12, 27, 48),
           ("sh", "rgb"): (12, 27), ("sh", "ycc"): (12, 27)}
#: The colour spaces of each supported type.
COLORSPACES = {"ptm": ("rgb", "lrgb", "ycc"), "hsh": ("rgb", "ycc"), "sh": ("rgb", "ycc"),
               "rbf": ("mrgb", "mycc"), "bilinear": ("mrgb", "mycc")}
#: Types Relight or OpenLIME know that Lanterna does not read, and why.
_OTHER_TYPES = {"h": "Relight's experimental H-basis",
                "dmd": "Relight's unfinished DMD basis", "bln": "OpenLIME's shader name; the "
                "info.json type is 'bilinear'", "neural": "a neural RTI", "img": "an image set"}
_SUPPORTED = ", ".join(COLORSPACES)
_ALL_COLORSPACES = ("rgb", "lrgb", "ycc", "mrgb", "mycc")


def read_relight(folder: str | Path) -> PlaneLayer:
    """Read a Relight web-format folder (or its ``info.json``): ptm, hsh, sh, rbf or bilinear.

    Returns
    -------
    PlaneLayer
        ``layer_type`` ``"ptm"`` (``colorspace`` ``"lrgb"`` or ``"rgb"``; ``ycc`` is converted
        to ``rgb``), ``"hsh"`` (``terms`` 4, 9 or 16) or ``"sh"`` (``terms`` 4 or 9), groups
        in Lanterna's channel order with the folder's bytes and per-channel scale/bias; or
        ``"rbf"`` / ``"bilinear"`` (``colorspace`` ``"mrgb"`` or ``"mycc"``) with groups
        ``P0 P1 P2``, … and the basis in ``pca``. ``extra`` records the source ``nplanes`` and
        ``quality``, and ``pixelSizeMM`` when info.json states ``pixelSizeInMM`` (the physical
        size of a pixel).

    Raises
    ------
    LanternaInputError
        If ``info.json`` or a plane is missing or unreadable, the type or colorspace is not
        supported, or the planes disagree with ``info.json``.
    """
    src = Path(folder)
    info_path = src if src.name == "info.json" and src.is_file() else src / "info.json"
    if not info_path.parent.is_dir():
        raise LanternaInputError(src, "folder not found")
    if not info_path.is_file():
        raise LanternaInputError(src, "no info.json: not a Relight web-format folder")
    info = read_document(info_path, "relight-info")
    rtype, colorspace, width, height, nplanes = _check_info(info, info_path)
    scale, bias = _quantisation(info, nplanes, info_path)
    pca = (read_pca_basis(info, info_path, rtype, colorspace, nplanes)
           if rtype in PCA_TYPES else None)
    ext = _plane_format(info, info_path)
    check_pixels(info_path, width, height, "the Relight image")
    # every plane's header first (sizes compared, nothing decoded), then the pixels
    njpegs = (nplanes + 2) // 3
    opened = [_open_plane(info_path.parent, i, ext, width, height, njpegs)
              for i in range(njpegs)]
    planes = np.stack([c for path, image in opened for c in _decode_plane(path, image)])
    planes = planes[:nplanes]
    lossy = ext == "jpg"  # the planes are JPEG decodes
    extra: dict[str, object] = {"source": "relight", "nplanes": nplanes}
    if isinstance(info.get("quality"), int):
        extra["quality"] = info["quality"]
    if "pixelSizeInMM" in info:
        extra["pixelSizeMM"] = float(info["pixelSizeInMM"])
    if pca is not None:
        return PlaneLayer(rtype, pca_groups(planes, scale, bias, lossy), colorspace, None, extra,
                          pca=pca)
    if colorspace == "ycc":
        planes, scale, bias = ycc_as_rgb(rtype, planes, scale, bias)
        colorspace = "rgb"
        extra["sourceColorspace"] = "ycc"
    if rtype in ("hsh", "sh"):
        rgb = [list(range(3 * k, 3 * k + 3)) for k in range(nplanes // 3)]
        groups = [PlaneGroup([f"R{k}", f"G{k}", f"B{k}"], _stack(planes, rgb[k]),
                             scale[3 * k : 3 * k + 3], bias[3 * k : 3 * k + 3], lossy)
                  for k in range(nplanes // 3)]
        return PlaneLayer(rtype, groups, None, nplanes // 3, extra)
    if colorspace == "lrgb":
        lum = [3 + t for t in PTM_TERM_OF]  # Relight plane of each Lanterna L channel
        groups = [_ptm_group(planes, [f"L{j}" for j in range(g, g + 3)], lum[g : g + 3],
                             scale, bias, lossy) for g in (0, 3)]
        groups.append(PlaneGroup(["R", "G", "B"], _stack(planes, [0, 1, 2]), scale[:3], bias[:3],
                                 lossy))
    else:
        groups = []
        for c, name in enumerate("RGB"):
            for g in (0, 3):
                idx = [3 * t + c for t in PTM_TERM_OF[g : g + 3]]
                groups.append(_ptm_group(planes, [f"{name}{j}" for j in range(g, g + 3)], idx,
                                         scale, bias, lossy))
    return PlaneLayer("ptm", groups, colorspace, None, extra)


def _check_info(info: dict[str, Any], path: Path) -> tuple[str, str, int, int, int]:
    rtype, colorspace = info.get("type"), info.get("colorspace")
    if rtype in _OTHER_TYPES:
        raise LanternaInputError(path, f"unsupported Relight type {rtype!r} "
                                 f"({_OTHER_TYPES[str(rtype)]}); supported: {_SUPPORTED}")
    if rtype not in COLORSPACES:
        raise LanternaInputError(path, f"unknown Relight type {rtype!r}; supported: "
                                 f"{_SUPPORTED}")
    if colorspace not in _ALL_COLORSPACES:
        raise LanternaInputError(path, f"unknown colorspace {colorspace!r}; supported: "
                                 f"{', '.join(_ALL_COLORSPACES)}")
    if colorspace not in COLORSPACES[rtype]:
        raise LanternaInputError(path, f"{rtype} with colorspace {colorspace} is not supported; "
                                 f"{rtype} takes {' or '.join(COLORSPACES[rtype])}")
    width, height = (as_int(info.get(key), key, path) for key in ("width", "height"))
    if width <= 0 or height <= 0:
        raise LanternaInputError(path, f"image size must be positive, got {width}x{height}")
    if rtype in PCA_TYPES:
        return rtype, colorspace, width, height, pca_nplanes(info, path, colorspace)
    nplanes = as_int(info.get("nplanes"), "nplanes", path)
    allowed = NPLANES[(rtype, colorspace)]
    if nplanes not in allowed:
        raise LanternaInputError(path, f"{rtype} {colorspace} needs nplanes "
                                 f"{' or '.join(map(str, allowed))}, got {nplanes}")
    return rtype, colorspace, width, height, nplanes


def _quantisation(info: dict[str, Any], nplanes: int, path: Path) -> tuple[list[float],
                                                                             list[float]]:
    """Return per-plane scale and bias from ``materials[0]`` (or top-level ``scale``/``bias``)."""
    materials = info.get("materials")
    if isinstance(materials, list) and materials:
        if len(materials) > 1:
            raise LanternaInputError(path, f"{len(materials)} materials; only one is supported "
                                     "(Relight's multi-material output, with segments.png, "
                                     "is not)")
        where, holder = "materials[0]", materials[0]
        if not isinstance(holder, dict):
            raise LanternaInputError(path, "materials[0] must be a JSON object")
    else:
        where, holder = "info.json", info
    out = []
    for key in ("scale", "bias"):
        values = holder.get(key)
        if not isinstance(values, list) or len(values) != nplanes:
            got = f"{len(values)} values" if isinstance(values, list) else repr(values)
            raise LanternaInputError(path, f"{where}.{key} must list {nplanes} numbers "
                                     f"(one per plane), got {got}")
        if not all(isinstance(v, int | float) and not isinstance(v, bool)
                   and math.isfinite(v) for v in values):
            raise LanternaInputError(path, f"{where}.{key} holds a non-numeric or non-finite "
                                     "value")
        out.append([float(v) for v in values])
    check_quantisation(path, out[0], out[1], where)
    return out[0], out[1]


def _plane_format(info: dict[str, Any], path: Path) -> str:
    fmt = info.get("format", "jpg")
    if fmt not in ("jpg", "png"):
        raise LanternaInputError(path, f"unsupported plane format {fmt!r}; expected jpg or png")
    return str(fmt)


def _open_plane(folder: Path, index: int, ext: str, width: int, height: int,
                count: int) -> tuple[Path, pyvips.Image]:
    """Open ``plane_{index}.{ext}`` (its header only), or the plane's tiled layout
    (:mod:`.relight_layouts`: deepzoom, tarzoom, itarzoom), and check its size and bands."""
    path = folder / f"plane_{index}.{ext}"
    source = None if path.is_file() else tiled_plane_source(folder, index)
    image = None if source is None else open_tiled_plane(folder, index, count, width, height)
    if source is not None and image is not None:
        path = source[1]
    elif not path.is_file():
        tiled = (folder / f"plane_{index}").exists()
        hint = "; tiled layouts google and zoomify are not supported" if tiled else ""
        raise LanternaInputError(path, f"plane {index} is missing{hint}")
    else:
        # From a buffer, not a file name: libvips caches loads by name, so a plane rewritten in
        # place would come back stale. open_rgb_plane checks 8-bit RGB, as the layouts check
        # every tile.
        image = open_rgb_plane(read_input(path, "a plane image"), path)
    w, h = image.width, image.height
    if (w, h) != (width, height):
        raise LanternaInputError(path, f"plane is {w}x{h}, info.json says {width}x{height}")
    return path, image


def _decode_plane(path: Path, image: pyvips.Image) -> list[npt.NDArray[np.uint8]]:
    """The three ``(H, W)`` channels of an opened plane."""
    try:
        pixels = image.write_to_memory()
    except pyvips.Error as exc:
        raise LanternaInputError(path, f"cannot decode plane ({vips_reason(exc)})") from None
    rgb = np.frombuffer(pixels, dtype=np.uint8).reshape(image.height, image.width, 3)
    return [rgb[..., c] for c in range(3)]


def _stack(planes: npt.NDArray[np.uint8], idx: list[int]) -> npt.NDArray[np.uint8]:
    return np.ascontiguousarray(np.stack([planes[i] for i in idx], axis=-1))


def _ptm_group(planes: npt.NDArray[np.uint8], channels: list[str], idx: list[int],
               scale: list[float], bias: list[float], lossy: bool) -> PlaneGroup:
    """One PTM group; planes beyond a degree-1 PTM become zero channels (scale 0, bias 0)."""
    n = planes.shape[0]
    if all(i >= n for i in idx):
        zeros = np.zeros(planes.shape[1:] + (3,), np.uint8)
        return PlaneGroup(channels, zeros, [0.0] * 3, [0.0] * 3)
    return PlaneGroup(channels, _stack(planes, idx), [scale[i] for i in idx],
                      [bias[i] for i in idx], lossy)
