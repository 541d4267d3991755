"""The sections of ``--param NAME=VALUE``, in the user's words.

A bare ``NAME`` is a segmentation parameter (region growing's, or the RANSAC baselines' with
``--method sp`` or ``snp``); ``SECTION.NAME`` sets a parameter of another section: ``split``
(the segmentation's post-processing), ``gravity``, ``planes``, ``relations``, ``proposals``,
``curved`` (the description) and ``decision`` (``classify``'s choice among the rules that
fired, and its gates).  This module is the one place that says so: the message for a name no
section has (:func:`unknown_parameters`), and the listing ``planerel params`` prints
(:func:`parameter_rows`).
"""

from __future__ import annotations

import dataclasses
import importlib
import inspect
import re

from planerel.errors import InputError, did_you_mean

__all__ = ["SECTIONS", "BARE", "section_class", "section_of", "names_of", "written",
           "unknown_parameters", "unknown_section", "parameter_rows", "meanings", "segmentation_only"]

#: section -> (module, dataclass, what it sets); the order of ``planerel params``
SECTIONS = {
    "segmentation": ("planerel.segment.params", "RegionGrowParams",
                     "region growing (--method regiongrow, the default)"),
    "ransac": ("planerel.segment.params", "RansacParams",
               "the RANSAC baselines (--method sp or snp)"),
    "split": ("planerel.segment.split", "SplitParams",
              "the segmentation's post-processing (split bent regions, merge pieces)"),
    "gravity": ("planerel.features.gravity", "GravityParams", "the up vector and the floor"),
    "planes": ("planerel.features.planes", "PlaneParams", "each plane's measures"),
    "relations": ("planerel.features.relations", "RelationParams",
                  "the relations between planes (adjacent, above, skirt, tall_face, ...)"),
    "proposals": ("planerel.features.relations", "ProposalParams",
                  "object proposals (which planes make one object)"),
    "curved": ("planerel.features.curved", "CurvedParams",
               "clusters of points no flat plane explains"),
    "decision": ("planerel.ilp.metrics", "DecisionParams",
                 "classify's choice among the rules that fired, and its gates"),
}
#: Sections whose parameters are given by a bare NAME (which one: the segmentation method).
BARE = ("segmentation", "ransac")
#: Bare names the segmentation takes besides its dataclass's fields.
_KEYWORDS = {"segmentation": ("preset", "split"), "ransac": ("split",)}
#: A section of at most this many parameters is listed whole in the message.
SHORT = 15
#: Where the full lists are, for the messages and the help.
LISTING = "planerel params"


def section_class(section: str):
    """The parameter dataclass of ``section`` (a key of :data:`SECTIONS`)."""
    module, cls, _ = SECTIONS[section]
    return getattr(importlib.import_module(module), cls)


def section_of(cls) -> str | None:
    """The section whose dataclass is ``cls``, or None."""
    for name, (module, cls_name, _) in SECTIONS.items():
        if cls.__module__ == module and cls.__name__ == cls_name:
            return name
    return None


def names_of(section: str) -> list[str]:
    """The parameter names of ``section``, in the dataclass's order."""
    return [f.name for f in dataclasses.fields(section_class(section))]


def written(section: str, key: str) -> str:
    """``key`` as ``--param`` takes it: bare for a segmentation parameter, else
    ``SECTION.key``."""
    return key if section in BARE else f"{section}.{key}"


def _dotted() -> str:
    return ", ".join(s for s in SECTIONS if s not in BARE)


def _elsewhere(section: str, key: str) -> list[str]:
    """``key`` as written in every other section that has it."""
    out = []
    for other in SECTIONS:
        if other == section or key not in names_of(other):
            continue
        if other in BARE:  # the other method's parameter
            out.append(f"{key} with --method {'regiongrow' if other == 'segmentation' else 'sp'}")
        else:
            out.append(written(other, key))
    return out


def _hint(section: str, key: str) -> str:
    """`` (did you mean X?)``: the same name in another section, else the closest name of
    ``section``, else ``""``."""
    others = _elsewhere(section, key)
    if others:
        return f" (did you mean {' or '.join(others)}?)"
    close = did_you_mean(key, [*names_of(section), *_KEYWORDS.get(section, ())])
    if close and section not in BARE:
        close = close.replace("mean ", f"mean {section}.", 1)
    return close


def _tail(section: str) -> str:
    """Where the section's parameters are listed (or the list itself, for a short one)."""
    names = names_of(section)
    if len(names) <= SHORT:
        return f"its parameters: {', '.join(names)} ('{LISTING} {section}' says what they do)"
    return f"'{LISTING} {section}' lists its {len(names)} parameters with their values and meaning"


