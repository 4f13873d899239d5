"""The overlay part of a manifest: one AnnotationPage of ``commenting`` annotations per layer.

Encoding (docs/annotations.md, "Storage and manifest"): per overlay level one Annotation,
motivated ``commenting`` (a motivation stock viewers such as Mirador list by default), whose
target is the canvas region the level's drawing covers (the level record's ``box``, in canvas
pixels, through an ``xywh`` ``FragmentSelector``; the whole canvas for a record without one or
with an empty drawing) and whose body is the level ``Image`` (with its ``ImageService3`` and a
``LanternaOverlayLevel`` service that carries the level and its texts), then a ``TextualBody``
of the short text (``text/plain``, purpose ``commenting``) and one of the long text
(``text/html``, purpose ``describing``), each when not empty; the label is the short text.
Built as plain dicts because iiif-prezi3 drops the keys it does not model on Annotation and
AnnotationBody.
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
    if short:
        body.append({"id": f"{anno_id}/short", "type": "TextualBody", "value": short,
                     "format": "text/plain", "purpose": "commenting"})
    if long:
        body.append({"id": f"{anno_id}/long", "type": "TextualBody", "value": long,
                     "format": "text/html", "purpose": "describing"})
    x, y, w, h = drawn_region(entry, desc)
    return {
        "id": anno_id,
        "type": "Annotation",
        "motivation": "commenting",
        "label": {"en": [short or f"Level {level}"]},
        "body": body,
        "target": {
            "type": "SpecificResource",
            "source": {"id": canvas_id, "type": "Canvas"},
            "selector": {"type": "FragmentSelector", "conformsTo": MEDIA_FRAGMENTS,
                         "value": f"xywh={x},{y},{w},{h}"},
        },
    }


def drawn_region(entry: dict[str, Any], desc: dict[str, Any]) -> tuple[int, int, int, int]:
    """The ``(x, y, w, h)`` canvas region a level record's drawing covers.

    Its ``box`` when that is four integers of a non-empty rectangle inside the canvas, else the
    whole canvas (records written before the box was kept, and empty drawings).
    """
    width, height = int(desc["width"]), int(desc["height"])
    box = entry.get("box")
    if (isinstance(box, list) and len(box) == 4
            and all(isinstance(v, int) and not isinstance(v, bool) for v in box)):
        x, y, w, h = box
        if w > 0 and h > 0 and x >= 0 and y >= 0 and x + w <= width and y + h <= height:
            return x, y, w, h
    return 0, 0, width, height
