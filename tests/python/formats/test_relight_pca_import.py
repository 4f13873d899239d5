"""``lanterna import`` of Relight PCA folders: valid datasets whose blocks carry the basis.

The real coin outputs (../shared/realdata/relight-coin) and synthetic folders written by
:func:`tests.python.formats.test_relight_pca.pca_folder`; bad folders exit 2 with one line on
stderr and leave no dataset behind.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import numpy as np
import pytest
import pyvips

from lanterna.cli import main
from lanterna.manifests.validate import validate_manifest
from lanterna.tiler.formats.pca_model import PcaBasis
from lanterna.tiler.formats.relight_web import read_relight
from tests.python.fixtures.publishing import leftovers
from tests.python.formats.test_relight_pca import COIN, pca_folder
from tests.python.formats.test_relight_web import H, W


def relight_blocks(manifest: Any) -> list[dict[str, Any]]:
    """Every ``LanternaRelight`` service block of a manifest, in document order."""
    found: list[dict[str, Any]] = []

    def walk(node: Any) -> None:
        if isinstance(node, dict):
            if node.get("type") == "LanternaRelight":
                found.append(node)
                return
            for value in node.values():
                walk(value)
        elif isinstance(node, list):
            for value in node:
                walk(value)

    walk(manifest)
    return found


def check_dataset(ds: Path, layers: dict[str, PcaBasis]) -> None:
    """lanterna.json, layers/*.json and the manifest all carry each layer's basis unchanged."""
    manifest = json.loads((ds / "manifest.json").read_text())
    assert validate_manifest(manifest) == []
    desc = json.loads((ds / "lanterna.json").read_text())
    blocks = {b["id"].rsplit("/", 1)[1].removesuffix(".json"): b
              for b in relight_blocks(manifest)}
    assert sorted(blocks) == sorted(layers)
    for layer in desc["layers"]:
        want = layers[layer["id"]]
        doc = json.loads((ds / "layers" / f"{layer['id']}.json").read_text())
        for block in (layer["service"], doc, blocks[layer["id"]]):
            assert block["layerType"] == want.layer_type
            got = PcaBasis.from_block(block)
            np.testing.assert_array_equal(got.basis, want.basis)
            assert (got.ranges, got.lights, got.sigma, got.resolution, got.yccplanes) == (
                want.ranges, want.lights, want.sigma, want.resolution, want.yccplanes)
            assert [p["channels"] for p in block["planes"]][0] == ["P0", "P1", "P2"]


@pytest.mark.realdata
def test_import_real_relight_coin_rbf_and_bilinear(tmp_path: Path) -> None:
    folders = [COIN / "rbf27", COIN / "bilinear18"]
    if not all((f / "info.json").is_file() for f in folders):
        pytest.skip("../shared/realdata/relight-coin not present (read-only test data beside "
                    "the repo)")
    ds = tmp_path / "out" / "coin"
    assert main(["import", *map(str, folders), "-o", str(ds)]) == 0
    layers = {f.name: read_relight(f).pca for f in folders}
    check_dataset(ds, {k: v for k, v in layers.items() if v is not None})
    desc = json.loads((ds / "lanterna.json").read_text())
    assert [len(layer["service"]["planes"]) for layer in desc["layers"]] == [9, 6]
    assert leftovers(tmp_path / "out") == ["coin"]


@pytest.mark.parametrize(("rtype", "colorspace", "nplanes", "ycc"), [
    ("rbf", "mrgb", 7, None), ("bilinear", "mycc", 10, [4, 3, 3])])
def test_import_synthetic_pca_folder_keeps_the_plane_bytes(tmp_path: Path, rtype: str,
                                                           colorspace: str, nplanes: int,
                                                           ycc: list[int] | None) -> None:
    src = tmp_path / "src"
    _, planes, _ = pca_folder(src, rtype, colorspace, nplanes, seed=11, yccplanes=ycc,
                              in_json=rtype == "rbf")
    ds = tmp_path / "out" / "ds"
    assert main(["import", str(src), "-o", str(ds), "--plane-format", "png"]) == 0
    pca = read_relight(src).pca
    assert pca is not None
    check_dataset(ds, {"src": pca})
    desc = json.loads((ds / "lanterna.json").read_text())
    service = desc["layers"][0]["service"]
    assert service["nplanes"] == nplanes and service["colorspace"] == colorspace
    for g, plane in enumerate(service["planes"]):
        image = plane["service"]["id"].rsplit("/", 1)[1]
        assert plane["format"] == "png"
        tile = pyvips.Image.new_from_file(str(ds / f"iiif/{image}/full/max/0/default.png"),
                                          access="sequential").numpy()
        assert tile.shape == (H, W, 3)
        for k in range(3):
            q = 3 * g + k
            if q < nplanes:
                np.testing.assert_array_equal(tile[..., k], planes[q])


BAD_FOLDERS = {
    "basis length": lambda info: {**info, "basis": [1, 2, 3]},
    "unknown colorspace": lambda info: {**info, "colorspace": "lab"},
    "nplanes 49": lambda info: {**info, "nplanes": 49},
    "sigma": lambda info: {**info, "sigma": -1},
}


@pytest.mark.parametrize("case", sorted(BAD_FOLDERS))
def test_bad_pca_folder_is_one_line_and_nothing_is_written(
        tmp_path: Path, capsys: pytest.CaptureFixture[str], case: str) -> None:
    src = tmp_path / "src"
    info, _, _ = pca_folder(src, "rbf", "mrgb", 6)
    (src / "info.json").write_text(json.dumps(BAD_FOLDERS[case](info)))
    out = tmp_path / "out"
    assert main(["import", str(src), "-o", str(out / "ds")]) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith(f"lanterna: error: {src / 'info.json'}: "), err
    assert len(err.splitlines()) == 1 and "Traceback" not in err
    assert leftovers(out) == []


def test_truncated_materials_bin_import_fails_cleanly(tmp_path: Path,
                                                      capsys: pytest.CaptureFixture[str]) -> None:
    src = tmp_path / "src"
    pca_folder(src, "rbf", "mrgb", 6, in_json=False)
    (src / "materials.bin").write_bytes(b"\x7f" * 50)
    out = tmp_path / "out"
    assert main(["import", str(src), "-o", str(out / "ds")]) == 2
    err = capsys.readouterr().err.strip()
    assert err == (f"lanterna: error: {src / 'materials.bin'}: is 50 bytes; the basis is "
                   "(nplanes + 1)·ndimensions·3 = (6 + 1)·5·3 = 105 bytes")
    assert leftovers(out) == []
