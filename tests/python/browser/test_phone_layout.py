"""Real Chromium, a phone (390×844, touch): the advanced viewer page's small-screen layout.

Every toolbar button can be tapped (nothing covers its centre), the page does not scroll sideways,
the title stays on one line, the panel starts collapsed and opens as a bottom sheet, and Home fits
the object into the part of the view the toolbar and the panel leave free (read from the pixels).
"""

from __future__ import annotations

from collections.abc import Iterator
from typing import Any

import numpy as np
import pytest

from tests.python.fixtures.lens import Dataset
from tests.python.fixtures.page_script import FRAME, READY, evaluate, frame, run_page
from tests.python.fixtures.servers import LiveServer

pytestmark = pytest.mark.browser

PHONE = (390, 844)

LAYOUT = evaluate("""() => {
  const rect = (el) => {
    const r = el.getBoundingClientRect();
    return [r.left, r.top, r.right, r.bottom];
  };
  const shown = [...document.querySelectorAll('#toolbar button')].filter((b) => !b.hidden);
  const buttons = shown.map((b) => {
    const [l, t, r, bo] = rect(b);
    const hit = document.elementFromPoint((l + r) / 2, (t + bo) / 2);
    return { id: b.id, hit: hit === b || b.contains(hit), width: r - l, height: bo - t };
  });
  const label = document.getElementById('label');
  const panel = document.getElementById('panel');
  return {
    buttons, scrollWidth: document.scrollingElement.scrollWidth,
    label: { height: label.getBoundingClientRect().height,
             cut: label.scrollWidth > label.clientWidth },
    toolbar: rect(document.getElementById('toolbar')),
    panel: panel.hidden ? null : rect(panel),
    expanded: document.getElementById('panel-toggle').getAttribute('aria-expanded'),
    lens: window.lanterna.getLens().enabled,
  };
}""")


@pytest.fixture(scope="module")
def phone_url(lens_dataset: Dataset) -> Iterator[str]:
    server = LiveServer(lens_dataset.root)
    try:
        yield f"{server.url}/viewer/?manifest={server.url}/datasets/lens/manifest.json"
    finally:
        server.close()


def object_box(value: dict[str, Any]) -> tuple[int, int, int, int]:
    """The bounding box (left, top, right, bottom) of the pixels the object covers."""
    px = frame(value)
    mask = px[..., 3] > 0 if (px[..., 3] == 0).any() else (px[..., :3].astype(int).sum(-1) > 0)
    ys, xs = np.nonzero(mask)
    return int(xs.min()), int(ys.min()), int(xs.max()) + 1, int(ys.max()) + 1


@pytest.fixture(scope="module")
def phone(phone_url: str, tmp_path_factory: pytest.TempPathFactory) -> list[Any]:
    folder = tmp_path_factory.mktemp("phone")
    steps = [
        READY, FRAME, LAYOUT,
        {"tap": "#home"}, FRAME, LAYOUT,
        {"tap": "#panel-toggle"}, {"tap": "#home"}, FRAME, LAYOUT,
        {"tap": "#lens"}, LAYOUT,
        {"screenshot": str(folder / "phone.png")},
    ]
    values: list[Any] = run_page(phone_url, steps, folder, PHONE, mobile=True)["values"]
    return values


def test_every_toolbar_button_is_tappable_and_nothing_scrolls_sideways(phone: list[Any]) -> None:
    for layout in (phone[2], phone[9]):
        assert layout["scrollWidth"] <= PHONE[0]
        ids = [b["id"] for b in layout["buttons"]]
        expected = {"panel-toggle", "mode", "home", "zoom-in", "zoom-out", "lens", "overlays"}
        assert expected <= set(ids), ids
        for b in layout["buttons"]:
            assert b["hit"], f"{b['id']} is covered"
            assert b["height"] >= 44 and b["width"] >= 32, b
    assert phone[9]["lens"] is False and phone[11]["lens"] is True, "a tap on Lens switches it on"


def test_the_title_stays_on_one_line(phone: list[Any]) -> None:
    label = phone[2]["label"]
    assert label["height"] < 30, label


def test_the_panel_starts_collapsed_and_opens_as_a_bottom_sheet(phone: list[Any]) -> None:
    assert phone[2]["panel"] is None and phone[2]["expanded"] == "false"
    left, top, right, bottom = phone[9]["panel"]
    assert phone[9]["expanded"] == "true"
    assert (left, right, bottom) == (0, PHONE[0], PHONE[1])
    assert PHONE[1] * 0.3 < top < PHONE[1] * 0.8


def test_home_fits_the_object_into_the_free_area(phone: list[Any]) -> None:
    toolbar_bottom = phone[5]["toolbar"][3]
    left, top, right, bottom = object_box(phone[4])
    assert top >= toolbar_bottom - 1 and bottom <= PHONE[1]
    assert right - left >= PHONE[0] - 2, "the object fills the free width"
    centre = (toolbar_bottom + PHONE[1]) / 2
    assert abs((top + bottom) / 2 - centre) <= 2, "centred in the free area"
    sheet_top = phone[9]["panel"][1]
    left, top, right, bottom = object_box(phone[8])
    assert top >= toolbar_bottom - 1 and bottom <= sheet_top + 1, (top, bottom, sheet_top)
    assert bottom - top >= (sheet_top - toolbar_bottom) * 0.95 or right - left >= PHONE[0] - 2
