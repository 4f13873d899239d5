"""The second pass's compiled byte paths against the numpy code they replace, bit for bit: the
8-/16-bit → float conversion of the sub-bands (:mod:`~lanterna.tiler.fit.unit_kernel` against
``stack.to_unit``), the luminance (:mod:`~lanterna.tiler.fit.luminance_kernel` against
``band @ weights``) and the quantisation of PTM/HSH planes (:mod:`~lanterna.tiler.fit.
quantise_kernel`, from a spill's 16-bit row codes, against ``ptm_quantize`` / ``hsh_quantize`` of
the codes' values and the plane gather) and of the maps stored as they are (``unit_bytes``
against numpy's round and clip)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import numpy.typing as npt
import pytest

from lanterna.tiler.fit.bands import LUMINANCE_WEIGHTS, luminance
from lanterna.tiler.fit.hsh import hsh_quantisation, hsh_quantize
from lanterna.tiler.fit.ptm import ptm_quantisation, ptm_quantize
from lanterna.tiler.fit.quantise_kernel import quantise_planes, unit_bytes
from lanterna.tiler.fit.spill_codes import decode_rows, encode_rows
from lanterna.tiler.fit.unit_kernel import to_unit_compiled
from lanterna.tiler.inputs.stack import to_unit


@pytest.mark.parametrize(("dtype", "full"), [(np.uint8, 255.0), (np.uint16, 65535.0)])
def test_compiled_to_unit_gives_the_same_floats(dtype: type, full: float) -> None:
    rng = np.random.default_rng(3)
    band = rng.integers(0, int(full) + 1, (7, 33, 3)).astype(dtype)
    band[0, :2] = [[0, 0, 0], [int(full)] * 3]  # both ends of the range
    ref = np.empty(band.shape, np.float32)
    out = np.full(band.shape, np.nan, np.float32)
    to_unit(band, full, ref)
    to_unit_compiled(band, full, out)
    assert out.dtype == np.float32
    assert np.array_equal(out.view(np.uint32), ref.view(np.uint32))
    assert out.min() == 0.0 and out.max() == 1.0


def test_compiled_to_unit_copies_floats_and_strided_input() -> None:
    band = np.linspace(0, 1, 5 * 4 * 3, dtype=np.float32).reshape(5, 4, 3)
    out = np.zeros_like(band)
    to_unit_compiled(band, None, out)
    assert np.array_equal(out, band)
    ints = np.arange(5 * 8 * 3, dtype=np.uint8).reshape(5, 8, 3)[:, ::2]  # not contiguous
    ref, got = np.empty(ints.shape, np.float32), np.empty(ints.shape, np.float32)
    to_unit(ints, 255.0, ref)
    to_unit_compiled(ints, 255.0, got)
    assert np.array_equal(got, ref)


def _coefficients(k: int, channels: tuple[int, ...], seed: int) -> np.ndarray:
    """Coefficient-major float32 values with extremes, halves and values past the range."""
    rng = np.random.default_rng(seed)
    values = rng.normal(0.0, 3.0, (k, 6, 11, *channels)).astype(np.float32)
    values[:, 0, 0] = 0.0
    values[0, 1, :4] = np.float32(0.5)
    return values


def _coded(values: npt.NDArray[np.float32]) -> tuple[tuple[npt.NDArray[np.generic], ...],
                                                     npt.NDArray[np.float32]]:
    """A spill's codes of ``values (K, rows, …)`` and rows' ranges, and the codes' values."""
    codes = encode_rows(values.reshape(values.shape[0], values.shape[1], -1))
    return codes, decode_rows(*codes).reshape(values.shape)


def test_ptm_planes_equal_numpy_quantisation_and_gather() -> None:
    codes, values = _coded(_coefficients(6, (3,), 1))
    flat = values.reshape(6, -1)
    scale, bias = ptm_quantisation(flat.min(axis=1), flat.max(axis=1) * 0.8)  # some clip at 255
    q = ptm_quantize(values, scale.reshape(-1, 1, 1, 1), bias.reshape(-1, 1, 1, 1))
    plan = np.array([[(3 * g + j, c) for j in range(3)] for c in range(3) for g in range(2)])
    planes = quantise_planes(*codes, scale, bias, plan, hsh=False, channels=3)
    assert planes.shape == (6, 66, 3)
    for p, (c, g) in enumerate((c, g) for c in range(3) for g in range(2)):
        ref = np.moveaxis(q[3 * g:3 * g + 3, :, :, c], 0, -1).reshape(-1, 3)
        assert np.array_equal(planes[p], ref)
    assert planes.max() == 255 and planes.min() == 0


