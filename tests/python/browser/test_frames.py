"""Real Chromium: the drawer's frame scheduling and the tile cache (docs/rendering.md).

While tiles arrive the drawer renders at most one relit frame per animation frame (it counts
them, ``getFrameCount``; render.mjs counts the animation frames in the page); the frame that
completes the loading still matches the reference; and switching layers A → B → A fetches no
tile again, with two views of more tiles together than OpenSeadragon's default cache of 150.
Both open the page at the viewer's own full detail (``minPixelRatio`` left to the page).
"""

from __future__ import annotations

import re
from pathlib import Path
from typing import Any

import numpy as np
import numpy.typing as npt
import pytest

from lanterna.tiler.dataset.layers import add_image_layer, add_ptm_layer
from lanterna.tiler.dataset.writer import DatasetWriter
from lanterna.tiler.formats.ptm_model import Ptm
from lanterna.tiler.iiif.pyramid import vips_from_array
from lanterna.tiler.render import level_channels, render
from tests.python.fixtures import browser

pytestmark = pytest.mark.browser

W, H = 3072, 2304
TILE = 256
TOLERANCE = 2  # out of 255
TILE_URL = re.compile(
    r"/iiif/(?P<image>[A-Za-z0-9_-]+)/(?P<region>full|\d+,\d+,\d+,\d+)/(?P<size>[^/]+)/")
#: OpenSeadragon's tile cache before it was sized by the view (maxImageCacheCount).
OLD_CACHE = 150

#: The dataset folder and each layer's relight block.
Data = tuple[Path, dict[str, dict[str, Any]]]


def gradient_ptm() -> Ptm:
    """A PTM whose coefficients vary smoothly (small PNGs) and differ per channel."""
    y, x = np.mgrid[0:H, 0:W].astype(np.float64)
    waves = [np.sin(x / (97 + 13 * k) + y / (71 + 7 * k) + k) for k in range(6)]
    coef = np.stack([np.round(128 + 60 * w) for w in waves], -1).astype(np.uint8)
    rgb = np.stack([np.round(150 + 80 * np.cos((x + y) / (53 + 11 * k))) for k in range(3)], -1)
    return Ptm("lrgb", coef, np.array([2, 2, 2, 2, 2, 1], np.float32),
               np.array([128, 128, 128, 128, 128, 0], np.int32), rgb.astype(np.uint8))


@pytest.fixture(scope="module")
def dataset(tmp_path_factory: pytest.TempPathFactory) -> Data:
    """A 3072×2304 dataset of 256² tiles: a PTM layer ``ptm`` and a PNG image layer ``image``."""
    root = tmp_path_factory.mktemp("frames")
    y, x = np.mgrid[0:H, 0:W]
    image = np.stack([x * 255 // W, y * 255 // H, (x + y) * 127 // (W + H)], -1).astype(np.uint8)
    with DatasetWriter(root / "frames", name="frames", label="Frames", width=W, height=H,
                       tile_size=TILE) as ds:
        add_ptm_layer(ds, gradient_ptm(), layer_id="ptm", label="PTM")
        add_image_layer(ds, vips_from_array(image), layer_id="image", label="Image", fmt="png")
        blocks = {layer["id"]: ds.layer_service(layer) for layer in ds.layers}
    return root, blocks


def shoot(root: Path, shots: list[browser.Shot],
          viewport: tuple[int, int]) -> list[npt.NDArray[np.uint8]]:
    """Render the shots from a cold page at the viewer's own full detail."""
    return browser.render_dataset(root, "frames", shots, viewport=viewport, query="&layer=ptm",
                                  options={"minPixelRatio": None})


def tiles_requested(meta: dict[str, Any]) -> set[tuple[str, str, str]]:
    """The distinct tile requests of a shot: (image, region, size)."""
    return {(m["image"], m["region"], m["size"]) for url in meta["requests"]
            if (m := TILE_URL.search(url))}


def test_at_most_one_relit_frame_per_animation_frame(dataset: Data, tmp_path: Path) -> None:
    root, blocks = dataset
    view = (640, 480)
    origin = (900, 700)
    light = (0.35, -0.4)
    shots = [
        browser.Shot(light=(-0.3, 0.2), region=(0, 0, W, H), out=tmp_path / "open.rgba",
                     layer="ptm"),
        browser.Shot(light=light, region=origin + view, out=tmp_path / "detail.rgba"),
    ]
    frames = shoot(root, shots, view)
    counts = [s.meta()["frames"] for s in shots]
    for shot, c in zip(shots, counts, strict=True):
        assert c["rendered"] >= 1 and c["ticks"] >= c["rendered"], (shot.out.name, c)
        assert c["maxPerTick"] <= 1, (
            f"{shot.out.name}: {c['maxPerTick']} relit frames in one animation frame")
    # The new view and light drew again.
    assert counts[1]["rendered"] > counts[0]["rendered"], counts
    assert tiles_requested(shots[1].meta()), "the detail view should have loaded level-0 tiles"
    # The completing frame shows every tile of level 0 (1 image px = 1 screen px), relit.
    ch = level_channels(root / "frames", blocks["ptm"], 1, origin + view)
    expected = np.round(render(blocks["ptm"], ch, light, "color") * 255).astype(np.int16)
    diff = np.abs(frames[1][..., :3].astype(np.int16) - expected).max(axis=-1)
    assert diff.max() <= TOLERANCE, (
        f"{(diff > TOLERANCE).sum()} pixels off by up to {diff.max()}/255")


def test_switching_layers_back_fetches_no_tile(dataset: Data, tmp_path: Path) -> None:
    root, _ = dataset
    view = (1200, 900)
    whole = (0, 0, W, H)  # zoom 0.39: level 1 at full detail
    light = (0.2, 0.3)
    # ptm, then image over the whole view, then image at 1 image px = 1 screen px on a 3 × 3 grid
    # (every level-0 tile of it: more tiles than the old cache held), then ptm again.
    grid = [(x, y) + view for y in (0, 702, H - view[1]) for x in (0, 936, W - view[0])]
    shots = [browser.Shot(light=light, region=whole, out=tmp_path / "0-ptm.rgba", layer="ptm"),
             browser.Shot(light=light, region=whole, out=tmp_path / "1-image.rgba", layer="image")]
    shots += [browser.Shot(light=light, region=r, out=tmp_path / f"{2 + i}-image.rgba")
              for i, r in enumerate(grid)]
    shots.append(browser.Shot(light=light, region=whole, out=tmp_path / "back-ptm.rgba",
                              layer="ptm"))
    shoot(root, shots, view)
    fetched = [tiles_requested(s.meta()) for s in shots]
    ptm = {(r, z) for image, r, z in fetched[0] if image.startswith("ptm")}
    image = {(r, z) for tiles in fetched[1:-1] for name, r, z in tiles if name.startswith("image")}
    assert ptm and len(image) > len(grid), (len(ptm), len(image))
    # Together more tiles than the old cache held: the cache must really be sized by the view.
    assert len(ptm) + len(image) > OLD_CACHE, (len(ptm), len(image))
    back = fetched[-1]
    assert back == set(), (
        f"switching back to ptm fetched {len(back)} tiles again, e.g. {sorted(back)[:3]}")
