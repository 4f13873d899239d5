"""Read light-position (``.lp``) files as they occur in the wild.

The format (``docs/fitting.md``; RTIBuilder, Relight, NeuralRTI): a first line with the image
count N, then N lines ``filename x y z``.  File names may carry Windows (``jpeg-exports\\0.jpg``),
relative or absolute paths, may differ in case from the files on disk, and may contain spaces
(extra tokens are rejoined, as Relight's ``parseLP`` does).  Directions are normalised to unit
length (x right, y up, z toward the camera).
"""

from __future__ import annotations

import math
from pathlib import Path, PureWindowsPath

import numpy as np
import numpy.typing as npt

from lanterna.errors import LanternaInputError
from lanterna.tiler.fileio import read_input

#: Largest .lp file read (a dome of 10,000 lights is about 0.5 MB).
MAX_LP_BYTES = 16 << 20


def read_lp(path: Path, images_dir: Path) -> tuple[list[Path], npt.NDArray[np.float64]]:
    """Return the image files named by ``path`` (found in ``images_dir``) and unit lights.

    Each name is resolved, in this order: as a path relative to the ``.lp`` file's folder (how
    collections are laid out: ``dirs.lp`` beside a ``jpg/`` folder it names, ``jpg/NAME.jpg``;
    ``\\`` or ``/``, each part exactly first, then case-insensitively); then by its base name
    in ``images_dir`` (any folder part dropped), exactly first, then case-insensitively.

    Returns
    -------
    files : list of Path
        One existing file per light, in the order of the ``.lp`` file.
    lights : ndarray, shape (N, 3)
        Unit light directions.

    Raises
    ------
    LanternaInputError
        One line naming the file (and line) on a bad count, a short or non-numeric row, a zero
        or non-finite vector, a count that does not match the rows, or an image not on disk.
    """
    path, images_dir = Path(path), Path(images_dir)
    text = read_input(path, "a light-position (.lp) file",
                      max_bytes=MAX_LP_BYTES).decode("utf-8-sig", errors="replace")
    lines = [(no, line.strip()) for no, line in enumerate(text.splitlines(), 1)]
    lines = [(no, line) for no, line in lines if line and not line.startswith("#")]
    if not lines:
        raise LanternaInputError(path, "empty light file (expected a count line, then "
                                 "'filename x y z' rows)")
    count_no, count_text = lines[0]
    try:
        count = int(count_text)
    except ValueError:
        raise LanternaInputError(path, f"line {count_no}: expected the image count, got "
                                 f"{count_text[:40]!r}") from None
    if count < 1:
        raise LanternaInputError(path, f"line {count_no}: image count must be at least 1, "
                                 f"got {count}")
    rows = lines[1:]
    if len(rows) != count:
        raise LanternaInputError(path, f"line {count_no}: says {count} images but "
                                 f"{len(rows)} rows follow")
    on_disk = _files_by_name(images_dir)
    files: list[Path] = []
    lights = np.empty((count, 3), np.float64)
    for i, (no, line) in enumerate(rows):
        tokens = line.split()
        if len(tokens) < 4:
            raise LanternaInputError(path, f"line {no}: expected 'filename x y z', got "
                                     f"{line[:60]!r}")
        name = " ".join(tokens[:-3])
        try:
            vec = [float(t) for t in tokens[-3:]]
        except ValueError:
            raise LanternaInputError(path, f"line {no}: non-numeric direction "
                                     f"{' '.join(tokens[-3:])!r}") from None
        norm = math.sqrt(sum(v * v for v in vec))
        if not math.isfinite(norm):
            raise LanternaInputError(path, f"line {no}: non-finite direction for {name}")
        if norm < 1e-9:
            raise LanternaInputError(path, f"line {no}: zero light vector for {name}")
        lights[i] = [v / norm for v in vec]
        files.append(_beside(path.parent, name) or _find(path, no, name, images_dir, on_disk))
    return files, lights


def _beside(folder: Path, name: str) -> Path | None:
    """The regular file ``name`` names relative to ``folder`` (its parts matched exactly, else
    case-insensitively when that is unambiguous), or None. Absolute names and ``..`` are not
    followed: an ``.lp`` names files of its own collection."""
    parts = PureWindowsPath(name).parts  # splits on both \\ and /
    if not parts or PureWindowsPath(name).anchor or any(p in ("..", ".") for p in parts):
        return None
    here = folder
    try:  # a name the file system refuses (too long, a NUL …) is not a path of the collection
        for part in parts:
            step = here / part
            if not step.exists():
                matches = [e for e in here.iterdir() if e.name.lower() == part.lower()]
                if len(matches) != 1:
                    return None
                step = matches[0]
            here = step
        return here if here.is_file() else None
    except (OSError, ValueError):
        return None


def _basename(name: str) -> str:
    """Return the last path component of ``name``, Windows or POSIX."""
    return PureWindowsPath(name).name


def _files_by_name(folder: Path) -> dict[str, list[Path]]:
    """Map lower-cased file names in ``folder`` to the files."""
    out: dict[str, list[Path]] = {}
    if folder.is_dir():
        for f in sorted(folder.iterdir()):
            if f.is_file():
                out.setdefault(f.name.lower(), []).append(f)
    return out


def _find(lp: Path, no: int, name: str, folder: Path, on_disk: dict[str, list[Path]]) -> Path:
    base = _basename(name)
    candidates = on_disk.get(base.lower(), [])
    exact = [f for f in candidates if f.name == base]
    if exact:
        return exact[0]
    if len(candidates) == 1:
        return candidates[0]
    if candidates:
        raise LanternaInputError(lp, f"line {no}: {base} matches several files in {folder} "
                                 f"that differ only in case")
    raise LanternaInputError(lp, f"line {no}: image {base} not found in {folder}")
