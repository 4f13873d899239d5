"""A preset library checked against its schema and against the dataset it belongs to.

A library (docs/presets.md, ``tiler/schemas/presets.schema.json``) holds named presets — one
layer, one render mode, its parameters, a light and a view — and the paper's two lists of
entries, ``base`` and ``lens``. :func:`check_library` checks a parsed library in two steps:
the schema (:mod:`lanterna.tiler.documents`), then the rules a schema cannot state, against the
dataset's description (``lanterna.json``): every layer a preset or an entry names is a layer of
the dataset, the preset's mode applies to that layer's type, the light lies in the unit disk, the
view lies within the image, every entry's preset exists. Each problem is one
:class:`~lanterna.errors.LanternaInputError` naming the file and the JSON path::

    presets.json: base[2].layer: no layer 'x' in the dataset (layers: ptm, hsh, …)
"""

from __future__ import annotations

import copy
from collections.abc import Mapping
from pathlib import Path
from typing import Any

from lanterna.errors import LanternaInputError
from lanterna.tiler.documents import check_document, load_json
from lanterna.tiler.render.modes import applicable_modes

#: The schema of ``tiler/schemas/`` a library is checked against.
SCHEMA = "presets"
#: The library's ``type`` and ``version``.
LIBRARY_TYPE, LIBRARY_VERSION = "LanternaPresets", 1
#: Slack on the unit disk (``lu² + lv² ≤ 1 + LIGHT_SLACK``), for lights written as rounded decimals.
LIGHT_SLACK = 1e-9
#: The two lists of entries.
LISTS = ("base", "lens")


class PresetError(LanternaInputError):
    """A preset library that is not valid (for the schema or for its dataset)."""


def empty_library() -> dict[str, Any]:
    """A library with no presets and empty lists."""
    return {"type": LIBRARY_TYPE, "version": LIBRARY_VERSION, "presets": {}, "base": [],
            "lens": []}


def read_library(path: Path, desc: Mapping[str, Any]) -> dict[str, Any]:
    """Read the library file ``path`` and check it against dataset description ``desc``."""
    return check_library(load_json(Path(path)), desc, Path(path).name)


def check_library(doc: Any, desc: Mapping[str, Any],
                  source: str | Path | None = "presets.json") -> dict[str, Any]:
    """Check a parsed library against the schema and the dataset ``desc``; return a copy.

    Raises
    ------
    PresetError
        Naming ``source`` and the JSON path of the first problem.
    """
    try:
        library = copy.deepcopy(check_document(doc, SCHEMA, source))
    except LanternaInputError as err:
        raise PresetError(err.source, err.problem) from None
    layers = layer_services(desc)
    width, height = float(desc["width"]), float(desc["height"])
    for pid, preset in library["presets"].items():
        where = f"presets.{pid}"
        _check_layer(preset["layer"], layers, f"{where}.layer", source)
        _check_mode(preset["mode"], preset["layer"], layers, f"{where}.mode", source)
        if "light" in preset:
            lu, lv = preset["light"]
            if lu * lu + lv * lv > 1 + LIGHT_SLACK:
                raise PresetError(source, f"{where}.light: [{lu}, {lv}] is outside the "
                                  "unit disk (lu² + lv² must be at most 1)")
        if "view" in preset:
            x, y, w, h = preset["view"]
            if x < 0 or y < 0 or x + w > width or y + h > height:
                raise PresetError(source, f"{where}.view: [{x}, {y}, {w}, {h}] is not "
                                  f"within the image ({int(width)}×{int(height)})")
    for name in LISTS:
        for i, entry in enumerate(library[name]):
            where = f"{name}[{i}]"
            preset = library["presets"].get(entry["preset"])
            if preset is None:
                known = ", ".join(sorted(library["presets"])) or "none"
                raise PresetError(source, f"{where}.preset: no preset "
                                  f"{entry['preset']!r} (presets: {known})")
            layer = entry.get("layer", preset["layer"])
            _check_layer(layer, layers, f"{where}.layer", source)
            _check_mode(preset["mode"], layer, layers, f"{where}.layer", source,
                        preset=entry["preset"])
    return library


def layer_services(desc: Mapping[str, Any]) -> dict[str, Mapping[str, Any]]:
    """The relight service block of every layer of a dataset description, by layer id."""
    return {str(layer["id"]): layer.get("service", {}) for layer in desc.get("layers", [])}


def _check_layer(layer: str, layers: Mapping[str, Any], where: str,
                 source: str | Path | None) -> None:
    if layer not in layers:
        shown = ", ".join(list(layers)[:8]) + (", …" if len(layers) > 8 else "")
        raise PresetError(source, f"{where}: no layer {layer!r} in the dataset "
                          f"(layers: {shown})")


def _check_mode(mode: str, layer: str, layers: Mapping[str, Mapping[str, Any]], where: str,
                source: str | Path | None, *, preset: str | None = None) -> None:
    try:
        modes = applicable_modes(layers[layer])
    except ValueError:
        raise PresetError(source, f"{where}: layer {layer!r} has no render modes "
                          "(unknown layer type)") from None
    if mode not in modes:
        whose = f"the mode {mode!r} of preset {preset!r}" if preset else f"mode {mode!r}"
        raise PresetError(source, f"{where}: {whose} does not apply to layer "
                          f"{layer!r} ({layers[layer].get('layerType')}; modes: "
                          f"{', '.join(modes)})")
