"""A band's pieces for the solvers (:mod:`lanterna.tiler.fit.sub_bands`)."""

from __future__ import annotations

import numpy as np

from lanterna.tiler.fit.sub_bands import SubBands
from lanterna.tiler.inputs.stack import to_unit


def test_float_pieces_are_the_band_in_0_1_and_decoded_pieces_its_rows() -> None:
    rng = np.random.default_rng(2)
    band = rng.integers(0, 256, (5, 11, 7, 3)).astype(np.uint8)
    ref = np.empty(band.shape, np.float32)
    to_unit(band, 255.0, ref)
    buffers = SubBands()
    floats = [(r0, piece.copy()) for r0, piece in buffers.floats(band, 255.0, 4)]
    assert [r0 for r0, _ in floats] == [0, 4, 8]
    assert np.array_equal(np.concatenate([p for _, p in floats], axis=1), ref)
    decoded = [(r0, piece.copy(), d) for r0, piece, d in buffers.as_decoded(band, 255.0, 4)]
    assert [r0 for r0, _, _ in decoded] == [0, 4, 8] and {d for *_, d in decoded} == {255.0}
    assert np.array_equal(np.concatenate([p for _, p, _ in decoded], axis=1), band)
    assert all(p.flags.c_contiguous and p.dtype == np.uint8 for _, p, _ in decoded)
    whole = list(buffers.as_decoded(band, 255.0, 11))
    assert len(whole) == 1 and whole[0][1] is band  # one contiguous piece: no copy
