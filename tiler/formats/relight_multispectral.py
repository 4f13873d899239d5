"""Read OpenLIME's multispectral folders: ``info.json`` + ``{basename}_NN.jpg``, N bands.

Format (OpenLIME ``src/LayerMultispectral.js`` ``loadInfo``, ``src/ShaderMultispectral.js``
``init``/``getBand``; its sample ``dist/assets/multispectral/oil_painting_ms_jpg/``):

- ``info.json``: ``type: "multispectral"``, ``width``, ``height``, ``basename`` (required),
  ``wavelength`` (one number per band, nm), ``nplanes`` (the band count), ``format`` (``jpg``
  default, or ``png``), ``pixelSizeInMM``.
- Band ``i`` is channel ``i % 3`` of the RGB image ``{basename}_{i // 3:02d}.{format}``
  (``_00``, ``_01``, …; the last image's unused channels are ignored). The values are used as
  stored (OpenLIME's rasters are ``isLinear``: no sRGB decoding).
- The tiled layouts name each image the same way (``{basename}_NN.dzi``, ``.tzi``) and the
  itarzoom pair ``{basename}.tzi`` / ``.tzb`` (:mod:`.relight_layouts`).
- Colour mixes ("Color Twist Weights") live beside it in ``presets.json``: ``{name: {red: [N],
  green: [N], blue: [N]}}``, the colour being ``Σᵢ wᵢ · bandᵢ`` per channel (OpenLIME's ``rgb``
  mode). The true-colour composite uses the preset ``d65_true_color`` (else ``true color``,
  ``true_color``, ``trueColor``); without one, :func:`range_weights`.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import numpy.typing as npt
import pyvips

from lanterna.errors import LanternaInputError
from lanterna.tiler.documents import document_type, load_json
from lanterna.tiler.fileio import read_input
from lanterna.tiler.limits import check_pixels

from .relight_layouts import open_rgb_plane, open_tiled_plane, tiled_plane_source

#: Most bands read (the description schema's limit on bands; OpenLIME's shader stops at 33).
MAX_BANDS = 64
#: Preset names of a true-colour mix, in order of preference.
TRUE_COLOUR_PRESETS = ("d65_true_color", "true color", "true_color", "trueColor")
#: The fallback mix: the wavelength range (nm) each of R, G, B averages, and its centre.
CHANNEL_RANGES = {"red": (600.0, 700.0), "green": (500.0, 600.0), "blue": (400.0, 500.0)}
_BASENAME = re.compile(r"[A-Za-z0-9_][A-Za-z0-9_.-]{0,199}")


@dataclass(frozen=True)
class Multispectral:
    """N co-registered bands with their wavelengths and a true-colour mix.

    ``bands`` is ``(N, H, W)`` uint8, ``weights`` ``(3, N)`` (R, G, B rows), ``weights_source``
    says where the mix came from (``presets.json 'd65_true_color'`` or ``wavelength ranges``).
    """

    wavelengths: list[float]
    bands: npt.NDArray[np.uint8]
    weights: npt.NDArray[np.float64]
    weights_source: str
    pixel_size_mm: float | None = None

    @property
    def width(self) -> int:
        return int(self.bands.shape[2])

    @property
    def height(self) -> int:
        return int(self.bands.shape[1])

    def composite(self, rows: int = 256) -> npt.NDArray[np.uint8]:
        """The true-colour ``(H, W, 3)`` image: ``clamp(Σᵢ wᵢ · bandᵢ/255)``, in row bands."""
        out = np.empty((self.height, self.width, 3), np.uint8)
        w = self.weights.astype(np.float32)
        for y0 in range(0, self.height, rows):
            t = self.bands[:, y0 : y0 + rows].astype(np.float32) / np.float32(255)
            rgb = np.einsum("cn,nhw->hwc", w, t)
            out[y0 : y0 + rows] = np.round(np.clip(rgb, 0, 1) * 255).astype(np.uint8)
        return out


def is_multispectral(folder: Path) -> bool:
    """Whether ``folder`` has an ``info.json`` whose ``type`` is ``multispectral``."""
    # an unreadable info.json is for the Relight reader to report
    return document_type(Path(folder) / "info.json") == "multispectral"


def read_multispectral(folder: str | Path) -> Multispectral:
    """Read an OpenLIME multispectral folder (any layout); check everything before decoding.

    Raises
    ------
    LanternaInputError
        Naming the file and field: a bad ``info.json`` or ``presets.json``, a missing or
        undecodable image, an image of the wrong size.
    """
    src = Path(folder)
    path = src / "info.json"
    doc = load_json(path)
    if not isinstance(doc, dict) or doc.get("type") != "multispectral":
        raise LanternaInputError(path, "not an OpenLIME multispectral info.json (type must be "
                                 "'multispectral')")
    width, height = (_positive_int(doc, key, path) for key in ("width", "height"))
    check_pixels(path, width, height, "the multispectral image")
    wavelengths = _wavelengths(doc, path)
    basename = doc.get("basename")
    if not isinstance(basename, str) or not _BASENAME.fullmatch(basename):
        raise LanternaInputError(path, f"basename must be a file name stem (letters, digits, "
                                 f"_ . -), got {basename!r}"[:200])
    fmt = doc.get("format", "jpg")
    if fmt not in ("jpg", "png"):
        raise LanternaInputError(path, f"format must be jpg or png, got {fmt!r}"[:200])
    weights, source = true_colour_weights(src / "presets.json", wavelengths)
    nimg = -(-len(wavelengths) // 3)
    images = [_open_image(src, basename, k, nimg, fmt, width, height) for k in range(nimg)]
    channels: list[npt.NDArray[np.uint8]] = []
    for k, image in enumerate(images):
        rgb = np.frombuffer(image.write_to_memory(), np.uint8).reshape(height, width, 3)
        channels.extend(rgb[..., c] for c in range(min(3, len(wavelengths) - 3 * k)))
    size = doc.get("pixelSizeInMM")
    return Multispectral(wavelengths, np.stack(channels), weights, source,
                         float(size) if isinstance(size, int | float) and size > 0 else None)


def _positive_int(doc: dict[str, Any], key: str, path: Path) -> int:
    value = doc.get(key)
    if isinstance(value, bool) or not isinstance(value, int) or value <= 0:
        raise LanternaInputError(path, f"{key} must be a positive integer, got {value!r}"[:200])
    return value


def _wavelengths(doc: dict[str, Any], path: Path) -> list[float]:
    raw = doc.get("wavelength")
    if not isinstance(raw, list) or not 1 <= len(raw) <= MAX_BANDS:
        got = f"{len(raw)} values" if isinstance(raw, list) else repr(raw)[:40]
        raise LanternaInputError(path, f"wavelength must list 1 to {MAX_BANDS} wavelengths (nm), "
                                 f"got {got}")
    out: list[float] = []
    for i, v in enumerate(raw):
        if isinstance(v, bool) or not isinstance(v, int | float) or not math.isfinite(v) \
                or not 0 < v < 1e6:
            raise LanternaInputError(path, f"wavelength[{i}] must be a positive number of nm, "
                                     f"got {v!r}"[:200])
        if float(v) in out:
            raise LanternaInputError(path, f"wavelength[{i}] {v:g} nm repeats wavelength"
                                     f"[{out.index(float(v))}]")
        out.append(float(v))
    nplanes = doc.get("nplanes", len(out))
    if nplanes != len(out):
        raise LanternaInputError(path, f"nplanes is {nplanes!r} but wavelength lists {len(out)} "
                                 "bands"[:200])
    return out


def true_colour_weights(presets: Path, wavelengths: list[float]) -> tuple[
        npt.NDArray[np.float64], str]:
    """The ``(3, N)`` true-colour mix: a preset of ``presets.json`` if it has one, else
    :func:`range_weights`."""
    if not presets.exists():
        return range_weights(wavelengths), "wavelength ranges"
    doc = load_json(presets)
    if not isinstance(doc, dict):
        raise LanternaInputError(presets, "must be a JSON object of presets")
    name = next((n for n in TRUE_COLOUR_PRESETS if n in doc), None)
    if name is None:
        return range_weights(wavelengths), "wavelength ranges"
    preset = doc[name]
    if not isinstance(preset, dict):
        raise LanternaInputError(presets, f"{name}: expected an object with red, green, blue")
    rows = []
    for channel in ("red", "green", "blue"):
        values = preset.get(channel)
        if not isinstance(values, list) or len(values) != len(wavelengths) or not all(
                isinstance(v, int | float) and not isinstance(v, bool) and math.isfinite(v)
                and abs(v) <= 1e3 for v in values):
            got = f"{len(values)} values" if isinstance(values, list) else repr(values)[:40]
            raise LanternaInputError(presets, f"{name}.{channel}: expected {len(wavelengths)} "
                                     f"finite weights (one per band, |w| ≤ 1000), got {got}")
        rows.append([float(v) for v in values])
    return np.array(rows, np.float64), f"presets.json {name!r}"


def range_weights(wavelengths: list[float]) -> npt.NDArray[np.float64]:
    """Each of R, G, B averages the bands in its range (:data:`CHANNEL_RANGES`, the upper end
    included for red only); a channel with none takes the band nearest its range's centre."""
    wl = np.array(wavelengths, np.float64)
    out = np.zeros((3, wl.size))
    for row, (low, high) in enumerate(CHANNEL_RANGES.values()):
        inside = (wl >= low) & ((wl < high) | (row == 0) & (wl == high))
        if inside.any():
            out[row, inside] = 1.0 / inside.sum()
        else:
            out[row, int(np.argmin(np.abs(wl - (low + high) / 2)))] = 1.0
    return out


def _open_image(folder: Path, basename: str, k: int, count: int, fmt: str, width: int,
                height: int) -> pyvips.Image:
    stem = f"{basename}_{k:02d}"
    path = folder / f"{stem}.{fmt}"
    if path.is_file():
        image = open_rgb_plane(read_input(path, "a band image"), path, "band image")
    else:
        source = tiled_plane_source(folder, k, name=stem, interleaved=basename)
        if source is None:
            raise LanternaInputError(path, f"band image {k} is missing (it holds bands from "
                                     f"{3 * k} on)")
        path = source[1]
        # tiles are checked 8-bit RGB and the image's size against the .dzi / .tzi
        image = open_tiled_plane(folder, k, count, width, height, name=stem,
                                 interleaved=basename)
    if (image.width, image.height) != (width, height):
        raise LanternaInputError(path, f"band image is {image.width}x{image.height}, info.json "
                                 f"says {width}x{height}")
    return image
