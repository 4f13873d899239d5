"""Overlay geometry as tables: patch names, level sizes, destination rectangles, clipping, order."""

from __future__ import annotations

import pytest

from lanterna.tiler.overlays import geometry as og

NAMES = {
    # name: (level, x, y, w, h, order, info)
    "0_10_20_30_40_1_crack.png": (0, 10, 20, 30, 40, 1, "crack"),
    "2_0_0_512_256_7_two_words_here.png": (2, 0, 0, 512, 256, 7, "two_words_here"),
    "1_-8_-4_16_16_-2_left edge.PNG": (1, -8, -4, 16, 16, -2, "left edge"),
    "3_5_6_7_8_9.png": (3, 5, 6, 7, 8, 9, ""),
    "0_1_2_3_4_5_.png": (0, 1, 2, 3, 4, 5, ""),
}


@pytest.mark.parametrize("name", NAMES)
def test_patch_names_parse(name: str) -> None:
    p = og.parse_patch_name(name)
    assert (p.level, p.x, p.y, p.w, p.h, p.order, p.info) == NAMES[name]
    assert p.file == name


BAD_NAMES = {
    "notes.txt": "not a .png patch",
    "0_1_2_3_4_5_x.jpg": "not a .png patch",
    "0_1_2_3_4.png": "malformed patch name",
    "a_1_2_3_4_5_x.png": "malformed patch name",
    "-1_0_0_4_4_0_x.png": "malformed patch name",
    "0_1.5_2_3_4_5_x.png": "malformed patch name",
    "0_1_2_-3_4_5_x.png": "malformed patch name",
    "0_1_2_0_4_5_x.png": "patch size 0x4 is empty",
    "0_1_2_3_0_5_x.png": "patch size 3x0 is empty",
}


@pytest.mark.parametrize("name", BAD_NAMES)
def test_malformed_names_say_why(name: str) -> None:
    with pytest.raises(og.PatchNameError, match=BAD_NAMES[name]) as err:
        og.parse_patch_name(name)
    assert "\n" not in str(err.value)


@pytest.mark.parametrize(("name", "level"), [("level_0.png", 0), ("2.png", 2),
                                             ("LEVEL_12.PNG", 12)])
def test_gimp_names(name: str, level: int) -> None:
    assert og.parse_gimp_name(name) == level


@pytest.mark.parametrize("name", ["level_x.png", "level2.png", "2.jpg", "overlay.png"])
def test_bad_gimp_names(name: str) -> None:
    with pytest.raises(og.PatchNameError, match="expected level_L.png or L.png"):
        og.parse_gimp_name(name)


@pytest.mark.parametrize(("w", "h", "level", "size"), [
    (1000, 600, 0, (1000, 600)),
    (1000, 600, 1, (500, 300)),
    (1001, 601, 1, (501, 301)),
    (1001, 601, 3, (126, 76)),
    (5, 3, 4, (1, 1)),
])
def test_level_sizes(w: int, h: int, level: int, size: tuple[int, int]) -> None:
    assert og.level_size(w, h, level) == size


@pytest.mark.parametrize(("factors", "level"), [([1], 0), ([1, 2], 1), ([1, 2, 4, 8], 3)])
def test_max_level(factors: list[int], level: int) -> None:
    assert og.max_level(factors) == level


# (name, canvas w, h) → (dest rectangle, clipped rectangle) or None (wholly outside)
PLACEMENTS: list[tuple[str, int, int, tuple[tuple[int, ...], tuple[int, ...]] | None]] = [
    ("0_10_20_30_40_0_a.png", 100, 100, ((10, 20, 40, 60), (10, 20, 40, 60))),
    # 2^-1: start floored, end ceiled
    ("1_10_20_30_40_0_a.png", 100, 100, ((5, 10, 20, 30), (5, 10, 20, 30))),
    ("1_11_21_30_40_0_a.png", 100, 100, ((5, 10, 21, 31), (5, 10, 21, 31))),
    ("2_3_5_2_2_0_a.png", 100, 100, ((0, 1, 2, 2), (0, 1, 2, 2))),
    ("3_7_9_1_1_0_a.png", 100, 100, ((0, 1, 1, 2), (0, 1, 1, 2))),
    # touching the border exactly: nothing clipped
    ("0_0_0_100_50_0_a.png", 100, 50, ((0, 0, 100, 50), (0, 0, 100, 50))),
    ("0_90_40_10_10_0_a.png", 100, 50, ((90, 40, 100, 50), (90, 40, 100, 50))),
    ("1_98_48_2_2_0_a.png", 99, 49, ((49, 24, 50, 25), (49, 24, 50, 25))),
    # partly outside: clipped to the level image
    ("0_90_40_20_20_0_a.png", 100, 50, ((90, 40, 110, 60), (90, 40, 100, 50))),
    ("0_-5_-6_10_10_0_a.png", 100, 50, ((-5, -6, 5, 4), (0, 0, 5, 4))),
    ("1_-5_-5_10_10_0_a.png", 100, 50, ((-3, -3, 3, 3), (0, 0, 3, 3))),
    # wholly outside
    ("0_100_0_10_10_0_a.png", 100, 50, None),
    ("0_0_50_10_10_0_a.png", 100, 50, None),
    ("0_-10_0_10_10_0_a.png", 100, 50, None),
    ("1_5_3_1_1_0_a.png", 5, 3, None),  # beyond the canvas though the ceil level has room
]


@pytest.mark.parametrize(("name", "w", "h", "expected"), PLACEMENTS)
def test_placement(name: str, w: int, h: int,
                   expected: tuple[tuple[int, ...], tuple[int, ...]] | None) -> None:
    placement = og.place(og.parse_patch_name(name), w, h)
    if expected is None:
        assert placement is None
    else:
        assert placement is not None
        assert (placement.dest, placement.clip) == expected


def test_source_box_is_the_clipped_part_of_the_resized_patch() -> None:
    placement = og.place(og.parse_patch_name("0_-5_-6_10_10_0_a.png"), 100, 50)
    assert placement is not None
    assert placement.size == (10, 10)
    assert placement.source_box == (5, 6, 5, 4)
    right = og.place(og.parse_patch_name("0_90_40_20_20_0_a.png"), 100, 50)
    assert right is not None and right.source_box == (0, 0, 10, 10)


def test_application_order_is_level_then_order_then_name() -> None:
    names = ["1_0_0_1_1_0_z.png", "0_0_0_1_1_5_b.png", "0_0_0_1_1_5_a.png",
             "0_0_0_1_1_-1_c.png", "0_0_0_1_1_10_d.png"]
    ordered = og.application_order(og.parse_patch_name(n) for n in names)
    assert [p.file for p in ordered] == ["0_0_0_1_1_-1_c.png", "0_0_0_1_1_5_a.png",
                                         "0_0_0_1_1_5_b.png", "0_0_0_1_1_10_d.png",
                                         "1_0_0_1_1_0_z.png"]
