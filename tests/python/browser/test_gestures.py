"""Real Chromium: gesture routing with synthetic touch, pen, mouse and wheel input (lens vs image).

Data and helpers: :mod:`tests.python.fixtures.lens`.
"""

from __future__ import annotations

from typing import Any

import pytest

from tests.python.fixtures.lens import Dataset, H, LensShot, W, shots_and_frames

pytestmark = pytest.mark.browser


GESTURE_VIEW = (800, 600)
GESTURE_LENS: dict[str, Any] = {"enabled": True, "center": [300, 300], "radius": 40,
                                "layer": "second", "mode": "color", "opacity": 1}


@pytest.fixture(scope="module")
def gesture_meta(lens_dataset: Dataset) -> dict[str, tuple[dict[str, Any], dict[str, Any]]]:
    """For each gesture: the state with the lens set up and no gesture, and after the gesture."""
    out = lens_dataset.root / "gestures"
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
        # the first finger lands and moves alone for 3 of 8 steps before the second lands
        "pinch, fingers one after the other": [{"type": "touch", "from": [[160, 320], [220, 370]],
                                                "to": [[120, 280], [260, 410]], "alone": 3}],
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
    shots_and_frames(lens_dataset, shots, viewport=GESTURE_VIEW)
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


@pytest.mark.parametrize("gesture", ["two fingers outside", "pinch, fingers one after the other"])
def test_a_pinch_leaves_the_light_where_it_was(
        gesture_meta: dict[str, tuple[dict[str, Any], dict[str, Any]]], gesture: str) -> None:
    """The first finger of a pinch lands alone (it starts a light drag): the light comes back."""
    before, after = gesture_meta[gesture]
    change = moved(before, after)
    assert change["view"], "the pinch zooms the image"
    assert after["light"] == before["light"], (before["light"], after["light"])


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
