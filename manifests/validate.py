"""Validate manifests against the official IIIF Presentation 3.0 JSON Schema.

The schema (``schema/iiif_3_0.json``) is the one the IIIF presentation validator uses, vendored
unchanged (see ``schema/NOTICE.md`` for its source, commit and licence). It declares no draft
that ``jsonschema`` knows, and uses the draft-07 keyword ``dependencies``, so it is checked as
draft 7, as the upstream validator does.
"""

from __future__ import annotations

import json
from functools import cache
from pathlib import Path
from typing import Any

from jsonschema import Draft7Validator
from jsonschema.exceptions import ValidationError

SCHEMA_PATH = Path(__file__).resolve().parent / "schema" / "iiif_3_0.json"
_MAX_MESSAGE = 160


@cache
def _validator(cls: str) -> Draft7Validator:
    schema: dict[str, Any] = json.loads(SCHEMA_PATH.read_text())
    # The root is a oneOf (Manifest, Collection, AnnotationCollection or AnnotationPage), which
    # reports one opaque error; checking the one class through allOf reports each error.
    del schema["oneOf"]
    schema["allOf"] = [{"$ref": f"#/classes/{cls}"}]
    return Draft7Validator(schema)


def validate_manifest(doc: Any) -> list[str]:
    """Check ``doc`` against the IIIF Presentation 3.0 JSON Schema.

    Parameters
    ----------
    doc
        A parsed manifest (the JSON-ready dict of :func:`lanterna.manifests.build.build_manifest`,
        or ``json.loads`` of a ``manifest.json``).

    Returns
    -------
    list of str
        One line per error, ``"<JSON path>: <message>"``; empty when the manifest is valid.
    """
    return _errors(doc, "manifest")


def validate_annotation_page(doc: Any) -> list[str]:
    """Check ``doc`` against the schema's AnnotationPage class; as :func:`validate_manifest`."""
    return _errors(doc, "annotationPage")


def _errors(doc: Any, cls: str) -> list[str]:
    errors = sorted(_validator(cls).iter_errors(doc), key=lambda e: list(e.path))
    lines: list[str] = []
    for err in errors:
        for leaf in _leaves(err):
            line = _describe(leaf)
            if line not in lines:
                lines.append(line)
    return lines


def _leaves(err: ValidationError) -> list[ValidationError]:
    """Follow a oneOf/anyOf failure into the branch the document came closest to matching.

    That is the branch whose errors lie deepest in the document (it matched the most structure),
    then the one with the fewest errors.
    """
    if not err.context:
        return [err]
    branches: dict[object, list[ValidationError]] = {}
    for sub in err.context:
        branch = sub.relative_schema_path[0] if sub.relative_schema_path else None
        branches.setdefault(branch, []).append(sub)
    closest = min(branches.values(),
                  key=lambda subs: (-max(len(s.absolute_path) for s in subs), len(subs)))
    return [leaf for sub in closest for leaf in _leaves(sub)]


def _describe(err: ValidationError) -> str:
    path = "/".join(str(p) for p in err.absolute_path) or "(root)"
    message = err.message if len(err.message) <= _MAX_MESSAGE else (
        err.message[: _MAX_MESSAGE - 1] + "…")
    return f"{path}: {message}"
