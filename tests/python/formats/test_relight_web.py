"""Tests for the Relight/OpenLIME web-format reader (tiler/formats/relight_web.py).

The reference evaluation here follows Relight itself (``src/rti.cpp``: ``lightWeightsPtm`` builds
``1, x, y, xx, xy, yy``; ``lightWeightsHsh``; ``render`` for rgb and lrgb), independently of the
reader, so a wrong reorder or regroup changes the relit image.
"""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import Any

import numpy as np
import numpy.typing as npt
import pytest
import pyvips

from lanterna.errors import LanternaInputError
from lanterna.tiler.formats.hsh_basis import hsh_weights
from lanterna.tiler.formats.planes import PlaneLayer
from lanterna.tiler.formats.ptm_model import ptm_weights
from lanterna.tiler.formats.relight_web import read_relight

W, H = 11, 6
LIGHTS = [(0.0, 0.0), (0.6, 0.1), (-0.5, 0.4), (0.2, -0.7), (-0.3, -0.35)]
F64 = npt.NDArray[np.float64]


def random_planes(nplanes: int, seed: int = 0) -> tuple[npt.NDArray[np.uint8], list[float],
                                                         list[float]]:
    rng = np.random.default_rng(seed)
    planes = rng.integers(0, 256, (nplanes, H, W), dtype=np.uint8)
    scale = [round(float(v), 4) for v in rng.uniform(0.2, 3.0, nplanes)]
    bias = [round(float(v), 4) for v in rng.uniform(0.0, 0.9, nplanes)]
    return planes, scale, bias


