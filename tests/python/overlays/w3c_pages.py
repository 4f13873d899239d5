"""W3C annotation pages as other tools write them, for the import tests.

``annotorious_page`` follows Annotorious 3's W3C output (``W3CImageFormat``: the annotation's
``@context`` and ``id`` ``#uuid``, ``TextualBody`` bodies with ``purpose`` commenting or tagging
and their own creator, ``target.source`` the image URL, a ``FragmentSelector``
``xywh=pixel:X,Y,W,H`` for rectangles and an ``SvgSelector``
``<svg><polygon points="x,y x,y …" /></svg>`` for polygons, ``creator`` ``{id, name}``), gathered
in an AnnotationPage. ``mirador_annotation`` is the shape mirador-annotations (paper.js) writes:
both a FragmentSelector and an SvgSelector, a styled, namespaced path with curves.
"""

from __future__ import annotations

from typing import Any

IMAGE = "https://example.org/iiif/tablet/full/max/0/default.jpg"
#: The polygons (canvas pixels): a five-sided sherd and a notched outline of ten vertices.
SHERD = [(40.5, 30.25), (150, 22), (181.75, 95), (120, 140.5), (52, 118)]
NOTCH = [(210, 40), (260, 35), (300, 60), (305, 110), (280, 150), (262, 120), (240, 152),
         (212, 140), (200, 100), (222, 80)]


def polygon_value(points: list[tuple[float, float]]) -> str:
    return f'<svg><polygon points="{" ".join(f"{x:g},{y:g}" for x, y in points)}" /></svg>'


def annotorious_page() -> dict[str, Any]:
    """Three annotations: two polygons (comment + tags; tags only) and a rectangle."""
    user = {"id": "ayfnqskl", "name": "Ada Conservator"}
    return {
        "@context": "http://www.w3.org/ns/anno.jsonld",
        "id": "https://example.org/annotations/tablet/page1",
        "type": "AnnotationPage",
        "items": [
            {"@context": "http://www.w3.org/ns/anno.jsonld",
             "id": "#a88b22d0-6106-4872-9435-c78b5e89fede", "type": "Annotation",
             "body": [{"type": "TextualBody", "purpose": "commenting",
                       "value": "Flaking paint along the rim", "creator": user,
                       "created": "2026-11-30T09:12:45.123Z"},
                      {"type": "TextualBody", "purpose": "tagging", "value": "flaking",
                       "creator": user, "created": "2026-11-30T09:12:45.123Z"}],
             "target": {"source": IMAGE,
                        "selector": {"type": "SvgSelector", "value": polygon_value(SHERD)}},
             "creator": user, "created": "2026-11-30T09:12:40.001Z"},
            {"@context": "http://www.w3.org/ns/anno.jsonld",
             "id": "#218d01ff-f077-4cc3-992d-1c81c426e51b", "type": "Annotation",
             "body": [{"type": "TextualBody", "purpose": "tagging", "value": "gilding"}],
             "target": {"source": IMAGE,
                        "selector": {"type": "SvgSelector", "value": polygon_value(NOTCH)}}},
            {"@context": "http://www.w3.org/ns/anno.jsonld",
             "id": "#9a4c10df-3c07-40c3-9108-672d1194bbf8", "type": "Annotation",
             "body": [{"type": "TextualBody", "value": "Restored in 1962"}],
             "target": {"source": IMAGE,
                        "selector": {"type": "FragmentSelector",
                                     "conformsTo": "http://www.w3.org/TR/media-frags/",
                                     "value": "xywh=pixel:20,160,90,30"}},
             "creator": {"id": "https://example.org/users/7"}},
        ],
    }


def mirador_annotation(canvas: str) -> dict[str, Any]:
    """An annotation as mirador-annotations writes it: fragment and SVG, styled curves."""
    svg = ("<svg xmlns='http://www.w3.org/2000/svg'><path xmlns='http://www.w3.org/2000/svg' "
           "d='M100,100c0,-40 80,-40 80,0c0,40 -80,40 -80,0z' data-paper-data='{}' "
           "fill-opacity='0' fill='#00BFFF' fill-rule='nonzero' stroke='#ff0000' "
           "stroke-width='2'/></svg>")
    return {"id": "https://example.org/anno/42", "type": "Annotation",
            "motivation": "commenting",
            "body": {"type": "TextualBody", "value": "<p>Under <b>UV</b>: retouching</p>",
                     "format": "text/html"},
            "target": {"source": canvas, "selector": [
                {"type": "FragmentSelector", "value": "xywh=100,70,80,60"},
                {"type": "SvgSelector", "value": svg}]}}
