"""Bad overlay input: one error per file, the valid patches still built, the dataset kept whole."""

from __future__ import annotations

import hashlib
import json
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from lanterna.cli import main
from lanterna.errors import LanternaInputError
from lanterna.tiler.overlays import rebuild
from lanterna.tiler.overlays.build import OverlayInputError, build_overlays
from tests.python.fixtures.overlays import make_dataset, patch
from tests.python.fixtures.publishing import leftovers
from tests.python.fixtures.sources import png


def tree(folder: Path) -> dict[str, str]:
    """Return every file under ``folder`` with a hash of its content."""
    return {str(p.relative_to(folder)): hashlib.sha1(p.read_bytes()).hexdigest()
            for p in sorted(folder.rglob("*")) if p.is_file()}


@pytest.fixture
def dataset(tmp_path: Path) -> Path:
    return make_dataset(tmp_path / "root")


def bad_folder(tmp_path: Path) -> Path:
    folder = tmp_path / "patches"
    folder.mkdir()
    png(folder / "0_10_10_20_20_0_good.png", patch(20, 20, (255, 0, 0), 255))
    png(folder / "1_0_0_40_40_0_also good.png", patch(20, 20, (0, 255, 0), 255))
    png(folder / "0_10_10_20_nope.png", patch(20, 20, (0, 0, 255), 255))
    png(folder / "0_600_0_20_20_0_outside.png", patch(20, 20, (0, 0, 255), 255))
    png(folder / "0_0_0_20_20_0_rgb.png", np.full((20, 20, 3), 128, np.uint8))
    png(folder / "3_0_0_20_20_0_too deep.png", patch(20, 20, (0, 0, 255), 255))
    (folder / "broken_0_0_1_1_0_x.png").write_text("not an image")
    (folder / ".DS_Store").write_bytes(b"\0")
    return folder


EXPECTED_ERRORS = [
    "0_0_0_20_20_0_rgb.png: has no alpha channel (3 band(s)); overlay images must be RGBA",
    "0_10_10_20_nope.png: malformed patch name (expected L_X_Y_W_H_O_INFO.png with integers "
    "L, X, Y, W, H, O)",
    "0_600_0_20_20_0_outside.png: rectangle 600,0,20,20 is outside the 600x400 canvas",
    "3_0_0_20_20_0_too deep.png: level 3 is beyond the pyramid (levels 0–2)",
    "broken_0_0_1_1_0_x.png: malformed patch name (expected L_X_Y_W_H_O_INFO.png with integers "
    "L, X, Y, W, H, O)",
]


def test_each_bad_file_has_one_error_and_the_valid_ones_are_built(tmp_path: Path,
                                                                   dataset: Path) -> None:
    folder = bad_folder(tmp_path)
    report = build_overlays(dataset, "vis", patches_dir=folder)
    assert [e.removeprefix(f"{folder}/") for e in report.errors] == EXPECTED_ERRORS
    assert report.levels == [0, 1] and report.patches == 2
    desc = json.loads((dataset / "lanterna.json").read_text())
    assert [p["info"] for p in desc["layers"][0]["overlay"]["patches"]] == ["good", "also good"]
    assert (dataset / "iiif/vis_ov1/info.json").is_file()


def test_cli_lists_rejected_files_and_exits_non_zero(tmp_path: Path, dataset: Path,
                                                     capsys: pytest.CaptureFixture[str]) -> None:
    folder = bad_folder(tmp_path)
    assert main(["annotate", "build", str(dataset), "--layer", "vis",
                 "--patches", str(folder)]) == 1
    captured = capsys.readouterr()
    errors = [line for line in captured.err.splitlines() if line.startswith("lanterna: error: ")]
    assert [e.removeprefix(f"lanterna: error: {folder}/") for e in errors] == EXPECTED_ERRORS
    assert "5 file(s) rejected" in captured.err
    assert "overlay levels 0, 1 from 2 patch(es)" in captured.out


def test_unreadable_png_with_a_good_name_is_reported(tmp_path: Path, dataset: Path) -> None:
    folder = tmp_path / "p"
    folder.mkdir()
    (folder / "0_0_0_4_4_0_truncated.png").write_bytes(b"\x89PNG\r\n\x1a\n")
    png(folder / "0_0_0_4_4_1_ok.png", patch(4, 4, (9, 9, 9), 255))
    report = build_overlays(dataset, "vis", patches_dir=folder)
    (error,) = report.errors
    assert error.startswith(f"{folder}/0_0_0_4_4_0_truncated.png: cannot read image (")
    assert "\n" not in error


