"""``lanterna demo`` rebuilds a demo dataset made by an older Lanterna (another edition)."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from lanterna.cli import main
from lanterna.tiler.demo import dataset
from lanterna.tiler.demo.dataset import DEMO_SOURCE, demo_is_current


def _fake_demo(folder: Path, source: str) -> Path:
    folder.mkdir(parents=True)
    (folder / "lanterna.json").write_text(json.dumps({"lanterna": 1, "source": source}))
    return folder


def test_only_a_demo_of_this_edition_is_current(tmp_path: Path) -> None:
    assert demo_is_current(_fake_demo(tmp_path / "now", DEMO_SOURCE))
    assert not demo_is_current(_fake_demo(tmp_path / "old", "synthetic"))
    assert not demo_is_current(tmp_path / "missing")
    (tmp_path / "broken").mkdir()
    (tmp_path / "broken" / "lanterna.json").write_text("{not json")
    assert not demo_is_current(tmp_path / "broken")


@pytest.mark.parametrize(("source", "rebuilt"), [("synthetic", True), (DEMO_SOURCE, False)])
def test_lanterna_demo_rebuilds_an_older_demo_only(tmp_path: Path, monkeypatch: pytest.MonkeyPatch,
                                                   capsys: pytest.CaptureFixture[str],
                                                   source: str, rebuilt: bool) -> None:
    _fake_demo(tmp_path / "demo", source)
    built: list[Path] = []

    def fake_build(out: Path, **_: object) -> Path:  # the real build takes minutes
        built.append(out)
        (out / "lanterna.json").write_text(json.dumps({"lanterna": 1, "source": DEMO_SOURCE}))
        return out

    monkeypatch.setattr(dataset, "build_demo", fake_build)
    monkeypatch.setattr("lanterna.commands.serve_cmd.print_written", lambda *a, **k: None)
    assert main(["demo", "--no-serve", "--root", str(tmp_path)]) == 0
    assert built == ([tmp_path / "demo"] if rebuilt else [])
    out = capsys.readouterr().out
    assert ("rebuilding (from an older Lanterna)" in out) == rebuilt
