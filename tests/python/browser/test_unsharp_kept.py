"""Real Chromium: the kept filtered quantity of the unsharp modes stays right.

The unsharp modes whose quantity does not read the light (``unsharpNormals``; ``unsharpImage`` on
an unlit layer) keep the filtered quantity of the view, ``unsharpNormals`` also the normal and
albedo of each pixel, and ``unsharpCoefficients``/``unsharpLuminance`` on PTM lrgb the filtered
luminance coefficients, while only the light moves (docs/rendering.md, "What is kept while the
light moves"). One Chromium run moves the light several times over one view, then changes the
parameters, pans, zooms, switches layers and back, and shows the same mode in the lens on another
layer; every frame must equal the numpy reference of its own light, view and parameters, so a kept
result that was not recomputed when it should have been (or one lens and base overwrote) shows
as wrong pixels. The relit quantities (``unsharpCoefficients`` on PTM rgb, ``unsharpImage`` on a
lit layer) are filtered again every frame: their frames must follow the light.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np
import numpy.typing as npt
import pytest

from lanterna.tiler.render import level_channels, render
from tests.python.browser.test_modes import TOLERANCE, VIEW, build, full_params
from tests.python.fixtures import browser

pytestmark = pytest.mark.browser

NORMALS = {"umGain": 3.0, "umKd": 0.8, "umEnv": 1.2}
LIGHTS = [(-0.45, 0.3), (0.5, -0.55), (0.1, 0.6), (-0.6, -0.2), (0.3, 0.3)]
LENS_C, LENS_R = (144, 108), 60
LENS = {"enabled": True, "center": list(LENS_C), "radius": LENS_R, "opacity": 1}


@dataclass
class Step:
    """One frame: layer, mode, light, region origin and zoom factor, parameters, optional lens."""

    name: str
    layer: str
    mode: str
    light: tuple[float, float]
    origin: tuple[int, int] = (200, 180)
    factor: int = 1
    params: dict[str, float] = field(default_factory=lambda: dict(NORMALS))
    lens: dict[str, Any] | None = None

    @property
    def region(self) -> tuple[int, int, int, int]:
        """The fitted region in full-resolution image pixels."""
        f = self.factor
        return (self.origin[0] * f, self.origin[1] * f, VIEW[0] * f, VIEW[1] * f)


L0, L1, L2, L3, L4 = LIGHTS
STEPS = [
    # several light moves over one view: the kept quantity is reused
    *[Step(f"light{i}", "ptm_lrgb", "unsharpNormals", light) for i, light in enumerate(LIGHTS)],
    # the combine's parameters (strength, kd, ambient) and the post step (gamma: another program)
    Step("gain", "ptm_lrgb", "unsharpNormals", L1, params={**NORMALS, "umGain": 1.2}),
    Step("kd", "ptm_lrgb", "unsharpNormals", L2, params={"umGain": 2.0, "umKd": 1.4, "umEnv": 0.3}),
    Step("gamma", "ptm_lrgb", "unsharpNormals", L3, params={**NORMALS, "gamma": 1.6}),
    # the view changes: recomputed
    Step("pan", "ptm_lrgb", "unsharpNormals", L0, origin=(232, 196)),
    Step("pan-light", "ptm_lrgb", "unsharpNormals", L4, origin=(232, 196)),
    Step("zoom", "ptm_lrgb", "unsharpNormals", L1, origin=(16, 12), factor=2),
    Step("zoom-light", "ptm_lrgb", "unsharpNormals", L2, origin=(16, 12), factor=2),
    # another layer (and kind), then back
    Step("hsh", "hsh9", "unsharpNormals", L3),
    Step("hsh-light", "hsh9", "unsharpNormals", L0),
    Step("svbrdf", "sv_linear", "unsharpNormals", L1),
    Step("back", "ptm_lrgb", "unsharpNormals", L4),
    Step("back-light", "ptm_lrgb", "unsharpNormals", L2),
    # the same mode in the lens on another layer: base and lens keep apart
    *[Step(f"lens{i}", "ptm_lrgb", "unsharpNormals", light,
           lens={**LENS, "layer": "hsh9", "mode": "unsharpNormals", "params": NORMALS})
      for i, light in enumerate([L0, L1, L2])],
    # an unlit layer's unsharpImage is kept too
    *[Step(f"image{i}", "img_rgb", "unsharpImage", light, params={"umGain": 2.0})
      for i, light in enumerate([L0, L1])],
    Step("image-pan", "img_rgb", "unsharpImage", L1, origin=(232, 196), params={"umGain": 2.0}),
    # PTM lrgb: the luminance coefficients are filtered once per view
    *[Step(f"coef{i}", "ptm_lrgb", "unsharpCoefficients", light, params={"umGain": 2.5})
      for i, light in enumerate([L0, L1, L2])],
    Step("coef-gain", "ptm_lrgb", "unsharpCoefficients", L3, params={"umGain": 4.0}),
    Step("coef-pan", "ptm_lrgb", "unsharpCoefficients", L3, origin=(232, 196),
         params={"umGain": 4.0}),
    *[Step(f"lum{i}", "ptm_lrgb", "unsharpLuminance", light, params={"umGain": 3.0})
      for i, light in enumerate([L0, L1])],
    # the relit quantities follow the light
    *[Step(f"rgb-coef{i}", "ptm_rgb", "unsharpCoefficients", light, params={"umGain": 2.5})
      for i, light in enumerate([L0, L1])],
    *[Step(f"relit-image{i}", "hsh9", "unsharpImage", light, params={"umGain": 2.0})
      for i, light in enumerate([L0, L1])],
]


def disk(cx: float, cy: float, r: float) -> npt.NDArray[np.bool_]:
    """Pixels of the view whose centres lie within r of (cx, cy)."""
    y, x = np.mgrid[0: VIEW[1], 0: VIEW[0]] + 0.5
    inside: npt.NDArray[np.bool_] = (x - cx) ** 2 + (y - cy) ** 2 <= r * r
    return inside


@pytest.fixture(scope="module")
def frames(tmp_path_factory: pytest.TempPathFactory) -> dict[str, tuple[Step, Any, Any]]:
    """Every step's frame (RGB, int16) and its reference, by step name."""
    tmp = tmp_path_factory.mktemp("unsharp_kept")
    layers = {b["id"].rsplit("/", 1)[1].removesuffix(".json"): b for b in build(tmp / "modes")}
    shots = []
    for i, s in enumerate(STEPS):
        extra: dict[str, Any] = {"lens": s.lens or {"enabled": False}}
        shots.append(browser.Shot(s.light, s.region, tmp / f"step{i:02d}.rgba", s.layer, s.mode,
                                  full_params(s.params), extra))
    got = browser.render_dataset(tmp, "modes", shots, viewport=VIEW)

    def reference(layer: str, s: Step, mode: str, params: dict[str, float]) -> Any:
        ch = level_channels(tmp / "modes", layers[layer], s.factor, s.origin + VIEW)
        return np.round(render(layers[layer], ch, s.light, mode, params) * 255).astype(np.int16)

    out: dict[str, tuple[Step, Any, Any]] = {}
    for s, frame in zip(STEPS, got, strict=True):
        assert frame.shape == (VIEW[1], VIEW[0], 4)
        expected = reference(s.layer, s, s.mode, s.params)
        if s.lens:
            lens_ref = reference(s.lens["layer"], s, s.lens["mode"], s.lens["params"])
            # the lens layer's filter sees only its tiles under the lens: compare its core (F5
            # reaches 10 px) with the lens layer's reference, and the base beyond the rim
            core = disk(*LENS_C, LENS_R - 16)
            expected = np.where(core[..., None], lens_ref, expected)
            skip = disk(*LENS_C, LENS_R + 1.5) & ~core
            expected = np.where(skip[..., None], -1, expected)
        out[s.name] = (s, frame[..., :3].astype(np.int16), expected)
    return out


