"""``lanterna fit``: image sets (one, or one per spectral band) to the layers of one dataset.

Everything is read and checked first (light files, image headers and sizes, fusion lights), then
each set is fitted in one streamed pass (:func:`~lanterna.tiler.fit.engine.fit_stream`) into a
scratch folder, and the dataset is written atomically (:func:`~lanterna.tiler.dataset.plan.
build_dataset`): bad input leaves nothing behind.  See ``docs/fitting.md``.
"""

from __future__ import annotations

import contextlib
import re
import tempfile
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import numpy.typing as npt

from lanterna.errors import LanternaInputError
from lanterna.tiler.dataset.layers import add_planes_layer
from lanterna.tiler.dataset.output import write_errors
from lanterna.tiler.dataset.plan import LayerPlan, build_dataset
from lanterna.tiler.dataset.plane_format import AUTO, PlaneFormat
from lanterna.tiler.dataset.publish import writing
from lanterna.tiler.dataset.writer import DEFAULT_BASE_URL
from lanterna.tiler.formats.planes import PlaneLayer
from lanterna.tiler.inputs.lp import read_lp
from lanterna.tiler.inputs.raw import is_raw, raw_to_tiff
from lanterna.tiler.inputs.stack import StackReader, to_tiled_tiff
from lanterna.tiler.progress import Progress

from .bands import luminance
from .cluster import DaskRunner
from .engine import fit_stream
from .held_out import REPORT_PIXELS
from .models import HOLDOUT_EVERY, model_table
from .pca import PCA_LABELS
from .pca_band import pca_models
from .row_bands import auto_band_rows

#: Largest memory the open decoders of a collection may hold before the images are re-encoded
#: as tiled TIFFs (:meth:`~lanterna.tiler.inputs.stack.StackReader.decoder_bytes`).
DECODER_BUDGET = 512 << 20

#: Makes a progress reporter: ``(label, total[, unit])``.
ProgressFactory = Callable[..., Progress]


@dataclass(frozen=True)
class ImageSet:
    """One multi-light collection: a band name (``None`` for a plain RGB set), images, lights."""

    name: str | None
    images_dir: Path
    lp: Path


class FusionStack:
    """Three co-lit bands as one RGB stack: channel c = the luminance of band c's image.

    Looks like a :class:`~lanterna.tiler.inputs.stack.StackReader` to :func:`fit_stream`
    (``shape``, ``[:, y0:y1]``), so any model fits a false-colour fusion.
    """

    dtype = np.dtype(np.float32)
    ndim = 4

    def __init__(self, bands: Sequence[StackReader]) -> None:
        self.bands = list(bands)
        self.shape = self.bands[0].shape

    def close(self) -> None:
        """Release the bands' decoders."""
        for band in self.bands:
            band.close()

    def __getitem__(self, key: Any) -> npt.NDArray[np.float32]:
        if not (isinstance(key, tuple) and len(key) == 2 and key[0] == slice(None)):
            raise TypeError(f"FusionStack supports [:, y0:y1] only, not {key!r}")
        out: npt.NDArray[np.float32] = np.stack(
            [luminance(np.asarray(band[key], np.float32)) for band in self.bands], axis=-1)
        return out


def _slug(name: str) -> str:
    return re.sub(r"[^a-z0-9]+", "_", name.lower()).strip("_") or "band"


def fit_collection(images_dir: Path, lp: Path, models: Sequence[str], out: Path,
                   **options: Any) -> dict[str, Any]:
    """Fit one collection (``IMAGES_DIR`` + ``LIGHTS.lp``); see :func:`fit_sets`."""
    return fit_sets([ImageSet(None, Path(images_dir), Path(lp))], models, out, **options)


