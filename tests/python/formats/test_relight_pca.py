"""Relight PCA folders (``rbf`` / ``bilinear``, ``mrgb`` / ``mycc``) through the reader.

Folders are written here as Relight writes them (``src/cli/rtibuilder.cpp`` ``saveJSON``: the
basis in info.json, or — older outputs — in ``materials.bin``; ``yccplanes`` instead of
``nplanes`` for ``mycc``) and must read back to the same plane bytes, scale/bias and basis.
"""

from __future__ import annotations

import json
import os
from pathlib import Path
from typing import Any

import numpy as np
import numpy.typing as npt
import pytest

from lanterna.errors import LanternaInputError
from lanterna.tiler.formats.pca_model import PcaBasis
from lanterna.tiler.formats.relight_web import read_relight
from tests.python.fixtures.paths import SHARED
from tests.python.formats.test_relight_web import H, W, write_folder

COIN = SHARED / "realdata" / "relight-coin"
U8 = npt.NDArray[np.uint8]


def pca_folder(folder: Path, rtype: str, colorspace: str, nplanes: int, *, seed: int = 0,
               in_json: bool = True, yccplanes: list[int] | None = None,
               ndim: int = 5) -> tuple[dict[str, Any], U8, U8]:
    """Write a PCA folder (PNG planes); return its info, planes ``(N, H, W)`` and basis bytes."""
    rng = np.random.default_rng(seed)
    njpeg = (nplanes + 2) // 3
    stored = rng.integers(0, 256, (3 * njpeg, H, W), dtype=np.uint8)
    resolution = 3
    d = resolution * resolution if rtype == "bilinear" else ndim
    basis = rng.integers(0, 256, (nplanes + 1) * d * 3, dtype=np.uint8)
    info: dict[str, Any] = {
        "width": W, "height": H, "format": "png", "type": rtype, "colorspace": colorspace,
        "quality": 95,
        "materials": [{"range": [round(float(v), 3) for v in rng.uniform(100, 900, nplanes)],
                       "scale": [round(float(v), 4) for v in rng.uniform(2, 9, nplanes)],
                       "bias": [round(float(v), 4) for v in rng.uniform(0, 0.6, nplanes)]}]}
    lights = rng.normal(size=(max(ndim, 4), 3))
    lights[:, 2] = np.abs(lights[:, 2])
    lights /= np.linalg.norm(lights, axis=1, keepdims=True)
    info["lights"] = [round(float(v), 3) for v in lights[: ndim if rtype == "rbf" else 4].ravel()]
    if rtype == "rbf":
        info["sigma"] = 0.125
    else:
        info["resolution"] = resolution
    if yccplanes is None:
        info["nplanes"] = nplanes
    else:
        info["yccplanes"] = yccplanes  # Relight writes it instead of nplanes
    if in_json:
        info["basis"] = [int(v) for v in basis]
    write_folder(folder, info, stored)
    if not in_json:
        (folder / "materials.bin").write_bytes(basis.tobytes())
    return info, stored[:nplanes], basis


