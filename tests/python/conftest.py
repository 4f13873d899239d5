"""Shared pytest fixtures: a live server on a free loopback port, the lens tests' dataset.

Helpers (synthetic data, servers, paths) live in ``tests/python/fixtures/``.
"""

from __future__ import annotations

from collections.abc import Callable, Iterator
from pathlib import Path

import pytest

from tests.python.fixtures.lens import Dataset, make_lens_dataset
from tests.python.fixtures.servers import LiveServer


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
def lens_dataset(tmp_path_factory: pytest.TempPathFactory) -> Dataset:
    """The overlay/lens/gesture tests' dataset (fixtures/lens.py), once per module."""
    return make_lens_dataset(tmp_path_factory)
