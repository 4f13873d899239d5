"""Multi-scale annotation overlays: level images from patches, GIMP levels or a seed-paper scene.

The contract is docs/annotations.md. A layer's overlay is a set of transparent RGBA level images
(``{layer}_ov{L}``, PNG pyramids) with a short and a long hypertext per level, plus the metadata of
the patches they were composited from. :func:`build_overlays` rewrites a dataset atomically (the
previous overlay stays until the new one is complete); :func:`scene_overlay` builds the levels of a
seed-paper scene's ``overlay`` entry during an import. The pure geometry is in
:mod:`lanterna.tiler.overlay_geometry`.

Compositing is done in float64 on premultiplied colour, source-over in application order, and
rounded to 8-bit straight alpha once per level (``round(a·255)``, ``round(c/a·255)``).
"""

from __future__ import annotations

import json
import logging
import shutil
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
import numpy.typing as npt
import pyvips

from . import overlay_geometry as og
from .dataset import DatasetWriter, read_description, rewriting
from .errors import LanternaInputError
from .fileio import read_json
from .pyramid import write_pyramid

log = logging.getLogger("lanterna.overlays")

Texts = dict[int, dict[str, str]]
FloatImage = npt.NDArray[np.float64]


class OverlayInputError(LanternaInputError):
    """No overlay level could be built; ``errors`` holds the one-line error of each bad file."""

    def __init__(self, source: str | Path | None, problem: str, errors: list[str]) -> None:
        super().__init__(source, problem)
        self.errors = errors


@dataclass
class OverlayReport:
    """What :func:`build_overlays` did: levels written, patches used, per-file errors."""

    layer: str
    levels: list[int] = field(default_factory=list)
    patches: int = 0
    errors: list[str] = field(default_factory=list)
    warnings: list[str] = field(default_factory=list)


# -- images ---------------------------------------------------------------------------------------
def load_rgba(path: Path) -> npt.NDArray[np.uint8]:
    """Read an image with an alpha channel as ``(H, W, 4)`` uint8 RGBA (grey + alpha expanded)."""
    try:
        img = pyvips.Image.new_from_file(str(path), access="sequential")
        if not img.hasalpha():
            raise LanternaInputError(path, f"has no alpha channel ({img.bands} band(s)); overlay "
                                     "images must be RGBA")
        if img.interpretation not in ("srgb", "b-w") or img.format != "uchar":
            img = img.colourspace("srgb" if img.bands > 2 else "b-w").cast("uchar")
        if img.bands == 2:
            img = img[0].bandjoin([img[0], img[0], img[1]])
        if img.bands != 4:
            raise LanternaInputError(path, f"has {img.bands} bands; overlay images must be RGBA")
        array: npt.NDArray[np.uint8] = np.ascontiguousarray(img.numpy(), dtype=np.uint8)
    except pyvips.Error as err:
        first = str(err).strip().splitlines()[0] if str(err).strip() else "unreadable image"
        raise LanternaInputError(path, f"cannot read image ({first})") from None
    return array


def premultiply(rgba: npt.NDArray[np.uint8]) -> FloatImage:
    """Return premultiplied float colour and alpha in 0–1."""
    out = rgba.astype(np.float64) / 255.0
    out[..., :3] *= out[..., 3:4]
    return out


def unpremultiply(pre: FloatImage) -> npt.NDArray[np.uint8]:
    """Round premultiplied float RGBA to 8-bit straight alpha (colour 0 where fully transparent)."""
    alpha = np.clip(pre[..., 3:4], 0.0, 1.0)
    safe = np.where(alpha > 0, alpha, 1.0)
    colour = np.where(alpha > 0, np.clip(pre[..., :3] / safe, 0.0, 1.0), 0.0)
    out = np.concatenate([colour, alpha], axis=-1) * 255.0
    return np.rint(out).astype(np.uint8)