def test_lrgb_planes_equal_numpy_quantisation() -> None:
    codes, values = _coded(_coefficients(6, (), 2))
    flat = values.reshape(6, -1)
    scale, bias = ptm_quantisation(flat.min(axis=1), flat.max(axis=1))
    q = ptm_quantize(values, scale.reshape(-1, 1, 1), bias.reshape(-1, 1, 1))
    plan = np.array([[(3 * g + j, 0) for j in range(3)] for g in range(2)])
    planes = quantise_planes(*codes, scale, bias, plan, hsh=False, channels=1)
    for g in range(2):
        assert np.array_equal(planes[g], np.moveaxis(q[3 * g:3 * g + 3], 0, -1).reshape(-1, 3))


def test_hsh_planes_equal_numpy_quantisation() -> None:
    codes, values = _coded(_coefficients(9, (3,), 4))
    flat = values.reshape(9, -1)
    scale, bias = hsh_quantisation(flat.min(axis=1) * 0.9, flat.max(axis=1) * 0.9)
    q = hsh_quantize(values, scale.reshape(-1, 1, 1, 1), bias.reshape(-1, 1, 1, 1))
    plan = np.array([[(t, c) for c in range(3)] for t in range(9)])
    planes = quantise_planes(*codes, scale, bias, plan, hsh=True, channels=3)
    for t in range(9):
        assert np.array_equal(planes[t], q[t].reshape(-1, 3))
    assert len(np.unique(planes)) > 200  # the test exercises the whole byte range


def _formula(band: npt.NDArray[np.float32], w: npt.NDArray[np.float32]
             ) -> npt.NDArray[np.float32]:
    out = band[..., 0] * w[0] + band[..., 1] * w[1] + band[..., 2] * w[2]
    assert out.dtype == np.float32
    return out


def test_compiled_luminance_gives_the_formulas_bits() -> None:
    """The compiled luminance of a contiguous float32 band bit for bit against
    ``(r·w0 + g·w1) + b·w2``, each product and sum rounded to float32 (numpy's elementwise
    float32 arithmetic; 8-bit levels, arbitrary floats, zeros, ones).  Not against numpy's
    ``band @ weights``: that product's rounding is its BLAS's (with fused multiply-adds on
    some CPUs, one ulp away: seen on an AMD EPYC).  Other bands go to numpy's product."""
    rng = np.random.default_rng(8)
    levels = rng.integers(0, 256, (5, 40, 3)).astype(np.float32) / np.float32(255)
    floats = rng.random((3, 1000, 3), dtype=np.float32) * np.float32(4.0)
    floats[0, :2] = [[0, 0, 0], [1, 1, 1]]
    weights = np.asarray(LUMINANCE_WEIGHTS, np.float32)
    for band in (levels, floats):
        got = luminance(band)
        assert got.dtype == np.float32 and got.shape == band.shape[:-1]
        assert np.array_equal(got.view(np.uint32), _formula(band, weights).view(np.uint32))
        assert np.abs(got - band @ weights).max() <= 1e-6  # numpy's product: an ulp or so
    strided = floats[:, ::3]  # copied, then compiled: the same rounding
    assert np.array_equal(luminance(strided).view(np.uint32),
                          _formula(strided, weights).view(np.uint32))
    assert luminance(floats.astype(np.float64)).dtype == np.float64  # numpy's, as before


@pytest.mark.parametrize("hsh", [True, False])
def test_planes_of_whole_terms_equal_the_gather_across_chunks(hsh: bool) -> None:
    """Planes that each hold one term's R, G, B (HSH's, here in a shuffled term order) take the
    run-per-term path; over several rows, with either formula, the bytes are those of the
    general gather (channels permuted: the general path) and of numpy's formula."""
    raw = np.random.default_rng(5).normal(0.0, 3.0, (5, 9, 1001, 3)).astype(np.float32)
    raw[1, 4] *= np.float32(0.01)  # a row of a much narrower range than its term's
    codes, values = _coded(raw)
    values = values.reshape(5, -1, 3)
    flat = values.reshape(5, -1)
    quant = hsh_quantisation if hsh else ptm_quantisation
    scale, bias = quant(flat.min(axis=1) * 0.9, flat.max(axis=1) * 0.9)
    order = [3, 0, 4, 1]
    plan = np.array([[(t, c) for c in range(3)] for t in order])
    planes = quantise_planes(*codes, scale, bias, plan, hsh=hsh, channels=3)
    swapped = quantise_planes(*codes, scale, bias, plan[:, ::-1], hsh=hsh,
                              channels=3)  # B, G, R: gathered
    formula = hsh_quantize if hsh else ptm_quantize
    q = formula(values, scale.reshape(-1, 1, 1), bias.reshape(-1, 1, 1))
    for g, t in enumerate(order):
        assert np.array_equal(planes[g], q[t])
        assert np.array_equal(swapped[g], q[t][:, ::-1])
    assert planes.min() == 0 and planes.max() == 255


