"""Run an ILP learner on an Aleph problem (``STEM.b``, ``STEM.f``, ``STEM.n``).

Two engines read the same files:

``builtin``
    planerel's own Aleph-compatible learner (``aleph/learner.pl``, SWI-Prolog; see
    ``docs/learner.md``).
``aleph``
    the real Aleph: the file named by the environment variable ``PLANEREL_ALEPH`` -- a classic
    single file that defines Aleph in module ``user`` (``aleph_orig.pl``) or the SWI-Prolog
    pack's module file (``aleph.pl``, ``:- module(aleph, ...)``), told apart by their text --
    or else the pack ``library(aleph)`` when it is installed.
``auto``
    the real Aleph when it is found, else ``builtin``; :attr:`LearnResult.engine_detail`
    says which ran and why.

Every run is its own ``swipl`` process in its own process group with a time limit; when the
limit passes the whole group is killed and :class:`~planerel.errors.LearnerError` says so.
Both engines end with the same machine-readable summary (lines starting with ``@@``), which
this module parses into a :class:`LearnResult`.

Example
-------
>>> from planerel.ilp.learn import learn                                  # doctest: +SKIP
>>> r = learn("tests/ilp/trains", settings={"search": "heuristic"})   # doctest: +SKIP
>>> r.rules                                                           # doctest: +SKIP
('eastbound(A) :- has_car(A,B), short(B), closed(B).',)
>>> r.train.accuracy                                                  # doctest: +SKIP
1.0
"""

from __future__ import annotations

import dataclasses
import os
import re
import signal
import subprocess
import time
from collections.abc import Mapping
from pathlib import Path

from planerel.errors import DependencyError, InputError, LearnerError
from planerel.ilp.prolog import find_swipl, swipl_command

__all__ = [
    "Confusion",
    "LearnResult",
    "ENGINES",
    "learn",
    "find_aleph",
    "aleph_kind",
    "format_report",
    "parse_settings",
    "run_process",
]

ENGINES = ("builtin", "aleph", "auto")
_SETTING_NAME = re.compile(r"^[a-z][a-zA-Z0-9_]*$")


@dataclasses.dataclass(frozen=True)
class Confusion:
    """A confusion matrix of a theory on labelled examples.

    Attributes
    ----------
    tp, fn : int
        Positive examples the theory covers / does not cover.
    fp, tn : int
        Negative examples the theory covers / does not cover.
    """

    tp: int
    fn: int
    fp: int
    tn: int

    def __post_init__(self) -> None:
        for name in ("tp", "fn", "fp", "tn"):
            value = getattr(self, name)
            if not isinstance(value, int) or isinstance(value, bool) or value < 0:
                raise InputError(f"Confusion.{name} must be a non-negative integer, got {value!r}")

    @property
    def total(self) -> int:
        """Number of examples."""
        return self.tp + self.fn + self.fp + self.tn

    @property
    def accuracy(self) -> float:
        """``(tp + tn) / total`` (0.0 when there are no examples)."""
        return (self.tp + self.tn) / self.total if self.total else 0.0

    def table(self) -> str:
        """The matrix as a small text table (rows: predicted, columns: actual)."""
        rows = [
            f"{'':8}{'actual +':>10}{'actual -':>10}",
            f"{'pred +':8}{self.tp:>10}{self.fp:>10}{self.tp + self.fp:>10}",
            f"{'pred -':8}{self.fn:>10}{self.tn:>10}{self.fn + self.tn:>10}",
            f"{'':8}{self.tp + self.fn:>10}{self.fp + self.tn:>10}{self.total:>10}",
        ]
        return "\n".join(rows)


