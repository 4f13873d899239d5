"""The demo dataset: a synthetic relief tablet shown as every kind of layer Lanterna draws.

From one procedural object with known normals, albedo and gloss (:mod:`.demo_object`), rendered
under a dome of lights (:mod:`.demo_render`):

- ``ptm``: an LRGB PTM fitted to the renders (the default layer);
- ``hsh``: a 9-term HSH fitted to the same renders;
- ``rbf``: Relight's default basis, 18 PCA planes interpolated by RBF, fitted to the same renders
  (σ 0.2 rather than Relight's 0.125, which suits ~100 lights: on this 48-light dome 0.2 reproduces
  lights between the dome's best, 31–41 dB against the object's own render, against 27–32 dB);
- ``svbrdf``: shape + material (normal map, kd, ks, gloss; Lambert + Ward);
- ``geometry``: the same normal map alone (default BRDF), stored once with ``svbrdf``;
- ``ir``, ``uv`` and ``R``/``G``/``B`` spectral bands as grey layers, where the infrared band shows
  a preparatory underdrawing invisible in the visible bands and the ultraviolet band shows the
  fluorescing paint; ``fc_ir_r_g``: an infrared false-colour fusion.

It ships a preset library (:mod:`.presets`) and a pixel size of 0.05 mm (a scale bar).
"""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import numpy as np
import numpy.typing as npt
from PIL import Image, ImageDraw

from lanterna.tiler.dataset.layers import (
    add_hsh_layer,
    add_image_layer,
    add_planes_layer,
    add_ptm_layer,
    add_svbrdf_layer,
)
from lanterna.tiler.dataset.writer import DEFAULT_BASE_URL, DatasetWriter
from lanterna.tiler.fit.hsh import fit_hsh
from lanterna.tiler.fit.pca import PcaSpec
from lanterna.tiler.fit.pca_band import fit_pca
from lanterna.tiler.fit.ptm import fit_ptm_lrgb
from lanterna.tiler.formats.layouts import encode_normals
from lanterna.tiler.formats.planes import PlaneLayer
from lanterna.tiler.formats.relight_pca import pca_groups
from lanterna.tiler.iiif.pyramid import vips_from_array
from lanterna.tiler.overlays.composite import premultiply, resize_premultiplied, unpremultiply
from lanterna.tiler.overlays.geometry import Patch, destination
from lanterna.tiler.overlays.rebuild import rebuild_from_store
from lanterna.tiler.overlays.store import (
    add_patch,
    layer_canvas,
    set_level_texts,
    store_dir,
    store_lock,
)

from .dome import demo_lights, render_stack
from .presets import DEMO_PIXEL_MM, DEMO_PUBLICATION, demo_presets
from .tablet import make_demo_object

DEMO_SIZE = (1536, 1152)
N_LIGHTS = 48
#: The demo's edition, in its ``lanterna.json`` ``source``: ``lanterna demo`` and
#: ``make screenshot`` rebuild a demo of another edition (raise it when the demo gains a layer or
#: a preset).
DEMO_SOURCE = "synthetic demo, edition 16"
#: The demo RBF's σ (see the module docstring).
DEMO_RBF_SIGMA = 0.2
F32 = npt.NDArray[np.float32]


def _to_u8(x: npt.NDArray[np.floating]) -> npt.NDArray[np.uint8]:
    out: npt.NDArray[np.uint8] = np.rint(np.clip(x, 0.0, 1.0) * 255.0).astype(np.uint8)
    return out


class _UnitBands:
    """A uint8 stack ``(n, H, W, 3)`` read as float32 0–1 bands (what the fit engine reads)."""

    def __init__(self, stack: npt.NDArray[np.uint8]) -> None:
        self.stack = stack
        self.shape = stack.shape

    def __getitem__(self, key: tuple[slice, slice]) -> F32:
        out: F32 = self.stack[key].astype(np.float32) / np.float32(255)
        return out


