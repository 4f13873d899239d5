"""Checking and editing libraries: the rules beyond the schema, and the edit functions."""

from __future__ import annotations

import copy
from typing import Any

import pytest

from lanterna.errors import LanternaInputError
from lanterna.tiler.presets.edit import add_entry, add_preset, merge_libraries, remove_preset
from lanterna.tiler.presets.library import (
    LIGHT_SLACK,
    PresetError,
    check_library,
    empty_library,
)
from tests.python.fixtures.presets import small_library

#: A description with the small dataset's layers (a PTM, an image) and size.
DESC: dict[str, Any] = {
    "width": 96, "height": 64,
    "layers": [{"id": "ptm", "service": {"layerType": "ptm", "colorspace": "lrgb"}},
               {"id": "uv", "service": {"layerType": "image"}}]}


def test_a_library_is_returned_as_a_copy() -> None:
    lib = small_library()
    out = check_library(lib, DESC)
    assert out == lib
    out["presets"]["raking"]["label"] = "changed"
    assert lib["presets"]["raking"]["label"] == "Raking"


def test_the_empty_library_is_valid() -> None:
    assert check_library(empty_library(), DESC) == empty_library()


def test_a_light_on_the_circle_passes_and_just_beyond_it_fails() -> None:
    lib = small_library()
    lib["presets"]["raking"]["light"] = [0.6, 0.8]  # 0.36 + 0.64 = 1 (within rounding)
    check_library(lib, DESC)
    lib["presets"]["raking"]["light"] = [0.6, 0.8 + 1e-6]
    with pytest.raises(PresetError, match=r"presets\.raking\.light: .* unit disk"):
        check_library(lib, DESC)
    assert LIGHT_SLACK < 1e-6


def test_a_view_must_fit_the_image() -> None:
    lib = small_library()
    lib["presets"]["raking"]["view"] = [0, 0, 96, 64]
    check_library(lib, DESC)
    for view in ([1, 0, 96, 64], [0, 0.5, 96, 64], [0, -0.1, 10, 10]):
        lib["presets"]["raking"]["view"] = view
        with pytest.raises(PresetError, match=r"presets\.raking\.view: .*96×64"):
            check_library(lib, DESC)


def test_an_entry_takes_its_presets_layer_unless_it_names_one() -> None:
    lib = small_library()
    lib["presets"]["gain"] = {"label": "Gain", "layer": "ptm", "mode": "diffuseGain"}
    lib["base"].append({"label": "Gain", "preset": "gain"})  # on ptm: applies
    check_library(lib, DESC)
    lib["base"].append({"label": "Gain on UV", "preset": "gain", "layer": "uv"})
    with pytest.raises(PresetError, match=r"^presets\.json: base\[2\]\.layer: the mode "
                                          r"'diffuseGain' of preset 'gain' does not apply"):
        check_library(lib, DESC)


def test_a_layer_of_unknown_type_is_one_line() -> None:
    desc = copy.deepcopy(DESC)
    desc["layers"][1]["service"]["layerType"] = "hologram"
    lib = small_library()
    with pytest.raises(PresetError, match=r"presets\.uv\.mode: layer 'uv' has no render modes"):
        check_library(lib, desc)


def test_errors_name_the_source_given() -> None:
    lib = small_library()
    lib["lens"][0]["preset"] = "ghost"
    with pytest.raises(PresetError) as info:
        check_library(lib, DESC, "mine.json")
    assert str(info.value) == "mine.json: lens[0].preset: no preset 'ghost' (presets: raking, uv)"


def test_add_preset_refuses_an_existing_id_unless_replacing() -> None:
    lib = small_library()
    new = {"label": "Top", "layer": "ptm", "mode": "color", "light": [0, 0]}
    with pytest.raises(LanternaInputError, match="exists already"):
        add_preset(lib, "raking", new)
    out = add_preset(lib, "raking", new, replace=True)
    assert out["presets"]["raking"] == new and lib["presets"]["raking"]["label"] == "Raking"
    assert add_preset(lib, "top", new)["presets"]["top"] == new


def test_add_entry_appends_to_the_list_named() -> None:
    lib = add_entry(small_library(), "lens", {"label": "Raking lens", "preset": "raking"})
    assert [e["label"] for e in lib["lens"]] == ["UV lens", "Raking lens"]
    assert small_library()["lens"] == [{"label": "UV lens", "preset": "uv", "opacity": 0.8}]
    with pytest.raises(ValueError):
        add_entry(lib, "middle", {"label": "x", "preset": "uv"})


def test_remove_preset_drops_its_entries_and_says_which() -> None:
    lib = add_entry(small_library(), "base", {"label": "UV as base", "preset": "uv"})
    out, dropped = remove_preset(lib, "uv")
    assert "uv" not in out["presets"]
    assert dropped == ["base: UV as base", "lens: UV lens"]
    assert out["base"] == [{"label": "Raking light", "preset": "raking"}] and out["lens"] == []
    check_library(out, DESC)
    with pytest.raises(LanternaInputError, match=r"no preset 'uv' \(presets: raking\)"):
        remove_preset(out, "uv")


def test_merge_adds_presets_and_replaces_entries_of_the_same_label() -> None:
    old = small_library()
    new = {"type": "LanternaPresets", "version": 1,
           "presets": {"raking": {"label": "Raking 2", "layer": "ptm", "mode": "normals"},
                       "flat": {"label": "Flat", "layer": "uv", "mode": "color"}},
           "base": [{"label": "Raking light", "preset": "flat"}], "lens": []}
    out = merge_libraries(old, new)
    assert set(out["presets"]) == {"raking", "uv", "flat"}
    assert out["presets"]["raking"]["label"] == "Raking 2"
    assert out["base"] == [{"label": "Raking light", "preset": "flat"}]
    assert out["lens"] == old["lens"]
    check_library(out, DESC)
