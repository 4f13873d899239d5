"""Plane tile formats (by hand, not a test): bytes and error of each format against the source.

For each source — the real JPEG_LRGB PTM ``ushabti.ptm`` and the HSH ``vase.rti`` of
``../shared/realdata/chi-ushabti-vase/`` (skipped with a message when absent) and the demo's
fitted 8-bit PTM (a lossless source) — every plane group is tiled in each format
(``--plane-format`` values, and WebP near-lossless levels, which ``auto`` may choose), and the
script reports: the plane bytes of level 0, of every level's tiles (what a viewer fetches) and
of the whole tree (also ``full/max`` and the ``sizes`` files; hard links counted once), the RMS
and max error of the level-0 tiles' decode against the reader's decode (the 8-bit values tiled),
and the ratio of the level-0 and all-tile bytes to the source file's. ``auto`` also shows what
it chose per group. Results in docs/dataset-format.md ("Tile formats").

Run::

    .venv/bin/python bench/plane_formats.py [--json bench/results-plane-formats.json]
"""

from __future__ import annotations

import argparse
import json
import os
import sys
import tempfile
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np
import pyvips

from lanterna.tiler.dataset.layers import add_planes_layer
from lanterna.tiler.dataset.plane_format import AUTO, PlaneFormat
from lanterna.tiler.dataset.writer import DatasetWriter
from lanterna.tiler.formats.hsh import read_rti
from lanterna.tiler.formats.layouts import hsh_plane_layer, hsh_plane_quantisation, ptm_plane_layer
from lanterna.tiler.formats.planes import PlaneData, PlaneLayer
from lanterna.tiler.formats.ptm import read_ptm
from lanterna.tiler.formats.ptm_model import Ptm
from lanterna.tiler.iiif import geometry as geo
from lanterna.tiler.iiif.encoding import TileFormat

REAL = Path(__file__).resolve().parent.parent.parent / "shared" / "realdata" / "chi-ushabti-vase"
FORMATS: dict[str, PlaneFormat] = {
    "auto": AUTO,
    "png": PlaneFormat(TileFormat("png")),
    "webp": PlaneFormat(TileFormat("webp")),
    "webp:near80": PlaneFormat(TileFormat("webp", 80)),
    "webp:near60": PlaneFormat(TileFormat("webp", 60)),
    "jpg:90": PlaneFormat(TileFormat("jpg", 90)),
    "jpg:95": PlaneFormat(TileFormat("jpg", 95)),
    "jpg:100": PlaneFormat(TileFormat("jpg", 100)),
}


def ptm_layer(ptm: Ptm) -> PlaneLayer:
    def coefficients(c: int | None, k: slice) -> PlaneData:
        return ptm.coefficients[..., k] if c is None else ptm.coefficients[:, :, c, k]
    return ptm_plane_layer(ptm.colorspace, ptm.scale, ptm.bias, coefficients, ptm.rgb,
                           lossy=ptm.lossy)


def hsh_layer(path: Path) -> PlaneLayer:
    hsh = read_rti(path)
    scales, biases = hsh_plane_quantisation(hsh)
    return hsh_plane_layer(scales, biases, lambda k: hsh.coefficients[:, :, :, k])


def sources() -> list[tuple[str, int, Callable[[], PlaneLayer]]]:
    out: list[tuple[str, int, Callable[[], PlaneLayer]]] = []
    for name, make in (("ushabti.ptm", lambda: ptm_layer(read_ptm(REAL / "ushabti.ptm"))),
                       ("vase.rti", lambda: hsh_layer(REAL / "vase.rti"))):
        if (REAL / name).is_file():
            out.append((name, (REAL / name).stat().st_size, make))
        else:
            print(f"skipped {name}: not found in {REAL}", file=sys.stderr)

    def demo() -> PlaneLayer:
        from lanterna.tiler.demo.dome import make_demo_ptm
        return ptm_layer(make_demo_ptm(512, 384))
    out.append(("demo fitted PTM 512x384 (lossless)", 0, demo))
    return out


