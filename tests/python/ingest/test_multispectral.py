"""OpenLIME multispectral folders through ``lanterna import``: a true-colour composite first, then
one grey layer per band labelled with its wavelength (tiler/formats/relight_multispectral.py,
tiler/ingest/multispectral.py). The folders are written here as OpenLIME's sample
(``dist/assets/multispectral/oil_painting_ms_jpg``) lays them out: band i is channel i % 3 of
``{basename}_{i // 3:02d}``."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import numpy as np
import numpy.typing as npt
import pytest
import pyvips

from lanterna.cli import main
from tests.python.fixtures.relight_layouts import write_itarzoom, write_tarzoom
from tests.python.fixtures.sources import read_desc

W, H = 21, 13
WAVELENGTHS = [420, 460, 510, 550, 600.5, 640, 690]  # 7 bands: 3 images, the last one used once
U8 = npt.NDArray[np.uint8]


def bands(seed: int = 0) -> U8:
    return np.random.default_rng(seed).integers(0, 256, (len(WAVELENGTHS), H, W), dtype=np.uint8)


def images_of(b: U8) -> list[U8]:
    """Pack bands three per RGB image (the last image's unused channels hold a constant)."""
    n = -(-b.shape[0] // 3)
    padded = np.concatenate([b, np.full((3 * n - b.shape[0], H, W), 77, np.uint8)])
    return [np.ascontiguousarray(padded[3 * k : 3 * k + 3].transpose(1, 2, 0)) for k in range(n)]


def write_ms(folder: Path, b: U8, *, layout: str = "image",
             presets: dict[str, Any] | None = None, **changes: Any) -> Path:
    folder.mkdir(parents=True)
    info = {"width": W, "height": H, "format": "png", "type": "multispectral",
            "pixelSizeInMM": 0.05, "nplanes": len(WAVELENGTHS), "basename": "ms",
            "wavelength": WAVELENGTHS, **changes}
    (folder / "info.json").write_text(json.dumps(info))
    if presets is not None:
        (folder / "presets.json").write_text(json.dumps(presets))
    images = images_of(b)
    if layout == "itarzoom":
        write_itarzoom(folder, images, stem="ms", tile=16, overlap=1)
    for k, rgb in enumerate(images):
        if layout == "tarzoom":
            write_tarzoom(folder, f"ms_{k:02d}", rgb, tile=16, overlap=1)
        elif layout == "image":
            pyvips.Image.new_from_array(rgb).pngsave(str(folder / f"ms_{k:02d}.png"))
    return folder


def stored(out: Path, layer: str) -> U8:
    return np.asarray(pyvips.Image.new_from_file(
        str(out / "iiif" / layer / "full/max/0/default.png")).numpy())


def expected_composite(b: U8, weights: npt.NDArray[np.float64]) -> npt.NDArray[np.float64]:
    """OpenLIME's ``rgb`` mode: colour_c = Σᵢ w_c,i · band_i (values as stored, 0–1), clamped."""
    t = b.astype(np.float64) / 255.0
    rgb = np.stack([sum(weights[c, i] * t[i] for i in range(t.shape[0])) for c in range(3)], -1)
    return np.clip(rgb, 0, 1) * 255


def test_import_makes_a_composite_and_one_layer_per_band(tmp_path: Path) -> None:
    b = bands()
    weights = np.random.default_rng(5).uniform(0, 0.3, (3, len(WAVELENGTHS)))
    presets = {"test430": {c: [0] * 7 for c in ("red", "green", "blue")},
               "d65_true_color": dict(zip(("red", "green", "blue"), weights.tolist(),
                                          strict=True))}
    src = write_ms(tmp_path / "painting", b, presets=presets)
    out = tmp_path / "ds"
    assert main(["import", str(src), "-o", str(out)]) == 0
    desc = read_desc(out)
    ids = [layer["id"] for layer in desc["layers"]]
    assert ids == ["painting", "painting_420nm", "painting_460nm", "painting_510nm",
                   "painting_550nm", "painting_600_5nm", "painting_640nm", "painting_690nm"]
    labels = [layer["label"] for layer in desc["layers"]]
    assert labels[0] == "painting (true colour, 7 bands 420–690 nm)"
    assert labels[1:] == ["420 nm", "460 nm", "510 nm", "550 nm", "600.5 nm", "640 nm", "690 nm"]
    for k, layer in enumerate(desc["layers"][1:]):
        assert layer["service"]["layerType"] == "image"
        assert layer["service"]["planes"][0]["channels"] == ["Y"]
        assert layer["service"]["wavelength"] == WAVELENGTHS[k]
        np.testing.assert_array_equal(stored(out, layer["id"]), b[k])
    got = stored(out, "painting").astype(np.float64)
    assert np.abs(got - expected_composite(b, weights)).max() <= 0.5 + 1e-6
    assert desc["pixelSizeMM"] == 0.05
    manifest = json.loads((out / "manifest.json").read_text())
    text = json.dumps(manifest)
    assert "600.5 nm" in text and "\"wavelength\": 600.5" in text
    assert manifest["metadata"] == [{"label": {"en": ["Wavelengths"]}, "value": {"en": [
        "420 nm, 460 nm, 510 nm, 550 nm, 600.5 nm, 640 nm, 690 nm"]}}]
    assert manifest["summary"]["en"][0] == (
        "Multispectral (OpenLIME): 7 bands at 420, 460, 510, 550, 600.5, 640, 690 nm; true "
        "colour from presets.json 'd65_true_color'.")


def test_without_presets_the_composite_averages_wavelength_ranges(tmp_path: Path) -> None:
    b = bands(1)
    out = tmp_path / "ds"
    assert main(["import", str(write_ms(tmp_path / "p", b)), "-o", str(out)]) == 0
    # red: 600–700 nm (600.5, 640, 690), green 500–600 (510, 550), blue 400–500 (420, 460)
    weights = np.zeros((3, 7))
    weights[0, 4:7], weights[1, 2:4], weights[2, 0:2] = 1 / 3, 1 / 2, 1 / 2
    got = stored(out, "p").astype(np.float64)
    assert np.abs(got - expected_composite(b, weights)).max() <= 0.5 + 1e-6
    assert "true colour from wavelength ranges" in read_desc(out)["summary"]


@pytest.mark.parametrize("layout", ["tarzoom", "itarzoom"])
def test_tiled_multispectral_folders(tmp_path: Path, layout: str) -> None:
    b = bands(2)
    out = tmp_path / "ds"
    assert main(["import", str(write_ms(tmp_path / "t", b, layout=layout)), "-o", str(out)]) == 0
    for k, layer in enumerate(read_desc(out)["layers"][1:]):
        np.testing.assert_array_equal(stored(out, layer["id"]), b[k])


@pytest.mark.parametrize(("changes", "presets", "message"), [
    ({"nplanes": 8}, None, "info.json: nplanes is 8 but wavelength lists 7 bands"),
    ({"wavelength": [420, 460, 420]}, None, "wavelength[2] 420 nm repeats wavelength[0]"),
    ({"wavelength": [420, "x"]}, None, "wavelength[1] must be a positive number of nm"),
    ({"basename": "../ms"}, None, "basename must be a file name stem"),
    ({"width": 0}, None, "width must be a positive integer, got 0"),
    ({"format": "tif"}, None, "format must be jpg or png, got 'tif'"),
    ({}, {"true color": {"red": [1] * 6, "green": [1] * 7, "blue": [1] * 7}},
     "presets.json: true color.red: expected 7 finite weights"),
    ({}, {"d65_true_color": [1, 2]}, "presets.json: d65_true_color: expected an object"),
])
def test_bad_multispectral_folders(tmp_path: Path, capsys: pytest.CaptureFixture[str],
                                   changes: dict[str, Any], presets: Any, message: str) -> None:
    src = write_ms(tmp_path / "m", bands(), presets=presets, **changes)
    out = tmp_path / "ds"
    assert main(["import", str(src), "-o", str(out)]) == 2
    err = capsys.readouterr().err.strip()
    assert message in err and err.count("\n") == 0, err
    assert not out.exists()


def test_missing_band_image(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    src = write_ms(tmp_path / "m", bands())
    (src / "ms_01.png").unlink()
    assert main(["import", str(src), "-o", str(tmp_path / "ds")]) == 2
    assert f"{src / 'ms_01.png'}: band image 1 is missing" in capsys.readouterr().err
    assert not (tmp_path / "ds").exists()


def test_a_description_cannot_name_a_multispectral_folder(
        tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    write_ms(tmp_path / "m", bands())
    (tmp_path / "d.json").write_text(json.dumps({"layers": [{"id": "x", "source": "m"}]}))
    assert main(["import", str(tmp_path / "d.json"), "-o", str(tmp_path / "ds")]) == 2
    err = capsys.readouterr().err
    assert "m: an OpenLIME multispectral folder makes several layers" in err
    assert not (tmp_path / "ds").exists()
