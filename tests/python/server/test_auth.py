"""The authoring token: read from a file or the environment, checked in constant time."""

from __future__ import annotations

import os
from pathlib import Path

import pytest

from lanterna.errors import LanternaInputError
from lanterna.server.auth import (
    MIN_TOKEN_LENGTH,
    TOKEN_ENV,
    authoring_token,
    bearer_matches,
    read_token_file,
)

TOKEN = "0123456789abcdef-token"


def test_the_first_line_of_the_file_is_the_token(tmp_path: Path) -> None:
    path = tmp_path / "token"
    path.write_text(f"  {TOKEN}  \nsecond line\n")
    assert read_token_file(path) == TOKEN
    assert authoring_token(path, {TOKEN_ENV: "another-token-from-env"}) == TOKEN


@pytest.mark.parametrize(("content", "problem"), [
    ("short\n", f"at least {MIN_TOKEN_LENGTH} characters (got 5)"),
    ("", "at least 16 characters (got 0)"),
    ("\n" + TOKEN, "at least 16 characters (got 0)"),
    ("0123456789abcdef\x07bell", "printable ASCII"),
])
def test_a_bad_token_file_is_a_one_line_error(tmp_path: Path, content: str,
                                              problem: str) -> None:
    path = tmp_path / "token"
    path.write_text(content)
    with pytest.raises(LanternaInputError) as info:
        read_token_file(path)
    assert str(info.value).startswith(f"{path}: ") and problem in str(info.value)
    assert "\n" not in str(info.value) and TOKEN not in str(info.value)


def test_the_file_must_be_a_regular_readable_file(tmp_path: Path) -> None:
    with pytest.raises(LanternaInputError, match="regular file"):
        read_token_file(tmp_path)
    with pytest.raises(LanternaInputError, match="cannot read"):
        read_token_file(tmp_path / "missing")
    fifo = tmp_path / "fifo"
    os.mkfifo(fifo)
    with pytest.raises(LanternaInputError, match="regular file"):
        read_token_file(fifo)  # refused before opening: no blocking read


def test_the_environment_is_used_without_a_file() -> None:
    assert authoring_token(None, {TOKEN_ENV: f" {TOKEN} "}) == TOKEN
    assert authoring_token(None, {}) is None
    assert authoring_token(None, {TOKEN_ENV: ""}) is None
    with pytest.raises(LanternaInputError, match=f"^{TOKEN_ENV}: the authoring token must"):
        authoring_token(None, {TOKEN_ENV: "short"})


@pytest.mark.parametrize(("header", "ok"), [
    (f"Bearer {TOKEN}", True), (f"bearer {TOKEN}", True), (f"Bearer  {TOKEN} ", True),
    (f"Bearer {TOKEN}x", False), (f"Bearer {TOKEN[:-1]}", False), (f"Basic {TOKEN}", False),
    (TOKEN, False), ("", False), (None, False), ("Bearer é", False),
])
def test_bearer_matches(header: str | None, ok: bool) -> None:
    assert bearer_matches(header, TOKEN) is ok
