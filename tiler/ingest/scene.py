"""Import the seed paper's scene description (Jaspe Villanueva et al., JOCCH 2021, §4.3).

A scene lists layers whose ``obj.shader.type`` is ``LRGB_PTM`` (maps ``coeff_0_1_2``,
``coeff_3_4_5``, ``coeff_6_7_8`` with ``scale``/``bias`` in 0–255 units) or ``SVBRDF`` (maps ``kd``,
``ks``, ``gloss``, ``N``, with ``glossLimits`` and ``inputColorSpace``). Image names are templates
completed by a two-digit level of detail: ``vis/kdMap.jpg`` names ``vis/kdMap00.jpg`` at full
resolution (we build our own pyramids, so only level ``00`` is read; a name that exists as
written is accepted too). Layers sharing a file (e.g. one normal map) share one stored image.
``overlay`` entries (``img`` template, ``range``, ``shortInfo``, ``longInfo``) become the layer's
overlay levels (:func:`lanterna.tiler.overlays.build.scene_overlay`); missing level images are
warnings.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

from lanterna.errors import LanternaInputError
from lanterna.tiler.dataset.layers import add_planes_layer
from lanterna.tiler.dataset.plan import LayerPlan
from lanterna.tiler.formats.planes import PlaneGroup, PlaneLayer
from lanterna.tiler.inputs.maps import load_color_map

from .overlay import attach_overlay
from .sources import layer_id_from, plan_svbrdf

SHADER_TYPES = ("LRGB_PTM", "SVBRDF")
_PTM_MAPS = ("coeff_0_1_2", "coeff_3_4_5", "coeff_6_7_8")
_SCENE_MAP_NAMES = {"N": "normals", "kd": "kd", "ks": "ks", "gloss": "gloss"}


def resolve_template(base: Path, name: str, scene: Path) -> Path:
    """Return the level-00 file of template ``name`` (or ``name`` itself if it exists)."""
    template = base / name
    level0 = template.with_name(f"{template.stem}00{template.suffix}")
    for candidate in (level0, template):
        if candidate.is_file():
            return candidate
    raise LanternaInputError(scene, f"map {name}: neither {level0.name} nor {template.name} exists "
                             f"in {template.parent}")


def plan_scene(doc: dict[str, Any], path: Path) -> tuple[dict[str, Any], list[LayerPlan]]:
    """Plan the layers of a seed-paper scene; return dataset fields and plans."""
    base = Path(path).parent
    plans = []
    for i, layer in enumerate(doc["layers"]):
        if not isinstance(layer, dict) or not isinstance(layer.get("obj"), dict):
            raise LanternaInputError(path, f"layer {i}: needs an \"obj\" object")
        lid = layer_id_from(str(layer.get("id", f"layer{i}")))
        label = str(layer.get("name", lid))
        shader = layer["obj"].get("shader", {})
        maps = layer["obj"].get("maps", {})
        kind = shader.get("type") if isinstance(shader, dict) else None
        if kind == "LRGB_PTM":
            plan = _plan_ptm(lid, label, shader, maps, base, path)
        elif kind == "SVBRDF":
            unknown = sorted(set(maps) - set(_SCENE_MAP_NAMES))
            if unknown:
                raise LanternaInputError(path, f"layer {lid}: unknown SVBRDF map(s) "
                                         f"{', '.join(unknown)}")
            limits = shader.get("glossLimits", [0.01, 0.5])
            plan = plan_svbrdf(
                {_SCENE_MAP_NAMES[k]: resolve_template(base, v, path) for k, v in maps.items()},
                layer_id=lid, label=label, gloss_limits=(float(limits[0]), float(limits[1])),
                input_colorspace=str(shader.get("inputColorSpace", "linear")).lower())
        else:
            raise LanternaInputError(path, f"layer {lid}: unknown shader type {kind!r} "
                                     f"(expected {' or '.join(SHADER_TYPES)})")
        if "overlay" in layer:
            attach_overlay(plan, layer["overlay"], base)
        plans.append(plan)
    for key in ("width", "height"):
        declared = doc.get(key)
        if declared is not None and plans and declared != getattr(plans[0], key):
            raise LanternaInputError(path, f"declares {key} {declared}, but the layers' maps are "
                                     f"{plans[0].width}x{plans[0].height}")
    fields = {"label": str(doc.get("name", Path(path).stem))}
    if isinstance(doc.get("info"), str):
        fields["summary"] = doc["info"]
    return fields, plans


def _plan_ptm(lid: str, label: str, shader: dict[str, Any], maps: dict[str, str], base: Path,
              path: Path) -> LayerPlan:
    missing = [m for m in _PTM_MAPS if m not in maps]
    if missing:
        raise LanternaInputError(path, f"layer {lid}: LRGB_PTM needs maps {', '.join(missing)}")
    scale, bias = shader.get("scale"), shader.get("bias")
    if not (isinstance(scale, list) and isinstance(bias, list) and len(scale) == len(bias) == 6):
        raise LanternaInputError(path, f"layer {lid}: LRGB_PTM needs 6 scales and 6 biases")
    images = [load_color_map(resolve_template(base, maps[m], path)) for m in _PTM_MAPS]
    if len({im.shape for im in images}) != 1:
        raise LanternaInputError(path, f"layer {lid}: the coefficient maps differ in size")
    s = [float(v) for v in scale]
    b = [float(v) / 255.0 for v in bias]
    planes = PlaneLayer("ptm", [
        PlaneGroup(["L0", "L1", "L2"], np.ascontiguousarray(images[0]), s[0:3], b[0:3]),
        PlaneGroup(["L3", "L4", "L5"], np.ascontiguousarray(images[1]), s[3:6], b[3:6]),
        PlaneGroup(["R", "G", "B"], np.ascontiguousarray(images[2]), [1.0] * 3, [0.0] * 3),
    ], colorspace="lrgb")
    return LayerPlan(lid, label, planes.width, planes.height, maps["coeff_0_1_2"],
                     lambda ds: add_planes_layer(ds, planes, layer_id=lid, label=label))
