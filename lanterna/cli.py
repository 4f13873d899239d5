"""The ``lanterna`` command line: import, fit, annotate, serve, demo."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from lanterna.tiler.dataset import DEFAULT_BASE_URL
from lanterna.tiler.errors import LanternaInputError

FIT_EXAMPLES = """examples:
  lanterna fit photos/ --lp photos/lights.lp --model ptm --model hsh --model normals -o datasets/obj
      fit three layers from one load of the images; prints and stores (lanterna.json "quality")
      the PSNR of each model on every 10th light, held out of a separate fit
  lanterna fit photos/ --lp lights.lp --model hsh --terms 16 -o datasets/obj16
"""

ANNOTATE_EXAMPLES = """examples:
  lanterna annotate build datasets/obj --layer vis --patches patches/
      composite patches named L_X_Y_W_H_O_INFO.png (level, full-resolution rectangle, order,
      free text) into the overlay levels of layer vis
  lanterna annotate build datasets/obj --layer vis --gimp levels/ --texts texts.json
      one transparent PNG per level (level_2.png or 2.png); texts.json is
      {"2": {"short": "Cracks", "long": "<p>Cracks in the glaze …</p>"}}
  lanterna annotate list datasets/obj                  levels, texts and patches per layer

The dataset is rewritten atomically: the previous overlay of the layer stays until the new one is
complete. Rejected files are listed one per line; the valid ones are still built (exit status 1).
"""

EXAMPLES = """examples:
  lanterna import ushabti.ptm -o datasets/ushabti     tile a PTM as a relightable IIIF dataset
  lanterna import vase.rti -o datasets/vase           an HSH .rti (4/9/16 terms)
  lanterna import vis.ptm vis.rti uv.png -o datasets/obj   several co-registered layers
  lanterna import object.json -o datasets/obj         a dataset description or a seed-paper scene
  lanterna import --band IR=ir.tif --band R=r.tif --band G=g.tif --fusion IR,R,G -o datasets/ms
                                                      multispectral bands + a false-colour layer
  lanterna fit photos/ --lp lights.lp --model ptm --model normals -o datasets/obj
                                                      fit layers to a multi-light image folder
  lanterna annotate build datasets/obj --layer vis --patches patches/
                                                      multi-scale annotation overlay of a layer
  lanterna serve datasets/                            serve every dataset on http://127.0.0.1:8000/
  lanterna demo                                       make the demo object and serve it
