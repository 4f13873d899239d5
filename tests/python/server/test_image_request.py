"""The pure IIIF image-request parser: every parameter form, its pixels and its error status."""

from __future__ import annotations

import pytest

from lanterna.server.image_request import (
    ImageRequest,
    Limits,
    RequestError,
    max_size,
    parse_image_request,
    parse_quality_format,
    parse_region,
    parse_rotation,
    parse_size,
)

W, H = 1000, 600
UP = Limits(upscaling=True)


@pytest.mark.parametrize("text, box", [
    ("full", (0, 0, 1000, 600)),
    ("square", (200, 0, 600, 600)),
    ("0,0,10,20", (0, 0, 10, 20)),
    ("990,590,50,50", (990, 590, 10, 10)),          # cropped at the edge
    ("999,599,1,1", (999, 599, 1, 1)),
    ("0,0,5000,5000", (0, 0, 1000, 600)),
    ("pct:0,0,100,100", (0, 0, 1000, 600)),
    ("pct:10,50,25,50", (100, 300, 250, 300)),
    ("pct:10.5,0,0.1,0.1", (105, 0, 1, 1)),         # under a pixel rounds up to one
    ("pct:90,90,50,50", (900, 540, 100, 60)),
])
def test_regions(text: str, box: tuple[int, int, int, int]) -> None:
    assert parse_region(text, W, H) == box


def test_square_of_a_tall_image() -> None:
    assert parse_region("square", 300, 1001) == (0, 350, 300, 300)


@pytest.mark.parametrize("text", [
    "", "fulll", "Full", "0,0,10", "0,0,10,10,10", "-1,0,10,10", "0,0,10.5,10", "a,b,c,d",
    "0,0,0,10", "0,0,10,0", "1000,0,10,10", "0,600,10,10", "pct:0,0,0,10", "pct:100,0,10,10",
    "pct:x,0,1,1", "pct:-1,0,1,1", "pct:0,0,10", " 0,0,1,1", "0,0,1,1 ", "%2e%2e", "1e3,0,1,1",
])
def test_bad_regions_are_400(text: str) -> None:
    with pytest.raises(RequestError) as err:
        parse_region(text, W, H)
    assert err.value.status == 400


@pytest.mark.parametrize("text, rw, rh, out", [
    ("max", 1000, 600, (1000, 600)),
    ("500,", 1000, 600, (500, 300)),
    ("333,", 1000, 600, (333, 200)),
    (",300", 1000, 600, (500, 300)),
    ("1,", 1000, 600, (1, 1)),                        # never below one pixel
    ("pct:50", 1000, 600, (500, 300)),
    ("pct:12.5", 1000, 600, (125, 75)),
    ("pct:100", 1000, 600, (1000, 600)),
    ("200,200", 1000, 600, (200, 200)),               # w,h may distort
    ("1000,600", 1000, 600, (1000, 600)),
    ("!500,500", 1000, 600, (500, 300)),              # width binds
    ("!900,300", 1000, 600, (500, 300)),              # height binds
    ("!1000,600", 1000, 600, (1000, 600)),
    ("!100,200", 300, 300, (100, 100)),
])
def test_sizes(text: str, rw: int, rh: int, out: tuple[int, int]) -> None:
    assert parse_size(text, rw, rh, Limits()) == out


@pytest.mark.parametrize("text", [
    "", "full", "MAX", "max ", ",", "!500,", "!,500", "0,", ",0", "0,0", "pct:0", "pct:0.01",
    "pct:", "pct:-5", "-5,", "abc", "10,10,10", "!0,10", "^", "^full", "!!10,10", "pct:1e2",
])
def test_bad_sizes_are_400(text: str) -> None:
    with pytest.raises(RequestError) as err:
        parse_size(text, 1000, 600, UP)
    assert err.value.status == 400


@pytest.mark.parametrize("text", ["1001,", ",601", "1001,600", "pct:100.1", "pct:200",
                                  "!2000,3000", "!1100,1100"])
def test_upscaling_without_caret_is_400(text: str) -> None:
    for limits in (Limits(), UP):
        with pytest.raises(RequestError) as err:
            parse_size(text, 1000, 600, limits)
        assert err.value.status == 400


@pytest.mark.parametrize("text", ["^max", "^500,", "^2000,", "^pct:50", "^!10,10", "^,10"])
def test_caret_is_501_when_upscaling_is_off(text: str) -> None:
    with pytest.raises(RequestError) as err:
        parse_size(text, 1000, 600, Limits())
    assert err.value.status == 501


@pytest.mark.parametrize("text, out", [
    ("^2000,", (2000, 1200)), ("^,1200", (2000, 1200)), ("^pct:200", (2000, 1200)),
    ("^2000,1000", (2000, 1000)), ("^!2000,500", (833, 500)), ("^!2000,3000", (2000, 1200)),
    ("^500,", (500, 300)), ("^max", (5287, 3172)),
])
def test_caret_sizes_when_upscaling_is_on(text: str, out: tuple[int, int]) -> None:
    assert parse_size(text, 1000, 600, UP) == out


