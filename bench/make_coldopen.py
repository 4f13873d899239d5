"""Make the cold-open benchmark's datasets from source files, with ``lanterna import``.

    .venv/bin/python bench/make_coldopen.py ROOT [--size 1024x1024 | --size 4096x3072]
        [--name coldopen] [--quality 90] [--import-arg=--plane-format=auto …]

Writes the sources first, then imports them as a user would, so that each layer's source bytes
are known (the issue's byte target is relative to them):

- ``ROOT/coldopen-sources/NAME/``: the demo tablet (analytic fits of a Lambertian tablet, as in
  ``make_datasets.py``) as ``image.jpg`` (the plain image layer), Relight web-format folders
  (``info.json`` + ``plane_k.jpg``) ``ptm_lrgb``, ``ptm_rgb``, ``hsh9``, ``hsh16``, a JPEG_LRGB
  ``ptm_jpeg.ptm`` and JPEG shape + material maps (``svbrdf``), listed by ``object.json``;
  imported as the dataset ``ROOT/NAME`` (``coldopen``).
- if ``../shared/realdata/chi-ushabti-vase/ushabti.ptm`` exists (``--ushabti PATH``), the real
  JPEG_LRGB PTM and a JPEG of its colour planes (the plain image of the same object), imported as
  ``ROOT/NAME-ushabti``.
- ``ROOT/coldopen-sources/sources.json``: per dataset and layer, the source files and their bytes
  (served at ``/datasets/coldopen-sources/sources.json``, where ``coldopen.mjs`` reads it); a
  second run under another ``--name`` adds its datasets to it.
"""

from __future__ import annotations

import argparse
import json
import shutil
import subprocess
import sys
from pathlib import Path
from typing import Any

import numpy as np
import pyvips

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO))

from make_datasets import hsh_coefficients, lambert_ptm_coefficients, quantise_ptm  # noqa: E402

from lanterna.tiler.demo.tablet import make_demo_object  # noqa: E402
from lanterna.tiler.formats.layouts import encode_normals  # noqa: E402
from lanterna.tiler.formats.ptm import read_ptm  # noqa: E402
from lanterna.tiler.formats.ptm_model import Ptm  # noqa: E402
from lanterna.tiler.formats.relight_web import PTM_TERM_OF  # noqa: E402

USHABTI = REPO.parent / "shared" / "realdata" / "chi-ushabti-vase" / "ushabti.ptm"
#: Layers of the demo object, in manifest order: id → label.
LABELS = {
    "ptm_lrgb": "PTM LRGB (Relight, JPEG planes)",
    "ptm_rgb": "PTM RGB (Relight, JPEG planes)",
    "hsh9": "HSH 9 (Relight, JPEG planes)",
    "hsh16": "HSH 16 (Relight, JPEG planes)",
    "svbrdf": "Shape and material (JPEG maps)",
    "ptm_jpeg": "PTM LRGB (JPEG_LRGB .ptm)",
    "image": "Image (JPEG)",
}


def save_jpeg(path: Path, pixels: np.ndarray, quality: int) -> None:
    """Write an 8-bit (H, W) or (H, W, 3) array as a baseline JPEG."""
    pyvips.Image.new_from_array(np.ascontiguousarray(pixels)).jpegsave(str(path), Q=quality)


