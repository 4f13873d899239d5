"""The seed paper's scene description (JOCCH 2021 §4.3) imported as a dataset."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import pyvips

from lanterna.cli import main
from tests.python.fixtures.sources import random_image, read_desc, seed_scene


def test_seed_paper_scene_is_imported(tmp_path: Path) -> None:
    out = tmp_path / "scene"
    assert main(["import", str(seed_scene(tmp_path)), "-o", str(out)]) == 0
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
    ext = ptm["planes"][0]["format"]  # a PNG map: stored lossless (PNG or WebP)
    assert ext in ("png", "webp")
    stored = pyvips.Image.new_from_file(str(out / f"iiif/{first}/full/max/0/default.{ext}"))
    np.testing.assert_array_equal(stored.numpy(), random_image(30))  # the file's own bytes
    assert uv["service"]["layerType"] == "svbrdf"
    assert uv["service"]["glossLimits"] == [0.01, 0.5]
    assert [p["channels"][0] for p in uv["service"]["planes"]] == ["NX", "KD_R", "KS_R", "GLOSS"]
    n_uv = uv["service"]["planes"][0]["service"]["id"]
    assert shape["service"]["planes"][0]["service"]["id"] == n_uv  # shared by URI matching


def test_scene_with_unknown_shader_type_is_refused(tmp_path: Path,
                                                   capsys: pytest.CaptureFixture[str]) -> None:
    path = seed_scene(tmp_path, shader_type="BRDF_MAGIC")
    assert main(["import", str(path), "-o", str(tmp_path / "out" / "s")]) == 2
    err = capsys.readouterr().err.strip()
    assert err.endswith("scene.json: layers[0].obj.shader.type: expected a shader type: LRGB_PTM "
                        "or SVBRDF (got 'BRDF_MAGIC')")
    assert len(err.splitlines()) == 1
    assert not (tmp_path / "out").exists()
