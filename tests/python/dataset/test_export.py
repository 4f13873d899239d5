"""``lanterna export``: ids rewritten everywhere, other files identical (hard links), atomic writes.

The official IIIF validators on exported trees are in test_export_validator.py (Image API,
plain static server) and test_manifest_schema.py (Presentation 3.0 schema).
"""

from __future__ import annotations

import hashlib
import json
import os
import shutil
from pathlib import Path
from typing import Any

import numpy as np
import pytest
import pyvips

from lanterna.cli import main
from lanterna.errors import LanternaInputError
from lanterna.manifests.validate import validate_manifest
from lanterna.tiler.dataset import export as export_mod
from lanterna.tiler.dataset.export import export, rebase
from lanterna.tiler.dataset.layers import add_image_layer
from lanterna.tiler.dataset.writer import DatasetWriter
from tests.python.fixtures.dataset_kinds import BASE, KINDS, build_kinds

NEW = "https://cdn.example.net/iiif/v2"


@pytest.fixture(scope="module")
def root(tmp_path_factory: pytest.TempPathFactory) -> Path:
    folder = tmp_path_factory.mktemp("export") / "root"
    build_kinds(folder)
    return folder


@pytest.fixture(scope="module")
def exported(root: Path) -> Path:
    out = root.parent / "site"
    assert main(["export", str(root), "--base-url", NEW + "/", "-o", str(out)]) == 0
    return out


def files(folder: Path) -> dict[str, Path]:
    return {str(p.relative_to(folder)): p for p in sorted(folder.rglob("*")) if p.is_file()}


def digest(folder: Path) -> dict[str, str]:
    return {rel: hashlib.sha256(p.read_bytes()).hexdigest() for rel, p in files(folder).items()}


def test_every_dataset_is_exported_with_the_same_files(root: Path, exported: Path) -> None:
    assert sorted(p.name for p in exported.iterdir()) == sorted(KINDS)
    for kind in KINDS:
        assert files(exported / kind).keys() == files(root / kind).keys()


def test_no_json_keeps_the_old_base_url(root: Path, exported: Path) -> None:
    # every document of the datasets (not the patch stores beside them: records, level texts)
    assert all(BASE in p.read_text() for kind in KINDS for p in (root / kind).rglob("*.json"))
    documents = [p for p in exported.rglob("*.json")]
    assert len(documents) > 50
    for doc in documents:
        text = doc.read_text()
        assert BASE not in text, doc
        json.loads(text)


def test_json_documents_are_the_originals_rebased(root: Path, exported: Path) -> None:
    for kind in KINDS:
        for rel, src in files(root / kind).items():
            if rel.endswith(".json"):
                want = rebase(json.loads(src.read_text()), BASE, NEW)
                assert json.loads((exported / kind / rel).read_text()) == want, rel


def test_ids_point_into_the_new_tree(exported: Path) -> None:
    for kind in KINDS:
        ds = exported / kind
        desc = json.loads((ds / "lanterna.json").read_text())
        assert desc["baseUrl"] == NEW
        manifest = json.loads((ds / "manifest.json").read_text())
        assert manifest["id"] == f"{NEW}/{kind}/manifest.json"
        assert validate_manifest(manifest) == []
        for info in ds.glob("iiif/*/info.json"):
            assert json.loads(info.read_text())["id"] == f"{NEW}/{kind}/iiif/{info.parent.name}"
        for layer in desc["layers"]:
            service = json.loads((ds / "layers" / f"{layer['id']}.json").read_text())
            assert service["id"] == f"{NEW}/{kind}/layers/{layer['id']}.json"
            for plane in service["planes"]:
                ident = plane["service"]["id"].removeprefix(f"{NEW}/{kind}/iiif/")
                assert (ds / "iiif" / ident / "info.json").is_file()
    pages = json.loads((exported / "overlay/manifest.json").read_text())["items"][0]["annotations"]
    body = pages[0]["items"][0]["body"][0]
    assert body["id"].startswith(f"{NEW}/overlay/iiif/vis_ov0/")
    assert body["service"][1]["id"] == f"{NEW}/overlay/layers/vis.json#overlay-0"


def test_other_files_are_hard_links_to_the_originals(root: Path, exported: Path) -> None:
    checked = 0
    for kind in KINDS:
        for rel, src in files(root / kind).items():
            if not rel.endswith(".json"):
                dst = exported / kind / rel
                assert dst.read_bytes() == src.read_bytes()
                assert os.path.samefile(src, dst), rel
                checked += 1
    assert checked > 100


