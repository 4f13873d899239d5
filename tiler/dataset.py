"""Write a dataset folder atomically: images, layer service documents, lanterna.json, manifest.

Everything goes to a temporary folder beside the target, renamed into place only when complete,
so a failure (bad input, a full disk, Ctrl-C) leaves nothing half-written.
"""

from __future__ import annotations

import json
import re
import shutil
import tempfile
from pathlib import Path
from types import TracebackType
from typing import Any

import numpy as np
import numpy.typing as npt
import pyvips

from lanterna.manifests.build import build_manifest

from .errors import LanternaInputError
from .pyramid import vips_from_array, write_pyramid

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
                 summary: str | None = None) -> None:
        self.out = Path(out)
        self.name = check_identifier(name, "dataset name")
        self.label = label
        self.width, self.height = width, height
        self.base_url = base_url.rstrip("/")
        self.tile_size = tile_size
        self.source = source
        self.summary = summary
        self.force = force
        self.images: dict[str, dict[str, Any]] = {}
        self.layers: list[dict[str, Any]] = []
        self._shared: dict[str, str] = {}
        self._tmp: Path | None = None

    # -- context manager -------------------------------------------------------------------
    def __enter__(self) -> DatasetWriter:
        if self.out.exists() and not self.force:
            raise LanternaInputError(self.out, "output exists (use --force to replace it)")
        self.out.parent.mkdir(parents=True, exist_ok=True)
        self._tmp = Path(tempfile.mkdtemp(prefix=f".{self.out.name}.tmp-", dir=self.out.parent))
        self._tmp.chmod(0o755)  # mkdtemp makes it private; the published dataset is public
        return self

    def __exit__(self, exc_type: type[BaseException] | None, exc: BaseException | None,
                 tb: TracebackType | None) -> None:
        assert self._tmp is not None
        try:
            if exc_type is None:
                self._finish()
        finally:
            shutil.rmtree(self._tmp, ignore_errors=True)

    # -- building --------------------------------------------------------------------------
    @property
    def dataset_url(self) -> str:
        return f"{self.base_url}/{self.name}"

    def add_image(self, identifier: str, image: npt.NDArray[np.uint8] | pyvips.Image, *,
                  fmt: str = "png", share_key: str | None = None) -> dict[str, Any]:
        """Tile ``image`` as IIIF image ``identifier``; return its ``ImageService3`` reference.

        Images given the same ``share_key`` (e.g. the resolved path of a normal map used by several
        layers) are stored and served once: later calls return the first image's service.
        """
        assert self._tmp is not None, "use DatasetWriter as a context manager"
        if share_key is not None and share_key in self._shared:
            return self._service(self._shared[share_key])
        check_identifier(identifier, "image identifier")
        if identifier in self.images:
            raise ValueError(f"image {identifier!r} added twice")
        vimg = vips_from_array(image) if isinstance(image, np.ndarray) else image
        if (vimg.width, vimg.height) != (self.width, self.height):
            raise LanternaInputError(self.source, f"image {identifier} is {vimg.width}x"
                                     f"{vimg.height}, the dataset is {self.width}x{self.height}")
        (self._tmp / "iiif").mkdir(exist_ok=True)
        service_id = f"{self.dataset_url}/iiif/{identifier}"
        write_pyramid(vimg, self._tmp / "iiif" / identifier, service_id, fmt=fmt,
                      tile_size=self.tile_size)
        self.images[identifier] = {"format": fmt, "width": vimg.width, "height": vimg.height,
                                   "bands": vimg.bands}
        if share_key is not None:
            self._shared[share_key] = identifier
        return self._service(identifier)

    def _service(self, identifier: str) -> dict[str, Any]:
        return {"id": f"{self.dataset_url}/iiif/{identifier}", "type": "ImageService3",
                "profile": "level0"}

    def add_layer(self, layer: dict[str, Any]) -> None:
        """Add a layer: ``{"id", "label", "layerType", "body": image id, ...relight fields}``."""
        check_identifier(layer["id"], "layer id")
        if any(other["id"] == layer["id"] for other in self.layers):
            raise ValueError(f"layer id {layer['id']!r} added twice")
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
            "images": self.images,
            "layers": [
                {"id": layer["id"], "label": layer["label"], "body": layer["body"],
                 "service": self.layer_service(layer),
                 **({"overlay": layer["overlay"]} if "overlay" in layer else {})}
                for layer in self.layers
            ],
        }

    def _finish(self) -> None:
        assert self._tmp is not None
        if not self.layers:
            raise ValueError("a dataset needs at least one layer")
        desc = self.description()
        (self._tmp / "layers").mkdir()
        for layer in desc["layers"]:
            _write_json(self._tmp / "layers" / f"{layer['id']}.json", layer["service"])
        _write_json(self._tmp / "lanterna.json", desc)
        _write_json(self._tmp / "manifest.json", build_manifest(desc))
        if self.out.exists():
            old = self.out.with_name(f".{self.out.name}.old-{self._tmp.name[-8:]}")
            self.out.rename(old)
            self._tmp.rename(self.out)
            shutil.rmtree(old, ignore_errors=True)
        else:
            self._tmp.rename(self.out)


def _write_json(path: Path, doc: dict[str, Any]) -> None:
    path.write_text(json.dumps(doc, indent=2) + "\n")
