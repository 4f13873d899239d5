"""`attachLanterna` from the npm package as a user gets it (docs/embedding.md).

In test_npm_pack.py's scratch project (the packed tarball installed outside the checkout): the types
check in a strict consumer, and a page bundled with Vite makes its own OpenSeadragon viewer (the
package's OpenSeadragon dependency) and attaches Lanterna to it in headless Chromium.
"""

from __future__ import annotations

import json
import subprocess
from pathlib import Path

import pytest

from tests.python.fixtures.browser import CHROMIUM
from tests.python.fixtures.servers import StaticServer
from tests.python.packaging.test_npm_pack import (  # noqa: F401 (the fixtures)
    DRIVE_MJS,
    PLAYWRIGHT,
    TSC,
    VITE,
    bundle_page,
    project,
    run,
    tarball,
)

pytestmark = pytest.mark.browser

USAGE_TS = """\
import type OpenSeadragon from 'openseadragon';
import { attachLanterna, type AttachLanternaOptions, type LanternaViewer } from '@lanterna/plugin';

declare const host: OpenSeadragon.Viewer;
const options: AttachLanternaOptions = { manifest: 'm.json', mode: 'pan', light: [0, 0] };
const lanterna: LanternaViewer = attachLanterna(host, options);
const same: OpenSeadragon.Viewer = lanterna.viewer;
// @ts-expect-error: the page's viewer has its element already
const withElement: AttachLanternaOptions = { manifest: 'm.json', element: 'viewer' };
// @ts-expect-error: the OpenSeadragon options are the page's
attachLanterna(host, { manifest: 'm.json', osd: {} });
export const used = [same, withElement];
"""

MAIN_JS = """\
import OpenSeadragon from 'openseadragon';
import { attachLanterna, LanternaError } from '@lanterna/plugin';

const host = OpenSeadragon({ element: document.getElementById('host'), showNavigator: true });
const lanterna = attachLanterna(host, { manifest: './no-such-manifest.json' });
const failure = await lanterna.ready.then(() => null, (e) => e);
const result = {
  sameViewer: lanterna.viewer === host,
  drawerType: host.drawer.getType(),
  readyError: failure && failure.name,
  readyErrorIsLanterna: failure instanceof LanternaError,
  widgets: host.element.querySelectorAll('[class*="lanterna"]').length,
};
lanterna.destroy();
result.widgetsAfter = host.element.querySelectorAll('[class*="lanterna"]').length;
result.drawerAfter = host.drawer.getType();
let again = null;
try {
  attachLanterna(host, { manifest: './no-such-manifest.json' }).destroy();
  attachLanterna({}, { manifest: 'm.json' });
} catch (e) {
  again = [e.name, e.message];
}
result.notAViewer = again;
window.result = result;
"""


def test_attach_types_check_in_a_strict_consumer(project: Path) -> None:  # noqa: F811
    (project / "attach-usage.ts").write_text(USAGE_TS)
    run(["node", str(TSC), "--noEmit", "--strict", "--module", "esnext", "--moduleResolution",
         "bundler", "--target", "es2022", "--lib", "es2022,dom", "--esModuleInterop",
         "attach-usage.ts"], project)
    # The check can fail: a wrong option type is rejected.
    (project / "attach-wrong.ts").write_text(USAGE_TS + "attachLanterna(host, { manifest: 1 });\n")
    proc = subprocess.run(["node", str(TSC), "--noEmit", "--strict", "--module", "esnext",
                           "--moduleResolution", "bundler", "--target", "es2022", "--lib",
                           "es2022,dom", "--esModuleInterop", "attach-wrong.ts"], cwd=project,
                          capture_output=True, text=True, timeout=60)
    assert proc.returncode != 0 and "attach-wrong.ts(" in proc.stdout, proc.stdout


def test_attach_runs_on_a_pages_own_viewer(project: Path) -> None:  # noqa: F811
    if not CHROMIUM.exists():
        pytest.fail("Debian's Chromium is missing: apt-get install -y chromium (make test does it)")
    page = project / "attach"
    page.mkdir(exist_ok=True)
    bundle = bundle_page(page, "host", MAIN_JS)
    drive = project / "drive-attach.mjs"
    drive.write_text(DRIVE_MJS.format(playwright=json.dumps(str(PLAYWRIGHT)),
                                      chromium=json.dumps(str(CHROMIUM))))
    with StaticServer(bundle) as server:
        proc = run(["node", str(drive), f"{server.url}/index.html"], project)
    report = json.loads(proc.stdout.strip().splitlines()[-1])
    assert report["errors"] == []
    result = report["result"]
    assert result["sameViewer"] is True
    assert result["drawerType"] == "lanterna"
    assert result["readyError"] == "FetchError"
    assert result["readyErrorIsLanterna"] is True
    assert result["widgets"] > 0
    assert result["widgetsAfter"] == 0
    assert result["drawerAfter"] in ("webgl", "canvas")
    # attaching again after destroy() works; what is not a viewer is a one-line LanternaError
    name, message = result["notAViewer"]
    assert name == "LanternaError"
    assert message.startswith("attachLanterna needs an OpenSeadragon 6 viewer")
    assert "\n" not in message
