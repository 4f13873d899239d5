"""Faults with real processes: ``kill -9`` at random points of a write, and two writers at once.

After every kill the dataset is complete and served (its previous version or the new one, never
neither), and the next write clears what the killed one left. Two writers on one dataset are
serialised by its lock: both layers' overlays survive, and two ``import --force`` leave one of
the two complete datasets, never a mix.
"""

from __future__ import annotations

import json
import os
import signal
import subprocess
import time
from pathlib import Path

import numpy as np
import pytest
import pyvips

from lanterna.tiler.dataset.layers import add_image_layer
from lanterna.tiler.dataset.lock import WAIT_ENV, dataset_lock
from lanterna.tiler.dataset.writer import DatasetWriter, read_description
from lanterna.tiler.formats.ptm import read_ptm
from tests.python.fixtures.overlays import patch
from tests.python.fixtures.paths import REPO
from tests.python.fixtures.ptm import random_ptm_of_size
from tests.python.fixtures.ptm_writer import write_ptm
from tests.python.fixtures.publishing import kill_points, lanterna, leftovers, servable
from tests.python.fixtures.sources import png

W, H = 1200, 900


def _timed(args: list[str]) -> float:
    t0 = time.monotonic()
    subprocess.run(args, cwd=REPO, check=True, capture_output=True)
    return time.monotonic() - t0


