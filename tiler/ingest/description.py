"""Dataset description files: several co-registered layers, as JSON, imported in one go.

Lanterna's own form (paths relative to the file; docs/importing.md)::

    {"name": "tablet", "label": "Tablet", "summary": "<p>…</p>",
     "rights": "http://creativecommons.org/licenses/by/4.0/", "attribution": "…",
     "provider": {"label": "…", "homepage": "https://…"}, "metadata": [{"label": …, "value": …}],
     "layers": [
       {"id": "vis", "source": "vis.ptm"},
       {"id": "hsh", "source": "vis.rti", "label": "Visible (HSH)"},
       {"id": "mat", "type": "svbrdf", "maps": {"normals": "N.png", "kd": "kd.png"},
        "glossLimits": [0.01, 0.5], "inputColorSpace": "srgb", "normalConvention": "opengl"},
       {"type": "bands", "bands": {"IR": "ir.tif", "R": "r.tif", "G": "g.tif"},
        "fusions": [["IR", "R", "G"]]}
     ]}

The document is checked against ``tiler/schemas/description.schema.json`` first (every problem a
one-line error with its JSON path), then read into typed records (:class:`SourceEntry`,
:class:`SvbrdfEntry`, :class:`BandsEntry`) that the layers are planned from. The seed paper's
scene description (``obj.shader`` / ``obj.maps``) is recognised too and converted by :mod:`.scene`.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Any

from lanterna.errors import LanternaInputError
from lanterna.tiler.dataset.plan import LayerPlan
from lanterna.tiler.dataset.plane_format import AUTO, PlaneFormat
from lanterna.tiler.documents import check_document, load_json

from .overlay import attach_overlay
from .paths import referenced
from .scene import is_scene, plan_scene
from .sources import plan_bands, plan_source, plan_svbrdf

#: The description's fields that go to the manifest as they are (lanterna.manifests.metadata).
PUBLICATION_FIELDS = ("rights", "attribution", "provider", "homepage", "seeAlso", "metadata")
#: Defaults of an svbrdf entry (docs/importing.md).
GLOSS_LIMITS = (0.01, 0.5)


@dataclass(frozen=True)
class SourceEntry:
    """A layer read from one source file or folder."""

    source: Path
    id: str | None = None
    label: str | None = None
    overlay: Any = None


@dataclass(frozen=True)
class SvbrdfEntry:
    """A shape + material layer from map files."""

    id: str
    maps: dict[str, Path]
    label: str | None = None
    gloss_limits: tuple[float, float] = GLOSS_LIMITS
    input_colorspace: str = "linear"
    normal_convention: str = "opengl"
    overlay: Any = None


@dataclass(frozen=True)
class BandsEntry:
    """Spectral bands (one grey layer each) and false-colour fusions of three of them."""

    bands: dict[str, Path]
    fusions: tuple[tuple[str, str, str], ...] = ()


Entry = SourceEntry | SvbrdfEntry | BandsEntry


def plan_description(path: Path, *, root: Path | None = None,
                     plane_format: PlaneFormat = AUTO) -> tuple[dict[str, Any], list[LayerPlan]]:
    """Return the dataset fields (name, label, summary, publication) and the layer plans of a
    description (``publication``: its rights, attribution, provider, homepage, seeAlso and
    metadata, as given; docs/dataset-format.md, "Manifest metadata").

    ``root``: every file the description names must be inside this folder (for descriptions that
    do not come from the command line: :mod:`.paths`). ``plane_format``: ``--plane-format``.
    """
    path = Path(path)
    doc = load_json(path)
    if is_scene(doc):
        return plan_scene(check_document(doc, "scene", path), path, root=root,
                          plane_format=plane_format)
    doc = check_document(doc, "description", path)
    plans: list[LayerPlan] = []
    for entry in read_entries(doc, path, root=root):
        plans.extend(plan_entry(entry, path.parent, plane_format))
    fields: dict[str, Any] = {k: doc[k] for k in ("name", "label", "summary") if k in doc}
    publication = {k: doc[k] for k in PUBLICATION_FIELDS if k in doc}
    if publication:
        fields["publication"] = publication
    return fields, plans


def read_entries(doc: dict[str, Any], path: Path, *, root: Path | None = None) -> list[Entry]:
    """The typed layer entries of a description that passed its schema."""
    base = path.parent

    def file(name: str, where: str) -> Path:
        return referenced(base, name, source=path, where=where, root=root)

    entries: list[Entry] = []
    for i, raw in enumerate(doc["layers"]):
        at = f"layers[{i}]"
        kind = raw.get("type", "source")
        if kind == "svbrdf":
            low, high = (float(v) for v in raw.get("glossLimits", GLOSS_LIMITS))
            if low > high:
                raise LanternaInputError(path, f"{at}.glossLimits: expected [min, max] with "
                                         f"min <= max (got [{low}, {high}])")
            entries.append(SvbrdfEntry(
                raw["id"], {k: file(v, f"{at}.maps.{k}") for k, v in raw["maps"].items()},
                raw.get("label"), (low, high), raw.get("inputColorSpace", "linear").lower(),
                raw.get("normalConvention", "opengl"), raw.get("overlay")))
        elif kind == "bands":
            bands = {k: file(v, f"{at}.bands.{k}") for k, v in raw["bands"].items()}
            fusions = tuple((a, b, c) for a, b, c in raw.get("fusions", []))
            for j, triple in enumerate(fusions):
                missing = [b for b in triple if b not in bands]
                if missing:
                    raise LanternaInputError(path, f"{at}.fusions[{j}]: unknown band(s) "
                                             f"{', '.join(missing)} (have {', '.join(bands)})")
            entries.append(BandsEntry(bands, fusions))
        else:
            entries.append(SourceEntry(file(raw["source"], f"{at}.source"), raw.get("id"),
                                       raw.get("label"), raw.get("overlay")))
    return entries


def plan_entry(entry: Entry, base: Path, plane_format: PlaneFormat = AUTO) -> list[LayerPlan]:
    """The layer plans of one entry (``base``: the folder overlay images are relative to)."""
    if isinstance(entry, BandsEntry):
        return plan_bands(entry.bands, entry.fusions)
    if isinstance(entry, SvbrdfEntry):
        plan = plan_svbrdf(entry.maps, layer_id=entry.id, label=entry.label,
                           gloss_limits=entry.gloss_limits,
                           input_colorspace=entry.input_colorspace,
                           normal_convention=entry.normal_convention,
                           plane_format=plane_format)
    else:
        plan = plan_source(entry.source, layer_id=entry.id, label=entry.label,
                           plane_format=plane_format)
    if entry.overlay is not None:
        attach_overlay(plan, entry.overlay, base)
    return [plan]
