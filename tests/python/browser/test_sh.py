"""Real Chromium relights Relight ``type: "sh"`` layers; pixels match the numpy reference.

Two Relight web-format folders written here — ``sh9`` (order 2, 27 planes, rgb) and ``sh4``
(order 1, 12 planes, ycc) — with the bytes and ``info.json`` Relight's builder writes (plane ``p``
is channel ``p % 3`` of ``plane_{p // 3}``, ``(t/255 − bias)·scale``), imported with
``lanterna import`` into one dataset, render in every mode sh supports at three lights within
2/255 of :func:`lanterna.tiler.render.render` over the stored tiles of the same region, across
tile seams.
"""

from __future__ import annotations

import json
from collections.abc import Iterator
from pathlib import Path

import numpy as np
import numpy.typing as npt
import pytest

from lanterna.cli import main
from lanterna.tiler.dataset.writer import read_description
from lanterna.tiler.render import applicable_modes
from tests.python.fixtures.mode_frames import ModeRun as Run
from tests.python.fixtures.mode_frames import check_mode, mode_frames, report
from tests.python.formats.test_relight_web import write_folder

pytestmark = pytest.mark.browser

W, H = 600, 400  # tile seams at x = 256, 512 and y = 256
VIEW = (280, 200)
ORIGIN = (180, 150)  # the region spans the seams x = 256 and y = 256
LIGHTS = [(-0.5, 0.35), (0.0, 0.0), (0.45, -0.55)]
TOLERANCE = 2  # out of 255
C1 = 0.488603  # Relight's band-1 constant: l·n = (n_y·Y1 + n_z·Y2 + n_x·Y3)/C1


def sh_values(rng: np.random.Generator, terms: int) -> npt.NDArray[np.float64]:
    """``(3·terms, H, W)`` plane values (Relight's plane order): a Lambertian relief (band 1 holds
    ``ρ·n/C1``) plus an ambient term and small smooth higher terms."""
    yy, xx = np.mgrid[0:H, 0:W].astype(np.float64)
    n = np.stack([0.5 * np.sin(xx / 37 + yy / 53), 0.45 * np.cos(yy / 29 - xx / 71),
                  np.ones_like(xx)], -1)
    n /= np.linalg.norm(n, axis=-1, keepdims=True)
    rho = np.stack([0.55 + 0.25 * np.sin(xx / 41 + c) * np.cos(yy / 47 - c) for c in range(3)], -1)
    v = np.zeros((terms, H, W, 3))
    v[0] = 0.15 / 0.282095 * rho
    for k, axis in ((1, 1), (2, 2), (3, 0)):
        v[k] = rho * n[..., axis, None] / C1
    for k in range(4, terms):
        v[k] = 0.08 * np.sin(xx / (19 + 3 * k) + yy / (23 + k) + k)[..., None] * rho
    v += rng.normal(0, 0.003, v.shape)
    return v.transpose(0, 3, 1, 2).reshape(3 * terms, H, W)


def quantise(v: npt.NDArray[np.float64]) -> tuple[npt.NDArray[np.uint8], list[float],
                                                    list[float]]:
    """Relight's per-plane quantisation: ``scale = (max − min)``, ``bias = −min/scale``."""
    lo, hi = v.min(axis=(1, 2)), v.max(axis=(1, 2))
    scale = np.maximum(hi - lo, 1e-6)
    bias = -lo / scale
    t = np.rint((v / scale[:, None, None] + bias[:, None, None]) * 255).clip(0, 255)
    return t.astype(np.uint8), [float(s) for s in scale], [float(b) for b in bias]


def to_ycc(v: npt.NDArray[np.float64]) -> npt.NDArray[np.float64]:
    """Relight's ycc planes: luma terms in planes ``3t``, the chroma (light-free) in planes 1, 2."""
    out = v.copy()
    r, g, b = v[0::3], v[1::3], v[2::3]
    y = 0.299 * r + 0.587 * g + 0.114 * b
    out[0::3] = y
    out[1::3], out[2::3] = 0.0, 0.0
    # chroma of the ambient colour, light-independent: Cb = ½ + (B − Y)/1.772 etc., at term 0's Y0
    out[1] = 0.5 + (b[0] - y[0]) * 0.282095 / 1.772
    out[2] = 0.5 + (r[0] - y[0]) * 0.282095 / 1.402
    return out


def write_relight_sh(folder: Path, rng: np.random.Generator, terms: int, colorspace: str) -> None:
    v = sh_values(rng, terms)
    planes, scale, bias = quantise(to_ycc(v) if colorspace == "ycc" else v)
    info = {"width": W, "height": H, "format": "png", "type": "sh", "colorspace": colorspace,
            "nplanes": 3 * terms, "quality": 95, "materials": [{"scale": scale, "bias": bias}]}
    write_folder(folder, info, planes, "png")
    assert json.loads((folder / "info.json").read_text())["type"] == "sh"


@pytest.fixture(scope="module")
def run(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Run]:
    tmp = tmp_path_factory.mktemp("sh")
    rng = np.random.default_rng(16)
    write_relight_sh(tmp / "src" / "sh9", rng, 9, "rgb")
    write_relight_sh(tmp / "src" / "sh4", rng, 4, "ycc")
    root = tmp / "root"
    assert main(["import", str(tmp / "src" / "sh9"), str(tmp / "src" / "sh4"),
                 "-o", str(root / "sh")]) == 0
    blocks = {layer["id"]: layer["service"] for layer in read_description(root / "sh")["layers"]}
    results = mode_frames(root, "sh", blocks, LIGHTS, ORIGIN, VIEW, tmp)
    yield Run(blocks, results)
    print("\n" + report(results))


def test_the_folders_import_as_sh_layers(run: Run) -> None:
    assert {lid: (b["layerType"], b["terms"], len(b["planes"])) for lid, b in run.blocks.items()} \
        == {"sh9": ("sh", 9, 9), "sh4": ("sh", 4, 4)}


LAYER_MODES = [(lid, mode) for lid in ("sh9", "sh4")
               for mode in applicable_modes({"layerType": "sh"})]


@pytest.mark.parametrize("layer, mode", LAYER_MODES)
def test_sh_mode_matches_the_reference(run: Run, layer: str, mode: str) -> None:
    check_mode(run.results, layer, mode, len(LIGHTS), TOLERANCE)


def test_the_light_moves_the_colour_the_way_the_relief_faces(run: Run) -> None:
    for layer in run.blocks:
        (_, left, _), _, (_, right, _) = run.results[(layer, "color")]
        assert np.abs(left - right).mean() > 5, layer
        (_, normals, _) = run.results[(layer, "normals")][1]
        nx = normals[..., 0] / 127.5 - 1
        change = left.mean(axis=-1) - right.mean(axis=-1)  # light from the left minus the right
        corr = float(np.corrcoef(nx.ravel(), change.ravel())[0, 1])
        assert corr < -0.5, f"{layer}: brightening under the left light vs n_x: {corr:.2f}"
