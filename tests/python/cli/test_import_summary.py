"""What ``lanterna import`` (and fit, demo --no-serve) prints at the end: the dataset made, read
back from its ``lanterna.json``, and the command to run next."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import pytest

from lanterna.cli import main
from lanterna.commands.summary import print_written, summary
from tests.python.fixtures.ptm import random_ptm_of_size
from tests.python.fixtures.ptm_writer import write_ptm


def _layer(layer_id: str, layer_type: str, channels: list[list[str]],
           **fields: Any) -> dict[str, Any]:
    service = {"layerType": layer_type, "width": 640, "height": 480, **fields,
               "planes": [{"channels": c} for c in channels]}
    return {"id": layer_id, "label": layer_id.upper(), "service": service}


DESC: dict[str, Any] = {
    "name": "tablet", "label": "A tablet", "width": 640, "height": 480,
    "images": {"a": {"tiff": "tiff/a.tif"}, "b": {"tiff": "tiff/b.tif"}, "c": {}},
    "layers": [
        {**_layer("vis", "ptm", [["L0", "L1", "L2"], ["L3", "L4", "L5"], ["R", "G", "B"]],
                  colorspace="lrgb"),
         "overlay": {"levels": [{"level": 0}, {"level": 2}], "patches": [{}, {}, {}]}},
        _layer("hsh", "hsh", [["R0", "G0", "B0"]] * 9, terms=9),
        _layer("shape", "svbrdf", [["NX", "NY", "NZ"], ["KD_R", "KD_G", "KD_B"], ["GLOSS"]]),
        _layer("ir", "image", [["Y"]]),
        _layer("fc", "image", [["R", "G", "B"]]),
    ],
}


def test_summary_names_the_dataset_and_each_layer() -> None:
    head, *layers, tiffs = summary(DESC)
    assert head == 'dataset tablet "A tablet", 640×480, 5 layers:'
    assert [line.split()[:3] for line in layers] == [
        ["vis", "PTM", "LRGB"], ["hsh", "HSH", "9"], ["shape", "SVBRDF", "normals+kd+gloss"],
        ["ir", "image", "grey"], ["fc", "image", "RGB"]]
    assert all("640×480" in line for line in layers)
    assert layers[0].endswith("3 images  annotations: 2 levels, 3 patches")
    assert layers[3].endswith("1 image")
    assert "annotations" not in " ".join(layers[1:])
    assert tiffs == "  2 pyramidal TIFFs in tiff/, served by the IIIF image server at /iiif/3/"


def test_summary_without_tiffs_or_overlays_has_a_line_per_layer() -> None:
    desc = {**DESC, "images": {"c": {}}, "layers": DESC["layers"][1:2]}
    lines = summary(desc)
    assert len(lines) == 2 and lines[0].endswith("1 layer:")
    assert lines[1].split() == ["hsh", "HSH", "9", "terms", "640×480", "9", "images"]


def test_summary_shows_each_layers_plane_formats() -> None:
    planes = [{"channels": ["R0", "G0", "B0"], "format": f,
               "service": {"id": f"http://h/d/iiif/hsh_t{k}"}}
              for k, f in enumerate(["webp", "jpg", "webp"])]
    desc = {**DESC, "images": {"hsh_t0": {"quality": 60}, "hsh_t1": {"quality": 85},
                               "hsh_t2": {"quality": 60}},
            "layers": [{"id": "hsh", "label": "H", "service": {
                "layerType": "hsh", "terms": 3, "width": 640, "height": 480, "planes": planes}}]}
    assert summary(desc)[1].split()[-3:] == ["3", "images", "jpg:85+webp:near60"]


def test_import_prints_the_summary_and_the_next_command(
        tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    src = tmp_path / "small.ptm"
    write_ptm(src, random_ptm_of_size(120, 80), "PTM_FORMAT_LRGB")
    out = tmp_path / "my datasets" / "small"
    assert main(["import", str(src), "--tiff", "-o", str(out)]) == 0
    lines = capsys.readouterr().out.splitlines()
    assert lines[0] == f'wrote {out}: dataset small "small", 120×80, 1 layer:'
    assert lines[1].split()[:4] == ["small", "PTM", "LRGB", "120×80"]
    assert lines[1].split()[4:6] == ["3", "images"]
    assert lines[1].split()[6] in ("png", "webp", "png+webp")  # the plane formats auto chose
    assert lines[2].startswith("  4 pyramidal TIFFs in tiff/")
    assert lines[3].startswith(f"next: lanterna serve '{tmp_path / 'my datasets'}' ")
    assert len(lines) == 4


def test_the_short_form_is_the_headline_alone(tmp_path: Path,
                                             capsys: pytest.CaptureFixture[str]) -> None:
    src = tmp_path / "small.ptm"
    write_ptm(src, random_ptm_of_size(64, 64), "PTM_FORMAT_LRGB")
    assert main(["import", str(src), "-o", str(tmp_path / "small")]) == 0
    capsys.readouterr()
    print_written(tmp_path / "small", details=False)
    assert capsys.readouterr().out == (f'wrote {tmp_path / "small"}: dataset small "small", '
                                       "64×64, 1 layer\n")
