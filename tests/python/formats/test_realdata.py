"""The real files of ../shared/realdata through the format readers: the ushabti PTM and the vase."""

from __future__ import annotations

import math

import numpy as np
import numpy.typing as npt
import pytest

from lanterna.tiler.formats.hsh import read_rti
from lanterna.tiler.formats.hsh_basis import hsh_weights
from lanterna.tiler.formats.hsh_model import Hsh
from lanterna.tiler.formats.ptm import read_ptm
from lanterna.tiler.formats.ptm_model import Ptm
from tests.python.fixtures.paths import SHARED

USHABTI = SHARED / "realdata" / "chi-ushabti-vase" / "ushabti.ptm"
VASE = SHARED / "realdata" / "chi-ushabti-vase" / "vase.rti"

# --- the real vase ----------------------------------------------------------------------------


def three_light_normals(hsh: Hsh) -> npt.NDArray[np.float64]:
    """HSH normals per docs/rendering.md: relight at θ = 45°, φ = 30°, 150°, 270°, sum RGB,
    solve ``M·g = I`` with rows ``l_i``, normalise."""
    s, c = math.sin(math.pi / 4), math.cos(math.pi / 4)
    lights = np.array([[s * math.cos(p), s * math.sin(p), c]
                       for p in (math.pi / 6, 5 * math.pi / 6, 3 * math.pi / 2)])
    weights = np.stack([hsh_weights(lx, ly, hsh.terms) for lx, ly, _ in lights], axis=1)
    intensity = (hsh.dequantized().astype(np.float64) @ weights).sum(axis=2)
    g = intensity @ np.linalg.inv(lights).T
    length = np.linalg.norm(g, axis=-1, keepdims=True)
    n: npt.NDArray[np.float64] = np.where(length >= 1e-6, g / np.maximum(length, 1e-12),
                                          (0.0, 0.0, 1.0))
    return n


@pytest.mark.realdata
def test_real_vase_is_upright_and_its_normals_point_the_right_way() -> None:
    if not VASE.is_file():
        pytest.skip("../shared/realdata/chi-ushabti-vase/vase.rti not present "
                    "(read-only test data beside the repo)")
    hsh = read_rti(VASE)
    assert (hsh.width, hsh.height, hsh.terms) == (320, 470, 9)
    assert VASE.stat().st_size == 4_060_902
    a = hsh.dequantized()
    lum = (a @ hsh_weights(0.0, 0.0, 9)).mean(axis=2)
    mask = lum > 0.08  # the vase against its black background
    widths = mask.sum(axis=1)
    # Upright: black above the mouth, the pedestal at the bottom, the body widest low down.
    assert widths[:30].max() == 0 and widths[-10:].min() > 100
    widest = int(np.argmax(np.where(np.arange(hsh.height) < 430, widths, 0)))
    assert 240 < widest < 310
    # Side lights brighten the matching half of the vase.
    left_half, right_half = mask.copy(), mask.copy()
    left_half[:, hsh.width // 2 :] = False
    right_half[:, : hsh.width // 2] = False
    lit_left = (a @ hsh_weights(-0.8, 0.0, 9)).mean(axis=2)
    lit_right = (a @ hsh_weights(0.8, 0.0, 9)).mean(axis=2)
    assert lit_left[left_half].mean() > 1.3 * lit_left[right_half].mean()
    assert lit_right[right_half].mean() > 1.3 * lit_right[left_half].mean()

    n = three_light_normals(hsh)
    shoulder, lower = np.zeros_like(mask), np.zeros_like(mask)
    shoulder[widest - 80 : widest - 20] = mask[widest - 80 : widest - 20]
    lower[widest + 20 : widest + 110] = mask[widest + 20 : widest + 110]
    assert n[..., 1][shoulder].mean() > 0.15 and (n[..., 1][shoulder] > 0).mean() > 0.8
    assert n[..., 1][lower].mean() < -0.1
    left_rim, right_rim = [], []
    for y in range(200, 400):
        xs = np.nonzero(mask[y])[0]
        left_rim.append(n[y, xs[0] + 4 : xs[0] + 20, 0].mean())
        right_rim.append(n[y, xs[-1] - 19 : xs[-1] - 3, 0].mean())
    assert np.mean(left_rim) < -0.4 and max(left_rim) < 0
    assert np.mean(right_rim) > 0.4 and min(right_rim) > 0


# --- the real file --------------------------------------------------------------------------


@pytest.fixture(scope="module")
def ushabti() -> Ptm:
    if not USHABTI.exists():
        pytest.skip(f"../shared/realdata not present: {USHABTI} is missing")
    return read_ptm(USHABTI)


def _object_mask(ptm: Ptm) -> np.ndarray:
    """The figure against its black background, lit from the viewer."""
    mask: np.ndarray = ptm.relight(0.0, 0.0).mean(axis=2) > 0.15
    return mask


@pytest.mark.realdata
def test_ushabti_header_and_upright(ushabti: Ptm) -> None:
    assert (ushabti.colorspace, ushabti.width, ushabti.height) == ("lrgb", 512, 1024)
    np.testing.assert_array_equal(ushabti.bias, [160, 160, 160, 127, 127, 0])
    mask = _object_mask(ushabti)
    rows = np.flatnonzero(mask.any(axis=1))
    top, bottom = rows[0], rows[-1]
    third = (bottom - top) // 3
    width_per_row = mask.sum(axis=1)
    upper = width_per_row[top : top + third].mean()
    lower = width_per_row[bottom - third : bottom].mean()
    # Checked by eye: head and broad shoulders at the top, narrow legs and a base below.
    # Upright the upper third is ~200 px wide and the lower ~140 px; flipped it fails.
    assert upper > 1.25 * lower
    widest_row = int(np.argmax(width_per_row))
    assert widest_row < ushabti.height // 2


@pytest.mark.realdata
@pytest.mark.parametrize(("lu", "lit_side"), [(-0.8, "left"), (0.8, "right")])
def test_ushabti_relights_from_the_correct_side(ushabti: Ptm, lu: float, lit_side: str) -> None:
    mask = _object_mask(ushabti)
    centre = int(round(np.flatnonzero(mask.any(axis=0)).mean()))
    image = ushabti.relight(lu, 0.0).mean(axis=2)
    left = image[:, :centre][mask[:, :centre]].mean()
    right = image[:, centre:][mask[:, centre:]].mean()
    bright, dark = (left, right) if lit_side == "left" else (right, left)
    assert bright > 1.5 * dark
