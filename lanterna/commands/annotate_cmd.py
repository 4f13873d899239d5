"""``lanterna annotate``: build or list a layer's multi-scale annotation overlay."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from .common import SubParsers, max_pixels_arg

_BUILD = """\
  lanterna annotate build datasets/obj --layer vis --patches patches/
      add patches named L_X_Y_W_H_O_INFO.png (level, full-resolution rectangle, order, free
      text) to layer vis's patch store, datasets/obj.annotations/vis/, and rebuild its overlay
  lanterna annotate build datasets/obj --layer vis --patches patches/ --replace
      the same, but the store first loses every patch it had (the overlay is patches/ alone)
  lanterna annotate build datasets/obj --layer vis
      rebuild the overlay from the store as it is (after dropping files into it, e.g. from GIMP)
  lanterna annotate build datasets/obj --layer vis --gimp levels/ --texts texts.json
      one transparent PNG per level (level_2.png or 2.png), stored as whole-canvas patches;
      texts.json is {"2": {"short": "Cracks", "long": "<p>Cracks in the glaze …</p>"}}
"""
_LIST = """\
  lanterna annotate list datasets/obj                  levels, texts and patches per layer
"""
_NOTE = """
The dataset is rewritten atomically: the previous overlay of the layer stays until the new one is
complete; the patch store is shared with the server's authoring API (docs/annotations.md). Rejected
files are listed one per line; the valid ones are still built (exit status 1).
"""
ANNOTATE_EXAMPLES = "examples:\n" + _BUILD + _LIST + _NOTE
BUILD_EXAMPLES = "examples:\n" + _BUILD + _NOTE
LIST_EXAMPLES = "examples:\n" + _LIST


def register(sub: SubParsers) -> None:
    ann = sub.add_parser("annotate", help="build or list a layer's multi-scale annotation overlay",
                         epilog=ANNOTATE_EXAMPLES,
                         formatter_class=argparse.RawDescriptionHelpFormatter)
    ann_sub = ann.add_subparsers(required=True, metavar="ACTION")
    build = ann_sub.add_parser("build", help="add to a layer's patch store and rebuild its "
                               "overlay",
                               epilog=BUILD_EXAMPLES,
                               formatter_class=argparse.RawDescriptionHelpFormatter)
    build.add_argument("dataset", type=Path, metavar="DATASET", help="dataset folder")
    build.add_argument("--layer", required=True, metavar="ID", help="layer id")
    src = build.add_mutually_exclusive_group()
    src.add_argument("--patches", type=Path, metavar="DIR",
                     help="add the patches of DIR, named L_X_Y_W_H_O_INFO.png (RGBA PNG), to "
                          "the store (same names replaced)")
    src.add_argument("--gimp", type=Path, metavar="DIR",
                     help="folder of one transparent PNG per level: level_L.png or L.png, "
                          "stored as whole-canvas patches (replacing earlier ones)")
    build.add_argument("--replace", action="store_true",
                       help="empty the layer's patch store first")
    max_pixels_arg(build)
    build.add_argument("--texts", type=Path, metavar="FILE",
                       help='JSON {"L": {"short": text, "long": html}}; levels without an entry '
                            "keep their previous texts")
    build.set_defaults(func=run_build)
    lst = ann_sub.add_parser("list", help="show overlay levels, texts and patch counts",
                             epilog=LIST_EXAMPLES,
                             formatter_class=argparse.RawDescriptionHelpFormatter)
    lst.add_argument("dataset", type=Path, metavar="DATASET", help="dataset folder")
    lst.set_defaults(func=run_list)
    # -- the W3C Web Annotation subcommands (export, import) are registered here: ----------
    # from .annotate_w3c import register_w3c
    # register_w3c(ann_sub)


def run_build(args: argparse.Namespace) -> int:
    from lanterna.tiler.overlays.build import OverlayInputError, build_overlays

    try:
        report = build_overlays(args.dataset, args.layer, patches_dir=args.patches,
                                gimp_dir=args.gimp, texts=args.texts, replace=args.replace)
    except OverlayInputError as err:
        for line in err.errors:
            print(f"lanterna: error: {line}", file=sys.stderr)
        raise
    for line in report.warnings:
        print(f"lanterna: warning: {line}", file=sys.stderr)
    for line in report.errors:
        print(f"lanterna: error: {line}", file=sys.stderr)
    levels = ", ".join(str(level) for level in report.levels) or "(none)"
    if report.changed:
        print(f"layer {report.layer}: overlay levels {levels} from {report.patches} patch(es) "
              f"written to {args.dataset} (build {report.build})")
    else:
        print(f"layer {report.layer}: overlay levels {levels} from {report.patches} patch(es) "
              f"already up to date with its patch store (build {report.build})")
    if report.errors:
        print(f"lanterna: {len(report.errors)} file(s) rejected", file=sys.stderr)
        return 1
    return 0


def run_list(args: argparse.Namespace) -> int:
    from lanterna.tiler.overlays.build import overlay_summary

    for row in overlay_summary(args.dataset):
        if not row["levels"]:
            print(f"{row['id']}: no overlay")
            continue
        origin = f" (from {row['source']})" if row["source"] else ""
        print(f"{row['id']}: {len(row['levels'])} level(s), {row['patches']} patch(es){origin}")
        for level in row["levels"]:
            long = " (long text)" if level.get("long") else ""
            print(f"  level {level['level']}  {level['width']}x{level['height']}  "
                  f"{level.get('short') or '-'}{long}")
    return 0
