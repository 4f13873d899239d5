"""The patch store (tiler/overlays/store.py): records, checks before storing, initialisation."""

from __future__ import annotations

import json
import os
from pathlib import Path

import numpy as np
import pytest
import pyvips

from lanterna.errors import LanternaInputError
from lanterna.tiler.overlays import store
from lanterna.tiler.overlays.build import build_overlays
from lanterna.tiler.overlays.rebuild import rebuild_from_store
from tests.python.fixtures.overlays import H, W, make_dataset, patch, read_image
from tests.python.fixtures.sources import png


@pytest.fixture
def dataset(tmp_path: Path) -> Path:
    return make_dataset(tmp_path / "root")


def square(size: int, rgb: tuple[int, int, int], alpha: int = 255) -> np.ndarray:
    out = np.zeros((size, size, 4), np.uint8)
    out[..., :3], out[..., 3] = rgb, alpha
    return out


def encoded(array: np.ndarray) -> bytes:
    data: bytes = pyvips.Image.new_from_array(array).copy(
        interpretation="srgb" if array.shape[2] >= 3 else "b-w").pngsave_buffer()
    return data


def files(folder: Path) -> list[str]:
    return sorted(p.name for p in folder.iterdir()) if folder.is_dir() else []


def test_the_store_is_a_folder_beside_the_dataset(dataset: Path) -> None:
    assert store.store_dir(dataset, "vis") == dataset.parent.resolve() / "obj.annotations/vis"
    assert not store.store_dir(dataset, "vis").exists()
    with pytest.raises(LanternaInputError, match="layer id"):
        store.store_dir(dataset, "../x")


def test_added_patches_get_the_next_order_and_a_slug_of_their_text(dataset: Path) -> None:
    first = store.add_patch(dataset, "vis", square(10, (255, 0, 0)),
                            {"level": 0, "x": 5, "y": 6, "w": 10, "h": 10,
                             "short": "Crack, près du bord!", "author": "Ada",
                             "state": {"layer": "vis", "mode": "color", "params": {"gain": 2},
                                       "light": [0.1, -0.5]}})
    second = store.add_patch(dataset, "vis", encoded(square(4, (0, 0, 255))),
                             {"level": 1, "x": 0, "y": 0, "w": 8, "h": 8, "motivation": "tagging"})
    assert first["id"] == "0_5_6_10_10_0_Crack-prs-du-bord" and first["order"] == 0
    assert second["id"] == "1_0_0_8_8_1_patch" and second["order"] == 1
    assert first["author"] == "Ada" and first["state"]["light"] == [0.1, -0.5]
    assert second["motivation"] == "tagging" and second["state"] is None
    folder = store.store_dir(dataset, "vis")
    assert files(folder) == ["0_5_6_10_10_0_Crack-prs-du-bord.json",
                             "0_5_6_10_10_0_Crack-prs-du-bord.png", "1_0_0_8_8_1_patch.json",
                             "1_0_0_8_8_1_patch.png"]
    assert json.loads((folder / f"{first['id']}.json").read_text()) == first
    assert store.list_patches(dataset, "vis") == [first, second]
    assert store.get_patch(dataset, "vis", second["id"]) == second
    stored = pyvips.Image.new_from_file(str(store.patch_image(dataset, "vis", first["id"])))
    np.testing.assert_array_equal(stored.numpy(), square(10, (255, 0, 0)))


BAD = [
    ("not a PNG", b"GIF89a not a png at all", {}, "the image is not a PNG"),
    ("no alpha", encoded(np.full((10, 10, 3), 9, np.uint8)), {},
     "the image has no alpha channel (RGB PNG without transparency)"),
    ("outside", encoded(square(10, (1, 2, 3))), {"x": W, "y": 0},
     f"rectangle {W},0,10,10 is outside the {W}x{H} canvas"),
    ("too deep", encoded(square(10, (1, 2, 3))), {"level": 3}, "level 3 is beyond the pyramid"),
    ("wrong size", encoded(square(12, (1, 2, 3))), {},
     "the image is 12x12; rectangle 0,0,10,10 at level 0 is 10x10"),
    ("unknown key", encoded(square(10, (1, 2, 3))), {"colour": "red"},
     "meta: unknown key(s) colour"),
    ("motivation", encoded(square(10, (1, 2, 3))), {"motivation": "painting"},
     "motivation: expected \"commenting\" or \"tagging\""),
    ("long author", encoded(square(10, (1, 2, 3))), {"author": "a" * 201},
     "author: expected a text (at most 200 characters)"),
    ("not a number", encoded(square(10, (1, 2, 3))), {"x": "3"}, "meta.x: expected an integer"),
]