def tree_bytes(folder: Path) -> int:
    seen: set[tuple[int, int]] = set()
    total = 0
    for root, _dirs, files in os.walk(folder):
        for f in files:
            st = os.stat(os.path.join(root, f))
            if (st.st_dev, st.st_ino) not in seen:
                seen.add((st.st_dev, st.st_ino))
                total += st.st_size
    return total


def tile_bytes(folder: Path, w: int, h: int, ext: str) -> int:
    """The bytes of every level's tiles (the spec's grid: what a viewer fetches)."""
    files = {folder / geo.canonical_path(w, h, t) / "0" / f"default.{ext}"
             for f in geo.scale_factors(w, h, 256) for t in geo.spec_tiles(w, h, 256, f)}
    return sum(f.stat().st_size for f in files)


def measure(layer: PlaneLayer, spec: PlaneFormat, work: Path) -> dict[str, Any]:
    out = work / "ds"
    t0 = time.perf_counter()
    with DatasetWriter(out, name="ds", label="bench", width=layer.width,
                       height=layer.height) as ds:
        add_planes_layer(ds, layer, layer_id="x", label="x", plane_format=spec)
        chosen = [ds.images[f"x_{n}"] for n in layer.group_names]
    seconds = time.perf_counter() - t0
    level0 = whole = tiles = 0
    sq, count, top = 0.0, 0, 0
    w, h = layer.width, layer.height
    for name, group in zip(layer.group_names, layer.groups, strict=True):
        folder = out / "iiif" / f"x_{name}"
        ext = json.loads((folder / "info.json").read_text()).get("preferredFormats", ["jpg"])[0]
        whole += tree_bytes(folder)
        tiles += tile_bytes(folder, w, h, ext)
        src = np.asarray(group.data)
        for t in geo.spec_tiles(w, h, 256, 1):
            tile = folder / geo.canonical_path(w, h, t) / "0" / f"default.{ext}"
            level0 += tile.stat().st_size
            got = pyvips.Image.new_from_file(str(tile)).numpy()
            want = src[t.y:t.y + t.h, t.x:t.x + t.w]
            got = got[..., 0] if want.ndim == 2 and got.ndim == 3 else got
            err = got.astype(np.int16) - want
            sq += float(np.square(err, dtype=np.float64).sum())
            count += err.size
            top = max(top, int(np.abs(err).max()))
    labels = [TileFormat(c["format"], c.get("quality")).label() for c in chosen]
    return {"level0": level0, "tiles": tiles, "whole": whole, "rms": (sq / count) ** 0.5,
            "max": top, "chosen": labels, "seconds": seconds}


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--json", type=Path, help="write the results here too")
    args = parser.parse_args()
    results = []
    for name, size, make in sources():
        layer = make()
        print(f"\n{name}: {layer.width}x{layer.height}, {len(layer.groups)} plane groups, "
              f"source {size:,} bytes")
        print(f"{'format':12s} {'level 0':>11s} {'all tiles':>11s} {'tree':>11s} "
              f"{'x src L0':>8s} {'x src all':>9s} {'rms':>6s} {'max':>4s} {'s':>6s}  chosen")
        for label, spec in FORMATS.items():
            with tempfile.TemporaryDirectory(prefix="lt-planes-") as work:
                r = measure(layer, spec, Path(work))
            ratio0 = f"{r['level0'] / size:8.2f}" if size else f"{'-':>8s}"
            ratio = f"{r['tiles'] / size:9.2f}" if size else f"{'-':>9s}"
            print(f"{label:12s} {r['level0']:11,d} {r['tiles']:11,d} {r['whole']:11,d} "
                  f"{ratio0} {ratio} "
                  f"{r['rms']:6.3f} {r['max']:4d} {r['seconds']:6.2f}  "
                  f"{', '.join(r['chosen']) if label == 'auto' else ''}")
            results.append({"source": name, "sourceBytes": size, "format": label, **r})
    if args.json:
        args.json.write_text(json.dumps(results, indent=1) + "\n")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
