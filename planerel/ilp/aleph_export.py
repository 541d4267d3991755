"""Described scenes to an Aleph learning task: ``STEM.b``, ``STEM.f``, ``STEM.n``.

The examples are *objects*, not scenes: for a per-class task ``stairs`` the positives are
``stairs(s0007_o1).`` for every stairs object and the negatives ``stairs(s0003_o1).`` for every
object of another class; a multi-class task uses ``class(+obj, #cls)`` with positives
``class(s0007_o1, stairs).`` and, as negatives, the other classes of each object.  Objects of
class ``other`` (clutter of the varied world: none of the classes) are negatives for every class
and never a class of their own.

``STEM.b`` holds, in this order: ``:- op(500, fy, #)`` (so the file also reads outside Aleph),
the settings and body modes of the task file (``aleph/modes_relational.pl``), the target's
``modeh`` and one ``determination`` per body predicate, the lazy-evaluation declarations,
``dynamic`` declarations of every background predicate, the type facts (``obj/1``, ``plane/1``,
``orient/1``, ``cls/1``), the comparison predicates (``prolog/compare.pl``), the derived
relations (``prolog/derived.pl``) and the scene facts of the example objects (their planes,
attributes and the relations of all pairs within each object; no planner facts).

Files follow the facts about the real Aleph in the design notes: one type per numeric attribute,
lazy thresholds (``lteq/2``, ``gteq/2``), dynamic background predicates, ``search(heuristic)``
with ``evalfn(laplace)``.  Settings given by the caller are checked here (the real Aleph stores
an illegal value with only a message).
"""

from __future__ import annotations

import functools
import re
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

from planerel.errors import InputError
from planerel.features import terms

#: The class of objects that are none of the learned classes: negatives for every class.
OTHER = "other"

__all__ = [
    "Example",
    "ExportResult",
    "TASK_FILE",
    "PAIRS",
    "load_task",
    "task_directives",
    "examples_of",
    "example_facts",
    "aleph_files",
    "export_aleph",
    "describe_dataset",
    "export_dataset",
    "check_setting",
    "check_task_vocabulary",
]

#: The default task file (package ``planerel.aleph``).
TASK_FILE = "modes_relational.pl"

#: The pairs of planes described for learning: every ordered pair within an object.  Classifying
#: describes the same pairs, so a learned ``parallel(B, C)`` means the same at both ends (with the
#: scene's adjacent pairs as well, C could be the floor or a wall at classification time only).
PAIRS = "object"

_MODEB = re.compile(r"^:-\s*modeb\(\s*([^,]+?)\s*,\s*([a-z][a-zA-Z0-9_]*)\((.*)\)\s*\)\.\s*$")
_SET = re.compile(r"^:-\s*set\(\s*([a-z_]+)\s*,\s*(.+?)\s*\)\.\s*$")

#: Settings this exporter accepts from callers, with a check of the value.
_SETTINGS = {
    "search": lambda v: v in ("bf", "df", "heuristic", "ibs", "ils", "rls", "scs", "id", "ic", "ar", "false"),
    "evalfn": lambda v: v in ("coverage", "laplace", "accuracy", "compression", "auto_m", "mestimate",
                              "pbayes", "posonly", "sd", "wracc", "entropy", "gini", "user"),
    "clauselength": lambda v: isinstance(v, int) and v >= 1,
    "i": lambda v: isinstance(v, int) and v >= 1,
    "nodes": lambda v: isinstance(v, int) and v >= 1,
    "minpos": lambda v: isinstance(v, int) and v >= 1,
    "noise": lambda v: isinstance(v, int) and v >= 0,
    "minacc": lambda v: isinstance(v, (int, float)) and 0 <= v <= 1,
    "depth": lambda v: isinstance(v, int) and v >= 1,
    "verbosity": lambda v: isinstance(v, int) and v >= 0,
    "samplesize": lambda v: isinstance(v, int) and v >= 0,
    # an acceptable clause (at most noise negatives) is specialised further while a
    # refinement could still score better (Aleph's explore)
    "explore": lambda v: v in ("true", "false"),
    # planerel's learner only: lazy thresholds count examples, not values (docs/learner.md)
    "lazy_examples": lambda v: v in ("true", "false"),
    # planerel's learner only: a measure's lazy thresholds evaluated when it is made (docs/learner.md)
    "lazy_lookahead": lambda v: v in ("true", "false"),
    # planerel's learner only: a lazy threshold moved past further positives while they cost at
    # most K standard deviations of the score (prolog/compare.pl; docs/learner.md)
    "cutoff_slack": lambda v: v == "off" or (isinstance(v, (int, float)) and v >= 0),
    # planerel's learner only: gteq also offers a band's lower edge (prolog/compare.pl)
    "lazy_band": lambda v: v in ("true", "false"),
    # planerel's own, read by planerel.ilp.pipeline.learn_rules and never written to STEM.b: a
    # class's negatives leave out the objects its decision's planar gate refuses anyway
    # (planerel.ilp.metrics.gated_negatives; seed29)
    "gated_negatives": lambda v: v in ("true", "false"),
}

