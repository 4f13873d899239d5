"""numpy reference renderer: every layer type and render mode of docs/rendering.md, in float32.

The browser tests compare the plugin's pixels with :func:`render` applied to the channels of the
very tiles the browser draws (:func:`level_channels`)::

    channels = level_channels(dataset_dir, layer_block, factor=1, region=(x, y, w, h))
    rgb = render(layer_block, channels, light=(0.3, 0.2), mode="specular")
"""

from __future__ import annotations

from .filters import box_filter, box_pass, f3, f5
from .hsh import hsh_basis, hsh_normals
from .levels import dequantise, level_channels, level_image
from .modes import (
    MODES,
    PARAMETERS,
    albedo,
    applicable_modes,
    normals,
    render,
    resolve_params,
    surface,
)
from .pca import pca_surface
from .ptm import ptm_normals
from .shading import linear_to_srgb, luma, post, srgb_to_linear

__all__ = [
    "MODES", "PARAMETERS", "albedo", "applicable_modes", "box_filter", "box_pass", "f3", "f5",
    "dequantise", "hsh_basis", "hsh_normals", "level_channels", "level_image", "linear_to_srgb",
    "luma", "normals", "pca_surface", "post", "ptm_normals", "render", "resolve_params",
    "srgb_to_linear", "surface",
]
