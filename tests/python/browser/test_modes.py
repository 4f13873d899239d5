"""Real Chromium renders every layer type in every applicable mode; pixels match the reference.

One dataset holds a layer of every type (PTM lrgb/rgb, HSH 4/9/16, shape + material with all maps
in linear and sRGB, geometry only, kd only, RGB and grey images). One Chromium run renders every
(layer, mode) at two lights and two zooms (1 image px = 1 screen px at level 0, then at level 1),
plus once with non-default parameters; each frame is compared with
:func:`lanterna.tiler.render.render` over the stored tiles of the same region (the canvas of the
screen-space filters). The regions lie inside the image and span tile seams.
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
import numpy.typing as npt
import pytest

from lanterna.tiler.dataset.layers import (
    add_hsh_layer,
    add_image_layer,
    add_ptm_layer,
    add_svbrdf_layer,
)
from lanterna.tiler.dataset.writer import DatasetWriter
from lanterna.tiler.formats.hsh_model import Hsh
from lanterna.tiler.formats.layouts import encode_normals
from lanterna.tiler.formats.ptm_model import Ptm
from lanterna.tiler.iiif.pyramid import vips_from_array
from lanterna.tiler.render import (
    PARAMETERS,
    applicable_modes,
    hsh_basis,
    level_channels,
    linear_to_srgb,
    render,
)
from tests.python.fixtures import browser
from tests.python.fixtures.fields import smooth_field

pytestmark = pytest.mark.browser

W, H = 640, 480  # level 0: tile seams at x = 256, 512 and y = 256; level 1 (320×240): x = 256
VIEW = (288, 216)
ZOOMS = {1: (200, 180), 2: (16, 12)}  # factor → region origin in level pixels
SEAMS = {1: (256 - 200, 256 - 180), 2: (256 - 16, None)}  # seam column, row on screen
LIGHTS = [(-0.45, 0.3), (0.5, -0.55)]
PARAM_LIGHT = (0.2, 0.7)
TOLERANCE = 2  # out of 255
PARAMS = {  # one non-default set per mode
    "color": {"lightIntensity": 1.6, "gamma": 1.8, "brightness": -0.1},
    "normals": {"gamma": 0.7, "brightness": 0.05},
    "albedo": {"brightness": 0.1, "gamma": 1.2},
    "diffuse": {"lightIntensity": 1.4},
    "achromatic": {"lightIntensity": 1.8, "gamma": 1.5},  # channels > 1: luma of unclamped c
    "specular": {"specKd": 0.6, "specKs": 0.3, "specExponent": 20},
    "diffuseGain": {"diffuseGain": 4.0},
    "unsharpNormals": {"umGain": 3.0, "umKd": 0.8, "umEnv": 1.2},
    "unsharpCoefficients": {"umGain": 2.5},
    "unsharpLuminance": {"umGain": 3.0},
    "unsharpImage": {"umGain": 2.0, "gamma": 1.3},
}


def smooth(rng: np.random.Generator, lo: float, hi: float, shape: tuple[int, ...] = (),
           cell: int = 24, noise: float = 0.15) -> npt.NDArray[np.float64]:
    """A smooth random field (:func:`smooth_field` in 0–1) plus a little per-pixel noise."""
    field_ = smooth_field(rng, 0.0, 1.0, (H, W), shape, cell)
    return lo + (hi - lo) * (field_ * (1 - noise) + noise * rng.uniform(0, 1, field_.shape))


def normal_field(rng: np.random.Generator, min_z: float = 0.3) -> npt.NDArray[np.float64]:
    """Unit normals with ``z >= min_z``: a smooth tilt field plus per-pixel jitter."""
    r = np.sqrt(1 - min_z**2) * np.sqrt(smooth(rng, 0, 1))
    phi = smooth(rng, -np.pi, 3 * np.pi, noise=0.1)
    return np.stack([r * np.cos(phi), r * np.sin(phi), np.sqrt(1 - r * r)], axis=-1)


def to_bytes(x: npt.NDArray[np.float64]) -> npt.NDArray[np.uint8]:
    return np.round(np.clip(x, 0, 1) * 255).astype(np.uint8)


def ptm(colorspace: str, rng: np.random.Generator) -> Ptm:
    """Quadratics with an interior maximum inside the disk (display units), quantised."""
    sets = (H, W) if colorspace == "lrgb" else (H, W, 3)
    ext = (3,) if colorspace == "rgb" else ()
    u0, v0 = smooth(rng, -0.5, 0.5, ext), smooth(rng, -0.5, 0.5, ext)
    a0, a1 = smooth(rng, -0.45, -0.2, ext), smooth(rng, -0.45, -0.2, ext)
    a2 = smooth(rng, -0.1, 0.1, ext)
    a = np.stack([a0, a1, a2, -2 * a0 * u0 - a2 * v0, -2 * a1 * v0 - a2 * u0,
                  smooth(rng, 0.55, 0.9, ext) + a0 * u0**2 + a1 * v0**2 + a2 * u0 * v0], -1)
    scale = np.array([2, 2, 2, 2, 2, 1], np.float32)
    bias = np.array([128, 128, 128, 128, 128, 0], np.int32)
    coef = np.clip(np.round(a * 255 / scale + bias), 0, 255).astype(np.uint8)
    assert coef.shape == sets + (6,)
    rgb = to_bytes(smooth(rng, 0.3, 1.0, (3,))) if colorspace == "lrgb" else None
    return Ptm(colorspace, coef, scale, bias, rgb)


def hsh(terms: int, rng: np.random.Generator) -> Hsh:
    """A least-squares fit of a Lambertian lobe over a normal field, quantised per term."""
    phi, z = rng.uniform(0, 2 * np.pi, 120), rng.uniform(0.15, 1, 120)
    lights = np.stack([np.sqrt(1 - z * z) * np.cos(phi), np.sqrt(1 - z * z) * np.sin(phi), z], -1)
    proj = np.linalg.pinv(hsh_basis(lights[:, 0], lights[:, 1], terms).astype(np.float64))
    lobe = np.maximum(0, normal_field(rng, 0.5).reshape(-1, 3) @ lights.T) @ proj.T
    a = smooth(rng, 0.3, 0.9, (3,)).reshape(-1, 3, 1) * lobe[:, None, :]  # (HW, 3, K)
    lo, hi = a.min(axis=(0, 1)), a.max(axis=(0, 1))
    coef = np.round((a - lo) / (hi - lo) * 255).astype(np.uint8).reshape(H, W, 3, terms)
    return Hsh(coef, (hi - lo).astype(np.float32), lo.astype(np.float32))


def build(out: Path) -> list[dict[str, Any]]:
    """Write the dataset; return every layer's relight service block."""
    rng = np.random.default_rng(2024)
    n = encode_normals(normal_field(rng))
    kd, ks = smooth(rng, 0.05, 0.8, (3,)), smooth(rng, 0.0, 0.4, (3,))
    gloss = to_bytes(smooth(rng, 0, 1))
    with DatasetWriter(out, name="modes", label="Every mode", width=W, height=H) as ds:
        add_ptm_layer(ds, ptm("lrgb", rng), layer_id="ptm_lrgb")
        add_ptm_layer(ds, ptm("rgb", rng), layer_id="ptm_rgb")
        for terms in (4, 9, 16):
            add_hsh_layer(ds, hsh(terms, rng), layer_id=f"hsh{terms}")
        share = {"normals": "n"}
        add_svbrdf_layer(ds, normals=n, kd=to_bytes(kd), ks=to_bytes(ks), gloss=gloss,
                         gloss_limits=(0.05, 0.45), share=share, layer_id="sv_linear")
        add_svbrdf_layer(ds, normals=n, kd=to_bytes(linear_to_srgb(kd)), ks=to_bytes(
            linear_to_srgb(ks)), gloss=gloss, input_colorspace="srgb", share=share,
            layer_id="sv_srgb")
        add_svbrdf_layer(ds, normals=n, kd=to_bytes(kd), ks=to_bytes(ks), gloss=gloss,
                         gloss_limits=(0.05, 0.45), input_colorspace="display", share=share,
                         layer_id="sv_display")
        add_svbrdf_layer(ds, kd=to_bytes(kd), input_colorspace="display",
                         layer_id="sv_display_image")
        add_svbrdf_layer(ds, normals=n, share=share, layer_id="sv_geometry")
        add_svbrdf_layer(ds, kd=to_bytes(kd), layer_id="sv_image")
        add_image_layer(ds, vips_from_array(to_bytes(smooth(rng, 0.1, 0.9, (3,)))),
                        layer_id="img_rgb")
        add_image_layer(ds, vips_from_array(to_bytes(smooth(rng, 0.1, 0.9))), layer_id="img_y",
                        fmt="png")
        return [ds.layer_service(layer) for layer in ds.layers]


