"""The overlay part of a manifest: one ``supplementing`` AnnotationPage per annotated layer.

Encoding (docs/annotations.md, "Storage and manifest"): per overlay level one Annotation whose
body is the level ``Image`` (with its ``ImageService3`` and a ``LanternaOverlayLevel`` service that
carries the level and its texts) and a ``TextualBody`` with the long text; the label is the short
text and the target the whole canvas through a ``FragmentSelector``. Built as plain dicts because
iiif-prezi3 drops the keys it does not model on Annotation and AnnotationBody.
"""

from __future__ import annotations

from typing import Any

from .services import image_service

OVERLAY_TYPE = "LanternaOverlayLevel"
OVERLAY_PROFILE = "urn:lanterna:overlay:1"
MEDIA_FRAGMENTS = "http://www.w3.org/TR/media-frags/"


def overlay_pages(desc: dict[str, Any],
                  infos: dict[str, dict[str, Any]] | None = None) -> list[dict[str, Any]]:
    """Return the AnnotationPages of every layer of ``desc`` that has overlay level images.

    ``infos`` (image id → info.json) gives the level images' embedded descriptions.
    """
    ds_url = f"{desc['baseUrl'].rstrip('/')}/{desc['name']}"
    canvas_id = f"{ds_url}/canvas/1"
    pages = []
    for layer in desc["layers"]:
        levels = _levels(layer)
        if not levels:
            continue
        page_id = f"{canvas_id}/overlays/{layer['id']}"
        pages.append({
            "id": page_id,
            "type": "AnnotationPage",
            "label": {"en": [f"Annotations: {layer['label']}"]},
            "items": [_annotation(ds_url, canvas_id, page_id, layer["id"], level, desc,
                                  (infos or {}).get(level["image"])) for level in levels],
        })
    return pages


def _levels(layer: dict[str, Any]) -> list[dict[str, Any]]:
    overlay = layer.get("overlay")
    if not isinstance(overlay, dict):
        return []
    levels = [e for e in overlay.get("levels", []) if isinstance(e, dict) and e.get("image")]
    return sorted(levels, key=lambda e: int(e["level"]))


def _annotation(ds_url: str, canvas_id: str, page_id: str, layer_id: str, entry: dict[str, Any],
                desc: dict[str, Any], info: dict[str, Any] | None) -> dict[str, Any]:
    level = int(entry["level"])
    short, long = str(entry.get("short", "")), str(entry.get("long", ""))
    service_id = f"{ds_url}/iiif/{entry['image']}"
    anno_id = f"{page_id}/level/{level}"
    body: list[dict[str, Any]] = [{
        "id": f"{service_id}/full/max/0/default.png",
        "type": "Image",
        "format": "image/png",
        "width": entry["width"],
        "height": entry["height"],
        "service": [
            image_service(service_id, info),
            {"id": f"{ds_url}/layers/{layer_id}.json#overlay-{level}", "type": OVERLAY_TYPE,
             "profile": OVERLAY_PROFILE, "layer": layer_id, "level": level, "short": short,
             "long": long},
        ],
    }]
    if long:
        body.append({"id": f"{anno_id}/long", "type": "TextualBody", "value": long,
                     "format": "text/html", "purpose": "describing"})
    return {
        "id": anno_id,
        "type": "Annotation",
        "motivation": "supplementing",
        "label": {"en": [short or f"Level {level}"]},
        "body": body,
        "target": {
            "type": "SpecificResource",
            "source": {"id": canvas_id, "type": "Canvas"},
            "selector": {"type": "FragmentSelector", "conformsTo": MEDIA_FRAGMENTS,
                         "value": f"xywh=0,0,{desc['width']},{desc['height']}"},
        },
    }