@dataclasses.dataclass(frozen=True)
class LearnResult:
    """What one learning run produced.

    Attributes
    ----------
    engine : str
        ``"builtin"`` or ``"aleph"`` (the engine that actually ran).
    engine_detail : str
        Which learner ran and why (e.g. the Aleph file used, or why ``auto`` fell back).
    stem : str
        The problem's file stem.
    rules_text : str
        The learned theory as Prolog text, one clause per line (loadable with ``consult``).
    rules : tuple of str
        The clauses, one string each, e.g. ``"eastbound(A) :- has_car(A,B), short(B)."``.
    train : Confusion
        The theory on the training examples (``STEM.f`` / ``STEM.n``).
    test : Confusion or None
        The theory on ``test_pos`` / ``test_neg`` when those settings are given.
    clauses_explored : int or None
        Clauses evaluated by the search (None when the engine does not report it).
    seconds : float
        Wall-clock time of the learner process (including SWI-Prolog's start-up).
    search_seconds : float or None
        CPU time of ``induce`` inside the learner (builtin engine only).
    output : str
        The learner's own printed report (without the ``@@`` summary lines).
    warnings : tuple of str
        Warnings the learner printed (unimplemented settings, ...).
    """

    engine: str
    engine_detail: str
    stem: str
    rules_text: str
    rules: tuple[str, ...]
    train: Confusion
    test: Confusion | None
    clauses_explored: int | None
    seconds: float
    search_seconds: float | None = None
    output: str = ""
    warnings: tuple[str, ...] = ()

    def __post_init__(self) -> None:
        if self.engine not in ("builtin", "aleph"):
            raise InputError(f"LearnResult.engine must be 'builtin' or 'aleph', got {self.engine!r}")
        if not self.seconds >= 0:
            raise InputError(f"LearnResult.seconds must be >= 0, got {self.seconds!r}")
        if self.clauses_explored is not None and self.clauses_explored < 0:
            raise InputError(f"LearnResult.clauses_explored must be >= 0, got {self.clauses_explored!r}")

    @property
    def accuracy(self) -> float:
        """Training-set accuracy."""
        return self.train.accuracy

    @property
    def test_accuracy(self) -> float | None:
        """Test-set accuracy, or None without a test set."""
        return None if self.test is None else self.test.accuracy

    @property
    def nodes_per_second(self) -> float | None:
        """Clauses explored per second of search time (None when unknown).

        Uses :attr:`search_seconds` when the engine reports it, else :attr:`seconds`.
        """
        secs = self.search_seconds if self.search_seconds is not None else self.seconds
        if self.clauses_explored is None or secs <= 0:
            return None
        return self.clauses_explored / secs


_MODULE_DECL = re.compile(rb"^\s*:-\s*module\(\s*aleph\s*,", re.MULTILINE)


def aleph_kind(path) -> str:
    """``"module"`` when the file declares ``:- module(aleph, ...)`` (the pack), else ``"classic"``."""
    try:
        with open(path, "rb") as fh:
            head = fh.read(1 << 16)
    except OSError as exc:
        raise InputError(f"PLANEREL_ALEPH={path}: cannot read the file ({exc.strerror})") from None
    return "module" if _MODULE_DECL.search(head) else "classic"


ALEPH_MISSING = ("the real Aleph was not found: set PLANEREL_ALEPH=/path/to/aleph.pl (the classic "
                 "single-file Aleph) or install the SWI-Prolog pack with: "
                 "swipl -g \"pack_install(aleph)\" -t halt; or use --engine builtin")


def check_engine(engine: str, swipl: str | None = None) -> None:
    """Fail now, not after hours of describing, when ``engine`` cannot run: an unknown name,
    SWI-Prolog missing, or ``"aleph"`` with no real Aleph to be found."""
    if engine not in ENGINES:
        raise InputError(f"engine must be one of {', '.join(ENGINES)}; got {engine!r}")
    exe = find_swipl(swipl)
    if engine == "aleph" and find_aleph(exe) is None:
        raise DependencyError(ALEPH_MISSING)


class LearnerTimeout(LearnerError):
    """A learner or a rule query ran past its time limit and was stopped."""


