"""``lanterna import``: sources (.ptm, .rti, Relight, maps, images, descriptions) as layers."""

from __future__ import annotations

import argparse
from pathlib import Path

from lanterna.errors import LanternaInputError

from .common import SubParsers, check_tile_size, dataset_args


def register(sub: SubParsers, epilog: str) -> None:
    imp = sub.add_parser("import", help="import sources as the layers of one dataset",
                         epilog=epilog, formatter_class=argparse.RawDescriptionHelpFormatter)
    imp.add_argument("sources", type=Path, nargs="*", metavar="SOURCE",
                     help=".ptm, .rti, a Relight folder, an image, or a description .json; "
                          "several sources become several layers (the first is the default)")
    imp.add_argument("--band", action="append", default=[], metavar="NAME=FILE",
                     help="a spectral band (single-band image) shown as a grey layer; repeatable")
    imp.add_argument("--fusion", action="append", default=[], metavar="A,B,C",
                     help="a false-colour layer from three bands mapped to R,G,B; repeatable")
    dataset_args(imp, label_default="the source's name")
    imp.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    from lanterna.tiler.ingest.importer import import_sources

    check_tile_size(args.tile_size)
    bands: dict[str, Path] = {}
    for item in args.band:
        band, sep, file = item.partition("=")
        if not sep or not band or not file:
            raise LanternaInputError(None, f"--band wants NAME=FILE, got {item!r}")
        bands[band] = Path(file)
    fusions = [tuple(part.strip() for part in f.split(",")) for f in args.fusion]
    if not args.sources and not bands:
        raise LanternaInputError(None, "nothing to import: give a SOURCE or --band NAME=FILE")
    out = import_sources(args.sources, args.output, name=args.name, label=args.label,
                         bands=bands, fusions=fusions, base_url=args.base_url,
                         tile_size=args.tile_size, force=args.force, tiff=args.tiff)
    print(f"wrote {out}")
    return 0
