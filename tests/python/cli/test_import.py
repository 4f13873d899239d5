"""`lanterna import`: real PTMs to datasets; bad input leaves nothing behind."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import pyvips

from lanterna.cli import main
from lanterna.tiler.formats.ptm import read_ptm
from lanterna.tiler.iiif import geometry as geo
from lanterna.tiler.iiif import pyramid
from tests.python.fixtures.paths import shared_file
from tests.python.fixtures.plane_bound import assert_within_bound
from tests.python.fixtures.ptm import random_ptm_of_size
from tests.python.fixtures.ptm_writer import write_ptm
from tests.python.fixtures.publishing import leftovers


def test_help_lists_commands_with_examples() -> None:
    out = subprocess.run([sys.executable, "-m", "lanterna.cli", "--help"], capture_output=True,
                         text=True, check=True).stdout
    for word in ("import", "serve", "demo", "examples:", "lanterna import ushabti.ptm"):
        assert word in out


@pytest.mark.realdata
def test_import_real_ushabti_stores_the_ptm_bytes(tmp_path: Path) -> None:
    src = shared_file("realdata/chi-ushabti-vase/ushabti.ptm")
    assert main(["import", str(src), "-o", str(tmp_path / "ushabti"), "--plane-format", "png"]) == 0
    desc = json.loads((tmp_path / "ushabti/lanterna.json").read_text())
    assert (desc["width"], desc["height"]) == (512, 1024)
    layer = desc["layers"][0]["service"]
    assert layer["layerType"] == "ptm" and layer["colorspace"] == "lrgb"
    assert [p["channels"] for p in layer["planes"]] == [
        ["L0", "L1", "L2"], ["L3", "L4", "L5"], ["R", "G", "B"]]
    assert layer["planes"][0]["scale"] == [2.0, 2.0, 2.0]
    assert layer["planes"][0]["bias"][0] == pytest.approx(160 / 255)
    assert desc["layers"][0]["id"] == "ushabti"  # named after the file
    c1, color_id = (p["service"]["id"].rsplit("/", 1)[1] for p in layer["planes"][1:])
    ptm = read_ptm(src)
    tile = pyvips.Image.new_from_file(
        str(tmp_path / f"ushabti/iiif/{c1}/256,768,256,256/256,256/0/default.png")).numpy()
    np.testing.assert_array_equal(tile, ptm.coefficients[768:1024, 256:512, 3:6])
    assert ptm.rgb is not None
    color = pyvips.Image.new_from_file(
        str(tmp_path / f"ushabti/iiif/{color_id}/0,0,256,256/256,256/0/default.png")).numpy()
    np.testing.assert_array_equal(color, ptm.rgb[:256, :256])


@pytest.mark.parametrize("colorspace", ["lrgb", "rgb"])
def test_import_written_ptm_round_trips(tmp_path: Path, colorspace: str) -> None:
    ptm = random_ptm_of_size(70, 40, colorspace)
    src = tmp_path / "small.ptm"
    write_ptm(src, ptm, "PTM_FORMAT_RGB" if colorspace == "rgb" else "PTM_FORMAT_LRGB")
    assert main(["import", str(src), "-o", str(tmp_path / "out" / "small")]) == 0
    desc = json.loads((tmp_path / "out/small/lanterna.json").read_text())
    planes = desc["layers"][0]["service"]["planes"]
    assert len(planes) == (3 if colorspace == "lrgb" else 6)
    assert leftovers(tmp_path / "out") == ["small"]


BAD = {
    "truncated": lambda good: good[: len(good) - 7],
    "garbled": lambda good: good[:20] + b"\x00garbage\xff" * 5 + good[60:],
    "unknown format": lambda good: good.replace(b"PTM_FORMAT_LRGB", b"PTM_FORMAT_FOO", 1),
    "sizes": lambda good: good.replace(b"\n70\n40\n", b"\n71\n40\n", 1),
    "not a ptm": lambda good: b"hello world\n" * 5,
}


@pytest.mark.parametrize("case", sorted(BAD))
def test_bad_ptm_is_one_line_error_and_nothing_written(tmp_path: Path,
                                                        capsys: pytest.CaptureFixture[str],
                                                        case: str) -> None:
    good = tmp_path / "good.ptm"
    write_ptm(good, random_ptm_of_size(70, 40), "PTM_FORMAT_LRGB")
    bad = tmp_path / "bad.ptm"
    bad.write_bytes(BAD[case](good.read_bytes()))
    out = tmp_path / "out"
    assert main(["import", str(bad), "-o", str(out / "ds")]) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith(f"lanterna: error: {bad}: ")
    assert len(err.splitlines()) == 1
    assert "Traceback" not in err
    assert leftovers(out) == []


def test_failure_mid_write_leaves_nothing_and_keeps_previous(
        tmp_path: Path, monkeypatch: pytest.MonkeyPatch,
        capsys: pytest.CaptureFixture[str]) -> None:
    src = tmp_path / "a.ptm"
    write_ptm(src, random_ptm_of_size(64, 48), "PTM_FORMAT_LRGB")
    out = tmp_path / "out" / "a"
    assert main(["import", str(src), "-o", str(out)]) == 0
    before = (out / "lanterna.json").read_text()
    calls = {"n": 0}
    real = pyramid.write_pyramid

    def failing(*args: object, **kwargs: object) -> object:
        calls["n"] += 1
        if calls["n"] == 3:
            raise OSError("disk full (simulated)")
        return real(*args, **kwargs)  # type: ignore[arg-type]

    monkeypatch.setattr("lanterna.tiler.dataset.writer.write_pyramid", failing)
    capsys.readouterr()
    assert main(["import", str(src), "-o", str(out), "--force", "--label", "changed"]) == 2
    assert capsys.readouterr().err == (f"lanterna: error: {out}: cannot write (disk full "
                                       "(simulated)); nothing was changed\n")
    assert leftovers(out.parent) == ["a"]
    assert (out / "lanterna.json").read_text() == before


def test_existing_output_needs_force(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    src = tmp_path / "a.ptm"
    write_ptm(src, random_ptm_of_size(20, 20), "PTM_FORMAT_LRGB")
    assert main(["import", str(src), "-o", str(tmp_path / "a")]) == 0
    assert main(["import", str(src), "-o", str(tmp_path / "a")]) == 2
    assert "use --force" in capsys.readouterr().err
    assert main(["import", str(src), "-o", str(tmp_path / "a"), "--force", "--label", "B"]) == 0
    assert json.loads((tmp_path / "a/lanterna.json").read_text())["label"] == "B"


def test_missing_source_and_bad_tile_size(tmp_path: Path,
                                          capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["import", str(tmp_path / "nope.ptm"), "-o", str(tmp_path / "x")]) == 2
    assert "nope.ptm: no such file" in capsys.readouterr().err
    assert main(["import", str(tmp_path / "nope.ptm"), "-o", str(tmp_path / "x"),
                 "--tile-size", "3"]) == 2
    assert not (tmp_path / "x").exists()


@pytest.mark.realdata
def test_import_real_ushabti_auto_stores_lossy_planes_within_the_bound(tmp_path: Path) -> None:
    """The JPEG PTM's planes: lossy tiles within the stated bound of the reader's decode, and
    level 0 within the issue's 1.25x of the source file's bytes (measured 1.04x)."""
    src = shared_file("realdata/chi-ushabti-vase/ushabti.ptm")
    assert main(["import", str(src), "-o", str(tmp_path / "u")]) == 0
    layer = json.loads((tmp_path / "u/lanterna.json").read_text())["layers"][0]["service"]
    ptm = read_ptm(src)
    assert ptm.rgb is not None
    sources = [ptm.coefficients[..., 0:3], ptm.coefficients[..., 3:6], ptm.rgb]
    level0 = 0
    for plane, source in zip(layer["planes"], sources, strict=True):
        assert plane["format"] in ("jpg", "webp")
        folder = tmp_path / "u/iiif" / plane["service"]["id"].rsplit("/", 1)[1]
        errors = []
        for t in geo.spec_tiles(512, 1024, 256, 1):
            path = folder / geo.canonical_path(512, 1024, t) / "0" / f"default.{plane['format']}"
            level0 += path.stat().st_size
            got = pyvips.Image.new_from_file(str(path)).numpy().astype(np.int16)
            errors.append((got - source[t.y:t.y + t.h, t.x:t.x + t.w]).ravel())
        assert_within_bound(np.concatenate(errors))
    assert level0 <= 1.25 * src.stat().st_size


def test_plane_format_flag_sets_every_plane(tmp_path: Path) -> None:
    src = tmp_path / "small.ptm"
    write_ptm(src, random_ptm_of_size(300, 40), "PTM_FORMAT_LRGB")
    for flag, ext in (("jpg:80", "jpg"), ("webp", "webp"), ("png", "png")):
        out = tmp_path / ext
        assert main(["import", str(src), "-o", str(out), "--plane-format", flag]) == 0
        desc = json.loads((out / "lanterna.json").read_text())
        planes = desc["layers"][0]["service"]["planes"]
        assert [p["format"] for p in planes] == [ext] * 3
        ident = planes[0]["service"]["id"].rsplit("/", 1)[1]
        assert desc["images"][ident].get("quality") == (80 if ext == "jpg" else None)
        assert (out / f"iiif/{ident}/0,0,256,40/256,40/0/default.{ext}").is_file()
        assert desc["images"][desc["layers"][0]["body"]]["format"] == "jpg"  # the preview


def test_bad_plane_format_is_a_one_line_usage_error(tmp_path: Path,
                                                    capsys: pytest.CaptureFixture[str]) -> None:
    src = tmp_path / "small.ptm"
    write_ptm(src, random_ptm_of_size(70, 40), "PTM_FORMAT_LRGB")
    assert main(["import", str(src), "-o", str(tmp_path / "x"), "--plane-format", "gif"]) == 2
    assert capsys.readouterr().err == ("lanterna: error: --plane-format wants auto, png, webp or "
                                       "jpg[:Q] with Q in 1-100, got 'gif'\n")
    assert not (tmp_path / "x").exists()
