"""Real Chromium relights PCA layers (rbf, bilinear; mrgb, mycc); pixels match the numpy reference.

Synthetic layers written here with :class:`PcaBasis` and the dataset writer (an rbf mycc layer, and
a bilinear mrgb one whose last plane group is padded) render in every mode they support at two
lights, within 2/255 of :func:`lanterna.tiler.render.render` over the stored tiles of the same
region (the canvas of the screen-space filters), across tile seams. Relight's own coin outputs are
in ``test_pca_realdata.py``.
"""

from __future__ import annotations

import json
import re
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from lanterna.tiler.dataset.layers import add_planes_layer
from lanterna.tiler.dataset.writer import DatasetWriter
from lanterna.tiler.formats.pca_model import PcaBasis, plane_channel_names
from lanterna.tiler.formats.planes import PlaneGroup, PlaneLayer
from lanterna.tiler.render import applicable_modes
from tests.python.fixtures import browser
from tests.python.fixtures.mode_frames import ModeRun as Run
from tests.python.fixtures.mode_frames import check_mode, mode_frames, report
from tests.python.fixtures.servers import LiveServer

pytestmark = pytest.mark.browser

W, H = 600, 400  # tile seams at x = 256, 512 and y = 256
VIEW = (280, 200)
ORIGIN = (180, 150)  # the region spans the seams x = 256 and y = 256
LIGHTS = [(-0.45, 0.3), (0.5, -0.55)]
TOLERANCE = 2  # out of 255


