"""Each output format's largest side is known before encoding: refused with 400 and a reason,
and the published ``maxWidth``/``maxHeight`` never promise a size some format cannot write."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import pyvips

from lanterna.cli import main
from lanterna.server.app import create_app
from lanterna.server.image_request import (
    ENCODER_MAX_SIDE,
    MAX_SIDE,
    Limits,
    RequestError,
    parse_image_request,
)
from lanterna.server.image_response import encode
from lanterna.tiler.dataset.layers import add_image_layer
from lanterna.tiler.dataset.writer import DatasetWriter

#: Limits far above every encoder's, so that only the encoder check can refuse.
HUGE = Limits(max_width=10**7, max_height=10**7, max_area=10**9)
LIMITED = sorted(fmt for fmt, side in ENCODER_MAX_SIDE.items() if side is not None)


def _strip(width: int, height: int) -> pyvips.Image:
    return pyvips.Image.black(width, height, bands=3).cast("uchar")


@pytest.mark.parametrize("fmt", LIMITED)
@pytest.mark.parametrize("wide", [True, False], ids=["width", "height"])
def test_the_table_is_what_libvips_can_encode(fmt: str, wide: bool) -> None:
    side = ENCODER_MAX_SIDE[fmt]
    assert side is not None
    shape = (side, 1) if wide else (1, side)
    assert len(encode(_strip(*shape), fmt, lossless=False)) > 0
    over = (side + 1, 1) if wide else (1, side + 1)
    with pytest.raises(pyvips.Error):
        encode(_strip(*over), fmt, lossless=False)


@pytest.mark.parametrize("fmt", sorted(set(ENCODER_MAX_SIDE) - set(LIMITED)))
def test_formats_without_a_limit_write_past_every_other_formats(fmt: str) -> None:
    beyond = max(side for side in ENCODER_MAX_SIDE.values() if side is not None) + 1
    assert len(encode(_strip(beyond, 1), fmt, lossless=True)) > 0


@pytest.mark.parametrize("fmt", LIMITED)
def test_a_size_the_encoder_cannot_write_is_400_before_any_pixel(fmt: str) -> None:
    side = ENCODER_MAX_SIDE[fmt]
    assert side is not None
    ok = parse_image_request("full", f"{side},", "0", f"default.{fmt}", side + 10, 4, HUGE)
    assert (ok.width, ok.height) == (side, 4)
    for size, rotation, w, h in ((f"{side + 1},", "0", side + 10, 4),
                                 (f",{side + 1}", "90", 4, side + 10)):
        with pytest.raises(RequestError) as err:
            parse_image_request("full", size, rotation, f"default.{fmt}", w, h, HUGE)
        assert err.value.status == 400
        assert f"is too large for {fmt} (at most {side} pixels on a side)" in err.value.message


def test_every_limited_format_is_offered_within_the_published_limits() -> None:
    assert MAX_SIDE == min(side for side in ENCODER_MAX_SIDE.values() if side is not None)
    assert Limits().max_width == Limits().max_height == MAX_SIDE
    assert Limits(max_width=20_000, max_height=100).encodable() == Limits(
        max_width=MAX_SIDE, max_height=100)


@pytest.fixture(scope="module")
def wide(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A 16384×6 image (wider than WebP can encode) with its TIFF."""
    root = tmp_path_factory.mktemp("wide") / "root"
    stripes = np.zeros((6, 16384, 3), np.uint8)
    stripes[:, ::2] = 255
    with DatasetWriter(root / "obj", name="obj", label="Wide", width=16384, height=6,
                       tiff=True) as ds:
        add_image_layer(ds, pyvips.Image.new_from_array(stripes).copy(interpretation="srgb"),
                        layer_id="pic", fmt="png")
    return root


@pytest.mark.parametrize("config", [{}, {"IIIF_MAX_WIDTH": 20_000, "IIIF_MAX_HEIGHT": 20_000}],
                         ids=["defaults", "configured-above"])
def test_max_of_a_16384_wide_image_is_served_in_every_format(wide: Path,
                                                           config: dict[str, int]) -> None:
    client = create_app({"DATA_ROOT": wide, **config}).test_client()
    info = client.get("/iiif/3/obj/pic/info.json").get_json()
    assert (info["maxWidth"], info["maxHeight"]) == (MAX_SIDE, MAX_SIDE)
    assert "webp" in info["extraFormats"]
    for fmt in ("jpg", "png", "webp", "tif"):
        resp = client.get(f"/iiif/3/obj/pic/full/max/0/default.{fmt}")
        assert resp.status_code == 200, (fmt, resp.data)
        assert pyvips.Image.new_from_buffer(resp.data, "").width == MAX_SIDE
        over = client.get(f"/iiif/3/obj/pic/full/16384,/0/default.{fmt}")
        assert over.status_code == 400 and b"exceeds the limits (maxWidth 16383" in over.data


def test_serve_refuses_a_max_size_no_format_could_honour(
        tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["serve", str(tmp_path), "--max-size", str(MAX_SIDE + 1)]) == 2
    assert capsys.readouterr().err == (
        f"lanterna: error: --max-size must be between 1 and {MAX_SIDE} (the largest side the "
        "image server can encode in every format it offers, WebP's)\n")