@dataclass
class ModeShot:
    """One frame: a layer, mode, parameters, light and zoom factor."""

    layer: str
    mode: str
    light: tuple[float, float]
    factor: int
    params: dict[str, float] = field(default_factory=dict)
    out: Path = Path()

    @property
    def region(self) -> tuple[int, int, int, int]:
        """The fitted region in full-resolution image pixels."""
        x, y = ZOOMS[self.factor]
        f = self.factor
        return (x * f, y * f, VIEW[0] * f, VIEW[1] * f)


def full_params(overrides: dict[str, float]) -> dict[str, float]:
    """Every parameter, defaults overridden: sent in full, so no shot inherits another's."""
    return {name: spec[0] for name, spec in PARAMETERS.items()} | overrides


@dataclass
class Run:
    """Frames and references of every shot, by (layer, mode)."""

    layers: dict[str, dict[str, Any]]
    results: dict[tuple[str, str], list[tuple[ModeShot, npt.NDArray[np.int16],
                                             npt.NDArray[np.int16]]]]


@pytest.fixture(scope="module")
def run(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Run]:
    tmp = tmp_path_factory.mktemp("modes")
    layers = {b["id"].rsplit("/", 1)[1].removesuffix(".json"): b for b in build(tmp / "modes")}
    shots: list[ModeShot] = []
    for lid, block in layers.items():
        for mode in applicable_modes(block):
            shots += [ModeShot(lid, mode, light, f) for f in ZOOMS for light in LIGHTS]
            shots.append(ModeShot(lid, mode, PARAM_LIGHT, 1, PARAMS[mode]))
    for i, s in enumerate(shots):
        s.out = tmp / f"shot{i:04d}.rgba"
    frames = browser.render_dataset(tmp, "modes", [browser.Shot(s.light, s.region, s.out, s.layer,
                                                                s.mode, full_params(s.params))
                                                   for s in shots], viewport=VIEW)
    channels = {(lid, f): level_channels(tmp / "modes", block, f, ZOOMS[f] + VIEW)
                for lid, block in layers.items() for f in ZOOMS}
    results: dict[tuple[str, str], list[Any]] = {}
    for s, frame in zip(shots, frames, strict=True):
        ref = render(layers[s.layer], channels[(s.layer, s.factor)], s.light, s.mode, s.params)
        expected = np.round(ref * 255).astype(np.int16)
        assert frame.shape == (VIEW[1], VIEW[0], 4), frame.shape
        assert (frame[..., 3] == 255).all(), f"{s.layer} {s.mode}: the view must be opaque"
        results.setdefault((s.layer, s.mode), []).append(
            (s, frame[..., :3].astype(np.int16), expected))
    yield Run(layers, results)
    report = ["layer/mode                       max  mean(/255)"]
    for (lid, mode), items in results.items():
        diffs = [np.abs(got - exp) for _, got, exp in items]
        report.append(f"{lid + '/' + mode:32} {max(int(d.max()) for d in diffs):3d}  "
                      f"{np.mean([d.mean() for d in diffs]):.4f}")
    (tmp / "differences.txt").write_text("\n".join(report) + "\n")
    print("\n" + "\n".join(report))


