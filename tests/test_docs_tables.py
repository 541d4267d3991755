"""Every Markdown table in the documentation has as many cells in each row as its header.

A ``|`` inside a cell (a Prolog list ``[A|B]``, a shell pipe, ``|cos|``) splits the cell in
GitHub's renderer even inside a code span unless written ``\\|``; the row then shows its text
under the wrong columns.  docs/status.md's issue-16 row once did this with a shell pipe.
"""

from __future__ import annotations

import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
DOCS = sorted((ROOT / "docs").glob("*.md")) + [ROOT / "README.md"]
_CELL_BAR = re.compile(r"(?<!\\)\|")


def cells(row: str) -> int:
    """The number of cells of a table row ``| a | b |`` (escaped bars ``\\|`` stay in a cell)."""
    return len(_CELL_BAR.split(row.strip())) - 2


def ragged_rows(text: str) -> list[tuple[int, int, int]]:
    """``(line number, header's cells, row's cells)`` of every table row whose count differs
    from its table's header; fenced code blocks are skipped."""
    out, header, fenced = [], None, False
    for n, line in enumerate(text.split("\n"), 1):
        if line.startswith("```"):
            fenced, header = not fenced, None
            continue
        if fenced or not line.startswith("|"):
            header = None
            continue
        c = cells(line)
        if header is None:
            header = c
        elif c != header:
            out.append((n, header, c))
    return out


def test_the_checker_sees_a_bar_that_splits_a_cell_and_not_an_escaped_one():
    table = "| a | b |\n|---|---|\n| `x|y` | 1 |\n| `x\\|y` | 1 |\n"
    assert ragged_rows(table) == [(3, 2, 3)]
    assert ragged_rows("```\n| a | b |\n| c |\n```\n") == []


@pytest.mark.parametrize("path", DOCS, ids=lambda p: p.name)
def test_every_table_row_has_its_headers_cells(path):
    assert ragged_rows(path.read_text(encoding="utf-8")) == []
