"""The server over versioned datasets: links followed, versions and leftovers never listed or
served by their own names, and a request that lost its version to a republish served anyway."""

from __future__ import annotations

import os
import shutil
from pathlib import Path

import numpy as np
import pytest
import pyvips

from lanterna.server import app as app_mod
from lanterna.server import image_api
from lanterna.server.app import create_app
from lanterna.server.safe_path import contained_file
from lanterna.tiler.dataset.layers import add_image_layer
from lanterna.tiler.dataset.writer import DatasetWriter
from lanterna.tiler.iiif.pyramid import vips_from_array


def _write(out: Path, label: str, value: int) -> None:
    img = vips_from_array(np.full((40, 60, 3), value, np.uint8))
    with DatasetWriter(out, name=out.name, label=label, width=60, height=40, force=True,
                       tiff=True) as ds:
        add_image_layer(ds, img, layer_id="pic", fmt="png")


@pytest.fixture
def root(tmp_path: Path) -> Path:
    root = tmp_path / "root"
    _write(root / "obj", "Linked", 10)
    _write(root / "tmp", "Plain", 20)
    shutil.copytree(root / "tmp", root / "plain")  # as an earlier Lanterna wrote it
    shutil.rmtree(os.path.realpath(root / "tmp"))
    (root / "tmp").unlink()
    for stale in (".obj.old-20250101T000000_abcdef", ".obj.tmp-x1y2z3"):
        shutil.copytree(root / "obj", root / stale)  # half-deleted or killed leftovers
        (root / stale / "lanterna.json").write_text('{"label": "STALE", "baseUrl": "x"}')
    return root


def test_the_index_lists_datasets_and_nothing_hidden(root: Path) -> None:
    page = create_app({"DATA_ROOT": root}).test_client().get("/").get_data(as_text=True)
    assert page.count("<li>") == 2 and "Linked" in page and "Plain" in page
    assert "STALE" not in page and ".obj" not in page


def test_a_version_is_served_through_its_dataset_only(root: Path) -> None:
    client = create_app({"DATA_ROOT": root}).test_client()
    version = os.readlink(root / "obj")
    assert client.get("/datasets/obj/lanterna.json").get_json()["label"] == "Linked"
    with client.get("/datasets/obj/iiif/pic/full/max/0/default.png") as tile:
        assert tile.status_code == 200
    assert client.get("/iiif/3/obj/pic/full/max/0/default.png").status_code == 200
    assert client.get("/datasets/plain/lanterna.json").get_json()["label"] == "Plain"
    for hidden in (version, ".obj.old-20250101T000000_abcdef"):
        assert client.get(f"/datasets/{hidden}/lanterna.json").status_code == 404
        assert client.get(f"/iiif/3/{hidden}/pic/info.json").status_code == 404


def _resolving_first_to(old_version: Path, module: object,
                        monkeypatch: pytest.MonkeyPatch) -> list[str]:
    """Make the first resolution in ``module`` return a file of the removed ``old_version``."""
    calls: list[str] = []

    def resolve(root: Path, relative: str) -> Path | None:
        calls.append(relative)
        if len(calls) == 1:
            return old_version / relative.split("/", 1)[1]
        return contained_file(root, relative)

    monkeypatch.setattr(module, "contained_file", resolve)
    return calls


@pytest.mark.parametrize("path", ["lanterna.json", "iiif/pic/full/max/0/default.png"])
def test_a_file_removed_by_a_republish_is_read_from_the_new_version(
        root: Path, path: str, monkeypatch: pytest.MonkeyPatch) -> None:
    old = Path(os.path.realpath(root / "obj"))
    _write(root / "obj", "Republished", 30)
    assert not old.exists()
    calls = _resolving_first_to(old, app_mod, monkeypatch)
    with create_app({"DATA_ROOT": root}).test_client().get(f"/datasets/obj/{path}") as resp:
        assert resp.status_code == 200 and len(calls) == 2
        if path.endswith(".png"):
            assert resp.data == (Path(os.path.realpath(root / "obj")) / path).read_bytes()
        else:
            assert resp.get_json()["label"] == "Republished"


def test_a_tiff_removed_by_a_republish_is_read_from_the_new_version(
        root: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    old = Path(os.path.realpath(root / "obj"))
    _write(root / "obj", "Republished", 30)
    calls = _resolving_first_to(old, image_api, monkeypatch)
    resp = create_app({"DATA_ROOT": root}).test_client().get(
        "/iiif/3/obj/pic/full/max/0/default.png")
    assert resp.status_code == 200 and len(calls) == 2
    pixels = pyvips.Image.new_from_buffer(resp.data, "").numpy()
    assert pixels.shape == (40, 60, 3) and (pixels == 30).all()


def test_a_document_of_a_version_being_removed_is_read_from_the_new_version(
        root: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    # A version half-way through its removal: its description already gone, its image
    # descriptions not yet. Served from it, info.json would keep its recorded base URL.
    _write(root / "obj", "Republished", 30)
    dying = root / ".obj.v-19990101T000000_abcdef"  # made after the republish, which removes it
    shutil.copytree(os.path.realpath(root / "obj"), dying)
    (dying / "lanterna.json").unlink()
    recorded = (dying / "iiif/pic/info.json").read_text()
    calls = _resolving_first_to(dying, app_mod, monkeypatch)
    resp = create_app({"DATA_ROOT": root}).test_client().get("/datasets/obj/iiif/pic/info.json")
    assert resp.status_code == 200 and len(calls) == 2
    served = resp.get_json()["id"]
    assert served.startswith("http://localhost/datasets/obj/") and served not in recorded