#: Settings :func:`check_setting` accepts that are planerel's own and no learner's: the caller
#: acts on them, :func:`aleph_files` never writes them into ``STEM.b``.
PLANEREL_SETTINGS = ("gated_negatives",)


def check_setting(name: str, value):
    """Validate one Aleph setting; return the value as Prolog text.

    Raises
    ------
    InputError
        Unknown name or illegal value (named in the message).
    """
    if name not in _SETTINGS:
        raise InputError(f"unknown or unsupported Aleph setting {name!r}; choose from "
                         f"{', '.join(sorted(_SETTINGS))}")
    if isinstance(value, str):
        text = value.strip()
        try:
            value = int(text)
        except ValueError:
            try:
                value = float(text)
            except ValueError:
                value = text
    if isinstance(value, bool) or not _SETTINGS[name](value):
        raise InputError(f"illegal value {value!r} for Aleph setting {name!r}")
    return terms.atom(value) if isinstance(value, str) else terms.number(value)


@dataclass(frozen=True)
class Example:
    """One training example: an object id and its class."""

    object_id: str
    klass: str


@dataclass(frozen=True)
class ExportResult:
    """What :func:`export_aleph` wrote: the file paths, stems, and example counts per class."""

    files: tuple
    stems: tuple
    counts: dict
    skipped: tuple = ()


def _resource_text(package: str, name: str) -> str:
    from importlib.resources import files

    try:
        return files(package).joinpath(name).read_text(encoding="utf-8")
    except (FileNotFoundError, OSError) as exc:
        raise InputError(f"cannot read {name} from package {package}: {exc}") from None


#: ``:- planerel_include('FILE').`` in a task file: FILE's lines stand where the directive is.
#: planerel expands it when it reads the task; it is never written into ``STEM.b`` (the real
#: Aleph knows no such directive).
_INCLUDE = re.compile(r"^:-\s*planerel_include\(\s*'([^'\\]+)'\s*\)\.\s*$")
_INCLUDE_WORD = re.compile(r"^:-\s*planerel_include\b")


@dataclass(frozen=True)
class _TaskSource:
    """One task file as read: its identity (include cycles), its name in messages, its text, and
    the folder its relative includes are looked up in (None: the package ``planerel.aleph``)."""

    key: str
    where: str
    text: str
    folder: Path | None


def _package_task(name: str) -> _TaskSource:
    from importlib.resources import files

    res = files("planerel.aleph").joinpath(name)
    text = _resource_text("planerel.aleph", name)
    key = str(Path(str(res)).resolve()) if isinstance(res, Path) else f"planerel.aleph/{name}"
    return _TaskSource(key, name, text, None)


def _path_task(p: Path) -> _TaskSource:
    try:
        text = p.read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as exc:
        raise InputError(f"{p}: cannot read the task file ({exc})") from None
    return _TaskSource(str(p.resolve()), str(p), text, p.parent)


def _task_source(task: str | None) -> _TaskSource:
    if task is None or ("/" not in str(task) and not Path(str(task)).exists()):
        return _package_task(task or TASK_FILE)
    return _path_task(Path(task))


