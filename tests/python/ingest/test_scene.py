"""The seed paper's scene description (JOCCH 2021 §4.3) imported as a dataset."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
import pyvips

from lanterna.cli import main
from tests.python.fixtures.sources import H, W, png, random_image, random_normal_map, read_desc


def _seed_scene(tmp_path: Path, shader_type: str = "LRGB_PTM") -> Path:
    (tmp_path / "vis").mkdir()
    (tmp_path / "shared").mkdir()
    for k in range(3):  # templates L1.png, L2.png, L3.png → level-00 files L100.png …
        png(tmp_path / f"L{k + 1}00.png", random_image(30 + k))
    png(tmp_path / "vis/kdMap00.png", random_image(40))
    png(tmp_path / "vis/ksMap00.png", random_image(41))
    png(tmp_path / "vis/glossMap00.png", random_image(42, 1))
    png(tmp_path / "shared/N00.png", random_normal_map(3))
    scene = {
        "name": "Sample dataset", "info": "<h1>Sample</h1>", "width": W, "height": H,
        "layers": [
            {"id": "VIS", "name": "Visible",
             "obj": {"shader": {"type": shader_type, "scale": [2, 2, 2, 2, 2, 2],
                                "bias": [164, 166, 101, 87, 78, 0]},
                     "maps": {"coeff_0_1_2": "L1.png", "coeff_3_4_5": "L2.png",
                              "coeff_6_7_8": "L3.png"}},
             "overlay": {"img": "vis/overlay.png", "range": [0, 3],
                         "shortInfo": ["a", "b", "c", "d"], "longInfo": ["A", "B", "C", "D"]}},
            {"id": "UV1", "name": "UV (385nm) + Fluorescence",
             "obj": {"shader": {"type": "SVBRDF", "glossLimits": [0.01, 0.5],
                                "inputColorSpace": "linear"},
                     "maps": {"kd": "vis/kdMap.png", "ks": "vis/ksMap.png",
                              "gloss": "vis/glossMap.png", "N": "shared/N.png"}}},
            {"id": "N", "name": "Shape", "obj": {"shader": {"type": "SVBRDF"},
                                                  "maps": {"N": "shared/N.png"}}},
        ],
    }
    path = tmp_path / "scene.json"
    path.write_text(json.dumps(scene))
    return path


def test_seed_paper_scene_is_imported(tmp_path: Path) -> None:
    out = tmp_path / "scene"
    assert main(["import", str(_seed_scene(tmp_path)), "-o", str(out)]) == 0
    desc = read_desc(out)
    assert desc["label"] == "Sample dataset" and desc["summary"] == "<h1>Sample</h1>"
    vis, uv, shape = desc["layers"]
    assert (vis["id"], vis["label"]) == ("VIS", "Visible")
    assert vis["overlay"]["range"] == [0, 3]  # kept for the annotation viewer
    ptm = vis["service"]
    assert ptm["layerType"] == "ptm" and ptm["colorspace"] == "lrgb"
    assert ptm["planes"][1]["bias"] == pytest.approx([87 / 255, 78 / 255, 0.0])
    assert ptm["planes"][0]["scale"] == [2.0, 2.0, 2.0]
    first = ptm["planes"][0]["service"]["id"].rsplit("/", 1)[1]
    stored = pyvips.Image.new_from_file(str(out / f"iiif/{first}/full/max/0/default.png"))
    np.testing.assert_array_equal(stored.numpy(), random_image(30))  # the file's own bytes
    assert uv["service"]["layerType"] == "svbrdf"
    assert uv["service"]["glossLimits"] == [0.01, 0.5]
    assert [p["channels"][0] for p in uv["service"]["planes"]] == ["NX", "KD_R", "KS_R", "GLOSS"]
    n_uv = uv["service"]["planes"][0]["service"]["id"]
    assert shape["service"]["planes"][0]["service"]["id"] == n_uv  # shared by URI matching


def test_scene_with_unknown_shader_type_is_refused(tmp_path: Path,
                                                   capsys: pytest.CaptureFixture[str]) -> None:
    path = _seed_scene(tmp_path, shader_type="BRDF_MAGIC")
    assert main(["import", str(path), "-o", str(tmp_path / "out" / "s")]) == 2
    err = capsys.readouterr().err.strip()
    assert err.endswith("scene.json: layers[0].obj.shader.type: expected a shader type: LRGB_PTM "
                        "or SVBRDF (got 'BRDF_MAGIC')")
    assert len(err.splitlines()) == 1
    assert not (tmp_path / "out").exists()
