"""``write_documents`` writes the W3C annotation files of a rewrite and removes the stale ones."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import numpy as np
import pyvips

from lanterna.manifests.validate import validate_annotation_page, validate_manifest
from lanterna.tiler.dataset.layers import add_image_layer
from lanterna.tiler.dataset.publish import reading
from lanterna.tiler.dataset.writer import DatasetWriter, rewriting

from .test_annotation_page import record
from .w3c_rules import w3c_errors

BASE = "https://example.org/data"


def _dataset(root: Path) -> Path:
    px = np.random.default_rng(3).integers(0, 256, (64, 96, 3), dtype=np.uint8)
    with DatasetWriter(root / "obj", name="obj", label="Object", width=96, height=64,
                       base_url=BASE, tile_size=64) as ds:
        add_image_layer(ds, pyvips.Image.new_from_array(px).copy(interpretation="srgb"),
                        layer_id="vis", label="Visible", fmt="png")
    return root / "obj"


def _publish(dataset: Path, records: list[dict[str, Any]]) -> None:
    """Publish ``records`` as layer vis's patches, with their PNGs, as a store rebuild does."""
    with rewriting(dataset) as (tmp, desc):
        folder = tmp / "annotations" / "vis"
        folder.mkdir(parents=True, exist_ok=True)
        for rec in records:
            px = np.full((rec["height"], rec["width"], 4), 200, np.uint8)
            pyvips.Image.new_from_array(px).pngsave(str(folder / rec["file"]))
        desc["layers"][0]["overlay"] = {"source": "store", "build": 1, "fingerprint": "0" * 64,
                                        "levels": [], "patches": records}


def _files(dataset: Path) -> list[str]:
    root = dataset / "annotations"
    return sorted(p.relative_to(root).as_posix() for p in root.rglob("*") if p.is_file())


def test_a_rewrite_writes_the_page_and_one_file_per_annotation(tmp_path: Path) -> None:
    dataset = _dataset(tmp_path)
    assert not (dataset / "annotations").exists()
    a = record("0_4_4_20_10_0_a", 0, 4, 4, 20, 10, 0, short="A", author="Ada")
    b = record("1_40_20_40_30_1_b", 1, 40, 20, 40, 30, 1, motivation="tagging", short="b")
    _publish(dataset, [a, b])
    assert _files(dataset) == ["vis.json", "vis/0_4_4_20_10_0_a.json", "vis/0_4_4_20_10_0_a.png",
                               "vis/1_40_20_40_30_1_b.json", "vis/1_40_20_40_30_1_b.png"]
    page = json.loads((dataset / "annotations" / "vis.json").read_text())
    assert validate_annotation_page(page) == [] and w3c_errors(page) == []
    alone = json.loads((dataset / "annotations/vis/0_4_4_20_10_0_a.json").read_text())
    assert alone["id"] == f"{BASE}/obj/annotations/vis/0_4_4_20_10_0_a.json"
    assert w3c_errors(alone) == []
    assert {k: v for k, v in alone.items() if k != "@context"} == page["items"][0]
    manifest = json.loads((dataset / "manifest.json").read_text())
    assert validate_manifest(manifest) == []
    assert manifest["items"][0]["annotations"][-1]["id"] == f"{BASE}/obj/annotations/vis.json"


def test_a_later_rewrite_removes_stale_documents(tmp_path: Path) -> None:
    dataset = _dataset(tmp_path)
    a = record("0_4_4_20_10_0_a", 0, 4, 4, 20, 10, 0)
    b = record("0_30_4_20_10_1_b", 0, 30, 4, 20, 10, 1)
    _publish(dataset, [a, b])
    with reading(dataset) as first_version:
        with rewriting(dataset) as (tmp, desc):  # patch a deleted
            (tmp / "annotations/vis/0_4_4_20_10_0_a.png").unlink()
            desc["layers"][0]["overlay"]["patches"] = [b]
        # the version being read (hard-linked into the rewrite) kept its files
        assert (first_version / "annotations/vis/0_4_4_20_10_0_a.json").is_file()
        assert len(json.loads((first_version / "annotations/vis.json").read_text())[
            "items"]) == 2
    assert _files(dataset) == ["vis.json", "vis/0_30_4_20_10_1_b.json",
                               "vis/0_30_4_20_10_1_b.png"]
    page = json.loads((dataset / "annotations" / "vis.json").read_text())
    assert [item["id"].rsplit("/", 1)[1] for item in page["items"]] == ["0_30_4_20_10_1_b.json"]
    with rewriting(dataset) as (_tmp, desc):  # the last patch goes: no page, no folder
        del desc["layers"][0]["overlay"]
    assert not (dataset / "annotations").exists()
    manifest = json.loads((dataset / "manifest.json").read_text())
    assert "annotations" not in manifest["items"][0]
