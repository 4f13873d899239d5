"""Fitting the PCA light bases (``lanterna fit --model rbf|bilinear``): a known reflectance with
a sharp highlight, the held-out lights kept out of the leave-one-out basis, streaming against
in memory, the written dataset through the numpy reference, and the option errors."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import numpy.typing as npt
import pytest

from lanterna.cli import main
from lanterna.tiler.fit.models import leave_one_out, model_table
from lanterna.tiler.fit.pca import PcaSpec, resample_matrix
from lanterna.tiler.fit.pca_band import fit_pca, prepare_pca
from lanterna.tiler.fit.pca_basis import fit_basis, light_major
from lanterna.tiler.fit.pca_sample import sample_pixels
from lanterna.tiler.formats.pca_model import bilinear_weights
from lanterna.tiler.inputs.lp import read_lp
from lanterna.tiler.inputs.stack import StackReader, load_stack
from lanterna.tiler.render import level_channels, render
from tests.python.fixtures.photos import bumpy_normals, spiral_lights, write_collection
from tests.python.fixtures.stored import stored_plane

F32 = npt.NDArray[np.float32]
N_LIGHTS = 150


def glossy(lights: npt.NDArray[np.float64]) -> F32:
    """Lambert (albedo per pixel) + a Blinn-Phong lobe of exponent 40 on the bumpy surface."""
    normals = bumpy_normals()
    albedo = np.random.default_rng(5).uniform(0.3, 0.75, normals.shape[:2] + (3,))
    shade = np.maximum(np.einsum("hwc,nc->nhw", normals, lights), 0.0)
    half = lights + np.array([0.0, 0.0, 1.0])
    half /= np.linalg.norm(half, axis=1, keepdims=True)
    lobe = np.maximum(np.einsum("hwc,nc->nhw", normals, half), 0.0) ** 40
    images = albedo[None] * shade[..., None] + 0.5 * (lobe * (shade > 0))[..., None]
    return np.clip(images, 0.0, 1.0).astype(np.float32)


@pytest.fixture(scope="module")
def scene() -> tuple[F32, npt.NDArray[np.float64]]:
    lights = spiral_lights(N_LIGHTS, (15.0, 85.0))
    return glossy(lights), lights


@pytest.fixture(scope="module")
def collection(tmp_path_factory: pytest.TempPathFactory,
               scene: tuple[F32, npt.NDArray[np.float64]]) -> Path:
    images, lights = scene
    return write_collection(tmp_path_factory.mktemp("glossy"), images, lights)


def test_pca_bases_reproduce_held_out_lights_better_than_hsh(
        scene: tuple[F32, npt.NDArray[np.float64]]) -> None:
    images, lights = scene
    table = model_table()
    hsh = leave_one_out(images, lights, table["hsh"])["meanPsnr"]
    for key in ("rbf", "bilinear"):
        report = leave_one_out(images, lights, table[key])
        assert len(report["heldOut"]) == N_LIGHTS // 10
        assert report["meanPsnr"] > hsh + 2.0, (key, report["meanPsnr"], hsh)


def test_leave_one_out_basis_never_sees_the_held_out_lights(
        scene: tuple[F32, npt.NDArray[np.float64]], tmp_path: Path) -> None:
    """The report's basis is learnt without the held-out images and interpolates the others."""
    images, lights = scene
    held = np.arange(0, N_LIGHTS, 10)
    spoiled = images.copy()
    spoiled[held] = np.random.default_rng(1).uniform(0, 1, spoiled[held].shape)
    h, w = images.shape[1:3]
    for spec in (PcaSpec("rbf"), PcaSpec("bilinear"), PcaSpec("rbf", "mycc", 9)):
        clean = prepare_pca(spec, sample_pixels(images, 8), lights, held, tmp_path, w, h,
                            layers=False).step
        noisy = prepare_pca(spec, sample_pixels(spoiled, 8), lights, held, tmp_path, w, h,
                            layers=False).step
        assert clean.loo is not None and noisy.loo is not None
        assert np.array_equal(clean.loo.basis.basis, noisy.loo.basis.basis)
        assert not np.array_equal(clean.full.basis.basis, noisy.full.basis.basis)
        if spec.layer_type == "rbf":
            train = np.setdiff1d(np.arange(N_LIGHTS), held)
            assert clean.loo.basis.lights is not None
            assert np.allclose(np.reshape(clean.loo.basis.lights, (-1, 3)), lights[train])


