"""Layer plans: sources read and checked first, a dataset written only once all of them are good.

A :class:`LayerPlan` holds one layer's decoded data (so sizes can be checked across layers before
anything is written) and a closure that adds it to a :class:`~.writer.DatasetWriter`.
:func:`build_dataset` checks that every layer has the canvas size and writes them in order.
The importers (:mod:`lanterna.tiler.ingest`) and the fitting run (:mod:`lanterna.tiler.fit.run`)
make the plans.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from lanterna.errors import LanternaInputError

from .writer import DEFAULT_BASE_URL, DatasetWriter


@dataclass
class LayerPlan:
    """One layer ready to be written: its id, size, source name and how to add it."""

    id: str
    label: str
    width: int
    height: int
    source: str
    add: Callable[[DatasetWriter], object]
    #: The physical size of a pixel the source states (Relight's ``pixelSizeInMM``), if any.
    pixel_size_mm: float | None = None


def build_dataset(plans: Sequence[LayerPlan], out: Path, *, name: str, label: str,
                  base_url: str = DEFAULT_BASE_URL, tile_size: int = 256, force: bool = False,
                  summary: str | None = None, quality: dict[str, Any] | None = None,
                  tiff: bool = False, pixel_size_mm: float | None = None,
                  publication: Mapping[str, Any] | None = None) -> Path:
    """Write the planned layers (same size, unique ids) as one dataset at ``out``.

    ``tiff=True`` also writes a pyramidal TIFF per image for the IIIF image server.
    ``pixel_size_mm`` is the physical size of a pixel (``--pixel-size``); without it, the first
    one a plan's source states is used. ``publication``: the manifest's rights, attribution,
    provider, links and metadata (:mod:`lanterna.manifests.metadata`).
    """
    if not plans:
        raise LanternaInputError(None, "nothing to import: give at least one source")
    w, h = plans[0].width, plans[0].height
    seen: set[str] = set()
    for plan in plans:
        if (plan.width, plan.height) != (w, h):
            raise LanternaInputError(plan.source, f"is {plan.width}x{plan.height}, but "
                                     f"{plans[0].source} is {w}x{h}: layers must be co-registered")
        if plan.id in seen:
            raise LanternaInputError(plan.source, f"layer id {plan.id!r} is used twice")
        seen.add(plan.id)
    if pixel_size_mm is None:
        pixel_size_mm = next((p.pixel_size_mm for p in plans if p.pixel_size_mm), None)
    with DatasetWriter(out, name=name, label=label, width=w, height=h, base_url=base_url,
                       tile_size=tile_size, source=", ".join(p.source for p in plans),
                       force=force, summary=summary,
                       quality=quality, tiff=tiff, pixel_size_mm=pixel_size_mm,
                       publication=publication) as ds:
        for plan in plans:
            plan.add(ds)
    return Path(out)
