"""Turn sources (files, folders, description files, spectral bands) into one dataset."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

from lanterna.errors import LanternaInputError
from lanterna.tiler.dataset.plan import LayerPlan, build_dataset
from lanterna.tiler.dataset.plane_format import AUTO, PlaneFormat
from lanterna.tiler.dataset.writer import DEFAULT_BASE_URL, check_identifier
from lanterna.tiler.formats.relight_multispectral import is_multispectral

from .archiox import is_manifest_source, plan_archiox
from .description import plan_description
from .multispectral import plan_multispectral
from .sources import plan_bands, plan_source


def import_sources(sources: Sequence[Path | str], out: Path, *, name: str | None = None,
                   label: str | None = None, bands: dict[str, Path] | None = None,
                   fusions: Sequence[Sequence[str]] = (), base_url: str = DEFAULT_BASE_URL,
                   tile_size: int = 256, force: bool = False, tiff: bool = False,
                   plane_format: PlaneFormat = AUTO, pixel_size_mm: float | None = None,
                   extra_plans: Sequence[LayerPlan] = (), summary: str | None = None,
                   publication: Mapping[str, Any] | None = None) -> Path:
    """Import sources as the layers of dataset ``out`` (in order; the first is the default).

    A source is a ``.ptm``, ``.rti``, a Relight web-format folder (any layout), an OpenLIME
    multispectral folder (a composite and one layer per band), an image, or a dataset
    description ``.json`` (Lanterna's or the seed paper's scene format), or an ARCHiOx-style IIIF
    manifest (a ``.json`` file or an http(s) URL; :mod:`.archiox`). ``extra_plans`` (e.g. an
    albedo + normal pair, :func:`.archiox.plan_map_pair`) follow the sources. ``bands`` adds one
    grey layer per spectral band, ``fusions`` one false-colour layer per band triple. ``tiff`` also
    writes a pyramidal TIFF per image (``tiff/<image>.tif``) for the IIIF image server.
    ``plane_format`` (``--plane-format``) is the tile format of relightable layers' planes
    (:mod:`lanterna.tiler.dataset.plane_format`). ``pixel_size_mm`` (``--pixel-size``) is the
    physical size of a pixel; without it, a Relight source's ``pixelSizeInMM`` is used.
    ``summary`` and ``publication`` (rights, attribution, provider, links, metadata:
    :mod:`lanterna.manifests.metadata`) come from the options; a description file's own
    fields fill in the ones not given, field by field.
    """
    plans: list[LayerPlan] = []
    fields: dict[str, Any] = {}
    for given in sources:
        if is_manifest_source(given):
            mf_fields, plan = plan_archiox(given, plane_format=plane_format)
            fields = {**mf_fields, **fields}
            plans.append(plan)
            continue
        source = Path(given)
        if source.suffix.lower() == ".json" and source.is_file():
            desc_fields, desc_plans = plan_description(source, plane_format=plane_format)
            fields = {**desc_fields, **fields}
            plans.extend(desc_plans)
        elif source.is_dir() and is_multispectral(source):
            ms_plans, ms_summary = plan_multispectral(source)
            fields.setdefault("summary", ms_summary)
            plans.extend(ms_plans)
        else:
            plans.append(plan_source(source, plane_format=plane_format))
    plans.extend(extra_plans)
    if bands:
        plans.extend(plan_bands(bands, fusions))
    elif fusions:
        raise LanternaInputError(None, "--fusion needs spectral bands (--band NAME=FILE)")
    first = Path(sources[0]) if sources else Path(out)
    ds_name = check_identifier(name or fields.get("name") or _safe_name(Path(out).name),
                               "dataset name")
    ds_label = label or fields.get("label") or first.stem
    return build_dataset(plans, out, name=ds_name, label=ds_label, base_url=base_url,
                         tile_size=tile_size, force=force,
                         summary=summary or fields.get("summary"), tiff=tiff,
                         pixel_size_mm=pixel_size_mm,
                         publication={**fields.get("publication", {}), **(publication or {})})


def _safe_name(stem: str) -> str:
    cleaned = "".join(ch if ch.isalnum() or ch in "_-" else "_" for ch in stem)
    return cleaned or "dataset"
