"""The one Prolog term writer of planerel.

Every Prolog text planerel writes (scene facts, Aleph ``.b/.f/.n`` files) goes through these
functions, so that any id and any number becomes valid, readable Prolog:

* atoms are written bare when they are plain identifiers (``s0007_p03``) and quoted otherwise
  (``'my scan''s plane'`` is written ``'my scan\\'s plane'``); control characters and every
  non-ASCII character are written as ``\\xHEX\\`` escapes, so the files are pure ASCII and load
  the same whatever the locale;
* integers are written as they are; floats with Python's shortest round-trip representation,
  always with a decimal point (``1.0e-5``, never ``1e-05``), so ``swipl`` reads back exactly the
  same double; ``round_to`` gives shorter, readable values where exactness beyond it is noise;
* NaN and infinities are refused with :class:`~planerel.errors.InputError` (Prolog has no portable
  syntax for them and a learner must never see them).

Example
-------
>>> fact("area", "s0007_p03", 0.25)
'area(s0007_p03, 0.25).'
>>> atom("it's")
"'it\\\\'s'"
"""

from __future__ import annotations

import functools
import math
import re
from collections.abc import Iterable

from planerel.errors import InputError

__all__ = [
    "Term",
    "atom",
    "number",
    "term",
    "compound",
    "plist",
    "fact",
    "directive",
    "is_plain_atom",
    "scene_id",
    "plane_id",
    "object_id",
]

_PLAIN = re.compile(r"[a-z][a-zA-Z0-9_]*\Z")
_ESCAPES = {"\\": "\\\\", "'": "\\'", "\n": "\\n", "\t": "\\t", "\r": "\\r",
            "\a": "\\a", "\b": "\\b", "\f": "\\f", "\v": "\\v"}


_INF = float("inf")


class Term(str):
    """Text that is already a rendered Prolog term; :func:`term` passes it through unchanged."""

    __slots__ = ()


def is_plain_atom(name: str) -> bool:
    """Whether ``name`` can be written as an atom without quotes (``[a-z][a-zA-Z0-9_]*``)."""
    return bool(_PLAIN.match(name))


def atom(name) -> Term:
    """Render a Python string as a Prolog atom, quoting and escaping when needed.

    Parameters
    ----------
    name : str
        Any string, including the empty string, quotes, spaces and unicode.  Lone UTF-16
        surrogates (which are not characters) and the unassigned code points U+D8000..U+DFFFF
        (which SWI-Prolog 9.0 refuses to read as ``\\x..\\`` escapes) are refused.

    Returns
    -------
    Term
    """
    if not isinstance(name, str):
        raise InputError(f"a Prolog atom must be a string, got {name!r}")
    return _atom(name)


@functools.lru_cache(maxsize=65536)
def _atom(name: str) -> Term:
    if _PLAIN.match(name):
        return Term(name)
    out = ["'"]
    for ch in name:
        code = ord(ch)
        esc = _ESCAPES.get(ch)
        if esc is not None:
            out.append(esc)
        elif 32 <= code < 127:
            out.append(ch)
        elif 0xD800 <= code <= 0xDFFF:
            raise InputError(f"atom {name!r} holds a lone surrogate U+{code:04X}, not a character")
        elif 0xD8000 <= code <= 0xDFFFF:
            raise InputError(f"atom {name!r} holds the unassigned code point U+{code:05X}, which "
                             "SWI-Prolog 9 cannot read back in an escape")
        else:
            out.append(f"\\x{code:x}\\")
    out.append("'")
    return Term("".join(out))


def number(value, round_to: int | None = None) -> Term:
    """Render an int or a finite float as a Prolog number.

    Parameters
    ----------
    value : int or float (numpy scalars accepted)
    round_to : int, optional
        Decimal places to round a float to before writing (``None``: exact shortest
        round-trip representation).  ``-0.0`` becomes ``0.0``.

    Raises
    ------
    InputError
        For NaN, infinities, booleans and non-numbers.
    """
    if isinstance(value, bool):
        raise InputError(f"refusing to write a boolean {value!r} as a Prolog number")
    if isinstance(value, int):
        return Term(str(value))
    # numpy scalars and other numbers
    if hasattr(value, "dtype") and getattr(value.dtype, "kind", "") in "iu":
        return Term(str(int(value)))
    try:
        x = float(value)
    except (TypeError, ValueError):
        raise InputError(f"cannot write {value!r} as a Prolog number") from None
    if not math.isfinite(x):
        raise InputError(f"refusing to write {x!r} as a Prolog number (NaN and infinities "
                         "have no place in the facts)")
    if round_to is not None:
        x = round(x, int(round_to))
    if x == 0.0:
        x = 0.0  # drop the sign of -0.0
    text = repr(x)
    mantissa, e, exponent = text.partition("e")
    if "." not in mantissa:
        mantissa += ".0"
    if e:
        exponent = exponent.lstrip("+")
        sign = "-" if exponent.startswith("-") else ""
        exponent = sign + exponent.lstrip("-").lstrip("0")
        return Term(f"{mantissa}e{exponent}")
    return Term(mantissa)


def _arg(value, round_to: int | None) -> str:
    if isinstance(value, str):
        return value if isinstance(value, Term) else _atom(value)
    if type(value) is float and value == value and value not in (_INF, -_INF):
        x = round(value, round_to) if round_to is not None else value
        text = repr(x) if x != 0.0 else "0.0"
        if "e" not in text and "n" not in text:
            return text
        return number(value, round_to)
    if isinstance(value, (list, tuple)):
        return plist(value, round_to)
    return number(value, round_to)


def plist(items: Iterable, round_to: int | None = None) -> Term:
    """Render a Python sequence as a Prolog list ``[a, b, c]`` (elements as in :func:`term`)."""
    return Term("[" + ", ".join(_arg(v, round_to) for v in items) + "]")


def term(name: str, *args, round_to: int | None = None) -> Term:
    """Render ``name(args...)``.

    Arguments may be :class:`Term` (written as is), ``str`` (atoms), ints, floats, or
    lists/tuples of those (Prolog lists).  ``round_to`` applies to every float argument.
    """
    head = atom(name)
    if not args:
        return head
    return Term(f"{head}(" + ", ".join(_arg(a, round_to) for a in args) + ")")


compound = term


def fact(name: str, *args, round_to: int | None = None) -> Term:
    """A fact: ``name(args...).``"""
    return Term(term(name, *args, round_to=round_to) + ".")


def directive(name: str, *args) -> Term:
    """A directive: ``:- name(args...).``"""
    return Term(":- " + term(name, *args) + ".")


def scene_id(index_or_name) -> str:
    """Stable scene id: ``7 -> 's0007'``; a string is used as given (it must not be empty)."""
    if isinstance(index_or_name, str):
        if not index_or_name:
            raise InputError("a scene id must not be empty")
        return index_or_name
    if isinstance(index_or_name, bool) or int(index_or_name) != index_or_name or index_or_name < 0:
        raise InputError(f"a scene index must be a non-negative integer, got {index_or_name!r}")
    return f"s{int(index_or_name):04d}"


def plane_id(scene: str, index: int) -> str:
    """Stable plane id: ``('s0007', 3) -> 's0007_p03'`` (two digits or more)."""
    return f"{scene}_p{int(index):02d}"


def object_id(scene: str, index: int) -> str:
    """Stable object id: ``('s0007', 1) -> 's0007_o1'``."""
    return f"{scene}_o{int(index)}"

