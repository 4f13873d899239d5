"""Write a dataset atomically: images, layer service documents, lanterna.json, manifest.

Everything goes to a temporary folder beside the target, published in one atomic step only when
complete (:mod:`.publish`), so a failure (bad input, a full disk, Ctrl-C, ``kill -9``) leaves the
previous dataset in place and nothing half-written. Writers hold the dataset's lock
(:mod:`.lock`) from their first read to the publish, so two never overwrite each other's work.
"""

from __future__ import annotations

import json
import math
import os
import re
import shutil
from collections.abc import Iterator, Mapping
from contextlib import ExitStack, contextmanager
from pathlib import Path
from types import TracebackType
from typing import Any

import numpy as np
import numpy.typing as npt
import pyvips

from lanterna.errors import LanternaInputError
from lanterna.manifests.annotation_page import annotation_documents
from lanterna.manifests.build import build_manifest
from lanterna.manifests.metadata import check_publication
from lanterna.manifests.services import with_plane_descriptions
from lanterna.tiler.iiif.encoding import TileFormat, tile_format
from lanterna.tiler.iiif.pyramid import vips_from_array, write_pyramid
from lanterna.tiler.iiif.tiff import write_tiff

from .output import json_text, write_errors
from .publish import new_temp, publish, writing

DEFAULT_BASE_URL = "http://127.0.0.1:8000/datasets"
RELIGHT_TYPE = "LanternaRelight"
RELIGHT_PROFILE = "urn:lanterna:relight:1"
FORMAT_VERSION = 1
#: Layer keys kept in lanterna.json but not in the relight service block.
_NOT_IN_SERVICE = ("id", "label", "body", "overlay")
_ID = re.compile(r"^[A-Za-z0-9_-]+$")


def check_identifier(value: str, what: str) -> str:
    """Return ``value`` if it is a safe identifier (``[A-Za-z0-9_-]+``), else raise."""
    if not _ID.match(value):
        raise LanternaInputError(None, f"{what} {value!r} must use only letters, digits, _ and -")
    return value


