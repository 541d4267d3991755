"""One naming rule for scenes: scene ids and output file names come from the input's file name.

The name of a scan is its file name without the format extension and without a trailing
``.depth`` / ``_depth`` / ``-depth`` (the same rule that finds a frame's sidecar JSON or OpenNI
XML, :mod:`planerel.io.readers`)::

    data/s0003.depth.png                         -> s0003
    kinect/frame_20121214T142256.068683_depth.tiff -> frame_20121214T142256.068683
    abw/abw.test.12.range                        -> abw.test.12
    office1.pcd                                  -> office1

``segment``, ``describe`` and ``classify`` use that name as the scene id (a Prolog atom, quoted
when needed) and as the stem of every file they write, so ``NAME.labels.npy``,
``scene(NAME)`` and ``NAME.classified.json`` always belong together.  Two inputs with the
same name are refused before anything is written.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

from planerel.errors import InputError

__all__ = ["SCAN_EXTENSIONS", "QUALIFIERS", "scene_name", "scene_names"]

# Extensions of the scan formats planerel reads (docs/formats.md); longest first.
SCAN_EXTENSIONS = (".range", ".tiff", ".npy", ".png", ".tif", ".pcd", ".ply")
# Qualifiers that say "this file is the depth channel of frame NAME".
QUALIFIERS = (".depth", "_depth", "-depth")


def scene_name(path) -> str:
    """The scene name of a scan path (see the module docstring).

    Parameters
    ----------
    path : str or Path

    Returns
    -------
    str
        Never empty: a file called only ``.depth.png`` keeps its full name.
    """
    name = Path(path).name
    stem = name
    low = stem.lower()
    for ext in SCAN_EXTENSIONS:
        if low.endswith(ext):
            stem = stem[: -len(ext)]
            break
    for q in QUALIFIERS:
        if stem.lower().endswith(q):
            stem = stem[: -len(q)]
            break
    return stem or name


def scene_names(paths: Sequence, ids: Sequence[str] | None = None, *,
                ids_option: bool = True, prolog: bool = False) -> list[str]:
    """Names of many inputs, refusing two inputs that would share a scene id or output file.

    Parameters
    ----------
    paths : sequence of path
    ids : sequence of str, optional
        Explicit names, one per path (``--ids``), used instead of the file names.
    ids_option : bool
        Whether the command has ``--ids`` (the messages suggest it only then).
    prolog : bool
        The names become Prolog atoms: refuse a file name that is not valid UTF-8 (Python
        keeps its bytes as lone surrogates, which no atom can hold).

    Returns
    -------
    list of str
        One name per path, in order.

    Raises
    ------
    InputError
        When two names are equal, or equal but for letter case (they would overwrite each
        other on a case-insensitive file system); the message names both inputs.
    """
    if ids is not None:
        ids = [str(i) for i in ids]
        if len(ids) != len(paths):
            raise InputError(f"--ids needs one id per input: {len(paths)} inputs, {len(ids)} ids")
        names = ids
    else:
        names = [scene_name(p) for p in paths]
    seen: dict[str, int] = {}
    for k, name in enumerate(names):
        if not name:
            raise InputError(f"{paths[k]}: empty scene id" + (" in --ids" if ids is not None
                                                               else ""))
        if prolog and any(0xD800 <= ord(ch) <= 0xDFFF for ch in name):
            shown = str(paths[k]).encode("utf-8", "surrogateescape").decode("utf-8", "replace")
            raise InputError(f"{shown}: the file name is not valid UTF-8, so it cannot be a scene "
                             "id in Prolog; rename the file"
                             + (" or give --ids" if ids_option else ""))
        key = name.casefold()
        if key in seen:
            j = seen[key]
            how = "id" if ids is not None else "name"
            raise InputError(
                f"{paths[j]} and {paths[k]} have the same scene {how} {names[j]!r}"
                + (f" / {name!r}" if names[j] != name else "")
                + "; their results would overwrite each other ("
                + ("give each input its own --ids)" if ids is not None
                   else "rename one, or give --ids)" if ids_option else "rename one)"))
        seen[key] = k
    return names