def lambertian_basis(rng: np.random.Generator, layer_type: str, colorspace: str,
                     nplanes: int) -> PcaBasis:
    """A basis whose mean is a Lambertian lobe and whose planes perturb it (Relight's bytes)."""
    if layer_type == "rbf":
        phi, z = rng.uniform(0, 2 * np.pi, 60), rng.uniform(0.2, 1.0, 60)
        lights = np.stack([np.sqrt(1 - z * z) * np.cos(phi), np.sqrt(1 - z * z) * np.sin(phi), z],
                          -1)
        samples, extra = lights, {"lights": tuple(float(v) for v in lights.ravel()),
                                  "sigma": 0.3}
    else:
        res = 8
        y, x = np.mgrid[0:res, 0:res] / (res - 1) * 2 - 1  # octahedral square, rotated 45°
        u, v = (x - y) / 2, (x + y) / 2
        lz = 1 - np.abs(u) - np.abs(v)
        samples = np.stack([u, v, lz], -1).reshape(-1, 3)
        samples /= np.linalg.norm(samples, axis=1, keepdims=True)
        extra = {"resolution": res}
    d = len(samples)
    mean = np.clip(0.25 + 0.7 * np.maximum(samples[:, 2], 0), 0, 1)[:, None] * [0.9, 0.8, 0.7]
    planes = rng.integers(60, 195, (nplanes, d, 3))
    basis = np.concatenate([np.round(mean * 255)[None], planes]).astype(np.uint8).ravel()
    ranges = tuple(float(v) for v in rng.uniform(250, 700, nplanes))
    ycc = (nplanes - 2 * (nplanes // 3), nplanes // 3, nplanes // 3)
    return PcaBasis(layer_type, colorspace, basis, ranges,
                    yccplanes=ycc if colorspace == "mycc" else None, **extra)


def pca_layer(rng: np.random.Generator, basis: PcaBasis) -> PlaneLayer:
    """Smooth random coefficients for the basis, quantised with one scale and a bias per plane."""
    yy, xx = np.mgrid[0:H, 0:W].astype(np.float64)
    groups = []
    for g, names in enumerate(plane_channel_names(basis.nplanes)):
        waves = [np.sin(xx / (23 + 7 * k + g) + yy / (31 + 5 * g + k) + k) for k in range(3)]
        t = np.stack(waves, -1) * 0.35 + 0.5 + rng.normal(0, 0.02, (H, W, 3))
        data = np.round(np.clip(t, 0, 1) * 255).astype(np.uint8)
        pad = [name.startswith("X") for name in names]
        groups.append(PlaneGroup(list(names), data, [0.0 if p else 0.8 for p in pad],
                                 [0.0 if p else 0.5 for p in pad]))
    return PlaneLayer(basis.layer_type, groups, pca=basis)


def build(out: Path) -> dict[str, dict[str, Any]]:
    """Write the dataset; return each layer's relight service block by layer id."""
    rng = np.random.default_rng(15)
    layers = {"rbf_mycc": lambertian_basis(rng, "rbf", "mycc", 9),
              "bilinear_mrgb": lambertian_basis(rng, "bilinear", "mrgb", 7)}
    with DatasetWriter(out, name="pca", label="PCA layers", width=W, height=H) as ds:
        for lid, basis in layers.items():
            add_planes_layer(ds, pca_layer(rng, basis), layer_id=lid, label=lid)
        return {layer["id"]: ds.layer_service(layer) for layer in ds.layers}


@pytest.fixture(scope="module")
def run(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Run]:
    tmp = tmp_path_factory.mktemp("pca")
    blocks = build(tmp / "pca")
    results = mode_frames(tmp, "pca", blocks, LIGHTS, ORIGIN, VIEW, tmp)
    yield Run(blocks, results)
    print("\n" + report(results))


LAYER_MODES = [(lid, mode) for lid, layer_type in [("rbf_mycc", "rbf"),
                                                   ("bilinear_mrgb", "bilinear")]
               for mode in applicable_modes({"layerType": layer_type})]


def test_the_modes_are_hsh_s() -> None:
    assert [m for lid, m in LAYER_MODES if lid == "rbf_mycc"] == [
        "color", "normals", "albedo", "diffuse", "achromatic", "specular", "unsharpNormals",
        "unsharpCoefficients", "unsharpImage"]


@pytest.mark.parametrize("layer, mode", LAYER_MODES)
def test_pca_mode_matches_the_reference(run: Run, layer: str, mode: str) -> None:
    check_mode(run.results, layer, mode, len(LIGHTS), TOLERANCE)


def test_the_light_moves_the_colour(run: Run) -> None:
    for layer in run.blocks:
        (_, a, _), (_, b, _) = run.results[(layer, "color")]
        assert np.abs(a - b).mean() > 5, layer


def test_a_bad_pca_block_is_a_one_line_message_naming_the_field(
        tmp_path: Path, live_server: Callable[[Path], LiveServer]) -> None:
    rng = np.random.default_rng(3)
    basis = lambertian_basis(rng, "rbf", "mrgb", 4)
    with DatasetWriter(tmp_path / "root" / "bad", name="bad", label="Bad", width=W,
                       height=H) as ds:
        add_planes_layer(ds, pca_layer(rng, basis), layer_id="coin", label="coin")
    server = live_server(tmp_path / "root")
    url = f"{server.url}/datasets/bad/manifest.json"
    manifest = json.loads((tmp_path / "root" / "bad" / "manifest.json").read_text())
    size = len(basis.basis)
    blocks = find_relight_blocks(manifest)
    assert [b["layerType"] for b in blocks] == ["rbf"]
    blocks[0]["basis"] = blocks[0]["basis"][:-1]
    routes = [{"match": f"^{re.escape(url)}$", "status": 200, "body": json.dumps(manifest),
               "contentType": "application/json"}]
    result = browser.open_failing(f"{server.url}/viewer/?manifest={url}", tmp_path / "page",
                                  options={"routes": routes,
                                           "allowConsoleErrors": [r"^\[lanterna\]"]})
    assert result["readyError"]["name"] == "RelightServiceError", result["readyError"]
    problem = result["errorBox"]["problem"] or ""
    assert f"coin.basis: {size - 1} values, expected {size}" in problem, problem
    assert "\n" not in result["readyError"]["message"]
    assert result["pageErrors"] == []


def find_relight_blocks(doc: Any) -> list[dict[str, Any]]:
    """Every LanternaRelight block of a manifest."""
    if isinstance(doc, dict):
        if doc.get("type") == "LanternaRelight":
            return [doc]
        return [b for v in doc.values() for b in find_relight_blocks(v)]
    if isinstance(doc, list):
        return [b for v in doc for b in find_relight_blocks(v)]
    return []