def test_bilinear_resampling_reproduces_a_smooth_function_of_the_light() -> None:
    """The grid samples (Relight's regularised resampling) read back at the lights ≈ the data."""
    lights = spiral_lights(N_LIGHTS, (15.0, 85.0))
    m = resample_matrix(lights, 8)
    assert m.shape == (64, N_LIGHTS)
    values = 0.3 + 0.5 * lights[:, 2] + 0.2 * lights[:, 0]  # smooth in the light
    grid = m @ values
    back = np.array([bilinear_weights(8, lx, ly) @ grid for lx, ly, _ in lights])
    # an 8 × 8 grid cannot hold lz exactly, and the regularisation pulls toward the RBF average
    err = back - values
    assert np.sqrt(np.mean(err ** 2)) < 0.02 and np.max(np.abs(err)) < 0.05
    flat = resample_matrix(lights, 8) @ np.full(N_LIGHTS, 0.4)
    assert np.allclose(flat, 0.4, atol=1e-9)  # a constant stays one (B's and A's rows sum to 1)


def _same_planes(a: npt.NDArray[np.uint8], b: npt.NDArray[np.uint8]) -> None:
    """Equal but for float32 rounding: the product's summation order follows the band's pixel
    count (BLAS blocking), so a value at a rounding boundary may move by one step (docs)."""
    diff = np.abs(a.astype(int) - b.astype(int))
    assert diff.max() <= 1 and np.mean(diff > 0) < 1e-3, (diff.max(), np.mean(diff > 0))


def test_streaming_equals_in_memory(collection: Path, tmp_path: Path) -> None:
    """The CLI's streamed planes (read in bands of 37 rows from disk) are the in-memory fit's:
    the same basis bytes, the same plane bytes within one step in 0.1 % of the values."""
    files, lights = read_lp(collection, collection.parent)
    memory = load_stack(files)
    for model, space in (("rbf", "mrgb"), ("bilinear", "mycc")):
        spec = PcaSpec(model, space, 7)
        fit, planes = fit_pca(memory, lights, spec, band_rows=5)
        fit_disk, planes_disk = fit_pca(StackReader(files), lights, spec, band_rows=37)
        assert np.array_equal(fit.basis.basis, fit_disk.basis.basis)
        _same_planes(planes, planes_disk)
        out = tmp_path / model
        assert main(["fit", str(collection.parent), "--lp", str(collection), "--model", model,
                     "--planes", "7", "--colorspace", space, "--band-rows", "37", "--quiet",
                     "-o", str(out)]) == 0
        block = json.loads((out / "layers" / f"{model}.json").read_text())
        assert block["layerType"] == model and block["nplanes"] == 7
        assert block["basis"] == [int(b) for b in fit.basis.basis]
        assert block["colorspace"] == space
        stored = np.concatenate([stored_plane(out, f"{model}_p{g}") for g in range(3)],
                                axis=-1)
        _same_planes(stored[..., :7], planes)
        assert not stored[..., 7:].any()  # the padding channels X7, X8


@pytest.mark.parametrize(("model", "space"), [("rbf", "mrgb"), ("bilinear", "mrgb"),
                                              ("rbf", "mycc")])