@pytest.mark.parametrize("name", [s.name for s in STEPS])
def test_frame_equals_the_reference(frames: dict[str, tuple[Step, Any, Any]], name: str) -> None:
    s, got, expected = frames[name]
    checked = expected[..., 0] >= 0
    diff = np.where(checked[..., None], np.abs(got - expected), 0)
    bad = np.argwhere(diff.max(axis=-1) > TOLERANCE)
    assert bad.size == 0, (
        f"{name}: {s.layer}/{s.mode} light={s.light} origin={s.origin} 1/{s.factor} "
        f"params={s.params}: {len(bad)} pixels off by up to {diff.max()}/255, first at "
        f"{tuple(bad[0])}: got {got[tuple(bad[0])]}, expected {expected[tuple(bad[0])]}")


def test_the_light_moves_change_the_picture(frames: dict[str, tuple[Step, Any, Any]]) -> None:
    """The frames of one view under different lights differ (the reuse is not of a stale frame)."""
    for names in (["light0", "light1", "light2", "light3", "light4"], ["lens0", "lens1", "lens2"],
                  ["coef0", "coef1", "coef2"], ["lum0", "lum1"], ["rgb-coef0", "rgb-coef1"],
                  ["relit-image0", "relit-image1"]):
        pictures = [frames[n][1] for n in names]
        for a, b in zip(pictures, pictures[1:], strict=False):
            assert np.abs(a - b).mean() > 3, f"{names}: the light did not change the picture"


def test_the_sharpening_shows(frames: dict[str, tuple[Step, Any, Any]]) -> None:
    """The references with sharpening differ from those with less: the parameters are tested."""
    _, _, strong = frames["light1"]
    _, _, weak = frames["gain"]
    assert np.abs(strong - weak).max() > 10


def test_a_lens_on_the_same_mode_shows_its_own_layer(
        frames: dict[str, tuple[Step, Any, Any]]) -> None:
    """Inside the lens the hsh9 picture, outside the base's (they differ: a mix-up would show)."""
    _, got, _ = frames["lens0"]
    _, base, _ = frames["light0"]
    core = disk(*LENS_C, LENS_R - 16)
    assert np.abs(got - base)[core].mean() > 5
    outside = ~disk(*LENS_C, LENS_R + 1.5)
    assert np.abs(got - base)[outside].max() <= TOLERANCE
