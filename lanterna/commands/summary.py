"""What a command that writes a dataset prints last: what was made, and the command to run next."""

from __future__ import annotations

import shlex
from collections.abc import Mapping
from pathlib import Path
from typing import Any


def summary(desc: Mapping[str, Any]) -> list[str]:
    """Describe a dataset from its parsed ``lanterna.json``.

    A headline (name, label, size, layer count), then one line per layer (id, type, size,
    images and their tile formats, overlay levels), then the pyramidal TIFFs if any were written.
    """
    from lanterna.tiler.overlays.build import overlay_rows

    layers: list[dict[str, Any]] = desc.get("layers", [])
    overlays = {row["id"]: row for row in overlay_rows(desc)}
    rows = [(layer["id"], _kind(layer["service"]), _size(layer["service"]),
             _count(len(layer["service"].get("planes", [])), "image")
             + _formats(layer["service"], desc.get("images", {})),
             _overlay(overlays.get(layer["id"]))) for layer in layers]
    w = [max((len(row[i]) for row in rows), default=0) for i in range(4)]
    lines = [f"dataset {desc['name']} \"{desc.get('label', desc['name'])}\", {_size(desc)}, "
             f"{_count(len(layers), 'layer')}:"]
    for layer_id, kind, size, images, overlay in rows:
        lines.append(f"  {layer_id:<{w[0]}}  {kind:<{w[1]}}  {size:>{w[2]}}  {images:<{w[3]}}"
                     f"{overlay}".rstrip())
    tiffs = sum(1 for image in desc.get("images", {}).values() if image.get("tiff"))
    if tiffs:
        lines.append(f"  {_count(tiffs, 'pyramidal TIFF')} in tiff/, served by the IIIF image "
                     "server at /iiif/3/")
    return lines


def print_written(dataset: Path, *, details: bool = True) -> None:
    """Print :func:`summary` of the dataset just written to ``dataset``, and how to serve it.

    Without ``details`` only the headline is printed.
    """
    from lanterna.tiler.dataset.writer import read_description

    head, *rest = summary(read_description(dataset))
    if not details:
        print(f"wrote {dataset}: {head.rstrip(':')}")
        return
    print(f"wrote {dataset}: {head}")
    for line in rest:
        print(line)
    print(f"next: lanterna serve {shlex.quote(str(dataset.parent))}   "
          "(prints the viewer URL of every dataset in that folder)")


def _kind(service: Mapping[str, Any]) -> str:
    from lanterna.tiler.formats.layouts import SVBRDF_MAPS

    kind = str(service.get("layerType"))
    planes = service.get("planes", [])
    if kind == "ptm":
        return f"PTM {str(service.get('colorspace', '')).upper()}".rstrip()
    if kind in ("hsh", "sh"):
        return f"{kind.upper()} {service.get('terms')} terms"
    if kind in ("rbf", "bilinear"):
        return f"{kind.upper()} {str(service.get('colorspace', '')).upper()} " \
               f"{service.get('nplanes')} planes"
    if kind == "svbrdf":
        names = {channels[0]: name for name, (channels, _, _) in SVBRDF_MAPS.items()}
        maps = [names.get(plane["channels"][0], "?") for plane in planes]
        return "SVBRDF " + "+".join(maps)
    if kind == "image":
        return "image grey" if [p["channels"] for p in planes] == [["Y"]] else "image RGB"
    return kind


def _formats(service: Mapping[str, Any], images: Mapping[str, Any]) -> str:
    """`` webp:near60``, `` png+webp``: the plane images' tile formats (--plane-format's choice)."""
    from lanterna.tiler.iiif.encoding import TileFormat

    labels = {TileFormat(plane["format"], images.get(
        str(plane["service"]["id"]).rsplit("/", 1)[-1], {}).get("quality")).label()
        for plane in service.get("planes", []) if "format" in plane}
    return " " + "+".join(sorted(labels)) if labels else ""


def _size(item: Mapping[str, Any]) -> str:
    return f"{item.get('width')}\u00d7{item.get('height')}"


def _count(n: int, noun: str, plural: str = "") -> str:
    return f"{n} {noun if n == 1 else plural or noun + 's'}"


def _overlay(row: Mapping[str, Any] | None) -> str:
    if not row or not row["levels"]:
        return ""
    levels = _count(len(row["levels"]), "level")
    return f"  annotations: {levels}, {_count(row['patches'], 'patch', 'patches')}"
