"""The default instance of each frozen parameter class, made once."""

from __future__ import annotations

from functools import cache


@cache
def defaults(cls):
    """``cls()``, made once per class.

    Building a parameter object validates every field (4-7 us), and describing one scene asks
    for the defaults of several classes; the objects are frozen dataclasses, so one instance
    serves every caller.

    Parameters
    ----------
    cls : type
        A frozen parameter dataclass whose fields all have defaults.

    Returns
    -------
    object
        The same ``cls()`` instance on every call.
    """
    return cls()
