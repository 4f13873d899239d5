"""Real Chromium: multi-scale annotation overlays, the hypertext widget and the lens.

One dataset: a PTM layer ``base`` (with an overlay at levels 0 and 1, none at level 2) and an RGB
image layer ``second``. The viewer fits regions so that at zoom 1/f one device pixel is one pixel
of level log2(f); frames are compared with :func:`lanterna.tiler.render.render` over the stored
tiles of that level, composited with the stored overlay level image where one is expected.
"""

from __future__ import annotations

import json
import re
from collections.abc import Iterator
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
import numpy.typing as npt
import pytest
import pyvips

from lanterna.tiler.dataset import DatasetWriter
from lanterna.tiler.layers import add_image_layer, add_ptm_layer
from lanterna.tiler.overlays import build_overlays
from lanterna.tiler.ptm_model import Ptm
from lanterna.tiler.pyramid import vips_from_array
from lanterna.tiler.render import level_channels, level_image, render

from . import browser
from .conftest import LiveServer

pytestmark = pytest.mark.browser

W, H = 1024, 768
TILE = 128
VIEW = (256, 192)
LIGHT = (0.3, 0.4)
TOLERANCE = 2  # out of 255
RED, GREEN = (230, 20, 20), (20, 210, 40)
# Overlay patches (full-resolution rectangles): level 0 red, level 1 green; nothing at level 2.
PATCHES = {0: (RED, (160, 140, 120, 90)), 1: (GREEN, (220, 160, 240, 200))}
TEXTS = {"0": {"short": "Glyph detail", "long": "<p>A <b>glyph</b>.<script>bad()</script></p>"},
         "1": {"short": "Whole panel", "long": "<p>The panel.</p>"}}
ORIGIN = {1: (120, 100), 2: (60, 50), 4: (0, 0)}  # zoom factor → region origin in level px
TILE_URL = re.compile(r"/iiif/(?P<image>[A-Za-z0-9_-]+)/(?P<region>full|\d+,\d+,\d+,\d+)/")


