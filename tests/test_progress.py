"""planerel.progress.progress_bar: the one progress bar of the scene loops."""

import io
import sys

from planerel.progress import progress_bar


def test_off_gives_the_items_themselves():
    items = [1, 2, 3]
    assert progress_bar(items, desc="x", enabled=False) is items


def test_on_wraps_and_yields_every_item(monkeypatch):
    err = io.StringIO()
    monkeypatch.setattr(sys, "stderr", err)
    bar = progress_bar(iter(range(4)), desc="scenes", enabled=True, total=4, leave=True)
    assert list(bar) == [0, 1, 2, 3]
    assert "scenes: 100%" in err.getvalue() and "4/4" in err.getvalue()


def test_default_follows_the_terminal(monkeypatch):
    monkeypatch.setattr(sys, "stderr", io.StringIO())  # no terminal: no bar
    items = (5, 6)
    assert progress_bar(items, desc="x") is items
