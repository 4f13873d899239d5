"""Shared fixtures: synthetic PTMs, datasets and a live server on a free loopback port."""

from __future__ import annotations

import threading
from collections.abc import Callable, Iterator
from pathlib import Path

import numpy as np
import pytest
from werkzeug.serving import make_server

from lanterna.server.app import create_app
from lanterna.tiler.formats.ptm_model import Ptm

REPO = Path(__file__).resolve().parents[2]
SHARED = REPO.parent / "shared"


def shared_file(relative: str) -> Path:
    """Return a file of ../shared, or skip the test with a clear message if it is absent."""
    path = SHARED / relative
    if not path.is_file():
        pytest.skip(f"../shared/{relative} not present (read-only test data beside the repo)")
    return path


def random_ptm(width: int, height: int, colorspace: str = "lrgb", seed: int = 0) -> Ptm:
    """Return a PTM with random bytes and the scale/bias of real JPEG-LRGB files."""
    rng = np.random.default_rng(seed)
    shape = (height, width, 6) if colorspace == "lrgb" else (height, width, 3, 6)
    rgb = rng.integers(0, 256, (height, width, 3), dtype=np.uint8) if colorspace == "lrgb" else None
    return Ptm(colorspace, rng.integers(0, 256, shape, dtype=np.uint8),
               np.full(6, 2.0, np.float32), np.array([160, 160, 160, 127, 127, 0], np.int32), rgb)


class LiveServer:
    """The Lanterna app served by werkzeug in a thread on 127.0.0.1."""

    def __init__(self, root: Path) -> None:
        self.app = create_app({"DATA_ROOT": root})
        self._server = make_server("127.0.0.1", 0, self.app, threaded=True)
        self.port = self._server.server_port
        self.url = f"http://127.0.0.1:{self.port}"
        self._thread = threading.Thread(target=self._server.serve_forever, daemon=True)
        self._thread.start()

    def close(self) -> None:
        self._server.shutdown()
        self._thread.join(5)


@pytest.fixture
def live_server() -> Iterator[Callable[[Path], LiveServer]]:
    servers: list[LiveServer] = []

    def start(root: Path) -> LiveServer:
        servers.append(LiveServer(root))
        return servers[-1]

    yield start
    for s in servers:
        s.close()


@pytest.fixture(scope="module")
def lens_dataset(tmp_path_factory: pytest.TempPathFactory) -> object:
    """The overlay/lens/gesture tests' dataset (tests/python/lens_fixtures.py), once per module."""
    from .lens_fixtures import make_lens_dataset

    return make_lens_dataset(tmp_path_factory)
