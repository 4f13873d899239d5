"""The npm package as a user gets it.

`npm pack` of the plugin workspace is installed into a scratch project outside the checkout, then
type-checked there with `tsc --strict` and bundled and run in headless Chromium (OpenSeadragon needs
a DOM as soon as it is imported, so Node alone cannot load the package).
"""

from __future__ import annotations

import json
import shutil
import subprocess
import tarfile
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest

from tests.python.fixtures.browser import CHROMIUM
from tests.python.fixtures.paths import REPO
from tests.python.fixtures.servers import StaticServer

PLUGIN = REPO / "plugin"
TSC = REPO / "node_modules/typescript/bin/tsc"
VITE = REPO / "node_modules/vite/bin/vite.js"
PLAYWRIGHT = REPO / "node_modules/playwright-core/index.mjs"

pytestmark = pytest.mark.browser

# Uses the public types; each @ts-expect-error line must be an error, so types that resolved to
# `any` (or a changed signature) fail the check.
USAGE_TS = """\
import {
  applicableModes, createViewer, LanternaError, lightFromProjection, parseRelightService,
  RelightDrawer, RENDER_MODES, RenderModeError, type CreateViewerOptions, type LanternaViewer,
  type LayerInfo, type Light, type RenderMode, type ShadingClass,
} from '@lanterna/plugin';

const layer = parseRelightService({});
const modes: RenderMode[] = applicableModes(layer);
const light: Light = lightFromProjection(0.5, 0.25);
const options: CreateViewerOptions = { element: 'viewer', manifest: 'm.json', light: [0, 0] };
const viewer: LanternaViewer = createViewer(options);
const layers: LayerInfo[] = viewer.getLayers();
const shading: ShadingClass | undefined = layers[0]?.shading;
declare const drawer: RelightDrawer;
drawer.setLight(light);
const type: string = drawer.getType();
const error: LanternaError = new RenderModeError('no such mode');
// @ts-expect-error: not a render mode
const wrong: RenderMode = 'shiny';
// @ts-expect-error: the drawer takes a Light, not (lu, lv)
drawer.setLight(0.5, 0.25);
// @ts-expect-error: LanternaViewer.setLight takes two numbers
viewer.setLight(light);
export const used = [modes, layers, shading, type, error, wrong, RENDER_MODES];
"""

MAIN_JS = """\
import * as lanterna from '@lanterna/plugin';

const viewer = lanterna.createViewer({ element: 'viewer', manifest: './no-such-manifest.json' });
const failure = await viewer.ready.then(() => null, (e) => e);
const layer = lanterna.parseRelightService({
  type: 'LanternaRelight', profile: 'urn:lanterna:relight:1', layerType: 'image',
  width: 4, height: 4,
  planes: [{ service: { id: 'http://h/i' }, channels: ['Y'], scale: [1], bias: [0] }],
});
window.result = {
  exports: Object.keys(lanterna).sort(),
  drawerType: viewer.viewer.drawer.getType(),
  readyError: failure && failure.name,
  readyErrorIsLanterna: failure instanceof lanterna.LanternaError,
  imageModes: lanterna.applicableModes(layer),
  light: lanterna.lightFromPointer(75, 25, 100, 100),
};
viewer.destroy();
"""

DRIVE_MJS = """\
import {{ chromium }} from {playwright};

const browser = await chromium.launch({{
  executablePath: {chromium}, headless: true,
  args: ['--no-sandbox', '--disable-gpu', '--disable-background-networking', '--no-first-run'],
}});
try {{
  const page = await browser.newPage();
  const errors = [];
  page.on('pageerror', (e) => errors.push(String(e)));
  await page.goto(process.argv[2]);
  const handle = await page.waitForFunction(() => window.result, null, {{ timeout: 30000 }});
  console.log(JSON.stringify({{ result: await handle.jsonValue(), errors }}));
}} finally {{
  await browser.close();
}}
"""

# Public names that must stay exported (a sample across the folders).
EXPECTED_EXPORTS = {
    "createViewer", "RelightDrawer", "RELIGHT_DRAWER_TYPE", "BundleTileSource", "parseManifest",
    "loadRelightManifest", "parseRelightService", "ptmWeights", "hshWeights", "lightFromPointer",
    "lightFromProjection", "RENDER_MODES", "MODE_LABELS", "applicableModes", "shadingClass",
    "PARAM_SPECS", "relevantParams", "createControls", "createLensControls", "createHypertext",
    "sanitizeHtml", "routeGesture", "LanternaError", "ManifestError", "FetchError",
    "RenderModeError", "UnknownLayerError", "ShaderError", "FloatTargetsUnavailableError",
    "attachLanterna",
}


def run(args: list[str], cwd: Path, timeout: float = 60) -> subprocess.CompletedProcess[str]:
    """Run a command; fail the test with its output when it exits non-zero."""
    proc = subprocess.run(args, cwd=cwd, capture_output=True, text=True, timeout=timeout)
    if proc.returncode != 0:
        pytest.fail(f"{' '.join(args)} exited {proc.returncode}:\n{proc.stdout}\n{proc.stderr}")
    return proc