def test_export_leaves_the_source_untouched(root: Path, tmp_path: Path) -> None:
    before = digest(root)
    assert main(["export", str(root / "hsh"), "--base-url", NEW, "-o", str(tmp_path / "a")]) == 0
    assert digest(root) == before
    assert [p.name for p in (tmp_path / "a").iterdir()] == ["hsh"]


def test_a_re_export_moves_the_tree_again(exported: Path, tmp_path: Path) -> None:
    again = "http://127.0.0.1:9000/mirror"
    report = export(exported, tmp_path / "b", again)
    assert report.manifests["hsh"] == f"{again}/hsh/manifest.json"
    for doc in (tmp_path / "b").rglob("*.json"):
        assert NEW not in doc.read_text() and BASE not in doc.read_text()


def test_with_viewer_copies_it_and_writes_an_index(root: Path, tmp_path: Path) -> None:
    viewer = tmp_path / "built"
    (viewer / "assets").mkdir(parents=True)
    (viewer / "index.html").write_text("<!doctype html>viewer")
    (viewer / "assets" / "app.js").write_text("//")
    report = export(root / "ptm_rgb", tmp_path / "c", NEW, viewer=viewer)
    assert report.viewer == f"{NEW}/viewer/"
    assert (tmp_path / "c/viewer/assets/app.js").read_text() == "//"
    index = (tmp_path / "c/index.html").read_text()
    assert f'href="viewer/?manifest={NEW}/ptm_rgb/manifest.json"' in index


def test_rebase_replaces_whole_prefixes_only() -> None:
    doc: Any = {"a": "http://h/b", "b": ["http://h/b/x", "http://h/bc/x", "see http://h/b/y"],
                "c": 3, "d": None}
    assert rebase(doc, "http://h/b", "https://n") == {
        "a": "https://n", "b": ["https://n/x", "http://h/bc/x", "see https://n/y"],
        "c": 3, "d": None}


def one_line_error(capsys: pytest.CaptureFixture[str], argv: list[str]) -> str:
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.startswith("lanterna: error: "), err
    return err


@pytest.mark.parametrize("url", ["ftp://example.org/x", "/datasets", "example.org/iiif",
                                 "https://example.org/x?a=1", "https://example.org/x#f", ""])
def test_a_bad_base_url_is_refused(root: Path, tmp_path: Path,
                                   capsys: pytest.CaptureFixture[str], url: str) -> None:
    err = one_line_error(capsys, ["export", str(root / "hsh"), "--base-url", url,
                                  "-o", str(tmp_path / "out")])
    assert "--base-url must be an absolute http(s) URL" in err
    assert list(tmp_path.iterdir()) == []


def test_missing_or_non_dataset_inputs_are_refused(tmp_path: Path,
                                                   capsys: pytest.CaptureFixture[str]) -> None:
    out = str(tmp_path / "out")
    err = one_line_error(capsys, ["export", str(tmp_path / "nope"), "--base-url", NEW, "-o", out])
    assert "no such folder" in err
    (tmp_path / "empty").mkdir()
    err = one_line_error(capsys, ["export", str(tmp_path / "empty"), "--base-url", NEW, "-o", out])
    assert "not a Lanterna dataset or data root" in err
    (tmp_path / "file.json").write_text("{}")
    err = one_line_error(capsys, ["export", str(tmp_path / "file.json"), "--base-url", NEW,
                                  "-o", out])
    assert "not a folder" in err
    (tmp_path / "bad").mkdir()
    (tmp_path / "bad/lanterna.json").write_text("{not json")
    err = one_line_error(capsys, ["export", str(tmp_path / "bad"), "--base-url", NEW, "-o", out])
    assert "not valid JSON" in err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["bad", "empty", "file.json"]


def test_an_existing_output_needs_force(root: Path, tmp_path: Path,
                                       capsys: pytest.CaptureFixture[str]) -> None:
    out = tmp_path / "out"
    out.mkdir()
    (out / "keep.txt").write_text("mine")
    err = one_line_error(capsys, ["export", str(root / "hsh"), "--base-url", NEW, "-o", str(out)])
    assert "output exists (use --force to replace it)" in err
    assert [p.name for p in out.iterdir()] == ["keep.txt"]
    assert main(["export", str(root / "hsh"), "--base-url", NEW, "-o", str(out), "--force"]) == 0
    assert [p.name for p in out.iterdir()] == ["hsh"]
    assert [p.name for p in tmp_path.iterdir()] == ["out"]  # no temporary folder left


def test_the_output_may_not_overlap_the_source(root: Path,
                                              capsys: pytest.CaptureFixture[str]) -> None:
    for out in (root, root / "hsh" / "site", root.parent):
        err = one_line_error(capsys, ["export", str(root / "hsh"), "--base-url", NEW,
                                      "-o", str(out), "--force"])
        assert "the output may not contain, or be inside" in err
    assert (root / "hsh" / "lanterna.json").is_file() and not (root / "hsh" / "site").exists()


