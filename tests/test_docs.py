"""The examples of docs/api.md run as written (from the repository root, as the page says)."""

from __future__ import annotations

import doctest
import os
import re
from pathlib import Path

import pytest

DOCS = Path(__file__).resolve().parents[1] / "docs"


@pytest.mark.parametrize("page", ["api.md"])
def test_doc_examples(page: str, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(DOCS.parent)
    result = doctest.testfile(
        str(DOCS / page), module_relative=False, optionflags=doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE
    )
    assert result.attempted > 10, "the page lost its examples"
    assert result.failed == 0, f"{result.failed} examples of {page} failed (run: python -m doctest -v docs/{page})"
    assert os.getcwd() == str(DOCS.parent)


def _pages() -> list[Path]:
    return [DOCS.parent / "README.md", *sorted(DOCS.glob("*.md"))]


def test_docs_name_no_file_beside_the_developers_checkout() -> None:
    """No page points into ``../shared`` (the developers' maps, beside their checkout only): an example
    uses a file the repository ships, or says the map is the reader's own."""
    found = [
        f"{page.name}:{number}: {line.strip()}"
        for page in _pages()
        for number, line in enumerate(page.read_text(encoding="utf-8").splitlines(), start=1)
        if "../shared" in line
    ]
    assert found == []


def test_doc_commands_name_shipped_files() -> None:
    """Each repository path (``levels/...``, ``tests/data/...``, ``examples/...``) in a command of a code
    block is there, so the command runs from a fresh clone."""
    missing = []
    for page in _pages():
        block = False
        for number, line in enumerate(page.read_text(encoding="utf-8").splitlines(), start=1):
            if line.lstrip().startswith("```"):
                block = not block
                continue
            command = line.strip().removeprefix("$ ")
            if block and command.startswith(("guardsim ", ".venv/bin/guardsim ", "python")):
                for path in re.findall(r"(?<![\w/.])((?:levels|tests/data|examples)/[\w./-]*\w)", command):
                    if not (DOCS.parent / path).exists():
                        missing.append(f"{page.name}:{number}: {path}")
    assert missing == []


def test_where_things_live_names_files_that_are_there() -> None:
    """Every file and folder docs/architecture.md names (``guardsim/...``, ``docs/...``, ``tests/...``) is
    there, and each name it gives in a file (``PLANNERS`` in ``guardsim/planners/__init__.py``) is in it."""
    text = (DOCS / "architecture.md").read_text(encoding="utf-8")
    paths = set(re.findall(r"`((?:guardsim|docs|tests)/[\w./-]*)`", text))
    assert len(paths) > 20, "the page lost its paths"
    assert sorted(path for path in paths if not (DOCS.parent / path).exists()) == []
    for name, path in re.findall(r"`(\w+)` in `(guardsim/[\w./-]+)`", text):
        assert name in (DOCS.parent / path).read_text(encoding="utf-8"), (name, path)
