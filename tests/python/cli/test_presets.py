"""``lanterna presets``: add → list → export → import round trips, and one-line errors."""

from __future__ import annotations

import json
import os
from pathlib import Path

import pytest

from lanterna.cli import main
from lanterna.manifests.validate import validate_manifest
from tests.python.fixtures.presets import read_json, small_dataset, small_library


@pytest.fixture
def dataset(tmp_path: Path) -> Path:
    return small_dataset(tmp_path / "root" / "obj")


def _run(argv: list[str | Path], capsys: pytest.CaptureFixture[str]) -> tuple[int, str, str]:
    status = main([str(a) for a in argv])
    out = capsys.readouterr()
    return status, out.out, out.err


def test_add_list_export_import_round_trip(dataset: Path, tmp_path: Path,
                                          capsys: pytest.CaptureFixture[str]) -> None:
    status, out, _ = _run(["presets", "add", dataset, "--id", "raking", "--label", "Raking",
                           "--layer", "ptm", "--mode", "color", "--light=-0.9,0.3",
                           "--view", "0,0,48,32", "--param", "lightIntensity=1.5",
                           "--base", "Raking light"], capsys)
    assert status == 0 and "added preset raking, listed in the base menu" in out
    status, _, _ = _run(["presets", "add", dataset, "--id", "uv", "--label", "UV", "--layer",
                         "uv", "--mode", "achromatic", "--lens", "UV lens", "--opacity", "0.8"],
                        capsys)
    assert status == 0
    expected = {"type": "LanternaPresets", "version": 1,
                "presets": {"raking": {"label": "Raking", "layer": "ptm", "mode": "color",
                                       "params": {"lightIntensity": 1.5}, "light": [-0.9, 0.3],
                                       "view": [0, 0, 48, 32]},
                            "uv": {"label": "UV", "layer": "uv", "mode": "achromatic"}},
                "base": [{"label": "Raking light", "preset": "raking"}],
                "lens": [{"label": "UV lens", "preset": "uv", "opacity": 0.8}]}
    assert read_json(dataset / "presets.json") == expected

    status, out, _ = _run(["presets", "list", dataset], capsys)
    lines = out.splitlines()
    assert status == 0 and lines[0].split() == ["ID", "LABEL", "LAYER", "MODE"]
    assert lines[1].split() == ["raking", "Raking", "ptm", "color"]
    assert lines[2].split() == ["uv", "UV", "uv", "achromatic"]
    assert "  1. Raking light  (raking on ptm)" in lines
    assert "  1. UV lens  (uv on uv, opacity 0.8)" in lines

    file = tmp_path / "lib.json"
    assert _run(["presets", "export", dataset, "-o", file], capsys)[0] == 0
    assert read_json(file) == expected

    other = small_dataset(tmp_path / "root" / "other")
    status, out, _ = _run(["presets", "import", other, file], capsys)
    assert status == 0 and "stored" in out
    assert read_json(other / "presets.json") == expected
    assert read_json(other / "lanterna.json")["presets"] == expected
    manifest = read_json(other / "manifest.json")
    assert validate_manifest(manifest) == []
    service = manifest["service"][0]
    assert service["id"].endswith("/other/presets.json")
    assert {k: v for k, v in service.items() if k not in ("id", "profile")} == expected


def test_import_merge_keeps_the_other_presets(dataset: Path, tmp_path: Path,
                                              capsys: pytest.CaptureFixture[str]) -> None:
    file = tmp_path / "lib.json"
    file.write_text(json.dumps(small_library()))
    assert _run(["presets", "import", dataset, file], capsys)[0] == 0
    extra = {"type": "LanternaPresets", "version": 1,
             "presets": {"top": {"label": "Top", "layer": "ptm", "mode": "normals"}},
             "base": [{"label": "Normals", "preset": "top"}], "lens": []}
    file.write_text(json.dumps(extra))
    status, out, _ = _run(["presets", "import", dataset, file, "--merge"], capsys)
    assert status == 0 and "merged" in out
    lib = read_json(dataset / "presets.json")
    assert set(lib["presets"]) == {"raking", "uv", "top"}
    assert [e["label"] for e in lib["base"]] == ["Raking light", "Normals"]
    assert _run(["presets", "import", dataset, file, "--replace"], capsys)[0] == 0
    assert read_json(dataset / "presets.json") == extra


