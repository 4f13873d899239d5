"""Publishing a dataset in one atomic step, and clearing what killed writers left behind.

A dataset ``ROOT/NAME`` is a symbolic link to its current version, ``ROOT/.NAME.v-ID``, a
complete folder beside it. A writer builds the next version in ``.NAME.tmp-*``, renames it to
``.NAME.v-ID``, makes a link ``.NAME.link-ID`` to it and renames that link over ``NAME``: one
``rename(2)``, so at every instant ``NAME`` is the old version or the new one, whatever happens
to the writer. The old version is removed afterwards, unless a reader (:func:`reading`) holds it.
A dataset written as a plain folder by an earlier Lanterna is swapped for a link the same way
with ``renameat2(RENAME_EXCHANGE)`` (Linux), or with two renames where that is not available.

Hidden entries of one dataset (``.NAME.tmp-*``, ``.NAME.v-*``, ``.NAME.link-*``, ``.NAME.old-*``)
are only ever made by a writer holding the dataset's lock (:mod:`.lock`). So when a writer takes
the lock, any it finds are leftovers of a killed writer: :func:`writing` removes them (versions
only when no link points to them and no reader holds them), after finishing a publish that was
killed between its two renames. Every listing of datasets skips hidden names.
"""

from __future__ import annotations

import ctypes
import errno
import fcntl
import os
import secrets
import shutil
import tempfile
import time
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from functools import cache
from pathlib import Path

from lanterna.errors import LanternaInputError
from lanterna.tiler.entry_names import entry_name, entry_prefix, parse_entry

from .lock import dataset_lock, same_file
from .output import write_errors

_RENAME_EXCHANGE = 2
_AT_FDCWD = -100


@contextmanager
def writing(out: Path) -> Iterator[None]:
    """Hold the write lock of dataset ``out``; on taking it, clear what killed writers left.

    The folder ``out`` is in must exist.
    """
    out = Path(out)
    if not out.parent.is_dir():
        raise LanternaInputError(out.parent, "no such folder")
    with dataset_lock(out) as first:
        if first:
            with write_errors(out):
                recover(out)
                sweep(out)
        yield


def new_temp(out: Path) -> Path:
    """Make the empty folder ``.NAME.tmp-*`` beside ``out`` for building its next version."""
    with write_errors(out):
        tmp = Path(tempfile.mkdtemp(prefix=entry_prefix(out.name, "tmp"), dir=out.parent))
        tmp.chmod(0o755)  # mkdtemp makes it private; the published dataset is public
    return tmp


def publish(tmp: Path, out: Path) -> None:
    """Make the complete folder ``tmp`` the dataset ``out`` in one atomic step.

    ``tmp`` becomes the version ``.NAME.v-ID`` and ``out`` a link to it; the version ``out``
    pointed to before (or the plain folder it was) is removed, unless a reader holds it.
    Raises ``OSError`` with nothing changed if the new version cannot be put in place.
    """
    parent, name, vid = out.parent, out.name, _version_id()
    version, link = parent / entry_name(name, "v", vid), parent / entry_name(name, "link", vid)
    old: Path | None = None
    published = False
    os.rename(tmp, version)
    try:
        os.symlink(version.name, link)
        if out.is_symlink() or not os.path.lexists(out):
            old = _our_version(out)
            os.replace(link, out)  # the atomic step
            published = True
        else:  # a plain folder (an earlier Lanterna's dataset): swap it for the link
            old = parent / entry_name(name, "old", vid)
            if exchange(link, out):
                published = True
                old = link if _rename_quietly(link, old) is None else old
            else:  # no exchange here: a moment without `out`, which recover() finishes
                os.rename(out, old)
                try:
                    os.rename(link, out)
                except BaseException:
                    os.rename(old, out)
                    raise
                published = True
    finally:
        if not published:
            _remove(link)
            _remove(version)
    if old is not None:
        _remove(old, unless_read=True)


def replace_folder(tmp: Path, out: Path) -> None:
    """Put the complete folder ``tmp`` at ``out`` as a plain folder (exported trees).

    The swap is atomic where ``renameat2(RENAME_EXCHANGE)`` works (Linux), else two renames.
    """
    if not os.path.lexists(out):
        os.rename(tmp, out)
    elif exchange(tmp, out):
        _remove(tmp)  # now the previous tree
    else:
        old = out.with_name(entry_name(out.name, "old", _version_id()))
        os.rename(out, old)
        os.rename(tmp, out)
        _remove(old)


