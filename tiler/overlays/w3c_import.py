"""``lanterna annotate export`` and ``import``: a layer's patches as a W3C AnnotationPage, and an
AnnotationPage (Annotorious, Mirador's annotation editor, a Lanterna export) into its patches.

docs/annotations.md, "Individual annotations (W3C)". :func:`export_page` copies the page the
published dataset serves (``annotations/LAYER.json``, written with every version by
:func:`~lanterna.tiler.dataset.writer.write_documents`); :func:`import_page` reads
a page (:mod:`.w3c_read`: every annotation checked and drawn before anything is stored), adds
each annotation to the layer's patch store on top of the others (:func:`.store.add_patch`),
then rebuilds the overlay once (:func:`.rebuild.rebuild_from_store`).
"""

from __future__ import annotations

import os
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any
from urllib.parse import unquote, urlsplit

import numpy as np
import numpy.typing as npt

from lanterna.errors import LanternaInputError
from lanterna.tiler.dataset.output import json_text, write_errors
from lanterna.tiler.dataset.publish import reading
from lanterna.tiler.dataset.writer import read_description
from lanterna.tiler.documents import load_json

from .build import OverlayReport
from .composite import load_rgba
from .published import find_layer
from .rebuild import rebuild_from_store
from .store import add_patch, layer_canvas
from .w3c_read import OwnImage, read_page


@dataclass
class ImportReport:
    """What :func:`import_page` stored: the new patch records, and the rebuild's report."""

    records: list[dict[str, Any]] = field(default_factory=list)
    rebuild: OverlayReport | None = None


def export_page(dataset: Path, layer_id: str, out: Path) -> int:
    """Write the AnnotationPage of ``layer_id``'s published patches to ``out``; return their
    number. A layer without published patches is an error (nothing is written)."""
    with reading(Path(dataset)) as version:
        find_layer(read_description(version), layer_id, Path(dataset))
        published = version / "annotations" / f"{layer_id}.json"
        if not published.is_file():
            raise LanternaInputError(dataset, f"layer {layer_id} has no published patches to "
                                     "export")
        page = load_json(published)
    out = Path(out)
    part = out.with_name(f".{out.name}.part")
    with write_errors(out):
        try:
            part.write_text(json_text(page, out) + "\n")
            os.replace(part, out)
        finally:
            part.unlink(missing_ok=True)
    return len(page["items"])


def import_page(dataset: Path, layer_id: str, page: Path) -> ImportReport:
    """Add every annotation of the AnnotationPage file ``page`` to ``layer_id``'s patch store,
    then rebuild its overlay. A page with a bad annotation stores nothing."""
    dataset = Path(dataset)
    canvas = layer_canvas(dataset, layer_id)
    patches = read_page(Path(page), width=canvas.width, height=canvas.height,
                        deepest=canvas.deepest, own_image=own_images(dataset))
    report = ImportReport()
    for patch in patches:
        x, y, w, h = patch.rect
        meta = {"level": patch.level, "x": x, "y": y, "w": w, "h": h, "short": patch.short,
                "long": patch.long, "motivation": patch.motivation, "author": patch.author}
        report.records.append(add_patch(dataset, layer_id, patch.rgba, meta, created=patch.created))
    report.rebuild = rebuild_from_store(dataset, layer_id)
    return report


def own_images(dataset: Path) -> OwnImage:
    """Find a patch image of this dataset by its URL (``…/{name}/annotations/LAYER/ID.png``,
    whatever the host: a page exported here or fetched from a server of this dataset)."""
    desc = read_description(dataset)
    marker = f"/{desc['name']}/annotations/"

    def find(url: str) -> npt.NDArray[np.uint8] | None:
        path = unquote(urlsplit(url).path)
        if marker not in path:
            return None
        rest = path.rsplit(marker, 1)[1]
        parts = rest.split("/")
        if len(parts) != 2 or any(p in ("", ".", "..") or p.startswith(".") for p in parts) \
                or not parts[1].endswith(".png"):
            return None
        file = Path(os.path.realpath(dataset)) / "annotations" / parts[0] / parts[1]
        try:
            return load_rgba(file) if file.is_file() else None
        except LanternaInputError:
            return None

    return find

