"""The one bridge to SWI-Prolog: every model load and every query goes through here.

Two ways in, one loading rule.

- **A ``swipl`` subprocess** (cross-validation and rule statistics, the class-name check, the
  learners, the Aleph look-up): :func:`swipl_command` builds every command line.  The goal text is a constant of the
  caller; every file reaches ``swipl`` as data after ``--`` (``current_prolog_flag(argv, ...)``),
  never inside a goal, so no path can be read as Prolog.
- **In process** through pyswip (classification): :func:`engine` starts one engine per process
  on first use (never at import); :func:`load_support` and :func:`load_file` load files by
  their path quoted as a Prolog atom (:func:`planerel.features.terms.atom`).

The loading rule, the same both ways: the support predicates (:data:`SUPPORT_FILES` from the
package ``planerel.prolog``, in that order) are loaded first with ``load_files(F,
[silent(true)])``, then the scene facts, then the model: its rules are read as data by
``planerel_load_model`` / ``planerel_predict_main`` (``prolog/classify.pl``) into a module of
their own and checked against :func:`model_vocabulary`, never consulted as a program.

In: goals, file paths.  Out: answers (``list[dict]`` in process, ``(code, stdout, stderr,
seconds)`` for a subprocess).
"""

from __future__ import annotations

import shutil
from pathlib import Path

from planerel.errors import DependencyError, PrologError

__all__ = [
    "SUPPORT_FILES",
    "SWIPL_INSTALL",
    "DERIVED_PREDICATES",
    "support_files",
    "model_vocabulary",
    "vocabulary_term",
    "find_swipl",
    "load_support_goal",
    "swipl_command",
    "engine",
    "query",
    "load_support",
    "load_file",
    "unload_file",
    "pl_path",
]

#: The support predicates, loaded in this order before any facts or model.
SUPPORT_FILES = ("compare.pl", "derived.pl", "classify.pl")
#: The command that installs SWI-Prolog, named in every "not installed" error.
SWIPL_INSTALL = "sudo apt-get install swi-prolog-nox"
#: Predicates of ``prolog/derived.pl`` and ``prolog/compare.pl`` a rule body may call.
DERIVED_PREDICATES = (("horizontal", 1), ("vertical", 1), ("inclined", 1), ("object_plane", 3),
                      ("step_up", 2), ("lteq", 2), ("gteq", 2))


def support_files() -> list[Path]:
    """Paths of the support predicates (``prolog/*.pl``) as installed, in loading order."""
    from importlib.resources import files

    base = files("planerel.prolog")
    return [Path(str(base / name)) for name in SUPPORT_FILES]


def model_vocabulary() -> list[tuple[str, int]]:
    """What a model's rule bodies may call: the scene facts' vocabulary
    (:data:`planerel.features.facts.PREDICATES`) and :data:`DERIVED_PREDICATES`, as (name, arity)."""
    from planerel.features.facts import PREDICATES

    return [(n, a) for n, a, _, _ in PREDICATES] + list(DERIVED_PREDICATES)


def vocabulary_term() -> str:
    """:func:`model_vocabulary` as the Prolog list ``[Name/Arity, ...]`` that
    ``planerel_load_model`` and ``planerel_load_background`` (``prolog/classify.pl``) take."""
    from planerel.features.terms import Term, atom, plist

    return plist([Term(f"{atom(n)}/{a}") for n, a in model_vocabulary()])


def find_swipl(swipl: str | None = None) -> str:
    """The ``swipl`` executable to use.

    Raises
    ------
    DependencyError
        When SWI-Prolog is not installed (the message gives the apt command).
    """
    if swipl is not None:
        found = shutil.which(swipl)
        if found is None:
            raise DependencyError(f"SWI-Prolog executable {swipl!r} not found; install SWI-Prolog "
                                  f"with: {SWIPL_INSTALL}")
        return found
    found = shutil.which("swipl")
    if found is None:
        raise DependencyError(f"SWI-Prolog (swipl) is not installed; install it with: {SWIPL_INSTALL}")
    return found


def load_support_goal(goal: str) -> str:
    """``goal`` after the loading rule in a subprocess: ``argv`` holds the support files, then the
    caller's data, which ``goal`` sees as the list ``Args``."""
    return (f"current_prolog_flag(argv, All), length(Support, {len(SUPPORT_FILES)}), "
            "append(Support, Args, All), "
            "forall(member(S, Support), load_files(S, [silent(true)])), " + goal)


def swipl_command(goal: str | None, data=(), *, exe: str | None = None, support: bool = True,
                  scripts=(), halt: str | None = "halt", flags=()) -> list[str]:
    """The ``swipl`` command line of one subprocess (run it with
    :func:`planerel.ilp.learn.run_process` or :mod:`subprocess`).

    Parameters
    ----------
    goal : str or None
        Constant goal text (no path, no name from the user: those go in ``data``).  With
        ``support`` it runs after the support files are loaded and sees ``data`` as ``Args``.
    data : sequence of str or path
        Files and names the goal reads, passed after ``--``.
    support : bool
        False: no support files (the goal, or a script, reads ``argv`` itself).
    scripts : sequence of path
        planerel's own programs (the learners) that ``swipl`` loads before running ``goal``.
    halt : str or None
        The toplevel goal (``-t``).
    flags : sequence of str
        Extra options (``--on-error=status`` ...).
    """
    exe = exe or find_swipl()
    data = [str(d) for d in data]
    if support and goal is not None:
        goal = load_support_goal(goal)
        data = [*(str(p) for p in support_files()), *data]
    cmd = [exe, "-q", *flags]
    if goal is not None:
        cmd += ["-g", goal]
    if halt is not None:
        cmd += ["-t", halt]
    return [*cmd, *(str(s) for s in scripts), "--", *data]


_ENGINE = None
_LOADED_SUPPORT = False


def engine():
    """The process's pyswip engine (created once, on first use)."""
    global _ENGINE
    if _ENGINE is None:
        import sys

        # pyswip encodes sys.argv to UTF-8 when imported (and uses it for nothing else): a
        # command line with a file name that is not UTF-8 made the import fail, reported as
        # "SWI-Prolog missing"
        argv, sys.argv = sys.argv, sys.argv[:1]
        try:
            from pyswip import Prolog
        except Exception as exc:  # pyswip raises plain exceptions when libswipl is missing
            raise DependencyError(
                f"pyswip cannot load SWI-Prolog ({exc}); install it with: "
                f"{SWIPL_INSTALL}") from None
        finally:
            sys.argv = argv
        _ENGINE = Prolog()
    return _ENGINE


def pl_path(path) -> str:
    """A file path as a quoted Prolog atom."""
    from planerel.features.terms import atom

    return atom(str(Path(path).resolve()))


def query(goal: str, what: str) -> list[dict]:
    """All answers of ``goal`` in the in-process engine; :class:`PrologError` naming ``what``."""
    try:
        return list(engine().query(goal))
    except Exception as exc:  # pyswip.prolog.PrologError and friends
        raise PrologError(f"{what}: {exc}") from None


def load_file(path, what: str) -> None:
    """Load one file into the in-process engine (after :func:`load_support`)."""
    query(f"load_files({pl_path(path)}, [silent(true)])", what)


def unload_file(path, what: str) -> None:
    query(f"unload_file({pl_path(path)})", what)


def load_support() -> None:
    """Load the support files into the in-process engine, once per process."""
    global _LOADED_SUPPORT
    if not _LOADED_SUPPORT:
        for f in support_files():
            load_file(f, f"cannot load {f.name}")
        _LOADED_SUPPORT = True
