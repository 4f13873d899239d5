"""Importing W3C AnnotationPages into the patch store, and exporting a layer's page."""

from __future__ import annotations

import json
import os
from pathlib import Path

import numpy as np
import pytest
import pyvips

from lanterna.errors import LanternaInputError
from lanterna.tiler.overlays import store
from lanterna.tiler.overlays.geometry import Patch, destination
from lanterna.tiler.overlays.shape_raster import DEFAULT_STROKE, SAMPLES
from lanterna.tiler.overlays.w3c_import import export_page, import_page
from tests.python.fixtures.overlays import make_dataset, patch, read_image

from . import raster_reference as ref
from .w3c_pages import NOTCH, SHERD, annotorious_page

YELLOW = (255, 204, 0)


@pytest.fixture
def dataset(tmp_path: Path) -> Path:
    return make_dataset(tmp_path / "root")


def _png(path: Path) -> np.ndarray:
    return np.asarray(pyvips.Image.new_from_file(str(path)).numpy())


def _page(tmp_path: Path, doc: object, name: str = "page.json") -> Path:
    path = tmp_path / name
    path.write_text(json.dumps(doc))
    return path


def test_annotorious_polygons_are_stored_as_patches_matching_an_independent_rasterisation(
        dataset: Path, tmp_path: Path) -> None:
    report = import_page(dataset, "vis", _page(tmp_path, annotorious_page()))
    sherd, notch, rect = report.records
    assert [r["order"] for r in report.records] == [0, 1, 2]
    assert report.rebuild is not None and report.rebuild.levels == [0]
    for record, points in ((sherd, SHERD), (notch, NOTCH)):
        stored = _png(store.patch_image(dataset, "vis", record["id"]))
        level = record["level"]
        dest = destination(Patch(level, record["x"], record["y"], record["w"], record["h"],
                                 order=0, info="", file=""))
        half = DEFAULT_STROKE * (1 << level) / 2
        expected = ref.composite([
            (ref.crossing_fill(points, level, dest, SAMPLES) * 0.3, YELLOW),
            (ref.distance_outline(points, True, half, level, dest, SAMPLES), YELLOW)])
        assert stored.shape == expected.shape
        diff = np.abs(stored.astype(float) - expected)
        assert diff[..., 3].max() <= 255 / SAMPLES**2 + 0.5  # one sample of 16, and rounding
        assert diff[..., 3].mean() < 0.5
        assert diff[..., :3][stored[..., 3] > 0].max() <= 0.5
        # the Pillow polygon agrees with the fill too (its own rounding at the border)
        fill = ref.pillow_fill(points, level, dest, SAMPLES)
        inside = stored[..., 3] > 0
        assert np.abs(fill[inside] - ref.crossing_fill(points, level, dest, SAMPLES)[
            inside]).mean() < 0.03
    assert (sherd["short"], sherd["author"], sherd["motivation"]) == (
        "Flaking paint along the rim; flaking", "Ada Conservator", "commenting")
    assert (notch["short"], notch["motivation"]) == ("gilding", "tagging")
    assert (rect["x"], rect["y"], rect["w"], rect["h"], rect["level"]) == (20, 160, 90, 30, 0)
    # the published overlay level is the composite of the three: the patch pixels show in it
    desc = json.loads((dataset / "lanterna.json").read_text())
    level0 = next(e for e in desc["layers"][0]["overlay"]["levels"] if e["level"] == 0)
    over = read_image(dataset, level0["image"])
    stored = _png(store.patch_image(dataset, "vis", rect["id"]))
    assert np.array_equal(over[160:190, 20:110], stored)
    page = json.loads((dataset / "annotations" / "vis.json").read_text())
    assert [a["body"][1]["value"] for a in page["items"]] == [
        "Flaking paint along the rim; flaking", "gilding", "Restored in 1962"]


def _svg_target(value: str) -> dict[str, object]:
    return {"type": "Annotation", "target": {"selector": {"type": "SvgSelector", "value": value}}}