@pytest.fixture(scope="module")
def tarball(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """`npm pack` of the built plugin workspace."""
    if shutil.which("npm") is None:
        pytest.skip("npm is not installed: the npm package cannot be packed")
    if not (PLUGIN / "dist/lib/lanterna.js").is_file():
        pytest.fail("plugin/dist/lib is not built: run `npm run build` (make test does it)")
    out = tmp_path_factory.mktemp("pack")
    proc = run(["npm", "pack", "--workspace", "plugin", "--pack-destination", str(out), "--json"],
               REPO)
    (name,) = [entry["filename"] for entry in json.loads(proc.stdout)]
    return out / name


@pytest.fixture(scope="module")
def project(tarball: Path, tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A scratch project outside the checkout with the tarball installed."""
    root = tmp_path_factory.mktemp("consumer")
    assert not root.resolve().is_relative_to(REPO)
    (root / "package.json").write_text(json.dumps({"name": "consumer", "private": True,
                                                   "type": "module"}))
    run(["npm", "install", str(tarball), "--no-audit", "--no-fund", "--prefer-offline"], root,
        timeout=120)
    return root


def tar_manifest(tarball: Path) -> tuple[list[str], dict[str, Any]]:
    """The tarball's file paths (without the `package/` prefix) and its package.json."""
    with tarfile.open(tarball) as tar:
        names = [m.name for m in tar.getmembers() if m.isfile()]
        meta = tar.extractfile("package/package.json")
        assert meta is not None
        package = json.loads(meta.read())
    assert all(n.startswith("package/") for n in names), names
    return [n.removeprefix("package/") for n in names], package


def test_tarball_holds_only_the_library_and_its_metadata(tarball: Path) -> None:
    files, package = tar_manifest(tarball)
    allowed = {"package.json", "README.md", "LICENSE", "dist/mirador/lanterna-mirador.js"}
    strays = [f for f in files if f not in allowed and not f.startswith("dist/lib/")]
    assert strays == []
    assert {"package.json", "README.md", "dist/lib/lanterna.js"} <= set(files)
    assert package["name"] == "@lanterna/plugin"
    assert package["license"] == "Apache-2.0"
    entry = package["exports"]["."]
    for target in (package["types"], entry["types"], entry["import"], package["main"]):
        assert target.removeprefix("./") in files, target
    assert package["types"] == entry["types"]
    m = package["exports"]["./mirador"]  # the Mirador entry and ready bundle (docs/mirador.md)
    assert {m["types"][2:], m["import"][2:], "dist/mirador/lanterna-mirador.js"} <= set(files)


def test_types_check_in_a_strict_consumer(project: Path) -> None:
    (project / "usage.ts").write_text(USAGE_TS)
    run(["node", str(TSC), "--noEmit", "--strict", "--module", "esnext", "--moduleResolution",
         "bundler", "--target", "es2022", "--lib", "es2022,dom", "usage.ts"], project)
    # The check can fail: the same file with one more wrong call is rejected.
    (project / "wrong.ts").write_text(USAGE_TS + "applicableModes('ptm');\n")
    proc = subprocess.run(["node", str(TSC), "--noEmit", "--strict", "--module", "esnext",
                           "--moduleResolution", "bundler", "--target", "es2022", "--lib",
                           "es2022,dom", "wrong.ts"], cwd=project, capture_output=True, text=True,
                          timeout=60)
    assert proc.returncode != 0 and "wrong.ts(" in proc.stdout, proc.stdout


def bundle_page(folder: Path, element_id: str, main_js: str) -> Path:
    """Write a page with one 320×240 ``div`` ``element_id`` that runs ``main_js``, bundle it
    with the workspace's Vite (imports resolved from the scratch project's ``node_modules``)
    and return the bundle's folder."""
    (folder / "index.html").write_text(
        '<!doctype html><html><head><meta charset="utf-8"></head><body>'
        f'<div id="{element_id}" style="width: 320px; height: 240px"></div>'
        '<script type="module" src="./main.js"></script></body></html>')
    (folder / "main.js").write_text(main_js)
    run(["node", str(VITE), "build", ".", "--outDir", "dist", "--emptyOutDir", "--minify", "false",
         "--base", "./", "--logLevel", "warn"], folder)
    return folder / "dist"


@pytest.fixture()
def served(project: Path) -> Iterator[str]:
    """The consumer page, bundled with the workspace's Vite and served on a loopback port."""
    with StaticServer(bundle_page(project, "viewer", MAIN_JS)) as server:
        yield f"{server.url}/index.html"


def test_package_runs_in_a_browser(project: Path, served: str) -> None:
    if not CHROMIUM.exists():
        pytest.fail("Debian's Chromium is missing: apt-get install -y chromium (make test does it)")
    drive = project / "drive.mjs"
    drive.write_text(DRIVE_MJS.format(playwright=json.dumps(str(PLAYWRIGHT)),
                                      chromium=json.dumps(str(CHROMIUM))))
    proc = run(["node", str(drive), served], project)
    report = json.loads(proc.stdout.strip().splitlines()[-1])
    assert report["errors"] == []
    result = report["result"]
    assert EXPECTED_EXPORTS <= set(result["exports"]), EXPECTED_EXPORTS - set(result["exports"])
    assert result["drawerType"] == "lanterna"
    assert result["readyError"] == "FetchError"
    assert result["readyErrorIsLanterna"] is True
    assert result["imageModes"] == ["color", "albedo", "achromatic", "unsharpImage"]
    assert result["light"]["lu"] == pytest.approx(0.5)
    assert result["light"]["lv"] == pytest.approx(0.5)
