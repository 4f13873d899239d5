"""Build a dataset's IIIF Presentation 3 manifest (iiif-prezi3) from its ``lanterna.json``.

One Canvas; one painting annotation whose body is a ``Choice`` of the layers (the first item is
the default visible layer). Each item is an ``Image`` (a concrete ``full/max`` URL of the layer's
colour image) with two services: the ``ImageService3`` of that image and the layer's
``LanternaRelight`` block, so any IIIF viewer shows the colour image and Lanterna relights it.
Every image service embeds its image's description (size, tiles, sizes), so a viewer needs no
``info.json`` before the first tile (:mod:`lanterna.manifests.services`).
Layers with an overlay add ``canvas.annotations`` (:mod:`lanterna.manifests.overlays`), and
layers with published patches a reference to their page of W3C annotations after them
(:mod:`lanterna.manifests.annotation_page`); the
preset library is a service on the Manifest and the pixel size a physdim service on the Canvas
(:mod:`lanterna.manifests.extensions`); the thumbnail, metadata, rights, attribution, provider and
links come from the description's ``publication`` (:mod:`lanterna.manifests.metadata`).

Every manifest built here is checked against the official IIIF Presentation 3.0 JSON Schema
(:mod:`lanterna.manifests.validate`, a few milliseconds) before it is written, so an import never
publishes an invalid manifest (a non-http ``--base-url`` is the usual culprit).
"""

from __future__ import annotations

import json
from typing import Any

from iiif_prezi3 import (
    Annotation,
    AnnotationBody,
    AnnotationPage,
    Choice,
    Manifest,
    ServiceV3,
    config,
)

from lanterna.errors import LanternaInputError

from .annotation_page import page_references
from .extensions import physdim_service, presets_service
from .lightingmap import add_lighting_maps
from .metadata import publication_properties
from .overlays import overlay_pages
from .services import MEDIA_TYPES, image_service, with_plane_descriptions
from .validate import validate_manifest

config.configs["helpers.auto_fields.AutoLang"].auto_lang = "en"

def build_manifest(desc: dict[str, Any],
                   infos: dict[str, dict[str, Any]] | None = None) -> dict[str, Any]:
    """Return the manifest of dataset description ``desc`` as a JSON-ready dict.

    ``infos`` maps image ids to their ``info.json``: every image service of an image found there
    embeds its description (:mod:`lanterna.manifests.services`); the others are bare references.
    """
    infos = infos or {}
    ds_url = f"{desc['baseUrl'].rstrip('/')}/{desc['name']}"
    width, height = desc["width"], desc["height"]
    manifest = Manifest(id=f"{ds_url}/manifest.json", label=desc["label"])
    if desc.get("summary"):
        manifest.summary = {"en": [desc["summary"]]}
    canvas = manifest.make_canvas(id=f"{ds_url}/canvas/1", width=width, height=height,
                                  label=desc["label"])
    bodies = []
    for layer in desc["layers"]:
        image_id = layer["body"]
        image = desc["images"][image_id]
        service_url = f"{ds_url}/iiif/{image_id}"
        body = AnnotationBody(
            id=f"{service_url}/full/max/0/default.jpg",
            type="Image",
            format=MEDIA_TYPES["jpg"],
            width=image.get("maxWidth", image["width"]),  # full/max of a large image is a
            height=image.get("maxHeight", image["height"]),  # reduced level (docs/dataset-format)
            label=layer["label"],
        )
        body.add_service(ServiceV3(**image_service(service_url, infos.get(image_id))))
        body.add_service(ServiceV3(**with_plane_descriptions(layer["service"], ds_url, infos)))
        bodies.append(body)
    page = AnnotationPage(id=f"{ds_url}/canvas/1/page/1")
    page.add_item(Annotation(id=f"{ds_url}/canvas/1/page/1/annotation/1", motivation="painting",
                             body=Choice(items=bodies), target=canvas.id))
    canvas.add_item(page)
    doc: dict[str, Any] = json.loads(manifest.json(indent=2))
    add_lighting_maps(doc, desc, infos)  # ARCHiOx's albedo + normal items (lightingmap.py)
    pages = [*overlay_pages(desc, infos), *page_references(desc)]
    if pages:
        doc["items"][0]["annotations"] = pages
    doc = _with_properties(doc, publication_properties(desc, infos, ds_url))
    presets, physdim = presets_service(desc, ds_url), physdim_service(desc, ds_url)
    if presets is not None:
        doc["service"] = [presets]
    if physdim is not None:
        doc["items"][0]["service"] = [physdim]
    errors = validate_manifest(doc)
    if errors:
        more = f" (and {len(errors) - 1} more)" if len(errors) > 1 else ""
        raise LanternaInputError(None, "the manifest would not be valid IIIF Presentation 3.0: "
                                 f"{errors[0]}{more}")
    return doc


def _with_properties(doc: dict[str, Any], properties: dict[str, Any]) -> dict[str, Any]:
    """``doc`` with ``properties`` inserted before its ``items`` (the spec's reading order)."""
    out: dict[str, Any] = {}
    for key, value in doc.items():
        if key == "items":
            out.update(properties)
        out[key] = value
    return out
