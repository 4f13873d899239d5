"""Streaming fit: a tall collection read in row bands fits exactly like the in-memory stack."""

from __future__ import annotations

import json
import tracemalloc
from collections.abc import Callable
from pathlib import Path

import numpy as np
import numpy.typing as npt
import pytest
import pyvips

from lanterna.errors import LanternaInputError
from lanterna.tiler.dataset import layers
from lanterna.tiler.dataset.layers import add_hsh_layer, add_ptm_layer
from lanterna.tiler.dataset.writer import DatasetWriter
from lanterna.tiler.fit import run as fit_run
from lanterna.tiler.fit.engine import fit_stream
from lanterna.tiler.fit.models import model_table
from lanterna.tiler.fit.run import fit_collection
from lanterna.tiler.formats.layouts import encode_normals
from lanterna.tiler.inputs import stack as stack_module
from lanterna.tiler.inputs.lp import read_lp
from lanterna.tiler.inputs.stack import StackReader, load_stack
from tests.python.fixtures.photos import BAND, tall_lights, write_tall_stack
from tests.python.fixtures.photos import TALL_H as H
from tests.python.fixtures.photos import TALL_N as N
from tests.python.fixtures.photos import TALL_W as W
from tests.python.fixtures.stored import stored_format, stored_plane


@pytest.fixture(scope="module")
def collection(tmp_path_factory: pytest.TempPathFactory
               ) -> tuple[list[Path], npt.NDArray[np.float64]]:
    lights = tall_lights()
    return write_tall_stack(tmp_path_factory.mktemp("tall") / "shots", lights), lights


def test_reader_bands_equal_load_stack(collection: tuple[list[Path], npt.NDArray[np.float64]]
                                       ) -> None:
    files, _ = collection
    full = load_stack(files)
    reader = StackReader(files)
    assert reader.shape == full.shape
    bands = [reader[:, y0:y0 + BAND] for y0 in range(0, H, BAND)]
    assert all(b.dtype == np.float32 for b in bands)
    assert np.array_equal(np.concatenate(bands, axis=1), full)
    # a new pass (a read above the current row) reopens the files; subsets and single images
    assert np.array_equal(reader[:, 5:9], full[:, 5:9])
    assert np.array_equal(reader[np.array([3, 1])][:, 990:1000], full[[3, 1], 990:1000])
    assert np.array_equal(reader[7], full[7])


@pytest.mark.parametrize("strip", [1, 3, 8, 64])
def test_bands_read_in_strips_equal_the_whole_images(
        collection: tuple[list[Path], npt.NDArray[np.float64]], strip: int,
        monkeypatch: pytest.MonkeyPatch) -> None:
    """A sequential pass fetches each image's rows from libvips ``FETCH_ROWS`` at a time; any
    strip height, bands not a multiple of it included, gives the images' own bytes."""
    files, _ = collection
    monkeypatch.setattr(stack_module, "FETCH_ROWS", strip)
    reader = StackReader(files)
    whole = np.stack([np.ndarray(buffer=im.write_to_memory(), dtype=np.uint8,
                                 shape=(H, W, 3)) for im in (
        pyvips.Image.new_from_file(str(f)) for f in files)])
    band = np.zeros((N, BAND, W, 3), np.uint8)
    for y0 in range(0, H, BAND):
        rows = min(BAND, H - y0)
        assert reader.band_into(y0, y0 + rows, band[:, :rows]) == 255.0
        assert np.array_equal(band[:, :rows], whole[:, y0:y0 + rows]), y0
    native = reader.native_rows(3, 3 + 2 * strip + 1)  # a new pass, from a row inside a strip
    assert all(np.array_equal(b, whole[i, 3:4 + 2 * strip]) for i, (b, _) in enumerate(native))