@pytest.mark.parametrize("n", [7, 24, 40])
def test_vectorised_rank_window_equals_the_pixel_loop_bit_for_bit(n: int) -> None:
    """The chunk path (≤ 64 lights, loops over pixels innermost) against the per-pixel one on
    ties, black pixels, shadowed samples and dim pixels, for three windows."""
    from lanterna.tiler.fit import normals_kernel as nk
    from tests.python.fixtures.photos import spiral_lights

    rng = np.random.default_rng(n)
    lights = spiral_lights(n, (12.0, 80.0))
    colour = rng.random((n, 700, 3)).astype(np.float32)
    colour[:, :60] = np.round(colour[:, :60] * 4) / 4  # ties
    colour[:, 60:70] = 0.0  # black
    colour[: n // 3, 70:300] = 0.0  # shadowed samples
    colour[:, 300:320] *= np.float32(1e-4)
    lum = colour @ np.array([0.2125, 0.7154, 0.0721], np.float32)
    for lo, hi, shadow in ((n // 4, 3 * n // 4, 0.05), (0, n, 0.0), (n // 2, n // 2 + 2, 0.3)):
        out = [np.full((700, 3), np.nan, np.float32) for _ in range(4)]
        nk.fit_chunk(nk.chunk_luminance(lum, 0, 700), colour, lights, lo, hi, shadow, out[0],
                     out[1], 0, np.float32(1))
        keep = np.empty(n, np.bool_)
        for q in range(700):
            nk._pixel(lum[:, q].astype(np.float64), colour, lights, lo, hi, shadow, out[2],
                      out[3], q, keep, np.float32(1))
        assert np.array_equal(out[0], out[2]) and np.array_equal(out[1], out[3])
        assert np.isfinite(out[0]).all() and len(np.unique(out[0][:, 2])) > 100


@pytest.mark.parametrize(("n", "dtype"), [(24, np.uint8), (24, np.float32), (7, np.uint16),
                                          (70, np.uint8)])
def test_rank_window_takes_the_luminance_in_the_kernel_bit_for_bit(n: int, dtype: type) -> None:
    """``lum`` None: the kernels take each chunk's luminance from the colour samples, and give
    the bits of a fit of the band's stored luminance (:func:`luminance`), with its report, for
    8-/16-bit and float bands, a width not a multiple of the chunk, and past the counted ranks
    (> 64 lights, each pixel sorted)."""
    from lanterna.tiler.fit import normals_kernel as nk
    from lanterna.tiler.fit.bands import _WEIGHTS32
    from lanterna.tiler.fit.normals import RANK_WINDOW, SHADOW_FRACTION, rank_bounds
    from lanterna.tiler.fit.normals_held_out_kernel import rank_window_normals_held_out
    from tests.python.fixtures.photos import spiral_lights

    rng = np.random.default_rng(n)
    lights = spiral_lights(n, (12.0, 80.0))
    top = 1.0 if dtype == np.float32 else float(np.iinfo(dtype).max)
    div = 1.0 if dtype == np.float32 else top
    values = rng.random((n, 1037, 3)) * top
    values[:, :90] = np.round(values[:, :90] / top * 3) * top / 3  # ties
    values[: n // 3, 90:400] = 0.0  # shadowed samples
    colour = (values if dtype == np.float32 else np.rint(values)).astype(dtype)
    lum = luminance(colour, div)
    lo, hi = rank_bounds(RANK_WINDOW, n)
    stored = nk.rank_window_normals(lum, colour, lights, lo, hi, SHADOW_FRACTION, div)
    taken = nk.rank_window_normals(None, colour, lights, lo, hi, SHADOW_FRACTION, div,
                                   _WEIGHTS32)
    for a, b in zip(stored, taken, strict=True):
        assert np.array_equal(a.view(np.uint32), b.view(np.uint32))
    assert len(np.unique(taken[0][:, 2])) > 500
    if n <= 64:
        train, held = np.arange(n)[np.arange(n) % 4 > 0], np.arange(n)[::4]
        args = (lights, (lo, hi), SHADOW_FRACTION, train, held,
                rank_bounds(RANK_WINDOW, len(train)), div)
        with_lum = rank_window_normals_held_out(lum, colour, *args)
        without = rank_window_normals_held_out(None, colour, *args, _WEIGHTS32)
        for a, b in zip(with_lum, without, strict=True):
            assert np.array_equal(a, b)
        assert with_lum[2].min() > 0
    with pytest.raises(ValueError, match="luminance is taken"):
        nk.rank_window_normals(None, colour.astype(np.float64), lights, lo, hi, 0.0, 1.0,
                               _WEIGHTS32)


@pytest.mark.parametrize("depth", [8, 16])
def test_pca_sample_from_disk_equals_the_sample_of_the_loaded_stack(tmp_path: Path,
                                                                   depth: int) -> None:
    """The sampling pass converts only the chosen pixels of the decoded bands: the same floats
    as the sample of the whole stack loaded in memory, at any band height."""
    from lanterna.tiler.fit.pca_sample import sample_pixels
    from lanterna.tiler.inputs.lp import read_lp
    from lanterna.tiler.inputs.stack import StackReader, load_stack
    from tests.python.fixtures.photos import spiral_lights, write_collection

    rng = np.random.default_rng(depth)
    lights = spiral_lights(9)
    lp = write_collection(tmp_path / "photos", rng.random((9, 23, 31, 3)).astype(np.float32),
                          lights, depth=depth)
    files, _ = read_lp(lp, lp.parent)
    ref = sample_pixels(load_stack(files), 23, cap=200)
    for rows in (1, 5, 23):
        got = sample_pixels(StackReader(files), rows, cap=200)
        assert got.shape == (200, 9, 3)
        assert np.array_equal(got, ref)
    assert len(np.unique(ref)) > 100


@pytest.mark.parametrize("n", [24, 70])
def test_normals_without_their_albedo_are_the_same_bits(n: int, tmp_path: Path) -> None:
    """A Ward fit needs the normals alone (it fits its own kd): ``albedo=False`` skips the
    albedo's sums in the rank window (counted ranks and, past 64 lights, sorted) and leaves
    every normal's bits as they were; a Ward fit's normals are a normals fit's."""
    from lanterna.tiler.fit import normals_kernel as nk
    from lanterna.tiler.fit.bands import _WEIGHTS32, normals_band
    from lanterna.tiler.fit.engine import fit_stream
    from lanterna.tiler.fit.normals import RANK_WINDOW, SHADOW_FRACTION, rank_bounds
    from tests.python.fixtures.photos import spiral_lights

    rng = np.random.default_rng(n)
    lights = spiral_lights(n, (12.0, 80.0))
    colour = np.rint(rng.random((n, 777, 3)) * 255).astype(np.uint8)
    lo, hi = rank_bounds(RANK_WINDOW, n)
    both = nk.rank_window_normals(None, colour, lights, lo, hi, SHADOW_FRACTION, 255.0,
                                  _WEIGHTS32)
    alone = nk.rank_window_normals(None, colour, lights, lo, hi, SHADOW_FRACTION, 255.0,
                                   _WEIGHTS32, albedo=False)
    assert np.array_equal(both[0].view(np.uint32), alone[0].view(np.uint32))
    assert alone[1].shape == (0, 3) and both[1].shape == (777, 3) and both[1].max() > 0.1
    band = colour.reshape(n, 21, 37, 3)
    assert set(normals_band(band, lights, div=255.0, albedo=False)) == {"normals"}
    if n <= 64:
        (tmp_path / "w").mkdir()
        (tmp_path / "n").mkdir()
        ward = fit_stream(band, lights, ["ward"], tmp_path / "w").layers["ward"].channels()
        normals = fit_stream(band, lights, ["normals"], tmp_path / "n").layers["normals"]
        assert all(np.array_equal(ward[f"N{c}"], normals.channels()[f"N{c}"]) for c in "XYZ")
        assert len(np.unique(ward["NX"])) > 20  # 8-bit normals, not all alike


@pytest.mark.parametrize("dtype", [np.float32, np.float64])
@pytest.mark.parametrize("limits", [(0.0, 1.0), (0.03, 0.6)])
def test_unit_bytes_equal_numpys_round_and_clip(dtype: type, limits: tuple[float, float]
                                                ) -> None:
    """The albedo's and Ward's maps: ``clip(round((v − lo)/(hi − lo)·255), 0, 255)`` in
    float64 (numpy's formula before), byte for byte, ties to even, out-of-range values clipped,
    any shape."""
    lo, hi = limits
    rng = np.random.default_rng(11)
    ties = lo + (np.arange(256) + 0.5) / 255 * (hi - lo)  # halfway between two levels
    values = np.concatenate([rng.uniform(lo - 0.3, hi + 0.3, 5000), ties,
                             lo + np.arange(256) / 255 * (hi - lo),
                             [np.inf, -np.inf, 0.0, -0.0, lo, hi]]).astype(dtype)
    ref = np.clip(np.round((values.astype(np.float64) - lo) / (hi - lo) * 255.0), 0,
                  255).astype(np.uint8)
    out = unit_bytes(values.reshape(-1, 2) if values.size % 2 == 0 else values, lo, hi)
    assert out.dtype == np.uint8
    assert np.array_equal(out.reshape(-1), ref)
    assert out.min() == 0 and out.max() == 255
