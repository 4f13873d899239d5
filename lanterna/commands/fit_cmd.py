"""``lanterna fit``: relightable layers from a multi-light image folder."""

from __future__ import annotations

import argparse
from pathlib import Path

from .common import SubParsers, check_tile_size, dataset_args

FIT_EXAMPLES = """examples:
  lanterna fit photos/ --lp photos/lights.lp --model ptm --model hsh --model normals -o datasets/obj
      fit three layers from one load of the images; prints and stores (lanterna.json "quality")
      the PSNR of each model on every 10th light, held out of a separate fit
  lanterna fit photos/ --lp lights.lp --model hsh --terms 16 -o datasets/obj16
"""


def register(sub: SubParsers) -> None:
    fit = sub.add_parser("fit", help="fit PTM/HSH/normals layers to a multi-light image folder",
                         epilog=FIT_EXAMPLES, formatter_class=argparse.RawDescriptionHelpFormatter)
    fit.add_argument("images", type=Path, metavar="IMAGES_DIR",
                     help="folder of photographs, one per light (JPEG/PNG/TIFF, 8 or 16 bit)")
    fit.add_argument("--lp", type=Path, required=True, metavar="LIGHTS.lp",
                     help="light file: a count line, then 'filename x y z' rows")
    fit.add_argument("--model", action="append", required=True,
                     choices=["ptm", "ptm-lrgb", "hsh", "normals", "ward"],
                     help="model to fit; repeat for several (one load of the images)")
    fit.add_argument("--terms", type=int, default=9, choices=[4, 9, 16],
                     help="HSH terms (default 9)")
    dataset_args(fit, label_default="the image folder's name")
    fit.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    from lanterna.tiler.fit import fit_collection

    check_tile_size(args.tile_size)
    fit_collection(args.images, args.lp, args.model, args.output, terms=args.terms,
                   name=args.name, label=args.label, base_url=args.base_url,
                   tile_size=args.tile_size, force=args.force, report=print)
    print(f"wrote {args.output}")
    return 0