@pytest.mark.parametrize("key", ["ptm", "ptm-lrgb", "hsh", "normals", "ward"])
def test_banded_fit_equals_in_memory_fit(
        collection: tuple[list[Path], npt.NDArray[np.float64]], key: str) -> None:
    files, lights = collection
    in_memory = model_table(9)[key].fit(load_stack(files), lights)
    streamed = model_table(9, band_rows=BAND)[key].fit(StackReader(files), lights)
    if key in ("ptm", "ptm-lrgb"):
        assert np.array_equal(streamed.coefficients, in_memory.coefficients)
        assert np.array_equal(streamed.scale, in_memory.scale)
        assert np.array_equal(streamed.bias, in_memory.bias)
        if key == "ptm-lrgb":
            assert np.array_equal(streamed.rgb, in_memory.rgb)
    elif key == "hsh":
        assert np.array_equal(streamed.coefficients, in_memory.coefficients)
        assert np.array_equal(streamed.scale, in_memory.scale)
        assert np.array_equal(streamed.bias, in_memory.bias)
    elif key == "normals":
        assert np.array_equal(encode_normals(streamed.normals),
                              encode_normals(in_memory.normals))
        np.testing.assert_allclose(streamed.albedo, in_memory.albedo, rtol=0, atol=1e-6)
    else:
        for field in ("normals", "kd", "ks", "gloss"):
            assert np.array_equal(getattr(streamed, field), getattr(in_memory, field)), field


def _peak(action: Callable[[], object]) -> int:
    tracemalloc.start()
    try:
        action()
        return tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()


def test_banded_fit_memory_is_bounded(collection: tuple[list[Path], npt.NDArray[np.float64]]
                                      ) -> None:
    files, lights = collection
    full_bytes = N * H * W * 3 * 4
    band_bytes = N * BAND * W * 3 * 4
    reader = StackReader(files)
    read_peak = _peak(lambda: max(float(reader[:, y0:y0 + BAND].max())
                                  for y0 in range(0, H, BAND)))
    fit = model_table(9, band_rows=BAND)["ptm-lrgb"].fit
    fit_peak = _peak(lambda: fit(StackReader(files), lights))
    memory_peak = _peak(lambda: fit(load_stack(files), lights))
    print(f"\nfull stack {full_bytes / 1e6:.2f} MB, one band {band_bytes / 1e6:.2f} MB; peaks: "
          f"banded read pass {read_peak / 1e6:.2f} MB, banded ptm-lrgb fit "
          f"{fit_peak / 1e6:.2f} MB, in-memory ptm-lrgb fit {memory_peak / 1e6:.2f} MB")
    # a read pass holds one band at a time
    assert read_peak < 2 * band_bytes
    # the fit adds only O(H·W) outputs (float coefficients, quantisation temporaries)
    assert fit_peak < 0.5 * full_bytes <= memory_peak


def test_reader_checks_sizes_from_headers(tmp_path: Path) -> None:
    files = write_tall_stack(tmp_path / "shots", tall_lights(3))
    pyvips.Image.black(W, H + 1, bands=3).write_to_file(str(files[2]))
    with pytest.raises(LanternaInputError, match=r"img_002\.png: is 40x1001, but img_000\.png"):
        StackReader(files)


def _plane(ds: Path, image: str) -> npt.NDArray[np.uint8]:
    assert stored_format(ds, image) in ("png", "webp")  # fitted planes: a lossless source
    return stored_plane(ds, image)


