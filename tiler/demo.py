"""The demo dataset: a synthetic relief tablet with known normals and albedo, as a PTM layer."""

from __future__ import annotations

from pathlib import Path

from .dataset import DEFAULT_BASE_URL, DatasetWriter
from .layers import add_ptm_layer

DEMO_SIZE = (1536, 1152)


def build_demo(out: Path, *, base_url: str = DEFAULT_BASE_URL, force: bool = False,
               size: tuple[int, int] = DEMO_SIZE) -> Path:
    """Generate the demo object, fit its PTM and write it as dataset ``out``."""
    from .demo_render import make_demo_ptm

    ptm = make_demo_ptm(width=size[0], height=size[1], seed=0)
    label = "Lanterna demo tablet (synthetic)"
    with DatasetWriter(out, name=Path(out).name, label=label, width=ptm.width,
                       height=ptm.height, base_url=base_url, source="synthetic",
                       force=force) as ds:
        add_ptm_layer(ds, ptm, label="Relief tablet (PTM LRGB)")
    return Path(out)