class DatasetWriter:
    """Build one dataset in a temporary folder; publish it at ``out`` on a clean exit.

    Use as a context manager::

        with DatasetWriter(out, name="ushabti", label="Ushabti", width=w, height=h) as ds:
            svc = ds.add_image("ptm_c0", planes, fmt="png")
            ds.add_layer({...})
    """

    def __init__(self, out: Path, *, name: str, label: str, width: int, height: int,
                 base_url: str = DEFAULT_BASE_URL, tile_size: int = 256,
                 source: str | None = None, force: bool = False,
                 summary: str | None = None, quality: dict[str, Any] | None = None,
                 tiff: bool = False, pixel_size_mm: float | None = None,
                 presets: dict[str, Any] | None = None,
                 publication: Mapping[str, Any] | None = None) -> None:
        self.out = Path(out)
        self.name = check_identifier(name, "dataset name")
        self.label = label
        self.width, self.height = width, height
        self.base_url = base_url.rstrip("/")
        self.tile_size = tile_size
        self.source = source
        self.summary = summary
        self.quality = quality
        self.force = force
        self.tiff = tiff
        self.pixel_size_mm = check_pixel_size(pixel_size_mm)
        self.presets = presets
        #: rights, attribution, provider, links, metadata (lanterna.manifests.metadata)
        self.publication = check_publication(publication)
        self.images: dict[str, dict[str, Any]] = {}
        self.layers: list[dict[str, Any]] = []
        self._shared: dict[str, str] = {}
        self._tmp: Path | None = None
        self._held = ExitStack()

    # -- context manager -------------------------------------------------------------------
    def __enter__(self) -> DatasetWriter:
        with write_errors(self.out):
            self.out.parent.mkdir(parents=True, exist_ok=True)
        with ExitStack() as held:
            held.enter_context(writing(self.out))
            if self.out.exists() and not self.force:
                raise LanternaInputError(self.out, "output exists (use --force to replace it)")
            self._tmp = new_temp(self.out)
            self._held = held.pop_all()  # the lock stays held until __exit__
        return self

    def __exit__(self, exc_type: type[BaseException] | None, exc: BaseException | None,
                 tb: TracebackType | None) -> None:
        assert self._tmp is not None
        try:
            if exc_type is None:
                self._finish()
        finally:
            shutil.rmtree(self._tmp, ignore_errors=True)
            self._held.close()

    # -- building --------------------------------------------------------------------------
    @property
    def dataset_url(self) -> str:
        return f"{self.base_url}/{self.name}"

    def add_image(self, identifier: str, image: npt.NDArray[np.uint8] | pyvips.Image, *,
                  fmt: str | TileFormat = "png", share_key: str | None = None,
                  size: tuple[int, int] | None = None) -> dict[str, Any]:
        """Tile ``image`` as IIIF image ``identifier``; return its ``ImageService3`` reference.

        Images given the same ``share_key`` (e.g. the resolved path of a normal map used by several
        layers) are stored and served once: later calls return the first image's service.
        ``size`` is the expected ``(width, height)`` when it is not the canvas's (overlay levels).
        With ``tiff=True`` the image is also written as ``tiff/<identifier>.tif``, a pyramidal
        TIFF for the IIIF image server (recorded as the image's ``tiff`` field). ``fmt`` is the
        tiles' format (:mod:`lanterna.tiler.iiif.encoding`), recorded as the image's ``format``
        (and ``quality`` when it has one).
        """
        assert self._tmp is not None, "use DatasetWriter as a context manager"
        shared = self.shared_image(share_key)
        if shared is not None:
            return self._service(shared)
        check_identifier(identifier, "image identifier")
        if identifier in self.images:
            raise LanternaInputError(self.source, f"image id {identifier!r} is used twice "
                                     "(two layers' ids clash)")
        vimg = vips_from_array(image) if isinstance(image, np.ndarray) else image
        want_w, want_h = size or (self.width, self.height)
        if (vimg.width, vimg.height) != (want_w, want_h):
            what = "the dataset is" if size is None else "expected"
            raise LanternaInputError(self.source, f"image {identifier} is {vimg.width}x"
                                     f"{vimg.height}, {what} {want_w}x{want_h}")
        service_id = f"{self.dataset_url}/iiif/{identifier}"
        with write_errors(self.out):
            (self._tmp / "iiif").mkdir(exist_ok=True)
            info = write_pyramid(vimg, self._tmp / "iiif" / identifier, service_id, fmt=fmt,
                                 tile_size=self.tile_size)
        tf = tile_format(fmt)
        self.images[identifier] = {"format": tf.ext, "width": vimg.width, "height": vimg.height,
                                   "bands": vimg.bands}
        if tf.quality is not None:
            self.images[identifier]["quality"] = tf.quality
        if "maxWidth" in info:  # full/max is a reduced level (large images)
            self.images[identifier].update(maxWidth=info["maxWidth"], maxHeight=info["maxHeight"])
        if self.tiff:
            with write_errors(self.out):
                (self._tmp / "tiff").mkdir(exist_ok=True)
                write_tiff(vimg, self._tmp / "tiff" / f"{identifier}.tif", fmt=fmt)
            self.images[identifier]["tiff"] = f"tiff/{identifier}.tif"
        if share_key is not None:
            self._shared[share_key] = identifier
        return self._service(identifier)

    def shared_image(self, share_key: str | None) -> str | None:
        """The identifier of the image already stored under ``share_key``, if any."""
        return None if share_key is None else self._shared.get(share_key)

    def _service(self, identifier: str) -> dict[str, Any]:
        return {"id": f"{self.dataset_url}/iiif/{identifier}", "type": "ImageService3",
                "profile": "level0"}

    def add_layer(self, layer: dict[str, Any]) -> None:
        """Add a layer: ``{"id", "label", "layerType", "body": image id, ...relight fields}``."""
        check_identifier(layer["id"], "layer id")
        if any(other["id"] == layer["id"] for other in self.layers):
            raise LanternaInputError(self.source, f"layer id {layer['id']!r} is used twice")
        if layer["body"] not in self.images:
            raise ValueError(f"layer body image {layer['body']!r} was not added")
        self.layers.append(layer)

    def layer_service(self, layer: dict[str, Any]) -> dict[str, Any]:
        """Return the relight service block of ``layer`` (see docs/dataset-format.md)."""
        block = {"id": f"{self.dataset_url}/layers/{layer['id']}.json", "type": RELIGHT_TYPE,
                 "profile": RELIGHT_PROFILE, "width": self.width, "height": self.height}
        block.update({k: v for k, v in layer.items() if k not in _NOT_IN_SERVICE})
        return block

    def description(self) -> dict[str, Any]:
        """Return the ``lanterna.json`` document."""
        return {
            "lanterna": FORMAT_VERSION,
            "name": self.name,
            "label": self.label,
            "width": self.width,
            "height": self.height,
            "baseUrl": self.base_url,
            "source": self.source,
            **({"summary": self.summary} if self.summary else {}),
            **({"quality": self.quality} if self.quality else {}),
            **({"pixelSizeMM": self.pixel_size_mm} if self.pixel_size_mm else {}),
            **({"publication": self.publication} if self.publication else {}),
            "images": self.images,
            "layers": [
                {"id": layer["id"], "label": layer["label"], "body": layer["body"],
                 "service": self.layer_service(layer),
                 **({"overlay": layer["overlay"]} if "overlay" in layer else {})}
                for layer in self.layers
            ],
            **({"presets": self.presets} if self.presets else {}),
        }

    def _finish(self) -> None:
        assert self._tmp is not None
        if not self.layers:
            raise ValueError("a dataset needs at least one layer")
        with write_errors(self.out):
            write_documents(self._tmp, self.description(), self.out)
            publish(self._tmp, self.out)