def resize_premultiplied(pre: FloatImage, width: int, height: int) -> FloatImage:
    """Resize premultiplied RGBA to exactly ``width`` × ``height`` (linear kernel, no ringing)."""
    h, w = pre.shape[:2]
    if (w, h) == (width, height):
        return pre
    img = pyvips.Image.new_from_array(np.ascontiguousarray(pre, dtype=np.float32))
    img = img.resize(width / w, vscale=height / h, kernel="linear")
    if (img.width, img.height) != (width, height):  # the rounding of the output size
        img = img.embed(0, 0, max(width, img.width), max(height, img.height), extend="copy")
        img = img.crop(0, 0, width, height)
    out = np.asarray(img.numpy(), dtype=np.float64).reshape(height, width, 4)
    out[..., 3] = np.clip(out[..., 3], 0.0, 1.0)
    out[..., :3] = np.clip(out[..., :3], 0.0, out[..., 3:4])
    return out


def composite(level_w: int, level_h: int,
              items: list[tuple[npt.NDArray[np.uint8], og.Placement]]) -> npt.NDArray[np.uint8]:
    """Composite patches (RGBA, each with its placement) source-over, in list order."""
    acc = np.zeros((level_h, level_w, 4), np.float64)
    for rgba, placement in items:
        pre = resize_premultiplied(premultiply(rgba), *placement.size)
        sx, sy, sw, sh = placement.source_box
        cx0, cy0, cx1, cy1 = placement.clip
        src = pre[sy:sy + sh, sx:sx + sw]
        dst = acc[cy0:cy1, cx0:cx1]
        dst *= 1.0 - src[..., 3:4]
        dst += src
    return unpremultiply(acc)


def fit_level_image(rgba: npt.NDArray[np.uint8], level: int, width: int, height: int,
                    path: Path) -> npt.NDArray[np.uint8]:
    """Return a per-level image at its level's size.

    Accepted: the level's size; floor-halved sizes (one pixel short, padded transparent); or the
    full canvas size (downscaled by ``2^-L``). Anything else is an error naming both sizes.
    """
    lw, lh = og.level_size(width, height, level)
    h, w = rgba.shape[:2]
    if (w, h) == (lw, lh):
        return rgba
    if (w, h) == (width, height):
        return unpremultiply(resize_premultiplied(premultiply(rgba), lw, lh))
    if lw - 1 <= w <= lw and lh - 1 <= h <= lh:
        out = np.zeros((lh, lw, 4), np.uint8)
        out[:h, :w] = rgba
        return out
    raise LanternaInputError(path, f"is {w}x{h}; level {level} of the {width}x{height} canvas is "
                             f"{lw}x{lh}")


# -- sources --------------------------------------------------------------------------------------
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
            errors.append(f"{path}: {err}")
            continue
        try:
            if patch.level > deepest:
                raise LanternaInputError(path, f"level {patch.level} is beyond the pyramid "
                                         f"(levels 0–{deepest})")
            placement = og.place(patch, width, height)
            if placement is None:
                raise LanternaInputError(path, f"rectangle {patch.x},{patch.y},{patch.w},"
                                         f"{patch.h} is outside the {width}x{height} canvas")
            images[patch.file] = (load_rgba(path), placement)
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
            errors.append(f"{path}: {err}")
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
    """Read ``{"L": {"short": "…", "long": "<p>…</p>"}}`` (a JSON file or a mapping)."""
    if texts is None:
        return {}
    source: Path | None = None
    if isinstance(texts, (str, Path)):
        source = Path(texts)
        texts = read_json(source)
    if not isinstance(texts, Mapping):
        raise LanternaInputError(source, "texts must be an object {\"L\": {\"short\", \"long\"}}")
    out: Texts = {}
    for key, value in texts.items():
        try:
            level = int(key)
        except (TypeError, ValueError):
            level = -1
        if level < 0 or not isinstance(value, Mapping) or not all(
                isinstance(value.get(k, ""), str) for k in ("short", "long")):
            raise LanternaInputError(source, f"texts entry {key!r}: expected a level number and "
                                     "{\"short\": text, \"long\": html}")
        out[level] = {"short": value.get("short", ""), "long": value.get("long", "")}
    return out


# -- datasets -------------------------------------------------------------------------------------
def image_id(layer_id: str, level: int) -> str:
    """Return the IIIF identifier of a layer's overlay level image."""
    return f"{layer_id}_ov{level}"


