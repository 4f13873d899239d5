"""The IIIF identifiers Lanterna writes and serves: JSON-LD contexts, protocol and profiles."""

from __future__ import annotations

#: JSON-LD context of an Image API 3 ``info.json`` (also its ``application/ld+json`` profile).
IMAGE_CONTEXT = "http://iiif.io/api/image/3/context.json"
#: The ``protocol`` of an Image API 3 service.
IMAGE_PROTOCOL = "http://iiif.io/api/image"
#: JSON-LD context of a Presentation API 3 manifest.
PRESENTATION_CONTEXT = "http://iiif.io/api/presentation/3/context.json"


def image_profile_uri(level: str) -> str:
    """The URI of an Image API 3 compliance level (``level0``, ``level1``, ``level2``)."""
    return f"http://iiif.io/api/image/3/{level}.json"
