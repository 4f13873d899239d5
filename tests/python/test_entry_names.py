"""A dataset's hidden entry names: the writer makes them, the server and the sweep parse them."""

from __future__ import annotations

import pytest
from hypothesis import given
from hypothesis import strategies as st

from lanterna.tiler.entry_names import KINDS, entry_name, entry_prefix, is_version, parse_entry

_NAMES = st.text(st.characters(min_codepoint=33, max_codepoint=0x2FFF, exclude_characters="/"),
                 min_size=1, max_size=20)
_IDS = st.from_regex(r"[A-Za-z0-9_]{1,16}", fullmatch=True)


@given(_NAMES, st.sampled_from(KINDS), _IDS)
def test_a_made_name_parses_back_to_its_dataset_and_kind(name: str, kind: str, eid: str) -> None:
    made = entry_name(name, kind, eid)
    assert made.startswith(entry_prefix(name, kind))
    assert parse_entry(made) == (name, kind)
    assert is_version(made) == (kind == "v")


@pytest.mark.parametrize("name, parsed", [
    (".obj.v-20250101T000000_dead01", ("obj", "v")),
    (".obj.v-x.tmp-abc", ("obj.v-x", "tmp")),  # dataset "obj.v-x" being built: not a version
    (".obj.tmp-not_an-id", None),  # "-" is not in an id
    ("obj.v-20250101T000000_dead01", None),  # not hidden
    (".obj.v-", None),  # no id
    (".obj.new-abc", None),  # no such kind
])
def test_names_that_are_and_are_not_entries(name: str, parsed: tuple[str, str] | None) -> None:
    assert parse_entry(name) == parsed
    assert is_version(name) == (parsed is not None and parsed[1] == "v")


def test_a_bad_kind_or_id_is_refused() -> None:
    with pytest.raises(ValueError, match="kind"):
        entry_prefix("obj", "version")
    with pytest.raises(ValueError, match="id"):
        entry_name("obj", "v", "a-b")