def test_lanterna_fit_planes_equal_the_in_memory_fits(
        collection: tuple[list[Path], npt.NDArray[np.float64]], tmp_path: Path,
        monkeypatch: pytest.MonkeyPatch) -> None:
    """One streamed pass for five models (37-row bands): every stored plane, byte for byte."""
    files, lights = collection
    monkeypatch.setattr(layers, "PREVIEW_PIXELS", W * 29)  # previews in 29-row bands
    lp = files[0].parent / "lights.lp"
    lp.write_text(f"{len(files)}\n" + "".join(
        f"{f.name} {x:.9f} {y:.9f} {z:.9f}\n" for f, (x, y, z) in zip(files, lights, strict=True)))
    lights = read_lp(lp, files[0].parent)[1]  # as parsed, to the last bit
    ds = tmp_path / "ds"
    fit_collection(files[0].parent, lp, ["ptm", "ptm-lrgb", "hsh", "normals", "ward"], ds,
                   band_rows=BAND)
    stack = load_stack(files)
    table = model_table(9)
    ptm = table["ptm"].fit(stack, lights)
    for c, name in enumerate("rgb"):
        for g in range(2):
            assert np.array_equal(_plane(ds, f"ptm_{name}{g}"),
                                  ptm.coefficients[:, :, c, 3 * g:3 * g + 3]), (name, g)
    lrgb = table["ptm-lrgb"].fit(stack, lights)
    assert np.array_equal(_plane(ds, "ptm_lrgb_c0"), lrgb.coefficients[..., :3])
    assert np.array_equal(_plane(ds, "ptm_lrgb_c1"), lrgb.coefficients[..., 3:])
    assert np.array_equal(_plane(ds, "ptm_lrgb_color"), lrgb.rgb)
    hsh = table["hsh"].fit(stack, lights)
    for t in range(9):
        assert np.array_equal(_plane(ds, f"hsh9_t{t}"), hsh.coefficients[..., t]), t
    ward = table["ward"].fit(stack, lights)
    assert np.array_equal(_plane(ds, "normals_normals"), encode_normals(ward.normals))
    for m in ("kd", "ks"):
        assert np.array_equal(_plane(ds, f"ward_{m}"), getattr(ward, m)), m
    assert np.array_equal(_plane(ds, "ward_gloss")[..., 0], ward.gloss)
    albedo = table["normals"].fit(stack, lights).albedo
    assert np.array_equal(_plane(ds, "normals_kd"),
                          np.clip(np.round(albedo.astype(np.float64) * 255), 0, 255))
    desc = json.loads((ds / "lanterna.json").read_text())
    services = {layer["id"]: layer["service"] for layer in desc["layers"]}
    stored = services["ptm"]["planes"][0]
    assert stored["scale"] == [float(v) for v in ptm.scale[:3]]
    assert stored["bias"] == [float(v) / 255 for v in ptm.bias[:3]]
    # the normal map is stored once and referenced by both shape layers
    assert (services["normals"]["planes"][0]["service"]["id"]
            == services["ward"]["planes"][0]["service"]["id"])
    assert not list(tmp_path.glob(".lanterna-fit-*")), "scratch folder left behind"
    # the band-wise preview of the file-backed planes equals the whole-image one
    with DatasetWriter(tmp_path / "mem", name="mem", label="mem", width=W, height=H) as mem:
        add_ptm_layer(mem, ptm, layer_id="ptm")
        add_hsh_layer(mem, hsh, layer_id="hsh9")
    for image in ("ptm_preview", "hsh9_preview"):
        streamed = (ds / "iiif" / image / "full/max/0/default.jpg").read_bytes()
        assert streamed == (tmp_path / "mem" / "iiif" / image / "full/max/0/default.jpg"
                            ).read_bytes(), image


def test_wide_collections_are_read_from_tiled_copies_with_the_same_result(
        collection: tuple[list[Path], npt.NDArray[np.float64]], tmp_path: Path,
        monkeypatch: pytest.MonkeyPatch) -> None:
    """Past the decoder budget the images are re-encoded as tiled TIFFs and read file by file
    per band (nothing kept between bands): the planes are unchanged."""
    files, lights = collection
    lp = files[0].parent / "lights.lp"
    lp.write_text(f"{len(files)}\n" + "".join(
        f"{f.name} {x:.9f} {y:.9f} {z:.9f}\n" for f, (x, y, z) in zip(files, lights, strict=True)))
    reader = StackReader(files)
    assert reader.decoder_bytes() == N * W * stack_module.DECODER_BYTES_PER_COLUMN
    fit_collection(files[0].parent, lp, ["ptm", "normals"], tmp_path / "direct", band_rows=BAND)
    made: list[Path] = []
    real = stack_module.to_tiled_tiff
    monkeypatch.setattr(fit_run, "DECODER_BUDGET", reader.decoder_bytes() - 1)
    monkeypatch.setattr(fit_run, "to_tiled_tiff", lambda p, o: made.append(o) or real(p, o))
    fit_collection(files[0].parent, lp, ["ptm", "normals"], tmp_path / "tiled", band_rows=BAND)
    assert len(made) == N and all(not p.exists() for p in made)  # in the removed scratch
    for image in ("ptm_r0", "ptm_g1", "ptm_b0", "normals_normals", "normals_kd"):
        assert np.array_equal(_plane(tmp_path / "direct", image), _plane(tmp_path / "tiled", image))
    tiled = StackReader([stack_module.to_tiled_tiff(f, tmp_path / f"{i}.tif")
                         for i, f in enumerate(files[:3])], reopen=True)
    assert tiled.decoder_bytes() == 0
    assert np.array_equal(tiled[:, 500:537], load_stack(files[:3])[:, 500:537])


