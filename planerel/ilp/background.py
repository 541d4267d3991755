"""Background predicates of the user's own: one Prolog file of plain clauses (``planerel learn
--background FILE``, ``export-aleph --background FILE``) that a model carries.

The file is data, as a model's rules are: ``planerel_load_background/5``
(``prolog/classify.pl``) reads it clause by clause and refuses a directive, a clause that
redefines planerel's vocabulary (:func:`planerel.ilp.prolog.model_vocabulary`) or a built-in,
library or planerel predicate, and a body that calls anything but the vocabulary, the safe
built-ins a rule may call and the predicates the file defines.  :func:`read_background` runs
that check in its own ``swipl`` before any scene is described; the learners get the clauses in
``STEM.b``; ``planerel learn`` copies the file into the model folder as
:data:`BACKGROUND_FILE`, named with its SHA-256 in ``model.json``
(:func:`planerel.ilp.model_settings.training_settings`), and every command that loads the
model's rules loads the clauses with them, after the same check
(:func:`model_background`, :class:`planerel.classify.Classifier`).

In: a file path.  Out: :class:`Background` (text, digest, the predicates it defines).
"""

from __future__ import annotations

import hashlib
from dataclasses import dataclass
from pathlib import Path

from planerel.errors import InputError, PrologError

__all__ = ["BACKGROUND_FILE", "Background", "read_background", "digest", "model_background"]

#: The background file's name in a model folder.
BACKGROUND_FILE = "background.pl"

# The goal text is constant: the file and the vocabulary reach swipl as data (argv).
_CHECK_GOAL = "Args = [File, Data], planerel_background_main(File, Data)"


@dataclass(frozen=True)
class Background:
    """A checked background file.

    Attributes
    ----------
    where : str
        The file as the user named it (for messages and ``STEM.b``'s comment).
    text : str
        Its clauses, as read (UTF-8).
    predicates : tuple of (str, int)
        ``(name, arity)`` of every predicate it defines, sorted (a name that is no plain
        Prolog atom in its quoted form).
    """

    where: str
    text: str
    predicates: tuple

    @property
    def sha256(self) -> str:
        """The SHA-256 of :attr:`text` in UTF-8: the bytes written into the model folder."""
        return digest(self.text.encode("utf-8"))


def digest(data: bytes) -> str:
    """The SHA-256 of ``data`` as hex digits (``model.json``'s ``background.sha256``)."""
    return hashlib.sha256(data).hexdigest()


def read_background(path, *, timeout: float = 120.0) -> Background:
    """Read and check a background file in its own ``swipl``.

    Parameters
    ----------
    path : path
        A Prolog file of facts and rules (no directives).
    timeout : float
        Seconds before the check is stopped.

    Returns
    -------
    Background

    Raises
    ------
    InputError
        The file cannot be read, or a clause is refused; one line naming the file and line
        (``FILE:LINE: ...``).
    PrologError
        The check itself failed.
    """
    from planerel.children import temp_dir
    from planerel.ilp.learn import run_process
    from planerel.ilp.prolog import swipl_command, vocabulary_term

    p = Path(path)
    try:
        text = p.read_bytes().decode("utf-8")
    except (OSError, UnicodeDecodeError) as exc:
        raise InputError(f"{p}: cannot read the background file "
                         f"({getattr(exc, 'strerror', None) or exc})") from None
    with temp_dir("background") as tmp:
        data = Path(tmp) / "vocabulary.pl"
        data.write_text(vocabulary_term() + ".\n")
        cmd = swipl_command(_CHECK_GOAL, [p.resolve(), data],
                            flags=("--on-error=status", "--on-warning=status"))
        code, out, err, _ = run_process(cmd, timeout, f"checking {p}")
    errors = [ln[len("error: "):] for ln in err.splitlines() if ln.startswith("error: ")]
    if code == 2 and errors:
        line, _, msg = errors[0].partition(": ")
        raise InputError(f"{p}:{line}: {msg}" if line.isdigit() and line != "0" else f"{p}: {msg}")
    if code != 0:
        raise PrologError(f"checking the background file {p} failed: "
                          f"{err.strip()[-600:] or f'exit status {code}'}")
    preds = []
    for ln in out.splitlines():
        if ln.startswith("@@defined "):
            name, _, arity = ln[len("@@defined "):].rpartition(" ")
            preds.append((name, int(arity)))
    if not preds:
        raise InputError(f"{p}: the background file defines no predicate")
    return Background(str(path), text, tuple(sorted(preds)))


def model_background(rules_path, recorded: dict | None) -> Path | None:
    """The background file a model's ``model.json`` names (``recorded``: its ``background``
    entry, ``{"file": ..., "sha256": ...}``; None: the model has none), checked to be the file
    the model was learned with.

    Raises
    ------
    InputError
        The file is missing, or its SHA-256 is not the recorded one (edited after learning).
    """
    if not recorded:
        return None
    folder = Path(rules_path).parent
    name = str(recorded.get("file", ""))
    if Path(name).name != name or not name.endswith(".pl"):
        raise InputError(f"{folder / 'model.json'}: background file {name!r} is not a file "
                         "name of the model folder")
    path = folder / name
    try:
        data = path.read_bytes()
    except OSError as exc:
        raise InputError(f"{path}: the model's background file is missing or unreadable "
                         f"({exc.strerror or exc}); its rules call the predicates it defines: "
                         "copy the whole model folder") from None
    if digest(data) != recorded.get("sha256"):
        raise InputError(f"{path}: the model's background file was changed after learning "
                         "(its SHA-256 is not the one model.json records); its rules were "
                         "learned with the file as it was: restore it, or learn the model again")
    return path
