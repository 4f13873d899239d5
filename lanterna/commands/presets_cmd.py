"""``lanterna presets``: add, list, remove, export and import a dataset's preset library."""

from __future__ import annotations

import argparse
import json
from pathlib import Path
from typing import Any

from lanterna.errors import LanternaInputError

from .common import SubParsers

_ADD = """\
  lanterna presets add datasets/demo --id raking-w --label "Raking light, west" --layer ptm \\
      --mode color --light=-0.95,0.1 --base "Raking light from the left"
      a preset of layer ptm lit from the left, listed in the base-layer menu
  lanterna presets add datasets/demo --id ir --label "Underdrawing" --layer band_ir \\
      --mode color --param gamma=1.4 --lens "Infrared underdrawing" --opacity 0.9
      a preset shown in the lens, listed in the lens menu
"""
_ACTIONS = {
    "list": "  lanterna presets list datasets/demo             the presets, then the base and lens "
            "lists\n",
    "remove": "  lanterna presets remove datasets/demo raking-w  a preset and the entries that use "
              "it\n",
    "export": "  lanterna presets export datasets/demo -o demo-presets.json\n"
              "      the library as a file, to edit or to import into another dataset\n",
    "import": "  lanterna presets import datasets/obj demo-presets.json --merge\n"
              "      add a library file's presets and entries (--replace, the default, replaces "
              "the library)\n",
}
_NOTE = """
The library is checked against the dataset (layer ids, the modes of each layer, light, view)
and the dataset is rewritten atomically: a bad library changes nothing. Format: docs/presets.md.
"""
PRESETS_EXAMPLES = "examples:\n" + _ADD + "".join(_ACTIONS.values()) + _NOTE
ADD_EXAMPLES = "examples:\n" + _ADD + _NOTE


def register(sub: SubParsers) -> None:
    fmt = argparse.RawDescriptionHelpFormatter
    pre = sub.add_parser("presets", help="add, list, remove, export or import a dataset's "
                         "presets", epilog=PRESETS_EXAMPLES, formatter_class=fmt)
    actions = pre.add_subparsers(required=True, metavar="ACTION")
    add = actions.add_parser("add", help="add a preset (and a base or lens entry for it)",
                             epilog=ADD_EXAMPLES, formatter_class=fmt)
    _dataset(add)
    add.add_argument("--id", required=True, help="preset id (letters, digits, . _ -)")
    add.add_argument("--label", required=True, help="the preset's name")
    add.add_argument("--layer", required=True, metavar="ID", help="layer id")
    add.add_argument("--mode", required=True, help="render mode (docs/rendering.md)")
    add.add_argument("--param", action="append", default=[], metavar="NAME=VALUE",
                     help="a render parameter (lightIntensity, gamma, …); repeatable")
    add.add_argument("--light", metavar="LU,LV",
                     help="light direction, lu² + lv² ≤ 1 (write --light=-0.9,0.2 when LU is "
                          "negative)")
    add.add_argument("--view", metavar="X,Y,W,H", help="region of the image, in pixels")
    where = add.add_mutually_exclusive_group()
    where.add_argument("--base", metavar="LABEL", help="also list it in the base menu as LABEL")
    where.add_argument("--lens", metavar="LABEL", help="also list it in the lens menu as LABEL")
    add.add_argument("--opacity", type=float, metavar="O", help="lens opacity 0–1 (with --lens)")
    add.add_argument("--replace", action="store_true", help="replace a preset of the same id")
    add.set_defaults(func=run_add)

    def action(name: str, text: str) -> argparse.ArgumentParser:
        return actions.add_parser(name, help=text, epilog="examples:\n" + _ACTIONS[name],
                                  formatter_class=fmt)

    lst = action("list", "show the presets and the base and lens lists")
    _dataset(lst)
    lst.set_defaults(func=run_list)

    rm = action("remove", "remove a preset and the entries that use it")
    _dataset(rm)
    rm.add_argument("preset_id", metavar="ID", help="preset id")
    rm.set_defaults(func=run_remove)

    exp = action("export", "write the library as a JSON file")
    _dataset(exp)
    exp.add_argument("-o", "--output", type=Path, required=True, metavar="FILE")
    exp.set_defaults(func=run_export)

    imp = action("import", "check a library file against the dataset and store it")
    _dataset(imp)
    imp.add_argument("file", type=Path, metavar="FILE", help="a preset library (.json)")
    how = imp.add_mutually_exclusive_group()
    how.add_argument("--replace", action="store_true",
                     help="the file becomes the library (the default)")
    how.add_argument("--merge", action="store_true",
                     help="add the file's presets (same id: the file's wins) and entries")
    imp.set_defaults(func=run_import)


def _dataset(p: argparse.ArgumentParser) -> None:
    p.add_argument("dataset", type=Path, metavar="DATASET", help="dataset folder")


