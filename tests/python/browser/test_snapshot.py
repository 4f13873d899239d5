"""Real Chromium: a snapshot (the S key, the Snapshot button, ``lanterna.snapshot()``) is a PNG of
exactly the pixels ``readPixels`` returns, with what it shows in its text chunks.

The PNG is decoded with pyvips; its chunks are read here with the standard library (CRC checked),
not with the plugin's reader.
"""

from __future__ import annotations

import base64
import struct
import zlib
from collections.abc import Iterator
from pathlib import Path

import numpy as np
import pytest
import pyvips

from tests.python.fixtures.lens import Dataset
from tests.python.fixtures.servers import LiveServer
from tests.python.fixtures.view_tools import frame, run_session

pytestmark = pytest.mark.browser

SETTLED = ("window.lanterna.viewer.element.dataset.lanternaLink !== undefined"
           " && window.lanterna.viewer.element.dataset.lanternaLink === location.hash")


@pytest.fixture(scope="module")
def page_url(lens_dataset: Dataset) -> Iterator[str]:
    server = LiveServer(lens_dataset.root)
    yield f"{server.url}/viewer/?manifest={server.url}/datasets/lens/manifest.json&layer=base"
    server.close()


def png_texts(data: bytes) -> dict[str, str]:
    """The tEXt and uncompressed iTXt chunks of a PNG, every chunk's CRC checked."""
    assert data[:8] == b"\x89PNG\r\n\x1a\n"
    at, texts = 8, {}
    while at < len(data):
        (length,) = struct.unpack(">I", data[at: at + 4])
        kind, body = data[at + 4: at + 8], data[at + 8: at + 8 + length]
        (crc,) = struct.unpack(">I", data[at + 8 + length: at + 12 + length])
        assert zlib.crc32(kind + body) == crc, kind
        if kind == b"iTXt":
            keyword, rest = body.split(b"\0", 1)
            assert rest[:2] == b"\0\0", "uncompressed"
            _lang, _translated, text = rest[2:].split(b"\0", 2)
            texts[keyword.decode("latin-1")] = text.decode("utf-8")
        at += 12 + length
        if kind == b"IEND":
            break
    assert at == len(data), "nothing after IEND"
    return texts


def test_snapshot_png_equals_read_pixels(page_url: str, tmp_path: Path) -> None:
    out = tmp_path / "snap"
    setup = """
      const l = window.lanterna;
      l.setRenderMode('specular'); l.setLight(0.3, 0.4); l.setRenderParams({ specKs: 0.9 });
      l.showImageRegion(200, 150, 500, 375);
      await l.setLens({ enabled: true, center: [500, 300], radius: 90, opacity: 0.5,
                        layer: 'second' });
      l.viewer.canvas.focus();
    """
    saved = run_session([{"url": page_url, "viewport": {"width": 1000, "height": 560}, "steps": [
        {"eval": setup},
        {"waitFor": SETTLED + " && location.hash.includes('lens=')"},
        {"frame": "view"},
        {"eval": "return location.hash;", "save": "hash"},
        {"download": "key.png", "press": "s"},
        {"download": "button.png", "click": "#toolbar button[title^='Save a PNG']"},
        {"eval": "const b = await window.lanterna.snapshot(); return [b.type, b.size];",
         "save": "blob"},
    ]}], out)
    view = frame(out, "view")
    assert view[..., :3].std() > 5
    assert saved["key.png"] == "Lens_and_overlays_base_specular.png"
    assert saved["button.png"] == saved["key.png"]
    for name in ("key.png", "button.png"):
        data = (out / name).read_bytes()
        assert saved["blob"] == ["image/png", len(data)]
        image = pyvips.Image.new_from_buffer(data, "")
        assert (image.width, image.height, image.bands) == (1000, 560, 4)
        pixels = np.asarray(image.numpy(), np.uint8)
        diff = np.abs(pixels.astype(int) - view.astype(int))
        bad = (diff.max(axis=-1) > 0).sum()
        assert diff.max() == 0, f"{name}: {bad} pixels differ by up to {diff.max()}"
        texts = png_texts(data)
        assert texts["Title"] == "Lens and overlays"
        assert texts["Software"] == "Lanterna"
        assert texts["Lanterna layer"] == "base" and texts["Lanterna mode"] == "specular"
        assert texts["Lanterna light"] == "0.3,0.4"
        assert "specKs:0.9" in texts["Lanterna params"] and "gamma:1" in texts["Lanterna params"]
        width = 375 * 1000 / 560  # the region's height fits the viewer's; its width is wider
        assert [float(v) for v in texts["Lanterna view"].split(",")] == pytest.approx(
            [200 - (width - 500) / 2, 150, width, 375], abs=0.01)
        assert texts["Lanterna link"] == saved["hash"]