def write_folder(folder: Path, info: dict[str, Any], planes: npt.NDArray[np.uint8],
                 fmt: str = "png") -> npt.NDArray[np.uint8]:
    """Write ``info.json`` and the planes (3 per image); return the planes as decoded back."""
    folder.mkdir(parents=True, exist_ok=True)
    (folder / "info.json").write_text(json.dumps(info))
    decoded = []
    for i in range(planes.shape[0] // 3):
        rgb = np.ascontiguousarray(planes[3 * i : 3 * i + 3].transpose(1, 2, 0))
        image = pyvips.Image.new_from_array(rgb).copy(interpretation="srgb")
        path = folder / f"plane_{i}.{fmt}"
        if fmt == "jpg":
            image.jpegsave(str(path), Q=100, subsample_mode="off")
        else:
            image.pngsave(str(path))
        back = pyvips.Image.new_from_file(str(path)).numpy()
        decoded.append(np.asarray(back).transpose(2, 0, 1))
    return np.concatenate(decoded).astype(np.uint8)


def info_json(rtype: str, colorspace: str, nplanes: int, scale: list[float], bias: list[float],
              fmt: str = "png") -> dict[str, Any]:
    return {"width": W, "height": H, "format": fmt, "type": rtype, "colorspace": colorspace,
            "lights": [0.0, 0.0, 1.0], "nplanes": nplanes, "quality": 95,
            "materials": [{"scale": scale, "bias": bias}]}


def relight_values(planes: npt.NDArray[np.uint8], scale: list[float],
                   bias: list[float]) -> F64:
    """Relight's dequantisation ``(t − bias)·scale`` per plane, ``(n, H, W)``."""
    t = planes.astype(np.float64) / 255.0
    out: F64 = (t - np.array(bias)[:, None, None]) * np.array(scale)[:, None, None]
    return out


def relight_ptm_weights(lx: float, ly: float, n: int) -> list[float]:
    """Relight ``lightWeightsPtm``: monomials by degree, ``x`` powers first."""
    out: list[float] = []
    degree = 0
    while len(out) < n:
        for k in range(degree + 1):
            out.append(ly**k * lx ** (degree - k))
        degree += 1
    return out[:n]


def relight_hsh_weights(lx: float, ly: float) -> list[float]:
    """Relight ``lightWeightsHsh`` (the ``lweights`` branch), 9 terms."""
    lz = math.sqrt(1 - lx * lx - ly * ly)
    phi = math.atan2(ly, lx)
    phi = phi + 2 * math.pi if phi < 0 else phi
    theta = min(math.acos(lz), math.pi / 2 - 0.01)
    cp, ct = math.cos(phi), math.cos(theta)
    ct2 = ct * ct
    s = math.sqrt(ct - ct2)
    pi = math.pi
    return [1 / math.sqrt(2 * pi), math.sqrt(6 / pi) * cp * s,
            math.sqrt(3 / (2 * pi)) * (2 * ct - 1), math.sqrt(6 / pi) * s * math.sin(phi),
            math.sqrt(30 / pi) * math.cos(2 * phi) * (ct2 - ct),
            math.sqrt(30 / pi) * cp * (2 * ct - 1) * s,
            math.sqrt(5 / (2 * pi)) * (1 - 6 * ct + 6 * ct2),
            math.sqrt(30 / pi) * (2 * ct - 1) * s * math.sin(phi),
            math.sqrt(30 / pi) * (ct2 - ct) * math.sin(2 * phi)]


def relight_render(rtype: str, colorspace: str, v: F64, lx: float, ly: float) -> F64:
    """Relight's ``render`` (without clamping), ``(H, W, 3)`` in 0–1 units."""
    n = v.shape[0]
    if colorspace == "lrgb":
        w = relight_ptm_weights(lx, ly, n - 3)
        lum = sum(w[t] * v[3 + t] for t in range(n - 3))
        return np.stack([v[c] * lum for c in range(3)], axis=-1)
    w = relight_ptm_weights(lx, ly, n // 3) if rtype == "ptm" else relight_hsh_weights(lx, ly)
    return np.stack([sum(w[t] * v[3 * t + c] for t in range(n // 3)) for c in range(3)], -1)


def lanterna_render(layer: PlaneLayer, lu: float, lv: float) -> F64:
    """docs/rendering.md ``color`` mode (unclamped) from the layer's named channels."""
    ch = {k: v.astype(np.float64) for k, v in layer.channels().items()}
    if layer.layer_type == "hsh":
        assert layer.terms is not None
        hw = hsh_weights(lu, lv, layer.terms)
        return np.stack([sum(ch[f"{c}{k}"] * hw[k] for k in range(layer.terms)) for c in "RGB"],
                        axis=-1)
    w = ptm_weights(lu, lv)
    if layer.colorspace == "lrgb":
        lum = sum(ch[f"L{k}"] * w[k] for k in range(6))
        return np.stack([ch[c] * lum for c in "RGB"], axis=-1)
    return np.stack([sum(ch[f"{c}{k}"] * w[k] for k in range(6)) for c in "RGB"], axis=-1)


# --- reordering checked by relighting ----------------------------------------------------------


@pytest.mark.parametrize(("rtype", "colorspace", "nplanes"), [
    ("ptm", "lrgb", 9), ("ptm", "lrgb", 6), ("ptm", "rgb", 18), ("ptm", "rgb", 9),
    ("hsh", "rgb", 27), ("hsh", "rgb", 12),
])
@pytest.mark.parametrize("fmt", ["png", "jpg"])
def test_relit_channels_match_relights_own_evaluation(tmp_path: Path, rtype: str,
                                                      colorspace: str, nplanes: int,
                                                      fmt: str) -> None:
    planes, scale, bias = random_planes(nplanes, seed=nplanes)
    if colorspace == "lrgb":
        scale[:3], bias[:3] = [1.0] * 3, [0.0] * 3  # Relight's base colour planes
    folder = tmp_path / "rti"
    stored = write_folder(folder, info_json(rtype, colorspace, nplanes, scale, bias, fmt),
                          planes, fmt)
    if fmt == "png":
        np.testing.assert_array_equal(stored, planes)
    layer = read_relight(folder)
    assert (layer.width, layer.height, layer.layer_type) == (W, H, rtype)
    if rtype == "hsh":
        assert layer.terms == nplanes // 3 and layer.colorspace is None
    else:
        assert layer.colorspace == colorspace and layer.terms is None
    v = relight_values(stored, scale, bias)
    for lx, ly in LIGHTS:
        expected = relight_render(rtype, colorspace, v, lx, ly)
        np.testing.assert_allclose(lanterna_render(layer, lx, ly), expected, atol=2e-5,
                                   err_msg=f"light {(lx, ly)}")


def test_hsh16_groups_are_per_term(tmp_path: Path) -> None:
    planes, scale, bias = random_planes(48, seed=16)
    write_folder(tmp_path, info_json("hsh", "rgb", 48, scale, bias), planes)
    layer = read_relight(tmp_path / "info.json")  # the info.json path works as well
    assert layer.terms == 16
    assert [g.channels for g in layer.groups] == [[f"R{k}", f"G{k}", f"B{k}"] for k in range(16)]
    np.testing.assert_array_equal(layer.groups[11].data, planes[33:36].transpose(1, 2, 0))
    assert layer.groups[11].scale == scale[33:36] and layer.groups[11].bias == bias[33:36]


def test_ptm_groups_keep_the_bytes_in_lanterna_order(tmp_path: Path) -> None:
    planes, scale, bias = random_planes(9, seed=1)
    write_folder(tmp_path, info_json("ptm", "lrgb", 9, scale, bias), planes)
    layer = read_relight(tmp_path)
    assert [g.channels for g in layer.groups] == [["L0", "L1", "L2"], ["L3", "L4", "L5"],
                                                  ["R", "G", "B"]]
    # Relight planes: 0–2 colour, then 1, u, v, u², uv, v²  →  L0..L5 = u², v², uv, u, v, 1
    order = [6, 8, 7, 4, 5, 3, 0, 1, 2]
    got = np.concatenate([g.data.transpose(2, 0, 1) for g in layer.groups])
    np.testing.assert_array_equal(got, planes[order])
    assert sum((g.scale for g in layer.groups), []) == [scale[i] for i in order]
    assert sum((g.bias for g in layer.groups), []) == [bias[i] for i in order]


def test_degree_one_ptm_gets_zero_quadratic_channels(tmp_path: Path) -> None:
    planes, scale, bias = random_planes(9, seed=2)
    write_folder(tmp_path, info_json("ptm", "rgb", 9, scale, bias), planes)
    layer = read_relight(tmp_path)
    ch = layer.channels()
    for c in "RGB":
        for k in (0, 1, 2):
            assert not ch[f"{c}{k}"].any()
    assert len(layer.groups) == 6 and layer.extra["nplanes"] == 9


def test_top_level_scale_and_bias_are_accepted(tmp_path: Path) -> None:
    planes, scale, bias = random_planes(18, seed=4)
    info = info_json("ptm", "rgb", 18, scale, bias)
    del info["materials"]
    info["scale"], info["bias"] = scale, bias
    write_folder(tmp_path, info, planes)
    layer = read_relight(tmp_path)
    v = relight_values(planes, scale, bias)
    np.testing.assert_allclose(lanterna_render(layer, 0.3, 0.2),
                               relight_render("ptm", "rgb", v, 0.3, 0.2), atol=2e-5)


# --- errors -------------------------------------------------------------------------------------


def _edit(info: dict[str, Any], **changes: Any) -> dict[str, Any]:
    out = dict(info)
    for k, v in changes.items():
        if v is None:
            out.pop(k, None)
        else:
            out[k] = v
    return out


BASE = info_json("ptm", "rgb", 18, [1.0] * 18, [0.0] * 18)
INFO_ERRORS: dict[str, tuple[dict[str, Any], str]] = {
    "unknown type": (_edit(BASE, type="xyz"), "unknown Relight type 'xyz'"),
    "h": (_edit(BASE, type="h"), "unsupported Relight type 'h' (Relight's experimental H-basis); "
          "supported: ptm, hsh, sh, rbf, bilinear"),
    "rbf rgb": (_edit(BASE, type="rbf"), "rbf with colorspace rgb is not supported; rbf takes "
                "mrgb or mycc"),
    "no type": (_edit(BASE, type=None), 'info.json: needs "type"'),
    "unknown colorspace": (_edit(BASE, colorspace="cmyk"), "unknown colorspace 'cmyk'; supported: "
                           "rgb, lrgb, ycc, mrgb, mycc"),
    "ptm mycc": (_edit(BASE, colorspace="mycc"), "ptm with colorspace mycc is not supported; "
                 "ptm takes rgb or lrgb or ycc"),
    "hsh lrgb": (_edit(BASE, type="hsh", colorspace="lrgb"), "hsh with colorspace lrgb"),
    "bad nplanes": (_edit(BASE, nplanes=12), "ptm rgb needs nplanes 9 or 18, got 12"),
    "hsh nplanes": (_edit(BASE, type="hsh", nplanes=18), "hsh rgb needs nplanes 12 or 27 or 48"),
    "width text": (_edit(BASE, width="wide"),
                   "width: expected a positive integer (or its decimal text) (got 'wide')"),
    "zero height": (_edit(BASE, height=0),
                    "height: expected a positive integer (or its decimal text) (got 0)"),
    "short scale": (_edit(BASE, materials=[{"scale": [1.0] * 17, "bias": [0.0] * 18}]),
                    "materials[0].scale must list 18 numbers (one per plane), got 17 values"),
    "nan bias": (_edit(BASE, materials=[{"scale": [1.0] * 18, "bias": [0.0] * 17 + ["x"]}]),
                 "materials[0].bias[17]: expected a number (got 'x')"),
    "no scale": (_edit(BASE, materials=None), "info.json.scale must list 18 numbers"),
    "two materials": (_edit(BASE, materials=[{}, {}]), "2 materials; only one is supported"),
    "format": (_edit(BASE, format="webp"), "unsupported plane format 'webp'"),
}


@pytest.mark.parametrize("case", sorted(INFO_ERRORS))
def test_bad_info_json(tmp_path: Path, case: str) -> None:
    info, expected = INFO_ERRORS[case]
    planes, _, _ = random_planes(18)
    write_folder(tmp_path, _edit(BASE), planes)
    (tmp_path / "info.json").write_text(json.dumps(info))
    with pytest.raises(LanternaInputError) as err:
        read_relight(tmp_path)
    message = str(err.value)
    assert expected in message, message
    assert message.startswith(str(tmp_path / "info.json") + ": ") and "\n" not in message


def test_missing_folder_info_and_invalid_json(tmp_path: Path) -> None:
    with pytest.raises(LanternaInputError, match="folder not found"):
        read_relight(tmp_path / "nope")
    with pytest.raises(LanternaInputError, match="no info.json"):
        read_relight(tmp_path)
    (tmp_path / "info.json").write_text("{\"width\": 3,")
    with pytest.raises(LanternaInputError, match="not valid JSON"):
        read_relight(tmp_path)
    (tmp_path / "info.json").write_text("[1, 2]")
    with pytest.raises(LanternaInputError, match="expected an info.json object"):
        read_relight(tmp_path)


def test_missing_plane(tmp_path: Path) -> None:
    planes, scale, bias = random_planes(18)
    write_folder(tmp_path, info_json("ptm", "rgb", 18, scale, bias), planes)
    (tmp_path / "plane_4.png").unlink()
    with pytest.raises(LanternaInputError, match=r"plane_4.png: plane 4 is missing$"):
        read_relight(tmp_path)
    (tmp_path / "plane_4").mkdir()  # a google or zoomify tree (deepzoom & co: test_relight_layouts)
    with pytest.raises(LanternaInputError, match="tiled layouts google and zoomify are not"):
        read_relight(tmp_path)


def test_plane_size_mismatch_and_band_count(tmp_path: Path) -> None:
    planes, scale, bias = random_planes(18)
    write_folder(tmp_path, info_json("ptm", "rgb", 18, scale, bias), planes)
    pyvips.Image.black(W + 1, H, bands=3).cast("uchar").pngsave(str(tmp_path / "plane_2.png"))
    with pytest.raises(LanternaInputError, match=rf"plane is {W + 1}x{H}, info.json says {W}x{H}"):
        read_relight(tmp_path)
    pyvips.Image.black(W, H).cast("uchar").pngsave(str(tmp_path / "plane_2.png"))
    with pytest.raises(LanternaInputError, match="plane has 1 band"):
        read_relight(tmp_path)


def test_corrupt_jpeg_plane(tmp_path: Path) -> None:
    planes, scale, bias = random_planes(18)
    write_folder(tmp_path, info_json("ptm", "rgb", 18, scale, bias, "jpg"), planes, "jpg")
    path = tmp_path / "plane_3.jpg"
    path.write_bytes(path.read_bytes()[:200])
    with pytest.raises(LanternaInputError) as err:
        read_relight(tmp_path)
    assert str(err.value).startswith(f"{path}: cannot decode plane")
    assert "\n" not in str(err.value)
