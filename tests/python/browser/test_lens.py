"""Real Chromium: multi-scale annotation overlays, the hypertext widget and the lens.

Data and helpers: :mod:`tests.python.fixtures.lens`.
"""

from __future__ import annotations

import re
from collections.abc import Iterator
from typing import Any

import numpy as np
import numpy.typing as npt
import pytest

from tests.python.fixtures.lens import (
    LIGHT,
    ORIGIN,
    PATCHES,
    TILE,
    TILE_URL,
    TOLERANCE,
    VIEW,
    Dataset,
    LensShot,
    assert_close,
    disk,
    level_channels,
    level_image,
    over,
    overlay_at,
    reference,
    region,
    render,
    shots_and_frames,
)

pytestmark = pytest.mark.browser

#: Frames of the lens fixture by name: the shot (with its metadata) and the RGBA frame.
LensFrames = dict[str, tuple[LensShot, npt.NDArray[np.uint8]]]

@pytest.fixture(scope="module")
def opening_and_zoom_shots(
        lens_dataset: Dataset) -> list[tuple[LensShot, npt.NDArray[np.uint8]]]:
    """The home view as the page opens, until it is loaded; then zoom 1/1, 1/2, 1/4, hidden.

    The page opens at the home view, whose overlay level (1) starts loading as ``ready``
    resolves: its requests may come after the driver starts a shot's request log, so the first
    shot waits for them; the shots after it log only their own requests.
    """
    out = lens_dataset.root / "shots"
    out.mkdir()
    shots = [LensShot(LIGHT, region(4), out / "opening.rgba", extra={"home": True})]
    shots += [LensShot(LIGHT, region(f), out / f"zoom{f}.rgba") for f in (1, 2, 4)]
    shots.append(LensShot(LIGHT, region(1), out / "hidden.rgba", overlays=False))
    frames = shots_and_frames(lens_dataset, shots)
    return list(zip(shots, frames, strict=True))


@pytest.fixture(scope="module")
def zoom_shots(opening_and_zoom_shots: list[tuple[LensShot, npt.NDArray[np.uint8]]]
               ) -> Iterator[list[tuple[LensShot, npt.NDArray[np.uint8]]]]:
    """Zoom 1/1, 1/2, 1/4 and 1/1 with the overlays hidden, after the opening."""
    yield opening_and_zoom_shots[1:]


#: zoom factor f (zoom 1/f) → the current level: the home view (1/4) shows the coarsest level, 1,
#: and each doubling of the zoom one level finer (docs/annotations.md, "Levels").
LEVEL_AT = {4: 1, 2: 0, 1: 0}


def test_overlay_of_the_current_level_is_drawn(
        lens_dataset: Dataset, zoom_shots: list[tuple[LensShot, npt.NDArray[np.uint8]]]) -> None:
    everywhere = np.ones((VIEW[1], VIEW[0]), bool)
    for (_shot, frame), factor in zip(zoom_shots[:3], (1, 2, 4), strict=True):
        level = LEVEL_AT[factor]
        ref = reference(lens_dataset, "base", factor)
        ov = overlay_at(lens_dataset, level, factor)
        opaque = ov[..., 3] == 1
        assert opaque.sum() > 1000, "the view must show a good part of the patch"
        assert_close(frame, over(ref, ov), everywhere,
                     f"zoom 1/{factor} with level {level}'s overlay")
        colour = np.array(PATCHES[level][0])
        assert (np.abs(frame[opaque][:, :3].astype(int) - colour) <= TOLERANCE).all()
        # (the whole frame matches the reference with only that level's image: no other level shows)


def test_only_the_current_levels_overlay_loads(
        opening_and_zoom_shots: list[tuple[LensShot, npt.NDArray[np.uint8]]]) -> None:
    """Overlay items of other levels have opacity 0: none of their tiles or info.json loads."""
    info = re.compile(r"/iiif/(?P<image>[A-Za-z0-9_-]+)/info\.json")

    def overlays(shot: LensShot) -> set[str]:
        urls = shot.meta()["requests"]
        fetched = {m["image"] for m in (TILE_URL.search(u) or info.search(u) for u in urls) if m}
        return {i for i in fetched if "_ov" in i}

    opening, *zoomed = (shot for shot, _ in opening_and_zoom_shots[:4])
    assert overlays(opening) <= {"base_ov1"}, "at the home view only its level's overlay loads"
    for shot, factor in zip(zoomed, (1, 2, 4), strict=True):
        wanted = {f"base_ov{LEVEL_AT[factor]}"}
        if factor == 4:  # the home view's level again: its tiles may still be in the tile cache
            assert overlays(shot) <= wanted, (factor, overlays(shot))
        else:  # level 0 never loaded before (hidden at the opening): it must load now, alone
            assert overlays(shot) == wanted, (factor, overlays(shot))


