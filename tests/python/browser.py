"""Drive the viewer in real Chromium through tests/browser/render.mjs (playwright-core)."""

from __future__ import annotations

import json
import shutil
import subprocess
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import numpy.typing as npt
import pytest

REPO = Path(__file__).resolve().parents[2]
RENDER = REPO / "tests" / "browser" / "render.mjs"
CHROMIUM = Path("/usr/bin/chromium")


@dataclass
class Shot:
    """One rendering: a light and the image-pixel rectangle fitted to the viewport.

    ``layer``, ``mode`` and ``params`` (all render parameters; unlisted ones take their defaults)
    select what is drawn; ``None`` keeps the viewer's current choice.
    """

    light: tuple[float, float]
    region: tuple[int, int, int, int]
    out: Path
    layer: str | None = None
    mode: str | None = None
    params: dict[str, float] | None = None

    def spec(self) -> dict[str, object]:
        """The shot as render.mjs reads it."""
        extra = {k: getattr(self, k) for k in ("layer", "mode", "params")
                 if getattr(self, k) is not None}
        return {"light": list(self.light), "region": list(self.region), "out": str(self.out),
                **extra}


def require_browser() -> None:
    """Fail (not skip) with the fix when the browser or the plugin build is missing."""
    if not CHROMIUM.exists():
        pytest.fail("Debian's Chromium is missing: apt-get install -y chromium (make test does it)")
    if shutil.which("node") is None:
        pytest.fail("node is missing")
    if not (REPO / "plugin/dist/viewer/index.html").is_file():
        pytest.fail("the viewer is not built: run `npm run build` (make test does it)")
    if not (REPO / "node_modules/playwright-core").is_dir():
        pytest.fail("node_modules missing: run `npm ci` (make test does it)")


def render(url: str, shots: list[Shot], viewport: tuple[int, int] = (640, 480),
           screenshot: Path | None = None, timeout: float = 180) -> list[npt.NDArray[np.uint8]]:
    """Render ``shots`` of the viewer page at ``url``; return the RGBA frames (H, W, 4)."""
    require_browser()
    spec: dict[str, object] = {
        "url": url,
        "viewport": {"width": viewport[0], "height": viewport[1]},
        "timeoutMs": int(timeout * 1000),
        "shots": [s.spec() for s in shots],
    }
    if screenshot is not None:
        spec["screenshot"] = str(screenshot)
    spec_path = shots[0].out.parent / "spec.json" if shots else Path("spec.json")
    spec_path.write_text(json.dumps(spec))
    proc = subprocess.run(["node", str(RENDER), str(spec_path)], capture_output=True, text=True,
                          timeout=timeout * 5, cwd=REPO)
    if proc.returncode != 0:
        raise AssertionError(
            f"render.mjs failed ({proc.returncode}):\n{proc.stdout}\n{proc.stderr}")
    frames = []
    for s in shots:
        meta = json.loads(Path(str(s.out) + ".json").read_text())
        raw = np.frombuffer(s.out.read_bytes(), np.uint8)
        frames.append(raw.reshape(meta["height"], meta["width"], 4))
    return frames
