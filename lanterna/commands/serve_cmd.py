"""``lanterna serve`` and ``lanterna demo``: the local server (and the demo dataset).

The socket is bound first (:func:`lanterna.server.local.listen`): a busy port is one line on
stderr before anything else is printed. Without ``--workers`` Werkzeug's threaded server runs in
this process (:mod:`lanterna.server.local`), with ``--workers N`` gunicorn runs N worker
processes (:mod:`lanterna.server.wsgi`); either logs requests only with ``--verbose``.
"""

from __future__ import annotations

import argparse
import errno
import ipaddress
import os
import socket
import sys
from pathlib import Path

from lanterna.errors import LanternaInputError

from .common import SubParsers, serve_args
from .summary import print_written

SERVE_EXAMPLES = """examples:
  lanterna serve datasets/                     every dataset in datasets/ at http://127.0.0.1:8000/
  lanterna serve datasets/ --port 8080 --verbose
      another port, and one log line per request
  lanterna serve datasets/ --host 0.0.0.0 --workers 4
      gunicorn with 4 worker processes, for several users on the network (docs/deploy.md)
  lanterna serve datasets/ --max-size 4096     cap the output of the IIIF image server at /iiif/3/
  lanterna serve datasets/ --authoring-token-file ~/.lanterna-token
      let the advanced viewer save presets and annotations into the datasets (/api/…,
      docs/serving.md); or set LANTERNA_AUTHORING_TOKEN in the environment. Never put the token
      on the command line.

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
                   help="serve with gunicorn, N worker processes (default: the built-in "
                        "server, for this machine)")
    p.add_argument("--threads", type=int, default=None, metavar="T",
                   help="threads per gunicorn worker (default 8; needs --workers)")
    p.add_argument("--max-size", type=int, default=None, metavar="PX",
                   help="IIIF image server: largest output width or height (default and "
                        "most 16383, the largest side WebP can encode)")
    p.add_argument("--max-area", type=float, default=None, metavar="MPX",
                   help="IIIF image server: largest output area in megapixels (default 16.8)")
    p.add_argument("--authoring-token-file", type=Path, default=None, metavar="FILE",
                   help="enable the authoring API (saving presets and annotations): its token is "
                        "the first line of FILE, at least 16 characters (default: "
                        "$LANTERNA_AUTHORING_TOKEN, else read-only)")


def _limits(args: argparse.Namespace) -> dict[str, object]:
    """The app settings given on the command line: the IIIF image server's output limits, the
    authoring token (docs/serving.md)."""
    config: dict[str, object] = {}
    size, area = getattr(args, "max_size", None), getattr(args, "max_area", None)
    if size is not None:
        from lanterna.server.image_request import MAX_SIDE

        if not 1 <= size <= MAX_SIDE:
            raise LanternaInputError(None, f"--max-size must be between 1 and {MAX_SIDE} (the "
                                     "largest side the image server can encode in every "
                                     "format it offers, WebP's)")
        config["IIIF_MAX_WIDTH"] = config["IIIF_MAX_HEIGHT"] = size
    if area is not None:
        if area <= 0:
            raise LanternaInputError(None, "--max-area must be positive")
        config["IIIF_MAX_AREA"] = int(area * 1e6)
    from lanterna.server.auth import authoring_token

    config["AUTHORING_TOKEN"] = authoring_token(getattr(args, "authoring_token_file", None),
                                                os.environ)
    return config


def run_serve(args: argparse.Namespace) -> int:
    root = args.root.resolve()
    if not root.is_dir():
        raise LanternaInputError(args.root, "not a folder")
    _check_workers(args)
    limits = _limits(args)
    listener = _listen(args, "serve")
    if listener is None:
        return 1
    return _serve(args, "serve", listener, root, limits)


def run_demo(args: argparse.Namespace) -> int:
    from lanterna.tiler.demo.dataset import build_demo, demo_is_current

    listener = None
    if not args.no_serve:  # refuse a busy port before the build, not after
        _check_workers(args)
        limits = _limits(args)
        listener = _listen(args, "demo")
        if listener is None:
            return 1
    out = args.root / "demo"
    if args.force or not demo_is_current(out):
        again = (out / "lanterna.json").is_file() and not args.force
        print(f"{'rebuilding (from an older Lanterna)' if again else 'building'} the demo "
              f"dataset in {out} …", flush=True)
        build_demo(out, force=True)
        if listener is not None:
            print_written(out, details=False)
    if listener is None:
        print_written(out)
        return 0
    return _serve(args, "demo", listener, args.root.resolve(), limits)


def _check_workers(args: argparse.Namespace) -> None:
    workers, threads = args.workers, args.threads
    if workers is not None and workers < 1:
        raise LanternaInputError(None, "--workers must be at least 1")
    if threads is not None and (workers is None or threads < 1):
        raise LanternaInputError(None, "--threads needs --workers and must be at least 1")


def _listen(args: argparse.Namespace, command: str) -> socket.socket | None:
    """Bind ``--host``/``--port``; on failure print one line and return None."""
    from lanterna.server.local import listen

    try:
        return listen(args.host, args.port)
    except OSError as err:
        print(f"lanterna {command}: error: {_listen_problem(args.host, args.port, err)}",
              file=sys.stderr)
        return None


def _listen_problem(host: str, port: int, err: OSError) -> str:
    """Say in a few words why ``host:port`` cannot be listened on, and what to try."""
    if isinstance(err, socket.gaierror):
        return f"unknown host {host!r} (--host takes a name or an address of this machine)"
    if err.errno == errno.EADDRINUSE:
        return f"port {port} is in use ({_free_port_hint(host, port)})"
    if err.errno == errno.EACCES:
        return f"no permission to listen on port {port} ({_free_port_hint(host, 8000)})"
    if err.errno == errno.EADDRNOTAVAIL:
        return f"{host} is not an address of this machine (try --host 127.0.0.1)"
    return f"cannot listen on {host}:{port}: {err.strerror or err}"


def _free_port_hint(host: str, port: int) -> str:
    from lanterna.server.local import listen

    for candidate in range(port + 1, min(port + 20, 65535) + 1):
        try:
            listen(host, candidate).close()
        except OSError:
            continue
        return f"try --port {candidate}"
    return "try another --port, or --port 0 for any free one"


def _serve(args: argparse.Namespace, command: str, listener: socket.socket, root: Path,
           limits: dict[str, object]) -> int:
    """Print the URLs, then serve on ``listener`` until Ctrl-C."""
    from lanterna.server.app import BUILD_VIEWER, create_app, default_viewer
    from lanterna.server.wsgi import DEFAULT_THREADS

    threads = args.threads or DEFAULT_THREADS
    _print_urls(args, listener.getsockname(), root, threads)
    print(_authoring_note(args, limits.get("AUTHORING_TOKEN")), flush=True)
    if not (default_viewer() / "index.html").is_file():
        print(f"lanterna {command}: warning: the viewer is not built, /viewer/ answers 404 "
              f"({BUILD_VIEWER})", file=sys.stderr)
    if args.workers is None:
        from lanterna.server.local import run_threaded

        run_threaded(create_app({**limits, "DATA_ROOT": root}), listener,
                     access_log=args.verbose)
    else:
        from lanterna.server.wsgi import run_gunicorn

        run_gunicorn(root, listener, args.workers, threads, limits, access_log=args.verbose)
    return 0


def _print_urls(args: argparse.Namespace, address: tuple[str, int], root: Path,
                threads: int) -> None:
    """Print where the server listens, each dataset's viewer URL, and what the server is."""
    host = f"[{args.host}]" if ":" in args.host else args.host
    url = f"http://{host}:{address[1]}/"
    workers = args.workers
    engine = ("" if workers is None else
              f" with gunicorn, {workers} worker{'s' if workers > 1 else ''} × {threads} threads")
    print(f"Lanterna serving {root} at {url}{engine}  (Ctrl-C to stop)")
    from lanterna.tiler.dataset.publish import list_datasets

    datasets = list_datasets(root)  # no hidden entries: versions, temporary folders
    for folder in datasets:
        manifest = f"{url}datasets/{folder.name}/manifest.json"
        print(f"  {folder.name}: {url}viewer/?manifest={manifest}")
        if (folder / "presets.json").is_file():  # the simplified viewer shows a dataset's presets
            simple = f"{url}viewer/simple.html?manifest={manifest}"
            print(f"  {folder.name} (simplified viewer): {simple}")
        print(f"  {folder.name} (in Mirador): {url}viewer/mirador.html?manifest={manifest}")
    if not datasets:
        print(f"  no datasets yet: lanterna import FILE -o {root / 'NAME'}")
    if workers is None:
        print(_local_note(address[0]))
    sys.stdout.flush()


def _authoring_note(args: argparse.Namespace, token: object) -> str:
    """Whether the authoring API can write, and where its token came from (never the token)."""
    if not token:
        return "Authoring API: off (read-only; --authoring-token-file FILE turns it on)"
    source = args.authoring_token_file or "$LANTERNA_AUTHORING_TOKEN"
    return f"Authoring API: on (token from {source}); viewers can save presets and annotations"


def _local_note(address: str) -> str:
    """One line on what the built-in server is for, given the address it listens on."""
    try:
        loopback = ipaddress.ip_address(address).is_loopback
    except ValueError:
        loopback = False
    where = (f"Local server for this machine ({address}), for one user"
             if loopback else f"Built-in server, reachable from other machines ({address})")
    return f"{where}; for several users use --workers N (docs/deploy.md)."
