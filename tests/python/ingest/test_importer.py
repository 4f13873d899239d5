"""Multi-layer datasets: several sources, description files, spectral bands."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
import pyvips
from flask.testing import FlaskClient

from lanterna.cli import main
from lanterna.server.app import create_app
from tests.python.fixtures.ptm import random_ptm_of_size
from tests.python.fixtures.ptm_writer import write_ptm
from tests.python.fixtures.sources import (
    H,
    W,
    manifest_items,
    png,
    random_image,
    random_normal_map,
    read_desc,
)


def test_several_sources_become_layers_in_order(tmp_path: Path) -> None:
    write_ptm(tmp_path / "vis.ptm", random_ptm_of_size(W, H), "PTM_FORMAT_LRGB")
    png(tmp_path / "uv.png", random_image(1))
    out = tmp_path / "out" / "obj"
    sources = [str(tmp_path / "vis.ptm"), str(tmp_path / "uv.png")]
    assert main(["import", *sources, "-o", str(out)]) == 0
    desc = read_desc(out)
    assert [layer["id"] for layer in desc["layers"]] == ["vis", "uv"]
    assert [layer["service"]["layerType"] for layer in desc["layers"]] == ["ptm", "image"]
    items = manifest_items(out)
    assert [i["label"]["en"][0] for i in items] == [layer["label"] for layer in desc["layers"]]
    assert items[0]["service"][1]["layerType"] == "ptm"  # the first item is the default layer


def test_layers_must_be_co_registered(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    write_ptm(tmp_path / "vis.ptm", random_ptm_of_size(W, H), "PTM_FORMAT_LRGB")
    png(tmp_path / "small.png", np.zeros((H, W - 1, 3), np.uint8))
    out = tmp_path / "out"
    assert main(["import", str(tmp_path / "vis.ptm"), str(tmp_path / "small.png"), "-o",
                 str(out / "x")]) == 2
    err = capsys.readouterr().err
    assert "small.png: is 95x64, but vis.ptm is 96x64" in err
    assert not out.exists() or list(out.iterdir()) == []


def _five_materials(tmp_path: Path) -> Path:
    png(tmp_path / "N.png", random_normal_map(0))
    layers = []
    for i in range(5):
        png(tmp_path / f"kd{i}.png", random_image(10 + i))
        layers.append({"id": f"mat{i}", "type": "svbrdf",
                       "maps": {"normals": "N.png", "kd": f"kd{i}.png"}})
    desc = tmp_path / "object.json"
    desc.write_text(json.dumps({"name": "five", "label": "Five materials", "layers": layers}))
    return desc


def test_shared_normal_map_is_stored_and_served_once(tmp_path: Path) -> None:
    out = tmp_path / "root" / "five"
    assert main(["import", str(_five_materials(tmp_path)), "-o", str(out)]) == 0
    desc = read_desc(out)
    normal_ids = {p["service"]["id"] for layer in desc["layers"]
                  for p in layer["service"]["planes"] if p["channels"][0] == "NX"}
    assert len(desc["layers"]) == 5 and len(normal_ids) == 1
    stored = sorted(p.name for p in (out / "iiif").iterdir())
    assert sum("normals" in s for s in stored) == 1
    assert sum("kd" in s for s in stored) == 5
    client: FlaskClient = create_app({"DATA_ROOT": out.parent}).test_client()
    ident = normal_ids.pop().rsplit("/", 1)[1]
    info = client.get(f"/datasets/five/iiif/{ident}/info.json").get_json()
    assert info["id"] == f"http://localhost/datasets/five/iiif/{ident}"
    ext = json.loads((out / "lanterna.json").read_text())["images"][ident]["format"]
    assert ext in ("png", "webp")  # PNG maps are stored lossless
    with client.get(f"/datasets/five/iiif/{ident}/full/max/0/default.{ext}") as resp:
        tile = pyvips.Image.new_from_buffer(resp.data, "").numpy()
    np.testing.assert_array_equal(tile, random_normal_map(0))


def test_bands_and_false_colour_fusion(tmp_path: Path) -> None:
    bands = {name: png(tmp_path / f"{name}.png", random_image(20 + i, 1))
             for i, name in enumerate(("IR", "R", "G"))}
    out = tmp_path / "ms"
    args = ["import", "-o", str(out), "--fusion", "IR,R,G"]
    for name, path in bands.items():
        args += ["--band", f"{name}={path}"]
    assert main(args) == 0
    desc = read_desc(out)
    assert [layer["id"] for layer in desc["layers"]] == ["IR", "R", "G", "fc_IR_R_G"]
    assert desc["layers"][0]["service"]["planes"][0]["channels"] == ["Y"]
    fused = pyvips.Image.new_from_file(
        str(out / "iiif/fc_IR_R_G/full/max/0/default.png")).numpy()
    expected = np.stack([random_image(20, 1), random_image(21, 1), random_image(22, 1)], axis=-1)
    np.testing.assert_array_equal(fused, expected)


def test_fusion_of_unknown_band_is_an_error(tmp_path: Path,
                                            capsys: pytest.CaptureFixture[str]) -> None:
    png(tmp_path / "ir.png", random_image(1, 1))
    assert main(["import", "-o", str(tmp_path / "x"), "--band", f"IR={tmp_path / 'ir.png'}",
                 "--fusion", "IR,R,G"]) == 2
    assert "unknown band(s) R, G" in capsys.readouterr().err
    assert not (tmp_path / "x").exists()


def test_maps_of_different_sizes_are_refused(tmp_path: Path,
                                             capsys: pytest.CaptureFixture[str]) -> None:
    png(tmp_path / "N.png", random_normal_map(0))
    png(tmp_path / "kd.png", np.zeros((H + 2, W, 3), np.uint8))
    desc = tmp_path / "d.json"
    desc.write_text(json.dumps({"layers": [{"id": "m", "type": "svbrdf",
                                            "maps": {"normals": "N.png", "kd": "kd.png"}}]}))
    assert main(["import", str(desc), "-o", str(tmp_path / "out" / "m")]) == 2
    err = capsys.readouterr().err
    assert "kd.png: map kd is 96x66, map normals is 96x64" in err
    assert not (tmp_path / "out").exists()


@pytest.mark.parametrize(("layers", "problem"), [
    ([], "d.json: layers: expected a non-empty list of layers"),
    ([{"id": "x", "type": "volumetric", "source": "a.ptm"}],
     "d.json: layers[0].type: expected a layer type: source, ptm, hsh, image, svbrdf or bands "
     "(got 'volumetric')"),
    ([{"id": "x", "type": "svbrdf", "maps": {"normals": "N.png", "albedo": "a.png"}}],
     "d.json: layers[0].maps: key 'albedo': expected a map name"),
    ([{"id": "x", "source": "missing.ptm"}], "missing.ptm: no such file"),
])
def test_bad_descriptions(tmp_path: Path, capsys: pytest.CaptureFixture[str], layers: list,
                          problem: str) -> None:
    desc = tmp_path / "d.json"
    desc.write_text(json.dumps({"layers": layers}))
    assert main(["import", str(desc), "-o", str(tmp_path / "out" / "d")]) == 2
    assert problem in capsys.readouterr().err
    assert not (tmp_path / "out").exists()


def test_depth_map_keeps_its_range(tmp_path: Path) -> None:
    png(tmp_path / "N.png", random_normal_map(0))
    depth = np.linspace(2.5, 7.5, W * H, dtype=np.float32).reshape(H, W)
    pyvips.Image.new_from_array(depth).tiffsave(str(tmp_path / "z.tif"))
    desc = tmp_path / "d.json"
    desc.write_text(json.dumps({"layers": [{"id": "m", "type": "svbrdf",
                                            "maps": {"normals": "N.png", "depth": "z.tif"}}]}))
    out = tmp_path / "depth"
    assert main(["import", str(desc), "-o", str(out)]) == 0
    plane = read_desc(out)["layers"][0]["service"]["planes"][1]
    assert plane["channels"] == ["DEPTH"]
    scale, bias = plane["scale"][0], plane["bias"][0]
    # (t − bias)·scale spans the source's depths: t = 0 → 2.5, t = 1 → 7.5
    assert (0 - bias) * scale == pytest.approx(2.5, abs=1e-5)
    assert (1 - bias) * scale == pytest.approx(7.5, abs=1e-5)
