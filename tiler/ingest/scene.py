"""Import the seed paper's scene description (Jaspe Villanueva et al., JOCCH 2021, §4.3).

A scene lists layers whose ``obj.shader.type`` is ``LRGB_PTM`` (maps ``coeff_0_1_2``,
``coeff_3_4_5``, ``coeff_6_7_8`` with ``scale``/``bias`` in 0–255 units) or ``SVBRDF`` (maps ``kd``,
``ks``, ``gloss``, ``N``, with ``glossLimits`` and ``inputColorSpace``). Image names are templates
completed by a two-digit level of detail: ``vis/kdMap.jpg`` names ``vis/kdMap00.jpg`` at full
resolution (we build our own pyramids, so only level ``00`` is read; a name that exists as
written is accepted too). Layers sharing a file (e.g. one normal map) share one stored image.
``overlay`` entries (``img`` template, ``range``, ``shortInfo``, ``longInfo``) become the layer's
overlay levels (:func:`lanterna.tiler.overlays.build.scene_overlay`); missing level images are
warnings. The scene is checked against ``tiler/schemas/scene.schema.json`` before it is read into
typed :class:`SceneLayer` records.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from lanterna.errors import LanternaInputError
from lanterna.tiler.dataset.layers import add_planes_layer
from lanterna.tiler.dataset.plan import LayerPlan
from lanterna.tiler.dataset.plane_format import AUTO, PlaneFormat
from lanterna.tiler.formats.planes import PlaneGroup, PlaneLayer
from lanterna.tiler.inputs.maps import is_lossy_file, load_color_map
from lanterna.tiler.limits import check_quantisation

from .overlay import attach_overlay
from .paths import referenced
from .sources import layer_id_from, plan_svbrdf

SHADER_TYPES = ("LRGB_PTM", "SVBRDF")
_PTM_MAPS = ("coeff_0_1_2", "coeff_3_4_5", "coeff_6_7_8")
_SCENE_MAP_NAMES = {"N": "normals", "kd": "kd", "ks": "ks", "gloss": "gloss"}


@dataclass(frozen=True)
class SceneLayer:
    """One layer of a scene, typed: its shader's parameters and its maps' level-00 files."""

    id: str
    label: str
    shader: str
    maps: dict[str, Path]
    scale: tuple[float, ...] = ()
    bias: tuple[float, ...] = ()
    gloss_limits: tuple[float, float] = (0.01, 0.5)
    input_colorspace: str = "linear"
    overlay: dict[str, Any] | None = None


def is_scene(doc: Any) -> bool:
    """Tell the seed paper's scene format (layers with ``obj``) from Lanterna's own."""
    layers = doc.get("layers") if isinstance(doc, dict) else None
    return isinstance(layers, list) and any(isinstance(x, dict) and "obj" in x for x in layers)


def resolve_template(base: Path, name: str, scene: Path, *, where: str = "map",
                     root: Path | None = None) -> Path:
    """Return the level-00 file of template ``name`` (or ``name`` itself if it exists)."""
    template = referenced(base, name, source=scene, where=where, root=root)
    level0 = template.with_name(f"{template.stem}00{template.suffix}")
    for candidate in (level0, template):
        if candidate.is_file():
            return candidate
    raise LanternaInputError(scene, f"{where}: neither {level0.name} nor {template.name} exists "
                             f"in {template.parent}")


def read_scene(doc: dict[str, Any], path: Path, *, root: Path | None = None) -> list[SceneLayer]:
    """The typed layers of a scene that passed its schema (map files resolved)."""
    base = Path(path).parent
    layers = []
    for i, raw in enumerate(doc["layers"]):
        at = f"layers[{i}]"
        lid = layer_id_from(str(raw.get("id", f"layer{i}")))
        shader, maps = raw["obj"]["shader"], raw["obj"]["maps"]
        unknown = sorted(set(maps) - set(_SCENE_MAP_NAMES)) if shader["type"] == "SVBRDF" else []
        missing = [m for m in _PTM_MAPS if m not in maps] if shader["type"] == "LRGB_PTM" else []
        if unknown or missing:
            problem = (f"unknown map(s) {', '.join(unknown)}" if unknown
                       else f"LRGB_PTM needs maps {', '.join(missing)}")
            raise LanternaInputError(path, f"{at}.obj.maps: {problem}")
        low, high = (float(v) for v in shader.get("glossLimits", (0.01, 0.5)))
        if low > high:
            raise LanternaInputError(path, f"{at}.obj.shader.glossLimits: expected [min, max] "
                                     f"with min <= max (got [{low}, {high}])")
        overlay = raw.get("overlay")
        layers.append(SceneLayer(
            lid, str(raw.get("name", lid)), shader["type"],
            {k: resolve_template(base, v, path, where=f"{at}.obj.maps.{k}", root=root)
             for k, v in maps.items() if k in _PTM_MAPS or shader["type"] == "SVBRDF"},
            tuple(float(v) for v in shader.get("scale", ())),
            tuple(float(v) for v in shader.get("bias", ())), (low, high),
            shader.get("inputColorSpace", "linear").lower(), overlay))
    return layers


def plan_scene(doc: dict[str, Any], path: Path, *, root: Path | None = None,
               plane_format: PlaneFormat = AUTO) -> tuple[dict[str, Any], list[LayerPlan]]:
    """Plan the layers of a seed-paper scene (checked against its schema); return dataset fields
    and plans."""
    base = Path(path).parent
    plans = []
    for layer in read_scene(doc, path, root=root):
        if layer.shader == "LRGB_PTM":
            plan = _plan_ptm(layer, path, plane_format)
        else:
            plan = plan_svbrdf({_SCENE_MAP_NAMES[k]: f for k, f in layer.maps.items()},
                               layer_id=layer.id, label=layer.label,
                               gloss_limits=layer.gloss_limits,
                               input_colorspace=layer.input_colorspace,
                               plane_format=plane_format)
        if layer.overlay is not None:
            attach_overlay(plan, layer.overlay, base)
        plans.append(plan)
    for key in ("width", "height"):
        declared = doc.get(key)
        if declared is not None and plans and declared != getattr(plans[0], key):
            raise LanternaInputError(path, f"{key}: declares {declared}, but the layers' maps are "
                                     f"{plans[0].width}x{plans[0].height}")
    fields = {"label": doc.get("name", Path(path).stem)}
    if "info" in doc:
        fields["summary"] = doc["info"]
    return fields, plans


def _plan_ptm(layer: SceneLayer, path: Path, plane_format: PlaneFormat) -> LayerPlan:
    images = [load_color_map(layer.maps[m]) for m in _PTM_MAPS]
    if len({im.shape for im in images}) != 1:
        raise LanternaInputError(path, f"layer {layer.id}: the coefficient maps differ in size")
    s = list(layer.scale)
    b = [v / 255.0 for v in layer.bias]
    check_quantisation(path, s, b, f"layer {layer.id}: LRGB_PTM")
    lossy = [is_lossy_file(layer.maps[m]) for m in _PTM_MAPS]
    planes = PlaneLayer("ptm", [
        PlaneGroup(["L0", "L1", "L2"], np.ascontiguousarray(images[0]), s[0:3], b[0:3], lossy[0]),
        PlaneGroup(["L3", "L4", "L5"], np.ascontiguousarray(images[1]), s[3:6], b[3:6], lossy[1]),
        PlaneGroup(["R", "G", "B"], np.ascontiguousarray(images[2]), [1.0] * 3, [0.0] * 3,
                   lossy[2]),
    ], colorspace="lrgb")
    lid, label = layer.id, layer.label
    return LayerPlan(lid, label, planes.width, planes.height, layer.maps["coeff_0_1_2"].name,
                     lambda ds: add_planes_layer(ds, planes, layer_id=lid, label=label,
                                                 plane_format=plane_format))