def _included(name: str, parent: _TaskSource, at: str) -> _TaskSource:
    """The file ``planerel_include(name)`` names in ``parent``: relative to the including file's
    folder, else (a bare name) planerel's ``aleph/`` folder (package ``planerel.aleph``)."""
    from importlib.resources import files

    looked = []
    if parent.folder is not None:
        p = parent.folder / name
        if p.is_file():
            return _path_task(p)
        looked.append(f"for {p}")
    if "/" not in name and "\\" not in name:
        res = files("planerel.aleph").joinpath(name)
        if res.is_file():
            return _package_task(name)
        looked.append("in planerel's aleph/ folder")
    raise InputError(f"{at}: planerel_include: no task file {name!r}"
                     + (f" (looked {' and '.join(looked)})" if looked else ""))


#: The end of a directive written on one line: its full stop, then at most a ``%`` comment.
_DIRECTIVE_END = re.compile(r"\.\s*(%.*)?$")


def _code_lines(src: _TaskSource):
    """``(line number, text)`` of each line of a task file that holds more than a comment or
    blank space, with its ``/* ... */`` comments taken out (a block comment may span lines)."""
    in_block = False
    for lineno, line in enumerate(src.text.splitlines(), 1):
        code, rest = [], line
        while rest:
            if in_block:
                end = rest.find("*/")
                if end < 0:
                    rest = ""
                else:
                    in_block, rest = False, rest[end + 2:]
            else:
                start = rest.find("/*")
                if start < 0:
                    code.append(rest)
                    rest = ""
                else:
                    code.append(rest[:start])
                    in_block, rest = True, rest[start + 2:]
        s = " ".join(code).strip()
        if s and not s.startswith("%"):
            yield lineno, s


def _directives(src: _TaskSource, chain: tuple = ()) -> list[tuple[str, int, str]]:
    """The directive lines of a task file, ``(where, line number, line)``, each include expanded in
    its place.

    A task file holds one-line directives only (they are copied into ``STEM.b`` line by line):
    a directive that goes on to the next line, or a line that is no directive (a clause of a
    background predicate of one's own), is an :class:`InputError` naming the file and line
    rather than a line left out or cut short in ``STEM.b`` (ilp90)."""
    chain = chain + (src,)
    out = []
    for lineno, s in _code_lines(src):
        if not s.startswith(":-"):
            raise InputError(
                f"{src.where}:{lineno}: a task file holds directives only (lines starting with "
                f"':-', each on one line); this line is not one, and would not reach STEM.b: "
                f"{s[:60]!r}. planerel learns and classifies with its own vocabulary "
                f"(docs/predicates.md); a background predicate of your own goes into the "
                f"exported STEM.b by hand (docs/learner.md, 'Background predicates of your own')")
        end = _DIRECTIVE_END.search(s)
        if not end:
            raise InputError(
                f"{src.where}:{lineno}: a directive of a task file must stand on one line and "
                f"end with its full stop: {s[:60]!r}")
        # a comment after the full stop is no part of the directive: a modeb with one is a mode
        # (with its determination), not an unknown directive copied as it stands
        s = s[:end.start() + 1].rstrip()
        if not _INCLUDE_WORD.match(s):
            out.append((src.where, lineno, s))
            continue
        at = f"{src.where}:{lineno}"
        m = _INCLUDE.match(s)
        if not m:
            raise InputError(f"{at}: planerel_include takes one file name in single quotes, as in "
                             ":- planerel_include('modes_relational.pl').")
        inc = _included(m.group(1), src, at)
        keys = [c.key for c in chain]
        if inc.key in keys:
            loop = [c.where for c in chain[keys.index(inc.key):]] + [inc.where]
            raise InputError(f"{at}: planerel_include cycle: {' -> '.join(loop)}")
        out += _directives(inc, chain)
    return out


def task_directives(task: str | None = None) -> list[str]:
    """The directive lines (``:- ...``) of a task file in order, with every
    ``:- planerel_include('FILE').`` replaced by FILE's directive lines: the lines
    :func:`load_task` sorts into settings, modes and other declarations.

    ``task`` as for :func:`load_task`.  An included name is looked up in the including file's
    folder, and a bare name (no ``/``) that is not there in planerel's ``aleph/`` folder; a
    missing or cyclic include is an :class:`InputError` naming the file and line.
    """
    return [s for _, _, s in _directives(_task_source(task))]