def test_a_failure_half_way_leaves_nothing(root: Path, tmp_path: Path,
                                           monkeypatch: pytest.MonkeyPatch) -> None:
    out = tmp_path / "out"
    out.mkdir()
    (out / "keep.txt").write_text("previous export")
    calls = []

    def failing(src: Path, dst: Path) -> bool:
        calls.append(src)
        if len(calls) == 40:
            raise OSError(28, "No space left on device")
        os.link(src, dst)
        return True

    monkeypatch.setattr(export_mod, "link_or_copy", failing)
    with pytest.raises(LanternaInputError) as err:
        export(root, out, NEW, force=True)
    assert str(err.value) == f"{out}: cannot write (No space left on device); nothing was changed"
    assert len(calls) == 40
    assert [p.name for p in tmp_path.iterdir()] == ["out"]
    assert [p.name for p in out.iterdir()] == ["keep.txt"]


def test_two_datasets_with_one_name_are_refused(root: Path, tmp_path: Path,
                                                capsys: pytest.CaptureFixture[str]) -> None:
    twin = tmp_path / "root"
    twin.mkdir()
    for copy in ("a", "b"):
        assert main(["export", str(root / "hsh"), "--base-url", NEW, "-o", str(tmp_path / copy)
                     ]) == 0
        (tmp_path / copy / "hsh").rename(twin / copy)
    err = one_line_error(capsys, ["export", str(twin), "--base-url", NEW,
                                  "-o", str(tmp_path / "out")])
    assert "two datasets are named 'hsh'" in err
    assert not (tmp_path / "out").exists()


def test_files_are_copied_when_they_cannot_be_linked(root: Path, tmp_path: Path,
                                                     monkeypatch: pytest.MonkeyPatch) -> None:
    def cross_device(src: object, dst: object) -> None:
        raise OSError(18, "Invalid cross-device link")

    monkeypatch.setattr(export_mod.os, "link", cross_device)
    report = export(root / "svbrdf", tmp_path / "d", NEW)
    assert report.linked == 0 and report.copied > 20
    for rel, src in files(root / "svbrdf").items():
        dst = tmp_path / "d" / "svbrdf" / rel
        if not rel.endswith(".json"):
            assert dst.read_bytes() == src.read_bytes() and not os.path.samefile(src, dst)


def _one_image(out: Path, label: str, value: int) -> None:
    img = pyvips.Image.new_from_array(np.full((20, 30, 3), value, np.uint8))
    with DatasetWriter(out, name=out.name, label=label, width=30, height=20, force=True) as ds:
        add_image_layer(ds, img.copy(interpretation="srgb"), layer_id="pic", fmt="png")


def test_leftovers_are_not_exported_and_linked_datasets_become_folders(tmp_path: Path) -> None:
    data = tmp_path / "data"
    _one_image(data / "obj", "current", 1)
    stale = data / ".obj.old-20250101T000000_abcdef"
    shutil.copytree(data / "obj", stale)  # a half-deleted previous version
    (stale / "lanterna.json").write_text(
        (stale / "lanterna.json").read_text().replace('"current"', '"stale"'))
    site = tmp_path / "site"
    report = export(data, site, NEW)
    assert list(report.manifests) == ["obj"] and os.listdir(site) == ["obj"]
    assert (data / "obj").is_symlink() and not (site / "obj").is_symlink()
    assert json.loads((site / "obj/lanterna.json").read_text())["label"] == "current"
    assert all(not p.is_symlink() for p in (site / "obj").rglob("*"))


def test_an_export_reads_one_version_while_the_dataset_is_republished(
        tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    data = tmp_path / "data"
    _one_image(data / "obj", "old", 1)
    old = Path(os.path.realpath(data / "obj"))
    real = export_mod._rewrite_json
    republished: list[str] = []

    def rewrite_then_republish(*args: Any) -> None:
        real(*args)
        if not republished:  # half-way through the export, someone rewrites the dataset
            _one_image(data / "obj", "new", 2)
            republished.append(os.readlink(data / "obj"))

    monkeypatch.setattr(export_mod, "_rewrite_json", rewrite_then_republish)
    export(data, tmp_path / "site", NEW)
    assert republished and republished[0] != old.name
    site = tmp_path / "site" / "obj"
    assert json.loads((site / "lanterna.json").read_text())["label"] == "old"
    assert {p.read_bytes() for p in site.rglob("*.png")} == {p.read_bytes()
                                                             for p in old.rglob("*.png")}
    assert old.is_dir()  # kept for the export, then swept by the next write
    _one_image(data / "obj", "newer", 3)
    assert not old.exists()
