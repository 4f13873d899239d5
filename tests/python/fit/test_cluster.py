"""The streamed fit on a Dask cluster (dask.distributed.LocalCluster): the same dataset."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from lanterna.errors import LanternaInputError
from lanterna.tiler.fit import held_out
from lanterna.tiler.fit.run import fit_collection
from tests.python.fixtures.photos import BAND, tall_lights, write_tall_stack
from tests.python.fixtures.stored import stored_format, stored_plane

pytest.importorskip("dask.distributed", reason="needs dask[distributed] (the dev extras)")


def _planes(ds: Path) -> dict[str, bytes]:
    """Every lossless image's pixels (the planes; previews are JPEG)."""
    out = {}
    for info in sorted((ds / "iiif").glob("*/info.json")):
        name = info.parent.name
        if stored_format(ds, name) in ("png", "webp"):
            out[name] = stored_plane(ds, name).tobytes()
    return out


def test_local_cluster_gives_the_local_result(tmp_path: Path,
                                              monkeypatch: pytest.MonkeyPatch) -> None:
    """Also the photometric reports' pixel sample (each band's rows known on the worker)."""
    monkeypatch.setattr(held_out, "REPORT_PIXELS", 10_000)
    lights = tall_lights()
    files = write_tall_stack(tmp_path / "shots", lights)
    lp = tmp_path / "shots" / "lights.lp"
    lp.write_text(f"{len(files)}\n" + "".join(
        f"{f.name} {x:.9f} {y:.9f} {z:.9f}\n" for f, (x, y, z) in zip(files, lights, strict=True)))
    models = ["ptm", "hsh", "normals", "ward"]
    local = fit_collection(tmp_path / "shots", lp, models, tmp_path / "local", band_rows=BAND)
    cluster = fit_collection(tmp_path / "shots", lp, models, tmp_path / "dask", band_rows=BAND,
                             scheduler="local:2")
    assert cluster == local  # the leave-one-out report, to the last digit
    assert 5_000 < local["models"]["ward"]["pixels"] < 15_000
    a, b = _planes(tmp_path / "local"), _planes(tmp_path / "dask")
    # PTM RGB 6, HSH9 9, normals + kd 2, Ward kd/ks/gloss 3 (its normal map is shared)
    assert len(a) == 6 + 9 + 2 + 3
    assert set(a) == set(b) and all(a[k] == b[k] for k in a), [k for k in a if a[k] != b[k]]
    desc = [json.dumps(json.loads((tmp_path / d / "lanterna.json").read_text())["layers"])
            for d in ("local", "dask")]
    assert desc[0] == desc[1].replace("/datasets/dask/", "/datasets/local/")


def test_unreachable_scheduler_is_a_clear_error(tmp_path: Path) -> None:
    lights = tall_lights(12)
    files = write_tall_stack(tmp_path / "shots", lights)
    lp = tmp_path / "shots" / "lights.lp"
    lp.write_text(f"{len(files)}\n" + "".join(
        f"{f.name} {x} {y} {z}\n" for f, (x, y, z) in zip(files, lights, strict=True)))
    with pytest.raises(LanternaInputError, match="cannot reach the Dask scheduler"):
        fit_collection(tmp_path / "shots", lp, ["ptm"], tmp_path / "ds",
                       scheduler="tcp://127.0.0.1:9")
    assert not (tmp_path / "ds").exists()
    assert np.all([f.is_file() for f in files])
