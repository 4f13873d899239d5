"""JSON documents Lanterna reads, each checked against its JSON Schema before anything uses it.

The schemas are files of ``tiler/schemas/`` (``<name>.schema.json``, JSON Schema 2020-12,
documented in docs/importing.md). :func:`read_document` reads a regular file of bounded size,
parses it (the non-standard ``NaN``/``Infinity`` literals refused, numbers too large for a float
refused), validates it and returns it; every problem is one :class:`~lanterna.errors.
LanternaInputError` naming the file and the JSON path::

    vis.json: layers[0].maps.kd: expected a file name (got 4)

A schema's leaf constraints carry a ``description`` saying what is expected ("a file name"),
which is what the message quotes.
"""

from __future__ import annotations

import json
import math
from collections.abc import Iterable, Mapping
from functools import cache
from importlib import resources
from pathlib import Path
from typing import Any

from jsonschema import Draft202012Validator
from jsonschema.exceptions import ValidationError, best_match
from referencing import Registry, Resource

from lanterna.errors import LanternaInputError

from .fileio import read_input

#: Largest JSON document read, in bytes.
MAX_DOCUMENT_BYTES = 16 << 20


@cache
def schemas() -> dict[str, dict[str, Any]]:
    """Every schema of ``tiler/schemas/`` by name (``<name>.schema.json``)."""
    out = {}
    for entry in resources.files("lanterna.tiler.schemas").iterdir():
        if entry.name.endswith(".schema.json"):
            schema = json.loads(entry.read_text(encoding="utf-8"))
            Draft202012Validator.check_schema(schema)
            out[entry.name.removesuffix(".schema.json")] = schema
    return out


@cache
def validator(name: str) -> Draft202012Validator:
    """The validator of schema ``name``; the schemas refer to each other by their ``$id``."""
    registry: Registry[Any] = Registry().with_resources(
        (schema["$id"], Resource.from_contents(schema)) for schema in schemas().values())
    return Draft202012Validator(schemas()[name], registry=registry)


def read_document(path: Path, schema: str) -> dict[str, Any]:
    """Read the JSON file ``path`` and check it against ``schema``; return the document."""
    return check_document(load_json(path), schema, path)


def load_json(path: Path) -> Any:
    """Parse the JSON file ``path`` (a regular file of at most :data:`MAX_DOCUMENT_BYTES`)."""
    return parse_json(read_input(Path(path), "a JSON file", max_bytes=MAX_DOCUMENT_BYTES), path)


def document_type(path: Path) -> str | None:
    """The top-level ``type`` of the JSON object in the file ``path``, or ``None`` when there is
    no such file, it cannot be read as JSON, or it has no text ``type`` (sniffing only: the
    document's own reader reports what is wrong with it)."""
    if not Path(path).is_file():
        return None
    try:
        doc = load_json(path)
    except LanternaInputError:
        return None
    kind = doc.get("type") if isinstance(doc, dict) else None
    return kind if isinstance(kind, str) else None


def parse_json(data: bytes, source: str | Path) -> Any:
    """Parse the JSON text ``data`` read from ``source`` (a file or a URL, for the errors)."""
    try:
        return json.loads(data.decode("utf-8"), parse_constant=_refuse_constant)
    except UnicodeDecodeError:
        raise LanternaInputError(source, "not valid JSON (not UTF-8 text)") from None
    except (ValueError, RecursionError) as err:
        raise LanternaInputError(source, f"not valid JSON ({_first_line(err)})") from None


def check_document(doc: Any, schema: str, source: str | Path | None) -> dict[str, Any]:
    """Check a parsed document (from a file or a caller) against ``schema``; return it."""
    found = non_finite(doc)
    if found is not None:
        raise LanternaInputError(source, f"{found[0]}: a number too large to use")
    error = best_match(validator(schema).iter_errors(doc))
    if error is not None:
        raise LanternaInputError(source, explain(error))
    if not isinstance(doc, dict):
        raise LanternaInputError(source, "expected a JSON object")
    return doc


def explain(error: ValidationError) -> str:
    """One line for a validation error: its JSON path and what was expected there."""
    while error.parent is not None and error.parent.validator in ("anyOf", "oneOf"):
        error = error.parent  # the alternatives' shared description says more than either
    where = json_path(error.absolute_path)
    at = "" if where == "(document)" else f"{where}: "
    expected = error.schema.get("description") if isinstance(error.schema, Mapping) else None
    kind = error.validator
    if "propertyNames" in error.absolute_schema_path:
        return f"{at}key {_short(error.instance)}: expected {expected or 'another key'}"
    if kind == "required":
        missing = str(error.message).split("'")[1] if "'" in str(error.message) else "a key"
        return f'{at}needs "{missing}"'
    if kind == "additionalProperties":
        return f"{at}{_unknown_keys(error)}"
    if not expected:
        return f"{at}{_first_line(error.message)}"
    if kind in ("minProperties", "maxProperties", "minItems", "maxItems"):
        return f"{at}expected {expected}"
    return f"{at}expected {expected} (got {_short(error.instance)})"


def json_path(parts: Iterable[str | int]) -> str:
    """``layers[0].maps.kd`` from the path ``("layers", 0, "maps", "kd")``; ``(document)``."""
    out = ""
    for part in parts:
        out += f"[{part}]" if isinstance(part, int) else (f".{part}" if out else str(part))
    return out or "(document)"


def non_finite(doc: Any, where: tuple[str | int, ...] = ()) -> tuple[str, float] | None:
    """The JSON path (:func:`json_path`) and value of the first non-finite number in a parsed
    document, if any (``NaN`` and infinities: what JSON cannot hold)."""
    if isinstance(doc, float):
        return None if math.isfinite(doc) else (json_path(where), doc)
    items = doc.items() if isinstance(doc, dict) else (
        enumerate(doc) if isinstance(doc, list | tuple) else ())
    for key, value in items:
        found = non_finite(value, (*where, key if isinstance(key, int) else str(key)))
        if found is not None:
            return found
    return None


def _unknown_keys(error: ValidationError) -> str:
    allowed = set(error.schema.get("properties", {})) if isinstance(error.schema, Mapping) \
        else set()
    keys = sorted(k for k in error.instance if k not in allowed) \
        if isinstance(error.instance, dict) else []
    shown = ", ".join(_short(k, 30) for k in keys[:3]) + (" …" if len(keys) > 3 else "")
    return f"unknown key{'s' if len(keys) != 1 else ''} {shown}" + (
        f" (expected {', '.join(sorted(allowed))})" if allowed else "")


def _refuse_constant(name: str) -> float:
    raise ValueError(f"{name} is not a JSON number")


def _short(value: Any, limit: int = 40) -> str:
    text = json.dumps(value) if not isinstance(value, str) else repr(value)
    return text if len(text) <= limit else text[: limit - 1] + "…"


def _first_line(err: object) -> str:
    text = str(err).strip()
    return text.splitlines()[0][:120] if text else type(err).__name__