def check_pixel_size(mm: float | None) -> float | None:
    """Return ``mm``, the physical size of a pixel (``--pixel-size``), if positive; else raise."""
    if mm is None:
        return None
    if not (isinstance(mm, int | float) and math.isfinite(mm) and mm > 0):
        raise LanternaInputError(None, f"--pixel-size must be a positive number of millimetres, "
                                 f"not {mm!r}")
    return float(mm)


def write_documents(folder: Path, desc: dict[str, Any], out: Path) -> None:
    """Write ``desc`` as ``layers/*.json``, ``lanterna.json``, ``manifest.json`` in folder, its
    preset library (``presets``) as ``presets.json`` (removed when there is none), and the W3C
    annotations of the layers' published patches (:func:`write_annotations`).

    ``folder`` becomes the dataset ``out``: a number that is not finite is a one-line error
    naming the file in ``out`` (see :func:`~.output.json_text`). The manifest and the layer
    documents embed each image's description, read from its ``info.json`` in ``folder``
    (:mod:`lanterna.manifests.services`); ``lanterna.json`` keeps the bare references.
    """
    infos = image_infos(folder, desc, out)
    ds_url = f"{desc['baseUrl'].rstrip('/')}/{desc['name']}"
    (folder / "layers").mkdir(exist_ok=True)
    for layer in desc["layers"]:
        name = f"layers/{layer['id']}.json"
        _write_json(folder / name, with_plane_descriptions(layer["service"], ds_url, infos),
                    out / name)
    if desc.get("presets"):
        _write_json(folder / "presets.json", desc["presets"], out / "presets.json")
    else:
        (folder / "presets.json").unlink(missing_ok=True)
    _write_json(folder / "lanterna.json", desc, out / "lanterna.json")
    _write_json(folder / "manifest.json", build_manifest(desc, infos), out / "manifest.json")
    write_annotations(folder, desc, out)