BAD = {
    "not json": "{\"type\": \"AnnotationPage\", \"items\": [",
    "wrong types": {"type": "AnnotationPage", "items": [{"type": "Annotation", "target": 7}]},
    "unknown selector": {"type": "AnnotationPage", "items": [
        {"type": "Annotation", "target": {"selector": {"type": "TextQuoteSelector",
                                                       "value": "x"}}}]},
    "outside": {"type": "AnnotationPage", "items": [
        {"type": "Annotation", "target": "https://x.org/c#xywh=10,10,5,5"},
        _svg_target("<svg><polygon points='700,10 800,10 750,90'/></svg>")]},
    "arcs refused": {"type": "AnnotationPage", "items": [
        _svg_target("<svg><path d='M10,10 A 20 20 0 0 1 50 50'/></svg>")]},
}
WHERE = {"not json": "not valid JSON", "wrong types": "items[0].target: expected a target",
         "unknown selector": "items[0].target: expected a target",
         "outside": "items[1].target.selector.value: the shape (700,10 to 800,90) is outside",
         "arcs refused": "items[0].target.selector.value: <path>: path arcs (A) are not"}


@pytest.mark.parametrize("case", sorted(BAD))
def test_a_bad_page_is_refused_whole_and_nothing_is_written(dataset: Path, tmp_path: Path,
                                                            case: str) -> None:
    doc = BAD[case]
    path = tmp_path / "bad.json"
    path.write_text(doc if isinstance(doc, str) else json.dumps(doc))
    version = os.path.realpath(dataset)
    with pytest.raises(LanternaInputError) as err:
        import_page(dataset, "vis", path)
    assert str(err.value).startswith(f"{path}: {WHERE[case]}")
    assert "\n" not in str(err.value)
    assert not store.store_dir(dataset, "vis").exists()
    assert os.path.realpath(dataset) == version


def test_export_then_import_keeps_rectangles_texts_and_author(dataset: Path,
                                                              tmp_path: Path) -> None:
    store.add_patch(dataset, "vis", patch(40, 60, (200, 30, 30), 180, seed=1),
                    {"level": 0, "x": 100, "y": 50, "w": 60, "h": 40, "short": "Crack",
                     "long": "<p>A crack <b>here</b></p>", "author": "Ada"})
    store.add_patch(dataset, "vis", patch(50, 100, (30, 30, 200), 120, seed=2),
                    {"level": 1, "x": 300, "y": 200, "w": 200, "h": 100, "short": "bird",
                     "motivation": "tagging"})
    from lanterna.tiler.overlays.rebuild import rebuild_from_store

    rebuild_from_store(dataset, "vis")
    out = tmp_path / "export.json"
    assert export_page(dataset, "vis", out) == 2
    other = make_dataset(tmp_path / "elsewhere", name="copy")
    report = import_page(other, "vis", out)
    keys = ("level", "x", "y", "w", "h", "short", "long", "author", "motivation")
    assert [{k: r[k] for k in keys} for r in report.records] == [
        {"level": 0, "x": 100, "y": 50, "w": 60, "h": 40, "short": "Crack",
         "long": "<p>A crack <b>here</b></p>", "author": "Ada", "motivation": "commenting"},
        {"level": 1, "x": 300, "y": 200, "w": 200, "h": 100, "short": "bird", "long": "",
         "author": "", "motivation": "tagging"}]
    # into the same dataset (another layer) the patch images themselves come back
    same = import_page(dataset, "uv", out)
    for original, copied in zip(store.list_patches(dataset, "vis"), same.records, strict=True):
        assert np.array_equal(_png(store.patch_image(dataset, "vis", original["id"])),
                              _png(store.patch_image(dataset, "uv", copied["id"])))


def test_export_of_a_layer_without_patches_is_an_error(dataset: Path, tmp_path: Path) -> None:
    with pytest.raises(LanternaInputError, match="layer vis has no published patches"):
        export_page(dataset, "vis", tmp_path / "x.json")
    with pytest.raises(LanternaInputError, match="no layer 'nope'"):
        export_page(dataset, "nope", tmp_path / "x.json")
    assert not (tmp_path / "x.json").exists()
