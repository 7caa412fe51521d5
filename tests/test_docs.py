"""The examples of docs/api.md run as written (from the repository root, as the page says)."""

from __future__ import annotations

import doctest
import os
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
