"""What pyproject.toml cannot declare: the package list of a remapped layout, and the viewer.

One import namespace, ``lanterna``, is mapped from four top-level folders (:data:`FOLDERS`).
Every package below them is found here, so a new sub-package needs no entry anywhere;
``manifests/schema`` (data only) is found as a namespace package and carries its files.

A wheel also carries the built viewer page (``plugin/dist/viewer``, written by ``npm run build``)
as ``lanterna/server/viewer``, and an sdist as ``plugin/dist/viewer`` for the wheel built from it;
building either without it fails with a one-line message. An editable install (``make install``)
does not copy it: the server then uses the checkout's ``plugin/dist/viewer``.
"""

from __future__ import annotations

import shutil
import warnings
from pathlib import Path

from setuptools import find_namespace_packages, setup
from setuptools.command.build_py import build_py
from setuptools.command.sdist import sdist
from setuptools.errors import FileError
from setuptools.warnings import InformationOnly

#: Import name → folder of the checkout it is built from.
FOLDERS = {
    "lanterna": "lanterna",
    "lanterna.tiler": "tiler",
    "lanterna.manifests": "manifests",
    "lanterna.server": "server",
}
VIEWER = Path("plugin", "dist", "viewer")
PACKAGED_VIEWER = Path("lanterna", "server", "viewer")

# An editable install of this layout goes through setuptools' import finder, which always warns
# to beware of folders in the working directory named like the package: here the `lanterna`
# folder is the package itself, so the warning tells nothing and is only noise on every install.
warnings.filterwarnings("ignore", "Editable installation", InformationOnly)


def packages() -> list[str]:
    """Every package and sub-package of :data:`FOLDERS` (``__pycache__`` aside)."""
    found: list[str] = []
    for name, folder in FOLDERS.items():
        subs = find_namespace_packages(where=folder, exclude=["__pycache__", "*.__pycache__"])
        found += [name, *(f"{name}.{sub}" for sub in subs)]
    return found


def require_viewer() -> None:
    """Fail in one line if the viewer is not built."""
    if not (VIEWER / "index.html").is_file():
        raise FileError(f"{VIEWER} is not built: run `make build` (npm ci && npm run build) "
                        "before building a wheel or an sdist")


def copy_viewer(target: Path) -> None:
    """Copy the built viewer to ``target``; source maps stay out (2.5 MB, for debugging)."""
    shutil.copytree(VIEWER, target, ignore=shutil.ignore_patterns("*.map"))


class BuildPyWithViewer(build_py):
    """``build_py`` from a clean build folder, adding the built viewer (not when editable)."""

    def run(self) -> None:
        if self.editable_mode:
            super().run()
            return
        require_viewer()
        # build/lib outlives builds: a module deleted or renamed since would ship again.
        shutil.rmtree(Path(self.build_lib, "lanterna"), ignore_errors=True)
        super().run()
        copy_viewer(Path(self.build_lib, PACKAGED_VIEWER))


class SdistWithViewer(sdist):
    """``sdist`` carrying the built viewer too, so that a wheel built from it has one."""

    def make_release_tree(self, base_dir: str, files: list[str]) -> None:
        require_viewer()
        super().make_release_tree(base_dir, files)
        copy_viewer(Path(base_dir, VIEWER))


setup(packages=packages(), package_dir=FOLDERS,
      cmdclass={"build_py": BuildPyWithViewer, "sdist": SdistWithViewer})
