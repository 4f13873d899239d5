"""The ``lanterna`` command line: import, fit, annotate, serve, demo."""

from __future__ import annotations

import argparse
import sys

from lanterna.commands import annotate_cmd, export_cmd, fit_cmd, import_cmd, serve_cmd
from lanterna.errors import LanternaInputError

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
  lanterna export datasets/ --base-url https://example.org/iiif -o site
                                                      static IIIF tree for any web server
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
    import_cmd.register(sub, EXAMPLES)
    fit_cmd.register(sub)
    annotate_cmd.register(sub)
    serve_cmd.register(sub)
    export_cmd.register(sub)
    return parser


if __name__ == "__main__":
    raise SystemExit(main())
