"""A description layer's ``overlay`` entry, attached to its plan."""

from __future__ import annotations

from pathlib import Path
from typing import Any

from lanterna.tiler.dataset.plan import LayerPlan
from lanterna.tiler.dataset.writer import DatasetWriter
from lanterna.tiler.overlays.build import scene_overlay


def attach_overlay(plan: LayerPlan, overlay: Any, base: Path | None = None) -> None:
    """Give a planned layer its overlay when it is added.

    A seed-paper ``{img, range, shortInfo, longInfo}`` entry has its level images (relative to
    ``base``) tiled as the layer's overlay levels; other values are kept in the dataset as given.
    """
    add = plan.add

    def add_with_overlay(ds: DatasetWriter) -> object:
        layer = add(ds)
        if isinstance(layer, dict):
            if base is not None and isinstance(overlay, dict) and "img" in overlay:
                layer["overlay"] = scene_overlay(ds, layer["id"], overlay, base)
            else:
                layer["overlay"] = overlay
        return layer

    plan.add = add_with_overlay
