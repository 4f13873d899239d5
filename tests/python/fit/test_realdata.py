"""Fitting the real 240-light NeuralRTI "Löwenkopf" collection: the baselines of the notes."""

from __future__ import annotations

import json
from typing import Any

import numpy as np
import pytest

from lanterna.tiler.fit.models import fit_normals, leave_one_out, model_table
from lanterna.tiler.fit.run import fit_collection
from lanterna.tiler.inputs.lp import read_lp
from lanterna.tiler.inputs.stack import load_stack
from tests.python.fixtures.paths import SHARED

LOEWENKOPF = SHARED / "realdata" / "neuralrti-loewenkopf"

pytestmark = [
    pytest.mark.realdata,
    pytest.mark.skipif(not (LOEWENKOPF / "dirs.lp").is_file(),
                       reason=f"real data not found at {LOEWENKOPF} (../shared/realdata)"),
]

# rti-formats.md §6: 24 held-out lights (every 10th), RGB 0–1 as stored, mean PSNR in dB
BASELINES = {"ptm": 27.5, "hsh": 28.8, "ward": 29.0}


@pytest.fixture(scope="module")
def collection() -> tuple[np.ndarray, np.ndarray]:
    files, lights = read_lp(LOEWENKOPF / "dirs.lp", LOEWENKOPF / "jpg")
    return load_stack(files), lights


@pytest.fixture(scope="module")
def fitted(tmp_path_factory: pytest.TempPathFactory) -> dict[str, Any]:
    """``lanterna fit`` of every model in one streamed pass: the stored quality report."""
    out = tmp_path_factory.mktemp("loewenkopf") / "ds"
    fit_collection(LOEWENKOPF / "jpg", LOEWENKOPF / "dirs.lp", ["ptm", "hsh", "ward"], out)
    quality: dict[str, Any] = json.loads((out / "lanterna.json").read_text())["quality"]
    return quality


@pytest.mark.parametrize(("model", "layer"), [("ptm", "ptm"), ("hsh", "hsh9"), ("ward", "ward")])
def test_leave_one_out_meets_baseline(fitted: dict[str, Any], model: str, layer: str) -> None:
    report = fitted["models"][layer]
    assert len(report["heldOut"]) == 24 and report["heldOut"][:2] == [0, 10]
    assert report["meanPsnr"] >= BASELINES[model], report


def test_leave_one_out_function_matches_the_stored_report(
        collection: tuple[np.ndarray, np.ndarray], fitted: dict[str, Any]) -> None:
    """The library call on the in-memory stack reports what the streamed CLI fit stored."""
    images, lights = collection
    assert images.shape[0] == 240
    report = leave_one_out(images, lights, model_table(9)["hsh"])
    assert report == fitted["models"]["hsh9"]


def test_normals_point_the_right_way(collection: tuple[np.ndarray, np.ndarray]) -> None:
    """A +x light brightens the right side and a +y light the top: normals agree."""
    images, lights = collection
    normals = fit_normals(images, lights).normals
    h, w = normals.shape[:2]
    lum = images.mean(axis=3)
    right = lights[:, 0] > 0.5
    top = lights[:, 1] > 0.5
    # the image-space gradient of brightness under those lights matches the normals' sign
    nx_side = normals[:, w // 2:, 0].mean() - normals[:, : w // 2, 0].mean()
    ny_side = normals[: h // 2, :, 1].mean() - normals[h // 2:, :, 1].mean()
    assert nx_side > 0.1 and ny_side > 0.1
    lit_right = lum[right].mean(axis=0)
    lit_left = lum[lights[:, 0] < -0.5].mean(axis=0)
    lit_top = lum[top].mean(axis=0)
    lit_bottom = lum[lights[:, 1] < -0.5].mean(axis=0)
    assert np.corrcoef((lit_right - lit_left).ravel(), normals[..., 0].ravel())[0, 1] > 0.5
    assert np.corrcoef((lit_top - lit_bottom).ravel(), normals[..., 1].ravel())[0, 1] > 0.5
    assert np.median(normals[..., 2]) > 0.5
