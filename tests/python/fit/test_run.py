"""lanterna fit with several image sets (spectral bands), false-colour fusions, camera RAW,
the fit-space option and progress bars."""

from __future__ import annotations

import io
import json
from pathlib import Path

import numpy as np
import numpy.typing as npt
import pytest
import pyvips

from lanterna.cli import main
from lanterna.errors import LanternaInputError
from lanterna.tiler.fit.bands import luminance
from lanterna.tiler.fit.models import fit_ptm_rgb
from lanterna.tiler.fit.run import ImageSet, fit_sets
from lanterna.tiler.inputs.stack import load_stack
from lanterna.tiler.progress import Progress
from tests.python.fixtures.photos import (
    bumpy_normals,
    render_bumpy,
    spiral_lights,
    write_collection,
)
from tests.python.fixtures.stored import stored_format, stored_plane

H, W = 24, 32


def _band(folder: Path, lights: npt.NDArray[np.float64], gain: float,
          shift: int = 0) -> Path:
    """A band: the test object with its albedo scaled by ``gain`` (and optionally shifted)."""
    images = np.clip(render_bumpy(bumpy_normals(), lights) * gain, 0, 1)
    if shift:
        images = np.roll(images, shift, axis=2)
    return write_collection(folder, images.astype(np.float32), lights)


@pytest.fixture(scope="module")
def bands(tmp_path_factory: pytest.TempPathFactory) -> dict[str, Path]:
    root = tmp_path_factory.mktemp("bands")
    lights = spiral_lights(30)
    return {name: _band(root / name, lights, gain)
            for name, gain in (("IR", 1.2), ("R", 0.9), ("G", 0.6))}


def _plane(ds: Path, image: str) -> npt.NDArray[np.uint8]:
    assert stored_format(ds, image) in ("png", "webp")  # fitted planes: a lossless source
    return stored_plane(ds, image)


def test_bands_and_fusion_layers(bands: dict[str, Path], tmp_path: Path,
                                 capsys: pytest.CaptureFixture[str]) -> None:
    out = tmp_path / "ms"
    argv = ["fit", "--model", "ptm", "--model", "normals", "--fusion", "IR,R,G", "-o", str(out)]
    for name, lp in bands.items():
        argv += ["--set", f"{name}={lp.parent},{lp}"]
    assert main(argv) == 0
    desc = json.loads((out / "lanterna.json").read_text())
    ids = [layer["id"] for layer in desc["layers"]]
    assert ids == ["ir_ptm", "ir_normals", "r_ptm", "r_normals", "g_ptm", "g_normals",
                   "fc_ir_r_g_ptm", "fc_ir_r_g_normals"]
    labels = {layer["id"]: layer["label"] for layer in desc["layers"]}
    assert labels["r_ptm"].startswith("R: ") and "False colour" in labels["fc_ir_r_g_ptm"]
    assert set(desc["quality"]["models"]) == set(ids)
    # the fusion is the RGB PTM of the stack whose R, G, B are the bands' luminances (the fit's
    # own, whose bits are the formula's: numpy's ``@ LUMINANCE_WEIGHTS`` can be an ulp away)
    lum = [luminance(load_stack(sorted(bands[b].parent.glob("*.png"))))
           for b in ("IR", "R", "G")]
    expected = fit_ptm_rgb(np.stack(lum, axis=-1), _lights_from(bands["IR"]))
    assert np.array_equal(_plane(out, "fc_ir_r_g_ptm_r0"), expected.coefficients[:, :, 0, :3])
    assert np.array_equal(_plane(out, "fc_ir_r_g_ptm_b1"), expected.coefficients[:, :, 2, 3:])
    # one band alone equals a plain single-set fit of its folder
    single = tmp_path / "r_only"
    assert main(["fit", str(bands["R"].parent), "--lp", str(bands["R"]), "--model", "ptm",
                 "--quiet", "-o", str(single)]) == 0
    assert np.array_equal(_plane(out, "r_ptm_g0"), _plane(single, "ptm_g0"))
    err = capsys.readouterr().err
    assert "fitting ptm, normals" in err and "100.0%" in err  # progress lines (not a TTY)


def _lights_from(lp: Path) -> npt.NDArray[np.float64]:
    from lanterna.tiler.inputs.lp import read_lp

    return read_lp(lp, lp.parent)[1]


def test_fusion_and_band_errors(bands: dict[str, Path], tmp_path: Path) -> None:
    sets = [ImageSet(n, lp.parent, lp) for n, lp in bands.items()]
    with pytest.raises(LanternaInputError, match="needs three of the bands IR, R, G"):
        fit_sets(sets, ["ptm"], tmp_path / "a", fusions=[("IR", "R", "UV")])
    with pytest.raises(LanternaInputError, match="band names must be unique"):
        fit_sets(sets + sets[:1], ["ptm"], tmp_path / "b")
    other = _band(tmp_path / "UV", spiral_lights(31), 1.0)
    with pytest.raises(LanternaInputError, match="band UV was not taken under the lights of"):
        fit_sets(sets + [ImageSet("UV", other.parent, other)], ["ptm"], tmp_path / "c",
                 fusions=[("IR", "R", "UV")])
    small = tmp_path / "S"
    small.mkdir()
    for f in sorted(bands["G"].parent.glob("*.png")):
        pyvips.Image.new_from_file(str(f)).crop(0, 0, W - 2, H).write_to_file(str(small / f.name))
    (small / "lights.lp").write_text(bands["G"].read_text())
    with pytest.raises(LanternaInputError, match="bands must be co-registered"):
        fit_sets(sets + [ImageSet("S", small, small / "lights.lp")], ["ptm"], tmp_path / "d")
    assert main(["fit", str(small), "--set", "A=x", "--model", "ptm", "-o",
                 str(tmp_path / "e")]) == 2
    assert main(["fit", "--set", "A=x", "--model", "ptm", "-o", str(tmp_path / "f")]) == 2
    assert sorted(p.name for p in tmp_path.iterdir()) == ["S", "UV"]  # nothing written


