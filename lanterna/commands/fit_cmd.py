"""``lanterna fit``: relightable layers from a multi-light image folder (or one per band)."""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import TYPE_CHECKING

from lanterna.errors import LanternaInputError

if TYPE_CHECKING:
    from lanterna.tiler.fit.run import ImageSet

from .common import (
    SubParsers,
    annotations_set_aside,
    check_tile_size,
    dataset_args,
    publication_of,
)
from .summary import print_written

FIT_EXAMPLES = """examples:
  lanterna fit photos/ --lp photos/lights.lp --model ptm --model hsh --model normals -o datasets/obj
      fit three layers in one pass over the images; prints and stores (lanterna.json "quality")
      the PSNR of each model on every 10th light, held out of a second fit in the same pass
  lanterna fit photos/ --lp lights.lp --model hsh --terms 16 -o datasets/obj16
  lanterna fit photos/ --lp photos/dirs.lp --model rbf --planes 27 -o datasets/obj-rbf
      Relight's RBF basis (PCA over RGB, 27 planes), as OpenLIME and Relight read it
  lanterna fit photos/ --lp lights.lp --model normals --model ward --fit-space linear -o ds/w
      photometric stereo (with IRLS) and Ward in linear light
  lanterna fit --set IR=ir/ --set R=red/ --set G=green/ --lp dome.lp --model ptm \\
      --fusion IR,R,G -o datasets/ms
      one PTM layer per spectral band (ir_ptm, r_ptm, g_ptm) and a false-colour PTM
      (fc_ir_r_g_ptm); a set may name its own light file: --set UV=uv/,uv/uv.lp
"""


def register(sub: SubParsers) -> None:
    fit = sub.add_parser("fit", help="fit PTM/HSH/RBF/bilinear/normals/Ward layers to "
                                     "multi-light images",
                         epilog=FIT_EXAMPLES, formatter_class=argparse.RawDescriptionHelpFormatter)
    fit.add_argument("images", type=Path, metavar="IMAGES_DIR", nargs="?",
                     help="folder of photographs, one per light (JPEG/PNG/TIFF, 8 or 16 bit, "
                          "or camera RAW with rawpy installed)")
    fit.add_argument("--lp", type=Path, metavar="LIGHTS.lp",
                     help="light file: a count line, then 'filename x y z' rows")
    fit.add_argument("--set", action="append", default=[], metavar="BAND=DIR[,LIGHTS.lp]",
                     help="a spectral band's image folder (and light file, default --lp); "
                          "repeat for each band, instead of IMAGES_DIR")
    fit.add_argument("--fusion", action="append", default=[], metavar="A,B,C",
                     help="a false-colour layer per model from three bands (same lights) "
                          "as R, G, B; repeatable")
    fit.add_argument("--model", action="append", required=True,
                     choices=["ptm", "ptm-lrgb", "hsh", "normals", "ward", "rbf", "bilinear"],
                     help="model to fit; repeat for several (one pass over the images; rbf "
                          "and bilinear, PCA bases as Relight's, add a pass sampling pixels)")
    fit.add_argument("--terms", type=int, default=9, choices=[4, 9, 16],
                     help="HSH terms (default 9)")
    fit.add_argument("--planes", metavar="N",
                     help="PCA coefficient planes of rbf/bilinear, 1 to 48 (default 18)")
    fit.add_argument("--colorspace", metavar="SPACE",
                     help="PCA colour space of rbf/bilinear: mrgb (default, one PCA over RGB) "
                          "or mycc (one per YCoCg channel)")
    fit.add_argument("--fit-space", choices=["stored", "linear"], default="stored",
                     help="fit normals/Ward to the values as stored (default, as RTI tools do; "
                          "their layers are shaded as stored) or in linear light (sRGB decoded; "
                          "adds IRLS to the photometric stereo)")
    fit.add_argument("--band-rows", type=int, metavar="N",
                     help="image rows read and solved at once (default: what fits 48 MB)")
    fit.add_argument("--scratch", type=Path, metavar="DIR",
                     help="folder for the temporary planes (default: beside the output); "
                          "needs ~2 bytes per PTM/HSH coefficient per pixel")
    fit.add_argument("--scheduler", metavar="ADDRESS",
                     help="solve the row bands on a Dask cluster (tcp://host:8786, or local[:N] "
                          "for N local worker processes); needs dask[distributed]")
    fit.add_argument("--quiet", action="store_true", help="no progress bars")
    dataset_args(fit, label_default="the image folder's name")
    fit.set_defaults(func=run)


def _sets(args: argparse.Namespace) -> list[ImageSet]:
    from lanterna.tiler.fit.run import ImageSet

    if args.images is not None and args.set:
        raise LanternaInputError(None, "give IMAGES_DIR or --set BAND=DIR, not both")
    if args.images is not None:
        if args.lp is None:
            raise LanternaInputError(None, "--lp LIGHTS.lp is required with IMAGES_DIR")
        return [ImageSet(None, args.images, args.lp)]
    if not args.set:
        raise LanternaInputError(None, "nothing to fit: give IMAGES_DIR or --set BAND=DIR")
    sets: list[ImageSet] = []
    for item in args.set:
        band, sep, rest = item.partition("=")
        folder, _, lp = rest.partition(",")
        if not sep or not band or not folder:
            raise LanternaInputError(None, f"--set wants BAND=DIR[,LIGHTS.lp], got {item!r}")
        if not lp and args.lp is None:
            raise LanternaInputError(None, f"--set {item}: no light file (add ,LIGHTS.lp or "
                                     "--lp)")
        sets.append(ImageSet(band, Path(folder), Path(lp) if lp else args.lp))
    return sets


def run(args: argparse.Namespace) -> int:
    from lanterna.tiler.dataset.plane_format import parse_plane_format
    from lanterna.tiler.fit.run import fit_sets
    from lanterna.tiler.progress import Progress

    check_tile_size(args.tile_size)
    plane_format = parse_plane_format(args.plane_format)
    fusions = [tuple(part.strip() for part in f.split(",")) for f in args.fusion]
    with annotations_set_aside(args.output, args.force):
        fit_sets(_sets(args), args.model, args.output, fusions=fusions,
                 terms=args.terms, name=args.name, label=args.label, base_url=args.base_url,
                 tile_size=args.tile_size, force=args.force, band_rows=args.band_rows,
                 tiff=args.tiff, scratch=args.scratch, fit_space=args.fit_space,
                 scheduler=args.scheduler, plane_format=plane_format, report=print,
                 progress=None if args.quiet else Progress, pixel_size_mm=args.pixel_size,
                 planes=args.planes, colorspace=args.colorspace, summary=args.summary,
                 publication=publication_of(args))
    print_written(args.output)
    return 0
