"""The ``ImageService3`` references of a manifest, with the image's description embedded.

A viewer needs an image's size, tiles and sizes before it can ask for any tile; a bare
``{id, type, profile}`` reference makes it fetch ``info.json`` first, one round trip per image.
So every image service the manifest names (each layer's painting image, each plane group of a
relight block, each overlay level) carries the description keys of its ``info.json``
(:data:`DESCRIPTION_KEYS`), the way the IIIF Presentation API lets a service embed its
description. Viewers that ignore them lose nothing; ``@context`` and ``protocol`` stay in
``info.json`` (the manifest's own context covers the embedded object).
"""

from __future__ import annotations

import copy
from typing import Any

#: The media type of each tile format a dataset's images are stored in (``images[id].format``).
MEDIA_TYPES = {"jpg": "image/jpeg", "png": "image/png", "webp": "image/webp"}
#: The IIIF Presentation 3 JSON-LD context.
PRESENTATION_CONTEXT = "http://iiif.io/api/presentation/3/context.json"

#: The keys of an ``info.json`` a manifest's image service embeds (when the info.json has them).
DESCRIPTION_KEYS = ("profile", "width", "height", "maxWidth", "maxHeight", "sizes", "tiles",
                    "preferredFormats", "extraFormats")


def image_service(service_id: str, info: dict[str, Any] | None) -> dict[str, Any]:
    """Return the ``ImageService3`` reference of ``service_id``, with ``info``'s description.

    Parameters
    ----------
    service_id
        The service's ``id`` (the image's IIIF base URL).
    info
        The image's ``info.json``, or None when it is unknown (a bare reference then).
    """
    service: dict[str, Any] = {"id": service_id, "type": "ImageService3", "profile": "level0"}
    for key in DESCRIPTION_KEYS:
        if info is not None and key in info:
            service[key] = copy.deepcopy(info[key])
    return service


def image_id_of(service_id: str, ds_url: str) -> str | None:
    """The dataset image a service id names (``{ds_url}/iiif/{image}``), or None."""
    prefix = f"{ds_url}/iiif/"
    rest = service_id.removeprefix(prefix) if service_id.startswith(prefix) else ""
    return rest if rest and "/" not in rest else None


def with_plane_descriptions(block: dict[str, Any], ds_url: str,
                            infos: dict[str, dict[str, Any]]) -> dict[str, Any]:
    """Return a relight service block whose plane services embed their images' descriptions.

    Plane services that name no image of ``infos`` are left as they are.
    """
    out = dict(block)
    planes = []
    for plane in block.get("planes", []):
        service = plane.get("service", {})
        image = image_id_of(str(service.get("id", "")), ds_url)
        if image is not None and image in infos:
            plane = {**plane, "service": image_service(service["id"], infos[image])}
        planes.append(plane)
    out["planes"] = planes
    return out