def check_timeout(timeout) -> float:
    """``timeout`` as a float, or an :class:`InputError`: a learning run's time limit must be a
    positive, finite number of seconds (``inf`` would also be no CPU limit for the child)."""
    import math

    if isinstance(timeout, bool) or not isinstance(timeout, (int, float)) or \
            not math.isfinite(timeout) or timeout <= 0:
        raise InputError(f"timeout must be a positive, finite number of seconds, got {timeout!r}")
    return float(timeout)


def find_aleph(swipl: str | None = None) -> tuple[str, str] | None:
    """Locate the real Aleph.

    Returns
    -------
    tuple or None
        ``("classic", path)`` or ``("module", path)`` for the file named by ``PLANEREL_ALEPH``
        (see :func:`aleph_kind`), ``("module", "library")`` when the SWI-Prolog pack is
        installed, else None.

    Raises
    ------
    InputError
        When ``PLANEREL_ALEPH`` names a file that does not exist.
    """
    env = os.environ.get("PLANEREL_ALEPH")
    if env:
        path = Path(env).expanduser()
        if not path.is_file():
            raise InputError(f"PLANEREL_ALEPH={env}: no such file (it must name Aleph's aleph.pl)")
        return (aleph_kind(path), str(path.resolve()))
    exe = find_swipl(swipl)
    goal = ("(absolute_file_name(library(aleph), _, [file_type(prolog), access(read), "
            "file_errors(fail)]) -> halt(0) ; halt(1))")
    try:
        proc = subprocess.run(swipl_command(goal, exe=exe, support=False, halt="halt(1)"),
                              capture_output=True,
                              timeout=30, check=False)
    except (OSError, subprocess.TimeoutExpired):
        return None
    return ("module", "library") if proc.returncode == 0 else None


def parse_settings(items) -> dict[str, str]:
    """``["nodes=2000", "search=heuristic"]`` -> ``{"nodes": "2000", ...}``.

    Raises
    ------
    InputError
        When an item is not ``NAME=VALUE`` with a Prolog-atom name.
    """
    out: dict[str, str] = {}
    for item in items or ():
        name, sep, value = str(item).partition("=")
        name = name.strip()
        if not sep or not _SETTING_NAME.match(name) or value.strip() == "":
            raise InputError(f"--set {item!r}: expected NAME=VALUE, for example nodes=2000")
        out[name] = value.strip()
    return out


def _setting_args(settings: Mapping[str, object] | None) -> list[str]:
    args = []
    for name, value in (settings or {}).items():
        if not isinstance(name, str) or not _SETTING_NAME.match(name):
            raise InputError(f"setting name {name!r} is not a valid Aleph setting name")
        if isinstance(value, bool):
            text = "true" if value else "false"
        elif isinstance(value, float):
            text = repr(value)
        else:
            text = str(value)
        if text == "" or "\n" in text:
            raise InputError(f"setting {name}: the value {value!r} is empty or has a newline")
        args.append(f"{name}={text}")
    return args


def _check_stem(stem) -> str:
    text = str(stem)
    for suffix in (".b", ".f", ".n"):
        if text.endswith(suffix) and not Path(text).is_dir():
            text = text[: -len(suffix)]
            break
    for suffix in (".b", ".f"):
        if not Path(text + suffix).is_file():
            raise InputError(f"{text + suffix}: no such file (an Aleph problem needs STEM.b, "
                             f"STEM.f and usually STEM.n)")
    return text


def _communicate(proc, timeout: float, on_progress):
    """``proc.communicate(timeout)``, calling ``on_progress(text)`` for each stderr line
    ``progress: text`` as soon as the child prints it."""
    if on_progress is None:
        return proc.communicate(timeout=timeout)
    import threading

    chunks: dict[str, list[bytes]] = {"out": [], "err": []}

    def read_out():
        chunks["out"].append(proc.stdout.read())

    def read_err():
        for raw in iter(proc.stderr.readline, b""):
            chunks["err"].append(raw)
            line = raw.decode("utf-8", "replace").rstrip("\n")
            if line.startswith("progress: "):
                try:
                    on_progress(line[len("progress: "):])
                except Exception:  # noqa: BLE001 - a display problem must not stop learning
                    pass

    readers = [threading.Thread(target=read_out, daemon=True),
               threading.Thread(target=read_err, daemon=True)]
    for t in readers:
        t.start()
    proc.wait(timeout=timeout)
    for t in readers:
        t.join()
    return b"".join(chunks["out"]), b"".join(chunks["err"])