#: A snapshot at `scale`, as base64 PNG bytes, and the state before and after it.
SCALED = """
const l = window.lanterna;
const before = l.getState();
const blob = await l.snapshot({ scale: %s });
const bytes = new Uint8Array(await blob.arrayBuffer());
let binary = '';
for (let i = 0; i < bytes.length; i += 0x8000) {
  binary += String.fromCharCode.apply(null, bytes.subarray(i, i + 0x8000));
}
return { png: btoa(binary), before, after: l.getState(), hash: location.hash };
"""


def test_a_scaled_snapshot_is_the_region_at_that_scale(page_url: str, tmp_path: Path) -> None:
    """At scale 2 the 400×300 region is drawn in four tiles on a 640×480 viewer; it must equal one
    800×600 viewer showing the same region at 2 device px per image px (opened on the same link)."""
    out = tmp_path / "scaled"
    setup = """
      const l = window.lanterna;
      l.setRenderMode('specular'); l.setLight(-0.2, 0.5);
      l.showImageRegion(100, 80, 400, 300);
      await l.setLens({ enabled: true, center: [330, 200], radius: 80, layer: 'second' });
    """
    saved = run_session([
        {"url": page_url, "steps": [
            {"eval": setup},
            {"waitFor": SETTLED + " && location.hash.includes('lens=')"},
            {"eval": "return location.hash;", "save": "hash"},
            {"eval": SCALED % 2, "save": "snap"},
        ]},
        {"url": page_url + "{hash}", "viewport": {"width": 800, "height": 600}, "steps": [
            {"waitFor": SETTLED},
            {"frame": "big"},
        ]},
    ], out)
    snap = saved["snap"]
    data = base64.b64decode(snap["png"])
    image = pyvips.Image.new_from_buffer(data, "")
    assert (image.width, image.height) == (800, 600)
    pixels = np.asarray(image.numpy(), np.uint8)
    big = frame(out, "big")
    assert big[..., :3].std() > 5
    diff = np.abs(pixels.astype(int) - big.astype(int)).max(axis=-1)
    assert diff.max() <= 1, f"{(diff > 1).sum()} pixels differ by more than 1, up to {diff.max()}"
    assert (diff == 0).mean() > 0.99
    assert png_texts(data)["Lanterna scale"] == "2 output px per image px"
    assert snap["after"] == snap["before"], "the view is put back"
    assert snap["hash"] == saved["hash"], "the link is not rewritten while drawing"


def test_a_snapshot_does_not_wait_for_tiles_that_failed(page_url: str, tmp_path: Path) -> None:
    """Level 0 of the base layer cannot be loaded: the snapshot is taken once the tiles have
    failed (the coarser level drawn there), and still equals the frame read back."""
    out = tmp_path / "failed"
    saved = run_session([{
        "url": page_url, "routes": [{"match": r"/iiif/base_c0/full/max/", "status": 404}],
        "allowConsoleErrors": [r"^Failed to load resource", r"^Tile %s failed to load"],
        "steps": [
            {"eval": "window.lanterna.showImageRegion(200, 150, 320, 240);"},
            {"eval": SCALED % "undefined", "save": "snap"},
            {"eval": "return window.lanterna.getNotices().map((n) => n.kind);", "save": "kinds"},
            {"eval": "const { width, height, data } = window.lanterna.readPixels();"
                     " return [width, height, Array.from(data.subarray(0, 4000))];",
             "save": "read"},
        ],
    }], out)
    assert "tiles-failed" in saved["kinds"]
    image = pyvips.Image.new_from_buffer(base64.b64decode(saved["snap"]["png"]), "")
    width, height, head = saved["read"]
    assert (image.width, image.height) == (width, height)
    pixels = np.asarray(image.numpy(), np.uint8).reshape(-1)[:4000]
    assert pixels[:4000].tolist() == head and np.asarray(head).std() > 5
