"""Progress bars on stderr (tqdm), one way for every stage that loops over scenes.

The batch runner's bar, which also prints a line every few seconds when stderr is no terminal,
is :class:`planerel.batch._Progress`.
"""

from __future__ import annotations

import sys
from collections.abc import Iterable

__all__ = ["progress_bar"]


def progress_bar(items: Iterable, *, desc: str, enabled: bool | None = None, total: int | None = None,
                 unit: str = "scene", leave: bool = False) -> Iterable:
    """``items`` wrapped in a tqdm bar on stderr when ``enabled`` (``None``: when stderr is a
    terminal), else ``items`` itself.

    Parameters
    ----------
    items : iterable
        What the caller loops over.
    desc, unit : str
        The bar's label and unit.
    enabled : bool or None, optional
        Show the bar; ``None`` shows it only on a terminal.
    total : int, optional
        Length of ``items`` when it has none (a generator).
    leave : bool, optional
        Keep the finished bar on screen.
    """
    if enabled is None:
        enabled = sys.stderr.isatty()
    if not enabled:
        return items
    from tqdm import tqdm

    return tqdm(items, total=total, desc=desc, unit=unit, leave=leave)