@pytest.mark.parametrize(("image", "meta", "message"), [b[1:] for b in BAD],
                         ids=[b[0] for b in BAD])
def test_a_bad_patch_is_refused_before_anything_is_stored(
        dataset: Path, image: bytes, meta: dict[str, object], message: str) -> None:
    with pytest.raises(store.PatchError) as caught:
        store.add_patch(dataset, "vis", image, {"level": 0, "x": 0, "y": 0, "w": 10, "h": 10,
                                                **meta})
    assert message in str(caught.value) and "\n" not in str(caught.value)
    assert not caught.value.too_large
    assert not store.store_root(dataset).exists()


def test_an_oversize_header_is_refused_as_too_large(dataset: Path) -> None:
    header = encoded(square(2, (1, 2, 3)))
    huge = header[:16] + (9000).to_bytes(4, "big") + (10).to_bytes(4, "big") + header[24:]
    with pytest.raises(store.PatchError, match="9000x10; patch images are at most 8192 px") as e:
        store.add_patch(dataset, "vis", huge, {"level": 0, "x": 0, "y": 0, "w": 10, "h": 10})
    assert e.value.too_large and not store.store_root(dataset).exists()


def test_replace_changes_texts_and_image_not_the_rectangle(dataset: Path) -> None:
    rec = store.add_patch(dataset, "vis", square(10, (255, 0, 0)),
                          {"level": 0, "x": 0, "y": 0, "w": 10, "h": 10, "short": "a"})
    before = store.fingerprint(dataset, "vis")
    new = store.replace_patch(dataset, "vis", rec["id"], meta={"short": "b", "long": "<p>c</p>"},
                              image=square(10, (0, 255, 0)))
    assert (new["id"], new["short"], new["long"], new["created"]) == (rec["id"], "b", "<p>c</p>",
                                                                      rec["created"])
    assert store.fingerprint(dataset, "vis") != before
    with pytest.raises(store.PatchError, match="meta: x cannot change"):
        store.replace_patch(dataset, "vis", rec["id"], meta={"x": 4})
    with pytest.raises(store.PatchError, match="the image is 4x4"):
        store.replace_patch(dataset, "vis", rec["id"], image=square(4, (0, 0, 0)))
    with pytest.raises(store.NoSuchPatch):
        store.replace_patch(dataset, "vis", "0_0_0_1_1_9_none", meta={"short": "x"})
    assert store.get_patch(dataset, "vis", rec["id"])["short"] == "b"
    store.delete_patch(dataset, "vis", rec["id"])
    assert store.list_patches(dataset, "vis") == []
    assert files(store.store_dir(dataset, "vis")) == []
    with pytest.raises(store.NoSuchPatch):
        store.delete_patch(dataset, "vis", rec["id"])


def test_a_same_size_rewrite_within_one_clock_tick_still_changes_the_fingerprint(
        dataset: Path) -> None:
    rec = store.add_patch(dataset, "vis", square(10, (255, 0, 0)),
                          {"level": 0, "x": 0, "y": 0, "w": 10, "h": 10, "short": "aaa"})
    folder = store.store_dir(dataset, "vis")
    seen = {store.fingerprint(dataset, "vis")}
    for text in ("bbb", "ccc", "ddd"):  # same sizes, written as fast as possible
        store.replace_patch(dataset, "vis", rec["id"], meta={"short": text})
        seen.add(store.fingerprint(dataset, "vis"))
    assert len(seen) == 4
    assert not [p for p in folder.iterdir() if p.name.startswith(".tmp-")]


