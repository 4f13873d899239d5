"""Fitting on a synthetic object rendered by the test: known normals, Lambert + highlights."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import numpy.typing as npt
import pytest
import pyvips

from lanterna.cli import main
from lanterna.errors import LanternaInputError
from lanterna.tiler.fit.models import fit_normals, leave_one_out, model_table
from lanterna.tiler.fit.run import fit_collection
from lanterna.tiler.inputs.stack import load_image, load_stack
from tests.python.fixtures.photos import (
    H,
    W,
    bumpy_normals,
    render_bumpy,
    spiral_lights,
    write_collection,
)


def _angles(a: npt.NDArray[np.floating], b: npt.NDArray[np.floating]) -> npt.NDArray[np.float64]:
    cos = np.clip(np.sum(a * b, axis=-1), -1.0, 1.0)
    return np.degrees(np.arccos(cos))


@pytest.mark.parametrize("specular", [0.0, 0.6], ids=["lambert", "with-highlights"])
def test_normals_recovered_within_a_degree(specular: float) -> None:
    truth = bumpy_normals()
    lights = spiral_lights()
    fitted = fit_normals(render_bumpy(truth, lights, specular=specular), lights)
    errors = _angles(fitted.normals, truth)
    assert np.median(errors) <= 1.0
    assert fitted.normals.shape == (H, W, 3)


def test_plain_least_squares_is_hurt_by_highlights() -> None:
    """The rank window matters: without it the highlights bias the normals."""
    truth, lights = bumpy_normals(), spiral_lights()
    images = render_bumpy(truth, lights, specular=0.6)
    plain = fit_normals(images, lights, rank_window=(0.0, 1.0), shadow=0.0)
    robust = fit_normals(images, lights)
    assert np.median(_angles(plain.normals, truth)) > 2 * np.median(
        _angles(robust.normals, truth))


@pytest.mark.parametrize("model, floor", [("ptm", 33.0), ("ptm-lrgb", 30.0), ("hsh", 35.0),
                                          ("normals", 40.0)])
def test_models_reproduce_held_out_renders(model: str, floor: float) -> None:
    lights = spiral_lights()
    images = render_bumpy(bumpy_normals(), lights)
    report = leave_one_out(images, lights, model_table(9)[model])
    assert report["heldOut"] == [0, 10, 20, 30, 40]
    assert report["meanPsnr"] >= floor, report


@pytest.mark.parametrize("suffix, depth", [(".png", 16), (".tif", 16), (".tif", 8),
                                           (".jpg", 8)])
def test_load_image_formats(tmp_path: Path, suffix: str, depth: int) -> None:
    overhead = np.array([[0.0, 0.0, 1.0]])
    images = render_bumpy(bumpy_normals(), overhead)
    write_collection(tmp_path, images, overhead, suffix=suffix, depth=depth)
    loaded = load_image(tmp_path / f"IMG_000{suffix}")
    assert loaded.shape == (H, W, 3) and loaded.dtype == np.float32
    error = np.abs(loaded - images[0])
    if suffix == ".jpg":  # lossy and chroma-subsampled (the albedo is per-pixel noise)
        assert abs(float(loaded.mean() - images[0].mean())) <= 0.01
    else:
        assert error.max() <= (0.5 / 255 if depth == 8 else 0.5 / 65535) + 1e-6


def test_cli_fit_writes_layers_and_quality(tmp_path: Path, capsys: pytest.CaptureFixture[str]
                                           ) -> None:
    lights = spiral_lights()
    images = render_bumpy(bumpy_normals(), lights)
    lp = write_collection(tmp_path / "shots", images, lights, depth=16)
    out = tmp_path / "ds"
    status = main(["fit", str(tmp_path / "shots"), "--lp", str(lp), "--model", "ptm",
                   "--model", "hsh", "--terms", "4", "--model", "normals", "-o", str(out)])
    assert status == 0
    printed = capsys.readouterr().out
    assert "hsh4: leave-one-out PSNR mean" in printed
    desc = json.loads((out / "lanterna.json").read_text())
    assert [layer["id"] for layer in desc["layers"]] == ["ptm", "hsh4", "normals"]
    assert set(desc["quality"]["models"]) == {"ptm", "hsh4", "normals"}
    assert desc["quality"]["models"]["normals"]["meanPsnr"] > 35.0


def test_fitted_normals_from_16_bit_files(tmp_path: Path) -> None:
    truth, lights = bumpy_normals(), spiral_lights()
    lp = write_collection(tmp_path, render_bumpy(truth, lights), lights, suffix=".tif", depth=16)
    from lanterna.tiler.inputs.lp import read_lp

    files, read_lights = read_lp(lp, tmp_path)
    fitted = fit_normals(load_stack(files), read_lights)
    assert np.median(_angles(fitted.normals, truth)) <= 1.0


def _assert_nothing_written(parent: Path, out: Path) -> None:
    assert not out.exists()
    assert not [p for p in parent.iterdir() if p.name.startswith(f".{out.name}.tmp")]


def test_bad_lp_writes_nothing(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    lights = spiral_lights(8)
    lp = write_collection(tmp_path / "shots", render_bumpy(bumpy_normals(), lights), lights)
    text = lp.read_text().splitlines()
    text[4] = "captures\\img_003.png 0 0 0"
    lp.write_text("\n".join(text))
    out = tmp_path / "ds"
    status = main(["fit", str(tmp_path / "shots"), "--lp", str(lp), "--model", "ptm",
                   "-o", str(out)])
    assert status == 2
    err = capsys.readouterr().err.strip()
    assert err == f"lanterna: error: {lp}: line 5: zero light vector for captures\\img_003.png"
    _assert_nothing_written(tmp_path, out)


def test_mismatched_sizes_write_nothing(tmp_path: Path) -> None:
    lights = spiral_lights(8)
    lp = write_collection(tmp_path / "shots", render_bumpy(bumpy_normals(), lights), lights)
    odd = tmp_path / "shots" / "IMG_005.png"
    pyvips.Image.black(W + 1, H, bands=3).write_to_file(str(odd))
    out = tmp_path / "ds"
    with pytest.raises(LanternaInputError) as info:
        fit_collection(tmp_path / "shots", lp, ["ptm"], out)
    assert str(info.value) == (f"{odd}: is {W + 1}x{H}, but IMG_000.png is {W}x{H}: all images "
                               "of a collection must have the same size")
    _assert_nothing_written(tmp_path, out)


def test_unreadable_image_writes_nothing(tmp_path: Path) -> None:
    lights = spiral_lights(8)
    lp = write_collection(tmp_path / "shots", render_bumpy(bumpy_normals(), lights), lights)
    broken = tmp_path / "shots" / "IMG_002.png"
    broken.write_bytes(b"not a png")
    out = tmp_path / "ds"
    with pytest.raises(LanternaInputError, match=r"IMG_002\.png: cannot read image"):
        fit_collection(tmp_path / "shots", lp, ["hsh"], out)
    _assert_nothing_written(tmp_path, out)


def test_too_few_lights_is_a_clear_error(tmp_path: Path) -> None:
    lights = spiral_lights(5)
    lp = write_collection(tmp_path / "shots", render_bumpy(bumpy_normals(), lights), lights)
    with pytest.raises(LanternaInputError, match="cannot fit ptm: .*6 PTM terms"):
        fit_collection(tmp_path / "shots", lp, ["ptm"], tmp_path / "ds")
    _assert_nothing_written(tmp_path, tmp_path / "ds")


def test_cli_fit_of_a_collection_whose_lp_names_a_subfolder(tmp_path: Path) -> None:
    """The README's ``lanterna fit photos/ --lp photos/dirs.lp`` on a collection laid out as in
    the wild: the ``.lp`` in the folder, the images in ``jpg/`` that it names (``jpg/NAME``)."""
    lights = spiral_lights()
    write_collection(tmp_path / "photos" / "jpg", render_bumpy(bumpy_normals(), lights), lights)
    rows = [f"jpg/IMG_{i:03d}.png {x} {y} {z}" for i, (x, y, z) in enumerate(lights)]
    lp = tmp_path / "photos" / "dirs.lp"
    lp.write_text("\n".join([str(len(rows)), *rows]) + "\n")
    (tmp_path / "photos" / "jpg" / "lights.lp").unlink()
    for images in (tmp_path / "photos", tmp_path / "photos" / "jpg"):
        out = tmp_path / f"ds-{images.name}"
        assert main(["fit", str(images), "--lp", str(lp), "--model", "normals", "--quiet",
                     "-o", str(out)]) == 0
        desc = json.loads((out / "lanterna.json").read_text())
        assert desc["label"] == "photos"  # the collection, not its jpg/ folder
