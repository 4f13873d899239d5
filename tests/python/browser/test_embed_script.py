"""``attachLanterna`` on a page that loads OpenSeadragon with a script tag (docs/embedding.md).

The page is made the way docs/embedding.md, "Without a bundler", tells: OpenSeadragon's own
``openseadragon.min.js`` as a classic script (``window.OpenSeadragon``), an import map that gives
the library that same OpenSeadragon (a one-line module exporting ``window.OpenSeadragon``) and
twgl.js's module build, and the library's ``dist/lib/lanterna.js`` as a module. In real Chromium
the page's viewer is relit within 2/255 of the numpy reference."""

from __future__ import annotations

import shutil
from collections.abc import Callable
from pathlib import Path
from urllib.parse import quote

import numpy as np
import pytest

from lanterna.tiler.dataset.layers import add_ptm_layer
from lanterna.tiler.dataset.writer import DatasetWriter
from tests.python.browser.test_embed import READY, REGION, VIEW, shot
from tests.python.fixtures.page_script import FRAME, evaluate, frame, run_page
from tests.python.fixtures.paths import REPO
from tests.python.fixtures.ptm_relight import TOLERANCE, H, W, numpy_relight, smooth_random_ptm
from tests.python.fixtures.servers import LiveServer, StaticServer

pytestmark = pytest.mark.browser

OSD_BUILD = REPO / "node_modules/openseadragon/build/openseadragon/openseadragon.min.js"
TWGL_MODULE = REPO / "node_modules/twgl.js/dist/7.x/twgl-full.module.js"
LIBRARY = REPO / "plugin/dist/lib/lanterna.js"

PAGE = """<!doctype html>
<html><head><meta charset="utf-8"><link rel="icon" href="data:,">
<script src="openseadragon.min.js"></script>
<script type="importmap">
{"imports": {"openseadragon": "./openseadragon-global.js", "twgl.js": "./twgl-full.module.js"}}
</script>
</head><body style="margin: 0">
<div id="osd" style="position: absolute; inset: 0"></div>
<script type="module">
  import { attachLanterna } from './lanterna.js';
  const viewer = OpenSeadragon({ id: 'osd', showNavigationControl: false });
  window.hostViewer = viewer;
  const manifest = new URLSearchParams(location.search).get('manifest');
  window.lanterna = attachLanterna(viewer, { manifest, mode: 'pan' });
</script>
</body></html>
"""


def test_a_script_tag_page_is_relit(tmp_path: Path,
                                    live_server: Callable[[Path], LiveServer]) -> None:
    for path in (OSD_BUILD, TWGL_MODULE, LIBRARY):
        if not path.is_file():
            pytest.fail(f"{path} is missing: run `npm ci && npm run build` (make test does it)")
    root = tmp_path / "root"
    with DatasetWriter(root / "obj", name="obj", label="Random PTM", width=W, height=H) as ds:
        layer = add_ptm_layer(ds, smooth_random_ptm("lrgb", seed=5))
    site = tmp_path / "site"
    site.mkdir()
    for path in (OSD_BUILD, TWGL_MODULE, LIBRARY):
        shutil.copy(path, site / path.name)
    (site / "openseadragon-global.js").write_text("export default window.OpenSeadragon;\n")
    (site / "index.html").write_text(PAGE)
    data = live_server(root)  # another origin than the page's: the app answers with CORS headers
    light = (0.4, 0.5)
    with StaticServer(site) as pages:
        url = (f"{pages.url}/index.html?manifest="
               f"{quote(data.url + '/datasets/obj/manifest.json', safe='')}")
        values = run_page(url, [
            {"waitFor": "() => window.lanterna"}, READY,
            evaluate("() => [window.hostViewer.drawer.getType(), typeof window.OpenSeadragon]"),
            shot(light), FRAME,
        ], tmp_path / "page", viewport=VIEW, routes=(), settle=False)["values"]
    assert values[2] == ["lanterna", "function"]
    ref = numpy_relight(root / "obj", layer, 1, light)
    x, y, w, h = REGION
    expected = np.round(ref[y: y + h, x: x + w] * 255.0).astype(np.int16)
    got = frame(values[4])
    assert got.shape[:2] == expected.shape[:2]
    assert expected.std() > 10
    assert (got[..., 3] == 255).all()
    diff = np.abs(got[..., :3].astype(np.int16) - expected)
    assert int(diff.max()) <= TOLERANCE, f"off by up to {diff.max()}/255"
