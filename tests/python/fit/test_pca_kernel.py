"""The PCA step's compiled passes (:mod:`~lanterna.tiler.fit.pca_kernel`) against the numpy steps
they replace, bit for bit: the light-major floats of a band as decoded, and the padded 8-bit
planes of a basis's coefficients."""

from __future__ import annotations

import numpy as np
import pytest

from lanterna.tiler.fit import pca_basis
from lanterna.tiler.fit.pca import PcaSpec
from lanterna.tiler.fit.pca_basis import fit_basis
from lanterna.tiler.fit.pca_kernel import light_major, quantise_planes
from tests.python.fixtures.photos import spiral_lights


@pytest.mark.parametrize(("dtype", "div"), [(np.uint8, 255.0), (np.uint16, 65535.0)])
def test_light_major_of_samples_as_decoded_is_the_float_band_swapped(dtype: type,
                                                                      div: float) -> None:
    rng = np.random.default_rng(4)
    band = rng.integers(0, int(div) + 1, (9, 5003, 3)).astype(dtype)
    band[:, 0] = [0, int(div), 1]
    floats = band.astype(np.float32) / np.float32(div)  # the engine's float band
    ref = pca_basis.light_major(floats)
    for got in (light_major(band, div), light_major(floats, 1.0)):
        assert got.shape == (27, 5003)
        assert np.array_equal(got.view(np.uint32), ref.view(np.uint32))
    # a run of pixels, into a reused buffer
    buffer = np.full((27, 1000), np.nan, np.float32)
    part = light_major(band, div, slice(2000, 3000), buffer)
    assert part is buffer and np.array_equal(part, ref[:, 2000:3000])


def test_quantised_planes_are_the_numpy_bytes_padded() -> None:
    rng = np.random.default_rng(6)
    lights = spiral_lights(30, (15.0, 80.0))
    sample = rng.uniform(0.0, 1.0, (400, 30, 3)).astype(np.float32)
    fit = fit_basis(sample, lights, PcaSpec("rbf", "mrgb", 8))  # 8 planes: 3 groups, 1 spare
    x = pca_basis.light_major(rng.uniform(0.0, 1.0, (30, 3001, 3)).astype(np.float32))
    coefficients = fit.coefficients(x)
    coefficients[:, :5] *= 40.0  # far past the range: clipped to 0 and 255
    ref = fit.quantise(coefficients)  # (P, 8)
    out = np.full((3, 3001 + 10, 3), 7, np.uint8)  # 3 groups, 10 pixels before this run
    lo, gain = fit.quantisation()
    quantise_planes(coefficients, lo, gain, out, 10)
    got = np.moveaxis(out[:, 10:], 0, 1).reshape(3001, 9)  # pixel-major, as numpy's
    assert np.array_equal(got[:, :8], ref)
    assert np.all(got[:, 8] == 0) and np.all(out[:, :10] == 7)  # nothing before the run
    assert {0, 255} <= set(np.unique(got[:5, :8]))
