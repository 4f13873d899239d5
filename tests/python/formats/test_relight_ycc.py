"""Relight ``colorspace: "ycc"`` (ptm, hsh) read as an equivalent ``rgb`` layer.

The reference is Relight's own ``Rti::render`` case ``YCC``, written here independently of the
reader: ``Y = Σ_t w_t·v[3t]``, ``Cb = v[1]``, ``Cr = v[2]`` (``v`` the planes dequantised,
``(t − bias)·scale``), then ``Color3::YCbCrToRgb``: ``R = Y + 1.402(Cr − ½)``,
``G = Y − 0.344136(Cb − ½) − 0.714136(Cr − ½)``, ``B = Y + 1.772(Cb − ½)``.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from lanterna.tiler.formats.relight_web import read_relight
from lanterna.tiler.formats.relight_ycc import requantise
from tests.python.formats.test_relight_web import (
    F64,
    LIGHTS,
    info_json,
    lanterna_render,
    random_planes,
    relight_hsh_weights,
    relight_ptm_weights,
    relight_values,
    write_folder,
)


def relight_ycc_render(rtype: str, v: F64, lx: float, ly: float) -> F64:
    n = v.shape[0]
    w = relight_ptm_weights(lx, ly, n // 3) if rtype == "ptm" else relight_hsh_weights(lx, ly)
    y = sum(w[t] * v[3 * t] for t in range(n // 3))
    cb, cr = v[1] - 0.5, v[2] - 0.5
    return np.stack([y + 1.402 * cr, y - 0.344136 * cb - 0.714136 * cr, y + 1.772 * cb], -1)


@pytest.mark.parametrize(("rtype", "nplanes"), [("ptm", 18), ("ptm", 9), ("hsh", 27),
                                                ("hsh", 12)])
def test_ycc_relights_as_relight_does(tmp_path: Path, rtype: str, nplanes: int) -> None:
    planes, scale, bias = random_planes(nplanes, seed=nplanes + 1)
    scale = [s / 4 for s in scale]  # chroma near ½ as in real files
    write_folder(tmp_path, info_json(rtype, "ycc", nplanes, scale, bias), planes)
    layer = read_relight(tmp_path)
    assert layer.layer_type == rtype and layer.extra["sourceColorspace"] == "ycc"
    assert layer.colorspace == ("rgb" if rtype == "ptm" else None)
    v = relight_values(planes, scale, bias)
    # only the constant term is requantised: its error is half a step of its own range
    const = "5" if rtype == "ptm" else "0"
    w0 = 1.0 if rtype == "ptm" else 1 / math.sqrt(2 * math.pi)
    steps = {}
    for g in layer.groups:
        for k, name in enumerate(g.channels):
            if name[1:] == const:
                steps[name[0]] = g.scale[k] / 255 / 2 * w0
    tol = np.array([steps[c] for c in "RGB"]) + 1e-6
    for lx, ly in LIGHTS:
        got = lanterna_render(layer, lx, ly)
        want = relight_ycc_render(rtype, v, lx, ly)
        assert np.all(np.abs(got - want) <= tol), (lx, ly, np.abs(got - want).max(axis=(0, 1)))
    # the light-dependent terms keep Y's bytes, scale and bias in every colour
    if rtype == "hsh":
        for t in range(1, nplanes // 3):
            group = layer.groups[t]
            for k in range(3):
                np.testing.assert_array_equal(group.data[..., k], planes[3 * t])
            assert group.scale == [scale[3 * t]] * 3 and group.bias == [bias[3 * t]] * 3


def test_requantise_spans_the_values_and_keeps_a_constant_exactly() -> None:
    v = np.linspace(-0.3, 1.7, 256).reshape(16, 16)
    t, scale, bias = requantise(v)
    assert t.min() == 0 and t.max() == 255
    back = (t / 255.0 - bias) * scale
    assert np.abs(back - v).max() <= scale / 510 + 1e-12
    t, scale, bias = requantise(np.full((3, 4), 0.625))
    assert not t.any() and (0 - bias) * scale == 0.625
