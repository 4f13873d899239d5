"""A progress bar on standard error: redrawn in place on a terminal, every 10 % otherwise."""

from __future__ import annotations

import sys
import time
from typing import TextIO


class Progress:
    """Report ``done`` of ``total`` units of one stage (``label``).

    On a terminal the bar is redrawn in place (at most 10 times a second); in a log (not a
    TTY) one line is written per 10 % step, so CI logs stay short.  ``total == 0`` writes
    nothing.
    """

    def __init__(self, label: str, total: int, unit: str = "rows",
                 stream: TextIO | None = None) -> None:
        self.label, self.total, self.unit = label, total, unit
        self.stream = stream if stream is not None else sys.stderr
        self.tty = bool(getattr(self.stream, "isatty", lambda: False)())
        self.start = time.monotonic()
        self._last_draw = 0.0
        self._last_tenth = -1

    def update(self, done: int) -> None:
        """Set the units done so far."""
        if self.total <= 0:
            return
        frac = min(1.0, done / self.total)
        now = time.monotonic()
        if self.tty:
            if now - self._last_draw < 0.1 and done < self.total:
                return
            self._last_draw = now
            self.stream.write("\r" + self.line(done, now) + ("\n" if done >= self.total else ""))
        else:
            tenth = int(frac * 10)
            if tenth == self._last_tenth:
                return
            self._last_tenth = tenth
            self.stream.write(self.line(done, now) + "\n")
        self.stream.flush()

    def line(self, done: int, now: float) -> str:
        """The text of the bar for ``done`` units at time ``now``."""
        frac = min(1.0, done / self.total) if self.total else 1.0
        filled = int(round(frac * 24))
        elapsed = now - self.start
        eta = elapsed / frac - elapsed if frac > 0 else 0.0
        return (f"  {self.label:<24} [{'#' * filled}{'.' * (24 - filled)}] {frac * 100:5.1f}% "
                f"{done}/{self.total} {self.unit}  {_clock(elapsed)} elapsed, "
                f"{_clock(eta)} left")


def _clock(seconds: float) -> str:
    s = int(round(seconds))
    return f"{s // 3600}:{s // 60 % 60:02d}:{s % 60:02d}"
