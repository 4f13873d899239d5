"""The demo dataset's preset library: each layer of the tablet at its best (docs/presets.md).

Base presets: the inscription under raking light from the left (the V-cut letters cast shadows),
the gold rosette under specular enhancement, the RBF layer's gold between the dome's lights,
shape + material lit from above left, the normal
map, unsharp-masked normals on the cracks and pitting, and plain overhead light. Lens presets:
the infrared band (the underdrawing), the ultraviolet band (the fluorescing red paint), the
HSH's unsharp-masked coefficients (enhanced relief) and the false-colour fusion. Views are
fractions of the image, so a smaller demo (``build_demo(size=…)``) keeps them.
"""

from __future__ import annotations

from typing import Any

#: The demo's physical pixel size: the 1536-pixel tablet is 76.8 mm wide.
DEMO_PIXEL_MM = 0.05


def _view(width: int, height: int, x: float, y: float, w: float, h: float) -> list[int]:
    """The region ``(x, y, w, h)`` given in fractions of the image, in whole pixels."""
    x0, y0 = round(x * width), round(y * height)
    return [x0, y0, min(round(w * width), width - x0), min(round(h * height), height - y0)]


def demo_presets(width: int, height: int) -> dict[str, Any]:
    """The preset library of a demo dataset of ``width`` × ``height`` pixels."""
    inscription = _view(width, height, 0.12, 0.46, 0.76, 0.37)
    inlay = _view(width, height, 0.355, 0.14, 0.28, 0.38)
    presets: dict[str, Any] = {
        "raking-west": {"label": "Raking light from the left", "layer": "ptm", "mode": "color",
                        "params": {"lightIntensity": 1.5}, "light": [-0.94, 0.18],
                        "view": inscription},
        "specular-inlay": {"label": "Specular enhancement", "layer": "ptm", "mode": "specular",
                           "params": {"specKd": 0.3, "specKs": 1.0, "specExponent": 20},
                           "light": [0.2, 0.3], "view": inlay},
        "rbf-inlay": {"label": "RBF (Relight's PCA basis)", "layer": "rbf", "mode": "color",
                      "light": [0.45, 0.1], "view": inlay},
        "material": {"label": "Shape + material", "layer": "svbrdf", "mode": "color",
                     "params": {"lightIntensity": 1.2}, "light": [-0.3, 0.35]},
        "normals": {"label": "Geometry (normals)", "layer": "geometry", "mode": "normals"},
        "unsharp-normals": {"label": "Unsharp normals", "layer": "geometry",
                            "mode": "unsharpNormals", "params": {"umGain": 3.0},
                            "light": [-0.5, 0.5]},
        "overhead": {"label": "Overhead light", "layer": "ptm", "mode": "color",
                     "light": [0.0, 0.0]},
        "infrared": {"label": "Infrared band", "layer": "band_ir", "mode": "color",
                     "params": {"gamma": 1.3}},
        "ultraviolet": {"label": "Ultraviolet band", "layer": "band_uv", "mode": "color",
                        "params": {"brightness": 0.1}},
        "relief": {"label": "Enhanced relief", "layer": "hsh", "mode": "unsharpCoefficients",
                   "params": {"umGain": 3.0}},
        "false-colour": {"label": "False colour (IR, R, G)", "layer": "fc_ir_r_g",
                         "mode": "color"},
    }
    return {
        "type": "LanternaPresets", "version": 1, "label": "Demo tablet presets",
        "presets": presets,
        "base": [{"label": "Raking light from the left", "preset": "raking-west"},
                 {"label": "Specular enhancement on the inlay", "preset": "specular-inlay"},
                 {"label": "The inlay as an RBF", "preset": "rbf-inlay"},
                 {"label": "Shape + material", "preset": "material"},
                 {"label": "Geometry (normals)", "preset": "normals"},
                 {"label": "Unsharp normals", "preset": "unsharp-normals"},
                 {"label": "Overhead light", "preset": "overhead"}],
        "lens": [{"label": "Infrared underdrawing", "preset": "infrared", "opacity": 0.9},
                 {"label": "UV fluorescence", "preset": "ultraviolet", "opacity": 0.85},
                 {"label": "Enhanced relief", "preset": "relief", "opacity": 1.0},
                 {"label": "False colour", "preset": "false-colour", "opacity": 1.0}],
    }