def write_relight(folder: Path, planes: list[np.ndarray], rtype: str, colorspace: str,
                  quality: int, fixed: int = 0) -> None:
    """A Relight web-format folder from float planes in Relight's order.

    Each plane is quantised over its own range, ``value = (t − bias)·scale`` with ``t = texel/255``
    (``scale`` = range, ``bias`` = −min/range); the first ``fixed`` planes are already 0–1
    (the base colour of an lrgb PTM) and keep scale 1, bias 0.
    """
    folder.mkdir(parents=True, exist_ok=True)
    h, w = planes[0].shape
    scale, bias, texels = [], [], []
    for i, p in enumerate(planes):
        lo, hi = (0.0, 1.0) if i < fixed else (float(p.min()), float(p.max()))
        span = hi - lo if hi > lo else 1.0
        scale.append(span)
        bias.append(-lo / span)
        texels.append(np.round((p - lo) / span * 255).clip(0, 255).astype(np.uint8))
    for k in range(len(planes) // 3):
        save_jpeg(folder / f"plane_{k}.jpg", np.stack(texels[3 * k : 3 * k + 3], axis=-1), quality)
    info = {"width": w, "height": h, "type": rtype, "colorspace": colorspace,
            "nplanes": len(planes), "format": "jpg", "quality": quality,
            "materials": [{"scale": scale, "bias": bias}]}
    (folder / "info.json").write_text(json.dumps(info, indent=1) + "\n")


def relight_ptm_terms(coef: np.ndarray) -> list[np.ndarray]:
    """Lanterna's PTM coefficients (…, 6) → the six terms in Relight's order 1, u, v, u², uv, v²."""
    return [coef[..., PTM_TERM_OF.index(t)] for t in range(6)]


def write_tablet_sources(folder: Path, width: int, height: int, quality: int) -> dict[str, Any]:
    """Write every source of the demo tablet and its ``object.json``; return the layer table."""
    obj = make_demo_object(width, height)
    n, albedo = obj.normals, obj.albedo.astype(np.float32)
    colour = np.round(np.clip(albedo, 0, 1) * 255).astype(np.uint8)
    lum = lambert_ptm_coefficients(n).astype(np.float32)
    save_jpeg(folder / "image.jpg", colour, quality)
    base = [colour[..., c].astype(np.float32) / 255 for c in range(3)]
    write_relight(folder / "ptm_lrgb", base + relight_ptm_terms(lum), "ptm", "lrgb", quality,
                  fixed=3)
    rgb = albedo[..., :, None] * lum[..., None, :]  # (H, W, 3, 6)
    terms = relight_ptm_terms(rgb)
    write_relight(folder / "ptm_rgb", [terms[t][..., c] for t in range(6) for c in range(3)],
                  "ptm", "rgb", quality)
    for k in (9, 16):
        coef = hsh_coefficients(n, albedo, k)
        write_relight(folder / f"hsh{k}", [coef[..., c, t] for t in range(k) for c in range(3)],
                      "hsh", "rgb", quality)
        del coef
    write_ptm_file(folder / "ptm_jpeg.ptm", Ptm("lrgb", *quantise_ptm(lum), colour), quality)
    lin = np.where(albedo <= 0.04045, albedo / 12.92, ((albedo + 0.055) / 1.055) ** 2.4)
    ks = (obj.specular[..., None] * obj.specular_color[None, None, :]).clip(0, 1)
    maps = {"normals": encode_normals(n), "kd": np.round(lin * 255).astype(np.uint8),
            "ks": np.round(ks * 255).astype(np.uint8),
            "gloss": np.round((1 - obj.specular) * 255).astype(np.uint8)}
    for name, pixels in maps.items():
        save_jpeg(folder / f"svbrdf_{name}.jpg", pixels, quality)
    layers: dict[str, Any] = {
        "ptm_lrgb": {"source": "ptm_lrgb"}, "ptm_rgb": {"source": "ptm_rgb"},
        "hsh9": {"source": "hsh9"}, "hsh16": {"source": "hsh16"},
        "svbrdf": {"type": "svbrdf", "maps": {m: f"svbrdf_{m}.jpg" for m in maps},
                   "inputColorSpace": "linear"},
        "ptm_jpeg": {"source": "ptm_jpeg.ptm"}, "image": {"source": "image.jpg"},
    }
    return layers


def write_ptm_file(path: Path, ptm: Ptm, quality: int) -> None:
    """A JPEG_LRGB ``.ptm`` file, by the tests' PTM writer (the inverse of ``read_ptm``)."""
    from tests.python.fixtures.ptm_writer import write_ptm

    write_ptm(path, ptm, "PTM_FORMAT_JPEG_LRGB", jpeg_quality=quality)


def write_ushabti_sources(folder: Path, ptm_path: Path,
                          quality: int) -> tuple[dict[str, Any], tuple[int, int]]:
    """The real PTM as is, and a JPEG of its colour planes as the plain image of the object;
    the layer table and the object's size."""
    ptm = read_ptm(ptm_path)
    if ptm.rgb is None:
        raise SystemExit(f"{ptm_path}: expected an LRGB PTM (its colour planes are the plain "
                         "image)")
    save_jpeg(folder / "image.jpg", ptm.rgb, quality)
    layers = {"ptm": {"source": str(ptm_path.resolve()), "label": "PTM (JPEG_LRGB, real)"},
              "image": {"source": "image.jpg", "label": "Image (JPEG of the PTM's colour)"}}
    return layers, (ptm.width, ptm.height)


def is_jpeg(path: Path) -> bool:
    """A JPEG image, a JPEG PTM, or a Relight folder's ``info.json`` (beside its JPEG planes)."""
    suffix = path.suffix.lower()
    if suffix == ".ptm":
        with path.open("rb") as f:
            return b"JPEG" in f.read(64)
    return suffix in (".jpg", ".jpeg") or path.name == "info.json"


def source_files(folder: Path, layer: dict[str, Any]) -> list[Path]:
    """The files a layer of ``object.json`` is read from."""
    names = list(layer["maps"].values()) if "maps" in layer else [layer["source"]]
    files: list[Path] = []
    for name in names:
        path = folder / name
        files.extend(sorted(p for p in path.iterdir() if p.is_file()) if path.is_dir() else [path])
    return files


def import_object(root: Path, name: str, label: str, folder: Path, layers: dict[str, Any],
                  import_args: list[str]) -> dict[str, Any]:
    """Write ``object.json``, run ``lanterna import`` on it, return the layers' source bytes."""
    description = {"name": name, "label": label,
                   "layers": [{"id": lid, "label": LABELS.get(lid, lid), **spec}
                              for lid, spec in layers.items()]}
    (folder / "object.json").write_text(json.dumps(description, indent=1) + "\n")
    lanterna = Path(sys.executable).with_name("lanterna")
    command = [str(lanterna), "import", str(folder / "object.json"), "-o", str(root / name),
               "--name", name, "--force", *import_args]
    print("+", " ".join(command), flush=True)
    subprocess.run(command, check=True)
    out: dict[str, Any] = {}
    for lid, spec in layers.items():
        files = source_files(folder, spec)
        jpeg = all(is_jpeg(p) for p in files)
        out[lid] = {"files": [str(p.relative_to(folder)) if p.is_relative_to(folder) else str(p)
                              for p in files],
                    "bytes": sum(p.stat().st_size for p in files),
                    "jpegSourced": jpeg}
    return out


def fresh_folder(path: Path) -> Path:
    """An empty folder at ``path`` (what was there before removed)."""
    shutil.rmtree(path, ignore_errors=True)
    path.mkdir(parents=True)
    return path


def parse_size(text: str) -> tuple[int, int]:
    try:
        w, h = (int(v) for v in text.lower().split("x"))
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected WIDTHxHEIGHT, got {text!r}") from None
    if w <= 0 or h <= 0:
        raise argparse.ArgumentTypeError(f"size must be positive, got {text!r}")
    return w, h


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("root", type=Path, help="data root (what `lanterna serve` serves)")
    parser.add_argument("--size", type=parse_size, default=(1024, 1024),
                        help="WIDTHxHEIGHT of the demo object (1024x1024; 4096x3072 also fits)")
    parser.add_argument("--name", default="coldopen",
                        help="dataset name (coldopen); the real PTM becomes NAME-ushabti")
    parser.add_argument("--quality", type=int, default=90, help="JPEG quality of the sources")
    parser.add_argument("--ushabti", type=Path, default=USHABTI,
                        help="a real JPEG_LRGB PTM imported as a second object, if it exists "
                             "(--ushabti none: skip it)")
    parser.add_argument("--import-arg", action="append", default=[], dest="import_args",
                        help="passed on to `lanterna import` (repeatable), e.g. "
                             "--import-arg=--plane-format=auto")
    args = parser.parse_args()
    sources = args.root / "coldopen-sources"
    # one table for every dataset made into this root (a second size under another --name)
    try:
        table: dict[str, Any] = json.loads((sources / "sources.json").read_text())
    except (OSError, ValueError):
        table = {"datasets": {}}
    made: dict[str, Any] = {}
    width, height = args.size
    folder = fresh_folder(sources / args.name)
    layers = write_tablet_sources(folder, width, height, args.quality)
    made[args.name] = {
        "width": width, "height": height, "reference": "image",
        "layers": import_object(args.root, args.name, f"Demo tablet {width}×{height}, every "
                                "layer type from JPEG sources", folder, layers, args.import_args)}
    if args.ushabti.is_file():
        folder = fresh_folder(sources / f"{args.name}-ushabti")
        layers, (w, h) = write_ushabti_sources(folder, args.ushabti, args.quality)
        made[f"{args.name}-ushabti"] = {
            "width": w, "height": h, "reference": "image",
            "layers": import_object(args.root, f"{args.name}-ushabti",
                                    "Ushabti (real JPEG_LRGB PTM)", folder, layers,
                                    args.import_args)}
    else:
        print(f"{args.ushabti}: not found, the second object (a real PTM) is skipped", flush=True)
    for ds in made.values():
        ds.update(quality=args.quality, importArgs=args.import_args)
    table["datasets"].update(made)
    (sources / "sources.json").write_text(json.dumps(table, indent=1) + "\n")
    for name, ds in made.items():
        for lid, layer in ds["layers"].items():
            print(f"{name}/{lid}: {layer['bytes']:,} source bytes"
                  f"{' (JPEG)' if layer['jpegSourced'] else ''}")


if __name__ == "__main__":
    main()
