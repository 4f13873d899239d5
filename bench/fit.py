"""Benchmark ``lanterna fit``: throughput against bare decoding, and peak memory (not a test).

    .venv/bin/python bench/fit.py throughput [--size 4096] [--lights 24] [--json OUT]
    .venv/bin/python bench/fit.py memory [--size 32768] [--lights 8] [--json OUT]
    .venv/bin/python bench/fit.py compare --python OTHER/.venv/bin/python [--size 1024] [--json OUT]
    .venv/bin/python bench/fit.py compare --stack COLLECTION/dirs.lp [--python OTHER] [--json OUT]
    .venv/bin/python bench/fit.py compare --relit RELIGHT_FOLDER --size 2048 [--python OTHER]
                                          [--idle SECONDS]

``throughput`` writes a synthetic multi-light JPEG stack (a bumpy Lambert + Phong object,
procedural in libvips, so it never exists whole in memory), then times, interleaved in one run
(medians of ``--rounds``): the bare decode of every image (libvips, top to bottom), the read
pass the fit makes (the bands as decoded, two decoding threads), and the streamed fit of each
model with and without its leave-one-out twin (:func:`~lanterna.tiler.fit.engine.fit_stream`: solve,
quantise, write the 8-bit planes; tiling excluded — see bench/tiler.py).

``compare`` measures this checkout against another one (its interpreter, ``--python``) on a
shared machine: per round and model, each version fits in a fresh process (imports and compiled
kernels loaded first, then the bare decode and the fit timed back to back, with the process's CPU
time), the two versions alternating; it reports per version the median and the minimum of the
per-run ratio fit ÷ decode, and the same for CPU time.  ``--stack`` measures a collection on
disk (a ``.lp`` file and its images: a real capture) instead of a synthetic stack, ``--relit`` a
real object relit by its Relight model (:func:`make_relit_stack`); without
``--python`` only this checkout is measured.  Either way the stack's size and its JPEGs' bits per
pixel are reported (a JPEG's decode time grows with its bytes).  ``--idle S`` waits ``S``
seconds before each fit's process: a fit started right after another one's process ended
reuses memory the host still backs, where a user's fit, started after a pause, may not (a VM
that reports free memory to its host does so within ~2 s).

``memory`` runs the whole ``lanterna fit`` (fit + tiling + manifest) of a large stack in a child
process and reports its peak resident set size (``ru_maxrss`` of the child).
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import resource
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

import numpy as np
import pyvips

REPO = Path(__file__).resolve().parents[1]


def lights(n: int) -> np.ndarray:
    """``n`` unit lights on a spiral, elevation 20°–75°."""
    k = np.arange(n)
    elev = np.radians(20 + 55 * k / max(1, n - 1))
    azim = k * np.pi * (3 - np.sqrt(5))
    return np.stack([np.cos(elev) * np.cos(azim), np.cos(elev) * np.sin(azim),
                     np.sin(elev)], axis=1)


def make_stack(folder: Path, size: int, n: int, grain: float = 0.0) -> Path:
    """Write ``n`` JPEGs (Q90) of a ``size``² procedural object and its ``lights.lp``.

    Past 4096 px the object is computed at 1/8 of the size and enlarged (bilinear), so a
    gigapixel stack takes minutes, not hours, to make.  The smooth object compresses to
    0.03 bytes a pixel, far below a photograph's; ``grain`` adds Gaussian noise of that many
    8-bit levels to each shot (its own seed per shot and channel), so that the JPEGs carry a real
    image's entropy and decode at its speed (docs/benchmarks.md "Fit throughput on grainy
    photographs").
    """
    folder.mkdir(parents=True, exist_ok=True)
    scale = 8 if size > 4096 else 1
    xy = pyvips.Image.xyz(-(-size // scale), -(-size // scale)).cast("float") * scale
    x, y = xy[0], xy[1]
    gx = (x / 37.0).sin() * 0.5 + (y / 91.0).cos() * 0.2
    gy = (y / 53.0).sin() * 0.4 + (x / 71.0).cos() * 0.2
    norm = (gx * gx + gy * gy + 1.0) ** 0.5
    nx, ny, nz = -gx / norm, -gy / norm, 1.0 / norm
    albedo = ((x / 113.0).sin() * 0.15 + 0.55).bandjoin([(y / 97.0).cos() * 0.1 + 0.5,
                                                         (x / 61.0 + y / 83.0).sin() * 0.1 + 0.4])
    rows = [str(n)]
    for i, (lx, ly, lz) in enumerate(lights(n)):
        cos = (nx * lx + ny * ly + nz * lz).cast("float")
        cos = (cos > 0).ifthenelse(cos, 0.0)
        hx, hy, hz = np.array([lx, ly, lz + 1.0]) / np.linalg.norm([lx, ly, lz + 1.0])
        nh = (nx * hx + ny * hy + nz * hz)
        nh = (nh > 0).ifthenelse(nh, 0.0)
        spec = (nh ** 60) * 0.25
        img = (albedo * cos + spec) * 255.0
        if scale > 1:
            img = img.resize(scale, kernel="linear").crop(0, 0, size, size)
        if grain > 0:  # independent noise per shot and channel (seeds 1, 2, 3, then 4, …)
            noise = [pyvips.Image.gaussnoise(size, size, sigma=grain, mean=0.0, seed=3 * i + c + 1)
                     for c in range(3)]
            img = img + noise[0].bandjoin(noise[1:])
        img = img.cast("uchar")  # values outside 0–255 clip
        name = f"img_{i:03d}.jpg"
        img.copy(interpretation="srgb").jpegsave(str(folder / name), Q=90)
        rows.append(f"{name} {lx:.6f} {ly:.6f} {lz:.6f}")
    (folder / "lights.lp").write_text("\n".join(rows) + "\n")
    return folder / "lights.lp"


def make_relit_stack(folder: Path, source: Path, size: int, n: int) -> Path:
    """Write ``n`` JPEGs (Q90) of a real object relit by its own fitted model, ``size``², and
    their ``lights.lp``: a stack with a real object's texture, where the procedural one has
    none (docs/benchmarks.md "Fit throughput on a real object").

    ``source`` is a Relight web-format folder (``../shared/realdata/relight-coin/rbf27``: the
    coin's RBF basis, fitted by Relight from its 116-light capture).  Each image is the
    reference renderer's view of it at one of ``n`` of the capture's own lights (spread over
    them in their order), in 8 bits, mirrored into a ``size``² mosaic (the same texture per
    pixel: a JPEG's bytes per pixel stay the render's, with no seam).
    """
    from lanterna.tiler.formats.relight_web import read_relight
    from lanterna.tiler.render import dequantise, render

    layer = read_relight(source)
    block = {"layerType": layer.layer_type, **layer.fields(), "planes": []}
    channels = {}
    for group in layer.groups:
        channels.update(dequantise(np.asarray(group.data), group.channels, group.scale,
                                   group.bias))
    assert layer.pca is not None and layer.pca.lights is not None
    captured = np.asarray(layer.pca.lights, np.float64).reshape(-1, 3)
    folder.mkdir(parents=True, exist_ok=True)
    rows = [str(n)]
    for i, k in enumerate(np.linspace(0, len(captured) - 1, n).round().astype(int)):
        lx, ly, lz = captured[k] / np.linalg.norm(captured[k])
        shot = np.clip(np.rint(render(block, channels, (float(lx), float(ly))) * 255), 0, 255)
        tile = pyvips.Image.new_from_array(shot.astype(np.uint8))
        pair = tile.join(tile.fliphor(), "horizontal")
        quad = pair.join(pair.flipver(), "vertical")
        img = quad.replicate(-(-size // quad.width), -(-size // quad.height)).crop(0, 0, size,
                                                                                  size)
        name = f"img_{i:03d}.jpg"
        img.copy(interpretation="srgb").jpegsave(str(folder / name), Q=90)
        rows.append(f"{name} {lx:.6f} {ly:.6f} {lz:.6f}")
    (folder / "lights.lp").write_text("\n".join(rows) + "\n")
    return folder / "lights.lp"


def _bare_decode(files: list[Path]) -> None:
    for f in files:
        pyvips.Image.new_from_file(str(f), access="sequential").avg()


def _read_pass(files: list[Path], rows: int) -> None:
    """The fit's own read, with nothing solved: every band as decoded, read ahead, each band's
    files decoded on two threads while nobody waits
    (:func:`~lanterna.tiler.fit.row_bands.read_bands`: here the consumer always waits, so the
    decode is always parallel)."""
    from lanterna.tiler.fit.row_bands import read_bands
    from lanterna.tiler.inputs.stack import StackReader

    reader = StackReader(files)
    h = reader.shape[1]
    for _ in read_bands(reader, [(y0, min(h, y0 + rows)) for y0 in range(0, h, rows)]):
        pass
    reader.close()


def auto_band_rows(n: int, width: int) -> int:
    """The fit's automatic band height, where this checkout or the one ``compare`` measures
    keeps it (tiler/fit/row_bands.py since 0f5b240, tiler/fit/engine.py before)."""
    try:
        from lanterna.tiler.fit import row_bands as home
    except ImportError:
        from lanterna.tiler.fit import engine as home
    rows: int = home.auto_band_rows(n, width)
    return rows


def _fit(files: Any, lts: np.ndarray, key: str, held: int, scratch: Path) -> None:
    """One streamed fit of ``key`` (of the image files, or of a stack in memory); a PCA basis
    (rbf, bilinear) also makes its sampling pass first, as ``lanterna fit`` does
    (:func:`~lanterna.tiler.fit.run.fit_sets`)."""
    from lanterna.tiler.fit.engine import fit_stream
    from lanterna.tiler.fit.pca import PcaSpec
    from lanterna.tiler.fit.pca_band import pca_models
    from lanterna.tiler.formats.pca_model import PCA_TYPES
    from lanterna.tiler.inputs.stack import StackReader

    out = Path(tempfile.mkdtemp(dir=scratch))
    try:
        stack = files if isinstance(files, np.ndarray) else StackReader(files)
        keys, extra = [key], []
        if key in PCA_TYPES:
            n, _, width, _ = stack.shape
            held_at = np.arange(0, n, held) if held else np.zeros(0, np.intp)
            keys, extra = [], pca_models(stack, lts, [PcaSpec(key)], held_at, out,
                                         band_rows=auto_band_rows(n, width))
        fit_stream(stack, lts, keys, out, holdout_every=held, extra=extra)
    finally:
        shutil.rmtree(out)


def throughput(args: argparse.Namespace) -> dict[str, Any]:
    from lanterna.tiler.inputs.lp import read_lp

    work = Path(tempfile.mkdtemp(prefix="lanterna-bench-fit-", dir=args.tmp))
    try:
        t0 = time.perf_counter()
        lp = make_stack(work / "shots", args.size, args.lights, args.grain)
        made = time.perf_counter() - t0
        files, lts = read_lp(lp, lp.parent)
        rows = auto_band_rows(len(files), args.size)
        held = 10 if len(files) >= 20 else 0
        cases: dict[str, Any] = {"decode (libvips)": lambda: _bare_decode(files),
                                 "read pass (bands as decoded, as the fit reads them)":
                                     lambda: _read_pass(files, rows)}
        for key in args.models:
            cases[f"{key}"] = (lambda k=key: _fit(files, lts, k, 0, work))
            if held:
                cases[f"{key} + leave-one-out"] = (lambda k=key: _fit(files, lts, k, held, work))
        times: dict[str, list[float]] = {name: [] for name in cases}
        cpus: dict[str, list[float]] = {name: [] for name in cases}
        for r in range(args.rounds):
            for name, run in cases.items():
                c, t = _cpu(), time.perf_counter()
                run()
                times[name].append(time.perf_counter() - t)
                cpus[name].append(_cpu() - c)
                print(f"round {r + 1}: {name}: {times[name][-1]:.2f} s "
                      f"(CPU {cpus[name][-1]:.2f} s)", flush=True)
        mpx = len(files) * args.size * args.size / 1e6
        base = statistics.median(times["decode (libvips)"])
        base_cpu = statistics.median(cpus["decode (libvips)"])
        result = {"size": args.size, "lights": len(files), "bandRows": rows,
                  "grain": args.grain, "jpegBytesPerPixel": round(
                      sum(f.stat().st_size for f in files) / (len(files) * args.size ** 2), 3),
                  "stackMegapixels": round(mpx, 1), "makeSeconds": round(made, 1),
                  "rounds": args.rounds, "cases": {}}
        for name, ts in times.items():
            med = statistics.median(ts)
            result["cases"][name] = {"seconds": [round(t, 3) for t in ts],
                                     "median": round(med, 3),
                                     "inputMpxPerSecond": round(mpx / med, 1),
                                     "vsDecode": round(med / base, 2),
                                     "cpuMedian": round(statistics.median(cpus[name]), 3),
                                     "cpuVsDecodeCpu": round(statistics.median(cpus[name])
                                                             / base_cpu, 2)}
        return result
    finally:
        shutil.rmtree(work, ignore_errors=True)


def _cpu() -> float:
    usage = resource.getrusage(resource.RUSAGE_SELF)
    return float(usage.ru_utime + usage.ru_stime)


def one(args: argparse.Namespace) -> dict[str, Any]:
    """One timed fit in this interpreter (``compare``'s worker): decode, then the fit (a PCA
    basis with its sampling pass, as :func:`_fit`)."""
    from lanterna.tiler.inputs.lp import read_lp

    lp = Path(args.stack)
    files, lts = read_lp(lp, lp.parent)
    work = Path(tempfile.mkdtemp(prefix="lanterna-bench-one-", dir=args.tmp))
    try:
        # imports, and the kernels the fit runs loaded from their cache: a fit of the images'
        # top rows, saved losslessly (the same sample format, so the same kernels; enough
        # pixels for a sampled report, as the whole images'); a float stack in memory
        # (before 2026-12-04) loaded the float kernels, and the timed fit then loaded its
        # own (0.05–0.09 s: docs/benchmarks.md "Fit throughput, thirteenth pass")
        _fit(_top_rows(files, work / "warm"), lts, args.models[0], args.held, work)
        c0, t0 = _cpu(), time.perf_counter()
        _bare_decode(files)
        decode, decode_cpu = time.perf_counter() - t0, _cpu() - c0
        c0, t0 = _cpu(), time.perf_counter()
        _fit(files, lts, args.models[0], args.held, work)
        return {"decode": decode, "decodeCpu": decode_cpu, "fit": time.perf_counter() - t0,
                "fitCpu": _cpu() - c0}
    finally:
        shutil.rmtree(work, ignore_errors=True)


def _top_rows(files: list[Path], folder: Path) -> list[Path]:
    """The images' top rows, losslessly in ``folder`` (8-/16-bit PNGs): twice the report's sample of
    pixels (``REPORT_PIXELS``, 2¹⁶), so their fit takes a sampled report as the whole
    images' does."""
    folder.mkdir()
    out = []
    for i, f in enumerate(files):
        img = pyvips.Image.new_from_file(str(f))
        rows = min(img.height, -(-2 * (1 << 16) // img.width) + 1)
        top = img.crop(0, 0, img.width, rows)
        out.append(folder / f"top{i:04d}.{'png' if top.format in ('uchar', 'ushort') else 'tif'}")
        top.write_to_file(str(out[-1]))
    return out


def compare(args: argparse.Namespace) -> dict[str, Any]:
    from lanterna.tiler.inputs.lp import read_lp

    work = Path(tempfile.mkdtemp(prefix="lanterna-bench-cmp-", dir=args.tmp))
    try:
        lp = (Path(args.stack).resolve() if args.stack else
              make_relit_stack(work / "shots", Path(args.relit), args.size, args.lights)
              if args.relit else make_stack(work / "shots", args.size, args.lights, args.grain))
        files, _ = read_lp(lp, lp.parent)
        first = pyvips.Image.new_from_file(str(files[0]))
        args.lights, size = len(files), [first.width, first.height]
        bits = 8 * sum(f.stat().st_size for f in files) / (len(files) * size[0] * size[1])
        held = 10 if args.lights >= 20 else 0
        sides = {"this": sys.executable, **({"other": args.python} if args.python else {})}
        if args.rounds % 2:  # the first fit of a pair is the slower one on this VM
            print("note: an odd --rounds lets one version run first more often in each case; "
                  "use an even number", file=sys.stderr)
        runs: dict[tuple[str, str], list[dict[str, float]]] = {}
        for r in range(args.rounds):
            for key in args.models:
                for h in ((0, held) if held else (0,)):
                    name = key + (" + leave-one-out" if h else "")
                    order = list(sides.items()) if r % 2 == 0 else list(sides.items())[::-1]
                    for side, python in order:
                        cmd = [python, str(Path(__file__).resolve()), "one", "--stack", str(lp),
                               "--model", key, "--held", str(h)]
                        time.sleep(args.idle)  # the machine idle, as between a user's commands
                        proc = subprocess.run(cmd, capture_output=True, text=True, cwd=REPO)
                        if proc.returncode != 0:
                            raise SystemExit(proc.stdout + proc.stderr)
                        run = json.loads(proc.stdout)
                        runs.setdefault((name, side), []).append(run)
                        print(f"round {r + 1}: {side}: {name}: fit {run['fit']:.2f} s, "
                              f"decode {run['decode']:.2f} s", flush=True)
        cases: dict[str, Any] = {}
        for (name, side), rs in runs.items():
            cases.setdefault(name, {})[side] = {
                "fitSeconds": [round(x["fit"], 3) for x in rs],
                "medianVsDecode": round(statistics.median(x["fit"] / x["decode"] for x in rs), 2),
                "minVsDecode": round(min(x["fit"] / x["decode"] for x in rs), 2),
                "medianCpuVsDecodeCpu": round(statistics.median(x["fitCpu"] / x["decodeCpu"]
                                                                for x in rs), 2)}
        return {"stack": str(lp) if args.stack else None,
                "size": None if args.stack else args.size, "imageSize": size,
                "lights": args.lights, "bitsPerPixel": round(bits, 3), "rounds": args.rounds,
                "grain": None if args.stack or args.relit else args.grain,
                "relit": args.relit, "other": args.python, "idleSeconds": args.idle,
                "cases": cases}
    finally:
        shutil.rmtree(work, ignore_errors=True)


def memory(args: argparse.Namespace) -> dict[str, Any]:
    work = Path(tempfile.mkdtemp(prefix="lanterna-bench-fitmem-", dir=args.tmp))
    try:
        t0 = time.perf_counter()
        lp = make_stack(work / "shots", args.size, args.lights, args.grain)
        made = time.perf_counter() - t0
        stack_bytes = sum(f.stat().st_size for f in lp.parent.glob("*.jpg"))
        cmd = [sys.executable, "-m", "lanterna.cli", "fit", str(lp.parent), "--lp", str(lp),
               "-o", str(work / "ds"), "--quiet"]
        for key in args.models:
            cmd += ["--model", key]
        before = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss
        t0 = time.perf_counter()
        proc = subprocess.run(cmd, capture_output=True, text=True, cwd=REPO)
        seconds = time.perf_counter() - t0
        peak_kb = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss
        if proc.returncode != 0:
            raise SystemExit(proc.stdout + proc.stderr)
        out_bytes = sum(p.stat().st_size for p in (work / "ds").rglob("*") if p.is_file())
        return {"size": args.size, "lights": args.lights, "models": args.models,
                "gigapixels": round(args.size * args.size / 1e9, 3),
                "jpegStackGB": round(stack_bytes / 1e9, 2), "makeSeconds": round(made, 1),
                "fitSeconds": round(seconds, 1), "peakRssMB": round(max(peak_kb, before) / 1024),
                "datasetGB": round(out_bytes / 1e9, 2), "stdout": proc.stdout.strip()}
    finally:
        shutil.rmtree(work, ignore_errors=True)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("what", choices=["throughput", "memory", "compare", "one"])
    parser.add_argument("--python", help="compare: the other checkout's interpreter")
    parser.add_argument("--stack", help="one, compare: the stack's .lp file (compare: instead "
                                        "of a synthetic stack)")
    parser.add_argument("--held", type=int, default=0, help="one: holdout_every")
    parser.add_argument("--size", type=int, help="image side (4096 / 32768)")
    parser.add_argument("--lights", type=int, help="images in the stack (24 / 8)")
    parser.add_argument("--model", dest="models", action="append",
                        help="models (default: all five / ptm-lrgb for memory)")
    parser.add_argument("--grain", type=float, default=0.0,
                        help="per-shot noise in 8-bit levels (photograph-like entropy; see docs)")
    parser.add_argument("--relit", help="compare: a Relight folder whose object, relit, makes "
                                        "the stack (make_relit_stack)")
    parser.add_argument("--rounds", type=int, default=3)
    parser.add_argument("--idle", type=float, default=0.0,
                        help="compare: seconds to wait before each fit's process (a VM that "
                             "reports free memory to its host does so after ~2 s: "
                             "docs/benchmarks.md \"Fit throughput, sixteenth pass\")")
    parser.add_argument("--tmp", default=None, help="scratch folder (needs disk: see docs)")
    parser.add_argument("--json", type=Path, help="write the result here")
    args = parser.parse_args()
    if args.tmp is not None and not Path(args.tmp).is_dir():
        parser.error(f"--tmp {args.tmp}: not a folder")
    if not 0 <= args.idle <= 600:
        parser.error(f"--idle {args.idle}: expected 0 to 600 seconds")
    big = args.what == "memory"
    if args.what == "one":  # runs in the other checkout's interpreter: its own lanterna
        print(json.dumps(one(args)))
        return
    sys.path.insert(0, str(REPO))
    args.size = args.size or (32768 if big else 1024 if args.what == "compare" else 4096)
    args.lights = args.lights or (8 if big else 24)
    args.models = args.models or (["ptm-lrgb"] if big else
                                  ["ptm", "ptm-lrgb", "hsh", "normals", "ward"])
    run = {"throughput": throughput, "memory": memory, "compare": compare}[args.what]
    result = run(args)
    result["machine"] = {"cpus": os.cpu_count(), "python": platform.python_version(),
                         "libvips": f"{pyvips.version(0)}.{pyvips.version(1)}."
                                    f"{pyvips.version(2)}",
                         "numpy": np.__version__, "platform": platform.platform()}
    text = json.dumps(result, indent=2)
    print(text)
    if args.json:
        args.json.write_text(text + "\n")


if __name__ == "__main__":
    main()
