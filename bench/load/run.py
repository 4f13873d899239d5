"""Load test on loopback (by hand, not a test): tiles/s and latency of Lanterna's servers.

Targets, measured side by side in one run (interleaved: every target at one client count, then
the next count):

``gunicorn``
    Static tiles through ``lanterna serve ROOT --workers N`` (gunicorn, ``lanterna.server.wsgi``).
``nginx``
    The same files through Debian's nginx (config generated in a temp folder), as the limit.
``dynamic``
    IIIF level-1 region requests (``/iiif/3/{dataset}/{image}/{x},{y},{w},{h}/{w},{h}/0/…``,
    docs/serving.md) for the same tile grid, rendered per request from the pyramidal TIFF by the
    same gunicorn server; skipped (reported missing) when that server's info.json is not there.
    ``--dynamic-urls FILE`` replaces the generated list by any list of paths.

``wsgi-floor`` (diagnostic, not in the default targets)
    The same files through a bare WSGI app (``floor_app.py``) under gunicorn with the same
    settings: what Python HTTP serving costs per tile without Flask.

Load generator: ``wrk`` with ``bench/load/urls.lua`` cycling through every tile URL of the image
(each wrk thread at another offset). Each run is bounded by ``--duration`` seconds and, with
``--max-requests``, by a request count. Client and server CPU are recorded so a saturated client
shows. Zero errors are required (a run with errors is reported as failed).

Run (the real run uses 60 s per point)::

    .venv/bin/python bench/load/run.py --duration 60 --json bench/results-load.json
"""

from __future__ import annotations

import argparse
import importlib.util
import json
import os
import resource
import shutil
import statistics
import subprocess
import sys
import time
import urllib.request
from pathlib import Path
from types import ModuleType
from typing import Any

import pyvips

from lanterna.tiler.iiif import geometry as geo
from lanterna.tiler.iiif.pyramid import write_pyramid
from lanterna.tiler.iiif.tiff import write_tiff

sys.path.insert(0, str(Path(__file__).resolve().parent))
from servers import Gunicorn, Nginx, Server, WsgiFloor, cpu_seconds, version  # noqa: E402

HERE = Path(__file__).resolve().parent
DATASET, IMAGE = "load", "img"


def _bench_tiler() -> ModuleType:
    """bench/tiler.py (procedural source image, machine facts), loaded by path."""
    spec = importlib.util.spec_from_file_location("bench_tiler", HERE.parent / "tiler.py")
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def make_dataset(root: Path, size: int, tile_size: int) -> tuple[int, int]:
    """Write a ``size``² JPEG image as a static IIIF tree and a pyramidal TIFF under ``root``."""
    src = root / "source.tif"
    _bench_tiler().make_source(src, size)
    image = pyvips.Image.new_from_file(str(src))
    (root / DATASET / "iiif").mkdir(parents=True)
    (root / DATASET / "tiff").mkdir()
    write_pyramid(image, root / DATASET / "iiif" / IMAGE, "http://bench.invalid", fmt="jpg",
                  tile_size=tile_size)
    write_tiff(image, root / DATASET / "tiff" / f"{IMAGE}.tif", fmt="jpg")
    src.unlink()
    return image.width, image.height


def tile_requests(width: int, height: int, tile_size: int) -> list[str]:
    """``region/size`` of every tile of every level, by the spec's algorithm."""
    return [geo.canonical_path(width, height, t)
            for f in geo.scale_factors(width, height, tile_size)
            for t in geo.spec_tiles(width, height, tile_size, f)]


def check(url: str, want_type: str = "image/jpeg") -> bytes:
    """GET ``url``; fail unless it answers 200 with ``want_type``."""
    with urllib.request.urlopen(url, timeout=60) as resp:
        if resp.status != 200 or resp.headers["Content-Type"] != want_type:
            raise RuntimeError(f"{url}: {resp.status} {resp.headers['Content-Type']}")
        body: bytes = resp.read()
        return body


