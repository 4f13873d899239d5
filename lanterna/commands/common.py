"""Options shared by several commands."""

from __future__ import annotations

import argparse
import math
import sys
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any, TypeAlias, TypeVar

from lanterna.errors import LanternaInputError
from lanterna.manifests import metadata as md
from lanterna.tiler.dataset.writer import DEFAULT_BASE_URL
from lanterna.tiler.limits import DEFAULT_MAX_PIXELS, ENVIRONMENT

#: What ``sub.add_parser`` is called on.
SubParsers: TypeAlias = "argparse._SubParsersAction[argparse.ArgumentParser]"
T = TypeVar("T")


def dataset_args(p: argparse.ArgumentParser, *, label_default: str) -> None:
    """The options of every command that writes a dataset (import, fit)."""
    p.add_argument("-o", "--output", type=Path, required=True, help="dataset folder to create")
    p.add_argument("--name", help="dataset name in URLs (default: the output folder's name)")
    p.add_argument("--label", help=f"human-readable label (default: {label_default})")
    p.add_argument("--base-url", default=DEFAULT_BASE_URL,
                   help=f"URL the data root is published at (default {DEFAULT_BASE_URL})")
    p.add_argument("--tile-size", type=int, default=256, help="tile size (default 256)")
    p.add_argument("--force", action="store_true", help="replace an existing output")
    p.add_argument("--tiff", action="store_true",
                   help="also write a pyramidal TIFF per image (tiff/<image>.tif) for the IIIF "
                        "image server at /iiif/3/ (and IIPImage or Cantaloupe)")
    p.add_argument("--plane-format", default="auto", metavar="auto|png|webp|jpg[:Q]",
                   help="tile format of relightable layers' planes (default auto: by source, "
                        "lossy sources within a stated error bound; docs/dataset-format.md)")
    p.add_argument("--pixel-size", type=_pixel_size, default=None, metavar="MM",
                   help="the physical size of one pixel on the object, in millimetres (a scale "
                        "bar in the viewers; default: a Relight source's pixelSizeInMM, else "
                        "none)")
    max_pixels_arg(p)
    publication_args(p)


def publication_args(p: argparse.ArgumentParser) -> None:
    """What the manifest tells a portal (docs/dataset-format.md, "Manifest metadata"); a
    description file's fields of the same names are used for the options not given."""
    g = p.add_argument_group("manifest metadata (what a portal shows; default: none of them, "
                             "and a thumbnail of the first layer)")
    g.add_argument("--summary", metavar="TEXT", help="a summary (HTML allowed)")
    g.add_argument("--rights", type=_checked(md.check_rights), metavar="URI",
                   help="licence or rights statement: a Creative Commons or RightsStatements.org "
                        "URI, e.g. http://creativecommons.org/licenses/by/4.0/")
    g.add_argument("--attribution", type=_checked(md.check_text), metavar="TEXT",
                   help="the attribution to show with the object (requiredStatement)")
    g.add_argument("--provider", type=_checked(md.parse_provider), metavar="NAME[,URL[,LOGO]]",
                   help="the institution publishing it, with its homepage and logo URLs")
    g.add_argument("--homepage", type=_checked(md.check_url), metavar="URL",
                   help="the object's web page")
    g.add_argument("--see-also", type=_checked(md.check_url), action="append", default=[],
                   metavar="URL", help="a machine-readable description of it; repeatable")
    g.add_argument("--metadata", type=_checked(md.parse_metadata), action="append", default=[],
                   metavar="LABEL=VALUE", help="a label and value pair to show; repeatable")


def publication_of(args: argparse.Namespace) -> dict[str, Any]:
    """The ``publication`` object of the options given (lanterna.manifests.metadata)."""
    given = {"rights": args.rights, "attribution": args.attribution, "provider": args.provider,
             "homepage": args.homepage, "seeAlso": args.see_also, "metadata": args.metadata}
    return {k: v for k, v in given.items() if v}


def _checked(check: Callable[[str], T]) -> Callable[[str], T]:
    """An argparse ``type`` from a check that raises ValueError (its message becomes argparse's)."""
    def parse(text: str) -> T:
        try:
            return check(text)
        except ValueError as err:
            raise argparse.ArgumentTypeError(str(err)) from None
    parse.__name__ = check.__name__
    return parse


def max_pixels_arg(p: argparse.ArgumentParser) -> None:
    """``--max-pixels``: the largest image any reader decodes (lanterna.tiler.limits)."""
    p.add_argument("--max-pixels", type=int, default=None, metavar="N",
                   help=f"refuse images over N pixels (default {DEFAULT_MAX_PIXELS:,}, "
                        f"or ${ENVIRONMENT}); guards against corrupt headers and "
                        "decompression bombs")


def check_tile_size(tile_size: int) -> None:
    """Refuse a tile size outside 64–4096."""
    if tile_size < 64 or tile_size > 4096:
        raise LanternaInputError(None, "--tile-size must be between 64 and 4096")


def serve_args(p: argparse.ArgumentParser) -> None:
    """The options of every command that runs the server (serve, demo)."""
    p.add_argument("--host", default="127.0.0.1", help="interface to bind (default 127.0.0.1)")
    p.add_argument("--port", type=_port, default=8000, help="port (default 8000; 0: any free one)")
    p.add_argument("-v", "--verbose", action="store_true",
                   help="log every request, one line each (errors are always logged)")


def _pixel_size(text: str) -> float:
    try:
        mm = float(text)
    except ValueError:
        mm = -1.0
    if not (math.isfinite(mm) and mm > 0):
        raise argparse.ArgumentTypeError(f"not a positive number of millimetres: {text!r}")
    return mm


def _port(text: str) -> int:
    try:
        port = int(text)
    except ValueError:
        port = -1
    if not 0 <= port <= 65535:
        raise argparse.ArgumentTypeError(f"not a port number (0-65535): {text!r}")
    return port


@contextmanager
def annotations_set_aside(out: Path, force: bool) -> Iterator[None]:
    """Around a ``--force`` write over an existing dataset: its patch store (its annotations,
    which belong to the object it was) is moved aside first, put back if the write fails, and
    the user is told where it went (docs/annotations.md, "The patch store")."""
    from lanterna.tiler.overlays.store_files import restore_store, retire_store, store_root

    aside = retire_store(out) if force and (Path(out) / "lanterna.json").is_file() else None
    try:
        yield
    except BaseException:
        if aside is not None:
            restore_store(out, aside)
        raise
    if aside is not None:
        print(f"lanterna: warning: the replaced dataset's annotations were moved to {aside}; if "
              f"it is the same object, move them back: mv {aside} {store_root(out)}",
              file=sys.stderr)
