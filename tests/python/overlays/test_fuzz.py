"""Property-based: patch folders with any names and sizes, and any texts, are built or refused.

Patch file names are generated around ``L_X_Y_W_H_O_INFO.png`` — huge, negative or overflowing
rectangles, levels beyond the pyramid, malformed names — on small RGBA drawings; each folder must
give level images and per-file one-line errors, and texts documents (any JSON) their texts or a
one-line error, within the case bounds of ``fixtures/fuzz.py``. (A 30 × 20 drawing named
``…_520_100000_…`` used to take 2.9 GB.)
"""

from __future__ import annotations

import json
import shutil
import tempfile
from pathlib import Path

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from lanterna.tiler.overlays.patches import levels_from_patches, read_texts
from tests.python.fixtures.fuzz import OUTCOMES, bounded, examples, gist, json_values, outcome
from tests.python.fixtures.sources import png

W, H, DEEPEST = 600, 400, 2
numbers = st.one_of(st.integers(-50, 700), st.integers(-50, 700), st.integers(-50, 700),
                    st.sampled_from([0, 2**31, 2**32, 2**63, 10**12, 100000, -100000]))
sizes = st.one_of(st.integers(1, 300), st.integers(1, 300),
                  st.sampled_from([0, 2**32, 10**12, 100000, 520]))
names = st.one_of(
    st.builds(lambda lv, x, y, w, h, o, info: f"{lv}_{x}_{y}_{w}_{h}_{o}{info}.png",
              st.one_of(st.integers(0, 2), st.integers(0, 40)), numbers, numbers, sizes, sizes,
              st.integers(-3, 3), st.sampled_from(["", "_note", "_a_b", "_ü"])),
    st.builds(lambda lv, x, y, w, h, o, info: f"{lv}_{x}_{y}_{w}_{h}_{o}{info}.png",
              st.one_of(st.integers(0, 2), st.integers(0, 40)), numbers, numbers, sizes, sizes,
              st.integers(-3, 3), st.sampled_from(["", "_note", "_a_b", "_ü"])),
    st.text(min_size=1, max_size=30).map(lambda t: t.replace("/", "_").replace("\0", "_") + ".png"))


@settings(max_examples=examples(150))
@given(files=st.lists(st.tuples(names, st.integers(1, 40), st.integers(1, 40)), min_size=1,
                      max_size=3, unique_by=lambda f: f[0]))
def test_patch_folders(files: list[tuple[str, int, int]]) -> None:
    folder = Path(tempfile.mkdtemp())
    for i, (name, w, h) in enumerate(files):
        rgba = np.full((h, w, 4), (255, 0, 0, 200), np.uint8)
        rgba[..., 1] = i * 40
        png(folder / name, rgba)
    counts = OUTCOMES.setdefault("annotation patches", __import__("collections").Counter())
    with bounded():
        levels, patches, errors = levels_from_patches(folder, W, H, DEEPEST)
    for err in errors:
        assert "\n" not in err and str(folder) in err, err
        counts["refused: " + gist(err.rsplit(".png: ", 1)[-1])] += 1
    counts["read"] += len(patches)
    # hidden files (a leading dot) are not patches: everything else is used or reported
    assert len(patches) + len(errors) == sum(not name.startswith(".") for name, _, _ in files)
    for level, image in levels.items():
        assert 0 <= level <= DEEPEST and image.shape[:2] == (-(-H // 2**level), -(-W // 2**level))
    shutil.rmtree(folder)


@settings(max_examples=examples(300))
@given(doc=st.one_of(json_values(3), st.dictionaries(
    st.sampled_from(["0", "1", "2", "3", "10"]),
    st.fixed_dictionaries({}, optional={"short": st.text(max_size=20),
                                        "long": st.text(max_size=40)})), st.dictionaries(
    st.sampled_from(["0", "1", "2", "3", "63", "64", "-1", "x", "01"]),
    st.one_of(json_values(1), st.fixed_dictionaries({}, optional={
        "short": st.one_of(st.text(max_size=20), json_values(0)),
        "long": st.one_of(st.text(max_size=20), json_values(0))})))))
def test_texts_documents(doc: object) -> None:
    folder = Path(tempfile.mkdtemp())
    path = folder / "texts.json"
    path.write_text(json.dumps(doc))
    texts = outcome("annotation texts JSON", path, lambda: read_texts(path))
    if texts is not None:
        assert all(0 <= level < 64 and set(t) == {"short", "long"} for level, t in texts.items())
    shutil.rmtree(folder)


def test_the_reported_huge_patch_rectangles_are_refused_per_file(tmp_path: Path) -> None:
    """The issue's cases: a 30 × 20 drawing named ``…_520_100000_…``, ``…_100000_100000_…`` and
    with W ≥ 2³² — each one refused, in one line, while a normal patch beside them is built."""
    drawing = np.full((20, 30, 4), (0, 0, 255, 255), np.uint8)
    for name in ("0_10_10_520_100000_1_tall.png", "0_10_10_100000_100000_2_huge.png",
                 f"0_10_10_{2**32}_20_3_overflow.png", "0_10_10_30_20_4_fine.png"):
        png(tmp_path / name, drawing)
    with bounded(seconds=10, headroom=1 << 30):
        levels, patches, errors = levels_from_patches(tmp_path, W, H, DEEPEST)
    assert [p.file for p in patches] == ["0_10_10_30_20_4_fine.png"]
    assert len(errors) == 3 and all("would be drawn" in e and "\n" not in e for e in errors)
    assert levels[0][10:30, 10:40, 2].min() == 255
