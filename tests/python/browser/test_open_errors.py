"""Real Chromium: a dataset that cannot be opened gives a readable message in the page.

Each case opens the viewer page on a broken manifest or ``info.json`` (missing, not JSON, the
wrong shape, no relight block, a server that refuses other origins, …): the page must show its
error box, titled, with the problem (naming the failing URL), the manifest URL and a hint, fitting
the viewport, and no page error (uncaught exception or unhandled rejection) may occur. The faults
come from the server itself, from render.mjs ``routes`` or from a host without CORS headers.
"""

from __future__ import annotations

import json
import re
import urllib.request
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import pytest

from tests.python.fixtures.browser import open_failing
from tests.python.fixtures.faults import NoCorsServer, make_noisy_dataset
from tests.python.fixtures.manifests import without_descriptions
from tests.python.fixtures.servers import LiveServer

pytestmark = pytest.mark.browser

TITLE = "Cannot open this dataset"
ALLOWED = [r"^Failed to load resource", r"^\[lanterna\]", r"blocked by CORS policy", r"net::ERR_"]


@dataclass
class Served:
    url: str  # the Lanterna server
    manifest: dict[str, Any]
    info: dict[str, Any]  # of plane image base_c1
    root: Path

    @property
    def manifest_url(self) -> str:
        return f"{self.url}/datasets/lens/manifest.json"

    @property
    def info_url(self) -> str:
        return f"{self.url}/datasets/lens/iiif/base_c1/info.json"


@pytest.fixture(scope="module")
def served(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Served]:
    dataset = make_noisy_dataset(tmp_path_factory, 300, 200)
    server = LiveServer(dataset.root)
    try:
        def get(url: str) -> dict[str, Any]:
            with urllib.request.urlopen(url) as r:
                found: dict[str, Any] = json.loads(r.read())
                return found
        manifest = get(f"{server.url}/datasets/lens/manifest.json")
        info = get(f"{server.url}/datasets/lens/iiif/base_c1/info.json")
        yield Served(server.url, manifest, info, dataset.root)
    finally:
        server.close()


def exactly(url: str, **fault: Any) -> dict[str, Any]:
    """A route answering requests for exactly ``url`` with ``fault``."""
    return {"match": f"^{re.escape(url)}$", **fault}


def json_body(doc: object) -> dict[str, Any]:
    return {"status": 200, "body": json.dumps(doc), "contentType": "application/json"}


def relight_blocks_changed(manifest: dict[str, Any],
                           change: Callable[[dict[str, Any]], Any]) -> Any:
    """The manifest with ``change`` applied to each LanternaRelight block (None: dropped)."""
    def walk(x: Any) -> Any:
        if isinstance(x, dict):
            if x.get("type") == "LanternaRelight":
                return change(dict(x))
            return {k: w for k, v in x.items() if (w := walk(v)) is not None}
        if isinstance(x, list):
            return [w for v in x if (w := walk(v)) is not None]
        return x
    return walk(manifest)


def services_changed(manifest: dict[str, Any],
                     change: Callable[[dict[str, Any]], dict[str, Any]]) -> Any:
    """The manifest with ``change`` applied to each ImageService3 reference."""
    def walk(x: Any) -> Any:
        if isinstance(x, dict):
            y = {k: walk(v) for k, v in x.items()}
            return change(y) if x.get("type") == "ImageService3" else y
        if isinstance(x, list):
            return [walk(v) for v in x]
        return x
    return walk(manifest)


def bare(s: Served, *routes: dict[str, Any]) -> tuple[str, list[dict[str, Any]]]:
    """Open the manifest without the embedded image descriptions (the viewer fetches info.json)."""
    older = without_descriptions(s.manifest)
    return s.manifest_url, [exactly(s.manifest_url, **json_body(older)), *routes]


def c1_embeds(s: Served, **changes: Any) -> tuple[str, list[dict[str, Any]]]:
    """Open the manifest with base_c1's embedded description changed."""
    doc = services_changed(s.manifest, lambda svc: {**svc, **changes}
                           if svc["id"].endswith("/base_c1") else svc)
    return s.manifest_url, [exactly(s.manifest_url, **json_body(doc))]


@dataclass
class Case:
    """How to break the page: the manifest URL to open and the routes, from the served dataset."""

    build: Callable[[Served], tuple[str | None, list[dict[str, Any]]]]
    error: str | None  # the name of the error lanterna.ready rejects with (None: no viewer made)
    problem: str  # in the problem line
    hint: str  # in the hint line
    launch: tuple[str, ...] = ()


