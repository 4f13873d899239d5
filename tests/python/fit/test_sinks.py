"""The fit's spill (:class:`~lanterna.tiler.fit.sinks.Spill`): bands back in order as their
row codes, the same from memory and from its scratch file, which it removes."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from lanterna.tiler.fit.sinks import Spill
from lanterna.tiler.fit.spill_codes import encode_rows


def _bands() -> list[np.ndarray]:
    rng = np.random.default_rng(6)
    return [rng.normal(0, 2, (rows, 9, 3, 4)).astype(np.float32) for rows in (3, 5, 2)]


def _spill(path: Path, budget: int) -> tuple[Spill, list[tuple[np.ndarray, ...]]]:
    spill = Spill(path, 10, [budget])
    for band in _bands():
        spill.append(band)
    return spill, [tuple(np.array(a) for a in part) for part in spill.bands()]


def test_memory_and_scratch_file_give_the_same_codes(tmp_path: Path) -> None:
    held, from_memory = _spill(tmp_path / "a.u16", 1 << 20)
    spilled, from_file = _spill(tmp_path / "b.u16", 0)  # no budget: written to disk
    assert held.file is None and spilled.file is not None
    assert not (tmp_path / "a.u16").exists() and not (tmp_path / "b.u16").exists()
    assert len(from_memory) == len(from_file) == 3
    for band, mine, theirs in zip(_bands(), from_memory, from_file, strict=True):
        km = np.moveaxis(band, -1, 0).reshape(4, band.shape[0], -1)
        ref = encode_rows(km)
        for a, b, r in zip(mine, theirs, ref, strict=True):
            assert np.array_equal(a, b) and np.array_equal(a, r)
    every = np.concatenate([np.moveaxis(b, -1, 0).reshape(4, -1) for b in _bands()], axis=1)
    assert held.lo is not None and held.hi is not None
    assert np.array_equal(held.lo, every.min(axis=1)) and np.array_equal(held.hi, every.max(axis=1))


def test_memory_spill_frees_each_band_once_yielded(tmp_path: Path) -> None:
    spill = Spill(tmp_path / "c.u16", 10, [1 << 20])
    for band in _bands():
        spill.append(band)
    assert spill.held is not None
    it = spill.bands()
    next(it)
    assert spill.held[0].size == 0 and spill.held[1].size > 0
