"""Pure SVG path data (``<path d="…">``) to polylines: straight segments, curves flattened.

The commands of SVG 1.1 §8.3 except arcs: ``M L H V Z`` and the curves ``C S Q T``, absolute
(upper case) and relative (lower case), with implicit repetition (pairs after ``M`` are
``L``). Curves are flattened into equal steps of their parameter, as many as Wang's bound
asks for a distance of at most :data:`TOLERANCE` canvas pixels between curve and chords
(cubic: ``n = ceil(sqrt(0.75·d / tol))``, quadratic: ``sqrt(0.25·d / tol)``, ``d`` the largest
second difference of the control points). Arcs (``A``) are refused with a message saying so.
"""

from __future__ import annotations

import math
import re
from collections.abc import Iterator

Point = tuple[float, float]

#: Largest distance between a flattened curve and the curve, in canvas pixels.
TOLERANCE = 0.1
#: Most segments one curve is flattened into.
MAX_STEPS = 1024
_TOKEN = re.compile(r"\s*,?\s*([MmLlHhVvZzCcSsQqTtAa]|[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?)")
#: Numbers each command takes per repetition.
_ARITY = {"M": 2, "L": 2, "H": 1, "V": 1, "Z": 0, "C": 6, "S": 4, "Q": 4, "T": 2, "A": 7}


class PathError(ValueError):
    """Path data Lanterna cannot draw; ``str`` is one line."""


def parse_path(d: str) -> list[tuple[list[Point], bool]]:
    """Parse path data into subpaths ``(points, closed)`` in absolute canvas coordinates."""
    tokens = list(_tokens(d))
    subpaths: list[tuple[list[Point], bool]] = []
    points: list[Point] = []
    cur: Point = (0.0, 0.0)
    start: Point = cur
    prev_ctrl: tuple[str, Point] | None = None  # the last curve's kind and second control point
    i, cmd = 0, ""
    while i < len(tokens):
        if isinstance(tokens[i], str):
            cmd = str(tokens[i])
            i += 1
            if i == 1 and cmd not in "Mm":
                raise PathError("path data must start with a moveto (M or m)")
        elif not cmd:
            raise PathError("path data must start with a moveto (M or m)"
                            if i == 0 else "numbers after Z need a command before them")
        kind, rel = cmd.upper(), cmd.islower()
        if kind == "A":
            raise PathError("path arcs (A) are not supported: use <circle>, <ellipse> or "
                            "straight segments")
        if kind == "Z":
            if points:
                subpaths.append((points, True))
            points, cur, prev_ctrl, cmd = [], start, None, ""
            continue
        n = _ARITY[kind]
        args = tokens[i:i + n]
        if len(args) < n or any(isinstance(a, str) for a in args):
            raise PathError(f"command {cmd} needs {n} numbers")
        i += n
        v = [float(a) for a in args]
        ox, oy = cur if rel else (0.0, 0.0)
        if kind == "M":
            if len(points) > 1:
                subpaths.append((points, False))
            cur = start = (ox + v[0], oy + v[1])
            points = [cur]
            cmd = "l" if rel else "L"  # further pairs are linetos
            prev_ctrl = None
            continue
        if not points:
            points = [cur]
        if kind in ("L", "H", "V"):
            cur = ((ox + v[0], oy + v[1]) if kind == "L" else
                   (ox + v[0], cur[1]) if kind == "H" else (cur[0], oy + v[0]))
            points.append(cur)
            prev_ctrl = None
            continue
        pts = [(ox + v[k], oy + v[k + 1]) for k in range(0, n, 2)]
        if kind in ("S", "T"):  # the first control point mirrors the previous curve's last
            same = prev_ctrl is not None and prev_ctrl[0] == ("C" if kind == "S" else "Q")
            mirror = (2 * cur[0] - prev_ctrl[1][0], 2 * cur[1] - prev_ctrl[1][1]) \
                if same and prev_ctrl is not None else cur
            pts = [mirror, *pts]
        controls = [cur, *pts]
        points.extend(_flatten(controls))
        prev_ctrl = ("C" if len(controls) == 4 else "Q", controls[-2])
        cur = controls[-1]
    if len(points) > 1:
        subpaths.append((points, False))
    return subpaths


def _tokens(d: str) -> Iterator[str | float]:
    pos = 0
    d = d.strip()
    while pos < len(d):
        m = _TOKEN.match(d, pos)
        if m is None or m.end() == pos:
            raise PathError(f"unexpected {d[pos:pos + 12]!r} in path data")
        tok = m.group(1)
        yield tok if tok.isalpha() else float(tok)
        pos = m.end()
        while pos < len(d) and d[pos] in " \t\r\n,":
            pos += 1


def _flatten(ctrl: list[Point]) -> list[Point]:
    """Points after the first of a quadratic (3 controls) or cubic (4) Bézier curve."""
    second = [math.hypot(ctrl[k][0] - 2 * ctrl[k + 1][0] + ctrl[k + 2][0],
                         ctrl[k][1] - 2 * ctrl[k + 1][1] + ctrl[k + 2][1])
              for k in range(len(ctrl) - 2)]
    factor = 0.75 if len(ctrl) == 4 else 0.25
    steps = min(MAX_STEPS, max(1, math.ceil(math.sqrt(factor * max(second) / TOLERANCE))))
    out = []
    for s in range(1, steps + 1):
        t = s / steps
        out.append(_bezier(ctrl, t))
    return out


def _bezier(ctrl: list[Point], t: float) -> Point:
    pts = list(ctrl)
    while len(pts) > 1:  # de Casteljau
        pts = [((1 - t) * a[0] + t * b[0], (1 - t) * a[1] + t * b[1])
               for a, b in zip(pts, pts[1:], strict=False)]
    return pts[0]
