"""Real Chromium renders PTM datasets through the plugin; pixels match a numpy relight.

The viewer fits image rectangles so that one image pixel of the level OpenSeadragon draws is
exactly one screen pixel (zoom 1 → full resolution, zoom 1/2 → the next level), and the
read-back frame is compared with a numpy relight of the very tiles that level is made of.
"""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

import numpy as np
import pytest

from lanterna.tiler.dataset.layers import add_ptm_layer
from lanterna.tiler.dataset.plane_format import PlaneFormat
from lanterna.tiler.dataset.writer import DatasetWriter
from lanterna.tiler.iiif.encoding import TileFormat
from tests.python.fixtures.browser import Shot, render
from tests.python.fixtures.ptm_relight import (
    LIGHTS,
    TOLERANCE,
    H,
    W,
    numpy_relight,
    smooth_random_ptm,
)
from tests.python.fixtures.servers import LiveServer

pytestmark = pytest.mark.browser


#: Plane tile formats the pixel test covers: every --plane-format, and the near-lossless WebP
#: ``auto`` may choose for a lossy source.
PLANE_FORMATS = {"png": PlaneFormat(TileFormat("png")), "webp": PlaneFormat(TileFormat("webp")),
                 "webp-near60": PlaneFormat(TileFormat("webp", 60)),
                 "jpg-85": PlaneFormat(TileFormat("jpg", 85))}


@pytest.mark.parametrize(("colorspace", "fmt"), [
    ("lrgb", "png"), ("rgb", "png"), ("lrgb", "webp"), ("lrgb", "webp-near60"),
    ("lrgb", "jpg-85"), ("rgb", "jpg-85")])
def test_relit_pixels_match_numpy(tmp_path: Path, live_server: Callable[[Path], LiveServer],
                                  colorspace: str, fmt: str) -> None:
    root = tmp_path / "root"
    with DatasetWriter(root / "obj", name="obj", label="Random PTM", width=W, height=H) as ds:
        layer = add_ptm_layer(ds, smooth_random_ptm(colorspace, seed=7),
                              plane_format=PLANE_FORMATS[fmt])
    stored = PLANE_FORMATS[fmt].fixed
    assert stored is not None
    assert [p["format"] for p in layer["planes"]] == [stored.ext] * len(layer["planes"])
    server = live_server(root)
    url = f"{server.url}/viewer/?manifest={server.url}/datasets/obj/manifest.json"
    vw, vh = 640, 480
    # zoom 1 over 6 tiles (seams at x=256, 512 and y=256); zoom 1/2 over 4 level-1 tiles
    views = [(1, (130, 100, vw, vh)), (2, (100, 60, 2 * vw, 2 * vh))]
    shots = [Shot(light, region, tmp_path / f"z{f}_{i}.rgba")
             for f, region in views for i, light in enumerate(LIGHTS)]
    frames = render(url, shots, viewport=(vw, vh))
    checked, worst = 0, 0
    for shot, frame in zip(shots, frames, strict=True):
        factor = 1 if shot.region[2] == vw else 2
        ref = numpy_relight(root / "obj", layer, factor, shot.light)
        x0, y0 = shot.region[0] // factor, shot.region[1] // factor
        ref = ref[y0: y0 + vh, x0: x0 + vw]
        got = frame[: ref.shape[0], : ref.shape[1]]
        expected = np.round(ref * 255.0).astype(np.int16)
        diff = np.abs(got[..., :3].astype(np.int16) - expected)
        assert got.shape[:2] == expected.shape[:2]
        assert (got[..., 3] == 255).all(), "the image area must be opaque"
        bad = np.argwhere(diff.max(axis=-1) > TOLERANCE)
        worst = max(worst, int(diff.max()))
        assert bad.size == 0, (
            f"{colorspace} {fmt} light={shot.light} zoom 1/{factor}: {len(bad)} pixels off by "
            f"up to {diff.max()} /255, first at (row, col) {tuple(bad[0])}: got "
            f"{got[tuple(bad[0])][:3]}, expected {expected[tuple(bad[0])]}")
        # the light changes the picture: not a constant image
        assert expected.std() > 10
        checked += diff.shape[0] * diff.shape[1]
    assert checked >= 4 * vw * vh
    print(f"{colorspace} {fmt}: largest difference {worst}/255")  # reported with -s


@pytest.mark.realdata
def test_real_ushabti_is_relit_from_the_side_the_light_comes_from(
        tmp_path: Path, live_server: Callable[[Path], LiveServer]) -> None:
    from lanterna.cli import main
    from tests.python.fixtures.paths import shared_file

    src = shared_file("realdata/chi-ushabti-vase/ushabti.ptm")
    root = tmp_path / "root"
    assert main(["import", str(src), "-o", str(root / "ushabti")]) == 0
    server = live_server(root)
    url = f"{server.url}/viewer/?manifest={server.url}/datasets/ushabti/manifest.json"
    # the whole figure, 512x1024, at zoom 1/2 in a 256x512 viewport
    shots = [Shot((lu, 0.0), (0, 0, 512, 1024), tmp_path / f"u{i}.rgba")
             for i, lu in enumerate((-0.8, 0.8))]
    left_lit, right_lit = (f[..., :3].astype(np.float64).mean(axis=-1)
                           for f in render(url, shots, viewport=(256, 512)))
    half = left_lit.shape[1] // 2
    # light from the left: the left half of the figure is brighter than the right, and vice versa
    assert left_lit[:, :half].mean() > 1.3 * left_lit[:, half:].mean()
    assert right_lit[:, half:].mean() > 1.3 * right_lit[:, :half].mean()
    # upright: the head and shoulders (top third) are wider than the feet (bottom third)
    mask = (left_lit + right_lit) > 40
    widths = mask.sum(axis=1)
    third = len(widths) // 3
    assert widths[:third].mean() > 1.1 * widths[-third:].mean()  # measured 1.23


@pytest.mark.realdata
def test_real_vase_hsh_is_relit_the_right_way_up(
        tmp_path: Path, live_server: Callable[[Path], LiveServer]) -> None:
    from lanterna.cli import main
    from tests.python.fixtures.paths import shared_file

    src = shared_file("realdata/chi-ushabti-vase/vase.rti")
    root = tmp_path / "root"
    assert main(["import", str(src), "-o", str(root / "vase")]) == 0
    server = live_server(root)
    url = f"{server.url}/viewer/?manifest={server.url}/datasets/vase/manifest.json"
    lights = {"left": (-0.8, 0.0), "right": (0.8, 0.0), "top": (0.0, 0.8), "bottom": (0.0, -0.8)}
    shots = [Shot(light, (0, 0, 320, 470), tmp_path / f"{name}.rgba")
             for name, light in lights.items()]
    frames = {name: f[..., :3].astype(np.float64).mean(axis=-1)
              for name, f in zip(lights, render(url, shots, viewport=(320, 470)), strict=True)}
    half = 160
    assert frames["left"][:, :half].mean() > 1.3 * frames["left"][:, half:].mean()
    assert frames["right"][:, half:].mean() > 1.3 * frames["right"][:, :half].mean()
    # the shoulder (rows 150–260, above the widest row at y≈272) faces up: lit from the top
    shoulder = slice(150, 260)
    assert frames["top"][shoulder].mean() > 1.2 * frames["bottom"][shoulder].mean()
