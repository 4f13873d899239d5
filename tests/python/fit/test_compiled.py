"""The compiled kernels' shared settings: the vector width they are built for changes no result."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import numpy.typing as npt
from llvmlite import binding as llvm

from lanterna.tiler.fit import compiled
from lanterna.tiler.fit.bands import luminance
from lanterna.tiler.fit.normals import solve_normals_band
from lanterna.tiler.fit.ward import fit_ward
from tests.python.fixtures.glossy import N, glossy_scene

REPO = Path(__file__).resolve().parents[3]

_FIT = """
import sys
import numpy as np
from tests.python.fit.test_compiled import kernel_outputs
np.savez(sys.argv[1], *kernel_outputs())
"""


def kernel_outputs() -> list[npt.NDArray[np.generic]]:
    """Normals, albedo, kd, ks and α of the glossy scene from the normals and Ward kernels."""
    img, lights, normals = glossy_scene()
    lum = luminance(img).reshape(N, -1)
    return [*solve_normals_band(lum, img.reshape(N, -1, 3), lights, iterations=0),
            *fit_ward(img, lights, normals, band_rows=7)]


def test_wide_vectors_only_on_avx512() -> None:
    assert compiled._wide_vectors("+sse2,+avx2,+fma") is None
    assert compiled._wide_vectors("+sse2,-avx512f,+avx2") is None
    assert compiled._wide_vectors("+avx2,+avx512f") == "+avx2,+avx512f,-prefer-256-bit"


def test_the_vector_width_changes_no_result(tmp_path: Path) -> None:
    """The normals and Ward kernels built for LLVM's default (256-bit) vectors, in a fresh
    process and cache, give the bits this process's build gives."""
    here = kernel_outputs()
    env = {**os.environ, "NUMBA_CPU_FEATURES": llvm.get_host_cpu_features().flatten(),
           "NUMBA_CACHE_DIR": str(tmp_path / "cache"), "PYTHONPATH": str(REPO)}
    out = tmp_path / "narrow.npz"
    subprocess.run([sys.executable, "-c", _FIT, str(out)], check=True, env=env, cwd=REPO)
    with np.load(out) as narrow:
        there = [narrow[f"arr_{i}"] for i in range(len(here))]
    for a, b in zip(here, there, strict=True):
        assert a.dtype == b.dtype and np.array_equal(a, b)
    assert here[3].max() > 0.05  # the Ward fit found highlights
