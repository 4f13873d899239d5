"""``lanterna annotate export`` / ``import``: a layer's patches as W3C Web Annotations."""

from __future__ import annotations

import argparse
from pathlib import Path

from .common import SubParsers

EXPORT_EXAMPLES = """\
examples:
  lanterna annotate export datasets/obj --layer vis -o vis-notes.json
      the layer's published patches as a W3C / IIIF AnnotationPage: one Annotation per patch
      (its rectangle as an xywh FragmentSelector, its image, texts, author and render state),
      the page the dataset serves at annotations/vis.json
"""
IMPORT_EXAMPLES = """\
examples:
  lanterna annotate import datasets/obj --layer vis annotorious.json
      an AnnotationPage {"type": "AnnotationPage", "items": [...]} from Annotorious, Mirador's
      annotation editor or an export: each Annotation becomes one patch of layer vis (on top
      of the others), then the overlay is rebuilt

Targets: a FragmentSelector xywh=X,Y,W,H (xywh=pixel:..., xywh=percent:...), a canvas URL
ending in #xywh=..., or an SvgSelector (<polygon>, <polyline>, <line>, <path> with straight
segments and curves, <rect>, <circle>, <ellipse>). Each shape is drawn as a translucent fill
and an opaque outline (its own fill and stroke if it has them) at the level its size suggests.
A page with one bad annotation is refused whole, with the file and JSON path of the problem.
"""


def register_w3c(ann_sub: SubParsers) -> None:
    """Add ``export`` and ``import`` to ``lanterna annotate``'s actions."""
    exp = ann_sub.add_parser("export", help="write a layer's patches as a W3C AnnotationPage",
                             epilog=EXPORT_EXAMPLES,
                             formatter_class=argparse.RawDescriptionHelpFormatter)
    exp.add_argument("dataset", type=Path, metavar="DATASET", help="dataset folder")
    exp.add_argument("--layer", required=True, metavar="ID", help="layer id")
    exp.add_argument("-o", "--output", type=Path, required=True, metavar="PAGE",
                     help="the AnnotationPage JSON file to write")
    exp.set_defaults(func=run_export)
    imp = ann_sub.add_parser("import", help="add a W3C AnnotationPage's annotations as patches",
                             epilog=IMPORT_EXAMPLES,
                             formatter_class=argparse.RawDescriptionHelpFormatter)
    imp.add_argument("dataset", type=Path, metavar="DATASET", help="dataset folder")
    imp.add_argument("--layer", required=True, metavar="ID", help="layer id")
    imp.add_argument("page", type=Path, metavar="PAGE", help="an AnnotationPage JSON file")
    imp.set_defaults(func=run_import)


def run_export(args: argparse.Namespace) -> int:
    from lanterna.tiler.overlays.w3c_import import export_page

    count = export_page(args.dataset, args.layer, args.output)
    print(f"wrote {args.output} ({count} annotation(s) of layer {args.layer})")
    return 0


def run_import(args: argparse.Namespace) -> int:
    from lanterna.tiler.overlays.w3c_import import import_page

    report = import_page(args.dataset, args.layer, args.page)
    levels = sorted({r["level"] for r in report.records})
    print(f"layer {args.layer}: {len(report.records)} patch(es) from {args.page} at level(s) "
          f"{', '.join(str(lv) for lv in levels)}; overlay rebuilt")
    return 0