def build_overlays(dataset_dir: Path, layer_id: str, *, patches_dir: Path | None = None,
                   gimp_dir: Path | None = None,
                   texts: Path | Mapping[Any, Any] | None = None) -> OverlayReport:
    """Build (or replace) the overlay of layer ``layer_id`` of a dataset.

    Parameters
    ----------
    dataset_dir:
        The dataset folder (with ``lanterna.json``).
    layer_id:
        The layer the overlay belongs to.
    patches_dir:
        A folder of ``L_X_Y_W_H_O_INFO.png`` patches (docs/annotations.md).
    gimp_dir:
        Instead of patches, a folder of one transparent image per level (``level_L.png``).
    texts:
        ``{"L": {"short": …, "long": …}}`` as a JSON file or a mapping. A level without an entry
        keeps the texts it had in the previous overlay.

    Returns
    -------
    The report; ``errors`` lists the rejected files (the valid ones are built).

    Raises
    ------
    OverlayInputError
        When no level can be built (the dataset is then unchanged).
    """
    if (patches_dir is None) == (gimp_dir is None):
        raise ValueError("give exactly one of patches_dir and gimp_dir")
    dataset_dir = Path(dataset_dir)
    desc = read_description(dataset_dir)
    layer = _find_layer(desc, layer_id, dataset_dir)
    width, height = int(desc["width"]), int(desc["height"])
    deepest, tile_size = _pyramid_of(dataset_dir, layer["body"])
    new_texts = read_texts(texts)
    report = OverlayReport(layer_id)
    patches: list[og.Patch] = []
    if patches_dir is not None:
        source = Path(patches_dir)
        levels, patches, report.errors = levels_from_patches(source, width, height, deepest)
    else:
        source = Path(gimp_dir)  # type: ignore[arg-type]
        levels, report.errors = levels_from_gimp(source, width, height, deepest)
    if not levels:
        problem = (f"no valid {'patches' if patches_dir is not None else 'level images'}"
                   f"{f' ({len(report.errors)} file(s) rejected)' if report.errors else ''}; "
                   "the dataset is unchanged")
        raise OverlayInputError(source, problem, report.errors)
    for level in sorted(set(new_texts) - set(levels)):
        report.warnings.append(f"texts for level {level} ignored: no overlay image at that level")

    previous = _previous_levels(layer)
    old_images = {e["image"] for e in previous.values()}
    clash = sorted(ident for ident in (image_id(layer_id, lv) for lv in levels)
                   if ident in desc.get("images", {}) and ident not in old_images)
    if clash:
        raise LanternaInputError(dataset_dir, f"image id(s) {', '.join(clash)} already used by "
                                 "something other than this layer's overlay")

    with rewriting(dataset_dir) as (tmp, new_desc):
        new_layer = _find_layer(new_desc, layer_id, dataset_dir)
        for entry in previous.values():  # an old overlay's images go; the new ones are rewritten
            shutil.rmtree(tmp / "iiif" / entry["image"], ignore_errors=True)
            new_desc["images"].pop(entry["image"], None)
        entries = []
        ds_url = f"{new_desc['baseUrl'].rstrip('/')}/{new_desc['name']}"
        for level, rgba in sorted(levels.items()):
            ident = image_id(layer_id, level)
            shutil.rmtree(tmp / "iiif" / ident, ignore_errors=True)
            (tmp / "iiif").mkdir(exist_ok=True)
            write_pyramid(pyvips.Image.new_from_array(rgba).copy(interpretation="srgb"),
                          tmp / "iiif" / ident, f"{ds_url}/iiif/{ident}", fmt="png",
                          tile_size=tile_size)
            h, w = rgba.shape[:2]
            new_desc["images"][ident] = {"format": "png", "width": w, "height": h, "bands": 4}
            text = new_texts.get(level) or previous.get(level) or {}
            entries.append({"level": level, "image": ident, "width": w, "height": h,
                            "short": text.get("short", ""), "long": text.get("long", "")})
        new_layer["overlay"] = {
            "source": "patches" if patches_dir is not None else "gimp",
            "levels": entries,
            "patches": [{"level": p.level, "x": p.x, "y": p.y, "w": p.w, "h": p.h,
                         "order": p.order, "info": p.info, "file": p.file} for p in patches],
        }
    report.levels = sorted(levels)
    report.patches = len(patches)
    return report


