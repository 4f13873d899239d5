"""Tiler benchmark (by hand, not a test): ``write_pyramid`` against bare ``dzsave --layout iiif3``.

Two measurements, each tiling run in its own child process (so its peak memory is its own, read
with ``os.wait4``):

``throughput``
    One procedural image (default 8192×8192, saved first as a tiled JPEG TIFF on disk) tiled by
    :func:`lanterna.tiler.iiif.pyramid.write_pyramid` (dzsave plus the level-0 completeness fixes)
    and by bare ``dzsave`` with the same arguments (same libvips, through pyvips; optionally also
    the Debian ``vips`` command line), interleaved, ``--rounds`` rounds, per format; medians.
``memory``
    The peak resident memory (max RSS) of tiling a 1-gigapixel image (32768×32768) with
    ``write_pyramid``, and of bare dzsave for comparison.

Diagnostic modes: ``--no-full-max`` also times ``write_pyramid`` with its ``full/max`` encode
stubbed out (to see what that costs), ``--before FILE`` also times another ``pyramid.py`` (an
older commit's, to compare), ``--cli`` also times Debian's ``vips dzsave`` command (a
different libvips version, reading the file itself).

Run::

    .venv/bin/python bench/tiler.py throughput --work /var/tmp/lt --json bench/results-tiler.json
    .venv/bin/python bench/tiler.py memory --work /var/tmp/lt --json bench/results-tiler-1gpx.json

The work folder is removed afterwards unless ``--keep``.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import shutil
import statistics
import subprocess
import sys
import time
from pathlib import Path
from typing import Any

import pyvips

JPEG_QUALITY = 90  # what write_pyramid uses
SERVICE_ID = "http://bench.invalid/img"


def make_source(path: Path, size: int) -> float:
    """Write a ``size``² procedural RGB image (smooth pattern plus noise) as a tiled JPEG TIFF.

    Returns the seconds taken. The pattern gives tiles JPEG sizes like a photographed object's
    rather than flat colour or pure noise.
    """
    t0 = time.perf_counter()
    xyz = pyvips.Image.xyz(size, size)
    x, y = xyz[0], xyz[1]
    r = (x * 0.37).sin() * 60 + (y * 0.21).cos() * 50 + 128
    g = ((x + y) * 0.11).sin() * 90 + 128
    b = ((x - y) * 0.05).cos() * 70 + (x * 0.9).sin() * 20 + 120
    noise = pyvips.Image.gaussnoise(size, size, sigma=10, mean=0)
    img = (r.bandjoin([g, b]) + noise).cast("uchar").copy(interpretation="srgb")
    img.tiffsave(str(path), tile=True, tile_width=256, tile_height=256, compression="jpeg",
                 Q=92, bigtiff=True)
    return time.perf_counter() - t0


def _child(mode: str, src: Path, out: Path, fmt: str, tile_size: int, source: str) -> None:
    """Tile ``src`` into ``out`` one way and print the seconds it took as JSON.

    ``source`` ``memory``: the image is decoded into memory first, untimed (planes reach the
    tiler as arrays); ``file``: tiled straight from the file.
    """
    image = pyvips.Image.new_from_file(str(src))
    if source == "memory":
        image = image.copy_memory()
    t0 = time.perf_counter()
    if mode in ("pyramid", "pyramid-no-full-max"):
        from lanterna.tiler.iiif import pyramid

        if mode == "pyramid-no-full-max":  # what the level-0 full/max encode costs
            pyramid._FullMax.run = lambda self: None
            pyramid._FullMax.move_into = lambda self, out_dir: None
        pyramid.write_pyramid(image, out, SERVICE_ID, fmt=fmt, tile_size=tile_size)
    elif mode == "pyramid-before":  # another write_pyramid, e.g. an older commit's file
        import importlib.util

        spec = importlib.util.spec_from_file_location("lanterna.tiler._pyramid_before",
                                                      os.environ["LANTERNA_BENCH_BEFORE"])
        assert spec is not None and spec.loader is not None
        before = importlib.util.module_from_spec(spec)
        spec.loader.exec_module(before)
        before.write_pyramid(image, out, SERVICE_ID, fmt=fmt, tile_size=tile_size)
    elif mode == "dzsave":
        save: dict[str, Any] = {"layout": "iiif3", "tile_size": tile_size, "overlap": 0}
        if fmt == "png":
            save["suffix"] = ".png[compression=3]"
        else:
            save["Q"] = JPEG_QUALITY
        image.dzsave(str(out), id=SERVICE_ID, **save)
    elif mode == "vips-cli":
        suffix = ".png[compression=3]" if fmt == "png" else f".jpg[Q={JPEG_QUALITY}]"
        subprocess.run(["vips", "dzsave", str(src), str(out), "--layout", "iiif3",
                        "--tile-size", str(tile_size), "--overlap", "0", "--suffix", suffix,
                        "--id", SERVICE_ID], check=True)
    else:
        raise ValueError(mode)
    print(json.dumps({"seconds": time.perf_counter() - t0}))


def run_one(mode: str, src: Path, out: Path, fmt: str, tile_size: int,
            source: str) -> dict[str, Any]:
    """Run one tiling child; return its time, CPU, peak RSS and output size, then delete it."""
    shutil.rmtree(out, ignore_errors=True)
    t0 = time.perf_counter()
    proc = subprocess.Popen([sys.executable, __file__, "_child", mode, str(src), str(out), fmt,
                             str(tile_size), source], stdout=subprocess.PIPE, text=True)
    assert proc.stdout is not None
    stdout = proc.stdout.read()
    _, status, usage = os.wait4(proc.pid, 0)
    proc.returncode = os.waitstatus_to_exitcode(status)
    wall = time.perf_counter() - t0
    if proc.returncode != 0:
        raise RuntimeError(f"{mode} failed with status {proc.returncode}")
    files = [p for p in out.rglob("*") if p.is_file()]
    result = {
        "mode": mode, "fmt": fmt, "source": source,
        "seconds": json.loads(stdout.splitlines()[-1])["seconds"],
        "wall_seconds": wall, "cpu_seconds": usage.ru_utime + usage.ru_stime,
        # includes the decoded source when it is held in memory (same for both modes); for
        # vips-cli it would be the python parent's, so it is left out
        "max_rss_mb": usage.ru_maxrss / 1024,
        "files": len(files), "bytes": sum(p.stat().st_size for p in files),
    }
    if mode == "vips-cli":
        result["max_rss_mb"] = None
    shutil.rmtree(out, ignore_errors=True)
    print(f"  {mode:9} {fmt}: {result['seconds']:7.2f} s, cpu {result['cpu_seconds']:7.2f} s, "
          f"rss {result['max_rss_mb'] or 0:7.0f} MB, {len(files)} files", flush=True)
    return result


def machine() -> dict[str, Any]:
    """Facts about this machine and the libraries used."""
    cpu = next((line.split(":", 1)[1].strip() for line in
                Path("/proc/cpuinfo").read_text().splitlines() if line.startswith("model name")),
               platform.processor())
    mem_kb = int(Path("/proc/meminfo").read_text().split()[1])
    cli = shutil.which("vips")
    cli_version = (subprocess.run([cli, "--version"], capture_output=True, text=True).stdout
                   .strip() if cli else None)
    return {"cpu": cpu, "vcpus": os.cpu_count(), "mem_gib": round(mem_kb / 2**20, 1),
            "os": platform.platform(), "python": platform.python_version(),
            "libvips (pyvips)": ".".join(str(pyvips.version(i)) for i in range(3)),
            "vips cli": cli_version, "date": time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime())}


def throughput(args: argparse.Namespace) -> dict[str, Any]:
    """Interleaved rounds of write_pyramid vs bare dzsave (and the CLI) per format; medians."""
    src = args.work / f"src-{args.size}.tif"
    made = make_source(src, args.size)
    print(f"source {args.size}² written in {made:.1f} s ({src.stat().st_size / 1e6:.0f} MB)")
    modes = ["pyramid", "dzsave"] + (["pyramid-no-full-max"] if args.no_full_max else []) + (
        ["pyramid-before"] if args.before else []) + (
        ["vips-cli"] if args.cli and shutil.which("vips") else [])
    if args.before:
        os.environ["LANTERNA_BENCH_BEFORE"] = str(args.before.resolve())
    runs: list[dict[str, Any]] = []
    for fmt in args.fmt.split(","):
        for rnd in range(args.rounds):
            order = modes[rnd % len(modes):] + modes[:rnd % len(modes)]
            for mode in order:
                runs.append({"round": rnd, **run_one(mode, src, args.work / "out", fmt,
                                                     args.tile_size, args.source)})
    summary: dict[str, Any] = {}
    for fmt in args.fmt.split(","):
        med = {m: statistics.median(r["seconds"] for r in runs if r["mode"] == m
                                    and r["fmt"] == fmt) for m in modes}
        mpx = args.size * args.size / 1e6
        summary[fmt] = {m: {"median_seconds": s, "mpx_per_s": mpx / s} for m, s in med.items()}
        summary[fmt]["pyramid_vs_dzsave"] = med["dzsave"] / med["pyramid"]
        # throughput relative to bare dzsave (time of dzsave / time of the mode), every mode
        summary[fmt]["vs_dzsave"] = {m: med["dzsave"] / s for m, s in med.items()}
        for m in modes:
            summary[fmt][m]["median_max_rss_mb"] = statistics.median(
                r["max_rss_mb"] or 0 for r in runs if r["mode"] == m and r["fmt"] == fmt)
            summary[fmt][m]["files"] = next(r["files"] for r in runs
                                            if r["mode"] == m and r["fmt"] == fmt)
        print(f"{fmt}: throughput / dzsave's: " + ", ".join(
            f"{m} {r:.3f}" for m, r in summary[fmt]["vs_dzsave"].items()))
    return {"size": args.size, "tile_size": args.tile_size, "rounds": args.rounds,
            "source": args.source,
            "source_seconds": made, "summary": summary, "runs": runs}


def memory(args: argparse.Namespace) -> dict[str, Any]:
    """Peak RSS of write_pyramid (and bare dzsave) tiling a ``--size``² image."""
    src = args.work / f"src-{args.size}.tif"
    made = make_source(src, args.size)
    print(f"source {args.size}² written in {made:.1f} s ({src.stat().st_size / 1e9:.2f} GB)")
    runs = [run_one(mode, src, args.work / "out", "jpg", args.tile_size, "file")
            for mode in ("pyramid", "dzsave")]
    return {"size": args.size, "tile_size": args.tile_size, "source_seconds": made,
            "source_bytes": src.stat().st_size, "runs": runs}


def main() -> None:
    if len(sys.argv) > 1 and sys.argv[1] == "_child":
        mode, src, out, fmt, tile, source = sys.argv[2:8]
        _child(mode, Path(src), Path(out), fmt, int(tile), source)
        return
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("what", choices=["throughput", "memory"])
    p.add_argument("--work", type=Path, default=Path("/var/tmp/lanterna-tiler-bench"),
                   help="scratch folder (created; removed afterwards unless --keep)")
    p.add_argument("--size", type=int, default=None,
                   help="image side (default 8192 for throughput, 32768 for memory)")
    p.add_argument("--tile-size", type=int, default=256)
    p.add_argument("--rounds", type=int, default=3)
    p.add_argument("--fmt", default="jpg,png", help="tile formats (throughput)")
    p.add_argument("--source", choices=["memory", "file"], default="memory",
                   help="throughput: tile a decoded in-memory image (default) or the file")
    p.add_argument("--no-full-max", action="store_true",
                   help="also time write_pyramid without its full/max encode (diagnostic)")
    p.add_argument("--before", type=Path,
                   help="also time this pyramid.py (e.g. `git show REV:tiler/iiif/pyramid.py`)")
    p.add_argument("--cli", action="store_true", help="also time the `vips` command line")
    p.add_argument("--json", type=Path, help="write the results here")
    p.add_argument("--keep", action="store_true")
    args = p.parse_args()
    args.size = args.size or (8192 if args.what == "throughput" else 32768)
    args.work.mkdir(parents=True, exist_ok=True)
    try:
        result = throughput(args) if args.what == "throughput" else memory(args)
    finally:
        if not args.keep:
            shutil.rmtree(args.work, ignore_errors=True)
    result = {"benchmark": f"tiler {args.what}", "machine": machine(), **result}
    if args.json:
        args.json.write_text(json.dumps(result, indent=2) + "\n")


if __name__ == "__main__":
    main()