def test_fit_space_linear_writes_linear_maps(tmp_path: Path) -> None:
    """Photometric stereo in linear light: sRGB-encoded photos of a Lambert object."""
    lights = spiral_lights(40)
    linear = render_bumpy(bumpy_normals(), lights)
    encoded = np.where(linear <= 0.0031308, 12.92 * linear,
                       1.055 * np.power(linear, 1 / 2.4) - 0.055).astype(np.float32)
    lp = write_collection(tmp_path / "shots", encoded, lights, depth=16, suffix=".png")
    reports = {}
    for space in ("stored", "linear"):
        out = tmp_path / space
        assert main(["fit", str(lp.parent), "--lp", str(lp), "--model", "normals", "--quiet",
                     "--fit-space", space, "-o", str(out)]) == 0
        desc = json.loads((out / "lanterna.json").read_text())
        assert desc["layers"][0]["service"]["inputColorSpace"] == (
            "linear" if space == "linear" else "display")
        reports[space] = desc["quality"]["models"]["normals"]["meanPsnr"]
        normals = _plane(out, "normals_normals").astype(np.float64) / 255 * 2 - 1
        normals /= np.linalg.norm(normals, axis=-1, keepdims=True)
        err = np.degrees(np.arccos(np.clip((normals * bumpy_normals()).sum(-1), -1, 1)))
        reports[space + "_err"] = float(np.median(err))
    print(reports)
    # Lambert holds in linear light only: better normals and a better prediction there
    assert reports["linear_err"] < 1.0 < reports["stored_err"]
    assert reports["linear"] > reports["stored"] + 3


def test_raw_collection_is_decoded_once_and_fitted(tmp_path: Path) -> None:
    pytest.importorskip("rawpy", reason="camera RAW needs rawpy (pip install rawpy)")
    from tests.python.fixtures.dng import dng_bytes, scene_to_raw

    lights = spiral_lights(12)
    images = render_bumpy(bumpy_normals(), lights)
    folder = tmp_path / "raw"
    folder.mkdir()
    rows = [str(len(lights))]
    for i, (img, light) in enumerate(zip(images, lights, strict=True)):
        (folder / f"shot_{i:02d}.dng").write_bytes(dng_bytes(scene_to_raw(
            np.repeat(np.repeat(img.astype(np.float64), 2, 0), 2, 1))))
        rows.append(f"shot_{i:02d}.dng {light[0]} {light[1]} {light[2]}")
    (folder / "lights.lp").write_text("\n".join(rows) + "\n")
    out = tmp_path / "ds"
    assert main(["fit", str(folder), "--lp", str(folder / "lights.lp"), "--model", "normals",
                 "--quiet", "-o", str(out)]) == 0
    desc = json.loads((out / "lanterna.json").read_text())
    assert (desc["width"], desc["height"]) == (2 * W, 2 * H)
    assert not list(tmp_path.glob(".lanterna-fit-*"))  # the decoded TIFFs are gone
    # a collection mixing RAW and PNG is refused
    pyvips.Image.black(2 * W, 2 * H, bands=3).write_to_file(str(folder / "shot_00.png"))
    (folder / "lights.lp").write_text((folder / "lights.lp").read_text().replace(
        "shot_00.dng", "shot_00.png"))
    with pytest.raises(LanternaInputError, match="must not mix camera RAW"):
        fit_sets([ImageSet(None, folder, folder / "lights.lp")], ["ptm"], tmp_path / "mixed")


def test_progress_lines() -> None:
    log = io.StringIO()
    bar = Progress("fitting ptm", 200, stream=log)
    for done in range(0, 201, 7):
        bar.update(done)
    bar.update(200)
    lines = log.getvalue().splitlines()
    assert 5 <= len(lines) <= 12  # one per 10 % step in a log, not one per update
    assert lines[-1].startswith("  fitting ptm") and "100.0% 200/200 rows" in lines[-1]
    assert "[########################]" in lines[-1]


def test_plane_format_flag_of_fit(bands: dict[str, Path], tmp_path: Path,
                                  capsys: pytest.CaptureFixture[str]) -> None:
    lp = bands["R"]
    argv = ["fit", str(lp.parent), "--lp", str(lp), "--model", "ptm", "--model", "normals"]
    assert main([*argv, "-o", str(tmp_path / "j"), "--plane-format", "jpg:70"]) == 0
    desc = json.loads((tmp_path / "j/lanterna.json").read_text())
    planes = [p for layer in desc["layers"] for p in layer["service"]["planes"]]
    assert len(planes) == 8 and {p["format"] for p in planes} == {"jpg"}  # RGB PTM, normals + kd
    assert {desc["images"][p["service"]["id"].rsplit("/", 1)[1]]["quality"] for p in planes} \
        == {70}
    assert main([*argv, "-o", str(tmp_path / "bad"), "--plane-format", "tiff"]) == 2
    assert "--plane-format wants auto, png, webp or jpg[:Q]" in capsys.readouterr().err
    assert not (tmp_path / "bad").exists()
