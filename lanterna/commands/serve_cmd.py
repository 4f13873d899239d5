"""``lanterna serve`` and ``lanterna demo``: the local server (and the demo dataset).

Without ``--workers`` the Flask development server runs (one process, a thread per request);
with ``--workers N`` gunicorn runs N worker processes (``lanterna.server.wsgi``).
"""

from __future__ import annotations

import argparse
from pathlib import Path

from lanterna.errors import LanternaInputError

from .common import SubParsers, serve_args
from .summary import print_written

SERVE_EXAMPLES = """examples:
  lanterna serve datasets/                     every dataset in datasets/ at http://127.0.0.1:8000/
  lanterna serve datasets/ --port 8080          another port
  lanterna serve datasets/ --host 0.0.0.0 --workers 4
      gunicorn with 4 worker processes, for several users on the network (docs/deploy.md)
  lanterna serve datasets/ --max-size 4096     cap the output of the IIIF image server at /iiif/3/

Without --workers the server is Werkzeug's (one process, a thread per connection): right for one
person on this machine, not for several users or a public address.
"""
DEMO_EXAMPLES = """examples:
  lanterna demo                        build datasets/demo (once), serve it at http://127.0.0.1:8000/
  lanterna demo --no-serve             only build it
  lanterna demo --force --port 8080    rebuild it, and serve it on another port
"""


def register(sub: SubParsers) -> None:
    srv = sub.add_parser("serve", help="serve a folder of datasets and the viewer",
                         epilog=SERVE_EXAMPLES,
                         formatter_class=argparse.RawDescriptionHelpFormatter)
    srv.add_argument("root", type=Path, help="folder holding datasets")
    serve_args(srv)
    _worker_args(srv)
    srv.set_defaults(func=run_serve)

    demo = sub.add_parser("demo", help="make the demo dataset (if missing) and serve it",
                          epilog=DEMO_EXAMPLES,
                          formatter_class=argparse.RawDescriptionHelpFormatter)
    demo.add_argument("--root", type=Path, default=Path("datasets"),
                      help="data root (default ./datasets)")
    demo.add_argument("--no-serve", action="store_true", help="only build the dataset")
    demo.add_argument("--force", action="store_true", help="rebuild the demo dataset")
    serve_args(demo)
    _worker_args(demo)
    demo.set_defaults(func=run_demo)


def _worker_args(p: argparse.ArgumentParser) -> None:
    p.add_argument("--workers", type=int, default=None, metavar="N",
                   help="serve with gunicorn, N worker processes (default: the Flask "
                        "development server)")
    p.add_argument("--threads", type=int, default=None, metavar="T",
                   help="threads per gunicorn worker (default 8; needs --workers)")
    p.add_argument("--max-size", type=int, default=None, metavar="PX",
                   help="IIIF image server: largest output width or height (default 16384)")
    p.add_argument("--max-area", type=float, default=None, metavar="MPX",
                   help="IIIF image server: largest output area in megapixels (default 16.8)")


def _limits(args: argparse.Namespace) -> dict[str, object]:
    """The IIIF image server's output limits given on the command line (docs/serving.md)."""
    config: dict[str, object] = {}
    size, area = getattr(args, "max_size", None), getattr(args, "max_area", None)
    if size is not None:
        if size < 1:
            raise LanternaInputError(None, "--max-size must be at least 1")
        config["IIIF_MAX_WIDTH"] = config["IIIF_MAX_HEIGHT"] = size
    if area is not None:
        if area <= 0:
            raise LanternaInputError(None, "--max-area must be positive")
        config["IIIF_MAX_AREA"] = int(area * 1e6)
    return config


def run_serve(args: argparse.Namespace) -> int:
    from lanterna.server.app import create_app

    root = args.root.resolve()
    if not root.is_dir():
        raise LanternaInputError(args.root, "not a folder")
    workers: int | None = getattr(args, "workers", None)
    threads: int | None = getattr(args, "threads", None)
    if workers is not None and workers < 1:
        raise LanternaInputError(None, "--workers must be at least 1")
    if threads is not None and (workers is None or threads < 1):
        raise LanternaInputError(None, "--threads needs --workers and must be at least 1")
    limits = _limits(args)
    url = f"http://{args.host}:{args.port}/"
    for desc in sorted(root.glob("*/lanterna.json")):
        manifest = f"{url}datasets/{desc.parent.name}/manifest.json"
        print(f"  {desc.parent.name}: {url}viewer/?manifest={manifest}")
    if workers is None:
        print(f"Lanterna serving {root} at {url}  (Ctrl-C to stop)", flush=True)
        create_app({**limits, "DATA_ROOT": root}).run(host=args.host, port=args.port,
                                                      threaded=True)
        return 0
    from lanterna.server.wsgi import DEFAULT_THREADS, run_gunicorn

    threads = threads or DEFAULT_THREADS
    print(f"Lanterna serving {root} at {url} with gunicorn, {workers} workers × {threads} "
          "threads  (Ctrl-C to stop)", flush=True)
    run_gunicorn(root, args.host, args.port, workers, threads, limits)
    return 0


def run_demo(args: argparse.Namespace) -> int:
    from lanterna.tiler.demo.dataset import build_demo

    out = args.root / "demo"
    if args.force or not (out / "lanterna.json").is_file():
        print(f"building the demo dataset in {out} …", flush=True)
        build_demo(out, force=True)
    if args.no_serve:
        print_written(out)
        return 0
    return run_serve(argparse.Namespace(root=args.root, host=args.host, port=args.port,
                                        workers=args.workers, threads=args.threads))
