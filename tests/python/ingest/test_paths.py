"""Where a description's files may be: anywhere from the command line, inside ``root`` otherwise."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from lanterna.errors import LanternaInputError
from lanterna.tiler.ingest.description import plan_description
from tests.python.fixtures.sources import png, random_image, seed_scene


def _description(folder: Path, source: str) -> Path:
    path = folder / "object.json"
    path.write_text(json.dumps({"layers": [{"id": "vis", "source": source}]}))
    return path


def test_a_description_may_name_files_outside_its_folder(tmp_path: Path) -> None:
    (tmp_path / "inside").mkdir()
    png(tmp_path / "outside.png", random_image(1))
    fields, plans = plan_description(_description(tmp_path / "inside", "../outside.png"))
    assert [p.id for p in plans] == ["vis"]


@pytest.mark.parametrize("name", ["../outside.png", "ABSOLUTE", "link.png"])
def test_with_a_root_every_file_must_be_inside_it(tmp_path: Path, name: str) -> None:
    inside = tmp_path / "inside"
    inside.mkdir()
    png(tmp_path / "outside.png", random_image(1))
    (inside / "link.png").symlink_to(tmp_path / "outside.png")  # resolved: outside
    name = str(tmp_path / "outside.png") if name == "ABSOLUTE" else name
    with pytest.raises(LanternaInputError, match=r"object.json: layers\[0\].source: .* is outside"):
        plan_description(_description(inside, name), root=inside)


def test_with_a_root_files_inside_it_are_read(tmp_path: Path) -> None:
    png(tmp_path / "vis.png", random_image(2))
    fields, plans = plan_description(_description(tmp_path, "vis.png"), root=tmp_path)
    assert [(p.id, p.width) for p in plans] == [("vis", 96)]


def test_a_scene_is_confined_too(tmp_path: Path) -> None:
    (tmp_path / "in").mkdir()
    scene = seed_scene(tmp_path / "in")
    plan_description(scene, root=tmp_path / "in")  # its own files: fine
    doc = json.loads(scene.read_text())
    doc["layers"][2]["obj"]["maps"]["N"] = "../../elsewhere/N.png"
    scene.write_text(json.dumps(doc))
    with pytest.raises(LanternaInputError, match=r"layers\[2\].obj.maps.N: .* is outside"):
        plan_description(scene, root=tmp_path / "in")
