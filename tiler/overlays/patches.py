"""Overlay sources: a folder of patches (``L_X_Y_W_H_O_INFO.png``), a folder of one image per
level (GIMP), and the levels' texts (docs/annotations.md)."""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path
from typing import Any

import numpy as np
import numpy.typing as npt

from lanterna.errors import LanternaInputError
from lanterna.tiler.documents import check_document, read_document

from . import geometry as og
from .composite import composite, fit_level_image, load_rgba

Texts = dict[int, dict[str, str]]


def levels_from_patches(folder: Path, width: int, height: int, deepest: int,
                        ) -> tuple[dict[int, npt.NDArray[np.uint8]], list[og.Patch], list[str]]:
    """Composite the patches of ``folder``; return level images, patches used, per-file errors."""
    patches: list[og.Patch] = []
    images: dict[str, tuple[npt.NDArray[np.uint8], og.Placement]] = {}
    errors: list[str] = []
    for path in _files(folder):
        try:
            patch = og.parse_patch_name(path.name)
        except og.PatchNameError as err:
            errors.append(str(LanternaInputError(path, str(err))))
            continue
        try:
            if patch.level > deepest:
                raise LanternaInputError(path, f"level {patch.level} is beyond the pyramid "
                                         f"(levels 0–{deepest})")
            placement = og.place(patch, width, height)
            if placement is None:
                raise LanternaInputError(path, f"rectangle {patch.x},{patch.y},{patch.w},"
                                         f"{patch.h} is outside the {width}x{height} canvas")
            rgba = load_rgba(path)
            problem = og.scale_problem((rgba.shape[1], rgba.shape[0]), placement)
            if problem:
                raise LanternaInputError(path, problem)
            images[patch.file] = (rgba, placement)
        except LanternaInputError as err:
            errors.append(str(err))
            continue
        patches.append(patch)
    patches = og.application_order(patches)
    levels: dict[int, npt.NDArray[np.uint8]] = {}
    for level in sorted({p.level for p in patches}):
        lw, lh = og.level_size(width, height, level)
        levels[level] = composite(lw, lh, [images[p.file] for p in patches if p.level == level])
    return levels, patches, errors


def levels_from_gimp(folder: Path, width: int, height: int, deepest: int,
                     ) -> tuple[dict[int, npt.NDArray[np.uint8]], list[str]]:
    """Read one transparent image per level (``level_L.png`` or ``L.png``); return them + errors."""
    levels: dict[int, npt.NDArray[np.uint8]] = {}
    seen: dict[int, str] = {}
    errors: list[str] = []
    for path in _files(folder):
        try:
            level = og.parse_gimp_name(path.name)
        except og.PatchNameError as err:
            errors.append(str(LanternaInputError(path, str(err))))
            continue
        try:
            if level in seen:
                raise LanternaInputError(path, f"level {level} is also given by {seen[level]}")
            if level > deepest:
                raise LanternaInputError(path, f"level {level} is beyond the pyramid "
                                         f"(levels 0–{deepest})")
            levels[level] = fit_level_image(load_rgba(path), level, width, height, path)
            seen[level] = path.name
        except LanternaInputError as err:
            errors.append(str(err))
    return levels, errors


def _files(folder: Path) -> list[Path]:
    folder = Path(folder)
    if not folder.is_dir():
        raise LanternaInputError(folder, "not a folder")
    return sorted(p for p in folder.iterdir() if p.is_file() and not p.name.startswith("."))


def read_texts(texts: Path | Mapping[Any, Any] | None) -> Texts:
    """Read ``{"L": {"short": "…", "long": "<p>…</p>"}}`` (a JSON file or a mapping), checked
    against ``tiler/schemas/texts.schema.json``."""
    if texts is None:
        return {}
    if isinstance(texts, (str, Path)):
        doc = read_document(Path(texts), "texts")
    else:
        doc = check_document({str(k): v for k, v in texts.items()} if isinstance(texts, Mapping)
                             else texts, "texts", None)
    return {int(key): {"short": value.get("short", ""), "long": value.get("long", "")}
            for key, value in doc.items()}
