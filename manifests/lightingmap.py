"""ARCHiOx's lighting maps: the albedo and normal map of a shape + material layer, as ARCHiOx-style
viewers (the Bodleian/Factum ARCHiOx Mirador plugin, the Strata viewer) look for them.

Their convention (the LightingMap extension, unregistered): among the painting ``Choice`` items
of a canvas, an ``Image`` whose ``service`` list holds its ``ImageService3`` **and**
``{"id", "type": "LightingMapExtension", "profile": LIGHTINGMAP_PROFILE, "mapType": "albedo" |
"normal"}`` is that map; the viewer finds the service by its profile and tiles the map from the
``ImageService3`` beside it. The manifest's ``@context`` lists the extension's context before
the Presentation 3 one (the IIIF rule: Presentation 3 last).

:func:`add_lighting_maps` appends one such pair of items to the ``Choice`` of a built manifest,
for the first ``svbrdf`` layer with both a normal map and a kd map: our stored plane images are
directly usable (8-bit RGB level-0 pyramids; normals encoded ``round((n + 1)/2·255)`` in the
OpenGL convention, x right, y up, z toward the viewer, as three.js normal maps are). The kd
image holds the layer's ``inputColorSpace`` values as stored. ARCHiOx relights one pair per
canvas, hence one pair. The items carry no ``LanternaRelight`` service, so Lanterna's own
parser skips them (plugin/src/iiif/manifest.ts keeps only images with one).
docs/dataset-format.md, "Lighting maps (ARCHiOx)".
"""

from __future__ import annotations

from typing import Any

from .services import MEDIA_TYPES, PRESENTATION_CONTEXT, image_id_of, image_service

LIGHTINGMAP_PROFILE = "http://iiif.io/api/extension/lightingmap"
#: The profile ARCHiOx's viewer looks for first (a later name of the same extension).
LIGHTINGMAP_ANNEX_PROFILE = "http://iiif.io/api/annex/services/lightingmap"
LIGHTINGMAP_CONTEXT = "https://iiif.bodleian.ox.ac.uk/contexts/lightingmap/context.json"
LIGHTINGMAP_TYPE = "LightingMapExtension"

#: mapType → (the svbrdf plane group holding it, its first channel, the label's suffix).
MAPS: dict[str, tuple[str, str, str]] = {
    "albedo": ("kd", "KD_R", "albedo"),
    "normal": ("normals", "NX", "normal map"),
}


def lighting_map_images(layer: dict[str, Any], ds_url: str) -> dict[str, str] | None:
    """The dataset image of each map type of an ``svbrdf`` layer, or None without both maps."""
    if layer["service"].get("layerType") != "svbrdf":
        return None
    found: dict[str, str] = {}
    for map_type, (_, channel, _) in MAPS.items():
        for plane in layer["service"].get("planes", []):
            image = image_id_of(str(plane.get("service", {}).get("id", "")), ds_url)
            if plane.get("channels", [None])[0] == channel and image is not None:
                found[map_type] = image
    return found if len(found) == len(MAPS) else None


def lighting_map_items(desc: dict[str, Any], ds_url: str,
                       infos: dict[str, dict[str, Any]]) -> list[dict[str, Any]]:
    """The albedo and normal ``Choice`` items of the first svbrdf layer with both, or ``[]``."""
    for layer in desc["layers"]:
        images = lighting_map_images(layer, ds_url)
        if images is None:
            continue
        items = []
        for map_type, image_id in images.items():
            image = desc["images"][image_id]
            service_url = f"{ds_url}/iiif/{image_id}"
            fmt = image["format"]
            items.append({
                "id": f"{service_url}/full/max/0/default.{fmt}",
                "type": "Image",
                "format": MEDIA_TYPES[fmt],
                "label": {"en": [f"{layer['label']} [{MAPS[map_type][2]}]"]},
                "width": image.get("maxWidth", image["width"]),
                "height": image.get("maxHeight", image["height"]),
                "service": [
                    image_service(service_url, infos.get(image_id)),
                    {"id": f"{ds_url}/lightingmap/{image_id}.json", "type": LIGHTINGMAP_TYPE,
                     "profile": LIGHTINGMAP_PROFILE, "mapType": map_type},
                ],
            })
        return items
    return []


def add_lighting_maps(doc: dict[str, Any], desc: dict[str, Any],
                      infos: dict[str, dict[str, Any]]) -> None:
    """Append the lighting-map items to the manifest ``doc``'s painting ``Choice`` (in place) and
    list the extension's context, when the dataset ``desc`` has a layer with both maps."""
    ds_url = f"{desc['baseUrl'].rstrip('/')}/{desc['name']}"
    items = lighting_map_items(desc, ds_url, infos)
    if not items:
        return
    body = doc["items"][0]["items"][0]["items"][0]["body"]
    body["items"].extend(items)
    doc["@context"] = [LIGHTINGMAP_CONTEXT, PRESENTATION_CONTEXT]  # keeps its first place