def run_wrk(server: Server, paths_file: Path, clients: int, duration: int,
            max_requests: int) -> dict[str, Any]:
    """One wrk run against ``server``; returns throughput, latency, errors and CPU use."""
    threads = min(clients, 2)
    env = dict(os.environ, LOAD_URLS=str(paths_file),
               LOAD_MAX_PER_THREAD=str(-(-max_requests // threads) if max_requests else 0))
    argv = ["wrk", "-t", str(threads), "-c", str(clients), "-d", f"{duration}s",
            "--timeout", "10s", "-s", str(HERE / "urls.lua"), server.url]
    pids = server.pids()
    server_cpu0, client_cpu0 = cpu_seconds(pids), _children_cpu()
    t0 = time.perf_counter()
    proc = subprocess.run(argv, capture_output=True, text=True, env=env)
    wall = time.perf_counter() - t0
    client_cpu = _children_cpu() - client_cpu0  # wrk is the only child reaped meanwhile
    if proc.returncode != 0:
        raise RuntimeError(f"wrk failed: {proc.stderr}")
    res = json.loads(proc.stdout.strip().splitlines()[-1])
    seconds = res["duration_us"] / 1e6
    return {
        "clients": clients, "wrk_threads": threads, "seconds": seconds,
        "requests": res["requests"], "tiles_per_s": res["requests"] / seconds,
        "mb_per_s": res["bytes"] / seconds / 1e6, "bytes": res["bytes"],
        "p50_ms": res["latency_us"]["p50"] / 1e3, "p90_ms": res["latency_us"]["p90"] / 1e3,
        "p99_ms": res["latency_us"]["p99"] / 1e3, "max_ms": res["latency_us"]["max"] / 1e3,
        "errors": res["errors"], "error_count": sum(res["errors"].values()),
        "server_cores": (cpu_seconds(pids) - server_cpu0) / wall,
        "client_cores": client_cpu / wall,
        "paths": res["paths"],
    }


def _children_cpu() -> float:
    """CPU seconds of this process's reaped children so far."""
    ru = resource.getrusage(resource.RUSAGE_CHILDREN)
    return ru.ru_utime + ru.ru_stime


def _server_of(target: str) -> str:
    """The server a target's requests go to (dynamic requests go to lanterna's gunicorn)."""
    return "gunicorn" if target == "dynamic" else target


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--work", type=Path, default=Path("/var/tmp/lanterna-load"),
                   help="scratch folder: dataset, nginx prefix, logs (removed unless --keep)")
    p.add_argument("--size", type=int, default=8192, help="image side (default 8192)")
    p.add_argument("--tile-size", type=int, default=256)
    p.add_argument("--duration", type=int, default=60, help="seconds per point (default 60)")
    p.add_argument("--warmup", type=int, default=3, help="untimed seconds per target first")
    p.add_argument("--clients", default="1,16,200", help="concurrent connections")
    p.add_argument("--max-requests", type=int, default=0,
                   help="also stop a point after this many responses (0: time only)")
    p.add_argument("--workers", type=int, default=2, help="gunicorn workers (default 2)")
    p.add_argument("--threads", type=int, default=None, help="threads per gunicorn worker")
    p.add_argument("--targets", default="gunicorn,nginx,dynamic")
    p.add_argument("--dynamic-urls", type=Path, help="paths for the dynamic target, one a line")
    p.add_argument("--json", type=Path, help="write the results here")
    p.add_argument("--keep", action="store_true")
    args = p.parse_args()
    work: Path = args.work
    if work.exists():
        shutil.rmtree(work)
    root = work / "root"
    root.mkdir(parents=True)
    os.chmod(work, 0o755)
    servers: dict[str, Server] = {}
    try:
        width, height = make_dataset(root, args.size, args.tile_size)
        requests = tile_requests(width, height, args.tile_size)
        lists = {"gunicorn": [f"/datasets/{DATASET}/iiif/{IMAGE}/{r}/0/default.jpg"
                              for r in requests]}
        lists["nginx"] = lists["wsgi-floor"] = lists["gunicorn"]
        lists["dynamic"] = ([line for line in args.dynamic_urls.read_text().splitlines() if line]
                            if args.dynamic_urls else
                            [f"/iiif/3/{DATASET}/{IMAGE}/{r}/0/default.jpg" for r in requests])
        files = {}
        for name, paths in lists.items():
            files[name] = work / f"urls-{name}.txt"
            files[name].write_text("\n".join(paths) + "\n")
        targets = args.targets.split(",")
        if "gunicorn" in targets or "dynamic" in targets:
            servers["gunicorn"] = Gunicorn(root, args.workers, args.threads,
                                           work / "gunicorn.log")
        if "nginx" in targets:
            servers["nginx"] = Nginx(root, work / "nginx", work / "nginx.log")
        if "wsgi-floor" in targets:
            servers["wsgi-floor"] = WsgiFloor(root, args.workers, args.threads,
                                              work / "wsgi-floor.log")
        missing = {}
        for name in targets:
            server = servers[_server_of(name)]
            try:
                bodies = [check(server.url + path) for path in lists[name][::97]]
            except (OSError, RuntimeError) as err:
                missing[name] = str(err)
                print(f"{name}: not measured ({err})", flush=True)
                continue
            print(f"{name}: {len(lists[name])} URLs, {len(bodies)} checked", flush=True)
        if "gunicorn" not in missing and "nginx" not in missing and {"gunicorn", "nginx"} <= set(
                targets):
            sample = lists["gunicorn"][len(requests) // 2]
            assert check(servers["gunicorn"].url + sample) == check(servers["nginx"].url + sample)
        live = [t for t in targets if t not in missing]
        for name in live:  # warm the page cache and the workers
            run_wrk(servers[_server_of(name)], files[name], 16,
                    args.warmup, 0)
        points: list[dict[str, Any]] = []
        for clients in (int(c) for c in args.clients.split(",")):
            for name in live:
                server = servers[_server_of(name)]
                point = {"target": name, **run_wrk(server, files[name], clients, args.duration,
                                                   args.max_requests)}
                points.append(point)
                print(f"  {name:8} c={clients:3}: {point['tiles_per_s']:8.0f} tiles/s, p50 "
                      f"{point['p50_ms']:7.2f} ms, p99 {point['p99_ms']:7.2f} ms, errors "
                      f"{point['error_count']}, server {point['server_cores']:.2f} cores, "
                      f"client {point['client_cores']:.2f} cores", flush=True)
        result = summarize(points, args, missing, width, height)
    finally:
        for server in servers.values():
            server.stop()
        if not args.keep:
            shutil.rmtree(work, ignore_errors=True)
    if args.json:
        args.json.write_text(json.dumps(result, indent=2) + "\n")


def summarize(points: list[dict[str, Any]], args: argparse.Namespace, missing: dict[str, str],
              width: int, height: int) -> dict[str, Any]:
    """Ratios per client count, the zero-error check and the run's facts."""
    ratios: dict[str, dict[str, float]] = {}
    for clients in sorted({p["clients"] for p in points}):
        at = {p["target"]: p["tiles_per_s"] for p in points if p["clients"] == clients}
        row = {}
        if "gunicorn" in at and "nginx" in at:
            row["gunicorn/nginx"] = at["gunicorn"] / at["nginx"]
        if "dynamic" in at and "nginx" in at:
            row["dynamic/nginx"] = at["dynamic"] / at["nginx"]
        if "dynamic" in at and "gunicorn" in at:
            row["dynamic/gunicorn"] = at["dynamic"] / at["gunicorn"]
        if "wsgi-floor" in at and "nginx" in at:
            row["wsgi-floor/nginx"] = at["wsgi-floor"] / at["nginx"]
        ratios[str(clients)] = row
    for name, row in ratios.items():
        print(f"c={name}: " + ", ".join(f"{k} {v:.2f}" for k, v in row.items()))
    errors = sum(p["error_count"] for p in points)
    print(f"errors: {errors}" + ("" if errors == 0 else "  (FAILED: 0 required)"))
    import gunicorn

    return {
        "benchmark": "load (loopback)", "machine": _bench_tiler().machine(),
        "tools": {"load generator": version(["wrk", "-v"]) + " + bench/load/urls.lua",
                  "nginx": version(["nginx", "-v"]), "gunicorn": gunicorn.__version__},
        "image": {"width": width, "height": height, "tile_size": args.tile_size,
                  "format": "jpg Q90", "tile_urls": len(tile_requests(width, height,
                                                                      args.tile_size))},
        "settings": {"duration_s": args.duration, "warmup_s": args.warmup,
                     "max_requests": args.max_requests, "gunicorn_workers": args.workers,
                     "gunicorn_threads": args.threads or 8, "nginx_workers": "auto"},
        "missing": missing, "errors": errors, "ratios": ratios, "points": points,
        "median_client_cores": statistics.median(p["client_cores"] for p in points)
        if points else None,
    }


if __name__ == "__main__":
    main()
