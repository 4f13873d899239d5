"""Camera RAW input (tiler/inputs/raw.py), checked on synthetic DNGs (fixtures/dng.py).

The fixture's camera records linear sRGB scaled by its ``AsShotNeutral``, so a correct decode
(camera white balance, the file's levels, colour matrix, no auto-brightening) returns the
scene colours themselves.  Patch means are compared within ``TOL`` of full scale, measured
``MARGIN`` pixels inside each flat quadrant (away from demosaicing at the edges).
"""

from __future__ import annotations

import sys
from pathlib import Path
from types import ModuleType

import numpy as np
import numpy.typing as npt
import pytest

from lanterna.errors import LanternaInputError
from lanterna.tiler.inputs.raw import RAW_SUFFIXES, is_raw, raw_to_tiff, scratch_name
from lanterna.tiler.inputs.stack import StackReader, load_image
from tests.python.fixtures.dng import (
    NEUTRAL,
    PATCHES,
    dng_bytes,
    patch_scene,
    scene_to_raw,
    write_dng,
)

TOL = 0.0005  # 0.05 % of full scale, ≈ 33 of 65535 (measured worst: 5 of 65535)
MARGIN = 4
H, W = 48, 64


@pytest.fixture
def rawpy() -> ModuleType:
    """Return rawpy, or skip: these tests decode RAW files through it."""
    module: ModuleType = pytest.importorskip(
        "rawpy", reason="camera RAW tests need rawpy: pip install rawpy (or 'lanterna[raw]')")
    return module


def srgb_encode(v: npt.NDArray[np.float64]) -> npt.NDArray[np.float64]:
    """Return the sRGB transfer curve (IEC 61966-2-1) of linear values ``v``."""
    return np.where(v <= 0.0031308, 12.92 * v, 1.055 * np.power(v, 1 / 2.4) - 0.055)


def read_tiff(path: Path) -> npt.NDArray[np.float32]:
    """Read a decoded TIFF as 0–1 float, asserting it is 16-bit RGB of the scene's size."""
    import pyvips

    img = pyvips.Image.new_from_file(str(path))
    assert (img.width, img.height, img.bands, img.format) == (W, H, 3, "ushort")
    rgb: npt.NDArray[np.float32] = load_image(path)
    return rgb