def test_remove_drops_the_entries_and_says_so(dataset: Path, tmp_path: Path,
                                             capsys: pytest.CaptureFixture[str]) -> None:
    file = tmp_path / "lib.json"
    file.write_text(json.dumps(small_library()))
    _run(["presets", "import", dataset, file], capsys)
    status, out, _ = _run(["presets", "remove", dataset, "uv"], capsys)
    assert status == 0
    assert out.strip().endswith("removed preset uv; also removed the entries that used it: "
                                "lens: UV lens")
    lib = read_json(dataset / "presets.json")
    assert set(lib["presets"]) == {"raking"} and lib["lens"] == []


def _unchanged(dataset: Path) -> tuple[str, bytes]:
    return os.readlink(dataset), (dataset / "lanterna.json").read_bytes()


@pytest.mark.parametrize(("argv", "message"), [
    (["add", "--id", "x", "--label", "X", "--layer", "ir", "--mode", "color"],
     "{ds}: presets.x.layer: no layer 'ir' in the dataset (layers: ptm, uv)"),
    (["add", "--id", "x", "--label", "X", "--layer", "uv", "--mode", "specular"],
     "{ds}: presets.x.mode: mode 'specular' does not apply to layer 'uv'"),
    (["add", "--id", "x", "--label", "X", "--layer", "ptm", "--mode", "color",
      "--param", "gamma=9"], "{ds}: presets.x.params.gamma: expected a number from 0.2 to 5"),
    (["add", "--id", "x", "--label", "X", "--layer", "ptm", "--mode", "color",
      "--light", "0.9,0.9"], "{ds}: presets.x.light: [0.9, 0.9] is outside the unit disk"),
    (["add", "--id", "x", "--label", "X", "--layer", "ptm", "--mode", "color",
      "--view", "0,0,97,10"], "{ds}: presets.x.view: [0, 0, 97, 10] is not within the image"),
    (["add", "--id", "x", "--label", "X", "--layer", "ptm", "--mode", "color",
      "--light", "0.5"], "--light wants LU,LV"),
    (["add", "--id", "x", "--label", "X", "--layer", "ptm", "--mode", "color",
      "--param", "gamma"], "--param wants NAME=VALUE"),
    (["add", "--id", "x", "--label", "X", "--layer", "ptm", "--mode", "color",
      "--opacity", "0.5"], "--opacity needs --lens"),
    (["add", "--id", "bad id", "--label", "X", "--layer", "ptm", "--mode", "color"],
     "{ds}: presets: key 'bad id': expected an id"),
    (["remove", "ghost"], "no preset 'ghost' (presets: none)"),
], ids=lambda v: v if isinstance(v, str) and v.startswith("{") else None)
def test_bad_input_is_one_line_and_changes_nothing(dataset: Path, argv: list[str],
                                                   message: str,
                                                   capsys: pytest.CaptureFixture[str]) -> None:
    before = _unchanged(dataset)
    status, out, err = _run(["presets", argv[0], dataset, *argv[1:]], capsys)
    assert status == 2 and out == ""
    assert err.count("\n") == 1
    assert err.startswith(f"lanterna: error: {message.format(ds=dataset)}"), err
    assert _unchanged(dataset) == before
    assert not (dataset / "presets.json").exists()


def test_a_bad_library_file_names_the_file_and_the_path(dataset: Path, tmp_path: Path,
                                                       capsys: pytest.CaptureFixture[str]) -> None:
    lib = small_library()
    lib["base"][0]["preset"] = "ghost"
    file = tmp_path / "lib.json"
    file.write_text(json.dumps(lib))
    before = _unchanged(dataset)
    for how in ([], ["--merge"]):
        status, _, err = _run(["presets", "import", dataset, file, *how], capsys)
        assert status == 2
        assert err == (f"lanterna: error: {file}: base[0].preset: no preset 'ghost' (presets: "
                       "raking, uv)\n")
        assert _unchanged(dataset) == before
    file.write_text('{"type": ')
    status, _, err = _run(["presets", "import", dataset, file], capsys)
    assert status == 2 and err.startswith(f"lanterna: error: {file}: not valid JSON")
    status, _, err = _run(["presets", "list", tmp_path], capsys)
    assert status == 2 and "not a Lanterna dataset" in err


def test_list_of_a_dataset_without_presets(dataset: Path,
                                           capsys: pytest.CaptureFixture[str]) -> None:
    status, out, _ = _run(["presets", "list", dataset], capsys)
    assert status == 0 and out.startswith("no presets")
