"""Plan the layers of an OpenLIME multispectral folder: a true-colour composite, then one grey
``image`` layer per band labelled with its wavelength (docs/importing.md "Multispectral")."""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

from lanterna.tiler.dataset.layers import add_image_layer
from lanterna.tiler.dataset.plan import LayerPlan
from lanterna.tiler.dataset.writer import DatasetWriter, check_identifier
from lanterna.tiler.formats.relight_multispectral import Multispectral, read_multispectral
from lanterna.tiler.iiif.pyramid import vips_from_array

from .sources import layer_id_from


def nm(wavelength: float) -> str:
    """A wavelength as written in labels: ``450``, ``450.5``."""
    return f"{wavelength:g}"


def plan_multispectral(folder: Path, *,
                       layer_id: str | None = None) -> tuple[list[LayerPlan], str]:
    """The composite (id ``{layer_id}``, default the folder's name) and one layer per band
    (``{layer_id}_{nm}nm``, label ``"450 nm"``; its service block has ``wavelength``), and a
    summary for the manifest naming the bands (:func:`summary`)."""
    folder = Path(folder)
    ms = read_multispectral(folder)
    base = check_identifier(layer_id or layer_id_from(folder.name), "layer id")
    lo, hi = nm(min(ms.wavelengths)), nm(max(ms.wavelengths))
    label = f"{folder.name} (true colour, {len(ms.wavelengths)} bands {lo}–{hi} nm)"
    composite = vips_from_array(ms.composite())
    plans = [LayerPlan(base, label, ms.width, ms.height, folder.name,
                       lambda ds: add_image_layer(ds, composite, layer_id=base, label=label,
                                                  fmt="png"),
                       pixel_size_mm=ms.pixel_size_mm)]
    for k, wavelength in enumerate(ms.wavelengths):
        lid = check_identifier(f"{base}_{nm(wavelength).replace('.', '_')}nm", "layer id")
        plans.append(LayerPlan(lid, f"{nm(wavelength)} nm", ms.width, ms.height,
                               f"{folder.name} band {k}", _band_adder(ms, k, lid)))
    return plans, summary(ms)


def summary(ms: Multispectral) -> str:
    """The manifest summary of a multispectral import: its bands and the composite's mix."""
    bands = ", ".join(nm(w) for w in ms.wavelengths)
    return (f"Multispectral (OpenLIME): {len(ms.wavelengths)} bands at {bands} nm; true colour "
            f"from {ms.weights_source}.")


def _band_adder(ms: Multispectral, k: int, lid: str) -> Callable[[DatasetWriter], object]:
    def add(ds: DatasetWriter) -> object:
        layer = add_image_layer(ds, vips_from_array(ms.bands[k]), layer_id=lid,
                                label=f"{nm(ms.wavelengths[k])} nm", fmt="png")
        layer["wavelength"] = ms.wavelengths[k]  # nm, in the layer's service block
        return layer
    return add