def test_bands_as_decoded_in_parallel_equal_the_float_bands(
        collection: tuple[list[Path], npt.NDArray[np.float64]], tmp_path: Path) -> None:
    """A band copied as decoded, its files decoded by a pool of threads, divided by the returned
    divisor, is the float band; a collection mixing sample formats has no common one, is read
    as float, and fits as the same collection all 8-bit does."""
    from concurrent.futures import ThreadPoolExecutor

    files, lights = collection
    full = load_stack(files)
    reader = StackReader(files)
    assert reader.native_dtype() == np.uint8
    with ThreadPoolExecutor(max_workers=3) as pool:
        for y0 in range(0, H, 211):
            y1 = min(H, y0 + 211)
            band = np.zeros((N, y1 - y0, W, 3), np.uint8)
            div = reader.band_into(y0, y1, band, pool if y0 % 2 else None)
            assert div == 255.0
            assert np.array_equal(band.astype(np.float32) / np.float32(div), full[:, y0:y1])
    wide = tmp_path / "sixteen.png"  # x · 257 / 65535 is x / 255: the same floats
    (pyvips.Image.new_from_file(str(files[1])).cast("ushort") * 257).cast("ushort") \
        .pngsave(str(wide))
    mixed = StackReader([files[0], wide, *files[2:]])
    assert mixed.native_dtype() is None
    assert np.array_equal(mixed[:, 40:77], full[:, 40:77])
    (tmp_path / "a").mkdir()
    (tmp_path / "b").mkdir()
    a = fit_stream(mixed, lights, ["ptm", "hsh"], tmp_path / "a", band_rows=BAND,
                   holdout_every=4)
    b = fit_stream(StackReader(files), lights, ["ptm", "hsh"], tmp_path / "b", band_rows=BAND,
                   holdout_every=4)
    assert a.quality == b.quality
    for key in ("ptm", "hsh"):
        for ga, gb in zip(a.layers[key].groups, b.layers[key].groups, strict=True):
            assert ga.scale == gb.scale and ga.bias == gb.bias
            assert np.array_equal(ga.data.rows(0, H), gb.data.rows(0, H))


def test_a_short_first_band_fits_as_whole_bands_do(
        collection: tuple[list[Path], npt.NDArray[np.float64]], tmp_path: Path,
        monkeypatch: pytest.MonkeyPatch) -> None:
    """With automatic band heights the pass reads a first band of one sub-band's rows (the
    solver starts sooner), then whole bands: every layer and report is what bands of one
    height give."""
    from lanterna.tiler.fit import engine
    from lanterna.tiler.progress import Progress

    files, lights = collection
    monkeypatch.setattr(engine, "sub_band_rows", lambda n, width, budget=0: 5)
    done: list[int] = []

    class Recorder(Progress):
        def update(self, rows: int) -> None:
            done.append(rows)

    keys = ["ptm", "ptm-lrgb", "hsh", "normals", "ward"]
    (tmp_path / "auto").mkdir()
    (tmp_path / "fixed").mkdir()
    auto = fit_stream(StackReader(files), lights, keys, tmp_path / "auto", holdout_every=4,
                      progress=lambda label, total: Recorder(label, total))
    assert done[:2] == [5, 5 + engine.auto_band_rows(N, W)]  # then whole bands
    fixed = fit_stream(StackReader(files), lights, keys, tmp_path / "fixed", holdout_every=4,
                       band_rows=engine.auto_band_rows(N, W))
    assert auto.quality.keys() == fixed.quality.keys()
    for key in keys:
        assert auto.quality[key]["psnr"] == pytest.approx(fixed.quality[key]["psnr"], abs=2e-3)
        for ga, gb in zip(auto.layers[key].groups, fixed.layers[key].groups, strict=True):
            assert ga.scale == gb.scale and ga.bias == gb.bias
            assert np.array_equal(ga.data.rows(0, H), gb.data.rows(0, H))


def test_band_spans_cover_the_rows_once() -> None:
    from lanterna.tiler.fit.engine import band_spans

    for height, rows, first in [(1000, 256, 5), (1000, 256, 300), (7, 256, 5), (1, 4, 9),
                                (513, 256, 256)]:
        spans = band_spans(height, rows, first)
        assert spans[0] == (0, min(height, first, rows))
        assert all(a[1] == b[0] for a, b in zip(spans, spans[1:], strict=False))
        assert spans[-1][1] == height
        assert all(0 < y1 - y0 <= rows for y0, y1 in spans[1:])
    assert band_spans(0, 256, 5) == []