def test_overlays_can_be_hidden(lens_dataset: Dataset,
                                zoom_shots: list[tuple[LensShot, npt.NDArray[np.uint8]]]) -> None:
    shot, frame = zoom_shots[3]
    ref = np.round(reference(lens_dataset, "base", 1) * 255).astype(np.int16)
    assert_close(frame, ref, np.ones(frame.shape[:2], bool), "overlays hidden")
    assert shot.meta()["overlayState"]["available"] is True  # the state still reports the level


def test_hypertext_follows_the_zoom(
        zoom_shots: list[tuple[LensShot, npt.NDArray[np.uint8]]]) -> None:
    states = [shot.meta() for shot, _ in zoom_shots[:3]]
    assert [s["overlayState"]["level"] for s in states] == [0, 0, 1]
    assert [s["overlayState"]["available"] for s in states] == [True, True, True]
    shorts = ["Glyph detail", "Glyph detail", "Whole panel"]
    assert [s["overlayState"]["short"] for s in states] == shorts
    assert [s["hypertext"] for s in states] == ["Glyph detail", "Glyph detail", "Whole panel"]
    long = states[0]["overlayState"]["long"]
    assert long == "<p>A <b>glyph</b>.</p>", "the long text is sanitised (no script)"


# -- magnified overlays -------------------------------------------------------------------------
#: 32×24 image px around the left edge of the level-0 patch (its 6-px alpha ramp starts at x = 160),
#: inside one 128-px overlay tile, magnified 8× into the 256×192 view.
MAGNIFIED = (152, 150, 32, 24)


def bilinear(img: npt.NDArray[np.float32], region: tuple[int, int, int, int],
             size: tuple[int, int]) -> npt.NDArray[np.float32]:
    """``img`` sampled bilinearly at the centres of a ``size`` grid of device px over ``region``."""
    x0, y0, w, h = region
    tx = x0 + (np.arange(size[0]) + 0.5) * w / size[0] - 0.5
    ty = y0 + (np.arange(size[1]) + 0.5) * h / size[1] - 0.5
    ix, iy = np.floor(tx).astype(int), np.floor(ty).astype(int)
    fx, fy = (tx - ix)[None, :, None], (ty - iy)[:, None, None]
    def at(dy: int, dx: int) -> npt.NDArray[np.float32]:
        return img[(iy + dy)[:, None], (ix + dx)[None, :]]
    out: npt.NDArray[np.float32] = ((at(0, 0) * (1 - fx) + at(0, 1) * fx) * (1 - fy)
                                    + (at(1, 0) * (1 - fx) + at(1, 1) * fx) * fy)
    return out


