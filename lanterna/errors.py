"""Errors raised for bad input: one line, naming the file and the problem."""

from __future__ import annotations

from pathlib import Path


class LanternaInputError(Exception):
    """Bad input file or argument; ``str(err)`` is a one-line message for the user."""

    def __init__(self, source: str | Path | None, problem: str) -> None:
        self.source = str(source) if source is not None else None
        self.problem = problem
        super().__init__(f"{self.source}: {problem}" if self.source else problem)
