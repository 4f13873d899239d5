"""Relight's own rbf and bilinear outputs (../shared/realdata/relight-coin) through the reference.

Each dataset is read here directly (``info.json``, ``materials.bin``, ``plane_K.jpg`` decoded
with pyvips), its block built with :class:`PcaBasis`, rendered by :func:`tiler.render.render`
and compared with :func:`relight_pixel`, an independent re-implementation of Relight's formula.
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

from lanterna.tiler.formats.pca_model import PcaBasis
from lanterna.tiler.render import render
from tests.python.fixtures.paths import SHARED

COIN = SHARED / "realdata" / "relight-coin"
LIGHTS = [(0.0, 0.0), (0.5, -0.3), (-0.4, 0.62)]
PIXELS = [(256, 256), (180, 320), (330, 140), (90, 260), (400, 400)]  # (x, y)

pytestmark = pytest.mark.realdata


class Relight:
    """One Relight web-format folder as its files hold it (bytes, not our model)."""

    def __init__(self, folder: Path) -> None:
        if not (folder / "info.json").is_file():
            pytest.skip(f"real data not found at {folder} (../shared/realdata/relight-coin)")
        self.info: dict[str, Any] = json.loads((folder / "info.json").read_text())
        self.nplanes = int(self.info["nplanes"])
        self.material = self.info["materials"][0]
        self.basis = np.frombuffer((folder / "materials.bin").read_bytes(), np.uint8)
        self.planes = np.concatenate(
            [pyvips.Image.new_from_file(str(folder / f"plane_{j}.jpg")).numpy()
             for j in range((self.nplanes + 2) // 3)], axis=-1)[..., :self.nplanes]

    def block(self) -> dict[str, Any]:
        kind = str(self.info["type"])
        basis = PcaBasis(kind, str(self.info["colorspace"]), self.basis,
                         tuple(float(v) for v in self.material["range"]),
                         tuple(float(v) for v in self.info["lights"]) if kind == "rbf" else None,
                         float(self.info["sigma"]) if kind == "rbf" else None,
                         int(self.info["resolution"]) if kind == "bilinear" else None)
        return {"layerType": kind, **basis.fields(), "planes": []}

    def channels(self) -> dict[str, npt.NDArray[np.float32]]:
        """Lanterna's dequantisation ``(t − bias)·scale``, ``t`` = byte/255."""
        t = self.planes.astype(np.float32) / np.float32(255)
        return {f"P{q}": ((t[..., q] - np.float32(self.material["bias"][q]))
                          * np.float32(self.material["scale"][q])) for q in range(self.nplanes)}


def relight_pixel(data: Relight, x: int, y: int, lx: float, ly: float) -> list[float]:
    """Relight's ``Rti::render`` (MRGB) of one pixel, in float64, divided by 255.

    - Light ``n = (lx, ly, √(1 − lx² − ly²))``.
    - ``Rti::lightWeightsRbf``: for each acquisition light ``l_i``, ``w_i = exp(−‖n − l_i‖²/σ²)``;
      ``w_i /= Σ w``; keep the ``w_i > 0.001`` and divide them by their sum.
    - ``Rti::lightWeightsBilinear``: ``s = |lx| + |ly| + |lz|``,
      ``x = ((lx + ly)/s + 1)/2·(R − 1)``, ``y = ((ly − lx)/s + 1)/2·(R − 1)``,
      ``(sx, sy) = clamp(⌊x, y⌋, 0, R − 2)``, ``(dx, dy) = (x − sx, y − sy)``; the cells
      ``(sx, sy)``, ``(sx+1, sy)``, ``(sx, sy+1)``, ``(sx+1, sy+1)`` (sample ``cx + cy·R``)
      weigh ``(1−dx)(1−dy)``, ``dx(1−dy)``, ``(1−dx)dy``, ``dx·dy``.
    - Basis (``Rti::load``): byte ``b`` at ``((p·D + d)·3 + k)``; ``b`` for the mean ``p = 0``,
      ``(b − 127)/range[p − 1]`` for ``p ≥ 1``; ``lweights[p][k] = Σ_d w_d·basis[p][d][k]``.
    - ``Material::Plane::dequantize(t) = 255·(t/255 − bias)·scale`` for the plane byte ``t``.
    - ``Rti::render`` MRGB: ``c_k = lweights[0][k] + Σ_p dequantize(t_p)·lweights[p + 1][k]``
      (0–255; Relight then truncates to a byte, here the value is divided by 255 instead).
    """
    info, n = data.info, data.nplanes
    lz = math.sqrt(1 - lx * lx - ly * ly)
    weights: dict[int, float] = {}
    if info["type"] == "rbf":
        lights, sigma = info["lights"], float(info["sigma"])
        raw = []
        for i in range(len(lights) // 3):
            d2 = ((lx - lights[3 * i]) ** 2 + (ly - lights[3 * i + 1]) ** 2
                  + (lz - lights[3 * i + 2]) ** 2)
            raw.append(math.exp(-d2 / (sigma * sigma)))
        total = sum(raw)
        kept = {i: w / total for i, w in enumerate(raw) if w / total > 0.001}
        retotal = sum(kept.values())
        weights = {i: w / retotal for i, w in kept.items()}
        dims = len(lights) // 3
    else:
        res = int(info["resolution"])
        dims = res * res
        s = abs(lx) + abs(ly) + abs(lz)
        gx = ((lx + ly) / s + 1) / 2 * (res - 1)
        gy = ((ly - lx) / s + 1) / 2 * (res - 1)
        sx = min(res - 2, max(0, math.floor(gx)))
        sy = min(res - 2, max(0, math.floor(gy)))
        dx, dy = gx - sx, gy - sy
        for cx, cy, w in ((sx, sy, (1 - dx) * (1 - dy)), (sx + 1, sy, dx * (1 - dy)),
                          (sx, sy + 1, (1 - dx) * dy), (sx + 1, sy + 1, dx * dy)):
            weights[cx + cy * res] = weights.get(cx + cy * res, 0.0) + w
    ranges = data.material["range"]

    def lweight(p: int, k: int) -> float:
        total = 0.0
        for d, w in weights.items():
            b = float(data.basis[(p * dims + d) * 3 + k])
            total += w * (b if p == 0 else (b - 127) / ranges[p - 1])
        return total

    out = []
    for k in range(3):
        c = lweight(0, k)
        for p in range(n):
            t = float(data.planes[y, x, p])
            value = 255 * (t / 255 - data.material["bias"][p]) * data.material["scale"][p]
            c += value * lweight(p + 1, k)
        out.append(c / 255)
    return out


@pytest.mark.parametrize("name", ["rbf27", "bilinear18"])
def test_relight_coin_renders_as_relight_renders_it(name: str) -> None:
    data = Relight(COIN / name)
    assert data.basis.size == (data.nplanes + 1) * 3 * (
        len(data.info["lights"]) // 3 if data.info["type"] == "rbf"
        else int(data.info["resolution"]) ** 2)
    layer, channels = data.block(), data.channels()
    inside = 0
    for lu, lv in LIGHTS:
        img = render(layer, channels, (lu, lv))
        for x, y in PIXELS:
            expected = np.clip(relight_pixel(data, x, y, lu, lv), 0, 1)
            np.testing.assert_allclose(img[y, x], expected, atol=1e-4,
                                       err_msg=f"{name} pixel ({x}, {y}) light ({lu}, {lv})")
            inside += int(np.all((expected > 0.02) & (expected < 0.98)))
    assert inside >= len(LIGHTS) * len(PIXELS) // 2, "too few pixels away from the clamps"