def test_fitted_dataset_renders_new_lights_close_to_the_object(
        collection: Path, tmp_path: Path, model: str, space: str) -> None:
    """The written layer through the numpy reference at lights the fit never saw."""
    out = tmp_path / "ds"
    assert main(["fit", str(collection.parent), "--lp", str(collection), "--model", model,
                 "--model", "hsh", "--colorspace", space, "--quiet", "-o", str(out)]) == 0
    new = spiral_lights(7, (25.0, 75.0))
    new[:, :2] = new[:, :2] @ np.array([[0.8, -0.6], [0.6, 0.8]])  # off the spiral
    truth = glossy(new)
    scores = {}
    for lid in (model, "hsh9"):
        block = json.loads((out / "layers" / f"{lid}.json").read_text())
        channels = level_channels(out, block, 1)
        mse = [float(np.mean((render(block, channels, (float(lx), float(ly))) - img) ** 2))
               for (lx, ly, _), img in zip(new, truth, strict=True)]
        scores[lid] = -10.0 * np.log10(np.mean(mse))
    assert scores[model] > 27.0 and scores[model] > scores["hsh9"] + 1.0, scores


def test_basis_bytes_follow_relight_quantisation(
        scene: tuple[F32, npt.NDArray[np.float64]]) -> None:
    """Planes ``127 + range·e`` with ``range = 127/max|e|`` (so each plane reaches 0 or 254),
    the mean ``255·m``, coefficient ranges from the sample's central 99.5 %."""
    images, lights = scene
    sample = sample_pixels(images, 8)
    fit = fit_basis(sample, lights, PcaSpec("rbf", "mrgb", 6))
    planes = fit.basis.basis.reshape(7, -1)[1:].astype(int)
    assert all(np.max(np.abs(p - 127)) == 127 for p in planes)
    mean = sample.reshape(len(sample), -1).mean(axis=0)
    assert np.max(np.abs(fit.basis.basis.reshape(7, -1)[0] - np.rint(mean * 255))) <= 1
    t = fit.quantise(fit.coefficients(light_major(np.swapaxes(sample, 0, 1))))
    clipped = np.mean((t == 0) | (t == 255), axis=0)
    assert np.all(clipped <= 0.01) and np.all(clipped > 0)


@pytest.mark.parametrize(("args", "message"), [
    (["--model", "rbf", "--planes", "0"], "--planes must be from 1 to 48, got 0"),
    (["--model", "rbf", "--planes", "49"], "--planes must be from 1 to 48, got 49"),
    (["--model", "bilinear", "--planes", "2.5"],
     "--planes must be an integer from 1 to 48, got '2.5'"),
    (["--model", "rbf", "--planes", "many"],
     "--planes must be an integer from 1 to 48, got 'many'"),
    (["--model", "hsh", "--colorspace", "mycc"],
     "--colorspace applies to --model rbf or bilinear only"),
    (["--model", "ptm", "--planes", "9"], "--planes applies to --model rbf or bilinear only"),
    (["--model", "rbf", "--colorspace", "lab"], "--colorspace must be mrgb or mycc, got 'lab'"),
])
def test_bad_pca_options_are_one_line_errors(collection: Path, tmp_path: Path,
                                             capsys: pytest.CaptureFixture[str],
                                             args: list[str], message: str) -> None:
    out = tmp_path / "bad"
    assert main(["fit", str(collection.parent), "--lp", str(collection), *args, "--quiet",
                 "-o", str(out)]) == 2
    err = capsys.readouterr().err.strip()
    assert message in err and len(err.splitlines()) == 1, err
    assert not out.exists() and list(tmp_path.iterdir()) == []


def test_too_many_planes_for_the_lights_names_the_light_file(
        tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    lights = spiral_lights(12)
    lp = write_collection(tmp_path / "few", glossy(lights), lights)
    out = tmp_path / "out"
    assert main(["fit", str(lp.parent), "--lp", str(lp), "--model", "rbf", "--planes", "40",
                 "--quiet", "-o", str(out)]) == 2
    err = capsys.readouterr().err.strip()
    assert "lights.lp" in err and "40 planes need at least 14 light samples, got 12" in err
    assert len(err.splitlines()) == 1 and not out.exists()