def load_task(task: str | None = None) -> tuple[list[str], list[str], list[tuple[str, int]], list[str]]:
    """Read a task file: (set lines, modeb lines, body predicates (name, arity), other lines).

    ``task`` is a file path, or the name of a file in the package ``planerel.aleph``
    (default :data:`TASK_FILE`).  ``:- planerel_include('FILE').`` lines are expanded in place
    (:func:`task_directives`).
    """
    src = _task_source(task)
    sets, modes, preds, other = [], [], [], []
    for where, lineno, s in _directives(src):
        m = _MODEB.match(s)
        if m:
            args = [a for a in m.group(3).split(",") if a.strip()]
            key = (m.group(2), len(args))
            if key not in preds:
                preds.append(key)
            modes.append(s)
        elif _SET.match(s):
            sets.append(s)
        elif s.startswith(":- modeh") or s.startswith(":- determination"):
            raise InputError(f"{where}:{lineno}: the task file must not hold modeh/determination "
                             "(export-aleph writes them for the target)")
        else:
            other.append(s)
    if not modes:
        raise InputError(f"{src.where}: no modeb declarations found")
    return sets, modes, preds, other


def check_task_vocabulary(task: str | None = None, background=None) -> None:
    """Refuse a task (:func:`load_task`) with a ``modeb`` on a predicate that is neither
    planerel's vocabulary (the scene facts and ``prolog/derived.pl``, ``compare.pl``) nor
    defined by ``background`` (a :class:`planerel.ilp.background.Background`, the run's
    ``--background`` file): a model whose rule calls it could not classify a scene."""
    from planerel.ilp.prolog import model_vocabulary

    _, _, preds, _ = load_task(task)
    vocabulary = set(model_vocabulary()) | set(background.predicates if background else ())
    unknown = [f"{n}/{a}" for n, a in preds if (n, a) not in vocabulary]
    if unknown:
        raise InputError(
            f"{_task_source(task).where}: modeb on {', '.join(unknown)}, which "
            f"{'is' if len(unknown) == 1 else 'are'} not planerel's vocabulary (docs/predicates.md)"
            + (f" nor defined in {background.where}" if background else "")
            + ": a model whose rules call it could not classify a scene. Define it in a "
            "background file of your own, --background FILE (docs/learner.md, 'Background "
            "predicates of your own')")


# The SWI-Prolog pack's module file aleph.pl (``library(aleph)``) exports neither ``set/2``
# nor ``determination/2``, so ``aleph:read_all(user:STEM)`` by hand ran every ``:- set`` and
# ``:- determination`` of STEM.b as an unknown procedure and learned one fact per example.
# These lines define the two in the loading module as calls of the module's ``set/3`` and
# ``determination/3`` when (and only when) that module is loaded and the loading module has
# no definition of its own: the classic aleph_orig.pl, planerel's learner and planerel's
# driver of the real Aleph skip them (docs/predicates.md, "The Aleph task").
PACK_SHIM = [
    "% ---- for the SWI-Prolog pack's module aleph.pl: set/2 and determination/2 (skipped elsewhere)",
    ":- if(current_predicate(aleph:set/3)).",
    ":- prolog_load_context(module, M), ( current_predicate(M:set/2) -> true ; "
    "assertz((M:set(N, V) :- aleph:set(N, V, M))) ).",
    ":- prolog_load_context(module, M), ( current_predicate(M:determination/2) -> true ; "
    "assertz((M:determination(P, Q) :- aleph:determination(P, Q, M))) ).",
    ":- endif.",
]


def _class_order(names) -> list[str]:
    """Distinct class names: box, stairs, ramp first (in that order), then the rest sorted
    (never :data:`OTHER`)."""
    known = ("box", "stairs", "ramp")
    found = set(names) - {OTHER}
    return [c for c in known if c in found] + sorted(found - set(known))


def examples_of(descs) -> list[Example]:
    """Objects with a class, in scene and object order."""
    out = []
    for d in descs:
        for o in d.objects:
            if o.klass:
                out.append(Example(o.id, o.klass))
    return out


