"""Each published patch of a layer as one W3C Web Annotation, in the layer's AnnotationPage.

docs/annotations.md, "Individual annotations (W3C)". From the layer's ``overlay.patches`` records
(the patches the published pyramid was built from, in application order):

- :func:`annotation_page` — the page ``{ds}/annotations/LAYER.json`` (``@context`` the W3C
  annotation context then the Presentation 3 one, ``label`` "Notes: {layer label}"), one
  ``Annotation`` per patch;
- :func:`patch_annotation` — one patch's Annotation, written alone as
  ``{ds}/annotations/LAYER/{id}.json`` (its ``id``), so each is addressable;
- :func:`page_reference` — the page as the canvas lists it (``annotations``, by reference);
- :func:`annotation_documents` — all of them by file, each page checked against the official
  Presentation 3 schema's AnnotationPage (as the manifest is, before anything is written).

An Annotation's ``motivation`` is ``["highlighting", M]`` (M the record's ``commenting`` or
``tagging``); its target the canvas through an ``xywh`` media-fragment ``FragmentSelector``;
its ``body`` the patch ``Image`` (with a ``LanternaPatch`` service: layer, level, order,
rectangle, render state), then a ``TextualBody`` of the short text (``text/plain``, purpose M)
and one of the long text (``text/html``, purpose ``describing``), each only when not empty;
``creator`` a ``Person`` when there is an author. Records of overlays built before the patch
store (no ``id``, ``width``, ``height``: the patch image was not published) are skipped.
Plain dicts, no I/O.
"""

from __future__ import annotations

from typing import Any
from urllib.parse import quote

from lanterna.errors import LanternaInputError

from .overlays import MEDIA_FRAGMENTS
from .services import PRESENTATION_CONTEXT
from .validate import validate_annotation_page

PATCH_TYPE = "LanternaPatch"
PATCH_PROFILE = "urn:lanterna:patch:1"
W3C_CONTEXT = "http://www.w3.org/ns/anno.jsonld"
#: W3C first, Presentation 3 last (the IIIF rule for several contexts).
CONTEXT = [W3C_CONTEXT, PRESENTATION_CONTEXT]
#: The texts' motivations a record may have; the drawing itself is ``highlighting``.
TEXT_MOTIVATIONS = ("commenting", "tagging")
#: The keys of a record copied into its ``LanternaPatch`` service block.
_SERVICE_KEYS = ("layer", "level", "order", "x", "y", "w", "h", "state")


def dataset_url(desc: dict[str, Any]) -> str:
    """The URL of the dataset ``desc`` describes (``{baseUrl}/{name}``)."""
    return f"{str(desc['baseUrl']).rstrip('/')}/{desc['name']}"


def page_url(desc: dict[str, Any], layer_id: str) -> str:
    """The URL of a layer's AnnotationPage, ``{ds}/annotations/LAYER.json``."""
    return f"{dataset_url(desc)}/annotations/{quote(layer_id)}.json"


def patch_url(desc: dict[str, Any], layer_id: str, patch_id: str, suffix: str) -> str:
    """The URL of a published patch file, ``{ds}/annotations/LAYER/{id}{suffix}``."""
    return f"{dataset_url(desc)}/annotations/{quote(layer_id)}/{quote(patch_id)}{suffix}"


def published_patches(layer: dict[str, Any]) -> list[dict[str, Any]]:
    """A layer's patch records that have a published image, in application order."""
    overlay = layer.get("overlay")
    patches = overlay.get("patches", []) if isinstance(overlay, dict) else []
    return [p for p in patches if isinstance(p, dict) and isinstance(p.get("id"), str)
            and all(isinstance(p.get(k), int) for k in ("width", "height"))]


