"""Errors raised for bad input: one line, naming the file and the problem."""

from __future__ import annotations

from pathlib import Path


class LanternaInputError(Exception):
    """Bad input file or argument; ``str(err)`` is a one-line message for the user.

    Control characters in the file name or the problem (a file named with a newline, a value
    quoted from the input) are shown escaped, so the message stays one line.
    """

    def __init__(self, source: str | Path | None, problem: str) -> None:
        self.source = str(source) if source is not None else None
        self.problem = problem
        text = f"{self.source}: {problem}" if self.source else problem
        super().__init__(text.translate(_ESCAPES))


#: Control characters (C0, DEL, the line and paragraph separators) → their escapes.
_ESCAPES = {c: repr(chr(c))[1:-1] for c in [*range(32), 127, 0x85, 0x2028, 0x2029]}
