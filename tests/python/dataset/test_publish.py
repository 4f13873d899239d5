"""Publishing versions: a dataset is a link swapped in one rename; leftovers are swept."""

from __future__ import annotations

import json
import os
import shutil
from pathlib import Path

import numpy as np
import pytest

from lanterna.tiler.dataset import publish as publish_mod
from lanterna.tiler.dataset.layers import add_image_layer
from lanterna.tiler.dataset.publish import list_datasets, reading, recover, sweep, writing
from lanterna.tiler.dataset.writer import DatasetWriter, read_description
from lanterna.tiler.iiif.pyramid import vips_from_array
from tests.python.fixtures.publishing import leftovers


def _write(out: Path, label: str, *, force: bool = True) -> Path:
    img = vips_from_array(np.full((20, 30, 3), len(label), np.uint8))
    with DatasetWriter(out, name=out.name, label=label, width=30, height=20, force=force) as ds:
        add_image_layer(ds, img, layer_id="pic", fmt="png")
    return out


def _plain(out: Path, label: str) -> Path:
    """A dataset as Lanterna wrote it before versions: a plain folder at ``out``."""
    _write(out.with_name("src"), label)
    shutil.copytree(out.with_name("src"), out)
    shutil.rmtree(os.path.realpath(out.with_name("src")))
    out.with_name("src").unlink()
    return out


def test_a_dataset_is_a_relative_link_to_its_only_version(tmp_path: Path) -> None:
    out = _write(tmp_path / "obj", "one", force=False)
    target = os.readlink(out)
    assert target.startswith(".obj.v-") and "/" not in target
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted([target, "obj"])
    assert read_description(out)["label"] == "one"


def test_publishing_again_swaps_the_link_and_removes_the_old_version(tmp_path: Path) -> None:
    out = _write(tmp_path / "obj", "one")
    first = os.readlink(out)
    _write(out, "two")
    assert os.readlink(out) != first and not (tmp_path / first).exists()
    assert leftovers(tmp_path) == ["obj"]
    assert read_description(out)["label"] == "two"


@pytest.mark.parametrize("atomic", [True, False], ids=["exchange", "two-renames"])
def test_a_plain_folder_dataset_is_upgraded_to_a_link(tmp_path: Path, atomic: bool,
                                                      monkeypatch: pytest.MonkeyPatch) -> None:
    out = _plain(tmp_path / "obj", "plain")
    assert not out.is_symlink() and read_description(out)["label"] == "plain"
    probe = [tmp_path / "probe-a", tmp_path / "probe-b"]
    for folder in probe:
        folder.mkdir()
    if atomic and not publish_mod.exchange(*probe):
        pytest.skip("renameat2(RENAME_EXCHANGE) is not available on this system")
    for folder in probe:
        folder.rmdir()
    swaps: list[bool] = []
    real = publish_mod.exchange

    def exchange(a: Path, b: Path) -> bool:
        swaps.append(real(a, b) if atomic else False)
        return swaps[-1]

    monkeypatch.setattr(publish_mod, "exchange", exchange)
    _write(out, "linked")
    assert swaps == [atomic]
    assert out.is_symlink() and read_description(out)["label"] == "linked"
    assert leftovers(tmp_path) == ["obj"]  # the plain folder is gone


def test_a_publish_killed_between_its_two_renames_is_finished_by_the_next_writer(
        tmp_path: Path) -> None:
    """The state the two-rename upgrade leaves if killed after moving the plain folder away."""
    out = _write(tmp_path / "obj", "new")
    version = os.readlink(out)
    out.unlink()
    (tmp_path / ".obj.link-20250101T000000_abcdef").symlink_to(version)
    shutil.copytree(tmp_path / version, tmp_path / ".obj.old-20250101T000000_abcdef")
    with writing(out):
        assert os.readlink(out) == version
    assert leftovers(tmp_path) == ["obj"] and read_description(out)["label"] == "new"