def preset_from_args(args: argparse.Namespace) -> dict[str, Any]:
    """The preset ``add`` describes (checked later, with the dataset)."""
    preset: dict[str, Any] = {"label": args.label, "layer": args.layer, "mode": args.mode}
    params: dict[str, float] = {}
    for item in args.param:
        name, sep, value = item.partition("=")
        if not sep or not name:
            raise LanternaInputError(None, f"--param wants NAME=VALUE, got {item!r}")
        params[name.strip()] = _number(value, f"--param {name}")
    if params:
        preset["params"] = params
    if args.light is not None:
        preset["light"] = _numbers(args.light, 2, "--light", "LU,LV")
    if args.view is not None:
        preset["view"] = [int(v) if v.is_integer() else v
                          for v in _numbers(args.view, 4, "--view", "X,Y,W,H")]
    return preset


def run_add(args: argparse.Namespace) -> int:
    from lanterna.tiler.presets.edit import add_entry, add_preset
    from lanterna.tiler.presets.store import update_library

    preset = preset_from_args(args)
    if args.opacity is not None and args.lens is None:
        raise LanternaInputError(None, "--opacity needs --lens")

    def change(library: dict[str, Any], _desc: object) -> dict[str, Any]:
        out = add_preset(library, args.id, preset, replace=args.replace)
        if args.base is not None:
            out = add_entry(out, "base", {"label": args.base, "preset": args.id})
        if args.lens is not None:
            entry: dict[str, Any] = {"label": args.lens, "preset": args.id}
            if args.opacity is not None:
                entry["opacity"] = args.opacity
            out = add_entry(out, "lens", entry)
        return out

    library = update_library(args.dataset, change, source=args.dataset)
    listed = f", listed in the {'base' if args.base else 'lens'} menu" \
        if args.base or args.lens else ""
    print(f"{args.dataset}: added preset {args.id}{listed} ({len(library['presets'])} "
          "preset(s))")
    return 0


def run_list(args: argparse.Namespace) -> int:
    from lanterna.tiler.presets.store import dataset_library

    print(format_library(dataset_library(args.dataset)))
    return 0


def format_library(library: dict[str, Any]) -> str:
    """The library as a readable table: the presets, then the base and lens lists."""
    presets = library["presets"]
    if not presets:
        return "no presets (lanterna presets add DATASET --help)"
    rows = [("ID", "LABEL", "LAYER", "MODE")] + [
        (pid, p["label"], p["layer"], p["mode"]) for pid, p in presets.items()]
    widths = [max(len(str(r[i])) for r in rows) for i in range(3)]
    lines = ["  ".join(str(v).ljust(w) for v, w in zip(r[:3], widths, strict=True)) + "  " + r[3]
             for r in rows]
    for which in ("base", "lens"):
        lines.append("")
        lines.append(f"{which} ({len(library[which])}):")
        for i, e in enumerate(library[which], 1):
            layer = e.get("layer", presets[e["preset"]]["layer"])
            opacity = f", opacity {e['opacity']}" if "opacity" in e else ""
            lines.append(f"  {i}. {e['label']}  ({e['preset']} on {layer}{opacity})")
    return "\n".join(lines)


def run_remove(args: argparse.Namespace) -> int:
    from lanterna.tiler.presets.edit import remove_preset
    from lanterna.tiler.presets.store import update_library

    dropped: list[str] = []

    def change(library: dict[str, Any], _desc: object) -> dict[str, Any]:
        out, gone = remove_preset(library, args.preset_id)
        dropped.extend(gone)
        return out

    update_library(args.dataset, change, source=args.dataset)
    also = f"; also removed the entries that used it: {'; '.join(dropped)}" if dropped else ""
    print(f"{args.dataset}: removed preset {args.preset_id}{also}")
    return 0


def run_export(args: argparse.Namespace) -> int:
    from lanterna.tiler.presets.store import dataset_library, write_library_file

    library = dataset_library(args.dataset)
    write_library_file(args.output, library)
    print(f"wrote {args.output} ({len(library['presets'])} preset(s))")
    return 0


def run_import(args: argparse.Namespace) -> int:
    from lanterna.tiler.documents import load_json
    from lanterna.tiler.presets.edit import merge_libraries
    from lanterna.tiler.presets.library import check_library
    from lanterna.tiler.presets.store import update_library

    given = load_json(args.file)

    def change(library: dict[str, Any], desc: dict[str, Any]) -> dict[str, Any]:
        checked = check_library(given, desc, args.file)  # errors name the file, not the merge
        return merge_libraries(library, checked) if args.merge else checked

    library = update_library(args.dataset, change, source=args.file)
    print(f"{args.dataset}: {'merged' if args.merge else 'stored'} {args.file} "
          f"({len(library['presets'])} preset(s), {len(library['base'])} base and "
          f"{len(library['lens'])} lens entries)")
    return 0


def _number(text: str, what: str) -> float:
    try:
        value = float(text)
    except ValueError:
        raise LanternaInputError(None, f"{what}: not a number: {text!r}") from None
    if value != value or value in (float("inf"), float("-inf")):
        raise LanternaInputError(None, f"{what}: not a finite number: {text!r}")
    return value


def _numbers(text: str, count: int, what: str, form: str) -> list[float]:
    parts = text.split(",")
    if len(parts) != count:
        raise LanternaInputError(None, f"{what} wants {form}, got {json.dumps(text)}")
    return [_number(p.strip(), what) for p in parts]