def test_a_magnified_overlay_is_filtered_smoothly_on_premultiplied_colour(
        lens_dataset: Dataset) -> None:
    out = lens_dataset.root / "magnified"
    out.mkdir()
    shots = [LensShot(LIGHT, MAGNIFIED, out / "shown.rgba", overlays=True),
             LensShot(LIGHT, MAGNIFIED, out / "hidden.rgba", overlays=False)]
    shown, hidden = shots_and_frames(lens_dataset, shots)
    assert shots[0].meta()["overlayState"]["level"] == 0
    img = level_image(lens_dataset.dir / "iiif" / "base_ov0", 1).astype(np.float32) / 255
    a = img[..., 3:4]
    premultiplied = bilinear(np.concatenate([img[..., :3] * a, a], -1), MAGNIFIED, VIEW)
    base = hidden[..., :3].astype(np.float32) / 255
    alpha = premultiplied[..., 3:4]
    expected = np.round((premultiplied[..., :3] + base * (1 - alpha)) * 255).astype(np.int16)
    assert_close(shown, expected, np.ones(VIEW[::-1], bool), "the magnified overlay edge")
    # a smooth ramp: many distinct partial coverages along a row, not a staircase of 0 and full
    row = alpha[VIEW[1] // 2, :, 0]
    assert len(np.unique(np.round(row[(row > 0.02) & (row < 0.98)], 3))) >= 40
    # filtering straight colour instead would darken the edge beyond the tolerance (the old fringe)
    straight = bilinear(img, MAGNIFIED, VIEW)
    s_alpha = straight[..., 3:4]
    fringe = np.round((straight[..., :3] * s_alpha + base * (1 - s_alpha)) * 255)
    assert np.abs(fringe - expected).max() > 3 * TOLERANCE


# -- lens ----------------------------------------------------------------------------------------
LENS_C, LENS_R = (128, 96), 56
LENS: dict[str, Any] = {"enabled": True, "center": list(LENS_C), "radius": LENS_R, "opacity": 1}


@pytest.fixture(scope="module")
def lens_shots(lens_dataset: Dataset) -> Iterator[LensFrames]:
    out = lens_dataset.root / "lens_shots"
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
    frames = shots_and_frames(lens_dataset, list(named.values()))
    yield {k: (s, f) for (k, s), f in zip(named.items(), frames, strict=True)}


def test_lens_shows_the_second_layer_inside_and_the_base_outside(
        lens_dataset: Dataset, lens_shots: LensFrames) -> None:
    (cx, cy), r = LENS_C, LENS_R
    inside, outside = disk(cx, cy, r - 1.5), ~disk(cx, cy, r + 1.5)
    base = np.round(reference(lens_dataset, "base", 1) * 255).astype(np.int16)
    for name, lens_layer, mode in [("second", "second", "color"), ("normals", "base", "normals")]:
        _, frame = lens_shots[name]
        lens_ref = np.round(reference(lens_dataset, lens_layer, 1, mode) * 255).astype(np.int16)
        assert_close(frame, lens_ref, inside, f"inside the lens ({lens_layer} {mode})")
        assert_close(frame, base, outside, f"outside the lens ({lens_layer} {mode})")
        assert np.abs(lens_ref - base)[inside].mean() > 20, "the two renderings must differ"
    _, frame = lens_shots["off"]
    assert_close(frame, base, np.ones(frame.shape[:2], bool), "lens off")


def test_lens_in_a_screen_space_mode(
        lens_dataset: Dataset, lens_shots: LensFrames) -> None:
    """An unsharp mode in the lens: its filter sees only the tiles under the lens, so pixels farther
    than the filter's reach (F5: 10 px) from the clip edge match the whole-view reference."""
    _, frame = lens_shots["unsharp"]
    (cx, cy), r = LENS_C, LENS_R
    x, y = ORIGIN[1]
    ch = level_channels(lens_dataset.dir, lens_dataset.blocks["base"], 1, (x, y) + VIEW)
    ref = render(lens_dataset.blocks["base"], ch, LIGHT, "unsharpLuminance", {"umGain": 3.0})
    expected = np.round(ref * 255).astype(np.int16)
    plain = np.round(reference(lens_dataset, "base", 1) * 255).astype(np.int16)
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
        lens_dataset: Dataset, lens_shots: LensFrames) -> None:
    _, frame = lens_shots["half"]
    (cx, cy), r = LENS_C, LENS_R
    base = reference(lens_dataset, "base", 1)
    second = reference(lens_dataset, "second", 1)
    expected = np.round((0.5 * second + 0.5 * base) * 255).astype(np.int16)
    assert_close(frame, expected, disk(cx, cy, r - 1.5), "half-opaque lens")
    assert_close(frame, np.round(base * 255).astype(np.int16), ~disk(cx, cy, r + 1.5),
                 "outside a half-opaque lens")


@pytest.mark.parametrize("display", ["inside", "outside"])
def test_annotations_only_inside_or_outside_the_lens(
        lens_dataset: Dataset, lens_shots: dict[str, tuple[LensShot, npt.NDArray[np.uint8]]],
        display: str) -> None:
    _, frame = lens_shots[display]
    (cx, cy), r = LENS_C, LENS_R
    base = reference(lens_dataset, "base", 1)
    ov = overlay_at(lens_dataset, 0, 1)
    shown, hidden = disk(cx, cy, r - 1.5), ~disk(cx, cy, r + 1.5)
    if display == "outside":
        shown, hidden = hidden, shown
    patch = ov[..., 3] > 0
    assert (patch & shown).sum() > 500 and (patch & hidden).sum() > 500
    assert_close(frame, over(base, ov), shown, f"annotations {display}: where they show")
    assert_close(frame, np.round(base * 255).astype(np.int16), hidden,
                 f"annotations {display}: where they are hidden")


def test_lens_layer_loads_only_the_tiles_under_the_lens(lens_dataset: Dataset) -> None:
    """A wide view over many tiles, a small lens in a corner: the lens layer's tile requests all
    lie under the lens's bounding box (image px), and are few."""
    out = lens_dataset.root / "requests"
    out.mkdir()
    view = (512, 384)
    factor = 2
    reg = (0, 0, view[0] * factor, view[1] * factor)  # the whole image: 4 × 3 level-1 tiles
    # image px: centre (896, 128), radius 80: inside the level-1 tile (768, 0, 256, 256)
    lens = {"enabled": True, "center": [448, 64], "radius": 40, "layer": "second",
            "mode": "color", "opacity": 1}
    shot = LensShot(LIGHT, reg, out / "req.rgba", overlays=False, lens=lens)
    shots_and_frames(lens_dataset, [shot], viewport=view)
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
