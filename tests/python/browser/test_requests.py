"""The requests the viewer makes to show a dataset, counted in real Chromium.

The manifest embeds each plane image's description (size, tiles, sizes), so no ``info.json`` is
fetched before the tiles; a manifest without them still opens, through ``info.json``. An image
that fits one tile costs one request per plane group; a small image loaded by whole levels
(``wholeLevelMaxSide``) costs one request per level and plane group, and its pixels are the numpy
relight of the very ``full/w,h`` files the page fetched.
"""

from __future__ import annotations

import json
import re
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np
import numpy.typing as npt
import pytest
import pyvips

from lanterna.tiler.dataset.layers import add_ptm_layer
from lanterna.tiler.dataset.writer import DatasetWriter
from lanterna.tiler.formats.ptm_model import ptm_weights
from lanterna.tiler.iiif import geometry as geo
from tests.python.fixtures.browser import Shot, render
from tests.python.fixtures.manifests import without_descriptions
from tests.python.fixtures.ptm import random_ptm_of_size
from tests.python.fixtures.ptm_relight import TOLERANCE
from tests.python.fixtures.servers import LiveServer
from tests.python.fixtures.stored import stored_format

pytestmark = pytest.mark.browser

#: A plane request: ``…/iiif/{image}/{region}/{size}/0/default.{fmt}``.
PLANE_URL = re.compile(
    r"/iiif/(?P<image>[A-Za-z0-9_-]+)/(?P<region>[^/]+)/(?P<size>[^/]+)/0/default\.\w+$")
LIGHT = (-0.4, 0.3)


def _dataset(root: Path, width: int, height: int) -> dict[str, Any]:
    with DatasetWriter(root / "obj", name="obj", label="PTM", width=width, height=height) as ds:
        return add_ptm_layer(ds, random_ptm_of_size(width, height, "lrgb", seed=3))


def _open(server: LiveServer, folder: Path, region: tuple[int, int, int, int],
          viewport: tuple[int, int], query: str = "",
          routes: list[dict[str, Any]] | None = None) -> tuple[npt.NDArray[np.uint8], list[str]]:
    """Open the dataset, show ``region``; return the frame and every URL the page requested."""
    url = f"{server.url}/viewer/?manifest={server.url}/datasets/obj/manifest.json{query}"
    result = folder / "result.json"
    (frame,) = render(url, [Shot(LIGHT, region, folder / "shot.rgba")], viewport=viewport,
                      options={"result": str(result), "routes": routes or []})
    requests: list[str] = json.loads(result.read_text())["requests"]
    return frame, requests


def _planes(requests: list[str]) -> list[re.Match[str]]:
    return [m for m in (PLANE_URL.search(u) for u in requests) if m]


def _group_ids(layer: dict[str, Any]) -> list[str]:
    return [p["service"]["id"].rsplit("/", 1)[1] for p in layer["planes"]]


def _relight(layer: dict[str, Any],
             level: dict[str, npt.NDArray[np.uint8]]) -> npt.NDArray[np.int16]:
    """The documented lrgb PTM maths (docs/dataset-format.md) on one level's plane images."""
    channels: dict[str, npt.NDArray[np.float32]] = {}
    for plane, ident in zip(layer["planes"], _group_ids(layer), strict=True):
        px = level[ident].astype(np.float32) / 255.0
        for k, name in enumerate(plane["channels"]):
            channels[name] = (px[..., k] - np.float32(plane["bias"][k])) * np.float32(
                plane["scale"][k])
    w = ptm_weights(*LIGHT).astype(np.float32)
    lum = sum(channels[f"L{k}"] * w[k] for k in range(6))
    out = np.clip(np.stack([channels[c] * lum for c in "RGB"], axis=-1), 0.0, 1.0)
    return np.round(out * 255.0).astype(np.int16)


def _read(path: Path) -> npt.NDArray[np.uint8]:
    """A stored plane file, in the tile format its image was written in (``default.*``)."""
    image_dir = next(p for p in path.parents if p.parent.name == "iiif")
    fmt = stored_format(image_dir.parent.parent, image_dir.name)
    px: npt.NDArray[np.uint8] = pyvips.Image.new_from_file(
        str(path.with_suffix(f".{fmt}"))).numpy()
    return px


def _tiled_level(image_dir: Path, width: int, height: int) -> npt.NDArray[np.uint8]:
    """Level 0 of a stored pyramid assembled from its 256² tile files."""
    out = np.zeros((height, width, 3), np.uint8)
    for t in geo.spec_tiles(width, height, 256, 1):
        px = _read(image_dir / geo.canonical_path(width, height, t) / "0" / "default.png")
        out[t.y: t.y + t.sh, t.x: t.x + t.sw] = px
    return out


def _assert_frame(frame: npt.NDArray[np.uint8], expected: npt.NDArray[np.int16], what: str) -> None:
    got = frame[: expected.shape[0], : expected.shape[1], :3].astype(np.int16)
    assert got.shape == expected.shape, what
    diff = np.abs(got - expected).max(axis=-1)
    bad = int((diff > TOLERANCE).sum())
    assert bad == 0, f"{what}: {bad} pixels off by up to {diff.max()}"
    assert expected.std() > 10, "the reference must not be a flat image"