def fit_sets(sets: Sequence[ImageSet], models: Sequence[str], out: Path, *,
             fusions: Sequence[tuple[str, str, str]] = (), terms: int = 9,
             name: str | None = None, label: str | None = None,
             base_url: str = DEFAULT_BASE_URL, tile_size: int = 256, force: bool = False,
             band_rows: int | None = None, tiff: bool = False, scratch: Path | None = None,
             fit_space: str = "stored", scheduler: str | None = None,
             plane_format: PlaneFormat = AUTO,
             report: Callable[[str], None] = lambda _: None,
             progress: ProgressFactory | None = None,
             pixel_size_mm: float | None = None, planes: object = None,
             colorspace: object = None, summary: str | None = None,
             publication: Mapping[str, Any] | None = None) -> dict[str, Any]:
    """Fit ``models`` to every image set (and fusion) and write them as one dataset ``out``.

    One set without a name gives layers named by model (``ptm``, ``hsh9``, …); named sets
    (spectral bands) give ``{band}_{model}`` layers, and each fusion ``(A, B, C)`` of three
    bands taken under the same lights a false-colour ``fc_{a}_{b}_{c}_{model}`` layer fitted to
    the stack whose R, G, B are the luminances of A, B, C.  Camera RAW files are decoded once
    into the scratch folder (:mod:`~lanterna.tiler.inputs.raw`).  ``fit_space`` is ``"stored"``
    (values as stored, the RTI convention) or ``"linear"`` (the photometric models fit
    linear light).  ``scheduler`` (a Dask scheduler address, or ``local[:N]``) solves the row
    bands on that cluster (:mod:`~lanterna.tiler.fit.cluster`), with the same result.
    ``plane_format`` (``--plane-format``) is the planes' tile format (fitted planes are a
    lossless source: ``auto`` stores the smaller of PNG and lossless WebP).  ``planes`` and
    ``colorspace`` (``--planes``, ``--colorspace``) shape the PCA bases ``rbf``/``bilinear``
    (:mod:`~lanterna.tiler.fit.pca`; a basis sampling pass precedes the fitting pass).  Returns
    the quality report (also stored as ``quality``).
    """
    if (planes is not None or colorspace is not None) and not set(models) & set(PCA_LABELS):
        flag = "--planes" if planes is not None else "--colorspace"
        raise LanternaInputError(None, f"{flag} applies to --model rbf or bilinear only")
    table = model_table(terms, band_rows, planes=planes, colorspace=colorspace)
    unknown = [m for m in models if m not in table]
    if unknown or not models:
        raise LanternaInputError(None, f"unknown model(s) {', '.join(unknown) or '(none)'}; "
                                 f"expected {', '.join(table)}")
    if fit_space not in ("stored", "linear"):
        raise LanternaInputError(None, f"--fit-space must be stored or linear, not {fit_space}")
    if band_rows is not None and band_rows < 1:
        raise LanternaInputError(None, f"--band-rows must be at least 1, got {band_rows}")
    keys = list(dict.fromkeys(models))
    engine_keys = [k for k in keys if table[k].pca is None]
    names = [s.name for s in sets]
    if len(sets) > 1 and None in names:
        raise LanternaInputError(None, "several image sets need a band name each")
    if len(set(names)) != len(names):
        raise LanternaInputError(None, f"band names must be unique: {names}")
    by_name = {s.name: s for s in sets}
    for fusion in fusions:
        missing = [b for b in fusion if b not in by_name]
        if len(fusion) != 3 or missing:
            raise LanternaInputError(None, f"--fusion {','.join(fusion)}: needs three of the "
                                     f"bands {', '.join(str(n) for n in names)}")
    out = Path(out)
    parent = Path(scratch) if scratch else out.parent
    with write_errors(out):
        out.parent.mkdir(parents=True, exist_ok=True)
        parent.mkdir(parents=True, exist_ok=True)
    with contextlib.ExitStack() as stack_:
        # the dataset's lock for the whole run, so that the scratch folder beside it (named as
        # the dataset's temporary folders are) is cleared by the next write if this one is killed
        stack_.enter_context(writing(out))
        if out.exists() and not force:  # say so now, not after the fit
            raise LanternaInputError(out, "output exists (use --force to replace it)")
        tmp = stack_.enter_context(tempfile.TemporaryDirectory(
            prefix=".lanterna-fit-" if scratch else f".{out.name}.tmp-", dir=parent))
        runner = stack_.enter_context(DaskRunner(scheduler)) if scheduler else None
        inputs = {s.name: _open_set(s, Path(tmp), progress) for s in sets}
        size = next(iter(inputs.values()))[0].shape[1:3]
        for s in sets:
            if inputs[s.name][0].shape[1:3] != size:
                raise LanternaInputError(s.images_dir, "images are "
                                         f"{inputs[s.name][0].shape[2]}x"
                                         f"{inputs[s.name][0].shape[1]}, other bands "
                                         f"{size[1]}x{size[0]}: bands must be co-registered")
        jobs: list[tuple[str, str, Any, npt.NDArray[np.float64], str, Path]] = []
        for s in sets:
            stack, lights = inputs[s.name]
            prefix = "" if s.name is None else f"{_slug(s.name)}_"
            tag = "" if s.name is None else f"{s.name}: "
            jobs.append((prefix, tag, stack, lights, f"{s.images_dir.name} + {s.lp.name}", s.lp))
        for fusion in fusions:
            lights = inputs[fusion[0]][1]
            for b in fusion[1:]:
                other = inputs[b][1]
                if other.shape != lights.shape or not np.allclose(other, lights, atol=1e-6):
                    raise LanternaInputError(by_name[b].lp, f"--fusion {','.join(fusion)}: "
                                             f"band {b} was not taken under the lights of "
                                             f"band {fusion[0]}")
            prefix = "fc_" + "_".join(_slug(b) for b in fusion) + "_"
            tag = f"False colour ({fusion[0]}, {fusion[1]}, {fusion[2]} as R, G, B): "
            jobs.append((prefix, tag, FusionStack([inputs[b][0] for b in fusion]), lights,
                         "fusion of " + ", ".join(fusion), by_name[fusion[0]].lp))
        quality: dict[str, Any] = {"protocol": f"fit without every {HOLDOUT_EVERY}th light "
                                   "(from the first), PSNR of the prediction on those, RGB 0-1; "
                                   "normals and Ward on a fixed pseudo-random sample of about "
                                   f"{REPORT_PIXELS} pixels of larger images ('pixels')",
                                   "models": {}}
        plans = []
        for j, (prefix, tag, stack, lights, source, lp) in enumerate(jobs):
            held = HOLDOUT_EVERY if len(lights) >= 2 * HOLDOUT_EVERY else 0
            folder = Path(tmp) / f"job{j}"
            folder.mkdir()
            if tag:
                report(f"{tag.rstrip(': ')}:")
            try:
                n, _, width, _ = stack.shape
                specs = [spec for k in keys if (spec := table[k].pca) is not None]
                extra = pca_models(stack, lights, specs,
                                   np.arange(0, n, held) if held else np.zeros(0, np.intp),
                                   folder, band_rows=band_rows or auto_band_rows(n, width),
                                   progress=progress)
                result = fit_stream(stack, lights, engine_keys, folder, terms=terms,
                                    band_rows=band_rows, holdout_every=held,
                                    linear=fit_space == "linear", progress=progress,
                                    runner=runner, extra=extra)
            except ValueError as err:
                raise LanternaInputError(lp, f"cannot fit {tag}{err}") from None
            for key in keys:
                model = table[key]
                lid = prefix + model.id
                if key in result.quality:
                    q = result.quality[key]
                    quality["models"][lid] = q
                    on = "" if q["pixels"] == stack.shape[1] * width else \
                        f" (on a sample of {q['pixels']} pixels)"
                    report(f"{lid}: leave-one-out PSNR mean {q['meanPsnr']:.2f} dB, "
                           f"median {q['medianPsnr']:.2f} dB over {len(q['heldOut'])} lights{on}")
                plans.append(_plan(result.layers[key], lid, tag + model.label, source,
                                   plane_format))
        default_label = collection_name(sets[0]) if len(sets) == 1 else Path(out).name
        build_dataset(plans, out, name=name or Path(out).name, label=label or default_label,
                      base_url=base_url, tile_size=tile_size, force=force, quality=quality,
                      tiff=tiff, pixel_size_mm=pixel_size_mm, summary=summary,
                      publication=publication)
    return quality