def test_limits() -> None:
    small = Limits(max_width=800, max_height=500, max_area=300_000)
    assert max_size(1000, 600, small) == (707, 424)           # the area binds
    assert max_size(1000, 600, Limits(max_width=800)) == (800, 480)
    assert max_size(100, 60, small) == (100, 60)
    assert parse_size("max", 1000, 600, small) == (707, 424)
    w, h = max_size(4097, 4097, Limits())
    assert w * h <= 16 * 1024 * 1024 and (w, h) == (4096, 4096)
    for text in ("801,", ",501", "800,480", "pct:90"):
        with pytest.raises(RequestError) as err:
            parse_size(text, 1000, 600, small)
        assert err.value.status == 400 and "limits" in err.value.message
    assert parse_size("700,400", 1000, 600, small) == (700, 400)


@pytest.mark.parametrize("text, out", [
    ("0", (0, False)), ("90", (90, False)), ("180", (180, False)), ("270", (270, False)),
    ("360", (0, False)), ("!0", (0, True)), ("!90", (90, True)), ("90.0", (90, False)),
    ("0.", (0, False)), ("000", (0, False)),
])
def test_rotations(text: str, out: tuple[int, bool]) -> None:
    assert parse_rotation(text) == out


@pytest.mark.parametrize("text, status", [
    ("45", 501), ("22.5", 501), ("!1", 501), ("359.9", 501), ("361", 400), ("-90", 400),
    ("abc", 400), ("", 400), ("!!90", 400), ("90!", 400), ("1e2", 400), ("9 0", 400),
])
def test_bad_rotations(text: str, status: int) -> None:
    with pytest.raises(RequestError) as err:
        parse_rotation(text)
    assert err.value.status == status


@pytest.mark.parametrize("text, out", [
    ("default.jpg", ("default", "jpg")), ("color.png", ("color", "png")),
    ("gray.webp", ("gray", "webp")), ("bitonal.tif", ("bitonal", "tif")),
])
def test_quality_formats(text: str, out: tuple[str, str]) -> None:
    assert parse_quality_format(text) == out


@pytest.mark.parametrize("text, status", [
    ("default.gif", 501), ("default.jp2", 501), ("default.pdf", 501), ("default.xyz", 400),
    ("grey.jpg", 400), ("native.jpg", 400), ("default", 400), ("default.", 400),
    (".jpg", 400), ("default.JPG", 400), ("default.jpg.png", 400), ("Default.jpg", 400),
])
def test_bad_quality_formats(text: str, status: int) -> None:
    with pytest.raises(RequestError) as err:
        parse_quality_format(text)
    assert err.value.status == status


def test_formats_can_be_restricted() -> None:
    with pytest.raises(RequestError) as err:
        parse_quality_format("default.webp", ("jpg", "png"))
    assert err.value.status == 501


def test_full_request_and_its_canonical_form() -> None:
    req = parse_image_request("pct:10,50,25,50", "!125,125", "!90", "gray.png", W, H)
    assert req == ImageRequest(100, 300, 250, 300, 104, 125, 90, True, "gray", "png")
    assert req.canonical(W, H, Limits()) == "100,300,250,300/104,125/!90/gray.png"
    full = parse_image_request("0,0,1000,600", "1000,", "360", "default.jpg", W, H)
    assert full.canonical(W, H, Limits()) == "full/max/0/default.jpg"
    square = parse_image_request("square", "max", "0", "default.jpg", W, H)
    assert square.canonical(W, H, Limits()) == "200,0,600,600/max/0/default.jpg"
    up = parse_image_request("full", "^2000,", "0", "default.jpg", W, H, UP)
    assert up.canonical(W, H, UP) == "full/^2000,1200/0/default.jpg"
    top = parse_image_request("full", "^max", "0", "default.jpg", W, H, UP)
    assert top.canonical(W, H, UP) == "full/^max/0/default.jpg"


def test_max_is_canonical_for_a_constrained_full_image() -> None:
    small = Limits(max_width=500, max_height=500, max_area=10**6)
    req = parse_image_request("full", "500,300", "0", "default.jpg", W, H, small)
    assert req.canonical(W, H, small) == "full/max/0/default.jpg"


@pytest.mark.parametrize("segments, status", [
    (("nope", "max", "0", "default.jpg"), 400),
    (("full", "nope", "0", "default.jpg"), 400),
    (("full", "max", "nope", "default.jpg"), 400),
    (("full", "max", "0", "nope.jpg"), 400),
    (("full", "max", "45", "default.xyz"), 400),     # syntax beats not-implemented
    (("full", "^max", "45", "default.gif"), 501),
    (("nope", "^max", "0", "default.jpg"), 400),
    (("full", "max", "45", "default.jpg"), 501),
])
def test_request_errors(segments: tuple[str, str, str, str], status: int) -> None:
    with pytest.raises(RequestError) as err:
        parse_image_request(*segments, W, H)
    assert err.value.status == status
