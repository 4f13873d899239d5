"""The manifest's own service blocks: the preset library (Manifest) and the physical scale (Canvas).

- :func:`presets_service`: the dataset's preset library (docs/presets.md) as a service on the
  Manifest, ``{"id": "{dataset url}/presets.json", "type": "LanternaPresets", "profile":
  "urn:lanterna:presets:1", "version": 1, "presets": {…}, "base": […], "lens": […]}``: the library
  document with an ``id`` (the same library is written as that file) and a ``profile``, so a
  static export of the manifest keeps it. The library's optional ``label`` (a plain string,
  where Presentation 3 wants a language map on every resource) stays out of the block;
  ``presets.json`` keeps it.
- :func:`physdim_service`: the IIIF Physical Dimensions service (the IIIF services annex) on the
  Canvas when the pixel size is known: ``physicalScale`` millimetres per canvas pixel. The annex
  defines ``@context``, ``profile``, ``physicalScale`` and ``physicalUnits``; Presentation 3
  wants an ``id`` and a ``type`` on every service, so the block has both (``type``
  :data:`PHYSDIM_TYPE`, docs/dataset-format.md says why). Viewers find it by its ``profile``.
"""

from __future__ import annotations

import copy
from typing import Any

PRESETS_PROFILE = "urn:lanterna:presets:1"
PHYSDIM_PROFILE = "http://iiif.io/api/annex/services/physdim"
PHYSDIM_CONTEXT = "http://iiif.io/api/annex/services/physdim/1/context.json"
PHYSDIM_TYPE = "PhysicalDimensions"


def presets_service(desc: dict[str, Any], ds_url: str) -> dict[str, Any] | None:
    """The preset library of dataset description ``desc`` as a Manifest service, or None."""
    library = desc.get("presets")
    if not library:
        return None
    return {"id": f"{ds_url}/presets.json", "type": library["type"], "profile": PRESETS_PROFILE,
            **{k: copy.deepcopy(v) for k, v in library.items() if k not in ("type", "label")}}


def physdim_service(desc: dict[str, Any], ds_url: str) -> dict[str, Any] | None:
    """The physical-dimensions service of the canvas (``pixelSizeMM`` known), or None."""
    mm = desc.get("pixelSizeMM")
    if not mm:
        return None
    return {"@context": PHYSDIM_CONTEXT, "id": f"{ds_url}/canvas/1/physdim", "type": PHYSDIM_TYPE,
            "profile": PHYSDIM_PROFILE, "physicalScale": float(mm), "physicalUnits": "mm"}
