"""Described scenes to a Popper learning task: ``bk.pl``, ``exs.pl``, ``bias.pl`` per class.

Popper (Cropper and Morel, "Learning programs by learning from failures", 2021) reads a task
folder with three files:

``exs.pl``
    ``pos(stairs(s0007_o1)).`` for every object of the class, ``neg(stairs(s0003_o1)).`` for
    every object of another class (Prolog).
``bk.pl``
    the background knowledge (Prolog): the same scene facts the Aleph export writes (the planes
    of each example object, their attributes and the relations of every ordered pair within the
    object, :data:`planerel.ilp.aleph_export.PAIRS`), the orientation classes ``horizontal/1``,
    ``vertical/1``, ``inclined/1`` (``prolog/derived.pl``) and the count constants
    ``zero/1``, ``one/1``, ``two/1``.
``bias.pl``
    the language (read by Popper with clingo): ``head_pred/2``, ``body_pred/2``, ``type/2``,
    ``direction/2`` for every predicate, and ``max_vars/1``, ``max_body/1``, ``max_clauses/1``.

Popper learns no numeric thresholds of its own, so the measures (angle, gap, rise, area, ...)
are in ``bk.pl`` but not in the bias; constants are unary predicates, as in Popper's examples
(``orientation(P, horizontal)`` is ``horizontal(P)``, ``nhorizontal(O, 1)`` is
``nhorizontal(O, N), one(N)``).
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

from planerel.errors import InputError
from planerel.features import terms

__all__ = ["BODY_PREDICATES", "COUNT_CONSTANTS", "popper_files", "export_popper", "export_dataset"]

#: Body predicates of the bias: (name, arity, types, directions).
BODY_PREDICATES: tuple[tuple[str, int, tuple[str, ...], tuple[str, ...]], ...] = (
    ("has_plane", 2, ("obj", "plane"), ("in", "out")),
    ("horizontal", 1, ("plane",), ("in",)),
    ("vertical", 1, ("plane",), ("in",)),
    ("inclined", 1, ("plane",), ("in",)),
    ("adjacent", 2, ("plane", "plane"), ("in", "out")),
    ("parallel", 2, ("plane", "plane"), ("in", "out")),
    ("perpendicular", 2, ("plane", "plane"), ("in", "out")),
    ("above", 2, ("plane", "plane"), ("in", "out")),
    # the relations the Aleph task's rules and the shipped model rest on (docs/predicates.md):
    # a top and a face hanging from it, two faces at a box's corner, two risers a step apart,
    # and the one-plane box literals (ilp90: without them Popper could not learn those rules)
    ("skirt", 2, ("plane", "plane"), ("in", "out")),
    ("corner", 2, ("plane", "plane"), ("in", "out")),
    ("face_pair", 2, ("plane", "plane"), ("in", "out")),
    ("stair_step", 2, ("plane", "plane"), ("in", "out")),
    ("tall_face", 1, ("plane",), ("in",)),
    ("lying", 1, ("plane",), ("in",)),
    ("curved", 1, ("obj",), ("in",)),
    ("nhorizontal", 2, ("obj", "count"), ("in", "out")),
    ("nvertical", 2, ("obj", "count"), ("in", "out")),
    ("ninclined", 2, ("obj", "count"), ("in", "out")),
    ("zero", 1, ("count",), ("in",)),
    ("one", 1, ("count",), ("in",)),
    ("two", 1, ("count",), ("in",)),
)

#: The count constants defined in ``bk.pl``: name -> value.
COUNT_CONSTANTS = {"zero": 0, "one": 1, "two": 2}

#: Default search bounds: the rules planerel learns have at most 4 variables and 4 body
#: literals (e.g. ``box(A) :- nhorizontal(A,B), one(B), ninclined(A,C), zero(C).``).
DEFAULT_BOUNDS = {"max_vars": 5, "max_body": 5, "max_clauses": 2}


def _tuple(items: Sequence[str]) -> str:
    """An ASP tuple as Popper's bias writes it: ``(a,b)``, and ``(a,)`` for one element."""
    return "(" + ",".join(items) + ("," if len(items) == 1 else "") + ")"


def _bounds(bounds: dict | None) -> dict:
    out = dict(DEFAULT_BOUNDS)
    for k, v in (bounds or {}).items():
        if k not in out:
            raise InputError(f"unknown Popper bound {k!r}; choose from {', '.join(out)}")
        if isinstance(v, bool) or not isinstance(v, int) or v < 1:
            raise InputError(f"Popper bound {k} must be a positive integer, got {v!r}")
        out[k] = v
    return out