def patch_annotation(desc: dict[str, Any], layer_id: str, record: dict[str, Any], *,
                     standalone: bool = False) -> dict[str, Any]:
    """One patch record as an Annotation; ``standalone`` adds the ``@context`` (own file)."""
    pid = str(record["id"])
    anno_id = patch_url(desc, layer_id, pid, ".json")
    motivation = record.get("motivation")
    motivation = motivation if motivation in TEXT_MOTIVATIONS else "commenting"
    service = {"id": f"{anno_id}#lanterna", "type": PATCH_TYPE, "profile": PATCH_PROFILE,
               **{k: record.get(k) for k in _SERVICE_KEYS}}
    service["layer"] = layer_id
    body: list[dict[str, Any]] = [{
        "id": patch_url(desc, layer_id, pid, ".png"), "type": "Image", "format": "image/png",
        "width": record["width"], "height": record["height"], "service": [service]}]
    short, long = str(record.get("short") or ""), str(record.get("long") or "")
    if short:
        body.append({"id": f"{anno_id}#short", "type": "TextualBody", "value": short,
                     "format": "text/plain", "purpose": motivation})
    if long:
        body.append({"id": f"{anno_id}#long", "type": "TextualBody", "value": long,
                     "format": "text/html", "purpose": "describing"})
    anno: dict[str, Any] = {"@context": CONTEXT} if standalone else {}
    anno.update({
        "id": anno_id,
        "type": "Annotation",
        "motivation": ["highlighting", motivation],
        "body": body,
        "target": {
            "type": "SpecificResource",
            "source": {"id": f"{dataset_url(desc)}/canvas/1", "type": "Canvas"},
            "selector": {"type": "FragmentSelector", "conformsTo": MEDIA_FRAGMENTS,
                         "value": f"xywh={record['x']},{record['y']},{record['w']},"
                                  f"{record['h']}"},
        },
    })
    if record.get("author"):
        anno["creator"] = {"type": "Person", "name": str(record["author"])}
    for key in ("created", "modified"):
        if record.get(key):
            anno[key] = str(record[key])
    return anno


def annotation_page(desc: dict[str, Any], layer: dict[str, Any]) -> dict[str, Any] | None:
    """The AnnotationPage of ``layer``'s published patches, or None when it has none."""
    patches = published_patches(layer)
    if not patches:
        return None
    return {"@context": CONTEXT, **page_reference(desc, layer),
            "items": [patch_annotation(desc, layer["id"], p) for p in patches]}


def page_reference(desc: dict[str, Any], layer: dict[str, Any]) -> dict[str, Any]:
    """The canvas's reference to ``layer``'s AnnotationPage: ``{id, type, label}``."""
    return {"id": page_url(desc, layer["id"]), "type": "AnnotationPage",
            "label": {"en": [f"Notes: {layer['label']}"]}}


def page_references(desc: dict[str, Any]) -> list[dict[str, Any]]:
    """The references of every layer of ``desc`` that has published patches, in layer order."""
    return [page_reference(desc, layer) for layer in desc["layers"] if published_patches(layer)]


def annotation_documents(desc: dict[str, Any]) -> dict[str, dict[str, Any]]:
    """Every W3C document of ``desc`` by its path in the dataset.

    ``annotations/LAYER.json`` (the page) and ``annotations/LAYER/{id}.json`` (each Annotation)
    for every layer with published patches. A page the Presentation 3 schema refuses is a
    one-line error (nothing is written then).
    """
    docs: dict[str, dict[str, Any]] = {}
    for layer in desc["layers"]:
        page = annotation_page(desc, layer)
        if page is None:
            continue
        errors = validate_annotation_page(page)
        if errors:
            raise LanternaInputError(None, f"the annotation page of layer {layer['id']} would "
                                     f"not be valid IIIF Presentation 3.0: {errors[0]}")
        docs[f"annotations/{layer['id']}.json"] = page
        for record in published_patches(layer):
            docs[f"annotations/{layer['id']}/{record['id']}.json"] = patch_annotation(
                desc, layer["id"], record, standalone=True)
    return docs