def scene_overlay(ds: DatasetWriter, layer_id: str, raw: Mapping[str, Any],
                  base: Path) -> dict[str, Any]:
    """Build the levels of a seed-paper scene ``overlay`` entry while importing a dataset.

    ``img`` is a template completed by a two-digit level (``vis/overlay.png`` →
    ``vis/overlay02.png``, relative to ``base``); ``range [a, b]`` (inclusive) lists the levels,
    ``shortInfo``/``longInfo`` their texts. Missing or unusable level images are warnings (the
    import goes on, the texts stay in the entry); the scene's own keys are kept as given.
    """
    result: dict[str, Any] = {**raw, "source": "scene", "levels": [], "patches": []}
    template, span = raw.get("img"), raw.get("range")
    if not isinstance(template, str) or not (
            isinstance(span, list) and len(span) == 2 and all(isinstance(v, int) for v in span)):
        log.warning("layer %s: overlay needs \"img\" and \"range\": [a, b]; kept as text only",
                    layer_id)
        return result
    shorts, longs = raw.get("shortInfo") or [], raw.get("longInfo") or []
    deepest = og.max_level(_factors(ds.width, ds.height, ds.tile_size))
    stem = base / template
    for i, level in enumerate(range(span[0], span[1] + 1)):
        path = stem.with_name(f"{stem.stem}{level:02d}{stem.suffix}")
        try:
            if level < 0 or level > deepest:
                raise LanternaInputError(path, f"level {level} is beyond the pyramid "
                                         f"(levels 0–{deepest})")
            if not path.is_file():
                raise LanternaInputError(path, "missing: this overlay level has texts only")
            rgba = fit_level_image(load_rgba(path), level, ds.width, ds.height, path)
        except LanternaInputError as err:
            log.warning("layer %s: overlay %s", layer_id, err)
            continue
        h, w = rgba.shape[:2]
        ident = image_id(layer_id, level)
        ds.add_image(ident, pyvips.Image.new_from_array(rgba).copy(interpretation="srgb"),
                     fmt="png", size=(w, h))
        result["levels"].append({
            "level": level, "image": ident, "width": w, "height": h,
            "short": str(shorts[i]) if i < len(shorts) else "",
            "long": str(longs[i]) if i < len(longs) else ""})
    return result


def overlay_summary(dataset_dir: Path) -> list[dict[str, Any]]:
    """Return, per layer, its overlay levels with texts and its patch count (``annotate list``)."""
    desc = read_description(Path(dataset_dir))
    rows = []
    for layer in desc["layers"]:
        overlay = layer.get("overlay")
        levels = overlay.get("levels", []) if isinstance(overlay, dict) else []
        patches = overlay.get("patches", []) if isinstance(overlay, dict) else []
        rows.append({"id": layer["id"], "label": layer["label"], "levels": levels,
                     "patches": len(patches),
                     "source": overlay.get("source") if isinstance(overlay, dict) else None})
    return rows


def _find_layer(desc: dict[str, Any], layer_id: str, where: Path) -> dict[str, Any]:
    layers: list[dict[str, Any]] = desc["layers"]
    for layer in layers:
        if layer["id"] == layer_id:
            return layer
    ids = ", ".join(layer["id"] for layer in layers)
    raise LanternaInputError(where, f"no layer {layer_id!r} (layers: {ids})")


def _previous_levels(layer: Mapping[str, Any]) -> dict[int, dict[str, Any]]:
    overlay = layer.get("overlay")
    if not isinstance(overlay, dict):
        return {}
    return {int(e["level"]): e for e in overlay.get("levels", [])
            if isinstance(e, dict) and isinstance(e.get("image"), str)}


def _pyramid_of(dataset_dir: Path, image: str) -> tuple[int, int]:
    """Return the deepest level and the tile size of a stored image's pyramid."""
    path = dataset_dir / "iiif" / image / "info.json"
    try:
        tiles = json.loads(path.read_text())["tiles"][0]
        return og.max_level(tiles["scaleFactors"]), int(tiles["width"])
    except (OSError, ValueError, KeyError, IndexError, TypeError):
        raise LanternaInputError(path, "cannot read the layer's pyramid") from None


def _factors(width: int, height: int, tile_size: int) -> list[int]:
    from .iiif_geometry import scale_factors

    return scale_factors(width, height, tile_size)