def test_nothing_valid_leaves_the_dataset_unchanged(tmp_path: Path, dataset: Path,
                                                    capsys: pytest.CaptureFixture[str]) -> None:
    folder = tmp_path / "p"
    folder.mkdir()
    png(folder / "9_0_0_4_4_0_deep.png", patch(4, 4, (9, 9, 9), 255))
    before = tree(dataset)
    with pytest.raises(OverlayInputError, match=r"no valid patches \(1 file\(s\) rejected\); "
                                                r"the dataset is unchanged") as err:
        build_overlays(dataset, "vis", patches_dir=folder)
    assert len(err.value.errors) == 1
    assert tree(dataset) == before
    assert main(["annotate", "build", str(dataset), "--layer", "vis", "--patches",
                 str(folder)]) == 2
    lines = capsys.readouterr().err.splitlines()
    assert lines[0].endswith("9_0_0_4_4_0_deep.png: level 9 is beyond the pyramid (levels 0–2)")
    assert lines[1].endswith("the dataset is unchanged")


@pytest.mark.parametrize(("args", "message"), [
    (["--layer", "nope"], "no layer 'nope' (layers: vis, uv)"),
    (["--layer", "vis", "--texts", "missing.json"], "missing.json: file not found"),
])
def test_argument_errors_are_one_line(tmp_path: Path, dataset: Path, args: list[str],
                                      message: str, capsys: pytest.CaptureFixture[str]) -> None:
    folder = tmp_path / "p"
    folder.mkdir()
    png(folder / "0_0_0_4_4_0_x.png", patch(4, 4, (9, 9, 9), 255))
    args = [a if a != "missing.json" else str(tmp_path / a) for a in args]
    assert main(["annotate", "build", str(dataset), "--patches", str(folder), *args]) == 2
    err = capsys.readouterr().err.strip()
    assert message in err and len(err.splitlines()) == 1


def test_not_a_dataset(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["annotate", "list", str(tmp_path)]) == 2
    assert "not a Lanterna dataset (no lanterna.json)" in capsys.readouterr().err


def test_failure_midway_keeps_the_previous_overlay_and_leaves_no_temp_dirs(
        tmp_path: Path, dataset: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    old, new = tmp_path / "old", tmp_path / "new"
    old.mkdir()
    new.mkdir()
    png(old / "0_0_0_10_10_0_old.png", patch(10, 10, (255, 0, 0), 255))
    build_overlays(dataset, "vis", patches_dir=old, texts={"0": {"short": "old"}})
    for level in (0, 1, 2):
        png(new / f"{level}_0_0_40_40_0_new.png", patch(10, 10, (0, 0, 255), 255))
    before = tree(dataset)
    calls: list[str] = []
    real = rebuild.write_pyramid

    def failing(*args: Any, **kwargs: Any) -> dict[str, Any]:
        calls.append(str(args[1]))
        if len(calls) == 2:
            raise OSError(28, "No space left on device")
        return real(*args, **kwargs)

    monkeypatch.setattr(rebuild, "write_pyramid", failing)
    with pytest.raises(LanternaInputError, match=f"^{dataset}: cannot write "
                       r"\(No space left on device\); nothing was changed$"):
        build_overlays(dataset, "vis", patches_dir=new)
    assert len(calls) == 2  # the first level was written in the copy before the failure
    assert tree(dataset) == before
    desc = json.loads((dataset / "lanterna.json").read_text())
    assert desc["layers"][0]["overlay"]["levels"][0]["short"] == "old"
    assert leftovers(dataset.parent) == [dataset.name, f"{dataset.name}.annotations"]
    # the patches are in the store: the next rebuild publishes them
    monkeypatch.undo()
    assert rebuild.is_stale(dataset, "vis")
    assert rebuild.rebuild_from_store(dataset, "vis").levels == [0, 1, 2]


def test_an_image_of_another_layer_is_never_replaced(tmp_path: Path) -> None:
    dataset = make_dataset(tmp_path / "root", layers=("vis", "vis_ov0"))
    folder = tmp_path / "p"
    folder.mkdir()
    png(folder / "0_0_0_4_4_0_x.png", patch(4, 4, (9, 9, 9), 255))
    before = tree(dataset)
    with pytest.raises(LanternaInputError, match=r"image id\(s\) vis_ov0 already used by "
                                                 "something other than this layer's overlay"):
        build_overlays(dataset, "vis", patches_dir=folder)
    assert tree(dataset) == before
