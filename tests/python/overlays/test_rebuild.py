"""Rebuilding an overlay from its patch store: snapshots, build numbers, kills (tiler/overlays/
rebuild.py)."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import time
from pathlib import Path
from typing import Any

import numpy as np
import pytest
import pyvips

from lanterna.cli import main
from lanterna.tiler.dataset.layers import add_image_layer
from lanterna.tiler.dataset.writer import DatasetWriter
from lanterna.tiler.overlays import rebuild, store
from tests.python.fixtures.overlays import make_dataset, read_image
from tests.python.fixtures.publishing import leftovers
from tests.python.fixtures.servers import LANTERNA
from tests.python.fixtures.sources import png

#: Deadline for a killed command's marker to appear (not a performance bound).
MARKER_DEADLINE_S = 120


def square(size: int, rgb: tuple[int, int, int]) -> np.ndarray:
    out = np.full((size, size, 4), 255, np.uint8)
    out[..., :3] = rgb
    return out


def add(dataset: Path, x: int, rgb: tuple[int, int, int], layer: str = "vis") -> dict[str, Any]:
    return store.add_patch(dataset, layer, square(10, rgb),
                           {"level": 0, "x": x, "y": 10, "w": 10, "h": 10})


def overlay(dataset: Path, layer: int = 0) -> dict[str, Any]:
    found: dict[str, Any] = json.loads((dataset / "lanterna.json").read_text())[
        "layers"][layer]["overlay"]
    return found


@pytest.fixture
def dataset(tmp_path: Path) -> Path:
    return make_dataset(tmp_path / "root")


def test_a_change_during_a_rebuild_is_in_the_next_one(dataset: Path,
                                                      monkeypatch: pytest.MonkeyPatch) -> None:
    add(dataset, 0, (255, 0, 0))
    real = rebuild.levels_from_patches
    late: list[dict[str, Any]] = []

    def with_a_concurrent_upload(*args: Any) -> Any:
        if not late:  # another client adds a patch while this build composites
            late.append(add(dataset, 100, (0, 0, 255)))
        return real(*args)

    monkeypatch.setattr(rebuild, "levels_from_patches", with_a_concurrent_upload)
    first = rebuild.rebuild_from_store(dataset, "vis")
    assert first.patches == 1 and first.build == 1
    assert [p["id"] for p in overlay(dataset)["patches"]] == ["0_0_10_10_10_0_patch"]
    assert rebuild.is_stale(dataset, "vis")
    second = rebuild.rebuild_from_store(dataset, "vis")
    assert second.patches == 2 and second.build == 2 and not rebuild.is_stale(dataset, "vis")
    level = read_image(dataset, "vis_ov0_b2")
    assert level[15, 5].tolist() == [255, 0, 0, 255] and level[15, 105].tolist() == [0, 0, 255,
                                                                                     255]


def test_an_unchanged_store_is_not_rebuilt(dataset: Path) -> None:
    add(dataset, 0, (255, 0, 0))
    assert rebuild.rebuild_from_store(dataset, "vis").changed
    version = os.readlink(dataset)
    report = rebuild.rebuild_from_store(dataset, "vis")
    assert not report.changed and report.build == 1 and report.levels == [0]
    assert os.readlink(dataset) == version
    assert rebuild.rebuild_from_store(dataset, "vis", force=True).build == 2


def test_an_emptied_store_keeps_counting_builds(dataset: Path) -> None:
    rec = add(dataset, 0, (255, 0, 0))
    rebuild.rebuild_from_store(dataset, "vis")
    store.delete_patch(dataset, "vis", rec["id"])
    report = rebuild.rebuild_from_store(dataset, "vis")
    assert report.levels == [] and report.build == 2
    entry = overlay(dataset)
    assert (entry["levels"], entry["patches"], entry["build"]) == ([], [], 2)
    assert not (dataset / "annotations/vis").exists()
    manifest = json.loads((dataset / "manifest.json").read_text())
    assert "annotations" not in manifest["items"][0]
    add(dataset, 0, (0, 255, 0))
    assert rebuild.rebuild_from_store(dataset, "vis").build == 3
    assert overlay(dataset)["levels"][0]["image"] == "vis_ov0_b3"  # never an id used before


def test_a_layer_without_store_or_overlay_is_left_alone(dataset: Path) -> None:
    version = os.readlink(dataset)
    assert not rebuild.is_stale(dataset, "uv")
    assert not rebuild.rebuild_from_store(dataset, "uv").changed
    assert os.readlink(dataset) == version and "overlay" not in json.loads(
        (dataset / "lanterna.json").read_text())["layers"][1]


def test_annotate_build_without_a_source_picks_up_dropped_files(
        dataset: Path, capsys: pytest.CaptureFixture[str]) -> None:
    add(dataset, 0, (255, 0, 0))
    assert main(["annotate", "build", str(dataset), "--layer", "vis"]) == 0
    assert "(build 1)" in capsys.readouterr().out
    png(store.store_dir(dataset, "vis") / "0_200_100_30_30_5_gimp.png", square(30, (0, 9, 99)))
    assert rebuild.is_stale(dataset, "vis")
    assert main(["annotate", "build", str(dataset), "--layer", "vis"]) == 0
    assert "from 2 patch(es) written to" in capsys.readouterr().out
    assert read_image(dataset, "vis_ov0_b2")[110, 210].tolist() == [0, 9, 99, 255]
    assert main(["annotate", "build", str(dataset), "--layer", "vis"]) == 0
    assert "already up to date with its patch store (build 2)" in capsys.readouterr().out


def _big_dataset(root: Path) -> Path:
    """A 3000×2000 dataset: a level-0 overlay of it takes a while to tile."""
    w, h = 3000, 2000
    rng = np.random.default_rng(2)
    with DatasetWriter(root / "big", name="big", label="Big", width=w, height=h) as ds:
        img = pyvips.Image.new_from_array(rng.integers(0, 256, (h, w, 3), dtype=np.uint8))
        add_image_layer(ds, img.copy(interpretation="srgb"), layer_id="vis", label="VIS",
                        fmt="jpg")
    return root / "big"


def test_a_rebuild_killed_midway_leaves_the_old_overlay_and_the_next_one_completes(
        tmp_path: Path) -> None:
    dataset = _big_dataset(tmp_path / "root")
    big = np.zeros((2000, 3000, 4), np.uint8)
    big[..., 0], big[..., 3] = 200, 100
    store.add_patch(dataset, "vis", big, {"level": 0, "x": 0, "y": 0, "w": 3000, "h": 2000})
    rebuild.rebuild_from_store(dataset, "vis")
    marker = store.store_dir(dataset, "vis") / store.BUILDING
    killed_before_publish = 0
    for attempt in range(5):  # until the kill lands while the new version is being written
        add(dataset, 20 * attempt, (0, 0, 255))
        version, build = os.readlink(dataset), overlay(dataset)["build"]
        proc = subprocess.Popen([str(LANTERNA), "annotate", "build", str(dataset), "--layer",
                                 "vis"], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        deadline = time.monotonic() + MARKER_DEADLINE_S
        while not marker.exists() and proc.poll() is None and time.monotonic() < deadline:
            time.sleep(0.002)
        proc.send_signal(signal.SIGKILL)
        proc.wait()
        if os.readlink(dataset) == version:
            killed_before_publish += 1
            assert overlay(dataset)["build"] == build  # the old overlay is still the one served
            info = json.loads((dataset / f"iiif/{overlay(dataset)['levels'][0]['image']}"
                               "/info.json").read_text())
            assert info["width"] == 3000
            assert rebuild.building_pid(dataset, "vis") is None  # its marker's pid is dead
            assert rebuild.is_stale(dataset, "vis")
            break
    assert killed_before_publish == 1
    report = rebuild.rebuild_from_store(dataset, "vis")  # the next one sweeps and completes
    assert report.changed and report.patches == len(store.list_patches(dataset, "vis"))
    assert not rebuild.is_stale(dataset, "vis")
    assert leftovers(dataset.parent) == ["big", "big.annotations"]