def popper_files(descs, target: str, *, classes: Sequence[str] | None = None,
                 bounds: dict | None = None) -> dict[str, str]:
    """The text of ``bk.pl``, ``exs.pl`` and ``bias.pl`` for one class.

    Parameters
    ----------
    descs : sequence of SceneDescription
        Described scenes whose objects carry a class.
    target : str
        The class to learn (the head predicate, ``target(+obj)``).
    classes : sequence of str, optional
        The classes of the task (default: those of the examples).
    bounds : dict, optional
        ``max_vars``, ``max_body``, ``max_clauses`` (defaults :data:`DEFAULT_BOUNDS`).

    Returns
    -------
    dict
        ``{"bk.pl": text, "exs.pl": text, "bias.pl": text}``.
    """
    from planerel.ilp.aleph_export import _resource_text, example_facts, task_examples

    if target == "class":
        raise InputError("a Popper task learns one class at a time; name the class")
    examples, classes = task_examples(descs, target, classes)
    if any(target == name for name, *_ in BODY_PREDICATES):
        raise InputError(f"class name {target!r} is a body predicate of the Popper task")
    b = _bounds(bounds)
    examples = [e for e in examples if e.klass in classes]
    names, arity, facts, _, _ = example_facts(descs, examples)

    bk = [f"% planerel Popper task {target}: background knowledge (Prolog)",
          "% written by planerel export-popper; vocabulary: docs/predicates.md",
          ":- dynamic((" + ", ".join(f"{n}/{arity[n]}" for n in names) + ")).", "",
          "% ---- orientation classes and derived relations (prolog/derived.pl)",
          _resource_text("planerel.prolog", "derived.pl").rstrip(), "",
          "% ---- count constants"]
    bk += [terms.fact(name, value) for name, value in COUNT_CONSTANTS.items()]
    bk += ["", "% ---- scene facts of the example objects"]
    for n in names:
        if facts.get(n):
            bk += [""] + facts[n]

    F = terms.fact
    pos = [F("pos", terms.term(target, e.object_id)) for e in examples if e.klass == target]
    neg = [F("neg", terms.term(target, e.object_id)) for e in examples if e.klass != target]
    exs = [f"% planerel Popper task {target}: {len(pos)} positive, {len(neg)} negative examples"]
    exs += pos + neg

    bias = [f"% planerel Popper task {target}: is the object a {target}",
            "% written by planerel export-popper (read by Popper with clingo)",
            f"max_vars({b['max_vars']}).", f"max_body({b['max_body']}).",
            f"max_clauses({b['max_clauses']}).", "", f"head_pred({target},1)."]
    bias += [f"body_pred({n},{a})." for n, a, _, _ in BODY_PREDICATES]
    bias += ["", f"type({target},{_tuple(['obj'])})."]
    bias += [f"type({n},{_tuple(t)})." for n, _, t, _ in BODY_PREDICATES]
    bias += ["", f"direction({target},{_tuple(['in'])})."]
    bias += [f"direction({n},{_tuple(d)})." for n, _, _, d in BODY_PREDICATES]
    return {"bk.pl": "\n".join(bk) + "\n", "exs.pl": "\n".join(exs) + "\n",
            "bias.pl": "\n".join(bias) + "\n"}


def export_popper(descs, out_dir, target: str = "all", *, classes: Sequence[str] | None = None,
                  bounds: dict | None = None) -> tuple[Path, ...]:
    """Write one Popper task folder per class: ``OUT/CLASS/{bk,exs,bias}.pl``.

    ``target``: a class name, or ``"all"`` (every class). Returns the folders written.
    """
    from planerel.atomic import write_text
    from planerel.ilp.aleph_export import _class_order, examples_of

    descs = list(descs)
    if classes is None:
        classes = _class_order(e.klass for e in examples_of(descs))
    targets = list(classes) if target == "all" else [target]
    texts = {t: popper_files(descs, t, classes=classes, bounds=bounds) for t in targets}
    out = Path(out_dir)
    folders = []
    for t, files in texts.items():
        for name, text in files.items():
            write_text(out / t / name, text)
        folders.append(out / t)
    return tuple(folders)


def export_dataset(dataset_dir, out_dir, target: str = "all", *, labels: str = "gt",
                   bounds: dict | None = None):
    """Describe a data set (:func:`planerel.ilp.aleph_export.describe_dataset`) and write the
    Popper tasks. Returns ``(folders, counts, skipped)``."""
    from planerel.ilp.aleph_export import (
        _class_order,
        check_export_target,
        describe_dataset,
        examples_of,
    )

    check_export_target(dataset_dir, out_dir)  # before describing every scene
    descs, skipped = describe_dataset(dataset_dir, labels=labels)
    examples = examples_of(descs)
    classes = _class_order(e.klass for e in examples)
    folders = export_popper(descs, out_dir, target, classes=classes, bounds=bounds)
    counts = {c: sum(1 for e in examples if e.klass == c) for c in classes}
    return folders, counts, tuple(skipped)
