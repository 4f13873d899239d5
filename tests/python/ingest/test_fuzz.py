"""Property-based: mutated description and scene files are imported or refused in one line.

A description with a layer of every kind (a PTM with an overlay entry, shape + material maps,
spectral bands with a fusion) and a seed-paper scene are mutated — values replaced by any JSON
value (wrong types, huge numbers, 5,000-character and ``/`` names, ``/dev/zero``, ``..``),
keys deleted or added — and imported whole (planned, tiled, manifest written): each must give a
dataset or a one-line ``LanternaInputError`` naming a file of the case, within the case bounds
of ``fixtures/fuzz.py``, and a refused import leaves no output.
"""

from __future__ import annotations

import json
import shutil
import tempfile
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from lanterna.tiler.ingest.importer import import_sources
from tests.python.fixtures.fuzz import examples, mutate_json, outcome
from tests.python.fixtures.ptm import random_ptm_of_size
from tests.python.fixtures.ptm_writer import write_ptm
from tests.python.fixtures.sources import H, W, png, random_image, random_normal_map, seed_scene

DESCRIPTION: dict[str, Any] = {
    "name": "obj", "label": "Object", "summary": "<p>An object</p>",
    "layers": [
        {"id": "vis", "source": "vis.ptm", "label": "Visible",
         "overlay": {"img": "ov.png", "range": [0, 1], "shortInfo": ["a", "b"]}},
        {"id": "mat", "type": "svbrdf", "label": "Material",
         "maps": {"normals": "N.png", "kd": "kd.png", "ks": "ks.png", "gloss": "gloss.png",
                  "depth": "z.png"},
         "glossLimits": [0.01, 0.5], "inputColorSpace": "srgb", "normalConvention": "opengl"},
        {"type": "bands", "bands": {"IR": "ir.png", "R": "r.png", "G": "g.png"},
         "fusions": [["IR", "R", "G"]]},
    ],
}


@pytest.fixture(scope="module")
def sources(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """The files the description names (W × H, small so that every case is fast)."""
    folder = tmp_path_factory.mktemp("sources")
    write_ptm(folder / "vis.ptm", random_ptm_of_size(W, H), "PTM_FORMAT_LRGB")
    png(folder / "N.png", random_normal_map(1))
    for i, name in enumerate(("kd", "ks")):
        png(folder / f"{name}.png", random_image(2 + i))
    for i, name in enumerate(("gloss", "z", "ir", "r", "g")):
        png(folder / f"{name}.png", random_image(10 + i, 1))
    overlay = np.zeros((H, W, 4), np.uint8)
    overlay[4:20, 4:30] = (255, 0, 0, 200)
    png(folder / "ov00.png", overlay)
    return folder


def _case(sources: Path, scratch: Path, name: str, doc: Any) -> tuple[Path, Path]:
    folder = Path(tempfile.mkdtemp(dir=scratch))
    shutil.copytree(sources, folder / "in")
    path = folder / "in" / name
    path.write_text(json.dumps(doc))
    return path, folder / "out"


@pytest.fixture(scope="module")
def scratch(tmp_path_factory: pytest.TempPathFactory) -> Path:
    return tmp_path_factory.mktemp("cases")


@settings(max_examples=examples(300))
@given(data=st.data())
def test_mutated_descriptions(sources: Path, scratch: Path, data: st.DataObject) -> None:
    path, out = _case(sources, scratch, "object.json", mutate_json(DESCRIPTION, data.draw))
    made = outcome("description JSON", path.parent, lambda: import_sources([path], out))
    assert (made is not None) == out.is_dir(), "a refused import left output behind"
    shutil.rmtree(path.parent.parent)


@pytest.fixture(scope="module")
def scene_folder(tmp_path_factory: pytest.TempPathFactory) -> Path:
    folder = tmp_path_factory.mktemp("scene")
    seed_scene(folder)
    return folder


@settings(max_examples=examples(200))
@given(data=st.data())
def test_mutated_scenes(scene_folder: Path, scratch: Path, data: st.DataObject) -> None:
    scene = json.loads((scene_folder / "scene.json").read_text())
    path, out = _case(scene_folder, scratch, "scene.json", mutate_json(scene, data.draw))
    made = outcome("scene JSON", path.parent, lambda: import_sources([path], out))
    assert (made is not None) == out.is_dir(), "a refused import left output behind"
    shutil.rmtree(path.parent.parent)


def test_the_unmutated_documents_import(sources: Path, scene_folder: Path,
                                        tmp_path: Path) -> None:
    """The fuzzed documents are valid to start with (so mutations explore near valid input)."""
    path, out = _case(sources, tmp_path, "object.json", DESCRIPTION)
    assert import_sources([path], out) == out
    assert json.loads((out / "lanterna.json").read_text())["layers"][0]["overlay"]["levels"]
    scene = json.loads((scene_folder / "scene.json").read_text())
    path, out = _case(scene_folder, tmp_path, "scene.json", scene)
    assert import_sources([path], out) == out