def _fit_rbf(stack: npt.NDArray[np.uint8], lights: npt.NDArray[np.float64]) -> PlaneLayer:
    """The demo's RBF layer (18 planes, mrgb) fitted in memory, band by band."""
    fit, planes = fit_pca(_UnitBands(stack), lights, PcaSpec("rbf", sigma=DEMO_RBF_SIGMA))
    scale, bias = fit.scale_bias()
    groups = pca_groups(np.moveaxis(planes, -1, 0), scale, bias, False)
    return PlaneLayer("rbf", groups, colorspace=fit.basis.colorspace, pca=fit.basis)


def _underdrawing(width: int, height: int) -> F32:
    """A hidden preparatory sketch: guide lines and a draft of the inscription, 0–1 strength."""
    img = Image.new("L", (width, height), 0)
    draw = ImageDraw.Draw(img)
    u = width / 1024
    for frac in (0.55, 0.615, 0.775, 0.835):  # ruling lines the carver followed
        y = int(height * frac)
        draw.line([(int(0.12 * width), y), (int(0.88 * width), y)], fill=150, width=max(1, int(u)))
    draw.line([(width // 2, int(0.12 * height)), (width // 2, int(0.9 * height))], fill=110,
              width=max(1, int(u)))
    draw.ellipse([int(0.38 * width), int(0.1 * height), int(0.62 * width), int(0.42 * height)],
                 outline=130, width=max(1, int(2 * u)))
    draw.text((int(0.2 * width), int(0.78 * height)), "Q · FABIVS · FECIT · ANNO · XII",
              fill=190, font_size=int(30 * u))
    return np.asarray(img, np.float32) / 255.0


def demo_is_current(out: Path) -> bool:
    """Whether ``out`` holds a demo dataset of this edition (:data:`DEMO_SOURCE`)."""
    try:
        desc = json.loads((Path(out) / "lanterna.json").read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return False
    return isinstance(desc, dict) and desc.get("source") == DEMO_SOURCE


def build_demo(out: Path, *, base_url: str = DEFAULT_BASE_URL, force: bool = False,
               size: tuple[int, int] = DEMO_SIZE) -> Path:
    """Generate the demo object, fit its layers and write them as dataset ``out``."""
    width, height = size
    obj = make_demo_object(width, height, seed=0)
    lights = demo_lights(N_LIGHTS)
    stack = render_stack(obj, lights)
    ptm = fit_ptm_lrgb(stack, lights)
    hsh = fit_hsh(stack, lights, 9)
    rbf = _fit_rbf(stack, lights)
    del stack

    # The object is shaded in display values (dome.render adds the highlight to the display-
    # referred albedo), so its maps are display values too, declared inputColorSpace "display":
    # the viewer evaluates Lambert + Ward on them as stored. Ward's peak is ks/(4α²), so
    # ks = specular_color·4α² gives the object's highlight colour at the peak.
    albedo = obj.albedo.astype(np.float32)
    gloss_limits = (0.02, 0.5)
    alpha = float(np.sqrt(2.0 / (obj.shininess + 2.0)))  # Ward α matching the Blinn-Phong lobe
    ks = obj.specular[..., None] * (np.asarray(obj.specular_color, np.float32) * 4 * alpha**2)
    gloss = np.where(obj.specular > 0, (alpha - gloss_limits[0]) / (gloss_limits[1] -
                                                                    gloss_limits[0]), 1.0)
    normals = encode_normals(obj.normals)

    luminance = albedo @ np.array([0.2126, 0.7152, 0.0722], np.float32)
    paint = np.clip((albedo[..., 0] - albedo[..., 1]) * 4.0, 0.0, 1.0)  # the reddish traces
    sketch = _underdrawing(width, height) * (obj.height_map > 0)
    ir = np.clip(0.15 + 0.8 * (luminance + 0.35 * paint) - 0.45 * sketch, 0.0, 1.0)
    uv = np.clip(0.08 + 0.12 * luminance + 0.7 * paint + 0.25 * obj.specular, 0.0, 1.0)
    bands = {"ir": ir, "uv": uv, "R": albedo[..., 0], "G": albedo[..., 1], "B": albedo[..., 2]}

    label = "Lanterna demo tablet (synthetic)"
    summary = ("A procedural limestone tablet with an incised, painted inscription and a gold "
               "inlay, shown as a PTM, an HSH, an RBF (Relight's PCA basis), shape + material "
               "maps, spectral bands (the infrared band reveals an underdrawing) and a "
               "false-colour fusion.")
    with DatasetWriter(out, name=Path(out).name, label=label, width=width, height=height,
                       base_url=base_url, source=DEMO_SOURCE, force=force,
                       summary=summary, pixel_size_mm=DEMO_PIXEL_MM,
                       presets=demo_presets(width, height), publication=DEMO_PUBLICATION) as ds:
        add_ptm_layer(ds, ptm, layer_id="ptm", label="Relief tablet (PTM LRGB)")
        add_hsh_layer(ds, hsh, layer_id="hsh", label="Relief tablet (HSH, 9 terms)")
        add_planes_layer(ds, rbf, layer_id="rbf", label="Relief tablet (RBF, 18 PCA planes)")
        share = {"normals": "demo-normals"}
        add_svbrdf_layer(ds, normals=normals, kd=_to_u8(albedo), ks=_to_u8(ks),
                         gloss=_to_u8(gloss), gloss_limits=gloss_limits, input_colorspace="display",
                         share=share, layer_id="svbrdf", label="Shape + material (Ward)")
        add_svbrdf_layer(ds, normals=normals, share=share, layer_id="geometry",
                         label="Geometry only (normal map)")
        for name, band in bands.items():
            add_image_layer(ds, vips_from_array(_to_u8(band)), layer_id=f"band_{name}",
                            label=f"{name.upper()} band", fmt="png")
        fc = np.stack([bands["ir"], bands["R"], bands["G"]], axis=-1)
        add_image_layer(ds, vips_from_array(_to_u8(fc)), layer_id="fc_ir_r_g",
                        label="False colour (IR, R, G)", fmt="png")
    _add_demo_overlays(Path(out), sketch)
    return Path(out)


DEMO_TEXTS = {
    "3": {"short": "An inscribed limestone tablet",
          "long": "<p>A slab with a moulded frame, a gilded rosette and a two-line incised "
                  "inscription. Zoom in: each level of detail has its own annotations.</p>"},
    "2": {"short": "Inscription and inlay",
          "long": "<p><b>LANTERNA</b> / <i>LVX IN TENEBRIS LVCET</i>, V-cut letters with traces "
                  "of red paint; a gold rosette set in a raised medallion.</p>"},
    "1": {"short": "Underdrawing (infrared)",
          "long": "<p>Ruling lines, a compass circle and a draft signature "
                  "<i>Q · FABIVS · FECIT</i>, visible only in the infrared band.</p>"},
    "0": {"short": "Rosette detail",
          "long": "<p>Eight petals and a central boss in gold leaf; burnished highlights move with "
                  "the light.</p>"},
}


#: Render states the demo's patches were "drawn under" (a patch's list entry restores its state).
_RAKING = {"layer": "ptm", "mode": "color", "params": {"lightIntensity": 1.5},
           "light": [-0.94, 0.18]}
_SPECULAR = {"layer": "ptm", "mode": "specular",
             "params": {"specKd": 0.3, "specKs": 1.0, "specExponent": 20}, "light": [0.2, 0.3]}
_OVERHEAD = {"layer": "ptm", "mode": "color", "params": {}, "light": [0.0, 0.0]}
DEMO_AUTHOR = "Lanterna demo"


def _add_demo_overlays(out: Path, sketch: F32) -> None:
    """Annotate the PTM layer at four levels: five patches, each with its note and the render
    state it was drawn under, put in the layer's patch store and built into its overlay pyramid.

    Each patch is drawn at full resolution and reduced to its rectangle at its level as the
    overlay builder reduces a larger patch (premultiplied, linear kernel), so the store holds it
    at the size a browser drawing of it has.
    """
    h, w = sketch.shape
    cyan, magenta, gold = (40, 220, 255), (255, 60, 200), (255, 200, 40)

    def outline(colour: tuple[int, int, int], width: int) -> object:
        return lambda d, bw, bh: d.rounded_rectangle([width, width, bw - width, bh - width],
                                                     radius=4 * width,
                                                     outline=colour + (230,), width=width)

    def drawn(box: tuple[int, int, int, int], draw: object) -> npt.NDArray[np.uint8]:
        img = Image.new("RGBA", box[2:], (0, 0, 0, 0))
        draw(ImageDraw.Draw(img), box[2], box[3])  # type: ignore[operator]
        return np.asarray(img)

    cx, cy, r = int(0.495 * w), int(0.33 * h), int(0.105 * w)
    tint = np.zeros((h, w, 4), np.uint8)
    tint[..., :3] = magenta
    tint[..., 3] = np.rint(np.clip(sketch * 1.6, 0.0, 1.0) * 220).astype(np.uint8)
    tablet = (int(0.08 * w), int(0.08 * h), int(0.84 * w), int(0.84 * h))
    inscription = (int(0.14 * w), int(0.48 * h), int(0.72 * w), int(0.33 * h))
    inlay = (cx - int(1.3 * r), cy - int(1.3 * r), int(2.6 * r), int(2.6 * r))
    rosette = (cx - r, cy - r, 2 * r, 2 * r)
    patches = [
        (3, tablet, drawn(tablet, outline(cyan, 24)), _OVERHEAD, "Moulded frame",
         "<p>The raised frame runs round all four sides; its inner edge is chipped at the "
         "lower right.</p>"),
        (2, inscription, drawn(inscription, outline(cyan, 12)), _RAKING, "Two-line inscription",
         "<p>Read it under raking light from the left: the V-cut strokes cast shadows.</p>"),
        (2, inlay, drawn(inlay, outline(gold, 12)), _SPECULAR, "Gold inlay",
         "<p>Specular enhancement shows the leaf's burnishing marks.</p>"),
        (1, (0, 0, w, h), tint, _OVERHEAD, "Underdrawing traced from the IR band",
         "<p>Traced over the infrared band (the <i>IR band</i> layer, or the lens): ruling "
         "lines, a compass circle and a draft signature.</p>"),
        (0, rosette, drawn(rosette, lambda d, bw, bh: d.ellipse([6, 6, bw - 6, bh - 6],
                                                                outline=gold + (240,), width=6)),
         _SPECULAR, "Rosette", "<p>Eight petals and a central boss in gold leaf.</p>"),
    ]
    with store_lock(out):  # a rebuilt demo starts with only its own notes
        shutil.rmtree(store_dir(out, "ptm"), ignore_errors=True)
    deepest = layer_canvas(out, "ptm").deepest  # a small demo has fewer levels
    for level, (x, y, bw, bh), rgba, state, short, long in patches:
        if level > deepest:
            continue
        x0, y0, x1, y1 = destination(Patch(level, x, y, bw, bh, 0, "", ""))
        small = unpremultiply(resize_premultiplied(premultiply(rgba), x1 - x0, y1 - y0))
        add_patch(out, "ptm", small, {"level": level, "x": x, "y": y, "w": bw, "h": bh,
                                      "short": short, "long": long, "author": DEMO_AUTHOR,
                                      "state": state})
    set_level_texts(out, "ptm", {k: v for k, v in DEMO_TEXTS.items() if int(k) <= deepest})
    rebuild_from_store(out, "ptm")
