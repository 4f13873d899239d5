"""The shared corpus (tests/data/presets): valid libraries pass, each invalid one fails naming
the JSON path its ``.expected`` file holds."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import pytest

from lanterna.tiler.demo.presets import demo_presets
from lanterna.tiler.presets.library import PresetError, check_library, read_library
from tests.python.fixtures.presets import corpus, demo_description, read_json


@pytest.fixture(scope="module")
def desc(tmp_path_factory: pytest.TempPathFactory) -> dict[str, Any]:
    return demo_description(tmp_path_factory.mktemp("demo"))


def test_the_corpus_is_there() -> None:
    assert len(corpus("valid")) >= 4
    assert len(corpus("invalid")) >= 12
    for path in corpus("invalid"):
        assert path.with_suffix(".expected").is_file(), path


@pytest.mark.parametrize("path", corpus("valid"), ids=lambda p: p.stem)
def test_valid_libraries_pass(path: Path, desc: dict[str, Any]) -> None:
    doc = read_json(path)
    assert read_library(path, desc) == doc  # accepted, and returned as given


@pytest.mark.parametrize("path", corpus("invalid"), ids=lambda p: p.stem)
def test_invalid_libraries_name_their_path(path: Path, desc: dict[str, Any]) -> None:
    expected = path.with_suffix(".expected").read_text().strip()
    with pytest.raises(PresetError) as info:
        read_library(path, desc)
    message = str(info.value)
    assert "\n" not in message
    assert message.startswith(f"{path.name}: {expected}: "), message


def test_the_demo_library_in_the_corpus_is_the_demos(desc: dict[str, Any]) -> None:
    assert read_json(next(p for p in corpus("valid") if p.stem == "demo")) == \
        demo_presets(1536, 1152)
    check_library(demo_presets(1536, 1152), desc)


def test_the_invalid_cases_are_valid_json_objects_of_the_library_shape() -> None:
    # each invalid file is broken in one place, not unreadable: the validators see a library
    for path in corpus("invalid"):
        doc = read_json(path)
        assert isinstance(doc, dict) and "presets" in doc, path