CASES: dict[str, Case] = {
    "manifest-404": Case(lambda s: (f"{s.url}/datasets/nothing/manifest.json", []),
                         "FetchError", "HTTP 404", "no document at this URL"),
    "manifest-500": Case(lambda s: (s.manifest_url, [exactly(s.manifest_url, status=500)]),
                         "FetchError", "HTTP 500", "answered with an error"),
    "manifest-network-error": Case(
        lambda s: (s.manifest_url, [exactly(s.manifest_url, abort="connectionrefused")]),
        "FetchError", "cannot be reached", "server is running"),
    "manifest-is-html": Case(
        lambda s: (s.manifest_url, [exactly(s.manifest_url, status=200, contentType="text/html",
                                            body="<html><body>Welcome</body></html>")]),
        "FetchError", "is not valid JSON", "not point at a JSON document"),
    "manifest-truncated": Case(
        lambda s: (s.manifest_url, [exactly(s.manifest_url, status=200,
                                            body=json.dumps(s.manifest)[:300])]),
        "FetchError", "is not valid JSON", "not point at a JSON document"),
    "manifest-not-a-manifest": Case(
        lambda s: (s.manifest_url, [exactly(s.manifest_url, **json_body([1, 2, 3]))]),
        "ManifestError", "not a IIIF Presentation 3 manifest", "Lanterna dataset format"),
    "manifest-wrong-shapes": Case(
        lambda s: (s.manifest_url, [exactly(s.manifest_url, **json_body(
            {**s.manifest, "items": {"not": "a list"}}))]),
        "ManifestError", "no painting Image", "Lanterna dataset format"),
    "manifest-without-relight-block": Case(
        lambda s: (s.manifest_url, [exactly(s.manifest_url, **json_body(
            relight_blocks_changed(s.manifest, lambda block: None)))]),
        "MissingRelightServiceError", "LanternaRelight", "not a Lanterna one"),
    "relight-block-invalid": Case(
        lambda s: (s.manifest_url, [exactly(s.manifest_url, **json_body(
            relight_blocks_changed(s.manifest, lambda block: {**block, "layerType": "bogus"})))]),
        "RelightServiceError", "unsupported layerType", "Lanterna dataset format"),
    "manifest-without-cors": Case(lambda s: ("NOCORS", []), "FetchError", "CORS",
                                  "Access-Control-Allow-Origin"),
    "info-404": Case(lambda s: bare(s, exactly(s.info_url, status=404)),
                     "FetchError", "base_c1/info.json", "no document at this URL"),
    "info-not-json": Case(lambda s: bare(s, exactly(s.info_url, status=200, body="width=300")),
                          "FetchError", "base_c1/info.json is not valid JSON", "JSON document"),
    "info-without-tiles": Case(
        lambda s: bare(s, exactly(s.info_url, **json_body(
            {k: v for k, v in s.info.items() if k != "tiles"}))),
        "ImageInfoError", "base_c1/info.json", "info.json is not a usable"),
    "info-other-size": Case(
        lambda s: bare(s, exactly(s.info_url, **json_body(
            {**s.info, "width": s.info["width"] + 1}))),
        "MismatchedPlanesError", "differs from plane group 0", "info.json is not a usable"),
    "embedded-without-scale-factors": Case(
        lambda s: c1_embeds(s, tiles=[{"width": 256, "height": 256}]),
        "ImageInfoError", "layers/base.json planes[1].service: tiles[0] needs width and "
        "scaleFactors", "info.json is not a usable"),
    "embedded-other-size": Case(
        lambda s: c1_embeds(s, width=s.info["width"] + 1),
        "MismatchedPlanesError", "planes[1].service: 301×200", "info.json is not a usable"),
    "no-webgl": Case(lambda s: (s.manifest_url, []), None, "WebGL2 is not available",
                     "needs WebGL2", launch=("--disable-webgl",)),
    "no-manifest-parameter": Case(lambda s: (None, []), None, "No manifest given", ""),
}


def open_case(served: Served, case: Case, folder: Path, viewport: tuple[int, int],
              **more: Any) -> tuple[str | None, dict[str, Any]]:
    manifest, routes = case.build(served)
    options: dict[str, Any] = {"routes": routes, "allowConsoleErrors": ALLOWED,
                               "launchArgs": list(case.launch), **more}
    if manifest == "NOCORS":
        (folder / "nocors").mkdir(parents=True)
        (folder / "nocors" / "manifest.json").write_text(json.dumps(served.manifest))
        with NoCorsServer(folder / "nocors") as host:
            manifest = f"{host.url}/manifest.json"
            page = f"{served.url}/viewer/?manifest={manifest}"
            return manifest, open_failing(page, folder, viewport, options=options)
    page = f"{served.url}/viewer/" + (f"?manifest={manifest}" if manifest else "")
    return manifest, open_failing(page, folder, viewport, options=options)


def check_message(name: str, case: Case, manifest: str | None, result: dict[str, Any],
                  viewport: tuple[int, int]) -> None:
    box = result["errorBox"]
    assert box["visible"], f"{name}: no error message shown"
    assert box["title"] == TITLE
    assert case.problem in (box["problem"] or ""), f"{name}: {box['problem']!r}"
    assert case.hint in (box["hint"] or ""), f"{name}: {box['hint']!r}"
    assert box["url"] == manifest, f"{name}: the message must name the manifest URL"
    if case.error is None:
        assert result["readyError"] is None
    else:
        assert result["readyError"]["name"] == case.error, result["readyError"]
    x, y, w, h = box["rect"]
    assert 0 <= x and 0 <= y and x + w <= viewport[0] and y + h <= viewport[1], box["rect"]
    assert box["scrollWidth"] <= box["clientWidth"], f"{name}: the message overflows sideways"
    assert result["pageErrors"] == []


@pytest.mark.parametrize("name", list(CASES))
def test_a_broken_dataset_gives_a_readable_message(served: Served, tmp_path: Path,
                                                   name: str) -> None:
    case = CASES[name]
    manifest, result = open_case(served, case, tmp_path, (800, 600))
    check_message(name, case, manifest, result, (800, 600))


@pytest.mark.parametrize("name", ["manifest-404", "info-other-size", "no-manifest-parameter"])
def test_the_message_fits_a_phone(served: Served, tmp_path: Path, name: str) -> None:
    case = CASES[name]
    manifest, result = open_case(served, case, tmp_path, (390, 844), mobile=True,
                                 screenshot=str(tmp_path / f"{name}-phone.png"))
    check_message(name, case, manifest, result, (390, 844))
