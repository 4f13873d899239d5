"""numpy reference renderer: every layer type and render mode of docs/rendering.md, in float32.

The browser tests compare the plugin's pixels with :func:`render` applied to the channels of the
very tiles the browser draws (:func:`level_channels`).
"""

from __future__ import annotations

from .hsh import hsh_basis, hsh_normals
from .ptm import ptm_normals

__all__ = ["hsh_basis", "hsh_normals", "ptm_normals"]