def patch_means(rgb: npt.NDArray[np.float32]) -> dict[tuple[int, int], npt.NDArray[np.float64]]:
    """Return the mean colour inside each quadrant of :func:`patch_scene`, keyed like PATCHES."""
    h, w = rgb.shape[:2]
    return {(qy, qx): rgb[qy * h // 2 + MARGIN:(qy + 1) * h // 2 - MARGIN,
                          qx * w // 2 + MARGIN:(qx + 1) * w // 2 - MARGIN]
            .reshape(-1, 3).mean(0, dtype=np.float64)
            for qy, qx in PATCHES}


def test_is_raw_by_suffix() -> None:
    assert is_raw("a/IMG_0001.CR2") and is_raw(Path("x.dng")) and is_raw("x.Nef")
    assert not is_raw("x.tif") and not is_raw("x.jpg") and not is_raw("dng")
    assert all(s == s.lower() and s.startswith(".") for s in RAW_SUFFIXES)


@pytest.mark.parametrize("neutral", [NEUTRAL, (0.7, 1.0, 0.45)])
def test_linear_decode_returns_scene_colours(rawpy: ModuleType, tmp_path: Path,
                                             neutral: tuple[float, float, float]) -> None:
    dng = write_dng(tmp_path / "light.dng", patch_scene(H, W), neutral=neutral)
    tiff = raw_to_tiff(dng, tmp_path / "scratch", linear=True)
    assert tiff.parent == tmp_path / "scratch" and tiff.suffix == ".tif"
    means = patch_means(read_tiff(tiff))
    for key, colour in PATCHES.items():
        np.testing.assert_allclose(means[key], colour, atol=TOL, err_msg=str(key))


def test_srgb_curve_is_the_srgb_transfer_function(rawpy: ModuleType, tmp_path: Path) -> None:
    dng = write_dng(tmp_path / "light.dng", patch_scene(H, W))
    linear = patch_means(read_tiff(raw_to_tiff(dng, tmp_path, linear=True)))
    srgb = patch_means(read_tiff(raw_to_tiff(dng, tmp_path, linear=False)))
    for key, colour in PATCHES.items():
        np.testing.assert_allclose(srgb[key], srgb_encode(np.asarray(colour)), atol=2 * TOL,
                                   err_msg=str(key))
        assert np.all(srgb[key] > linear[key])  # mid-tones and darks brighter
    assert srgb[(0, 0)][1] == pytest.approx(0.4614, abs=2 * TOL)  # 18 % grey → sRGB 118/255


def test_srgb_curve_is_monotonic_on_a_ramp(rawpy: ModuleType, tmp_path: Path) -> None:
    ramp = np.linspace(0.0, 0.95, W)
    scene = np.broadcast_to(ramp[None, :, None], (H, W, 3)).copy()
    tiff = raw_to_tiff(write_dng(tmp_path / "ramp.dng", scene), tmp_path, linear=False)
    columns = read_tiff(tiff)[MARGIN:-MARGIN].mean(axis=(0, 2))
    assert np.all(np.diff(columns[MARGIN:-MARGIN]) > 0)
    np.testing.assert_allclose(columns[MARGIN:-MARGIN], srgb_encode(ramp)[MARGIN:-MARGIN],
                               atol=3 * TOL)


def dot_centre(rgb: npt.NDArray[np.float32]) -> tuple[float, float]:
    """Return the (row, column) centroid of the pixels brighter than half the maximum."""
    grey = rgb.mean(axis=2)
    ys, xs = np.nonzero(grey > grey.max() / 2)
    weights = grey[ys, xs]
    return float(np.average(ys, weights=weights)), float(np.average(xs, weights=weights))


def test_orientation_flag_is_ignored_so_images_stay_coregistered(
        rawpy: ModuleType, tmp_path: Path) -> None:
    scene = np.full((H, W, 3), 0.02)
    scene[17:20, 29:32] = 0.9  # a 3×3 dot centred on row 18, column 30
    centres = {}
    for orientation in (1, 3, 6, 8):  # none, 180°, 90° CW, 90° CCW
        dng = write_dng(tmp_path / f"o{orientation}.dng", scene, orientation=orientation)
        centres[orientation] = dot_centre(read_tiff(raw_to_tiff(dng, tmp_path, linear=True)))
        if orientation in (6, 8):  # the flag is real: LibRaw's default would rotate
            with rawpy.imread(str(dng)) as raw:
                assert raw.postprocess().shape[:2] == (W, H)
    for orientation, (y, x) in centres.items():
        assert y == pytest.approx(18, abs=0.25) and x == pytest.approx(30, abs=0.25), orientation


def test_brightness_is_not_rescaled_per_image(rawpy: ModuleType, tmp_path: Path) -> None:
    """A dim frame stays dim and a near-white one is not stretched: one fixed scale."""
    levels = []
    for value in (0.05, 0.97):
        dng = write_dng(tmp_path / f"v{value}.dng", np.full((H, W, 3), value))
        rgb = read_tiff(raw_to_tiff(dng, tmp_path, linear=True))
        levels.append(float(rgb[MARGIN:-MARGIN, MARGIN:-MARGIN].mean()))
    assert levels == pytest.approx([0.05, 0.97], abs=TOL)


def test_decoded_tiffs_stream_through_the_stack_reader(rawpy: ModuleType,
                                                       tmp_path: Path) -> None:
    tiffs = []
    for i, value in enumerate((0.2, 0.4, 0.6)):
        dng = write_dng(tmp_path / f"{i}.dng", patch_scene(H, W) * value / 0.9)
        tiffs.append(raw_to_tiff(dng, tmp_path / "scratch", linear=True))
    reader = StackReader(tiffs)
    assert reader.shape == (3, H, W, 3)
    bands = np.concatenate([reader[:, y:y + 7] for y in range(0, H, 7)], axis=1)
    np.testing.assert_array_equal(bands, np.stack([load_image(t) for t in tiffs]))


def test_scratch_names_are_unique_and_leave_no_temporaries(rawpy: ModuleType,
                                                           tmp_path: Path) -> None:
    (tmp_path / "a").mkdir()
    (tmp_path / "b").mkdir()
    scene = patch_scene(H, W)
    one = raw_to_tiff(write_dng(tmp_path / "a" / "x.dng", scene), tmp_path / "s", linear=True)
    two = raw_to_tiff(write_dng(tmp_path / "b" / "x.dng", scene), tmp_path / "s", linear=True)
    again = raw_to_tiff(tmp_path / "a" / "x.dng", tmp_path / "s", linear=True)
    srgb = raw_to_tiff(tmp_path / "a" / "x.dng", tmp_path / "s", linear=False)
    assert one == again and len({one, two, srgb}) == 3
    assert one.name == scratch_name(tmp_path / "a" / "x.dng", linear=True)
    assert sorted(p.name for p in (tmp_path / "s").iterdir()) == sorted({one.name, two.name,
                                                                         srgb.name})


@pytest.mark.parametrize("damage", ["truncated", "header only", "garbage", "empty"])
def test_bad_raw_names_the_file(rawpy: ModuleType, tmp_path: Path, damage: str) -> None:
    good = dng_bytes(scene_to_raw(patch_scene(H, W)))
    data = {"truncated": good[:len(good) // 2], "header only": good[:300],
            "garbage": b"not a raw file " * 64, "empty": b""}[damage]
    bad = tmp_path / "broken.dng"
    bad.write_bytes(data)
    with pytest.raises(LanternaInputError, match=r"broken\.dng: cannot decode camera RAW"):
        raw_to_tiff(bad, tmp_path / "scratch", linear=True)
    assert not (tmp_path / "scratch").exists() or not any((tmp_path / "scratch").iterdir())


def test_missing_file_names_it(rawpy: ModuleType, tmp_path: Path) -> None:
    with pytest.raises(LanternaInputError, match=r"nope\.nef: file not found"):
        raw_to_tiff(tmp_path / "nope.nef", tmp_path, linear=True)


def test_without_rawpy_says_how_to_install(tmp_path: Path,
                                           monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setitem(sys.modules, "rawpy", None)  # makes `import rawpy` raise ImportError
    dng = tmp_path / "light.dng"
    dng.write_bytes(dng_bytes(scene_to_raw(patch_scene(H, W))))
    with pytest.raises(LanternaInputError) as caught:
        raw_to_tiff(dng, tmp_path, linear=True)
    assert str(caught.value) == (f"{dng}: camera RAW needs rawpy: pip install rawpy "
                                 "(or 'lanterna[raw]')")
