"""Real Chromium: a dataset whose other layers or overlays fail to load keeps working.

The lens dataset, with a manifest that does not embed the image descriptions (so the viewer fetches
each image's ``info.json``), opens on its PTM layer ``base``; the ``info.json`` of the image layer
``second`` and of ``base``'s level-0 overlay answer 404. Switching to ``second`` in the panel,
showing ``second`` in the lens, and the overlay of the current level all fail: each gives an error
notice, the view keeps showing ``base`` (exactly the reference), the layer menu shows ``base``
again, and waiting for the view to load still ends (it used to wait forever for the lens layer).
"""

from __future__ import annotations

import json
import shutil
from collections.abc import Iterator

import numpy as np
import numpy.typing as npt
import pytest

from tests.python.fixtures import lens
from tests.python.fixtures.lens import Dataset, LensShot
from tests.python.fixtures.manifests import without_descriptions

pytestmark = pytest.mark.browser

LAYER_MENU = "select[name=layer]"
ROUTES = [{"match": r"/iiif/(second|base_ov0)/info\.json$", "status": 404, "body": "missing"}]


@pytest.fixture(scope="module")
def partial(lens_dataset: Dataset) -> Iterator[list[tuple[LensShot, npt.NDArray[np.uint8]]]]:
    out = lens_dataset.root / "partial"
    out.mkdir()
    # a copy of the dataset whose manifest is bare (the embedded descriptions would spare the
    # info.json requests that fail here)
    bare = Dataset(out / "bare-root", lens_dataset.blocks)
    shutil.copytree(lens_dataset.dir, bare.dir)
    manifest = json.loads((bare.dir / "manifest.json").read_text())
    (bare.dir / "manifest.json").write_text(json.dumps(without_descriptions(manifest)))
    shots = [
        LensShot(lens.LIGHT, lens.region(1), out / "overlay.rgba", layer="base", overlays=True),
        LensShot(lens.LIGHT, lens.region(1), out / "switch.rgba", extra={"read": [LAYER_MENU]},
                 gestures=[{"type": "select", "selector": LAYER_MENU, "value": "second"},
                           {"type": "wait", "ms": 500}]),
        LensShot(lens.LIGHT, lens.region(1), out / "lens.rgba",
                 lens={"enabled": True, "layer": "second", "center": [128, 96], "radius": 50}),
    ]
    options = {"routes": ROUTES, "allowConsoleErrors": [r"^Failed to load resource"]}
    frames = lens.shots_and_frames(bare, shots, options=options)
    yield list(zip(shots, frames, strict=True))


def errors(shot: LensShot) -> list[str]:
    return [n["message"] for n in shot.meta()["notices"]["list"] if n["kind"] == "error"]


def test_the_view_keeps_showing_the_layer_that_loaded(
        lens_dataset: Dataset, partial: list[tuple[LensShot, npt.NDArray[np.uint8]]]) -> None:
    expected = np.round(lens.reference(lens_dataset, "base", 1) * 255).astype(np.int16)
    everywhere = np.ones(expected.shape[:2], bool)
    for shot, frame in partial:
        lens.assert_close(frame, expected, everywhere, f"{shot.out.name}: base without its overlay")


def test_each_failure_is_an_error_notice_naming_the_url(
        partial: list[tuple[LensShot, npt.NDArray[np.uint8]]]) -> None:
    overlay, switch, lens = (shot for shot, _ in partial)
    assert any("base_ov0/info.json" in e and "404" in e for e in errors(overlay)), errors(overlay)
    assert any("second/info.json" in e and "404" in e for e in errors(switch)), errors(switch)
    assert overlay.meta()["notices"]["visible"]
    assert len(errors(lens)) <= 3


def test_the_layer_menu_shows_the_layer_still_shown(
        partial: list[tuple[LensShot, npt.NDArray[np.uint8]]]) -> None:
    switch = partial[1][0]
    assert switch.meta()["values"][LAYER_MENU] == "base"