@pytest.mark.parametrize(("rtype", "nplanes"), [("rbf", 9), ("rbf", 7), ("bilinear", 8)])
@pytest.mark.parametrize("in_json", [True, False], ids=["basis-in-json", "materials-bin"])
def test_mrgb_reads_back_the_planes_and_the_basis(tmp_path: Path, rtype: str, nplanes: int,
                                                  in_json: bool) -> None:
    info, planes, basis = pca_folder(tmp_path, rtype, "mrgb", nplanes, seed=nplanes,
                                     in_json=in_json)
    layer = read_relight(tmp_path)
    assert (layer.layer_type, layer.colorspace, layer.width, layer.height) == (
        rtype, "mrgb", W, H)
    ngroups = (nplanes + 2) // 3
    assert layer.group_names == [f"p{g}" for g in range(ngroups)]
    names = [f"P{q}" if q < nplanes else f"X{q}" for q in range(3 * ngroups)]
    assert [g.channels for g in layer.groups] == [names[3 * g: 3 * g + 3] for g in range(ngroups)]
    got = np.concatenate([g.data.transpose(2, 0, 1) for g in layer.groups])
    np.testing.assert_array_equal(got[:nplanes], planes)  # the file's bytes, unchanged
    assert not got[nplanes:].any()
    mat = info["materials"][0]
    pad = 3 * ngroups - nplanes
    assert sum((g.scale for g in layer.groups), []) == mat["scale"] + [0.0] * pad
    assert sum((g.bias for g in layer.groups), []) == mat["bias"] + [0.0] * pad
    pca = layer.pca
    assert pca is not None
    np.testing.assert_array_equal(pca.basis, basis)
    assert list(pca.ranges) == mat["range"] and pca.nplanes == nplanes
    if rtype == "rbf":
        assert pca.lights == tuple(info["lights"]) and pca.sigma == 0.125
        assert pca.ndimensions == len(info["lights"]) // 3
    else:
        assert pca.resolution == 3 and pca.lights is None and pca.ndimensions == 9
    block = {"layerType": rtype, **layer.fields()}
    assert block["nplanes"] == nplanes and len(block["basis"]) == basis.size
    back = PcaBasis.from_block(json.loads(json.dumps(block)))
    np.testing.assert_array_equal(back.basis, pca.basis)
    assert (back.ranges, back.lights, back.sigma, back.resolution, back.yccplanes) == (
        pca.ranges, pca.lights, pca.sigma, pca.resolution, pca.yccplanes)


def test_basis_in_json_and_materials_bin_give_the_same_layer(tmp_path: Path) -> None:
    pca_folder(tmp_path / "a", "rbf", "mrgb", 6, seed=3, in_json=True)
    pca_folder(tmp_path / "b", "rbf", "mrgb", 6, seed=3, in_json=False)
    a, b = read_relight(tmp_path / "a"), read_relight(tmp_path / "b")
    assert a.fields() == b.fields()
    assert a.pca is not None and b.pca is not None
    np.testing.assert_array_equal(a.pca.weights(0.3, -0.2), b.pca.weights(0.3, -0.2))


@pytest.mark.parametrize("rtype", ["rbf", "bilinear"])
def test_mycc_takes_nplanes_from_yccplanes(tmp_path: Path, rtype: str) -> None:
    info, planes, basis = pca_folder(tmp_path, rtype, "mycc", 10, seed=5, yccplanes=[4, 3, 3])
    assert "nplanes" not in info
    layer = read_relight(tmp_path)
    assert layer.colorspace == "mycc" and layer.extra["nplanes"] == 10
    assert layer.pca is not None and layer.pca.yccplanes == (4, 3, 3)
    fields = layer.fields()
    assert fields["yccplanes"] == [4, 3, 3] and fields["nplanes"] == 10
    got = np.concatenate([g.data.transpose(2, 0, 1) for g in layer.groups])
    np.testing.assert_array_equal(got[:10], planes)


def test_mycc_with_a_matching_nplanes_is_accepted(tmp_path: Path) -> None:
    info, _, _ = pca_folder(tmp_path, "rbf", "mycc", 7, yccplanes=[3, 2, 2])
    info["nplanes"] = 7
    (tmp_path / "info.json").write_text(json.dumps(info))
    assert read_relight(tmp_path).extra["nplanes"] == 7


# --- the real Relight outputs -------------------------------------------------------------------


@pytest.mark.realdata
@pytest.mark.parametrize(("name", "rtype", "nplanes", "ndim"),
                         [("rbf27", "rbf", 27, 116), ("bilinear18", "bilinear", 18, 81)])
def test_real_relight_coin_reads_and_its_block_round_trips(name: str, rtype: str, nplanes: int,
                                                           ndim: int) -> None:
    folder = COIN / name
    if not (folder / "info.json").is_file():
        pytest.skip(f"../shared/realdata/relight-coin/{name} not present (read-only test data "
                    "beside the repo)")
    layer = read_relight(folder)
    assert (layer.layer_type, layer.colorspace, layer.width, layer.height) == (
        rtype, "mrgb", 512, 512)
    pca = layer.pca
    assert pca is not None and (pca.nplanes, pca.ndimensions) == (nplanes, ndim)
    # the basis is materials.bin byte for byte (these older outputs have no "basis" array)
    np.testing.assert_array_equal(pca.basis, np.fromfile(folder / "materials.bin", np.uint8))
    info = json.loads((folder / "info.json").read_text())
    assert list(pca.ranges) == info["materials"][0]["range"]
    block = json.loads(json.dumps({"layerType": rtype, **layer.fields()}))
    back = PcaBasis.from_block(block)
    for light in [(0.0, 0.0), (0.5, 0.3), (-0.4, -0.6)]:
        np.testing.assert_array_equal(back.weights(*light), pca.weights(*light))
    assert len(layer.groups) == nplanes // 3 and layer.groups[0].lossy


