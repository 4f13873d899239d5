"""Real Chromium: failed tiles leave the coarser level showing and a notice, never a blank view.

The view shows level 0 of a PTM layer of random coefficients (one device pixel = one level-0
pixel) over four level-0 tiles whose requests are faulted (render.mjs ``routes``):

- A, every plane answers 404; B, one plane of three answers 404 (the bundle fails as a whole);
- C, one plane never answers (OpenSeadragon's time limit, set to 2.5 s, passes);
- D, one plane answers 500 once (the plane is retried on its own, and the tile loads);
- E, one plane answers 200 with bytes that are not an image (not retried).

Where A, B, C and E are missing the frame must be the level-1 tile there, upsampled and relit
(:func:`tests.python.fixtures.faults.coarse_reference`); everywhere else the level-0 reference.
"""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path
from typing import Any

import numpy as np
import numpy.typing as npt
import pytest

from tests.python.fixtures.faults import coarse_reference, make_noisy_dataset, tile_route
from tests.python.fixtures.lens import (
    LIGHT,
    ORIGIN,
    TILE,
    VIEW,
    Dataset,
    LensShot,
    assert_close,
    reference,
    region,
    shots_and_frames,
)

pytestmark = pytest.mark.browser

PLANES = "base_c0|base_c1|base_color"
MISSING = {"A": (128, 128), "B": (256, 128), "C": (128, 256), "E": (128, 0)}  # level-0 origins
RETRIED = (256, 256)
ROUTES = [
    tile_route(PLANES, *MISSING["A"], status=404, body="no such tile"),
    tile_route("base_c1", *MISSING["B"], status=404, body="no such tile"),
    tile_route("base_color", *MISSING["C"], hang=True),
    tile_route("base_c0", *RETRIED, status=500, body="try again", times=1),
    tile_route("base_c0", *MISSING["E"], status=200, body="not a png", contentType="image/png"),
]
ALLOWED = [r"^Failed to load resource", r"^Tile .* failed to load"]
NOTICE_TEXT = "Some tiles could not be loaded (4)"
RETRY = '.lanterna-notice[data-kind="tiles-failed"] .lanterna-notice-action'
DRAG_FROM = (150, 360)  # in a 640×480 view: on the notice's text, left of the panel


def on_screen(x: int, y: int) -> tuple[slice, slice]:
    """The rows and columns of the view that level-0 tile (x, y) covers (clipped to the view)."""
    ox, oy = ORIGIN[1]
    rows = slice(max(0, y - oy), max(0, min(VIEW[1], y + TILE - oy)))
    cols = slice(max(0, x - ox), max(0, min(VIEW[0], x + TILE - ox)))
    return rows, cols


def options(folder: Path, routes: list[dict[str, Any]], **more: Any) -> dict[str, Any]:
    return {"routes": routes, "allowConsoleErrors": ALLOWED, "tileTimeoutMs": 2500,
            "result": str(folder / "result.json"), **more}


@pytest.fixture(scope="module")
def noisy(tmp_path_factory: pytest.TempPathFactory) -> Dataset:
    return make_noisy_dataset(tmp_path_factory)


@pytest.fixture(scope="module")
def faulted(noisy: Dataset) -> Iterator[tuple[list[LensShot], list[npt.NDArray[np.uint8]]]]:
    out = noisy.root / "faults"
    out.mkdir()
    shots = [
        LensShot(LIGHT, region(1), out / "faults.rgba", layer="base",
                 extra={"screenshot": str(out / "faults.png")}),
        # Retry by hand: the tiles are asked for again (and fail again).
        LensShot(LIGHT, region(1), out / "retried.rgba", gestures=[
            {"type": "click", "selector": RETRY}, {"type": "wait", "ms": 300}]),
    ]
    frames = shots_and_frames(noisy, shots, options=options(out, ROUTES))
    yield shots, frames