#: Facts never exported for learning: scene structure and planner data.
_NOT_EXPORTED = {"scene", "scene_plane", "floor", "up", "object", "support", "plane_model", "hull"}


def example_facts(descs, examples: list[Example]):
    """The scene facts of the example objects, as written for learning.

    Returns
    -------
    names : list of str
        The exported predicates, in vocabulary order.
    arity : dict
        Name -> arity.
    facts : dict
        Name -> list of fact lines (planes, attributes, the :data:`PAIRS` of each object).
    objects, planes : list of str
        The example objects and their planes, in scene order.
    """
    from dataclasses import replace

    from planerel.features.facts import PREDICATES, FactParams, scene_facts

    wanted = {e.object_id for e in examples}
    params = FactParams(pairs=PAIRS, planner=False, planes="objects")
    merged: dict[str, list[str]] = {}
    objs, planes = [], []
    for d in descs:
        keep = tuple(o for o in d.objects if o.id in wanted)
        if not keep:
            continue
        for name, lines in scene_facts(replace(d, objects=keep), params).items():
            merged.setdefault(name, []).extend(lines)
        for o in keep:
            objs.append(o.id)
            planes.extend(d.plane_id(x) for x in o.planes)
    names = [n for n, _, _, _ in PREDICATES if n not in _NOT_EXPORTED]
    arity = {n: a for n, a, _, _ in PREDICATES}
    return names, arity, merged, objs, planes


def _background(descs, examples: list[Example], classes: Sequence[str],
                background=None) -> list[str]:
    names, arity, merged, objs, planes = example_facts(descs, examples)
    lines = ["% ---- dynamic background predicates",
             ":- dynamic((" + ", ".join(f"{n}/{arity[n]}" for n in names) + ")).", "",
             "% ---- types"]
    lines += [terms.fact("obj", o) for o in objs]
    lines += [terms.fact("plane", p) for p in planes]
    lines += [terms.fact("orient", o) for o in ("horizontal", "vertical", "inclined")]
    lines += [terms.fact("cls", c) for c in classes]
    lines += ["", "% ---- comparison predicates (prolog/compare.pl)",
              _resource_text("planerel.prolog", "compare.pl").rstrip(),
              "", "% ---- derived relations (prolog/derived.pl)",
              _resource_text("planerel.prolog", "derived.pl").rstrip()]
    if background is not None:
        lines += ["", "% ---- background predicates of your own (--background "
                  + "".join(ch if 32 <= ord(ch) < 127 else "?" for ch in background.where) + ")",
                  background.text.rstrip()]
    lines += ["", "% ---- scene facts of the example objects"]
    for n in names:
        if merged.get(n):
            lines += [""] + merged[n]
    return lines



def task_examples(descs, target, classes=None, *, other_negatives: bool = False):
    """The examples of a learning task and its classes, checked (shared by the Aleph and
    Popper exports).

    Parameters
    ----------
    descs : sequence of SceneDescription
    target : str
        The class to learn, or ``"class"`` for one multi-class task.
    classes : sequence of str, optional
        The task's classes (default: those of the examples, in the usual order).
    other_negatives : bool
        Objects of class ``other`` are negatives of the task (the Aleph files): then one
        class and at least one ``other`` object make a task (box against everything else).

    Returns
    -------
    (list of Example, list of str)

    Raises
    ------
    InputError
        Fewer than two classes, a target without examples, or a name that is not a plain
        Prolog atom.
    """
    examples = examples_of(descs)
    if classes is None:
        classes = _class_order(e.klass for e in examples)
    classes = list(classes)
    n_other = sum(1 for e in examples if e.klass == OTHER)
    if len(classes) < 2 and not (other_negatives and classes and n_other):
        raise InputError(f"a learning task needs objects of at least two classes; found "
                         f"{', '.join(classes) or 'none'}"
                         + (f" (and {n_other} of class {OTHER!r}, which the Popper task "
                            "leaves out)" if n_other else
                            f" (objects of class {OTHER!r} would be negatives of every "
                            "class)"))
    if target != "class":
        if target not in classes:
            raise InputError(f"target class {target!r} has no examples; classes present: "
                             f"{', '.join(classes)}")
        if not terms.is_plain_atom(target):
            raise InputError(f"target {target!r} must be a plain Prolog name "
                             "([a-z][a-zA-Z0-9_]*)")
    for c in classes:
        if not terms.is_plain_atom(c):
            raise InputError(f"class name {c!r} must be a plain Prolog name ([a-z][a-zA-Z0-9_]*)")
    return examples, classes

