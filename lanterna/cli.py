"""The ``lanterna`` command line: import, fit, annotate, presets, serve, demo, export."""

from __future__ import annotations

import argparse
import sys

from lanterna.commands import (
    annotate_cmd,
    export_cmd,
    fit_cmd,
    import_cmd,
    presets_cmd,
    serve_cmd,
)
from lanterna.errors import LanternaInputError
from lanterna.tiler.limits import set_max_pixels

OVERVIEW = """examples:
  lanterna demo                                     make the demo object and serve it
  lanterna import ushabti.ptm -o datasets/ushabti   tile a PTM as a relightable IIIF dataset
  lanterna serve datasets/                          serve every dataset in datasets/

Each command's options and examples: lanterna COMMAND --help
"""


def main(argv: list[str] | None = None) -> int:
    """Run the CLI; return the exit status."""
    parser = _parser()
    args = parser.parse_args(argv)
    try:
        set_max_pixels(getattr(args, "max_pixels", None))
        status: int = args.func(args)
        return status
    except LanternaInputError as err:
        print(f"lanterna: error: {err}", file=sys.stderr)
        return 2
    except OSError as err:  # one no command turned into its own error: still one line
        where = f"{err.filename}: " if err.filename else ""
        print(f"lanterna: error: {where}{err.strerror or err}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        return 130
    finally:
        set_max_pixels(None)


def _parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="lanterna", description="Annotated, multi-layered relightable images, as IIIF.",
        epilog=OVERVIEW, formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = parser.add_subparsers(required=True, metavar="COMMAND")
    import_cmd.register(sub)
    fit_cmd.register(sub)
    annotate_cmd.register(sub)
    presets_cmd.register(sub)
    serve_cmd.register(sub)
    export_cmd.register(sub)
    return parser


if __name__ == "__main__":
    raise SystemExit(main())
