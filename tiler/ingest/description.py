"""Dataset description files: several co-registered layers, as JSON, imported in one go.

Lanterna's own form (paths relative to the file; docs/importing.md)::

    {"name": "tablet", "label": "Tablet", "summary": "<p>…</p>",
     "layers": [
       {"id": "vis", "source": "vis.ptm"},
       {"id": "hsh", "source": "vis.rti", "label": "Visible (HSH)"},
       {"id": "mat", "type": "svbrdf", "maps": {"normals": "N.png", "kd": "kd.png"},
        "glossLimits": [0.01, 0.5], "inputColorSpace": "srgb", "normalConvention": "opengl"},
       {"type": "bands", "bands": {"IR": "ir.tif", "R": "r.tif", "G": "g.tif"},
        "fusions": [["IR", "R", "G"]]}
     ]}

The seed paper's scene description (``obj.shader`` / ``obj.maps``) is recognised too and converted
by :mod:`.scene`.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

from lanterna.errors import LanternaInputError
from lanterna.tiler.dataset.plan import LayerPlan
from lanterna.tiler.fileio import read_json

from .overlay import attach_overlay
from .scene import plan_scene
from .sources import plan_bands, plan_source, plan_svbrdf


def is_scene(doc: dict[str, Any]) -> bool:
    """Tell the seed paper's scene format (layers with ``obj``) from Lanterna's own."""
    layers = doc.get("layers")
    return isinstance(layers, list) and any(isinstance(x, dict) and "obj" in x for x in layers)


def plan_description(path: Path) -> tuple[dict[str, Any], list[LayerPlan]]:
    """Return the dataset fields (name, label, summary) and the layer plans of a description."""
    path = Path(path)
    doc = read_json(path)
    if is_scene(doc):
        return plan_scene(doc, path)
    layers = doc.get("layers")
    if not isinstance(layers, list) or not layers:
        raise LanternaInputError(path, "needs a non-empty \"layers\" list")
    base = path.parent
    plans: list[LayerPlan] = []
    for i, entry in enumerate(layers):
        if not isinstance(entry, dict):
            raise LanternaInputError(path, f"layer {i} is not an object")
        plans.extend(_plan_entry(entry, base, path, i))
    fields = {k: doc[k] for k in ("name", "label", "summary") if isinstance(doc.get(k), str)}
    return fields, plans


def _plan_entry(entry: dict[str, Any], base: Path, path: Path, i: int) -> list[LayerPlan]:
    kind = entry.get("type", "source")
    lid = entry.get("id")
    label = entry.get("label")
    where = f"layer {lid or i}"
    if kind == "source" or (kind in ("ptm", "hsh", "image") and "source" in entry):
        if "source" not in entry:
            raise LanternaInputError(path, f"{where}: needs \"source\"")
        plan = plan_source(base / entry["source"], layer_id=lid, label=label)
        if "overlay" in entry:
            attach_overlay(plan, entry["overlay"], base)
        return [plan]
    if kind == "svbrdf":
        maps = entry.get("maps")
        if not isinstance(maps, dict) or not lid:
            raise LanternaInputError(path, f"{where}: an svbrdf layer needs \"id\" and \"maps\"")
        limits = entry.get("glossLimits", [0.01, 0.5])
        if not (isinstance(limits, list) and len(limits) == 2):
            raise LanternaInputError(path, f"{where}: glossLimits must be [min, max]")
        plan = plan_svbrdf({k: base / v for k, v in maps.items()}, layer_id=lid, label=label,
                           gloss_limits=(float(limits[0]), float(limits[1])),
                           input_colorspace=str(entry.get("inputColorSpace", "linear")).lower(),
                           normal_convention=str(entry.get("normalConvention", "opengl")))
        if "overlay" in entry:
            attach_overlay(plan, entry["overlay"], base)
        return [plan]
    if kind == "bands":
        bands = entry.get("bands")
        if not isinstance(bands, dict) or not bands:
            raise LanternaInputError(path,
                                     f"{where}: a bands entry needs \"bands\": {{name: file}}")
        return plan_bands({k: base / v for k, v in bands.items()}, entry.get("fusions", []))
    raise LanternaInputError(path, f"{where}: unknown layer type {kind!r} (expected a source, "
                             "svbrdf or bands)")