def collection_name(s: ImageSet) -> str:
    """The name of a collection: the folder of its ``.lp`` file when the images are in it or
    below it (``photos/dirs.lp`` + ``photos/jpg/``: "photos"), else the images' folder."""
    lp_dir, images = Path(s.lp).resolve().parent, Path(s.images_dir).resolve()
    return lp_dir.name if images == lp_dir or lp_dir in images.parents else images.name


def _open_set(s: ImageSet, scratch: Path, progress: ProgressFactory | None
              ) -> tuple[StackReader, npt.NDArray[np.float64]]:
    """Read the light file, decode camera RAW files, check every image header."""
    files, lights = read_lp(s.lp, s.images_dir)
    raw = [is_raw(f) for f in files]
    if any(raw):
        if not all(raw):
            raise LanternaInputError(s.lp, "a collection must not mix camera RAW files with "
                                     "JPEG/PNG/TIFF images")
        bar = (progress(f"decoding RAW {s.name or ''}".strip(), len(files), "images")
               if progress else None)
        decoded = []
        for i, f in enumerate(files):
            decoded.append(raw_to_tiff(f, scratch / "raw", linear=False))
            if bar:
                bar.update(i + 1)
        files = decoded
    reader = StackReader(files)
    if reader.decoder_bytes() > DECODER_BUDGET:
        # wide images: as many open decoders would hold too much; re-encode each (lossless,
        # tiled) so a band can be read file by file with nothing kept between bands
        tiled = scratch / "tiled" / (s.name or "images")
        tiled.mkdir(parents=True, exist_ok=True)
        bar = progress("tiling inputs " + (s.name or ""), len(files), "images") if progress \
            else None
        out = []
        for i, f in enumerate(files):
            out.append(to_tiled_tiff(f, tiled / f"{i:05d}.tif"))
            if bar:
                bar.update(i + 1)
        reader = StackReader(out, reopen=True)
    return reader, lights


def _plan(layer: PlaneLayer, lid: str, label: str, source: str,
          plane_format: PlaneFormat) -> LayerPlan:
    """A dataset layer from fitted planes; a fitted normal map is stored once per dataset."""
    share = {i: f"fitted:{getattr(g.data, 'path', '')}" for i, g in enumerate(layer.groups)
             if layer.group_names[i] == "normals"}
    return LayerPlan(lid, label, layer.width, layer.height, source,
                     lambda ds: add_planes_layer(ds, layer, layer_id=lid, label=label,
                                                 share=share, plane_format=plane_format))
