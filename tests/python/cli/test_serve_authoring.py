"""``lanterna serve``'s authoring options: the startup line says whether authoring is on (never
the token), a bad token file is one line before anything else, the environment works too."""

from __future__ import annotations

import json
import urllib.request
from pathlib import Path

import pytest

from lanterna.cli import main
from tests.python.fixtures.presets import read_json, small_dataset, small_library
from tests.python.fixtures.servers import lanterna_serve

TOKEN = "environment-token-0123456789"


@pytest.fixture(scope="module")
def root(tmp_path_factory: pytest.TempPathFactory) -> Path:
    root = tmp_path_factory.mktemp("root")
    small_dataset(root / "obj")
    return root


def _startup(root: Path, env: dict[str, str], *options: str,
             put: dict[str, object] | None = None) -> tuple[list[str], int | None]:
    """Start ``lanterna serve``, read its lines up to the authoring one, PUT ``put``, stop it."""
    status = None
    with lanterna_serve(root, *options, env=env) as (url, lines):
        if put is not None:
            req = urllib.request.Request(f"{url}/api/datasets/obj/presets", method="PUT",
                                         data=json.dumps(put).encode(),
                                         headers={"Authorization": f"Bearer {TOKEN}"})
            with urllib.request.urlopen(req, timeout=60) as resp:
                status = resp.status
    return lines, status


def test_without_a_token_authoring_is_off(root: Path) -> None:
    lines, _ = _startup(root, {"LANTERNA_AUTHORING_TOKEN": ""})
    assert lines[-1].startswith("Authoring API: off (read-only")


def test_the_environment_token_turns_authoring_on(root: Path) -> None:
    lines, status = _startup(root, {"LANTERNA_AUTHORING_TOKEN": TOKEN}, put=small_library())
    assert lines[-1] == ("Authoring API: on (token from $LANTERNA_AUTHORING_TOKEN); viewers can "
                         "save presets and annotations\n")
    assert not any(TOKEN in line for line in lines)
    assert status == 200 and read_json(root / "obj" / "presets.json") == small_library()


@pytest.mark.parametrize(("content", "problem"), [
    ("short", "the authoring token must be at least 16 characters (got 5)"),
    (None, "cannot read the authoring token file"),
])
def test_a_bad_token_file_is_one_line_before_anything_else(
        root: Path, tmp_path: Path, content: str | None, problem: str,
        capsys: pytest.CaptureFixture[str]) -> None:
    path = tmp_path / "token"
    if content is not None:
        path.write_text(content + "\n")
    assert main(["serve", str(root), "--authoring-token-file", str(path)]) == 2
    out, err = capsys.readouterr()
    assert out == ""
    assert err.startswith(f"lanterna: error: {path}: {problem}") and err.count("\n") == 1