LAYER_MODES = [(lid, m) for lid, kind in [
    ("ptm_lrgb", {"layerType": "ptm", "colorspace": "lrgb"}),
    ("ptm_rgb", {"layerType": "ptm", "colorspace": "rgb"}),
    ("hsh4", {"layerType": "hsh"}), ("hsh9", {"layerType": "hsh"}),
    ("hsh16", {"layerType": "hsh"}),
    ("sv_linear", {"layerType": "svbrdf", "planes": [{"channels": ["NX"]}]}),
    ("sv_srgb", {"layerType": "svbrdf", "planes": [{"channels": ["NX"]}]}),
    ("sv_display", {"layerType": "svbrdf", "planes": [{"channels": ["NX"]}]}),
    ("sv_display_image", {"layerType": "svbrdf", "planes": [{"channels": ["KD_R"]}]}),
    ("sv_geometry", {"layerType": "svbrdf", "planes": [{"channels": ["NX"]}]}),
    ("sv_image", {"layerType": "svbrdf", "planes": [{"channels": ["KD_R"]}]}),
    ("img_rgb", {"layerType": "image"}), ("img_y", {"layerType": "image"}),
] for m in applicable_modes(kind)]


@pytest.mark.parametrize("layer, mode", LAYER_MODES)
def test_mode_matches_the_reference(run: Run, layer: str, mode: str) -> None:
    items = run.results[(layer, mode)]
    assert len(items) == 2 * len(LIGHTS) + 1
    for shot, got, expected in items:
        diff = np.abs(got - expected)
        bad = np.argwhere(diff.max(axis=-1) > TOLERANCE)
        assert bad.size == 0, (
            f"{layer}/{mode} light={shot.light} zoom 1/{shot.factor} params={shot.params}: "
            f"{len(bad)} pixels off by up to {diff.max()}/255, first at (row, col) "
            f"{tuple(bad[0])}: got {got[tuple(bad[0])]}, expected {expected[tuple(bad[0])]}")
    # the picture is not flat (but a geometry layer's albedo is the default kd everywhere)
    if (layer, mode) != ("sv_geometry", "albedo"):
        assert max(float(exp.std()) for _, _, exp in items) > 5


@pytest.mark.parametrize("layer, mode", [(lid, m) for lid, m in LAYER_MODES
                                         if m.startswith("unsharp")])
def test_unsharp_modes_have_no_seams(run: Run, layer: str, mode: str) -> None:
    """Across a tile seam the step between neighbours matches the reference's."""
    for shot, got, expected in run.results[(layer, mode)]:
        col, row = SEAMS[shot.factor]
        err = (got - expected).astype(np.float64)
        steps = [err[:, col] - err[:, col - 1]]
        if row is not None:
            steps.append(err[row] - err[row - 1])
        for step in steps:
            assert abs(step.mean()) < 0.25 and np.abs(step).max() <= TOLERANCE, (
                f"{layer}/{mode} zoom 1/{shot.factor}: a jump at the seam, mean "
                f"{step.mean():.2f}, max {np.abs(step).max()}")
