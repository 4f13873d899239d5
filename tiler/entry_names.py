"""How the hidden entries beside a dataset are named: ``.NAME.KIND-ID``.

A dataset ``ROOT/NAME`` is a link to its current version ``ROOT/.NAME.v-ID``. The other kinds are a
version being built (``tmp``), the next link before it is renamed over ``NAME`` (``link``) and a
replaced folder on its way out (``old``). Names only, no file system: the writer
(:mod:`lanterna.tiler.dataset.publish`) makes and sweeps them, the server recognises versions.
"""

from __future__ import annotations

import re

KINDS = ("tmp", "v", "link", "old")
_ID = r"[A-Za-z0-9_]+"
_ENTRY = re.compile(r"^\.(?P<name>.+)\.(?P<kind>" + "|".join(KINDS) + r")-(?P<id>" + _ID + r")$")


def entry_prefix(dataset: str, kind: str) -> str:
    """``.NAME.KIND-``: the name of dataset ``dataset``'s hidden entry of ``kind``, but its id."""
    if kind not in KINDS:
        raise ValueError(f"not an entry kind: {kind!r}")
    return f".{dataset}.{kind}-"


def entry_name(dataset: str, kind: str, entry_id: str) -> str:
    """The name of dataset ``dataset``'s hidden entry of ``kind`` with id ``entry_id``."""
    if not re.fullmatch(_ID, entry_id):
        raise ValueError(f"not an entry id: {entry_id!r}")
    return entry_prefix(dataset, kind) + entry_id


def parse_entry(name: str) -> tuple[str, str] | None:
    """``(dataset name, kind)`` if ``name`` is a hidden entry of a dataset, else ``None``."""
    m = _ENTRY.match(name)
    return (m.group("name"), m.group("kind")) if m else None


def is_version(name: str) -> bool:
    """Whether ``name`` is the name of a published version (``.NAME.v-ID``)."""
    parsed = parse_entry(name)
    return parsed is not None and parsed[1] == "v"