def aleph_files(descs, target: str, *, classes: Sequence[str] | None = None,
                task: str | None = None, settings: dict | None = None,
                stem: str | None = None, skip_negatives=(), skip_positives=(),
                background=None) -> dict[str, str]:
    """The text of ``STEM.b``, ``STEM.f`` and ``STEM.n`` for one target.

    Parameters
    ----------
    descs : sequence of SceneDescription
        Described scenes whose objects carry a class (``SceneObject.klass``).
    target : str
        A class name (per-class task ``target(+obj)``) or ``"class"`` (multi-class task
        ``class(+obj, #cls)``).
    classes : sequence of str, optional
        The classes of the task (default: those of the examples, in order of appearance).
    task : str, optional
        Task file (default ``aleph/modes_relational.pl``; ``modes_objects.pl`` is the
        variant with the hand-written ``step_up/2``).
    settings : dict, optional
        Extra ``set/2`` values, checked by :func:`check_setting`; they override the task file.
    stem : str, optional
        File stem (default ``target``).
    skip_negatives : collection of str, optional
        Object ids that are no negative example of this target (a per-class task only): the
        objects the decision refuses the class for whatever the rules say
        (:func:`planerel.ilp.metrics.gated_negatives`).  Their facts stay in ``STEM.b``.
    skip_positives : collection of str, optional
        Object ids of this target left out of ``STEM.f`` (a per-class task only): the
        positives a prior theory already proves, when extending it
        (:func:`planerel.ilp.pipeline.learn_rules`' ``prior``).  Their facts stay in ``STEM.b``.
    background : Background, optional
        Background predicates of the user's own (:func:`planerel.ilp.background.read_background`):
        its clauses follow the derived relations in ``STEM.b``, and the task's ``modeb`` may name
        them.

    Returns
    -------
    dict
        ``{"STEM.b": text, "STEM.f": text, "STEM.n": text}``.
    """
    examples, classes = task_examples(descs, target, classes, other_negatives=True)
    multi = target == "class"
    check_class_names(classes)
    clash = [c for c in classes if (c, 1) in (background.predicates if background else ())]
    if clash or (multi and ("class", 2) in (background.predicates if background else ())):
        raise InputError(f"{background.where} defines {clash[0] if clash else 'class'}/"
                         f"{1 if clash else 2}, the target of the learning task; rename it")
    examples = [e for e in examples if e.klass in classes or e.klass == OTHER]
    stem = stem or target
    sets, modes, preds, other = load_task(task)
    overrides = {k: check_setting(k, v) for k, v in (settings or {}).items()
                 if k not in PLANEREL_SETTINGS}
    if str((settings or {}).get("gated_negatives", "false")).strip() == "true":
        raise InputError("gated_negatives=true is read by planerel learn (learn_rules), which "
                         "knows the planar gate's domain; the Aleph files alone cannot leave "
                         "gated objects out (pass skip_negatives, or drop the setting)")
    skip = frozenset(skip_negatives or ())
    if skip and target == "class":
        raise InputError("skip_negatives needs a per-class task, not the multi-class 'class'")
    have = frozenset(skip_positives or ())
    if have and target == "class":
        raise InputError("skip_positives needs a per-class task, not the multi-class 'class'")
    set_lines = []
    for s in sets:
        name = _SET.match(s).group(1)
        if name not in overrides:
            set_lines.append(s)
    set_lines += [f":- set({k}, {v})." for k, v in overrides.items()]
    head = "class(+obj, #cls)" if multi else f"{target}(+obj)"
    tname, tar = ("class", 2) if multi else (target, 1)
    npos = sum(1 for e in examples if (e.klass in classes if multi
                                       else e.klass == target and e.object_id not in have))
    nneg = (sum(len(classes) - (e.klass in classes) for e in examples) if multi
            else sum(1 for e in examples if e.klass != target and e.object_id not in skip))
    b = [f"% planerel Aleph task {stem}: {'multi-class' if multi else 'is the object a ' + target}",
         f"% examples: {npos} positive, {nneg} negative; classes: {', '.join(classes)}",
         "% written by planerel export-aleph; vocabulary: docs/predicates.md",
         ":- op(500, fy, #).", ""] + PACK_SHIM + ["", "% ---- settings"] + set_lines
    b += ["", "% ---- modes", f":- modeh(1, {head})."] + modes
    b += ["", "% ---- determinations"]
    b += [f":- determination({tname}/{tar}, {n}/{a})." for n, a in preds]
    b += ["", "% ---- other declarations"] + other + [""]
    b += _background(descs, examples, classes, background)
    F = terms.fact
    if multi:
        pos = [F("class", e.object_id, e.klass) for e in examples if e.klass in classes]
        neg = [F("class", e.object_id, c) for e in examples for c in classes if c != e.klass]
    else:
        pos = [F(target, e.object_id) for e in examples
               if e.klass == target and e.object_id not in have]
        neg = [F(target, e.object_id) for e in examples
               if e.klass != target and e.object_id not in skip]
    return {f"{stem}.b": "\n".join(b) + "\n", f"{stem}.f": "".join(x + "\n" for x in pos),
            f"{stem}.n": "".join(x + "\n" for x in neg)}