def unknown_parameters(section: str, keys) -> InputError:
    """The error for parameter names ``keys`` that ``section`` does not have.

    Parameters
    ----------
    section : str
        A key of :data:`SECTIONS`: where the names were looked up.
    keys : iterable of str
        The unknown names, without the ``SECTION.`` prefix.

    Returns
    -------
    InputError
        One line: each name as the user wrote it, with the same name in another section or
        the closest one of this section; which section it was looked up in; and where the
        section's names are listed (the names themselves for a short section).
    """
    keys = sorted(str(k) for k in keys)
    dotted = [k for k in keys if "." in k and section in BARE]
    if dotted:  # SECTION.NAME with a section no one knows, read as a bare name
        return unknown_section(dotted[0])
    items = ", ".join(written(section, k) + _hint(section, k) for k in keys)
    many = len(keys) > 1
    if section in BARE:
        what = "segmentation parameter" + ("s" if many else "")
        what = (("not " if many else "not a ") + what
                + ("" if section == "segmentation" else " of --method sp or snp"))
        where = (f"{what} (a bare NAME is a segmentation parameter, SECTION.NAME one of "
                 f"the sections {_dotted()})")
    else:
        quoted = ", ".join(repr(k) for k in keys)
        where = f"{section} has no parameter{'s' if many else ''} {quoted}"
    return InputError(f"unknown parameter(s) {items}: {where}; {_tail(section)}")


def unknown_section(name: str) -> InputError:
    """The error for ``SECTION.NAME`` whose section does not exist."""
    sec = str(name).partition(".")[0]
    return InputError(f"unknown parameter(s) {name}: unknown section {sec!r}"
                      f"{did_you_mean(sec, [s for s in SECTIONS if s not in BARE])}; a bare "
                      f"NAME is a segmentation parameter, SECTION.NAME one of the sections "
                      f"{_dotted()}; '{LISTING}' lists the sections")


def _plain(text: str) -> str:
    """Docstring text without Sphinx roles and literal quotes, on one line."""
    text = re.sub(r":\w+:`~?([^`]*)`", lambda m: m.group(1).rsplit(".", 1)[-1], text)
    return " ".join(text.replace("``", "").split())


def meanings(cls) -> dict[str, str]:
    """``{field: description}`` from the class's numpy docstring (``name : type`` entries)
    and its ``#:`` comments before a field."""
    out: dict[str, str] = {}
    doc = inspect.getdoc(cls) or ""
    current, lines = None, []
    for line in doc.splitlines() + ["end"]:
        head = re.match(r"^(\w+(?:\s*,\s*\w+)*)\s+:\s", line)
        if head or (line and not line.startswith(" ")):
            if current:
                for n in current:
                    out.setdefault(n, _plain(" ".join(lines)))
            current = [n.strip() for n in head.group(1).split(",")] if head else None
            lines = []
        elif current is not None and line.strip():
            lines.append(line.strip())
    try:
        source = inspect.getsource(cls)
    except (OSError, TypeError):  # no source shipped: the docstring's entries only
        return out
    comment: list[str] = []
    for line in source.splitlines():
        s = line.strip()
        if s.startswith("#:"):
            comment.append(s[2:].strip())
            continue
        field = re.match(r"^(\w+)\s*:", s)
        if field and comment:
            out.setdefault(field.group(1), _plain(" ".join(comment)))
        comment = []
    return out


def _first_sentence(text: str, most: int = 170) -> str:
    """The first sentence of ``text``, cut at a word and ended with `` ...`` past ``most``
    characters."""
    m = re.match(r"(.+?\.)\s+[A-Z]", text)
    text = m.group(1) if m else text
    return text if len(text) <= most else text[:most].rsplit(" ", 1)[0] + " ..."


def parameter_rows(section: str, values: dict | None = None) -> list[tuple[str, object, str]]:
    """``(name as --param takes it, value, meaning)`` for each parameter of ``section``.

    Parameters
    ----------
    section : str
        A key of :data:`SECTIONS`.
    values : dict, optional
        ``{name: value}`` to show in place of the defaults (a model's settings); names it does
        not hold show the default.

    Returns
    -------
    list of (str, object, str)
        The meaning is the first sentence of the field's documentation, cut at about two
        lines ("" when it has none; :func:`meanings` has it whole).
    """
    cls = section_class(section)
    defaults = {f.name: (f.default if f.default is not dataclasses.MISSING
                         else f.default_factory() if f.default_factory is not dataclasses.MISSING
                         else None) for f in dataclasses.fields(cls)}
    said = meanings(cls)
    values = values or {}
    return [(written(section, n), values.get(n, v), _first_sentence(said.get(n, "")))
            for n, v in defaults.items()]


def segmentation_only(names, command: str) -> None:
    """Refuse ``SECTION.NAME`` (but ``split.NAME``) for ``command``, which takes segmentation
    parameters only (``segment``, ``learn``), saying which command takes it.

    Raises
    ------
    InputError
        For the first such name.
    """
    for name in names:
        sec, dot, _ = str(name).partition(".")
        if not dot or sec == "split":
            continue
        if sec not in SECTIONS or sec in BARE:
            raise unknown_section(name)
        also = "" if sec == "decision" else " (and of 'planerel describe')"
        raise InputError(f"--param {name}: {command} takes segmentation parameters (NAME or "
                         f"split.NAME); {sec}.NAME is a setting of 'planerel classify MODEL "
                         f"--param {name}=VALUE'{also}")