def run_process(cmd: list[str], timeout: float, what: str, cwd: str | None = None,
                on_progress=None):
    """Run ``cmd`` in its own process group; kill the group when ``timeout`` passes or this
    process is interrupted.  The child also dies with this process (even a SIGKILLed one) and
    has its own CPU-time limit (:func:`planerel.children.child_preexec`).  ``on_progress``,
    when given, receives the text of each ``progress: ...`` line of the child's stderr as it
    comes."""
    from planerel.children import child_preexec, register_child, unregister_child

    start = time.perf_counter()
    try:
        proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                                stdin=subprocess.DEVNULL, start_new_session=True, cwd=cwd,
                                preexec_fn=child_preexec(timeout))
    except OSError as exc:
        raise LearnerError(f"cannot start {cmd[0]}: {exc.strerror}") from None
    try:
        register_child(proc)
        out, err = _communicate(proc, timeout, on_progress)
    except subprocess.TimeoutExpired:
        try:
            os.killpg(proc.pid, signal.SIGKILL)
        except ProcessLookupError:
            pass
        proc.communicate()
        raise LearnerTimeout(f"{what} timed out after {timeout:g} s and was stopped") from None
    except BaseException:
        try:
            os.killpg(proc.pid, signal.SIGKILL)
        except ProcessLookupError:
            pass
        proc.communicate()
        raise
    finally:
        unregister_child(proc)
    seconds = time.perf_counter() - start
    return proc.returncode, out.decode("utf-8", "replace"), err.decode("utf-8", "replace"), seconds


def _parse(stdout: str, stderr: str, code: int, what: str):
    errors = [ln[len("error: "):] for ln in stderr.splitlines() if ln.startswith("error: ")]
    if code == 2:
        raise InputError(errors[0] if errors else f"{what} rejected its input: {stderr.strip()[-500:]}")
    if code != 0 or "@@begin" not in stdout or "@@end" not in stdout:
        detail = errors[0] if errors else (stderr.strip()[-800:] or f"exit status {code}")
        if what == "Aleph" and "zero_divisor" in detail:
            # measured on 1,000 varied scenes: aleph_orig.pl divides by a clause's coverage in
            # maxlength_neg_ok/4 even when its parent covers no example
            detail += (" (a division by zero inside the real Aleph, in its clause-length check "
                       "maxlength_neg_ok/4, seen on large data sets; planerel's own learner, "
                       "--engine builtin, learns the same files)")
        if what == "Aleph" and "procedure,read_all/1" in detail.replace(" ", ""):
            env = os.environ.get("PLANEREL_ALEPH")
            detail += (f" (PLANEREL_ALEPH={env} defines no read_all/1: it must name Aleph's "
                       "aleph.pl or aleph_orig.pl)" if env else
                       " (the Aleph found defines no read_all/1)")
        raise LearnerError(f"{what} failed: {detail}")
    rules: list[str] = []
    train = test = None
    nodes = None
    cputime = None
    log_lines = []
    for line in stdout.splitlines():
        if not line.startswith("@@"):
            log_lines.append(line)
            continue
        key, _, rest = line[2:].partition(" ")
        if key == "rule":
            rules.append(rest)
        elif key in ("train", "test"):
            cm = Confusion(*(int(v) for v in rest.split()))
            if key == "train":
                train = cm
            else:
                test = cm
        elif key == "nodes":
            nodes = int(rest)
        elif key == "cputime":
            cputime = float(rest)
    if train is None:
        raise LearnerError(f"{what} printed no training-set confusion matrix")
    warnings = tuple(ln[len("warning: "):] for ln in stderr.splitlines() if ln.startswith("warning: "))
    log = "\n".join(log_lines).rstrip("\n") + "\n"
    return rules, train, test, nodes, cputime, log, warnings


