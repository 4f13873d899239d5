"""The wheel, as a user installs it: built from the checkout, installed into a fresh venv outside
it, then every module imported and ``lanterna import`` + ``lanterna serve`` run from there.

Builds without build isolation (the dev venv's setuptools), so it needs no network for the build;
installing the wheel's dependencies comes from pip's cache after ``make install``, or the index.
"""

from __future__ import annotations

import json
import os
import re
import select
import signal
import subprocess
import sys
import urllib.request
import zipfile
from pathlib import Path

import pytest

from tests.python.fixtures.paths import REPO
from tests.python.fixtures.ptm import random_ptm_of_size
from tests.python.fixtures.ptm_writer import write_ptm

pytestmark = pytest.mark.packaging

#: The import name of each top-level folder (setup.py).
FOLDERS = {"lanterna": "lanterna", "lanterna.tiler": "tiler", "lanterna.manifests": "manifests",
           "lanterna.server": "server"}
DIST_INFO = "lanterna-0.1.0.dist-info"
#: The viewer pages (plugin/*.html, built into plugin/dist/viewer).
VIEWER_PAGES = ("index", "simple")
#: Deadline for the server to print its first line (not a performance bound).
START_DEADLINE_S = 60
IMPORT_ALL = """
import importlib, json, pkgutil, lanterna
names = [m.name for m in pkgutil.walk_packages(lanterna.__path__, "lanterna.")]
failed = {}
for name in names:
    try:
        importlib.import_module(name)
    except Exception as err:
        failed[name] = repr(err)
print(json.dumps({"file": lanterna.__file__, "modules": names, "failed": failed}))
"""


def _source_modules() -> dict[str, str]:
    """Every module of the checkout's four folders: wheel path → dotted name."""
    modules = {}
    for name, folder in FOLDERS.items():
        for path in sorted((REPO / folder).rglob("*.py")):
            rel = path.relative_to(REPO / folder)
            if "__pycache__" in rel.parts:
                continue
            parts = [*name.split("."), *rel.with_suffix("").parts]
            dotted = ".".join(parts[:-1] if parts[-1] == "__init__" else parts)
            modules["/".join([*name.split("."), *rel.parts])] = dotted
    return modules


def _clean_env(venv: Path) -> dict[str, str]:
    """No PYTHONPATH, no activated venv: only the fresh venv's bin/ ahead of the system's."""
    return {"PATH": f"{venv / 'bin'}:/usr/bin:/bin", "HOME": os.environ.get("HOME", "/tmp"),
            "LANG": "C.UTF-8"}


@pytest.fixture(scope="module")
def wheel(tmp_path_factory: pytest.TempPathFactory) -> Path:
    out = tmp_path_factory.mktemp("wheel")
    build = subprocess.run([sys.executable, "-m", "pip", "wheel", "--quiet", "--no-deps",
                            "--no-build-isolation", "--disable-pip-version-check", "-w",
                            str(out), str(REPO)], capture_output=True, text=True)
    assert build.returncode == 0, build.stdout + build.stderr
    assert "Warning" not in build.stdout + build.stderr  # no setuptools warnings
    wheels = list(out.glob("lanterna-*.whl"))
    assert len(wheels) == 1, wheels
    return wheels[0]


@pytest.fixture(scope="module")
def venv(wheel: Path, tmp_path_factory: pytest.TempPathFactory) -> Path:
    venv = tmp_path_factory.mktemp("fresh") / "venv"
    assert not venv.is_relative_to(REPO)
    subprocess.run([sys.executable, "-m", "venv", "--without-pip", str(venv)], check=True)
    env = {k: v for k, v in os.environ.items()
           if k not in ("PYTHONPATH", "PYTHONHOME", "VIRTUAL_ENV")}
    install = subprocess.run([sys.executable, "-m", "pip", "--python", str(venv / "bin/python"),
                              "install", "--quiet", "--disable-pip-version-check", str(wheel)],
                             capture_output=True, text=True, env=env)
    assert install.returncode == 0, install.stdout + install.stderr
    return venv


