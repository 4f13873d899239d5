"""Turn sources (files, folders, description files, spectral bands) into one dataset."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

import pyvips

from .dataset import DEFAULT_BASE_URL, check_identifier
from .errors import LanternaInputError
from .plans import LayerPlan, build_dataset, plan_bands, plan_source


def load_rgb_image(path: Path) -> pyvips.Image:
    """Load an image file as 8-bit sRGB without alpha, with a clear error if it can't be read."""
    try:
        img = pyvips.Image.new_from_file(str(path), access="sequential")
        if img.hasalpha():
            img = img.flatten(background=[0, 0, 0])
        if img.interpretation not in ("srgb", "b-w") or img.format != "uchar":
            img = img.colourspace("srgb").cast("uchar")
        if img.bands == 1:
            img = img.bandjoin([img, img])
        img = img.copy_memory()
    except pyvips.Error as err:
        first = str(err).strip().splitlines()[0] if str(err).strip() else "unreadable image"
        raise LanternaInputError(path, f"cannot read image ({first})") from None
    return img.copy(interpretation="srgb")


def import_sources(sources: Sequence[Path], out: Path, *, name: str | None = None,
                   label: str | None = None, bands: dict[str, Path] | None = None,
                   fusions: Sequence[Sequence[str]] = (), base_url: str = DEFAULT_BASE_URL,
                   tile_size: int = 256, force: bool = False, tiff: bool = False) -> Path:
    """Import sources as the layers of dataset ``out`` (in order; the first is the default).

    A source is a ``.ptm``, ``.rti``, a Relight web-format folder, an image, or a dataset
    description ``.json`` (Lanterna's or the seed paper's scene format). ``bands`` adds one grey
    layer per spectral band, ``fusions`` one false-colour layer per band triple. ``tiff`` also
    writes a pyramidal TIFF per image (``tiff/<image>.tif``) for the IIIF image server.
    """
    from .description import plan_description

    plans: list[LayerPlan] = []
    fields: dict[str, str] = {}
    for source in sources:
        source = Path(source)
        if source.suffix.lower() == ".json" and source.is_file():
            desc_fields, desc_plans = plan_description(source)
            fields = {**desc_fields, **fields}
            plans.extend(desc_plans)
        else:
            plans.append(plan_source(source))
    if bands:
        plans.extend(plan_bands(bands, fusions))
    elif fusions:
        raise LanternaInputError(None, "--fusion needs spectral bands (--band NAME=FILE)")
    first = Path(sources[0]) if sources else Path(out)
    ds_name = check_identifier(name or fields.get("name") or _safe_name(Path(out).name),
                               "dataset name")
    ds_label = label or fields.get("label") or first.stem
    return build_dataset(plans, out, name=ds_name, label=ds_label, base_url=base_url,
                         tile_size=tile_size, force=force, summary=fields.get("summary"),
                         tiff=tiff)


def import_source(source: Path, out: Path, **kwargs: object) -> Path:
    """Import one source as dataset ``out`` (see :func:`import_sources`)."""
    return import_sources([source], out, **kwargs)  # type: ignore[arg-type]


def _safe_name(stem: str) -> str:
    cleaned = "".join(ch if ch.isalnum() or ch in "_-" else "_" for ch in stem)
    return cleaned or "dataset"
