"""``lanterna import``: sources (.ptm, .rti, Relight, maps, images, descriptions) as layers."""

from __future__ import annotations

import argparse
from pathlib import Path

from lanterna.errors import LanternaInputError

from .common import (
    SubParsers,
    annotations_set_aside,
    check_tile_size,
    dataset_args,
    publication_of,
)
from .summary import print_written

IMPORT_EXAMPLES = """examples:
  lanterna import ushabti.ptm -o datasets/ushabti     a PTM (RGB, LRGB, JPEG_LRGB, JPEG_RGB)
  lanterna import vase.rti -o datasets/vase           an HSH .rti (4/9/16 terms)
  lanterna import vis.ptm vis.rti uv.png -o datasets/obj
      several co-registered sources, one layer each (the first is the default)
  lanterna import object.json -o datasets/obj
      a description file (shape + material maps, shared files) or a seed-paper scene
  lanterna import --band IR=ir.tif --band R=r.tif --band G=g.tif --fusion IR,R,G -o datasets/ms
      multispectral bands as grey layers, and a false-colour layer
  lanterna import ushabti.ptm --tiff -o datasets/ushabti
      also a pyramidal TIFF per image, for the IIIF image server at /iiif/3/
  lanterna import vase.rti --plane-format png -o datasets/vase
      PNG plane tiles (default auto: chosen by source, docs/dataset-format.md)
  lanterna import tablet.ptm --pixel-size 0.05 -o datasets/tablet
      one pixel is 0.05 mm on the object: the viewers show a scale bar
  lanterna import https://example.org/iiif/object/manifest.json -o datasets/obj
      an ARCHiOx-style manifest (URL or .json file): its albedo + normal map as one layer
  lanterna import --albedo albedo.png --normal normals.png -o datasets/obj
      a local albedo + normal map pair as one shape + material layer

Every source type and the description file: docs/importing.md.
"""


def register(sub: SubParsers) -> None:
    imp = sub.add_parser("import", help="import sources as the layers of one dataset",
                         epilog=IMPORT_EXAMPLES,
                         formatter_class=argparse.RawDescriptionHelpFormatter)
    imp.add_argument("sources", nargs="*", metavar="SOURCE",
                     help=".ptm, .rti, a Relight folder, an image, a description .json, or an "
                          "ARCHiOx-style IIIF manifest (.json or http(s) URL); several sources "
                          "become several layers (the first is the default)")
    imp.add_argument("--albedo", type=Path, metavar="FILE",
                     help="an albedo (sRGB colour) map: with --normal, one shape + material "
                          "layer (Lambert), after the sources")
    imp.add_argument("--normal", type=Path, metavar="FILE",
                     help="the normal map of --albedo (RGB = (n + 1)/2, 8 or 16 bits)")
    imp.add_argument("--normal-convention", choices=("opengl", "directx"), default="opengl",
                     help="the normal map's y axis: opengl (y up, the default) or directx "
                          "(y down)")
    imp.add_argument("--band", action="append", default=[], metavar="NAME=FILE",
                     help="a spectral band (single-band image) shown as a grey layer; repeatable")
    imp.add_argument("--fusion", action="append", default=[], metavar="A,B,C",
                     help="a false-colour layer from three bands mapped to R,G,B; repeatable")
    dataset_args(imp, label_default="the source's name")
    imp.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    from lanterna.tiler.dataset.plane_format import parse_plane_format
    from lanterna.tiler.ingest.archiox import plan_map_pair
    from lanterna.tiler.ingest.importer import import_sources

    check_tile_size(args.tile_size)
    plane_format = parse_plane_format(args.plane_format)
    bands: dict[str, Path] = {}
    for item in args.band:
        band, sep, file = item.partition("=")
        if not sep or not band or not file:
            raise LanternaInputError(None, f"--band wants NAME=FILE, got {item!r}")
        bands[band] = Path(file)
    fusions = [tuple(part.strip() for part in f.split(",")) for f in args.fusion]
    if (args.albedo is None) != (args.normal is None):
        raise LanternaInputError(None, "--albedo and --normal go together (one map pair)")
    if not args.sources and not bands and args.albedo is None:
        raise LanternaInputError(None, "nothing to import: give a SOURCE, --band NAME=FILE or "
                                 "--albedo FILE --normal FILE")
    pair = [] if args.albedo is None else [plan_map_pair(
        args.albedo, args.normal, normal_convention=args.normal_convention,
        plane_format=plane_format)]
    with annotations_set_aside(args.output, args.force):
        out = import_sources(args.sources, args.output, extra_plans=pair, name=args.name,
                             label=args.label,
                             bands=bands, fusions=fusions, base_url=args.base_url,
                             tile_size=args.tile_size, force=args.force, tiff=args.tiff,
                             plane_format=plane_format, pixel_size_mm=args.pixel_size,
                             summary=args.summary, publication=publication_of(args))
    print_written(out)
    return 0
