"""Real Chromium: a lost WebGL context (`WEBGL_lose_context`) is restored, same pixels redrawn.

Each shot renders a frame, reads it back, loses the context (the page must show a notice, and
drawing or reading back while it is lost must not throw), restores it, waits until the view is
loaded and reads it again (render.mjs ``contextLoss``). The frames before and after must be
identical, byte for byte: the textures are uploaded again from the tiles' cached bundles, the
programs and the float targets of the screen-space filters are made again.

Data and helpers: :mod:`tests.python.fixtures.lens` (a PTM layer with overlays, an image layer).
"""

from __future__ import annotations

from collections.abc import Iterator

import numpy as np
import numpy.typing as npt
import pytest

from tests.python.fixtures import lens
from tests.python.fixtures.lens import Dataset, LensShot

pytestmark = pytest.mark.browser

LOST_TEXT = "Graphics context lost"

#: name → (what the shot draws: LensShot keyword arguments)
CASES: dict[str, dict[str, object]] = {
    "ptm-color": {"mode": "color", "overlays": False},
    "ptm-unsharp": {"mode": "unsharpCoefficients", "params": {"umGain": 2.5}, "overlays": False},
    "ptm-unsharp-luminance": {"mode": "unsharpLuminance", "overlays": False},
    "lens-and-overlays": {"mode": "color", "overlays": True,
                          "lens": {"enabled": True, "center": [128, 96], "radius": 60,
                                   "mode": "unsharpNormals", "layer": "base"}},
}


@pytest.fixture(scope="module")
def restored(lens_dataset: Dataset) -> Iterator[dict[str, tuple[LensShot, npt.NDArray[np.uint8]]]]:
    out = lens_dataset.root / "context"
    out.mkdir()
    shots = [LensShot(lens.LIGHT, lens.region(1), out / f"{name}.rgba", layer="base",
                      extra={"contextLoss": True, "lostScreenshot": str(out / f"{name}-lost.png")},
                      **case)  # type: ignore[arg-type]
             for name, case in CASES.items()]
    frames = lens.shots_and_frames(lens_dataset, shots)
    yield {name: (shot, frame) for name, shot, frame in zip(CASES, shots, frames, strict=True)}


@pytest.mark.parametrize("name", list(CASES))
def test_the_restored_context_redraws_the_same_pixels(
        restored: dict[str, tuple[LensShot, npt.NDArray[np.uint8]]], name: str) -> None:
    shot, before = restored[name]
    after = shot.restored()
    assert before.shape == after.shape == (lens.VIEW[1], lens.VIEW[0], 4)
    assert (before[..., 3] == 255).all(), "the frame before the loss must be drawn"
    differ = np.argwhere((before != after).any(axis=-1))
    assert differ.size == 0, (
        f"{name}: {len(differ)} pixels differ after the restoration, first at (row, col) "
        f"{tuple(differ[0])}: {before[tuple(differ[0])]} before, {after[tuple(differ[0])]} after")


def test_the_frame_before_the_loss_is_the_reference(
        lens_dataset: Dataset, restored: dict[str, tuple[LensShot, npt.NDArray[np.uint8]]]) -> None:
    # The comparison above is meaningful only for a correct frame: check one against numpy.
    _shot, frame = restored["ptm-color"]
    expected = np.round(lens.reference(lens_dataset, "base", 1) * 255).astype(np.int16)
    lens.assert_close(frame, expected, np.ones(frame.shape[:2], bool), "ptm colour before the loss")


@pytest.mark.parametrize("name", list(CASES))
def test_a_notice_shows_while_the_context_is_lost_and_goes_after(
        restored: dict[str, tuple[LensShot, npt.NDArray[np.uint8]]], name: str) -> None:
    meta = restored[name][0].meta()
    lost = meta["noticesWhileLost"]
    assert lost["visible"], f"{name}: no visible notice while the context was lost: {lost}"
    assert any(LOST_TEXT in t for t in lost["texts"]), lost["texts"]
    assert [n["kind"] for n in lost["list"]] == ["context-lost"]
    assert not any(LOST_TEXT in t for t in meta["notices"]["texts"]), meta["notices"]
    assert meta["notices"]["list"] == []