def export_aleph(descs, out_dir, target: str = "all", *, classes: Sequence[str] | None = None,
                 task: str | None = None, settings: dict | None = None,
                 class_settings: dict | None = None,
                 skip_negatives: dict | None = None,
                 skip_positives: dict | None = None, background=None) -> ExportResult:
    """Write the Aleph files of a target to ``out_dir``.

    ``target``: a class name; ``"all"`` (one stem per class); ``"class"`` (one multi-class
    stem ``class``).  ``class_settings`` (``{stem: {name: value}}``) replace ``settings`` in
    that stem's ``.b`` only, so each file says what its class was learned with.
    ``skip_negatives`` (``{stem: object ids}``): objects that are no negative of that stem
    (:func:`aleph_files`); ``background``: a checked background file of the user's own
    (:func:`aleph_files`).
    """
    from planerel.atomic import write_text

    descs = list(descs)
    examples = examples_of(descs)
    if classes is None:
        classes = _class_order(e.klass for e in examples)
    targets = list(classes) if target == "all" else [target]
    texts: dict[str, str] = {}
    for t in targets:
        own = {**(settings or {}), **(class_settings or {}).get(t, {})}
        texts.update(aleph_files(descs, t, classes=classes, task=task, settings=own or None,
                                 skip_negatives=(skip_negatives or {}).get(t, ()),
                                 skip_positives=(skip_positives or {}).get(t, ()),
                                 background=background))
    out = Path(out_dir)
    paths = tuple(write_text(out / name, text) for name, text in sorted(texts.items()))
    counts = {c: sum(1 for e in examples if e.klass == c) for c in classes}
    stems = tuple(dict.fromkeys(Path(n).stem for n in sorted(texts)))
    return ExportResult(paths, stems, counts)


def describe_dataset(dataset_dir, *, labels: str = "gt", classes: Sequence[str] | None = None,
                     method: str = "regiongrow"):
    """Describe every scene of a data set, with its ground-truth object as the example.

    Parameters
    ----------
    dataset_dir : path
        A data set written by ``planerel dataset synth`` (or in the same format).
    labels : ``"gt"`` or ``"segment"``
        Plane labels from the ground truth, or from :func:`planerel.segment.segment`
        (planes then join the ground-truth object they mostly cover).
    classes : sequence of str, optional
        The classes of the task: the objects of the scenes of other classes are objects of
        class ``other``, every class's negatives (as :func:`planerel.ilp.scenes.describe_scenes`).

    Returns
    -------
    descs : list of SceneDescription
    skipped : list of str
        Scenes whose object has no measured plane, with the reason.
    """
    from planerel.features.dataset import describe_truth_scene, iter_scenes

    if labels not in ("gt", "segment"):
        raise InputError(f"labels must be 'gt' or 'segment', got {labels!r}")
    from planerel.ilp.scenes import example_rule

    rule = example_rule(dataset_dir)
    descs, skipped = [], []
    from planerel.ilp.scenes import unlisted_as_other

    for row, cloud, gt, meta in iter_scenes(dataset_dir):
        if gt is None:
            raise InputError(f"{dataset_dir}: scene {row.scene_id} has no ground-truth labels, "
                             "so its object is unknown")
        if labels == "gt":
            lab = gt
        else:
            from planerel.segment import segment

            lab = segment(cloud, method).labels
        d = describe_truth_scene(cloud, lab, gt, meta, row.scene_id, row.klass, rule=rule)
        if classes is not None:
            d = unlisted_as_other(d, classes)
        if not d.objects:
            skipped.append(f"{row.scene_id}: no plane of its {row.klass} was measured")
        descs.append(d)
    return descs, skipped