def test_the_first_change_fills_the_store_from_the_published_patches(dataset: Path,
                                                                    tmp_path: Path) -> None:
    gimp = tmp_path / "gimp"
    gimp.mkdir()
    level1 = patch(200, 300, (200, 100, 50), 120, 7)
    png(gimp / "level_1.png", level1)
    build_overlays(dataset, "uv", gimp_dir=gimp, texts={"1": {"short": "one", "long": "<p>1</p>"}})
    store_folder = store.store_dir(dataset, "uv")
    os.rename(store_folder, tmp_path / "gone")  # a store lost, or a dataset copied alone
    published = store.list_patches(dataset, "uv")  # no store: the published overlay's
    assert len(published) == 1 and store.patch_count(dataset, "uv") == 1
    store.add_patch(dataset, "uv", square(4, (0, 0, 255)),
                    {"level": 0, "x": 0, "y": 0, "w": 4, "h": 4})
    assert files(store_folder) == ["0_0_0_4_4_1_patch.json", "0_0_0_4_4_1_patch.png",
                                   f"1_0_0_{W}_{H}_0_level.json", f"1_0_0_{W}_{H}_0_level.png",
                                   "levels.json"]
    assert json.loads((store_folder / "levels.json").read_text()) == {
        "1": {"short": "one", "long": "<p>1</p>"}}
    report = rebuild_from_store(dataset, "uv")
    assert report.levels == [0, 1] and report.build == 2
    np.testing.assert_array_equal(read_image(dataset, "uv_ov1_b2"), level1)


def test_the_first_change_fills_the_store_from_level_images_of_an_old_overlay(
        dataset: Path, tmp_path: Path) -> None:
    gimp = tmp_path / "gimp"
    gimp.mkdir()
    level2 = patch(100, 150, (10, 200, 100), 200, 3)
    png(gimp / "2.png", level2)
    build_overlays(dataset, "vis", gimp_dir=gimp, texts={"2": {"short": "two"}})
    # an overlay written by an earlier Lanterna: no store, no published patch files
    store.store_dir(dataset, "vis").joinpath("2_0_0_600_400_0_level.png").unlink()
    store.store_dir(dataset, "vis").joinpath("levels.json").unlink()
    store.store_dir(dataset, "vis").rmdir()
    store.set_level_texts(dataset, "vis", {"0": {"short": "zero"}})
    folder = store.store_dir(dataset, "vis")
    assert files(folder) == ["2_0_0_600_400_0_level.json", "2_0_0_600_400_0_level.png",
                             "levels.json"]
    assert store.level_texts(dataset, "vis") == {"0": {"short": "zero", "long": ""},
                                                 "2": {"short": "two", "long": ""}}
    stored = pyvips.Image.new_from_file(str(folder / "2_0_0_600_400_0_level.png")).numpy()
    np.testing.assert_array_equal(stored, level2)


def test_a_dropped_file_without_a_record_gets_one_from_its_name(dataset: Path) -> None:
    store.add_patch(dataset, "vis", square(10, (255, 0, 0)),
                    {"level": 0, "x": 0, "y": 0, "w": 10, "h": 10})
    folder = store.store_dir(dataset, "vis")
    png(folder / "0_50_60_20_20_7_from gimp.png", square(20, (0, 255, 0)))
    (folder / "notes.txt").write_text("not a patch")
    records = store.list_patches(dataset, "vis")
    assert [r["id"] for r in records] == ["0_0_0_10_10_0_patch", "0_50_60_20_20_7_from gimp"]
    assert store.patch_count(dataset, "vis") == 2  # notes.txt is not a patch
    dropped = records[1]
    assert (dropped["author"], dropped["short"], dropped["motivation"], dropped["state"],
            dropped["info"]) == ("", "", "commenting", None, "from gimp")
    report = rebuild_from_store(dataset, "vis")
    assert report.patches == 2 and len(report.errors) == 1 and "notes.txt" in report.errors[0]
    assert read_image(dataset, "vis_ov0")[70, 60].tolist() == [0, 255, 0, 255]