def write_annotations(folder: Path, desc: dict[str, Any], out: Path) -> None:
    """Write ``annotations/LAYER.json`` and ``annotations/LAYER/{id}.json`` for every layer with
    published patches (:mod:`lanterna.manifests.annotation_page`); remove the stale ones.

    Stale: a ``.json`` of ``annotations/`` that is not one of these documents, and the folder of
    a layer that has no published patches (its patch images with it).
    """
    docs = annotation_documents(desc)
    root = folder / "annotations"
    if root.is_dir():
        for path in sorted(root.rglob("*.json")):
            if path.relative_to(folder).as_posix() not in docs:
                path.unlink()
        for sub in sorted(p for p in root.iterdir() if p.is_dir()):
            if f"annotations/{sub.name}.json" not in docs:
                shutil.rmtree(sub)
    for rel, doc in docs.items():
        (folder / rel).parent.mkdir(parents=True, exist_ok=True)
        _write_json(folder / rel, doc, out / rel)
    if root.is_dir() and not any(root.iterdir()):
        root.rmdir()


def image_infos(folder: Path, desc: dict[str, Any], out: Path) -> dict[str, dict[str, Any]]:
    """The ``info.json`` of every image of ``desc`` found in ``folder``, by image id.

    An image whose info.json is missing is left out (its services stay bare references); one
    that is not a JSON object is a one-line error naming the file in ``out``.
    """
    infos: dict[str, dict[str, Any]] = {}
    for image in desc.get("images", {}):
        path = folder / "iiif" / image / "info.json"
        try:
            text = path.read_text()
        except FileNotFoundError:
            continue
        try:
            info = json.loads(text)
        except ValueError as err:
            raise LanternaInputError(out / "iiif" / image / "info.json",
                                     f"not valid JSON ({err})") from None
        if not isinstance(info, dict):
            raise LanternaInputError(out / "iiif" / image / "info.json", "not a JSON object")
        infos[image] = info
    return infos


@contextmanager
def rewriting(out: Path) -> Iterator[tuple[Path, dict[str, Any]]]:
    """Rewrite the existing dataset ``out`` atomically; yield ``(folder, description)``.

    Holds the dataset's lock throughout (callers that read the dataset before deciding what to
    change take it first, with :func:`~.publish.writing`). The current version is copied into a
    temporary folder beside it (files hard-linked, so unchanged tiles cost nothing; files are
    only ever replaced, never written through a link). The caller changes the copy and the
    description in place; on a clean exit the documents (``lanterna.json``, ``layers/*.json``,
    ``manifest.json``) are regenerated from the description and the copy is published as the
    next version. On an error the copy is removed and ``out`` is untouched.
    """
    out = Path(out)
    with writing(out):
        desc = read_description(out)
        tmp = new_temp(out)
        try:
            with write_errors(out):
                shutil.copytree(os.path.realpath(out), tmp, dirs_exist_ok=True,
                                copy_function=link_or_copy)
                yield tmp, desc
                write_documents(tmp, desc, out)
                publish(tmp, out)
        finally:
            shutil.rmtree(tmp, ignore_errors=True)


def read_description(dataset: Path) -> dict[str, Any]:
    """Read a dataset's ``lanterna.json`` with a one-line error if it is not a dataset."""
    path = Path(dataset) / "lanterna.json"
    try:
        desc = json.loads(path.read_text())
    except OSError:
        raise LanternaInputError(dataset, "not a Lanterna dataset (no lanterna.json)") from None
    except ValueError as err:
        raise LanternaInputError(path, f"not valid JSON ({err})") from None
    if not isinstance(desc, dict) or desc.get("lanterna") != FORMAT_VERSION:
        raise LanternaInputError(path, f"not a version-{FORMAT_VERSION} dataset description")
    return desc


def link_or_copy(src: str | Path, dst: str | Path) -> bool:
    """Hard-link ``src`` at ``dst``; copy it when that is impossible. True if linked."""
    try:
        os.link(src, dst)
        return True
    except OSError:
        shutil.copy2(src, dst)
        return False


def _write_json(path: Path, doc: dict[str, Any], shown: Path) -> None:
    # Write a new file and rename it over the old one: ``path`` may be a hard link shared with
    # the published dataset (see ``rewriting``), which must not change.
    part = path.with_name(path.name + ".part")
    part.write_text(json_text(doc, shown) + "\n")
    os.replace(part, path)
