"""The W3C Web Annotation Data Model's rules for what Lanterna writes, as a small JSON Schema.

Written from the model (https://www.w3.org/TR/annotation-model/) for the parts our documents use:
an Annotation has ``@context`` holding ``http://www.w3.org/ns/anno.jsonld`` (when it is a document
of its own), an IRI ``id``, ``type`` "Annotation", motivations from the model's vocabulary (§3.3.5),
a ``target``; a ``SpecificResource`` has a ``source``; a ``FragmentSelector`` of an image region
``conformsTo`` the media-fragments spec and holds an ``xywh=`` value; a ``TextualBody`` has a
string ``value``, a media-type ``format`` and a ``purpose`` from the same vocabulary; ``creator``
is an Agent (Person, Organization or Software) and ``created``/``modified`` are xsd:dateTime with a
time zone. An AnnotationPage is an ``AnnotationPage`` whose ``items`` are Annotations.
"""

from __future__ import annotations

from typing import Any

from jsonschema import Draft202012Validator

ANNO_CONTEXT = "http://www.w3.org/ns/anno.jsonld"
#: The model's motivations and purposes (§3.3.5, oa:Motivation instances).
MOTIVATIONS = ["assessing", "bookmarking", "classifying", "commenting", "describing", "editing",
               "highlighting", "identifying", "linking", "moderating", "questioning", "replying",
               "tagging"]
_IRI = {"type": "string", "pattern": r"^[a-z][a-z0-9+.-]*:[^\s]+$"}
_DATETIME = {"type": "string",
             "pattern": r"^\d{4}-\d\d-\d\dT\d\d:\d\d:\d\d(\.\d+)?(Z|[+-]\d\d:\d\d)$"}
_MOTIVATION = {"enum": MOTIVATIONS}
_CONTEXT = {"anyOf": [{"const": ANNO_CONTEXT},
                      {"type": "array", "contains": {"const": ANNO_CONTEXT}}]}

RULES: dict[str, Any] = {
    "$schema": "https://json-schema.org/draft/2020-12/schema",
    "$defs": {
        "fragment": {
            "type": "object", "required": ["type", "value", "conformsTo"],
            "properties": {
                "type": {"const": "FragmentSelector"},
                "conformsTo": {"const": "http://www.w3.org/TR/media-frags/"},
                "value": {"type": "string",
                          "pattern": r"^xywh=(pixel:)?\d+(\.\d+)?(,\d+(\.\d+)?){3}$"}}},
        "specific": {
            "type": "object", "required": ["type", "source", "selector"],
            "properties": {
                "type": {"const": "SpecificResource"},
                "source": {"anyOf": [_IRI, {"type": "object", "required": ["id"],
                                            "properties": {"id": _IRI}}]},
                "selector": {"$ref": "#/$defs/fragment"}}},
        "textual": {
            "type": "object", "required": ["type", "value"],
            "properties": {
                "type": {"const": "TextualBody"}, "value": {"type": "string"},
                "format": {"type": "string", "pattern": r"^[a-z]+/[a-z0-9.+-]+$"},
                "purpose": _MOTIVATION, "id": _IRI}},
        "image": {
            "type": "object", "required": ["id", "type", "format"],
            "properties": {"id": _IRI, "type": {"const": "Image"},
                           "format": {"const": "image/png"}}},
        "agent": {
            "type": "object", "required": ["type", "name"],
            "properties": {"type": {"enum": ["Person", "Organization", "Software"]},
                           "name": {"type": "string", "minLength": 1}}},
        "annotation": {
            "type": "object", "required": ["id", "type", "motivation", "target", "body"],
            "properties": {
                "@context": _CONTEXT,
                "id": _IRI,
                "type": {"const": "Annotation"},
                "motivation": {"anyOf": [_MOTIVATION, {"type": "array", "minItems": 1,
                                                        "items": _MOTIVATION}]},
                "target": {"$ref": "#/$defs/specific"},
                "body": {"type": "array", "minItems": 1, "items": {
                    "anyOf": [{"$ref": "#/$defs/image"}, {"$ref": "#/$defs/textual"}]}},
                "creator": {"$ref": "#/$defs/agent"},
                "created": _DATETIME,
                "modified": _DATETIME}},
    },
    "anyOf": [
        {"allOf": [{"$ref": "#/$defs/annotation"}, {"required": ["@context"]}]},
        {"type": "object", "required": ["@context", "id", "type", "items"],
         "properties": {"@context": _CONTEXT, "id": _IRI, "type": {"const": "AnnotationPage"},
                        "items": {"type": "array",
                                  "items": {"$ref": "#/$defs/annotation"}}}},
    ],
}


def w3c_errors(doc: Any) -> list[str]:
    """The W3C model rules ``doc`` (an Annotation document or an AnnotationPage) breaks."""
    validator = Draft202012Validator(RULES)
    return [f"{'/'.join(str(p) for p in e.absolute_path)}: {e.message}"
            for e in validator.iter_errors(doc)]