def test_missing_tiles_show_the_coarser_level_and_the_rest_is_exact(
        noisy: Dataset, faulted: tuple[list[LensShot], list[npt.NDArray[np.uint8]]]) -> None:
    frame = faulted[1][0]
    assert (frame[..., 3] == 255).all(), "no pixel of the view may be blank"
    exact = np.ones(frame.shape[:2], bool)
    for name, (x, y) in MISSING.items():
        rows, cols = on_screen(x, y)
        exact[rows, cols] = False
        coarse = coarse_reference(noisy, "base", x, y, LIGHT)
        ox, oy = ORIGIN[1]
        expected = np.zeros((VIEW[1], VIEW[0], 3), np.int16)
        expected[rows, cols] = np.round(coarse[rows.start + oy - y: rows.stop + oy - y,
                                               cols.start + ox - x: cols.stop + ox - x] * 255)
        mask = np.zeros_like(exact)
        mask[rows, cols] = True
        assert_close(frame, expected, mask, f"tile {name} at {x},{y}: the coarser level")
        fine = np.round(reference(noisy, "base", 1) * 255).astype(np.int16)
        differs = np.abs(frame[..., :3].astype(np.int16) - fine).max(axis=-1)[mask]
        assert (differs > 2).mean() > 0.5, f"tile {name}: the level-0 tile must not be drawn"
    expected = np.round(reference(noisy, "base", 1) * 255).astype(np.int16)
    assert_close(frame, expected, exact, "the tiles that loaded (D after one retry)")


def test_the_notice_is_visible_and_counts_the_missing_tiles(
        faulted: tuple[list[LensShot], list[npt.NDArray[np.uint8]]]) -> None:
    notices = faulted[0][0].meta()["notices"]
    assert notices["visible"], notices
    assert any(NOTICE_TEXT in t for t in notices["texts"]), notices["texts"]
    [notice] = notices["list"]
    assert notice["kind"] == "tiles-failed"
    # The detail names the last failure: a URL and why (404, no answer in time, not an image).
    assert "/iiif/base_" in notice["detail"]
    reasons = ("HTTP 404", "no answer", "not a decodable image")
    assert any(why in notice["detail"] for why in reasons), notice["detail"]


def test_retry_asks_for_the_failed_tiles_again(
        faulted: tuple[list[LensShot], list[npt.NDArray[np.uint8]]]) -> None:
    first, retried = (s.meta() for s in faulted[0])
    # A: 3 planes, B: 1, C: 1 (the one that never answers), D: 1 (then the server answers), E: 1
    assert first["routeHits"][:2] == [3, 1] and first["routeHits"][3:] == [1, 1]
    assert first["routeHits"][2] >= 1
    assert retried["routeHits"][0] > first["routeHits"][0], "Retry must request tile A again"
    assert retried["routeHits"][1] > first["routeHits"][1], "Retry must request tile B again"
    assert any(NOTICE_TEXT[:30] in t for t in retried["notices"]["texts"]), retried["notices"]
    assert (faulted[1][1][..., 3] == 255).all()


def test_tiles_that_come_back_are_loaded_by_the_automatic_retry(
        noisy: Dataset, tmp_path: Path) -> None:
    # Tile A fails once on each plane, then the server answers: after the automatic retry
    # (4 s later) the view is the level-0 reference everywhere and the notice has gone.
    shots = [LensShot(LIGHT, region(1), tmp_path / "failed.rgba", layer="base"),
             LensShot(LIGHT, region(1), tmp_path / "back.rgba",
                      gestures=[{"type": "wait", "ms": 5500}])]
    routes = [tile_route(PLANES, *MISSING["A"], status=503, body="busy", times=9)]
    failed, back = shots_and_frames(noisy, shots, options=options(tmp_path, routes))
    rows, cols = on_screen(*MISSING["A"])
    expected = np.round(reference(noisy, "base", 1) * 255).astype(np.int16)
    everywhere = np.ones(back.shape[:2], bool)
    assert shots[0].meta()["notices"]["visible"]
    assert_close(back, expected, everywhere, "after the automatic retry")
    assert shots[1].meta()["notices"]["list"] == []
    assert np.abs(failed[rows, cols, :3].astype(np.int16) - expected[rows, cols]).max() > 2


def test_the_notice_does_not_block_the_viewer(noisy: Dataset, tmp_path: Path) -> None:
    # A drag that starts on the notice's text moves the light, as anywhere on the image.
    view = (120, 100, 640, 480)
    shots = [LensShot(LIGHT, view, tmp_path / "failed.rgba", layer="base"),
             LensShot(LIGHT, view, tmp_path / "dragged.rgba", gestures=[
                 {"type": "mouse", "from": list(DRAG_FROM), "to": [600, 40]}])]
    routes = [tile_route(PLANES, *MISSING["A"], status=404)]
    shots_and_frames(noisy, shots, viewport=(640, 480), options=options(tmp_path, routes))
    failed, dragged = (s.meta() for s in shots)
    x, y, w, h = failed["notices"]["rect"]
    assert x <= DRAG_FROM[0] <= x + w and y <= DRAG_FROM[1] <= y + h, failed["notices"]
    light = dragged["light"]
    assert (light["lu"], light["lv"]) != pytest.approx(LIGHT, abs=0.05), light
