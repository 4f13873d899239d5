"""Each `lanterna COMMAND --help` ends with its own examples; `lanterna --help` is short."""

from __future__ import annotations

import pytest

from lanterna.cli import main

COMMANDS = ["import", "fit", "annotate", "presets", "serve", "demo", "export"]


def _help(argv: list[str], capsys: pytest.CaptureFixture[str]) -> str:
    with pytest.raises(SystemExit) as exit_:
        main([*argv, "--help"])
    assert exit_.value.code == 0
    return capsys.readouterr().out


@pytest.mark.parametrize("argv", [[c] for c in COMMANDS] +
                         [["annotate", a] for a in ("build", "list", "export", "import")] +
                         [["presets", a] for a in ("add", "list", "remove", "export", "import")],
                         ids=" ".join)
def test_each_command_ends_with_its_own_examples(argv: list[str],
                                                 capsys: pytest.CaptureFixture[str]) -> None:
    usage, _, examples = _help(argv, capsys).rpartition("\nexamples:\n")
    assert usage, "no examples section"
    assert "  -h, --help" in usage  # the examples come after the options
    own = f"  lanterna {' '.join(argv)} "
    assert own in examples
    for line in examples.splitlines():
        if line.startswith("  lanterna "):
            assert line.startswith(own), line
    for other in set(COMMANDS) - {argv[0]}:
        assert f"lanterna {other} " not in examples


def test_annotate_shows_both_actions_and_each_action_only_its_own(
        capsys: pytest.CaptureFixture[str]) -> None:
    group = _help(["annotate"], capsys)
    assert "lanterna annotate build" in group and "lanterna annotate list" in group
    assert "lanterna annotate list" not in _help(["annotate", "build"], capsys)
    assert "lanterna annotate build" not in _help(["annotate", "list"], capsys)


def test_the_global_help_is_a_short_overview(capsys: pytest.CaptureFixture[str]) -> None:
    out = _help([], capsys)
    assert len(out.splitlines()) <= 30
    for command in COMMANDS:
        assert f"\n    {command} " in out  # listed with its one-line help
    assert "lanterna COMMAND --help" in out
    assert "--fusion" not in out and "--base-url" not in out  # details live in each command
