"""Import lighting maps as one shape + material layer: an ARCHiOx-style IIIF manifest (a local
``.json`` file or an http(s) URL), or a local albedo + normal map pair.

The manifest convention (docs/importing.md, "ARCHiOx manifests and albedo + normal pairs";
:mod:`lanterna.manifests.lightingmap` writes it): painting bodies (``Image``\\ s, or the items of a
``Choice``) whose ``service`` list holds a ``LightingMapExtension`` service (profile
``http://iiif.io/api/extension/lightingmap``, or the annex's ``…/annex/services/lightingmap``)
with ``mapType`` ``albedo`` or ``normal``, beside the ``ImageService3`` (or ``ImageService2``)
serving the map. The first canvas with a normal map is used. Both maps' ``info.json`` are
checked (size, pixel limit) before either image is downloaded; then ``full/max`` of each is
fetched and decoded with the map loaders of :mod:`lanterna.tiler.inputs.maps`, and the layer is a
Lambert one: the normal map (OpenGL convention, RGB = (n + 1)/2·255) and the albedo as kd, in
sRGB. Every problem is one line naming the manifest and the JSON path; nothing is written.
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import numpy.typing as npt

from lanterna.errors import LanternaInputError
from lanterna.tiler.dataset.layers import add_svbrdf_layer
from lanterna.tiler.dataset.plan import LayerPlan
from lanterna.tiler.dataset.plane_format import AUTO, PlaneFormat
from lanterna.tiler.dataset.writer import DatasetWriter, check_identifier
from lanterna.tiler.documents import (
    MAX_DOCUMENT_BYTES,
    check_document,
    document_type,
    json_path,
    load_json,
    parse_json,
)
from lanterna.tiler.inputs.iiif_image import ImageInfo, fetch_full, read_info
from lanterna.tiler.inputs.maps import load_color_map, load_normal_map
from lanterna.tiler.inputs.remote import fetch, is_url

from .sources import layer_id_from, plan_svbrdf

PROFILES = ("http://iiif.io/api/annex/services/lightingmap",
            "http://iiif.io/api/extension/lightingmap")
#: mapType → the svbrdf map it becomes.
MAP_TYPES = {"normal": "normals", "albedo": "kd"}
_ACCEPT = ('application/ld+json;profile="http://iiif.io/api/presentation/3/context.json", '
           "application/json;q=0.9")
_IMAGE_SERVICES = (("type", "id", "ImageService3"), ("@type", "@id", "ImageService2"))


@dataclass(frozen=True)
class MapRef:
    """One lighting map found in a manifest: its JSON path, image service URL and label."""

    path: str
    service: str
    label: str


def is_manifest_source(source: str | Path) -> bool:
    """True for an http(s) URL, or a ``.json`` regular file holding a IIIF ``Manifest``."""
    if is_url(source):
        return True
    path = Path(source)  # a bad manifest is for the description reader to report
    return path.suffix.lower() == ".json" and document_type(path) == "Manifest"


def read_manifest(source: str | Path) -> dict[str, Any]:
    """The manifest at ``source`` (URL or file), checked against its schema."""
    if is_url(source):
        raw = fetch(str(source), "a IIIF manifest", max_bytes=MAX_DOCUMENT_BYTES, accept=_ACCEPT)
        doc = parse_json(raw, str(source))
    else:
        doc = load_json(Path(source))
    return check_document(doc, "lightingmap-manifest", str(source))


def _listed(value: Any) -> list[Any]:
    return value if isinstance(value, list) else [] if value is None else [value]


def _bodies(canvas: dict[str, Any], k: int) -> Iterator[tuple[str, Any]]:
    """(JSON path, body) of every painting body of canvas ``k``, Choice items included."""
    for p, page in enumerate(canvas.get("items", [])):
        for a, anno in enumerate(page.get("items", [])):
            where: list[str | int] = ["items", k, "items", p, "items", a, "body"]
            raw = anno.get("body")
            for b, body in enumerate(_listed(raw)):
                at: list[str | int] = [*where, b] if isinstance(raw, list) else where
                if body.get("type") == "Choice":
                    for i, item in enumerate(body.get("items", [])):
                        yield json_path([*at, "items", i]), item
                else:
                    yield json_path(at), body


def text_of(label: Any) -> str:
    """The first text of a language map, or ``""``."""
    if isinstance(label, dict):
        for texts in label.values():
            if texts:
                return str(texts[0])
    return ""


def find_maps(doc: dict[str, Any], source: str | Path) -> dict[str, MapRef]:
    """The albedo and normal map of the first canvas with a normal map, by mapType."""
    seen: list[str] = []
    for k, canvas in enumerate(doc["items"]):
        found: dict[str, MapRef] = {}
        for where, body in _bodies(canvas, k):
            services = _listed(body.get("service"))
            marks = [s for s in services if s.get("profile") in PROFILES]
            if not marks:
                continue
            map_type = marks[0].get("mapType")
            seen.append(str(map_type))
            if map_type not in MAP_TYPES or map_type in found:
                continue
            service = _image_service(services)
            if service is None:
                raise LanternaInputError(source, f"{where}.service: the {map_type} map has no "
                                         "ImageService3 (or ImageService2) service with an id")
            found[map_type] = MapRef(where, service, text_of(body.get("label")))
        if "normal" in found:
            if "albedo" not in found:
                raise LanternaInputError(source, f"items[{k}]: a normal map but no albedo map "
                                         "(a LightingMapExtension service with mapType albedo)")
            return found
    got = f" (found mapType {', '.join(sorted(set(seen)))})" if seen else ""
    raise LanternaInputError(source, "no normal map: no painting Image with a "
                             f"LightingMapExtension service of mapType normal{got}")


def _image_service(services: list[Any]) -> str | None:
    for type_key, id_key, kind in _IMAGE_SERVICES:
        for service in services:
            if service.get(type_key) == kind and isinstance(service.get(id_key), str):
                return str(service[id_key])
    return None


def plan_archiox(source: str | Path, *, layer_id: str | None = None,
                 plane_format: PlaneFormat = AUTO) -> tuple[dict[str, str], LayerPlan]:
    """Plan the lighting maps of the manifest ``source`` as one shape + material layer.

    Returns the dataset fields the manifest gives (``label``, ``summary``) and the plan.
    """
    doc = read_manifest(source)
    refs = find_maps(doc, source)
    infos: dict[str, ImageInfo] = {
        t: read_info(ref.service, f"{source}: {ref.path}") for t, ref in refs.items()}
    normal, albedo = infos["normal"], infos["albedo"]
    if (albedo.width, albedo.height) != (normal.width, normal.height):
        raise LanternaInputError(source, f"{refs['albedo'].path}: the albedo map is "
                                 f"{albedo.width}x{albedo.height}, the normal map "
                                 f"({refs['normal'].path}) {normal.width}x{normal.height}")
    data: dict[str, npt.NDArray[np.uint8]] = {}
    lossy = set()
    for map_type, info in infos.items():
        where = f"{source}: {refs[map_type].path}"
        full = fetch_full(info, where)
        try:
            array = (load_normal_map(full.url, data=full.data) if map_type == "normal"
                     else load_color_map(full.url, data=full.data))
        except LanternaInputError as err:
            raise LanternaInputError(where, str(err)) from None
        if array.shape[:2] != (info.height, info.width):
            raise LanternaInputError(where, f"{full.url}: the image is {array.shape[1]}x"
                                     f"{array.shape[0]}, its info.json says {info.width}x"
                                     f"{info.height}")
        data[MAP_TYPES[map_type]] = array
        if info.fmt == "jpg":
            lossy.add(MAP_TYPES[map_type])
    title = text_of(doc.get("label"))
    lid = check_identifier(layer_id or layer_id_from((title or "lighting_maps")[:64]),
                           "layer id")
    label = f"{title or lid} (albedo + normal map)"
    share = {name: f"{source}#{refs[t].path}" for t, name in MAP_TYPES.items()}

    def add(ds: DatasetWriter) -> object:
        return add_svbrdf_layer(ds, normals=data["normals"], kd=data["kd"],
                                input_colorspace="srgb", share=share, lossy=frozenset(lossy),
                                layer_id=lid, label=label, plane_format=plane_format)

    fields = {"label": title} if title else {}
    if text_of(doc.get("summary")):
        fields["summary"] = text_of(doc.get("summary"))
    return fields, LayerPlan(lid, label, normal.width, normal.height, str(source), add)


def plan_map_pair(albedo: Path, normal: Path, *, normal_convention: str = "opengl",
                  plane_format: PlaneFormat = AUTO) -> LayerPlan:
    """Plan a local albedo (sRGB) + normal map pair as one Lambert shape + material layer."""
    lid = check_identifier(layer_id_from(Path(albedo).stem), "layer id")
    return plan_svbrdf({"normals": Path(normal), "kd": Path(albedo)}, layer_id=lid,
                       label=f"{lid} (albedo + normal map)", input_colorspace="srgb",
                       normal_convention=normal_convention, plane_format=plane_format)
