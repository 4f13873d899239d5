"""Shared pytest fixtures: a live server on a free loopback port, the lens tests' dataset; the
Hypothesis profiles of the property-based tests and their outcome table.

Helpers (synthetic data, servers, paths) live in ``tests/python/fixtures/``. The property-based
tests run the ``ci`` profile (fixed seed, bounded examples: deterministic, a few minutes);
``HYPOTHESIS_PROFILE=long`` runs 20 times as many random examples (docs/reliability.md).
"""

from __future__ import annotations

import os
from collections.abc import Callable, Iterator
from pathlib import Path

import pytest
from hypothesis import HealthCheck, settings

from tests.python.fixtures import fuzz
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


_RELAXED = [HealthCheck.too_slow, HealthCheck.data_too_large, HealthCheck.filter_too_much]
settings.register_profile("ci", derandomize=True, database=None, deadline=None,
                          suppress_health_check=_RELAXED, print_blob=False)
settings.register_profile("long", derandomize=False, deadline=None,
                          suppress_health_check=_RELAXED)
settings.load_profile(os.environ.get("HYPOTHESIS_PROFILE", "ci"))


def pytest_terminal_summary(terminalreporter: pytest.TerminalReporter) -> None:
    """Print how many generated cases each format saw, and how they ended."""
    lines = fuzz.summary_lines()
    if lines:
        terminalreporter.write_sep("-", "property-based tests: generated cases per format")
        for line in lines:
            terminalreporter.write_line(line)