def export_dataset(dataset_dir, out_dir, target: str = "all", *, labels: str = "gt",
                   task: str | None = None, settings: dict | None = None,
                   background=None) -> ExportResult:
    """:func:`describe_dataset` then :func:`export_aleph`.

    ``background``: a background file of the user's own (a path), checked by
    :func:`planerel.ilp.background.read_background`; its clauses go into every ``STEM.b``.
    What would fail after describing every scene fails first: the background file, the task
    file, the settings and the output folder (an empty name, a file, a folder that cannot be
    written)."""
    if background is not None:
        from planerel.ilp.background import read_background

        background = read_background(background)
    load_task(task)
    for name, value in (settings or {}).items():
        check_setting(name, value)
    check_export_target(dataset_dir, out_dir)
    descs, skipped = describe_dataset(dataset_dir, labels=labels)
    res = export_aleph(descs, out_dir, target, task=task, settings=settings,
                       background=background)
    return ExportResult(res.files, res.stems, res.counts, tuple(skipped))


def check_export_target(dataset_dir, out_dir) -> None:
    """Before describing a data set for an export: its manifest reads, and ``out_dir`` is a
    folder that can be written (made when missing, :func:`planerel.atomic.check_output_dir`)."""
    from planerel.atomic import check_output_dir
    from planerel.features.dataset import load_manifest

    load_manifest(dataset_dir)
    check_output_dir(out_dir, "OUT_DIR")


def check_class_names(classes) -> None:
    """Refuse class names that are built-in or library predicates of arity 1 (``halt``,
    ``shell``, ``atom``...), part of the scene vocabulary or of planerel's support code: a
    class ``C`` becomes the predicate ``C/1`` of the learning task.

    Raises
    ------
    InputError
        Naming the first such class.
    """
    from planerel.ilp.prolog import model_vocabulary

    vocab = {n for n, _ in model_vocabulary()}
    for c in classes:
        if c in vocab or c.startswith("planerel_") or c == "class":
            raise InputError(f"class name {c!r} is a predicate of planerel's vocabulary; "
                             "choose another name")
    clash = _reserved_names(tuple(sorted(set(classes))))
    if clash:
        raise InputError(f"class name {clash[0]!r} is a built-in or library predicate of "
                         "SWI-Prolog; choose another name")


@functools.lru_cache(maxsize=64)
def _reserved_names(names: tuple) -> list:
    """The names among ``names`` that ``planerel_reserved_class/1`` (prolog/classify.pl) refuses;
    asked of a fresh ``swipl`` once per set of names (none when SWI-Prolog is missing: the
    learner then fails with its own clear error)."""
    import subprocess

    from planerel.children import child_preexec
    from planerel.errors import DependencyError
    from planerel.ilp.prolog import find_swipl, swipl_command

    try:
        exe = find_swipl()
    except DependencyError:
        return []
    goal = "forall(( member(N, Args), planerel_reserved_class(N) ), writeln(N))"
    try:
        proc = subprocess.run(swipl_command(goal, names, exe=exe),
                              capture_output=True, text=True, timeout=60, check=False,
                              preexec_fn=child_preexec(60))
    except (OSError, subprocess.TimeoutExpired):
        return []
    found = set(proc.stdout.split())
    return [n for n in names if n in found]