# --- bad input ----------------------------------------------------------------------------------


def _mutate(info: dict[str, Any], key: str, value: Any) -> dict[str, Any]:
    out: dict[str, Any] = json.loads(json.dumps(info))
    holder = out["materials"][0] if key.startswith("materials.") else out
    key = key.removeprefix("materials.")
    if value is None:
        holder.pop(key, None)
    else:
        holder[key] = value
    return out


BAD: dict[str, tuple[str, Any, str]] = {
    "basis length": ("basis", [127] * 10, "'basis' must list (nplanes + 1)·ndimensions·3 = "
                     "(6 + 1)·5·3 = 105 integers 0–255, got 10 values"),
    "basis 256": ("basis", [127] * 104 + [256], "basis[104] must be an integer 0–255, got 256"),
    "basis negative": ("basis", [-1] + [127] * 104, "basis[0] must be an integer 0–255, got -1"),
    "basis fraction": ("basis", [127.5] * 105, "basis[0] must be an integer 0–255, got 127.5"),
    "basis text": ("basis", [127] * 50 + ["7"] + [127] * 54,
                   "basis[50]: expected an integer 0–255 (got '7')"),
    "no range": ("materials.range", None, "materials[0].range must list 6 numbers > 0 (one "
                 "per plane), got None"),
    "short range": ("materials.range", [1.0] * 5, "materials[0].range must list 6 numbers > 0 "
                    "(one per plane), got 5 values"),
    "zero range": ("materials.range", [1.0] * 5 + [0], "materials[0].range[5] must be a finite "
                   "number > 0, got 0"),
    "lights not 3s": ("lights", [0.0] * 14, "rbf needs 'lights': D·3 numbers (x, y, z per "
                      "acquisition light), got 14 numbers"),
    "no lights": ("lights", None, "rbf needs 'lights': D·3 numbers"),
    "light text": ("lights", [0.0] * 14 + ["x"], "lights[14]: expected a number (got 'x')"),
    "sigma 0": ("sigma", 0, "rbf needs 'sigma' > 0, got 0"),
    "sigma missing": ("sigma", None, "rbf needs 'sigma' > 0, got None"),
    "nplanes 49": ("nplanes", 49, "'nplanes' must be 1 to 48 for a PCA basis, got 49"),
    "nplanes 0": ("nplanes", 0, "'nplanes' must be 1 to 48 for a PCA basis, got 0"),
    "no nplanes": ("nplanes", None, "mrgb needs 'nplanes'"),
    "colorspace": ("colorspace", "rgb", "rbf with colorspace rgb is not supported; rbf takes "
                   "mrgb or mycc"),
    "lrgb": ("colorspace", "lrgb", "rbf with colorspace lrgb is not supported"),
    "unknown colorspace": ("colorspace", "xyz", "unknown colorspace 'xyz'; supported: rgb, lrgb, "
                           "ycc, mrgb, mycc"),
    "mycc no yccplanes": ("colorspace", "mycc", "mycc needs 'yccplanes' [ny, nc, nc]"),
    "two materials": ("materials", [{}, {}], "2 materials; only one is supported (Relight's "
                      "multi-material output, with segments.png, is not)"),
}


def _expect_refusal(folder: Path, expected: str, where: str = "info.json") -> None:
    with pytest.raises(LanternaInputError) as err:
        read_relight(folder)
    message = str(err.value)
    assert message.startswith(f"{folder / where}: "), message
    assert expected in message and "\n" not in message, message


@pytest.mark.parametrize("case", sorted(BAD))
def test_bad_rbf_info_is_a_one_line_error_naming_the_field(tmp_path: Path, case: str) -> None:
    key, value, expected = BAD[case]
    info, _, _ = pca_folder(tmp_path, "rbf", "mrgb", 6)
    (tmp_path / "info.json").write_text(json.dumps(_mutate(info, key, value)))
    _expect_refusal(tmp_path, expected)


