"""``lanterna annotate export`` and ``import`` from the command line."""

from __future__ import annotations

import json
import os
from pathlib import Path

import pytest

from lanterna.cli import main
from lanterna.tiler.overlays import store
from tests.python.fixtures.overlays import make_dataset
from tests.python.manifests.w3c_rules import w3c_errors
from tests.python.overlays.w3c_pages import annotorious_page


def test_import_then_export(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    dataset = make_dataset(tmp_path / "root")
    page = tmp_path / "annotorious.json"
    page.write_text(json.dumps(annotorious_page()))
    assert main(["annotate", "import", str(dataset), "--layer", "vis", str(page)]) == 0
    assert capsys.readouterr().out == (
        f"layer vis: 3 patch(es) from {page} at level(s) 0; overlay rebuilt\n")
    assert len(store.list_patches(dataset, "vis")) == 3
    out = tmp_path / "notes.json"
    assert main(["annotate", "export", str(dataset), "--layer", "vis", "-o", str(out)]) == 0
    assert capsys.readouterr().out == f"wrote {out} (3 annotation(s) of layer vis)\n"
    exported = json.loads(out.read_text())
    assert exported == json.loads((dataset / "annotations" / "vis.json").read_text())
    assert w3c_errors(exported) == []
    assert [a["creator"]["name"] for a in exported["items"] if "creator" in a] == [
        "Ada Conservator", "https://example.org/users/7"]


def test_a_bad_page_is_one_line_and_exit_2(tmp_path: Path,
                                           capsys: pytest.CaptureFixture[str]) -> None:
    dataset = make_dataset(tmp_path / "root")
    doc = annotorious_page()
    doc["items"][1]["target"]["selector"]["value"] = "<svg><path d='M0 0 A 1 1 0 0 1 9 9'/></svg>"
    page = tmp_path / "bad.json"
    page.write_text(json.dumps(doc))
    version = os.path.realpath(dataset)
    assert main(["annotate", "import", str(dataset), "--layer", "vis", str(page)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1
    assert err.startswith(f"lanterna: error: {page}: items[1].target.selector.value: ")
    assert not store.store_dir(dataset, "vis").exists()
    assert os.path.realpath(dataset) == version


def test_export_of_an_unknown_layer(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    dataset = make_dataset(tmp_path / "root")
    out = tmp_path / "x.json"
    assert main(["annotate", "export", str(dataset), "--layer", "ir", "-o", str(out)]) == 2
    assert "no layer 'ir' (layers: vis, uv)" in capsys.readouterr().err
    assert not out.exists()