def learn(
    stem,
    *,
    engine: str = "builtin",
    settings: Mapping[str, object] | None = None,
    timeout: float = 120.0,
    swipl: str | None = None,
    progress=None,
) -> LearnResult:
    """Learn a theory for the Aleph problem ``STEM.b`` / ``STEM.f`` / ``STEM.n``.

    Parameters
    ----------
    stem : str or path
        The file stem (``STEM.b`` etc.; a path ending in ``.b``/``.f``/``.n`` is accepted).
    engine : {"builtin", "aleph", "auto"}
        Which learner runs (see the module docstring).
    settings : mapping, optional
        Aleph settings applied after the files are read (they override ``:- set/2`` in
        ``STEM.b``), e.g. ``{"search": "heuristic", "evalfn": "laplace", "nodes": 2000}``.
    timeout : float
        Seconds before the learner process (group) is killed.
    swipl : str, optional
        The SWI-Prolog executable (default: ``swipl`` on ``PATH``).
    progress : callable, optional
        Called with one line of text per clause the builtin learner adds, while it runs
        (e.g. ``"box/1 rule 3 (2 literals, 120 pos, 0 neg): 40 of 692 positives left, 4.1 s
        CPU"``).

    Returns
    -------
    LearnResult

    Raises
    ------
    InputError
        Missing files, a malformed problem (the message names file and line), a bad setting.
    LearnerError
        The learner crashed or ran past ``timeout``.
    DependencyError
        SWI-Prolog is missing, or ``engine="aleph"`` and no real Aleph is found.
    """
    if engine not in ENGINES:
        raise InputError(f"engine must be one of {', '.join(ENGINES)}; got {engine!r}")
    check_timeout(timeout)
    stem_text = _check_stem(stem)
    exe = find_swipl(swipl)
    set_args = _setting_args(settings)
    from importlib.resources import as_file, files

    aleph = None
    if engine in ("aleph", "auto"):
        aleph = find_aleph(exe)
        if aleph is None and engine == "aleph":
            raise DependencyError(ALEPH_MISSING)
    abs_stem = str(Path(stem_text).resolve())
    if aleph is None:
        detail = "builtin (planerel's learner)"
        if engine == "auto":
            detail += "; the real Aleph was not found (PLANEREL_ALEPH unset, no library(aleph))"
        resource = files("planerel.aleph").joinpath("learner.pl")
        with as_file(resource) as pl:
            cmd = swipl_command("planerel_learner:planerel_main", [abs_stem, *set_args],
                                exe=exe, support=False, scripts=[pl], halt="halt(3)")
            code, out, err, secs = run_process(cmd, timeout, f"the builtin learner on {stem_text}",
                                               on_progress=progress)
        rules, train, test, nodes, cputime, log, warns = _parse(out, err, code, "the builtin learner")
        used = "builtin"
    else:
        kind, where = aleph
        detail = f"aleph ({'library(aleph)' if where == 'library' else where}, {kind})"

        resource = files("planerel.aleph").joinpath("learner_aleph.pl")
        from planerel.children import temp_dir

        with temp_dir("aleph") as tmp, as_file(resource) as pl:
            rules_file = str(Path(tmp) / "rules.pl")
            cmd = swipl_command(None, [kind, where, abs_stem, rules_file, *set_args], exe=exe,
                                support=False, scripts=[pl], halt=None)
            code, out, err, secs = run_process(cmd, timeout, f"Aleph on {stem_text}",
                                        cwd=str(Path(abs_stem).parent))
        rules, train, test, nodes, cputime, log, warns = _parse(out, err, code, "Aleph")
        total = re.findall(r"\[total clauses constructed\]\s*\[?(\d+)", out)
        constructed = [int(m) for m in re.findall(r"^\[clauses constructed\]\s*\[?(\d+)", out,
                                                  re.MULTILINE)]
        nodes = int(total[-1]) if total else (sum(constructed) if constructed else None)
        used = "aleph"
    rules_text = "".join(r + "\n" for r in rules)
    return LearnResult(engine=used, engine_detail=detail, stem=stem_text, rules_text=rules_text,
                       rules=tuple(rules), train=train, test=test, clauses_explored=nodes,
                       seconds=secs, search_seconds=cputime, output=log, warnings=warns)