def _killed(args: list[str], delay: float, writing_in: Path | None = None) -> None:
    """Run ``args`` and kill it ``delay`` s after it starts or, given ``writing_in``, after a new
    temporary folder of a write appears there (so that the kill lands mid-write however slow the
    process is to start on a loaded machine)."""
    earlier = {e.name for e in writing_in.iterdir()} if writing_in is not None else set()
    proc = subprocess.Popen(args, cwd=REPO, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    if writing_in is not None:  # a new temporary folder: this process is writing
        deadline = time.monotonic() + 60
        while proc.poll() is None and time.monotonic() < deadline and not any(
                ".tmp-" in e.name and e.name not in earlier for e in writing_in.iterdir()):
            time.sleep(0.005)
    time.sleep(delay)
    proc.send_signal(signal.SIGKILL)  # nothing if it has finished: then the write is complete
    proc.wait(30)


@pytest.fixture
def two_layers(tmp_path: Path) -> Path:
    """A W×H dataset with image layers ``vis`` and ``uv`` and a folder of patches per layer."""
    rng = np.random.default_rng(5)
    out = tmp_path / "root" / "obj"
    with DatasetWriter(out, name="obj", label="Object", width=W, height=H) as ds:
        for lid in ("vis", "uv"):
            img = pyvips.Image.new_from_array(rng.integers(0, 256, (H, W, 3), dtype=np.uint8))
            add_image_layer(ds, img.copy(interpretation="srgb"), layer_id=lid, fmt="png")
    for lid in ("vis", "uv"):
        folder = tmp_path / f"patches-{lid}"
        folder.mkdir()
        for level in (0, 1, 2):
            png(folder / f"{level}_0_0_{W}_{H}_0_{lid}.png", patch(H >> level, W >> level,
                                                                   (255, 0, 0), 200, level))
    return out


def _annotate(dataset: Path, layer: str, texts: Path | None = None) -> list[str]:
    extra = ["--texts", str(texts)] if texts else []
    return lanterna("annotate", "build", dataset, "--layer", layer, "--patches",
                    dataset.parent.parent / f"patches-{layer}", *extra)


def _overlay_levels(desc: dict, layer: str) -> list[int]:
    entry = next(item for item in desc["layers"] if item["id"] == layer)
    return [level["level"] for level in entry.get("overlay", {}).get("levels", [])]


def test_kill_9_during_import_force_always_leaves_a_dataset(tmp_path: Path) -> None:
    root, src = tmp_path / "root", tmp_path / "obj.ptm"
    write_ptm(src, random_ptm_of_size(1000, 1000, seed=3), "PTM_FORMAT_LRGB")
    duration = _timed(lanterna("import", src, "-o", root / "obj", "--label", "v0"))
    label, interrupted = "v0", 0
    for i, delay in enumerate(kill_points(duration, 8, seed=7), 1):
        _killed(lanterna("import", src, "-o", root / "obj", "--force", "--label", f"v{i}"), delay)
        desc = servable(root, "obj")
        assert desc["label"] in (label, f"v{i}"), (i, delay)
        label = desc["label"]
        interrupted += leftovers(root) != ["obj"]
        assert sum(".obj.tmp-" in name for name in leftovers(root)) <= 1  # earlier ones swept
    assert interrupted >= 2  # kills that landed mid-write, leaving what the next write clears
    subprocess.run(lanterna("import", src, "-o", root / "obj", "--force", "--label", "last"),
                   cwd=REPO, check=True, capture_output=True)
    assert servable(root, "obj")["label"] == "last" and leftovers(root) == ["obj"]


def test_kill_9_during_annotate_build_keeps_the_overlay_whole(two_layers: Path) -> None:
    root = two_layers.parent
    duration = _timed(_annotate(two_layers, "vis"))
    interrupted = 0
    # Three kills timed from the start, three from the moment the write's temporary folder appears.
    kills = [(delay, None) for delay in kill_points(duration, 3, seed=11)] + [
        (delay, root) for delay in kill_points(duration / 4, 3, seed=12)]
    for delay, writing_in in kills:
        _killed(_annotate(two_layers, "uv"), delay, writing_in)
        desc = servable(root, "obj")
        assert _overlay_levels(desc, "vis") == [0, 1, 2]
        assert _overlay_levels(desc, "uv") in ([], [0, 1, 2])
        interrupted += leftovers(root) not in (["obj"], ["obj", "obj.annotations"])
        assert sum(".obj.tmp-" in name for name in leftovers(root)) <= 1  # earlier ones swept
    assert interrupted >= 2
    subprocess.run(_annotate(two_layers, "uv"), cwd=REPO, check=True, capture_output=True)
    desc = servable(root, "obj")
    assert _overlay_levels(desc, "uv") == [0, 1, 2]
    assert leftovers(root) == ["obj", "obj.annotations"]  # the layers' patch stores beside it


def test_two_annotate_builds_at_once_lose_nothing(two_layers: Path, tmp_path: Path) -> None:
    # 1. Both start while the lock is held, so both wait; then they run one after the other.
    with dataset_lock(two_layers):
        procs = [subprocess.Popen(_annotate(two_layers, lid), cwd=REPO, text=True,
                                  stdout=subprocess.PIPE, stderr=subprocess.PIPE)
                 for lid in ("vis", "uv")]
        for proc in procs:
            assert proc.stderr is not None
            assert proc.stderr.readline() == (
                f"lanterna: {two_layers}: waiting for another Lanterna process (pid "
                f"{os.getpid()}) to finish writing this dataset …\n")
    for proc in procs:
        proc.communicate(timeout=60)
        assert proc.returncode == 0
    desc = servable(two_layers.parent, "obj")
    assert _overlay_levels(desc, "vis") == _overlay_levels(desc, "uv") == [0, 1, 2]
    # 2. A free race, with new texts: each build keeps the other layer's new overlay.
    for lid in ("vis", "uv"):
        (tmp_path / f"{lid}.json").write_text(json.dumps({"1": {"short": f"race {lid}"}}))
    procs = [subprocess.Popen(_annotate(two_layers, lid, tmp_path / f"{lid}.json"), cwd=REPO,
                              stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
             for lid in ("vis", "uv")]
    assert [proc.wait(60) for proc in procs] == [0, 0]
    desc = servable(two_layers.parent, "obj")
    for layer in desc["layers"]:
        assert layer["overlay"]["levels"][1]["short"] == f"race {layer['id']}"
    assert leftovers(two_layers.parent) == ["obj", "obj.annotations"]


def test_a_writer_told_not_to_wait_stops_with_one_line(two_layers: Path) -> None:
    before = (two_layers / "lanterna.json").read_text()
    with dataset_lock(two_layers):
        done = subprocess.run(_annotate(two_layers, "vis"), cwd=REPO, text=True,
                              capture_output=True, env={**os.environ, WAIT_ENV: "0"})
    assert done.returncode == 2
    assert done.stderr == (f"lanterna: error: {two_layers}: another Lanterna process is writing "
                           f"this dataset (pid {os.getpid()}); try again when it has finished\n")
    assert (two_layers / "lanterna.json").read_text() == before


def test_two_import_force_at_once_leave_one_whole_dataset(tmp_path: Path) -> None:
    root = tmp_path / "root"
    sources = {}
    for label, seed in (("A", 1), ("B", 2)):
        (tmp_path / label).mkdir()
        sources[label] = tmp_path / label / "obj.ptm"  # the same layer and image ids
        write_ptm(sources[label], random_ptm_of_size(600, 400, seed=seed), "PTM_FORMAT_LRGB")
    for _ in range(2):
        procs = [subprocess.Popen(lanterna("import", src, "-o", root / "obj", "--force",
                                           "--label", label), cwd=REPO,
                                  stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
                 for label, src in sources.items()]
        assert [proc.wait(60) for proc in procs] == [0, 0]
        desc = servable(root, "obj")
        ptm = read_ptm(sources[desc["label"]])
        assert ptm.rgb is not None
        expected = [ptm.coefficients[..., 0:3], ptm.coefficients[..., 3:6], ptm.rgb]
        for plane, pixels in zip(desc["layers"][0]["service"]["planes"], expected, strict=True):
            image = plane["service"]["id"].rsplit("/", 1)[1]
            ext = plane["format"]  # an 8-bit PTM: a lossless source, PNG or WebP
            assert ext in ("png", "webp")
            tile = root / "obj" / "iiif" / image / "256,256,256,144" / f"256,144/0/default.{ext}"
            # from the bytes: libvips caches images by file name, and the name stays
            got = pyvips.Image.new_from_buffer(tile.read_bytes(), "").numpy()
            np.testing.assert_array_equal(got, pixels[256:400, 256:512])
        assert leftovers(root) == ["obj"]
    assert read_description(root / "obj")["label"] in sources