def test_the_wheel_holds_every_module_the_viewer_and_the_licence(wheel: Path) -> None:
    with zipfile.ZipFile(wheel) as zf:
        names = set(zf.namelist())
        licence = zf.read(f"{DIST_INFO}/licenses/LICENSE")
        metadata = zf.read(f"{DIST_INFO}/METADATA").decode()
        pages = {page: zf.read(f"lanterna/server/viewer/{page}.html").decode()
                 for page in VIEWER_PAGES}
    assert {n for n in names if n.endswith(".py")} == set(_source_modules())
    for page, html in pages.items():  # the advanced and the simplified viewer, and their assets
        script = re.search(rf'<script type="module"[^>]* src="\./(assets/{page}-[\w-]+\.js)"', html)
        assert script, html
        assets = re.findall(r'(?:src|href)="\./(assets/[^"]+)"', html)
        assert script[1] in assets
        assert {f"lanterna/server/viewer/{a}" for a in assets} <= names, (page, assets)
    assert not [n for n in names if n.endswith(".map")]  # source maps stay in the checkout
    assert {"lanterna/manifests/schema/iiif_3_0.json",
            "lanterna/manifests/schema/NOTICE.md"} <= names
    # every document schema the readers check against (presets, patches, annotation pages …)
    schemas = {f"lanterna/tiler/schemas/{p.name}" for p in (REPO / "tiler/schemas").glob("*.json")}
    assert {"lanterna/tiler/schemas/patch.schema.json",
            "lanterna/tiler/schemas/annotation-page.schema.json"} <= schemas <= names
    assert licence == (REPO / "LICENSE").read_bytes()
    assert "License-Expression: Apache-2.0" in metadata.splitlines()
    assert all(n.startswith(("lanterna/", f"{DIST_INFO}/")) for n in names)
    assert not [n for n in names if re.search(r"(^|/)(tests|bench)/", n)]


def test_every_module_imports_from_the_fresh_venv(venv: Path, tmp_path: Path) -> None:
    run = subprocess.run([str(venv / "bin/python"), "-c", IMPORT_ALL], cwd=tmp_path,
                         env=_clean_env(venv), capture_output=True, text=True)
    assert run.returncode == 0, run.stderr
    result = json.loads(run.stdout)
    assert Path(result["file"]).is_relative_to(venv), result["file"]
    assert result["failed"] == {}
    expected = set(_source_modules().values()) - {"lanterna"}
    assert set(result["modules"]) == expected


def test_import_and_serve_from_the_fresh_venv(venv: Path, tmp_path: Path) -> None:
    env = _clean_env(venv)
    write_ptm(tmp_path / "obj.ptm", random_ptm_of_size(300, 200), "PTM_FORMAT_LRGB")
    imported = subprocess.run([str(venv / "bin/lanterna"), "import", "obj.ptm", "-o",
                               "datasets/obj"], cwd=tmp_path, env=env, capture_output=True,
                              text=True)
    assert imported.returncode == 0, imported.stderr
    assert imported.stdout.startswith("wrote datasets/obj: dataset obj")
    assert "next: lanterna serve datasets " in imported.stdout

    proc = subprocess.Popen([str(venv / "bin/lanterna"), "serve", "datasets", "--port", "0"],
                            cwd=tmp_path, env=env, stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True)
    try:
        assert proc.stdout is not None
        ready, _, _ = select.select([proc.stdout], [], [], START_DEADLINE_S)
        first = proc.stdout.readline() if ready else ""
        found = re.search(r" at (http://127\.0\.0\.1:\d+)/", first)
        assert found, first
        url = found[1]
        with urllib.request.urlopen(f"{url}/viewer/", timeout=30) as resp:
            page = resp.read().decode()
        packaged = next(venv.glob("lib/python*/site-packages/lanterna/server/viewer"))
        assert page == (packaged / "index.html").read_text()
        script = re.search(r'src="\./(assets/[^"]+\.js)"', page)
        assert script, page
        with urllib.request.urlopen(f"{url}/viewer/{script[1]}", timeout=30) as resp:
            assert "javascript" in resp.headers["Content-Type"]
            assert resp.read() == (packaged / script[1]).read_bytes()
        with urllib.request.urlopen(f"{url}/viewer/simple.html", timeout=30) as resp:
            simple = resp.read().decode()
        assert simple == (packaged / "simple.html").read_text()
        for asset in re.findall(r'(?:src|href)="\./(assets/[^"]+\.js)"', simple):
            with urllib.request.urlopen(f"{url}/viewer/{asset}", timeout=30) as resp:
                assert resp.read() == (packaged / asset).read_bytes()

        image = tmp_path / "datasets/obj/iiif/obj_c0"
        with urllib.request.urlopen(f"{url}/datasets/obj/iiif/obj_c0/info.json",
                                    timeout=30) as resp:
            info = json.loads(resp.read())
        assert info["id"] == f"{url}/datasets/obj/iiif/obj_c0"
        assert (info["width"], info["height"]) == (300, 200)
        tile = min(image.rglob("default.*"))  # PNG or lossless WebP, whichever is smaller
        with urllib.request.urlopen(f"{url}/datasets/{tile.relative_to(tmp_path / 'datasets')}",
                                    timeout=30) as resp:
            assert resp.headers["Content-Type"] == f"image/{tile.suffix[1:]}"
            assert resp.read() == tile.read_bytes()
    finally:
        proc.send_signal(signal.SIGTERM)
        _, err = proc.communicate(timeout=60)
    assert "Traceback" not in err, err