BAD_BILINEAR_MYCC: dict[str, tuple[str, Any, str]] = {
    "resolution 1": ("resolution", 1, "bilinear needs 'resolution' 2 to 32, got 1"),
    "resolution 33": ("resolution", 33, "bilinear needs 'resolution' 2 to 32, got 33"),
    "no resolution": ("resolution", None, "'resolution' must be an integer, got None"),
    "yccplanes unequal chroma": ("yccplanes", [4, 2, 3], "'yccplanes' must be [ny, nc, nc] with "
                                 "ny ≥ nc and ny + 2·nc ≥ 1, got [4, 2, 3]"),
    "yccplanes ny < nc": ("yccplanes", [1, 2, 2], "got [1, 2, 2]"),
    "yccplanes two": ("yccplanes", [4, 3], "yccplanes: expected three integers [ny, nc, nc]"),
    "yccplanes sum 49": ("yccplanes", [17, 16, 16], "'nplanes' must be 1 to 48 for a PCA basis, "
                         "got 49"),
    "nplanes disagrees": ("nplanes", 9, "'nplanes' 9 disagrees with 'yccplanes' [4, 3, 3] "
                          "(ny + 2·nc = 10)"),
}


@pytest.mark.parametrize("case", sorted(BAD_BILINEAR_MYCC))
def test_bad_bilinear_mycc_info_is_a_one_line_error(tmp_path: Path, case: str) -> None:
    key, value, expected = BAD_BILINEAR_MYCC[case]
    info, _, _ = pca_folder(tmp_path, "bilinear", "mycc", 10, yccplanes=[4, 3, 3])
    (tmp_path / "info.json").write_text(json.dumps(_mutate(info, key, value)))
    _expect_refusal(tmp_path, expected)


@pytest.mark.parametrize(("rtype", "colorspace"), [("ptm", "mrgb"), ("hsh", "mycc")])
def test_fixed_bases_with_pca_colour_spaces_are_refused(tmp_path: Path, rtype: str,
                                                        colorspace: str) -> None:
    info, _, _ = pca_folder(tmp_path, "rbf", "mrgb", 9)
    info.update(type=rtype, colorspace=colorspace)
    (tmp_path / "info.json").write_text(json.dumps(info))
    _expect_refusal(tmp_path, f"{rtype} with colorspace {colorspace} is not supported")


def test_truncated_or_long_materials_bin_is_refused_before_reading(tmp_path: Path) -> None:
    _, _, basis = pca_folder(tmp_path, "rbf", "mrgb", 6, in_json=False)
    path = tmp_path / "materials.bin"
    path.write_bytes(basis.tobytes()[:-1])
    _expect_refusal(tmp_path, "is 104 bytes; the basis is (nplanes + 1)·ndimensions·3 = "
                    "(6 + 1)·5·3 = 105 bytes", "materials.bin")
    path.write_bytes(basis.tobytes() + b"\0")
    _expect_refusal(tmp_path, "is 106 bytes", "materials.bin")
    path.unlink()
    _expect_refusal(tmp_path, "no 'basis' and no materials.bin beside info.json: the PCA basis "
                    "is missing")
    path.mkdir()
    _expect_refusal(tmp_path, "is a directory, not a Relight basis (materials.bin)",
                    "materials.bin")


def test_materials_bin_fifo_is_refused_without_blocking(tmp_path: Path) -> None:
    pca_folder(tmp_path, "rbf", "mrgb", 6, in_json=False)
    (tmp_path / "materials.bin").unlink()
    os.mkfifo(tmp_path / "materials.bin")
    _expect_refusal(tmp_path, "is not a regular file", "materials.bin")


def test_a_refused_basis_decodes_no_plane(tmp_path: Path) -> None:
    """The basis is checked before any plane image is opened (a missing plane is not reported)."""
    info, _, _ = pca_folder(tmp_path, "rbf", "mrgb", 6)
    (tmp_path / "plane_0.png").unlink()
    (tmp_path / "info.json").write_text(json.dumps(_mutate(info, "basis", [1])))
    _expect_refusal(tmp_path, "'basis' must list")