"""


def main(argv: list[str] | None = None) -> int:
    """Run the CLI; return the exit status."""
    parser = _parser()
    args = parser.parse_args(argv)
    try:
        status: int = args.func(args)
        return status
    except LanternaInputError as err:
        print(f"lanterna: error: {err}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        return 130


def _parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="lanterna", description="Annotated, multi-layered relightable images, as IIIF.",
        epilog=EXAMPLES, formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = parser.add_subparsers(required=True, metavar="COMMAND")

    imp = sub.add_parser("import", help="import sources as the layers of one dataset",
                         epilog=EXAMPLES, formatter_class=argparse.RawDescriptionHelpFormatter)
    imp.add_argument("sources", type=Path, nargs="*", metavar="SOURCE",
                     help=".ptm, .rti, a Relight folder, an image, or a description .json; "
                          "several sources become several layers (the first is the default)")
    imp.add_argument("--band", action="append", default=[], metavar="NAME=FILE",
                     help="a spectral band (single-band image) shown as a grey layer; repeatable")
    imp.add_argument("--fusion", action="append", default=[], metavar="A,B,C",
                     help="a false-colour layer from three bands mapped to R,G,B; repeatable")
    _dataset_args(imp, label_default="the source's name")
    imp.set_defaults(func=_cmd_import)

    _fit_parser(sub)
    _annotate_parser(sub)

    srv = sub.add_parser("serve", help="serve a folder of datasets and the viewer")
    srv.add_argument("root", type=Path, help="folder holding datasets")
    _serve_args(srv)
    srv.set_defaults(func=_cmd_serve)

    demo = sub.add_parser("demo", help="make the demo dataset (if missing) and serve it")
    demo.add_argument("--root", type=Path, default=Path("datasets"),
                      help="data root (default ./datasets)")
    demo.add_argument("--no-serve", action="store_true", help="only build the dataset")
    demo.add_argument("--force", action="store_true", help="rebuild the demo dataset")
    _serve_args(demo)
    demo.set_defaults(func=_cmd_demo)
    return parser


def _fit_parser(sub: argparse._SubParsersAction[argparse.ArgumentParser]) -> None:
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
    _dataset_args(fit, label_default="the image folder's name")
    fit.set_defaults(func=_cmd_fit)


def _cmd_fit(args: argparse.Namespace) -> int:
    from lanterna.tiler.fit import fit_collection

    if args.tile_size < 64 or args.tile_size > 4096:
        raise LanternaInputError(None, "--tile-size must be between 64 and 4096")
    fit_collection(args.images, args.lp, args.model, args.output, terms=args.terms,
                   name=args.name, label=args.label, base_url=args.base_url,
                   tile_size=args.tile_size, force=args.force, report=print)
    print(f"wrote {args.output}")
    return 0


def _annotate_parser(sub: argparse._SubParsersAction[argparse.ArgumentParser]) -> None:
    ann = sub.add_parser("annotate", help="build or list a layer's multi-scale annotation overlay",
                         epilog=ANNOTATE_EXAMPLES,
                         formatter_class=argparse.RawDescriptionHelpFormatter)
    ann_sub = ann.add_subparsers(required=True, metavar="ACTION")
    build = ann_sub.add_parser("build", help="build (or replace) the overlay of one layer",
                               epilog=ANNOTATE_EXAMPLES,
                               formatter_class=argparse.RawDescriptionHelpFormatter)
    build.add_argument("dataset", type=Path, metavar="DATASET", help="dataset folder")
    build.add_argument("--layer", required=True, metavar="ID", help="layer id")
    src = build.add_mutually_exclusive_group(required=True)
    src.add_argument("--patches", type=Path, metavar="DIR",
                     help="folder of patches named L_X_Y_W_H_O_INFO.png (RGBA PNG)")
    src.add_argument("--gimp", type=Path, metavar="DIR",
                     help="folder of one transparent PNG per level: level_L.png or L.png")
    build.add_argument("--texts", type=Path, metavar="FILE",
                       help='JSON {"L": {"short": text, "long": html}}; levels without an entry '
                            "keep their previous texts")
    build.set_defaults(func=_cmd_annotate_build)
    lst = ann_sub.add_parser("list", help="show overlay levels, texts and patch counts")
    lst.add_argument("dataset", type=Path, metavar="DATASET", help="dataset folder")
    lst.set_defaults(func=_cmd_annotate_list)


def _cmd_annotate_build(args: argparse.Namespace) -> int:
    from lanterna.tiler.overlays import OverlayInputError, build_overlays

    try:
        report = build_overlays(args.dataset, args.layer, patches_dir=args.patches,
                                gimp_dir=args.gimp, texts=args.texts)
    except OverlayInputError as err:
        for line in err.errors:
            print(f"lanterna: error: {line}", file=sys.stderr)
        raise
    for line in report.warnings:
        print(f"lanterna: warning: {line}", file=sys.stderr)
    for line in report.errors:
        print(f"lanterna: error: {line}", file=sys.stderr)
    levels = ", ".join(str(level) for level in report.levels)
    print(f"layer {report.layer}: overlay levels {levels} from {report.patches} patch(es) "
          f"written to {args.dataset}")
    if report.errors:
        print(f"lanterna: {len(report.errors)} file(s) rejected", file=sys.stderr)
        return 1
    return 0


def _cmd_annotate_list(args: argparse.Namespace) -> int:
    from lanterna.tiler.overlays import overlay_summary

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


def _dataset_args(p: argparse.ArgumentParser, *, label_default: str) -> None:
    """The options of every command that writes a dataset (import, fit)."""
    p.add_argument("-o", "--output", type=Path, required=True, help="dataset folder to create")
    p.add_argument("--name", help="dataset name in URLs (default: the output folder's name)")
    p.add_argument("--label", help=f"human-readable label (default: {label_default})")
    p.add_argument("--base-url", default=DEFAULT_BASE_URL,
                   help=f"URL the data root is published at (default {DEFAULT_BASE_URL})")
    p.add_argument("--tile-size", type=int, default=256, help="tile size (default 256)")
    p.add_argument("--force", action="store_true", help="replace an existing output")


def _serve_args(p: argparse.ArgumentParser) -> None:
    p.add_argument("--host", default="127.0.0.1", help="interface to bind (default 127.0.0.1)")
    p.add_argument("--port", type=int, default=8000, help="port (default 8000)")


def _cmd_import(args: argparse.Namespace) -> int:
    from lanterna.tiler.importers import import_sources

    if args.tile_size < 64 or args.tile_size > 4096:
        raise LanternaInputError(None, "--tile-size must be between 64 and 4096")
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
                         tile_size=args.tile_size, force=args.force)
    print(f"wrote {out}")
    return 0


def _cmd_serve(args: argparse.Namespace) -> int:
    from lanterna.server.app import create_app

    root = args.root.resolve()
    if not root.is_dir():
        raise LanternaInputError(args.root, "not a folder")
    app = create_app({"DATA_ROOT": root})
    url = f"http://{args.host}:{args.port}/"
    for desc in sorted(root.glob("*/lanterna.json")):
        manifest = f"{url}datasets/{desc.parent.name}/manifest.json"
        print(f"  {desc.parent.name}: {url}viewer/?manifest={manifest}")
    print(f"Lanterna serving {root} at {url}  (Ctrl-C to stop)", flush=True)
    app.run(host=args.host, port=args.port, threaded=True)
    return 0


def _cmd_demo(args: argparse.Namespace) -> int:
    from lanterna.tiler.demo import build_demo

    out = args.root / "demo"
    if args.force or not (out / "lanterna.json").is_file():
        print(f"building the demo dataset in {out} …", flush=True)
        build_demo(out, force=True)
    if args.no_serve:
        print(f"demo dataset at {out}")
        return 0
    return _cmd_serve(argparse.Namespace(root=args.root, host=args.host, port=args.port))


if __name__ == "__main__":
    raise SystemExit(main())