def smooth(rng: np.random.Generator, lo: float, hi: float, shape: tuple[int, ...] = (),
           cell: int = 32) -> npt.NDArray[np.float64]:
    """A smooth random field (bilinear over a coarse grid)."""
    coarse = rng.uniform(lo, hi, (H // cell + 2, W // cell + 2) + shape)
    y, x = np.arange(H) / cell, np.arange(W) / cell
    y0, x0 = y.astype(int), x.astype(int)
    fy = (y - y0).reshape((H, 1) + (1,) * len(shape))
    fx = (x - x0).reshape((1, W) + (1,) * len(shape))
    top = coarse[y0][:, x0] * (1 - fx) + coarse[y0][:, x0 + 1] * fx
    bottom = coarse[y0 + 1][:, x0] * (1 - fx) + coarse[y0 + 1][:, x0 + 1] * fx
    out: npt.NDArray[np.float64] = top * (1 - fy) + bottom * fy
    return out


def base_ptm(rng: np.random.Generator) -> Ptm:
    """An LRGB PTM with an interior maximum, in range for every light."""
    a0, a1 = smooth(rng, -0.45, -0.2), smooth(rng, -0.45, -0.2)
    u0, v0 = smooth(rng, -0.4, 0.4), smooth(rng, -0.4, 0.4)
    a = np.stack([a0, a1, np.zeros_like(a0), -2 * a0 * u0, -2 * a1 * v0,
                  smooth(rng, 0.5, 0.8) + a0 * u0**2 + a1 * v0**2], -1)
    scale = np.array([2, 2, 2, 2, 2, 1], np.float32)
    bias = np.array([128, 128, 128, 128, 128, 0], np.int32)
    coef = np.clip(np.round(a * 255 / scale + bias), 0, 255).astype(np.uint8)
    rgb = np.round(smooth(rng, 0.3, 1.0, (3,)) * 255).astype(np.uint8)
    return Ptm("lrgb", coef, scale, bias, rgb)


def write_patches(folder: Path) -> None:
    """One opaque rectangle per level, with a soft 6-px alpha ramp on its left side."""
    folder.mkdir()
    for level, (colour, (x, y, w, h)) in PATCHES.items():
        px = np.zeros((h, w, 4), np.uint8)
        px[..., :3] = colour
        px[..., 3] = 255
        px[:, :6, 3] = np.linspace(40, 220, 6).astype(np.uint8)
        pyvips.Image.new_from_array(px).copy(interpretation="srgb").write_to_file(
            str(folder / f"{level}_{x}_{y}_{w}_{h}_0_patch{level}.png"))


@dataclass
class Dataset:
    root: Path
    blocks: dict[str, dict[str, Any]]

    @property
    def dir(self) -> Path:
        return self.root / "lens"


@pytest.fixture(scope="module")
def dataset(tmp_path_factory: pytest.TempPathFactory) -> Dataset:
    tmp = tmp_path_factory.mktemp("lens")
    rng = np.random.default_rng(11)
    with DatasetWriter(tmp / "lens", name="lens", label="Lens and overlays", width=W, height=H,
                       tile_size=TILE) as ds:
        add_ptm_layer(ds, base_ptm(rng), layer_id="base", label="Base")
        second = np.round(smooth(rng, 0.1, 0.9, (3,)) * 255).astype(np.uint8)
        add_image_layer(ds, vips_from_array(second), layer_id="second", label="Second", fmt="png")
        blocks = {layer["id"]: ds.layer_service(layer) for layer in ds.layers}
    write_patches(tmp / "patches")
    report = build_overlays(tmp / "lens", "base", patches_dir=tmp / "patches", texts=TEXTS)
    assert report.levels == [0, 1] and not report.errors
    return Dataset(tmp, blocks)


@dataclass
class LensShot(browser.Shot):
    """A browser shot with the lens, overlay and gesture fields of render.mjs."""

    lens: dict[str, Any] | None = None
    overlays: bool | None = None
    gestures: list[dict[str, Any]] = field(default_factory=list)

    def spec(self) -> dict[str, object]:
        out = super().spec()
        if self.lens is not None:
            out["lens"] = self.lens
        if self.overlays is not None:
            out["overlays"] = self.overlays
        if self.gestures:
            out["gestures"] = self.gestures
        return out

    def meta(self) -> dict[str, Any]:
        """What render.mjs wrote beside the frame (state after the shot, requests)."""
        result: dict[str, Any] = json.loads(Path(str(self.out) + ".json").read_text())
        return result


def region(factor: int) -> tuple[int, int, int, int]:
    x, y = ORIGIN[factor]
    return (x * factor, y * factor, VIEW[0] * factor, VIEW[1] * factor)


def shots_and_frames(dataset: Dataset, shots: list[LensShot],
                     viewport: tuple[int, int] = VIEW) -> list[npt.NDArray[np.uint8]]:
    server = LiveServer(dataset.root)
    try:
        url = f"{server.url}/viewer/?manifest={server.url}/datasets/lens/manifest.json&layer=base"
        return browser.render(url, list(shots), viewport=viewport)
    finally:
        server.close()


def reference(dataset: Dataset, layer: str, factor: int, mode: str = "color",
              light: tuple[float, float] = LIGHT) -> npt.NDArray[np.float32]:
    """The layer rendered at zoom 1/factor over the shot's view, display values 0–1."""
    x, y = ORIGIN[factor]
    ch = level_channels(dataset.dir, dataset.blocks[layer], factor, (x, y) + VIEW)
    out: npt.NDArray[np.float32] = render(dataset.blocks[layer], ch, light, mode)
    return out


def overlay_at(dataset: Dataset, level: int, factor: int) -> npt.NDArray[np.float32]:
    """The stored level image over the shot's view (RGBA 0–1; transparent outside the image)."""
    img = level_image(dataset.dir / "iiif" / f"base_ov{level}", 1).astype(np.float32) / 255
    x, y = ORIGIN[factor]
    out = np.zeros((VIEW[1], VIEW[0], 4), np.float32)
    crop = img[y: y + VIEW[1], x: x + VIEW[0]]
    out[: crop.shape[0], : crop.shape[1]] = crop
    return out


def over(ref: npt.NDArray[np.float32], ov: npt.NDArray[np.float32]) -> npt.NDArray[np.int16]:
    """Premultiplied source-over of the overlay on the reference, in bytes."""
    a = ov[..., 3:4]
    return np.round((ov[..., :3] * a + ref * (1 - a)) * 255).astype(np.int16)


def assert_close(got: npt.NDArray[np.uint8], expected: npt.NDArray[np.int16],
                 mask: npt.NDArray[np.bool_], what: str) -> None:
    diff = np.abs(got[..., :3].astype(np.int16) - expected).max(axis=-1)
    diff = np.where(mask, diff, 0)
    bad = np.argwhere(diff > TOLERANCE)
    assert mask.sum() > 100, f"{what}: too few pixels checked ({mask.sum()})"
    assert bad.size == 0, (
        f"{what}: {len(bad)} of {mask.sum()} pixels off by up to {diff.max()}/255, first at "
        f"(row, col) {tuple(bad[0])}: got {got[tuple(bad[0])][:3]}, expected "
        f"{expected[tuple(bad[0])]}")


def disk(cx: float, cy: float, r: float) -> npt.NDArray[np.bool_]:
    """Pixels whose centres lie within r of (cx, cy) (CSS px = device px here)."""
    y, x = np.mgrid[0: VIEW[1], 0: VIEW[0]] + 0.5
    inside: npt.NDArray[np.bool_] = (x - cx) ** 2 + (y - cy) ** 2 <= r * r
    return inside


# -- overlays and hypertext ----------------------------------------------------------------------
@pytest.fixture(scope="module")
def zoom_shots(dataset: Dataset) -> Iterator[list[tuple[LensShot, npt.NDArray[np.uint8]]]]:
    out = dataset.root / "shots"
    out.mkdir()
    shots = [LensShot(LIGHT, region(f), out / f"zoom{f}.rgba") for f in (1, 2, 4)]
    shots.append(LensShot(LIGHT, region(1), out / "hidden.rgba", overlays=False))
    frames = shots_and_frames(dataset, shots)
    yield list(zip(shots, frames, strict=True))


def test_overlay_of_level_k_is_drawn_only_at_zoom_k(
        dataset: Dataset, zoom_shots: list[tuple[LensShot, npt.NDArray[np.uint8]]]) -> None:
    everywhere = np.ones((VIEW[1], VIEW[0]), bool)
    for (_shot, frame), factor in zip(zoom_shots[:3], (1, 2, 4), strict=True):
        level = factor.bit_length() - 1
        ref = reference(dataset, "base", factor)
        if level in PATCHES:
            ov = overlay_at(dataset, level, factor)
            opaque = ov[..., 3] == 1
            assert opaque.sum() > 2000, "the view must show a good part of the patch"
            assert_close(frame, over(ref, ov), everywhere, f"zoom 1/{factor} with its overlay")
            colour = np.array(PATCHES[level][0])
            assert (np.abs(frame[opaque][:, :3].astype(int) - colour) <= TOLERANCE).all()
        else:
            assert_close(frame, np.round(ref * 255).astype(np.int16), everywhere,
                         f"zoom 1/{factor}: no overlay at level {level}")
        # (the whole frame matches the reference with only level k's image: no other level shows)


def test_only_the_current_levels_overlay_loads(
        zoom_shots: list[tuple[LensShot, npt.NDArray[np.uint8]]]) -> None:
    """Overlay items of other levels have opacity 0: none of their tiles or info.json loads."""
    info = re.compile(r"/iiif/(?P<image>[A-Za-z0-9_-]+)/info\.json")
    for (shot, _), level in zip(zoom_shots[:3], (0, 1, 2), strict=True):
        urls = shot.meta()["requests"]
        fetched = {m["image"] for m in (TILE_URL.search(u) or info.search(u) for u in urls) if m}
        overlays = {i for i in fetched if "_ov" in i}
        assert overlays == ({f"base_ov{level}"} if level in PATCHES else set()), (level, overlays)


def test_overlays_can_be_hidden(dataset: Dataset,
                                zoom_shots: list[tuple[LensShot, npt.NDArray[np.uint8]]]) -> None:
    shot, frame = zoom_shots[3]
    ref = np.round(reference(dataset, "base", 1) * 255).astype(np.int16)
    assert_close(frame, ref, np.ones(frame.shape[:2], bool), "overlays hidden")
    assert shot.meta()["overlayState"]["available"] is True  # the state still reports the level


def test_hypertext_follows_the_zoom(
        zoom_shots: list[tuple[LensShot, npt.NDArray[np.uint8]]]) -> None:
    states = [shot.meta() for shot, _ in zoom_shots[:3]]
    assert [s["overlayState"]["level"] for s in states] == [0, 1, 2]
    assert [s["overlayState"]["available"] for s in states] == [True, True, False]
    assert [s["overlayState"]["short"] for s in states] == ["Glyph detail", "Whole panel", ""]
    assert [s["hypertext"] for s in states] == ["Glyph detail", "Whole panel",
                                                "No annotation at this level"]
    long = states[0]["overlayState"]["long"]
    assert long == "<p>A <b>glyph</b>.</p>", "the long text is sanitised (no script)"


# -- lens ----------------------------------------------------------------------------------------
LENS_C, LENS_R = (128, 96), 56
LENS: dict[str, Any] = {"enabled": True, "center": list(LENS_C), "radius": LENS_R, "opacity": 1}


@pytest.fixture(scope="module")
def lens_shots(dataset: Dataset) -> Iterator[dict[str, tuple[LensShot, npt.NDArray[np.uint8]]]]:
    out = dataset.root / "lens_shots"
    out.mkdir()
    off = {"enabled": False}
    # the red (level-0) patch spans view columns 40–160, rows 40–130: the lens cuts through it
    named = {
        "second": LensShot(LIGHT, region(1), out / "second.rgba", overlays=False,
                           lens={**LENS, "layer": "second", "mode": "color"}),
        "normals": LensShot(LIGHT, region(1), out / "normals.rgba", overlays=False,
                            lens={**LENS, "layer": "base", "mode": "normals"}),
        "unsharp": LensShot(LIGHT, region(1), out / "unsharp.rgba", overlays=False,
                            lens={**LENS, "layer": "base", "mode": "unsharpLuminance",
                                  "params": {"umGain": 3.0}}),
        "half": LensShot(LIGHT, region(1), out / "half.rgba", overlays=False,
                         lens={**LENS, "layer": "second", "mode": "color", "opacity": 0.5}),
        "inside": LensShot(LIGHT, region(1), out / "inside.rgba", overlays=True,
                           lens={**LENS, "layer": "base", "mode": "color",
                                 "annotations": "inside"}),
        "outside": LensShot(LIGHT, region(1), out / "outside.rgba", overlays=True,
                            lens={**LENS, "layer": "base", "mode": "color",
                                  "annotations": "outside"}),
        "off": LensShot(LIGHT, region(1), out / "off.rgba", overlays=False, lens=off),
    }
    frames = shots_and_frames(dataset, list(named.values()))
    yield {k: (s, f) for (k, s), f in zip(named.items(), frames, strict=True)}


def test_lens_shows_the_second_layer_inside_and_the_base_outside(
        dataset: Dataset, lens_shots: dict[str, tuple[LensShot, npt.NDArray[np.uint8]]]) -> None:
    (cx, cy), r = LENS_C, LENS_R
    inside, outside = disk(cx, cy, r - 1.5), ~disk(cx, cy, r + 1.5)
    base = np.round(reference(dataset, "base", 1) * 255).astype(np.int16)
    for name, lens_layer, mode in [("second", "second", "color"), ("normals", "base", "normals")]:
        _, frame = lens_shots[name]
        lens_ref = np.round(reference(dataset, lens_layer, 1, mode) * 255).astype(np.int16)
        assert_close(frame, lens_ref, inside, f"inside the lens ({lens_layer} {mode})")
        assert_close(frame, base, outside, f"outside the lens ({lens_layer} {mode})")
        assert np.abs(lens_ref - base)[inside].mean() > 20, "the two renderings must differ"
    _, frame = lens_shots["off"]
    assert_close(frame, base, np.ones(frame.shape[:2], bool), "lens off")


def test_lens_in_a_screen_space_mode(
        dataset: Dataset, lens_shots: dict[str, tuple[LensShot, npt.NDArray[np.uint8]]]) -> None:
    """An unsharp mode in the lens: its filter sees only the tiles under the lens, so pixels farther
    than the filter's reach (F5: 10 px) from the clip edge match the whole-view reference."""
    _, frame = lens_shots["unsharp"]
    (cx, cy), r = LENS_C, LENS_R
    x, y = ORIGIN[1]
    ch = level_channels(dataset.dir, dataset.blocks["base"], 1, (x, y) + VIEW)
    ref = render(dataset.blocks["base"], ch, LIGHT, "unsharpLuminance", {"umGain": 3.0})
    expected = np.round(ref * 255).astype(np.int16)
    plain = np.round(reference(dataset, "base", 1) * 255).astype(np.int16)
    core = disk(cx, cy, r - 16)
    assert_close(frame, expected, core, "unsharp lens core")
    assert_close(frame, plain, ~disk(cx, cy, r + 1.5), "outside an unsharp lens")
    assert np.abs(expected - plain)[core].max() > 10, "the filter must change the picture"


def test_lens_on_the_same_layer_reuses_its_tiles(
        lens_shots: dict[str, tuple[LensShot, npt.NDArray[np.uint8]]]) -> None:
    """The base layer's tiles of this view are loaded; the lens on the same layer (another mode)
    shares their cache records (bundle hash key), so it requests no base tile again."""
    shot, _ = lens_shots["normals"]
    again = [u for u in shot.meta()["requests"] if "/iiif/base_" in u and "_ov" not in u]
    assert again == []


def test_lens_opacity_blends_over_the_base(
        dataset: Dataset, lens_shots: dict[str, tuple[LensShot, npt.NDArray[np.uint8]]]) -> None:
    _, frame = lens_shots["half"]
    (cx, cy), r = LENS_C, LENS_R
    base = reference(dataset, "base", 1)
    second = reference(dataset, "second", 1)
    expected = np.round((0.5 * second + 0.5 * base) * 255).astype(np.int16)
    assert_close(frame, expected, disk(cx, cy, r - 1.5), "half-opaque lens")
    assert_close(frame, np.round(base * 255).astype(np.int16), ~disk(cx, cy, r + 1.5),
                 "outside a half-opaque lens")


@pytest.mark.parametrize("display", ["inside", "outside"])
def test_annotations_only_inside_or_outside_the_lens(
        dataset: Dataset, lens_shots: dict[str, tuple[LensShot, npt.NDArray[np.uint8]]],
        display: str) -> None:
    _, frame = lens_shots[display]
    (cx, cy), r = LENS_C, LENS_R
    base = reference(dataset, "base", 1)
    ov = overlay_at(dataset, 0, 1)
    shown, hidden = disk(cx, cy, r - 1.5), ~disk(cx, cy, r + 1.5)
    if display == "outside":
        shown, hidden = hidden, shown
    patch = ov[..., 3] > 0
    assert (patch & shown).sum() > 500 and (patch & hidden).sum() > 500
    assert_close(frame, over(base, ov), shown, f"annotations {display}: where they show")
    assert_close(frame, np.round(base * 255).astype(np.int16), hidden,
                 f"annotations {display}: where they are hidden")




def test_lens_layer_loads_only_the_tiles_under_the_lens(dataset: Dataset) -> None:
    """A wide view over many tiles, a small lens in a corner: the lens layer's tile requests all
    lie under the lens's bounding box (image px), and are few."""
    out = dataset.root / "requests"
    out.mkdir()
    view = (512, 384)
    factor = 2
    reg = (0, 0, view[0] * factor, view[1] * factor)  # the whole image: 4 × 3 level-1 tiles
    # image px: centre (896, 128), radius 80: inside the level-1 tile (768, 0, 256, 256)
    lens = {"enabled": True, "center": [448, 64], "radius": 40, "layer": "second",
            "mode": "color", "opacity": 1}
    shot = LensShot(LIGHT, reg, out / "req.rgba", overlays=False, lens=lens)
    shots_and_frames(dataset, [shot], viewport=view)
    requests = shot.meta()["requests"]
    tiles = [m for m in (TILE_URL.search(u) for u in requests) if m]
    second = [m for m in tiles if m["image"] == "second"]
    assert second, "the lens layer loads some tiles"
    cx, cy, r = (v * factor for v in (448, 64, 40))  # image px
    margin = 8 * factor
    for m in second:
        if m["region"] == "full":
            continue  # a whole small level (coarse fallback)
        x, y, w, h = (int(v) for v in m["region"].split(","))
        assert x < cx + r + margin and x + w > cx - r - margin and y < cy + r + margin \
            and y + h > cy - r - margin, f"tile {m.group(0)} is not under the lens"
    level1 = [m for m in second if m["region"] != "full"
              and int(m["region"].split(",")[2]) == TILE * factor]
    assert len(level1) == 1, f"level-1 tiles of the lens layer: {[m[0] for m in level1]}"


# -- gestures ------------------------------------------------------------------------------------
# 800×600: the gestures stay clear of the page's panel (right), toolbar (top) and light widget.
GESTURE_VIEW = (800, 600)
GESTURE_LENS: dict[str, Any] = {"enabled": True, "center": [300, 300], "radius": 40,
                                "layer": "second", "mode": "color", "opacity": 1}


@pytest.fixture(scope="module")
def gesture_meta(dataset: Dataset) -> dict[str, tuple[dict[str, Any], dict[str, Any]]]:
    """For each gesture: the state with the lens set up and no gesture, and after the gesture."""
    out = dataset.root / "gestures"
    out.mkdir()
    c = GESTURE_LENS["center"]
    cases: dict[str, list[dict[str, Any]]] = {
        "one finger inside": [{"type": "touch", "from": [[c[0], c[1]]],
                               "to": [[c[0] + 40, c[1] + 20]]}],
        "one finger outside": [{"type": "touch", "from": [[150, 450]], "to": [[450, 150]]}],
        "two fingers inside": [{"type": "touch", "from": [[c[0] - 10, c[1]], [c[0] + 10, c[1]]],
                                "to": [[c[0] + 10, c[1] + 10], [c[0] + 50, c[1] + 10]]}],
        "two fingers outside": [{"type": "touch", "from": [[150, 450], [190, 450]],
                                 "to": [[140, 440], [212, 460]]}],
        "mouse inside": [{"type": "mouse", "from": [c[0] + 5, c[1]], "to": [c[0] - 25, c[1] - 15]}],
        "mouse border": [{"type": "mouse", "from": [c[0] + 40, c[1]], "to": [c[0] + 70, c[1]]}],
        "pen inside": [{"type": "pen", "from": [c[0], c[1] + 5], "to": [c[0] + 30, c[1] + 45]}],
        "pen outside": [{"type": "pen", "from": [150, 450], "to": [450, 150]}],
        "wheel inside": [{"type": "wheel", "at": [c[0], c[1]], "deltaY": -100}],
        "wheel outside": [{"type": "wheel", "at": [450, 150], "deltaY": -100}],
    }
    shots: list[LensShot] = []
    whole = (0, 0, W, H)
    for i, (_name, steps) in enumerate(cases.items()):
        shots.append(LensShot((0.0, 0.0), whole, out / f"before{i}.rgba", overlays=False,
                              lens=GESTURE_LENS))
        shots.append(LensShot((0.0, 0.0), whole, out / f"after{i}.rgba", overlays=False,
                              lens=GESTURE_LENS, gestures=steps))
    shots_and_frames(dataset, shots, viewport=GESTURE_VIEW)
    return {name: (shots[2 * i].meta(), shots[2 * i + 1].meta())
            for i, name in enumerate(cases)}


def moved(before: dict[str, Any], after: dict[str, Any]) -> dict[str, bool]:
    """Which of lens centre, lens radius, light and view changed."""
    def near(a: list[float], b: list[float], eps: float) -> bool:
        return all(abs(x - y) <= eps for x, y in zip(a, b, strict=True))
    return {
        "lens": not near(before["lens"]["center"], after["lens"]["center"], 0.5),
        "radius": abs(before["lens"]["radius"] - after["lens"]["radius"]) > 0.5,
        "light": not near([before["light"]["lu"], before["light"]["lv"]],
                          [after["light"]["lu"], after["light"]["lv"]], 1e-3),
        "view": not near(before["view"]["center"] + [before["view"]["zoom"]],
                         after["view"]["center"] + [after["view"]["zoom"]], 1e-6),
    }


@pytest.mark.parametrize("gesture, expected", [
    ("one finger inside", {"lens": True, "radius": False, "light": False, "view": False}),
    ("one finger outside", {"lens": False, "radius": False, "light": True, "view": False}),
    ("two fingers inside", {"lens": True, "radius": True, "light": False, "view": False}),
    ("mouse inside", {"lens": True, "radius": False, "light": False, "view": False}),
    ("mouse border", {"lens": False, "radius": True, "light": False, "view": False}),
    ("pen inside", {"lens": True, "radius": False, "light": False, "view": False}),
    ("pen outside", {"lens": False, "radius": False, "light": True, "view": False}),
    ("wheel inside", {"lens": False, "radius": True, "light": False, "view": False}),
    ("wheel outside", {"lens": False, "radius": False, "light": False, "view": True}),
])
def test_gesture_routing(gesture_meta: dict[str, tuple[dict[str, Any], dict[str, Any]]],
                         gesture: str, expected: dict[str, bool]) -> None:
    before, after = gesture_meta[gesture]
    assert moved(before, after) == expected, (gesture, before, after)


def test_two_fingers_outside_the_lens_pan_and_zoom_the_image(
        gesture_meta: dict[str, tuple[dict[str, Any], dict[str, Any]]]) -> None:
    before, after = gesture_meta["two fingers outside"]
    change = moved(before, after)
    assert change["view"] and not change["lens"] and not change["radius"]
    assert after["view"]["zoom"] > before["view"]["zoom"] * 1.2  # fingers 40 → 72 px apart


def test_gestures_move_and_scale_the_lens_by_the_fingers(
        gesture_meta: dict[str, tuple[dict[str, Any], dict[str, Any]]]) -> None:
    c = GESTURE_LENS["center"]
    _, after = gesture_meta["one finger inside"]
    assert after["lens"]["center"] == pytest.approx([c[0] + 40, c[1] + 20], abs=0.5)
    _, after = gesture_meta["two fingers inside"]
    # midpoint (128, 96) → (158, 106); distance 20 → 40: radius doubles
    assert after["lens"]["center"] == pytest.approx([c[0] + 30, c[1] + 10], abs=0.5)
    assert after["lens"]["radius"] == pytest.approx(2 * GESTURE_LENS["radius"], rel=0.02)
    _, after = gesture_meta["mouse border"]
    assert after["lens"]["radius"] == pytest.approx(70, abs=0.5)