def test_no_info_json_request_when_the_manifest_embeds_the_descriptions(
        tmp_path: Path, live_server: Callable[[Path], LiveServer]) -> None:
    w, h = 600, 400
    layer = _dataset(tmp_path / "root", w, h)
    server = live_server(tmp_path / "root")
    frame, requests = _open(server, tmp_path, (0, 0, w, h), (w, h))
    assert not [u for u in requests if u.endswith("info.json")], requests
    planes = _planes(requests)
    assert {m["image"] for m in planes} == set(_group_ids(layer))
    # tiles: a whole image only for the coarsest level, which fits one tile
    assert {m["size"] for m in planes if m["region"] == "full"} <= {"150,100"}
    assert any(m["region"] != "full" for m in planes)
    ds = tmp_path / "root" / "obj"
    level = {i: _tiled_level(ds / "iiif" / i, w, h) for i in _group_ids(layer)}
    _assert_frame(frame, _relight(layer, level), "embedded descriptions, tiles")


def test_a_manifest_without_descriptions_opens_through_info_json(
        tmp_path: Path, live_server: Callable[[Path], LiveServer]) -> None:
    w, h = 600, 400
    layer = _dataset(tmp_path / "root", w, h)
    ds = tmp_path / "root" / "obj"
    server = live_server(tmp_path / "root")
    manifest_url = f"{server.url}/datasets/obj/manifest.json"
    served = json.loads((ds / "manifest.json").read_text().replace(
        "http://127.0.0.1:8000/datasets", f"{server.url}/datasets"))
    bare = without_descriptions(served)
    assert "tiles" not in json.dumps(bare) and "LanternaRelight" in json.dumps(bare)
    route = {"match": f"^{re.escape(manifest_url)}$", "status": 200, "body": json.dumps(bare),
             "contentType": "application/json"}
    frame, requests = _open(server, tmp_path, (0, 0, w, h), (w, h), routes=[route])
    infos = sorted(u for u in requests if u.endswith("info.json"))
    assert infos == sorted(f"{server.url}/datasets/obj/iiif/{i}/info.json"
                           for i in _group_ids(layer)), "one info.json per plane group, once"
    level = {i: _tiled_level(ds / "iiif" / i, w, h) for i in _group_ids(layer)}
    _assert_frame(frame, _relight(layer, level), "info.json descriptions, tiles")


def test_a_one_tile_image_costs_one_request_per_plane_group(
        tmp_path: Path, live_server: Callable[[Path], LiveServer]) -> None:
    w, h = 200, 150  # one 256² tile: one level
    layer = _dataset(tmp_path / "root", w, h)
    server = live_server(tmp_path / "root")
    frame, requests = _open(server, tmp_path, (0, 0, w, h), (w, h), query="&wholeLevelMaxSide=1024")
    data = [u for u in requests if u.startswith(f"{server.url}/datasets/")]
    planes = _planes(data)
    assert sorted(m["image"] for m in planes) == sorted(_group_ids(layer)), data
    assert len(data) == 1 + len(planes), f"the manifest and one request per plane group: {data}"
    ds = tmp_path / "root" / "obj"
    level = {m["image"]: _read(ds / "iiif" / m["image"] / m["region"] / m["size"] / "0/default.png")
             for m in planes}
    _assert_frame(frame, _relight(layer, level), "one-tile image")


def test_a_small_image_loads_one_whole_image_per_level_and_plane_group(
        tmp_path: Path, live_server: Callable[[Path], LiveServer]) -> None:
    w, h = 640, 480  # tiled: 6 tiles at level 0, 2 at level 1, 1 at level 2
    layer = _dataset(tmp_path / "root", w, h)
    server = live_server(tmp_path / "root")
    ds = tmp_path / "root" / "obj"
    url = (f"{server.url}/viewer/?manifest={server.url}/datasets/obj/manifest.json"
           "&wholeLevelMaxSide=1024")
    result = tmp_path / "result.json"
    # the home view (1:1), then zoomed out to 1:2
    shots = [Shot(LIGHT, (0, 0, w, h), tmp_path / "home.rgba"),
             Shot(LIGHT, (0, 0, 2 * w, 2 * h), tmp_path / "half.rgba")]
    home, half = render(url, shots, viewport=(w, h), options={"result": str(result)})
    requests: list[str] = json.loads(result.read_text())["requests"]
    assert not [u for u in requests if u.endswith("info.json")]
    planes = _planes(requests)
    assert planes and all(m["region"] == "full" for m in planes), requests
    groups = _group_ids(layer)
    # opening costs one request per plane group: the level the view needs, as one whole image
    opening = _planes([u for u in requests if u not in set(shots[1].meta()["requests"])])
    assert sorted((m["image"], m["size"]) for m in opening) == sorted((i, "max") for i in groups)
    level = {i: _read(ds / "iiif" / i / "full/max/0/default.png") for i in groups}
    _assert_frame(home, _relight(layer, level), "whole levels, level 0")
    # zooming out fetches the coarser levels' whole images, once each, and draws level 1 from them
    zoomed = _planes(shots[1].meta()["requests"])
    for ident in groups:
        sizes = sorted(m["size"] for m in zoomed if m["image"] == ident)
        assert "320,240" in sizes and set(sizes) <= {"320,240", "160,120"}, (ident, sizes)
        assert len(sizes) == len(set(sizes)), (ident, sizes)
    level = {i: _read(ds / "iiif" / i / "full/320,240/0/default.png") for i in groups}
    _assert_frame(half, _relight(layer, level), "whole levels, level 1")
