"""Relight's ``type: "sh"`` folders (plain real spherical harmonics) read as ``sh`` layers.

The check relights every folder with an independent transcription of Relight itself, written
here from ``src/rti.cpp``: ``Rti::lightWeightsSh`` gives, for the light ``(lx, ly)`` with
``lz = √(1 − lx² − ly²)``, the nine weights ::

    0.282095, 0.488603·ly, 0.488603·lz, 0.488603·lx, 1.092548·lx·ly, 1.092548·ly·lz,
    0.315392·(3·lz² − 1), 1.092548·lx·lz, 0.546274·(lx² − ly²)

and ``Rti::render`` (case ``RGB``) relights colour ``c`` as ``Σ_t w_t·v[3t + c]`` over the
``nplanes / 3`` terms, ``v[p] = (t/255 − bias[p])·scale[p]``; case ``YCC`` relights luma the
same way over the planes ``3t`` and adds the light-independent chroma of planes 1 and 2.
The Lanterna side is the reference renderer's colour mode (:func:`lanterna.tiler.render.surface`).
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest

from lanterna.errors import LanternaInputError
from lanterna.tiler.formats.planes import PlaneLayer
from lanterna.tiler.formats.relight_web import read_relight
from lanterna.tiler.render import surface
from lanterna.tiler.render.shading import make_light
from tests.python.formats.test_relight_web import (
    F64,
    LIGHTS,
    info_json,
    random_planes,
    relight_values,
    write_folder,
)


def relight_sh_weights(lx: float, ly: float) -> list[float]:
    """Relight ``Rti::lightWeightsSh`` as written there (its rounded constants)."""
    lz = math.sqrt(1.0 - lx * lx - ly * ly)
    c0, c1, c2, c3, c4 = 0.282095, 0.488603, 1.092548, 0.315392, 0.546274
    return [c0, c1 * ly, c1 * lz, c1 * lx, c2 * lx * ly, c2 * ly * lz, c3 * (3 * lz * lz - 1),
            c2 * lx * lz, c4 * (lx * lx - ly * ly)]


def relight_sh_render(colorspace: str, v: F64, lx: float, ly: float) -> F64:
    """Relight's ``render`` of an sh folder (unclamped), ``(H, W, 3)`` in 0–1 units."""
    w = relight_sh_weights(lx, ly)
    terms = v.shape[0] // 3
    if colorspace == "rgb":
        return np.stack([sum(w[t] * v[3 * t + c] for t in range(terms)) for c in range(3)], -1)
    y = sum(w[t] * v[3 * t] for t in range(terms))
    cb, cr = v[1] - 0.5, v[2] - 0.5
    return np.stack([y + 1.402 * cr, y - 0.344136 * cb - 0.714136 * cr, y + 1.772 * cb], -1)


def reference_color(layer: PlaneLayer, lx: float, ly: float) -> F64:
    block = {"layerType": layer.layer_type, **layer.fields()}
    out: F64 = surface(block, layer.channels()).color(make_light(lx, ly)).astype(np.float64)
    return out


@pytest.mark.parametrize("nplanes", [12, 27])
@pytest.mark.parametrize("fmt", ["png", "jpg"])
def test_sh_relights_as_relight_does(tmp_path: Path, nplanes: int, fmt: str) -> None:
    planes, scale, bias = random_planes(nplanes, seed=nplanes + 40)
    stored = write_folder(tmp_path, info_json("sh", "rgb", nplanes, scale, bias, fmt), planes,
                          fmt)
    layer = read_relight(tmp_path)
    assert (layer.layer_type, layer.terms, layer.colorspace) == ("sh", nplanes // 3, None)
    assert layer.fields() == {"terms": nplanes // 3}
    assert [g.channels for g in layer.groups] == [[f"R{k}", f"G{k}", f"B{k}"]
                                                  for k in range(nplanes // 3)]
    v = relight_values(stored, scale, bias)
    for lx, ly in LIGHTS:
        np.testing.assert_allclose(reference_color(layer, lx, ly),
                                   relight_sh_render("rgb", v, lx, ly), atol=2e-5,
                                   err_msg=f"light {(lx, ly)}")


def test_the_basis_is_not_hsh_s(tmp_path: Path) -> None:
    """The same bytes read as hsh relight differently: sh is a layer type of its own."""
    planes, scale, bias = random_planes(27, seed=3)
    write_folder(tmp_path / "sh", info_json("sh", "rgb", 27, scale, bias), planes)
    write_folder(tmp_path / "hsh", info_json("hsh", "rgb", 27, scale, bias), planes)
    sh, hsh = read_relight(tmp_path / "sh"), read_relight(tmp_path / "hsh")
    diff = np.abs(reference_color(sh, 0.5, 0.3) - reference_color(hsh, 0.5, 0.3))
    assert diff.mean() > 0.05


@pytest.mark.parametrize("nplanes", [12, 27])
def test_sh_ycc_relights_as_relight_does(tmp_path: Path, nplanes: int) -> None:
    planes, scale, bias = random_planes(nplanes, seed=nplanes + 2)
    scale = [s / 4 for s in scale]  # chroma near ½ as in real files
    write_folder(tmp_path, info_json("sh", "ycc", nplanes, scale, bias), planes)
    layer = read_relight(tmp_path)
    assert layer.layer_type == "sh" and layer.extra["sourceColorspace"] == "ycc"
    v = relight_values(planes, scale, bias)
    # only the constant term is requantised: half a step of its own range, times Y0
    steps = {g.channels[k][0]: g.scale[k] / 255 / 2 * 0.282095
             for g in layer.groups[:1] for k in range(3)}
    tol = np.array([steps[c] for c in "RGB"]) + 1e-6
    for lx, ly in LIGHTS:
        diff = np.abs(reference_color(layer, lx, ly) - relight_sh_render("ycc", v, lx, ly))
        assert np.all(diff <= tol), (lx, ly, diff.max(axis=(0, 1)))


@pytest.mark.parametrize(("colorspace", "nplanes", "expected"), [
    ("rgb", 48, "sh rgb needs nplanes 12 or 27, got 48"),
    ("rgb", 18, "sh rgb needs nplanes 12 or 27, got 18"),
    ("ycc", 9, "sh ycc needs nplanes 12 or 27, got 9"),
    ("lrgb", 27, "sh with colorspace lrgb is not supported; sh takes rgb or ycc"),
    ("mrgb", 27, "sh with colorspace mrgb is not supported; sh takes rgb or ycc"),
])
def test_a_wrong_sh_folder_is_a_one_line_error(tmp_path: Path, colorspace: str, nplanes: int,
                                               expected: str) -> None:
    planes, scale, bias = random_planes(27)
    write_folder(tmp_path, info_json("sh", "rgb", 27, scale, bias), planes)
    info = info_json("sh", colorspace, nplanes, [1.0] * nplanes, [0.0] * nplanes)
    (tmp_path / "info.json").write_text(json.dumps(info))
    with pytest.raises(LanternaInputError) as err:
        read_relight(tmp_path)
    message = str(err.value)
    assert message == f"{tmp_path / 'info.json'}: {expected}"