@contextmanager
def reading(dataset: Path) -> Iterator[Path]:
    """Yield the folder of ``dataset``'s current version, kept in place until the block ends.

    A shared ``flock`` on the version folder stops writers from removing it meanwhile (they
    leave it to a later sweep), so a long reader (``lanterna export``) sees one version whole.
    """
    dataset = Path(dataset)
    for _ in range(20):
        real = Path(os.path.realpath(dataset))
        try:
            fd = os.open(real, os.O_RDONLY | os.O_DIRECTORY)
        except FileNotFoundError:
            time.sleep(0.01)  # retired an instant ago: resolve the link again
            continue
        except OSError as err:
            raise LanternaInputError(dataset, f"cannot read ({err.strerror})") from None
        try:
            if _lock_shared(fd) and same_file(fd, dataset):
                yield real
                return
        finally:
            os.close(fd)
        time.sleep(0.01)
    raise LanternaInputError(dataset, "is being replaced again and again; try again later")


def sweep(out: Path) -> list[str]:
    """Remove the leftovers of killed writers of ``out``; return the names removed.

    Call with the dataset's lock held. Temporary folders, replaced plain folders and stale
    links always go; a version only when no link points to it and no reader holds it.
    """
    parent = out.parent
    ours = dict(_entries(out))
    kept = {os.path.realpath(parent / e.name) for e in os.scandir(parent)
            if e.is_symlink() and e.name not in ours}
    removed = []
    for entry, kind in sorted(ours.items()):
        path = parent / entry
        if kind == "v" and os.path.realpath(path) in kept:
            continue
        if _remove(path, unless_read=True):
            removed.append(entry)
    return removed


def recover(out: Path) -> None:
    """Finish a publish killed between its two renames (no ``out``, a complete link to it)."""
    if os.path.lexists(out):
        return
    links = sorted(entry for entry, kind in _entries(out) if kind == "link"
                   and (out.parent / entry).is_symlink() and (out.parent / entry).is_dir())
    if links:
        os.rename(out.parent / links[-1], out)


def list_datasets(root: Path) -> list[Path]:
    """Return the datasets of the data root ``root``: entries with a ``lanterna.json``.

    Hidden entries (versions, temporary and old folders, anything starting with ``.``) are
    never datasets.
    """
    names = sorted(e.name for e in os.scandir(root) if not e.name.startswith("."))
    return [root / n for n in names if (root / n / "lanterna.json").is_file()]


def exchange(a: Path, b: Path) -> bool:
    """Swap the entries ``a`` and ``b`` atomically; False where the system cannot."""
    renameat2 = _renameat2()
    if renameat2 is None:
        return False
    if renameat2(_AT_FDCWD, os.fsencode(a), _AT_FDCWD, os.fsencode(b), _RENAME_EXCHANGE) == 0:
        return True
    code = ctypes.get_errno()
    if code in (errno.ENOSYS, errno.EINVAL, errno.EOPNOTSUPP):
        return False  # an old kernel, or a file system without RENAME_EXCHANGE
    raise OSError(code, os.strerror(code), str(b))


@cache
def _renameat2() -> Callable[..., int] | None:
    try:
        fn = ctypes.CDLL(None, use_errno=True).renameat2
    except (AttributeError, OSError):  # not glibc ≥ 2.28 (macOS, musl before 1.2.3, …)
        return None
    fn.argtypes = [ctypes.c_int, ctypes.c_char_p, ctypes.c_int, ctypes.c_char_p, ctypes.c_uint]
    fn.restype = ctypes.c_int
    return fn


def _entries(out: Path) -> Iterator[tuple[str, str]]:
    """``(entry name, kind)`` of the hidden entries of dataset ``out`` in its folder."""
    for e in os.scandir(out.parent):
        parsed = parse_entry(e.name)
        if parsed and parsed[0] == out.name:
            yield e.name, parsed[1]


def _our_version(out: Path) -> Path | None:
    """The version folder the link ``out`` points to, if it is one of ours (else None)."""
    if not out.is_symlink():
        return None
    target = os.readlink(out)
    if "/" in target or parse_entry(target) != (out.name, "v"):
        return None
    return out.parent / target


def _version_id() -> str:
    return f"{time.strftime('%Y%m%dT%H%M%S', time.gmtime())}_{secrets.token_hex(3)}"


def _lock_shared(fd: int) -> bool:
    try:
        fcntl.flock(fd, fcntl.LOCK_SH | fcntl.LOCK_NB)
    except BlockingIOError:
        return False  # a writer is removing it
    except OSError:
        pass  # no flock on folders here: read without the guarantee
    return True


def _rename_quietly(src: Path, dst: Path) -> Path | None:
    try:
        os.rename(src, dst)
    except OSError:
        return None
    return dst


def _remove(path: Path, *, unless_read: bool = False) -> bool:
    """Remove a file, link or folder tree; with ``unless_read``, not a folder a reader holds."""
    try:
        if path.is_symlink() or not path.is_dir():
            path.unlink(missing_ok=True)
            return True
        fd = os.open(path, os.O_RDONLY | os.O_DIRECTORY)
    except OSError:
        return False
    try:
        if unless_read:
            try:
                fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
            except BlockingIOError:
                return False  # a reader holds it: a later sweep removes it
            except OSError:
                pass
        shutil.rmtree(path, ignore_errors=True)
        return not os.path.lexists(path)
    finally:
        os.close(fd)