def score_theory(stem, rules, *, timeout: float = 600.0, swipl: str | None = None) -> Confusion:
    """A theory (e.g. learned on other data) scored on the examples ``STEM.f`` / ``STEM.n``
    over ``STEM.b`` by the builtin learner's own coverage test (held-out accuracy).

    Parameters
    ----------
    stem : str or path
        An Aleph problem (its ``.b`` holds the facts of the examples' objects).
    rules : sequence of str
        Clauses, one string each (as :attr:`LearnResult.rules`).

    Returns
    -------
    Confusion
    """
    return _score(stem, rules, timeout, swipl, covered=False)[0]


def theory_coverage(stem, rules, *, timeout: float = 600.0,
                    swipl: str | None = None) -> tuple[Confusion, tuple, tuple]:
    """:func:`score_theory` with the examples the theory proves.

    Returns
    -------
    confusion : Confusion
    positives, negatives : tuple of str
        The proved examples' atoms as the learner writes them (``box(s0089_o2)``), in file
        order (benchmarks/clause_support.py ``--names``).
    """
    return _score(stem, rules, timeout, swipl, covered=True)


def _score(stem, rules, timeout, swipl, *, covered: bool):
    """``(Confusion, proved positives, proved negatives)``; the two tuples are empty unless
    ``covered`` (the learner's ``@@covered`` lines)."""
    from importlib.resources import as_file, files

    from planerel.children import temp_dir

    stem_text = _check_stem(stem)
    exe = find_swipl(swipl)
    resource = files("planerel.aleph").joinpath("learner.pl")
    with temp_dir("score") as tmp, as_file(resource) as pl:
        rules_file = Path(tmp) / "rules.pl"
        rules_file.write_text("".join(r + "\n" for r in rules))
        cmd = swipl_command("planerel_learner:planerel_score_main",
                            [str(Path(stem_text).resolve()), str(rules_file),
                             *(["covered"] if covered else [])],
                            exe=exe, support=False, scripts=[pl], halt="halt(3)")
        code, out, err, _ = run_process(cmd, timeout, f"scoring a theory on {stem_text}")
    m = re.search(r"^@@score (\d+) (\d+) (\d+) (\d+)$", out, re.MULTILINE)
    if code != 0 or m is None:
        raise LearnerError(f"scoring a theory on {stem_text} failed: {(err or out).strip()[-400:]}")
    found = re.findall(r"^@@covered (pos|neg) (.+)$", out, re.MULTILINE)
    return (Confusion(*(int(g) for g in m.groups())),
            tuple(a for k, a in found if k == "pos"), tuple(a for k, a in found if k == "neg"))


def format_report(result: LearnResult, *, with_time: bool = True) -> str:
    """The theory, the confusion matrices with ``accuracy: 0.950`` lines, and the time."""
    lines = [f"engine: {result.engine_detail}", "", "[theory]"]
    lines += list(result.rules) or ["(empty theory)"]
    lines += ["", "[training set performance]", result.train.table(),
              f"accuracy: {result.train.accuracy:.3f}"]
    if result.test is not None:
        lines += ["", "[test set performance]", result.test.table(),
                  f"accuracy: {result.test.accuracy:.3f}"]
    lines.append("")
    if result.clauses_explored is not None:
        lines.append(f"clauses explored: {result.clauses_explored}")
    if with_time:
        rate = result.nodes_per_second
        extra = f" ({rate:.0f} clauses/s)" if rate is not None else ""
        search = (f", search {result.search_seconds:.2f} s"
                  if result.search_seconds is not None else "")
        lines.append(f"time: {result.seconds:.2f} s{search}{extra}")
    return "\n".join(lines) + "\n"