def test_no_link_no_recovery(tmp_path: Path) -> None:
    """A dataset whose link was deleted by hand stays deleted (its version is swept)."""
    out = _write(tmp_path / "obj", "gone")
    out.unlink()
    with writing(out):
        pass
    assert sorted(os.listdir(tmp_path)) == []


def test_the_sweep_removes_only_this_datasets_leftovers(tmp_path: Path) -> None:
    out = _write(tmp_path / "obj", "current")
    other = _write(tmp_path / "obj2", "neighbour")
    stale = ["obj.tmp-k2j3_x", "obj.old-20250101T000000_abcdef", "obj.v-20250101T000000_dead01",
             "obj.link-20250101T000000_dead01"]
    for name in stale[:3]:
        (tmp_path / f".{name}" / "iiif").mkdir(parents=True)
        (tmp_path / f".{name}" / "lanterna.json").write_text("{}")
    (tmp_path / f".{stale[3]}").symlink_to(f".{stale[2]}")
    theirs = [".obj2.tmp-abc", ".obj.v-x.tmp-abc", ".obj.tmp-not_an-id", "obj.tmp-visible"]
    for name in theirs:  # another dataset's, dataset "obj.v-x"'s, and no dataset's
        (tmp_path / name).mkdir()
    kept_version = tmp_path / ".obj.v-20250101T000000_kept01"
    kept_version.mkdir()
    (tmp_path / "snapshot").symlink_to(kept_version.name)  # a link someone made: kept
    with writing(out):
        pass
    assert leftovers(tmp_path) == sorted(["obj", "obj2", *theirs, "snapshot"])
    assert kept_version.is_dir() and read_description(other)["label"] == "neighbour"
    assert not any((tmp_path / f".{name}").exists() or (tmp_path / f".{name}").is_symlink()
                   for name in stale)


def test_sweep_reports_what_it_removed(tmp_path: Path) -> None:
    out = _write(tmp_path / "obj", "x")
    (tmp_path / ".obj.tmp-abc").mkdir()
    assert sweep(out) == [".obj.tmp-abc"] and sweep(out) == []


def test_a_version_being_read_outlives_its_replacement_until_the_next_write(
        tmp_path: Path) -> None:
    out = _write(tmp_path / "obj", "one")
    with reading(out) as version:
        _write(out, "two")
        assert version.is_dir() and json.loads((version / "lanterna.json").read_text())[
            "label"] == "one"
        assert leftovers(tmp_path) == [version.name, "obj"]
        _write(out, "three")  # the sweep leaves it too while it is read
        assert version.is_dir()
    _write(out, "four")
    assert not version.exists() and leftovers(tmp_path) == ["obj"]


def test_recover_leaves_a_present_dataset_alone(tmp_path: Path) -> None:
    out = _write(tmp_path / "obj", "here")
    (tmp_path / ".obj.link-20250101T000000_abcdef").symlink_to(os.readlink(out))
    before = os.readlink(out)
    recover(out)
    assert os.readlink(out) == before


def test_listing_skips_hidden_entries_and_follows_links(tmp_path: Path) -> None:
    _write(tmp_path / "b", "b")
    _plain(tmp_path / "a", "a")
    (tmp_path / ".b.old-20250101T000000_abcdef").mkdir()
    (tmp_path / ".b.old-20250101T000000_abcdef" / "lanterna.json").write_text("{}")
    (tmp_path / "notes").mkdir()
    assert list_datasets(tmp_path) == [tmp_path / "a", tmp_path / "b"]


def test_a_link_to_somewhere_else_is_replaced_and_its_target_left_alone(tmp_path: Path) -> None:
    elsewhere = _write(tmp_path / "disk" / "obj", "elsewhere")
    root = tmp_path / "root"
    root.mkdir()
    (root / "obj").symlink_to(elsewhere)
    _write(root / "obj", "here")
    assert read_description(root / "obj")["label"] == "here"
    assert read_description(elsewhere)["label"] == "elsewhere"
