"""The end-to-end job: data set -> segmentation (cached) -> descriptions -> Aleph files ->
rules -> cross-validated metrics -> a model directory.

Every function takes plain data and returns plain data; ``planerel learn`` and the report are
thin layers over :func:`learn_model` and :func:`evaluate_learning`.

Scoring a theory is a logic query, the same one ``planerel classify`` asks: the rules, the
support predicates of ``prolog/`` and the scene facts are loaded into one ``swipl`` process,
which says for every object which rules prove which class (:func:`prolog_predict`).
"""

from __future__ import annotations

import functools
import sys
import time
from collections.abc import Sequence
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import TYPE_CHECKING

from planerel.children import temp_dir
from planerel.errors import InputError, LearnerError, PrologError
from planerel.ilp.metrics import (
    FLIGHT_FRAGMENTS,
    FLIGHT_GATE,
    LEVEL_GATE,
    OTHER,
    PLANAR_GATE,
    PLANAR_MARGIN,
    PROOF_GATE,
    PROOF_MARGIN,
    PROOF_MIN_POSITIVES,
    RANGE_CLASSES,
    RANGE_GATE,
    RANGE_MARGIN,
    SIZE_CLASSES,
    SIZE_GATE,
    SIZE_MARGIN,
    SLENDER_CLASSES,
    SLENDER_GATE,
    SLENDER_MARGIN,
    VETO_RATIO,
    accuracy_scores,
    confusion_columns,
    decide,
    error_kinds,
    gated_negatives,
    horizontal_counts,
    laplace,
    level_domain,
    planar_domain,
    plane_extents,
    plane_ranges,
    plane_slenderness,
    proof_domain,
    range_domain,
    score_objects,
    size_domain,
    size_gated,
    slender_domain,
    stratified_folds,
)
from planerel.ilp.scenes import describe_scenes

if TYPE_CHECKING:
    from planerel.ilp.background import Background

__all__ = [
    "DEFAULT_CLASSES",
    "Prediction",
    "Model",
    "Members",
    "learn_rules",
    "learn_members",
    "write_members",
    "prolog_predict",
    "OTHER",
    "cross_validate",
    "held_out_scores",
    "with_decision",
    "learn_model",
    "evaluate_learning",
    "draw_confusion",
]

DEFAULT_CLASSES = ("box", "stairs", "ramp")


# ----------------------------------------------------------------------------- learning


@dataclass(frozen=True)
class Model:
    """Rules learned for each class.

    Attributes
    ----------
    classes : tuple of str
    rules : dict
        ``{class: (clause text, ...)}``.
    stats : tuple
        ``(index, class, tp, fp)`` per clause in file order, measured on the training objects.
    engine : str
        The learner that ran (``builtin`` or ``aleph``) and why.
    seconds : float
        Learning time (all classes).
    clauses_explored : int
    cofire : tuple
        ``(i, j, class, n)``: ``n`` training objects of ``class`` (or ``other``) on which the
        clauses ``i < j`` of two different targets both fired (:func:`choose_class` decides
        such conflicts with them).
    dropped : tuple
        ``(class, clause text, tp, fp)`` of the clauses the learner found and
        :func:`drop_redundant` left out (their training positives were all proved by the other
        clauses of their class); written into :meth:`text` as comments.
    uncovered : dict
        ``{class: n}`` training objects no general rule covers (Aleph keeps them as ground
        facts when ``minpos`` is 1 and leaves them out otherwise; a model for new scenes has no
        use for them, so they are counted, not kept).
    planar_domain : tuple
        ``(class, low, high, n)``: the planar fractions of each class's training positives
        (:func:`planerel.ilp.metrics.planar_domain`; ``model.json`` keeps them).  Empty: no
        planar gate (a model from before they were kept).
    planar_gate : bool
        Whether :func:`prolog_predict` refuses a class for an object far less planar than the
        class's training positives (:class:`planerel.ilp.metrics.DecisionParams`).
    planar_margin : float
        The gate's margin below ``low`` (:func:`planerel.ilp.metrics.planar_refusals`).
    proof_domain : tuple
        ``(index, class, low, high, n)``: how large the planes are that each rule proved its
        training positives with (:func:`planerel.ilp.metrics.proof_domain`; ``model.json``
        keeps them).  Empty: no proof gate (a model from before they were kept).
    proof_gate : bool
        Whether :func:`prolog_predict` refuses a rule whose proof of an object is made of
        planes far smaller than its training proofs' (:func:`planerel.ilp.metrics.proof_refusals`).
    proof_margin : float
        That gate's margin below ``low``.
    proof_min_positives : int
        The fewest true positives a rule's entry must have been measured on to count.
    veto_ratio : float
        A rule for ``other`` is set aside for an object a class rule proves with planes more
        than this many times larger (:func:`planerel.ilp.metrics.veto_refusals`; 0 = off).
    level_domain : tuple
        ``(class, low, n)``: the fewest horizontal planes of each class's training positives
        (:func:`planerel.ilp.metrics.level_domain`; ``model.json`` keeps them).  Empty: no
        level gate (a model from before they were kept).
    level_gate : bool
        Whether :func:`prolog_predict` refuses a class for an object with fewer horizontal
        planes than any of its training positives (:func:`planerel.ilp.metrics.level_refusals`).
    flight_gate : bool
        Whether :func:`prolog_predict` refuses ``stairs`` for an object whose faces show no
        staircase's steps (:func:`planerel.ilp.metrics.flight_refusals`).
    flight_fragments : bool
        Whether that test reads a flight seen in fragments too
        (:func:`planerel.features.step_chains.flight_fragments`).
    size_domain : tuple
        ``(class, high, n)``: the longest plane each class's rules proved its training
        positives with (:func:`planerel.ilp.metrics.size_domain`; ``model.json`` keeps it).
        Empty: no size gate (a model from before it was kept).
    size_gate : bool
        Whether :func:`prolog_predict` refuses a rule whose proof binds a plane far longer
        than the class's training proofs' (:func:`planerel.ilp.metrics.size_refusals`).
    size_margin : float
        That gate's margin above ``high`` (a share of it).
    size_classes : str
        The classes that gate holds for, comma-separated.
    slender_domain : tuple
        ``(class, high, n)``: the most slender top each class's rules proved its training
        positives with (:func:`planerel.ilp.metrics.slender_domain`; ``model.json`` keeps it).
        Empty: no slenderness gate (a model from before it was kept).
    slender_gate : bool
        Whether :func:`prolog_predict` refuses a rule whose proof binds a top far more slender
        than the class's training proofs' (:func:`planerel.ilp.metrics.slender_refusals`).
    slender_margin : float
        That gate's margin above ``high`` (a share of it).
    slender_classes : str
        The classes that gate holds for, comma-separated.
    range_domain : tuple
        ``(class, high, n)``: the farthest plane from the sensor each class's rules proved its
        training positives with (:func:`planerel.ilp.metrics.range_domain`; ``model.json``
        keeps it).  Empty: no range gate (a model from before it was kept).
    range_gate : bool
        Whether :func:`prolog_predict` refuses a rule whose proof binds a plane far farther
        from the sensor than the class's training proofs' (:func:`planerel.ilp.metrics.range_refusals`).
    range_margin : float
        That gate's margin above ``high`` (a share of it).
    range_classes : str
        The classes that gate holds for, comma-separated.
    background : Background or None
        The background file of the user's own the rules may call
        (:func:`planerel.ilp.background.read_background`; ``learn --background``): loaded with
        the rules wherever they are queried.
    """

    classes: tuple
    rules: dict
    stats: tuple = ()
    engine: str = ""
    seconds: float = 0.0
    clauses_explored: int = 0
    uncovered: dict = field(default_factory=dict)
    cofire: tuple = ()
    dropped: tuple = ()
    planar_domain: tuple = ()
    planar_gate: bool = PLANAR_GATE
    planar_margin: float = PLANAR_MARGIN
    proof_domain: tuple = ()
    proof_gate: bool = PROOF_GATE
    proof_margin: float = PROOF_MARGIN
    proof_min_positives: int = PROOF_MIN_POSITIVES
    veto_ratio: float = VETO_RATIO
    level_domain: tuple = ()
    level_gate: bool = LEVEL_GATE
    flight_gate: bool = FLIGHT_GATE
    flight_fragments: bool = FLIGHT_FRAGMENTS
    size_domain: tuple = ()
    size_gate: bool = SIZE_GATE
    size_margin: float = SIZE_MARGIN
    size_classes: str = SIZE_CLASSES
    slender_domain: tuple = ()
    slender_gate: bool = SLENDER_GATE
    slender_margin: float = SLENDER_MARGIN
    slender_classes: str = SLENDER_CLASSES
    range_domain: tuple = ()
    range_gate: bool = RANGE_GATE
    range_margin: float = RANGE_MARGIN
    range_classes: str = RANGE_CLASSES
    background: Background | None = None

    @property
    def targets(self) -> tuple:
        """The classes, then ``other`` when the model has rules for it (rules that describe
        objects of none of the classes, :func:`learn_rules`' ``other_rules``)."""
        return self.classes + ((OTHER,) if self.rules.get(OTHER) and OTHER not in self.classes
                               else ())

    def clauses(self) -> list[str]:
        """All clauses in target order (the order of :meth:`text`)."""
        return [c for k in self.targets for c in self.rules.get(k, ())]

    def text(self, header: str = "") -> str:
        """The model as a Prolog file: rules plus ``planerel_rule_stats/4`` and
        ``planerel_rule_cofire/4`` facts."""
        from planerel.features.terms import fact

        # comments in printable ASCII whatever the header holds (paths in any encoding)
        safe = ["".join(ch if 32 <= ord(ch) < 127 else "?" for ch in ln)
                for ln in header.splitlines()]
        lines = [f"% {ln}" if ln else "%" for ln in safe]
        lines += ["% planerel model: learned rules, one class after another.",
                  "% Load with the support predicates of planerel's prolog/ folder",
                  "% (compare.pl, derived.pl) and scene facts; see docs/results.md.",
                  ":- dynamic(planerel_rule_stats/4).", ":- multifile(planerel_rule_stats/4).",
                  ":- dynamic(planerel_rule_cofire/4).", ":- multifile(planerel_rule_cofire/4).",
                  ":- style_check(-singleton).  % learned rules name variables they only bind", ""]
        for k in self.targets:
            lines.append(f"% ---- {k}" + ("  (none of the classes: these rules win an object "
                                          "when their precision is higher)" if k == OTHER else ""))
            lines += list(self.rules.get(k, ())) or [f"% (no rule learned for {k})"]
            lines.append("")
        if self.dropped:
            lines.append("% clauses learned but left out: every training object of their class "
                         "they proved, another clause proves too")
            lines += [f"%   {k}: {text}  (proved {tp} {k}, {fp} other objects)"
                      for k, text, tp, fp in self.dropped]
            lines.append("")
        if self.stats:
            lines.append("% planerel_rule_stats(Index, Class, TruePositives, FalsePositives)")
            lines += [fact("planerel_rule_stats", i, k, tp, fp) for i, k, tp, fp in self.stats]
        if self.cofire:
            lines.append("% planerel_rule_cofire(I, J, Class, N): N training objects of Class on "
                         "which clauses I and J (of two classes) both fired")
            lines += [fact("planerel_rule_cofire", i, j, k, n) for i, j, k, n in self.cofire]
        return "\n".join(lines) + "\n"


@dataclass(frozen=True)
class Members:
    """A model of several members (:mod:`planerel.ilp.members`): one :class:`Model` per
    disjoint part of the training set, their answers joined by
    :func:`planerel.ilp.members.vote`.  :func:`prolog_predict` and :func:`held_out_scores`
    take it wherever they take a :class:`Model`.

    Attributes
    ----------
    models : tuple of Model
    """

    models: tuple

    @property
    def classes(self) -> tuple:
        """The classes of the members, in order of first appearance."""
        return tuple(dict.fromkeys(k for m in self.models for k in m.classes))

    @property
    def stats(self) -> tuple:
        """``((member, index), class, tp, fp)`` of every member's rules."""
        return tuple(((n, i), k, tp, fp) for n, m in enumerate(self.models)
                     for i, k, tp, fp in m.stats)

    def clauses(self) -> list[str]:
        return [c for m in self.models for c in m.clauses()]

    def text(self, header: str = "") -> str:
        """Every member's rules, each under a comment header: plain clauses, read as data
        (the members' statistics are in their own folders, ``members/N/rules.pl``)."""
        safe = ["".join(ch if 32 <= ord(ch) < 127 else "?" for ch in ln)
                for ln in header.splitlines()]
        lines = [f"% {ln}" if ln else "%" for ln in safe]
        lines += [f"% planerel model of {len(self.models)} members: each learned on its own "
                  "part of the training set;",
                  "% an object's class is the members' vote (model.json, 'vote'). Each "
                  "member's rules,",
                  "% training statistics and settings are in members/N/; the rules below are "
                  "for reading.", ""]
        for n, m in enumerate(self.models, start=1):
            lines.append(f"% ======== member {n} (members/{n}/rules.pl)")
            for k in m.targets:
                lines.append(f"% ---- member {n}: {k}")
                lines += list(m.rules.get(k, ())) or [f"% (no rule learned for {k})"]
            lines.append("")
        return "\n".join(lines) + "\n"


def _examples(descs):
    return [(o.id, o.klass) for d in descs for o in d.objects if o.klass]


def object_shows(test, where: dict, object_id) -> bool:
    """``test(planes, labels)`` of object ``object_id`` (False when it is not in ``where``,
    ``{object id: (description, object)}``): the level gate's
    :func:`planerel.features.step_chains.flight_faces` and the flight gate's
    :func:`~planerel.features.step_chains.flight_evidence`, with the default proposal settings
    ``planerel learn`` describes scenes with."""
    if object_id not in where:
        return False
    d, o = where[object_id]
    return test(d.planes, o.planes)


def with_decision(model, decision: dict | None):
    """``model`` (a :class:`Model` or :class:`Members`) with the decision settings ``decision``
    (``{name: value}``, fields of :class:`Model` such as ``proof_gate``) in place of its own."""
    if not decision:
        return model
    if isinstance(model, Members):
        return replace(model, models=tuple(replace(m, **decision) for m in model.models))
    return replace(model, **decision)


def _metrics_head(dataset_dir, classes, method, seg_params, seed, settings, task, recipe,
                  other_rules, decision) -> dict:
    """The first keys of a model's ``metrics.json``: what it was learned from and how
    (``decision``: the recipe's decision settings written into the model, ``{}`` for none)."""
    return {"dataset": str(dataset_dir), "classes": list(classes), "method": method,
            "seg_params": dict(seg_params or {}), "seed": seed,
            "learner_settings": {k: str(v) for k, v in (settings or {}).items()},
            "task": task or "modes_relational.pl", "recipe": recipe,
            "other_rules": other_rules, "decision": dict(decision or {})}


def _example_counts(descs, classes) -> dict:
    """``n_scenes``, ``n_examples`` (objects of a learned class), ``examples`` (those per
    class), ``n_other`` and ``excluded`` (:func:`excluded_counts`: the ground-truth objects
    that are no example, by class and reason) of ``descs``."""
    kinds = [k for _, k in _examples(descs)]
    return {"n_scenes": len(descs), "n_examples": sum(k in classes for k in kinds),
            "examples": {k: kinds.count(k) for k in classes},
            "n_other": sum(k == OTHER for k in kinds), "excluded": excluded_counts(descs)}


def excluded_counts(descs) -> dict:
    """``{class: {reason: n}}`` of the ground-truth objects that are no example
    (:func:`planerel.features.truth_examples.judge_objects`), to report beside the scores."""
    out: dict = {}
    for d in descs:
        for _oid, klass, why in getattr(d, "excluded", ()):
            per = out.setdefault(klass, {})
            per[why] = per.get(why, 0) + 1
    return {k: dict(sorted(v.items())) for k, v in sorted(out.items())}


def split_class_settings(settings: dict | None, classes: Sequence[str]) -> tuple[dict, dict]:
    """Split learner settings into the ones for every class and per-class overrides.

    A name ``CLASS:NAME`` (``box:noise``) applies to that class only, after the common
    settings; a plain ``NAME`` applies to every class.  Classes differ in how many of their
    examples look alike: the demo's box positives need more noise than its stairs.

    Returns
    -------
    (dict, dict)
        ``{name: value}`` for every class and ``{class: {name: value}}``.

    Settings for ``other`` are left out when ``other`` is not learned (no ``other_rules``, or
    fewer than two ``other`` objects), as ``other_rules`` itself then learns nothing: a recipe
    with rules for ``other`` still applies to a data set without clutter.

    Raises
    ------
    InputError
        When ``CLASS`` is not one of ``classes`` nor ``other``.
    """
    common: dict = {}
    per_class: dict = {}
    for name, value in (settings or {}).items():
        cls, sep, rest = str(name).partition(":")
        if not sep:
            common[name] = value
            continue
        if cls == OTHER and cls not in classes:
            continue
        if cls not in classes:
            raise InputError(f"setting {name!r}: {cls!r} is not a class being learned "
                             f"({', '.join(classes)})")
        per_class.setdefault(cls, {})[rest] = value
    return common, per_class


def learn_rules(descs, classes: Sequence[str], *, engine: str = "builtin", timeout: float = 120.0,
                settings: dict | None = None, work_dir=None, task: str | None = None,
                jobs: int | None = None, log=None, other_rules: bool = False,
                keep_redundant: bool = False, prior: dict | None = None,
                extend_only: Sequence[str] | None = None, background=None) -> Model:
    """Learn one theory per class from described scenes (one Aleph run per class).

    With ``other_rules`` and objects of class ``other`` among the examples (clutter: none of
    the classes), a theory for ``other`` is learned too (its negatives are the objects of
    every class), so that "none of the classes" is an answer a rule proves, not only what is
    left when no class rule fires: where a class rule and an ``other`` rule both prove an
    object, the one with the higher training precision wins (:func:`choose_class`).  Off by
    default: measured in docs/results.md ("Rules for other").

    Parameters
    ----------
    descs : list of SceneDescription
        Scenes whose objects carry their class.
    classes : sequence of str
        The classes; each needs at least one example, and there must be two or more.
    engine : {"builtin", "aleph", "auto"}
    timeout : float
        Seconds per class before the learner is stopped.
    settings : dict, optional
        Aleph settings (``set/2``) for every class; a name ``CLASS:NAME`` sets it for one class
        only (:func:`split_class_settings`).
    work_dir : path, optional
        Where the Aleph files are written (kept); default a temporary folder.
    jobs : int, optional
        Classes learned at once, one ``swipl`` each (None: as many as cores, at most one per
        class); the model does not depend on it.
    log : callable, optional
        Receives progress lines (``"[box] rule 3 ..."``, one per clause added, and one per
        class learned).
    other_rules : bool
        Learn rules for ``other`` as well when there are at least two ``other`` objects
        (settings for it: ``other:NAME``).
    keep_redundant : bool
        Keep every clause the learner returned.  By default a clause whose training positives
        the other clauses of its class all prove, and that proves some objects of other
        classes, is left out (:func:`drop_redundant`).
    prior : dict, optional
        ``{class: clauses}``: a theory to extend, not to learn again (``learn --extend``).
        Its clauses are kept as they are and come first; the learner is given only the
        positives they do not prove (every negative stays), as Aleph's cover loop does after
        each clause it adds, so the clauses it adds describe what the prior theory misses
        (new kinds of objects in the data) and no prior clause's bounds move.  The
        statistics and domains are measured on every training object, prior clauses
        included; :func:`drop_redundant` never leaves a prior clause out.
    extend_only : sequence of str, optional
        With ``prior``: only these classes are given to the learner; every other class's
        clauses are the prior theory's, as they are (``learn --extend M --extend-only ramp``:
        a part of the data that shows a new kind of ramp adds ramp clauses and no box clause
        learned from its negatives).  None: every class.
    background : Background, optional
        A checked background file of the user's own
        (:func:`planerel.ilp.background.read_background`): its clauses go into every
        ``STEM.b``, the rules may call its predicates, and the model carries it
        (:attr:`Model.background`).

    Returns
    -------
    Model
        Rules per class, with coverage statistics on the training objects.
    """
    from planerel.ilp.aleph_export import PLANEREL_SETTINGS, export_aleph
    from planerel.ilp.learn import LearnerTimeout, learn

    examples = _examples(descs)
    present = {k for _, k in examples}
    missing = [k for k in classes if k not in present]
    if missing:
        raise InputError(f"class {', '.join(missing)} has no example to learn from")
    # one class is enough when objects of class other give its negatives (box against the rest)
    if len(classes) < 2 and not (classes and OTHER in present):
        raise InputError(f"learning needs at least two classes, got {', '.join(classes) or 'none'}")
    tmp = None
    if work_dir is None:
        tmp = temp_dir("learn")
        work_dir = tmp.name
    targets = tuple(classes)
    if other_rules and OTHER not in targets and sum(k == OTHER for _, k in examples) >= 2:
        targets += (OTHER,)
    if extend_only is not None:
        if prior is None:
            raise InputError("extend_only (--extend-only) needs a prior theory to extend "
                             "(--extend MODEL_DIR)")
        unknown = sorted(set(extend_only) - set(targets))
        if unknown or not extend_only:
            raise InputError(f"--extend-only names {', '.join(unknown) or 'no class'}; choose "
                             f"from {', '.join(targets)}")
    learned = tuple(k for k in targets if extend_only is None or k in extend_only)
    try:
        common, per_class = split_class_settings(settings, targets)
        planar = {o.id: o.planar_fraction for d in descs for o in d.objects}
        domain = planar_domain(examples, planar, classes)
        gated = gated_negatives(examples, planar, domain)
        skip = {k: gated.get(k, ()) for k in targets
                if str(per_class.get(k, {}).get("gated_negatives",
                                                 common.get("gated_negatives", "false"))) == "true"}
        # planerel's own settings are acted on here, never handed to a learner
        common = {n: v for n, v in common.items() if n not in PLANEREL_SETTINGS}
        per_class = {k: {n: v for n, v in kv.items() if n not in PLANEREL_SETTINGS}
                     for k, kv in per_class.items()}
        prior = {k: tuple(v) for k, v in (prior or {}).items() if v}
        if OTHER in prior and OTHER not in targets:
            raise InputError("the prior theory has rules for other: extend it with other rules "
                             "too (--other-rules), or they would be lost")
        proved = (_prior_proved(prior, classes, descs, examples, timeout, background)
                  if prior else {})
        # (every class's files: a class's negatives are the other classes' objects)
        export_aleph(descs, work_dir, "all", classes=list(targets), task=task, settings=common,
                     class_settings=per_class, skip_negatives=skip, skip_positives=proved,
                     background=background)
        rules, uncovered, seconds, explored, engines = {}, {}, 0.0, 0, set()

        def one(k):
            say = None if log is None else (lambda text, k=k: log(f"[{k}] {text}"))
            t0 = time.perf_counter()
            try:
                res = learn(Path(work_dir) / k, engine=engine, timeout=timeout, progress=say,
                            settings=per_class.get(k))
            except LearnerTimeout:  # not the temporary folder's name: the class and the option
                raise LearnerTimeout(
                    f"learning the {k} rules timed out after {timeout:g} s and was stopped "
                    "(the time limit of each class's learner: --timeout, or timeout= in "
                    "Python)") from None
            except LearnerError as exc:  # which class failed (ilp90: the demo's "Aleph failed")
                raise LearnerError(f"learning the {k} rules: {exc}") from None
            if log is not None:
                log(f"[{k}] learned {len(res.rules)} clause(s) in {time.perf_counter() - t0:.1f} s")
            return res

        from planerel.batch import resolve_jobs

        n_jobs = max(1, min(resolve_jobs(jobs), len(learned)))
        if n_jobs == 1:
            results = [one(k) for k in learned]
        else:
            from concurrent.futures import ThreadPoolExecutor

            from planerel.children import stop_children, wait_result

            pool = ThreadPoolExecutor(n_jobs)            # each class is its own swipl process
            try:
                futures = [pool.submit(one, k) for k in learned]
                results = [wait_result(fut) for fut in futures]
            except BaseException:  # a failed class, Ctrl-C, SIGTERM: stop the others' learners
                with stop_children():
                    pool.shutdown(wait=True, cancel_futures=True)
                raise
            pool.shutdown()
        for k in targets:  # not given to the learner (extend_only): the prior's clauses
            if k not in learned:
                rules[k] = prior.get(k, ())
                uncovered[k] = sum(c == k for _, c in examples) - len(proved.get(k, ()))
        for k, res in zip(learned, results, strict=True):
            rules[k] = prior.get(k, ()) + tuple(r for r in res.rules if ":-" in r
                                                 and r not in prior.get(k, ()))
            # unit clauses (seeds Aleph keeps as facts when minpos =< 1) and the positives
            # the theory leaves out (seeds without a clause when minpos > 1)
            uncovered[k] = len(res.rules) - len(rules[k]) + res.train.fn
            seconds += res.seconds
            explored += res.clauses_explored or 0
            engines.add(res.engine_detail or res.engine)
        model = Model(tuple(classes), rules, (), "; ".join(sorted(engines)), seconds, explored,
                      uncovered, planar_domain=domain,
                      level_domain=level_domain(examples, horizontal_counts(descs), classes),
                      background=background)
        if not model.clauses():
            return model
        fired = _parse_fired(_prolog_run(model, descs, [o for o, _ in examples], timeout))
        if not keep_redundant:
            fixed = {i for i, k in _index_class(model)
                     if model.clauses()[i - 1] in prior.get(k, ())}
            model, fired = drop_redundant(model, fired, dict(examples), fixed=fixed)
        stats, cofire = _stats_from_fired(model, fired, dict(examples))
        return replace(model, stats=stats, cofire=cofire,
                       proof_domain=proof_domain(fired, dict(examples)),
                       size_domain=size_domain(fired, dict(examples), plane_extents(descs)),
                       slender_domain=slender_domain(fired, dict(examples),
                                                     plane_slenderness(descs)),
                       range_domain=range_domain(fired, dict(examples), plane_ranges(descs)))
    finally:
        if tmp is not None:
            tmp.cleanup()


def prior_rules(model_dir) -> dict:
    """``{class: clauses}`` of a model folder written by :func:`learn_model` (its
    ``metrics.json``), to extend with ``learn_model(prior=...)`` (``planerel learn --extend``).

    Raises
    ------
    InputError
        No such model folder, a members model (several theories: extend one member's
        folder), or a model with no rule.
    """
    import json

    path = Path(model_dir) / "metrics.json"
    try:
        metrics = json.loads(path.read_text(encoding="utf-8"))
    except FileNotFoundError:
        raise InputError(f"--extend {model_dir}: no model folder there (no metrics.json)") from None
    except (OSError, UnicodeDecodeError, json.JSONDecodeError) as exc:
        raise InputError(f"--extend {model_dir}: cannot read {path}: {exc}") from None
    if not isinstance(metrics, dict) or metrics.get("members"):
        raise InputError(f"--extend {model_dir}: a members model holds several theories; "
                         f"extend one member's folder ({model_dir}/members/N)")
    rules = metrics.get("rules")
    if not isinstance(rules, dict) or not any(rules.values()):
        raise InputError(f"--extend {model_dir}: the model has no rule to extend")
    return {str(k): tuple(str(c) for c in v) for k, v in rules.items() if v}


def _prior_proved(prior: dict, classes, descs, examples, timeout: float,
                  background=None) -> dict:
    """``{class: object ids}``: the training positives of each class that ``prior``'s clauses
    of that class prove (:func:`learn_rules`' ``prior``, with its ``background``)."""
    unknown = sorted(set(prior) - set(classes) - {OTHER})
    if unknown:
        raise InputError(f"the prior theory has rules for {', '.join(unknown)}, which the "
                         f"training data has no example of")
    model = Model(tuple(k for k in classes if k in prior), dict(prior), background=background)
    fired = _parse_fired(_prolog_run(model, descs, [o for o, _ in examples], timeout))
    truth = dict(examples)
    class_of = dict(_index_class(model))
    out: dict = {}
    for obj, hits in fired.items():
        for h in hits:
            if truth.get(obj) == class_of[h[1]]:
                out.setdefault(truth[obj], set()).add(obj)
    return out


# ----------------------------------------------------------------------------- logic queries


@dataclass(frozen=True)
class Prediction:
    """The answer of the rules for one object.

    Attributes
    ----------
    object_id : str
    klass : str
        The chosen class, or ``"other"`` (none of the classes, see :func:`choose_class`).
    rule : str or None
        The clause that proved it.
    bindings : dict
        ``{variable name: value}`` of that clause's first proof (plane ids among them).
    fired : tuple
        ``(class, rule index)`` for every rule that proves something about the object.
    precision : float or None
        The chosen rule's Laplace precision on the training objects.
    refused : tuple of Refusal
        Classes whose rules proved the object and that the decision refused there (its planar
        fraction far below their training positives', :func:`planerel.ilp.metrics.decide`).
    votes : tuple of Prediction
        A :class:`Members` model's answer: each member's own prediction, in member order
        (the answer's rule, bindings and refusals are those of :attr:`member`'s); empty for a
        single model.
    member : int or None
        Which member (0-based) the rule and bindings come from (None: a single model).
    """

    object_id: str
    klass: str
    rule: str | None = None
    rule_index: int | None = None
    bindings: dict = field(default_factory=dict)
    fired: tuple = ()
    precision: float | None = None
    refused: tuple = ()
    votes: tuple = ()
    member: int | None = None

    @property
    def planes(self) -> list[str]:
        """The plane ids bound by the rule's variables, in variable order."""
        return [v for v in self.bindings.values() if "_p" in v]


# The goal text is constant: every path reaches swipl as data (argv), never inside a goal; the
# support files come first (the bridge's loading rule, planerel.ilp.prolog).
_PREDICT_GOAL = ("Args = [Facts, Rules, Data|Background], "
                 "planerel_predict_main(Facts, Rules, Data, Background)")


def _prolog_run(model: Model, descs, object_ids: Sequence[str], timeout: float):
    """Run the support predicates + facts + rules in swipl; parse ``@@`` lines."""
    from planerel.features.facts import FactParams, facts_text
    from planerel.features.terms import atom, plist
    from planerel.ilp.aleph_export import PAIRS
    from planerel.ilp.background import BACKGROUND_FILE
    from planerel.ilp.learn import run_process
    from planerel.ilp.prolog import swipl_command, vocabulary_term

    with temp_dir("predict") as tmp:
        facts = Path(tmp) / "facts.pl"
        facts.write_text(facts_text(descs, FactParams(pairs=PAIRS, planner=False)))
        rules = Path(tmp) / "rules.pl"
        rules.write_text(model.text())
        data = Path(tmp) / "objects.pl"
        data.write_text(plist([atom(o) for o in object_ids]) + ".\n" + vocabulary_term() + ".\n")
        background = Path(tmp) / BACKGROUND_FILE
        if model.background is not None:
            background.write_text(model.background.text, encoding="utf-8")
        cmd = swipl_command(_PREDICT_GOAL, [facts, rules, data]
                            + ([background] if model.background is not None else []),
                            flags=("--on-error=status", "--on-warning=status"))
        code, out, err, _ = run_process(cmd, timeout, "the rule query")
    if code == 2:
        errors = [ln[len("error: "):] for ln in err.splitlines() if ln.startswith("error: ")]
        if errors:
            error = errors[0].replace(str(rules), "the model")
            if model.background is not None:
                error = error.replace(str(background), model.background.where)
            raise InputError(error)
    if code != 0:
        raise PrologError(f"the rule query failed: {err.strip()[-600:] or f'exit status {code}'}")
    return out


def _parse_fired(out: str):
    """``{object: [(class, index, bindings, text, scale), ...]}`` from ``@@`` lines (``scale``:
    the proof scale of the ``@@scale`` line after each ``@@fired`` line, m^2, or None)."""
    import re

    result: dict[str, list] = {}
    current = None
    pat = re.compile(r"^@@fired (\S+) (\d+) \[(.*)\] (.*)$")
    for line in out.splitlines():
        if line.startswith("@@object "):
            current = _unquote(line[len("@@object "):])
            result[current] = []
        elif line.startswith("@@fired ") and current is not None:
            m = pat.match(line)
            if not m:
                continue
            klass, index, binds, text = m.groups()
            pairs = {}
            for item in _split_top(binds):
                name, _, value = item.partition("-")
                pairs[_unquote(name)] = _unquote(value)
            result[current].append((_unquote(klass), int(index), pairs, _unquote(text), None))
        elif line.startswith("@@scale ") and current is not None and result[current]:
            value = line[len("@@scale "):].strip()
            try:
                scale = float(value)
            except ValueError:       # "none": no proof binds a plane with an area
                continue
            hit = result[current][-1]
            result[current][-1] = (*hit[:4], scale)
    return result


def _split_top(text: str) -> list[str]:
    """Split a Prolog list body on top-level commas (quotes respected)."""
    items, buf, quote, depth, i = [], [], False, 0, 0
    while i < len(text):
        ch = text[i]
        if quote:
            buf.append(ch)
            if ch == "\\" and i + 1 < len(text):
                buf.append(text[i + 1])
                i += 1
            elif ch == "'":
                quote = False
        elif ch == "'":
            quote = True
            buf.append(ch)
        elif ch in "([":
            depth += 1
            buf.append(ch)
        elif ch in ")]":
            depth -= 1
            buf.append(ch)
        elif ch == "," and depth == 0:
            items.append("".join(buf))
            buf = []
        else:
            buf.append(ch)
        i += 1
    if buf:
        items.append("".join(buf))
    return [s.strip() for s in items if s.strip()]


def _unquote(text: str) -> str:
    text = text.strip()
    if len(text) >= 2 and text[0] == "'" and text[-1] == "'":
        body = text[1:-1]
        out, i = [], 0
        simple = {"n": "\n", "t": "\t", "\\": "\\", "'": "'", "r": "\r"}
        while i < len(body):
            ch = body[i]
            if ch == "\\" and i + 1 < len(body):
                nxt = body[i + 1]
                if nxt in simple:
                    out.append(simple[nxt])
                    i += 2
                    continue
                if nxt == "x":
                    end = body.index("\\", i + 2)
                    out.append(chr(int(body[i + 2:end], 16)))
                    i = end + 1
                    continue
            if ch == "'" and i + 1 < len(body) and body[i + 1] == "'":
                out.append("'")
                i += 2
                continue
            out.append(ch)
            i += 1
        return "".join(out)
    return text


def rule_stats(model: Model, descs, *, timeout: float = 120.0) -> tuple:
    """``(index, class, tp, fp)`` of every clause of ``model`` on the objects of ``descs``."""
    return training_stats(model, descs, timeout=timeout)[0]


def training_stats(model: Model, descs, *, timeout: float = 120.0) -> tuple[tuple, tuple]:
    """:func:`rule_stats` and the :attr:`Model.cofire` rows, from one rule query."""
    examples = _examples(descs)
    if not model.clauses():
        return (), ()
    fired = _parse_fired(_prolog_run(model, descs, [o for o, _ in examples], timeout))
    return _stats_from_fired(model, fired, dict(examples))


def _index_class(model: Model) -> list[tuple[int, str]]:
    """``(index, class)`` of every clause, numbered from 1 in :meth:`Model.clauses` order."""
    return [(i + 1, k) for i, k in enumerate(k for k in model.targets
                                             for _ in model.rules.get(k, ()))]


def _stats_from_fired(model: Model, fired: dict, truth: dict) -> tuple[tuple, tuple]:
    """Rule statistics and co-fire rows from the rules each object fired (:func:`_parse_fired`)
    and ``truth`` (``{object: class}``)."""
    index_class = _index_class(model)
    class_of = dict(index_class)
    counts = {i: [0, 0] for i, _ in index_class}
    together: dict = {}
    for obj, hits in fired.items():
        idx = sorted({h[1] for h in hits})
        for i in idx:
            counts[i][0 if truth.get(obj) == class_of[i] else 1] += 1
        if truth.get(obj) is None:
            continue
        for a_pos, a in enumerate(idx):
            for b in idx[a_pos + 1:]:
                if class_of[a] != class_of[b]:
                    key = (a, b, truth[obj])
                    together[key] = together.get(key, 0) + 1
    stats = tuple((i, k, counts[i][0], counts[i][1]) for i, k in index_class)
    return stats, tuple((a, b, k, n) for (a, b, k), n in sorted(together.items()))


def drop_redundant(model: Model, fired: dict, truth: dict, fixed=()) -> tuple[Model, dict]:
    """Leave out the clauses that add only false positives on the training objects.

    Aleph's cover loop adds clauses one after another and never looks back: a later, more
    general clause can prove every positive an earlier one proved, and the earlier one then
    adds nothing but the objects of other classes it proves (the demo's ``ramp(A) :-
    has_plane(A,B), above(B,C), plane_width(B,D), gteq(D,0.734)``: 22 ramps, all also proved by
    the inclined-plane clause, and 4 other objects; on a real office cloud it called two wall
    pieces a ramp).  Rule: while some clause proves no training object of its class that the
    other remaining clauses of the class do not also prove, and proves at least one object of
    another class, the one of them with the most such false positives (ties: the later clause)
    is left out.  A redundant clause with no false positive stays (it costs nothing).

    Parameters
    ----------
    model : Model
        Without statistics (they are measured again on what is kept).
    fired : dict
        ``{object: [(class, index, bindings, text), ...]}`` on the training objects
        (:func:`_parse_fired`), indices of ``model``'s clauses.
    truth : dict
        ``{object: class}`` of the training objects (``other`` included).
    fixed : collection of int
        Clause indices never left out (a prior theory's, :func:`learn_rules`).

    Returns
    -------
    (Model, dict)
        The model without the clauses left out (recorded in :attr:`Model.dropped`), and
        ``fired`` renumbered to its clauses.
    """
    index_class = _index_class(model)
    class_of = dict(index_class)
    text_of = dict(zip((i for i, _ in index_class), model.clauses(), strict=True))
    proves: dict = {i: (set(), set()) for i, _ in index_class}   # (true, false) positives
    for obj, hits in fired.items():
        for i in {h[1] for h in hits}:
            proves[i][0 if truth.get(obj) == class_of[i] else 1].add(obj)
    keep = [i for i, _ in index_class]
    dropped = []
    while True:
        worst = None
        for i in keep:
            tp, fp = proves[i]
            if not fp or i in fixed:
                continue
            others = set().union(*(proves[j][0] for j in keep if j != i and class_of[j] == class_of[i]))
            if tp <= others and (worst is None or len(fp) >= len(proves[worst][1])):
                worst = i
        if worst is None:
            break
        keep.remove(worst)
        dropped.append(worst)
    if not dropped:
        return model, fired
    new_index = {old: new for new, old in enumerate(keep, start=1)}
    rules = {k: tuple(text_of[i] for i in keep if class_of[i] == k) for k in model.rules}
    gone = tuple((class_of[i], text_of[i], len(proves[i][0]), len(proves[i][1]))
                 for i in sorted(dropped))
    renumbered = {obj: [(h[0], new_index[h[1]], *h[2:]) for h in hits if h[1] in new_index]
                  for obj, hits in fired.items()}
    return replace(model, rules=rules, dropped=model.dropped + gone), renumbered


def prolog_predict(model: Model, descs, object_ids: Sequence[str] | None = None, *,
                   timeout: float = 120.0) -> list[Prediction]:
    """Classify objects by logic query: which rules of ``model`` prove which class.

    Parameters
    ----------
    model : Model
    descs : list of SceneDescription
        The scenes the objects belong to (their facts are loaded).
    object_ids : sequence of str, optional
        Objects to classify (default: every object of ``descs``).

    Returns
    -------
    list of Prediction, in the order of ``object_ids``.

    A :class:`Members` model: each member answers as a model of its own, then the members
    vote (:func:`planerel.ilp.members.vote`; :attr:`Prediction.votes` holds each member's).
    """
    if object_ids is None:
        object_ids = [o.id for d in descs for o in d.objects]
    object_ids = list(object_ids)
    if not object_ids:
        return []
    if isinstance(model, Members):
        return _voted([prolog_predict(m, descs, object_ids, timeout=timeout)
                       for m in model.models])
    if not model.clauses():
        return [Prediction(o, OTHER) for o in object_ids]
    from planerel.features.step_chains import flight_evidence, flight_faces

    fired = _parse_fired(_prolog_run(model, descs, object_ids, timeout))
    flight_test = functools.partial(flight_evidence, fragments=model.flight_fragments)
    planar = {o.id: o.planar_fraction for d in descs for o in d.objects}
    levels = horizontal_counts(descs)
    where = {o.id: (d, o) for d in descs for o in d.objects}
    extents = plane_extents(descs) if model.size_gate and model.size_domain else None
    slender = (plane_slenderness(descs) if model.slender_gate and model.slender_domain
               else None)
    distances = plane_ranges(descs) if model.range_gate and model.range_domain else None
    out = []
    for o in object_ids:
        hits = fired.get(o, [])
        best, refused = decide(hits, model.stats, model.classes, model.cofire,
                               planar_fraction=planar.get(o),
                               domain=model.planar_domain if model.planar_gate else (),
                               margin=model.planar_margin,
                               proofs=model.proof_domain if model.proof_gate else (),
                               proof_margin=model.proof_margin,
                               proof_min_positives=model.proof_min_positives,
                               veto_ratio=model.veto_ratio,
                               n_horizontal=levels.get(o),
                               levels=model.level_domain if model.level_gate else (),
                               stepped=lambda o=o: object_shows(flight_faces, where, o),
                               flight=(lambda o=o: object_shows(flight_test, where, o))
                               if model.flight_gate else None,
                               extents=extents,
                               sizes=(size_gated(model.size_domain, model.size_classes)
                                      if model.size_gate else ()),
                               size_margin=model.size_margin,
                               slender=slender,
                               slenders=(size_gated(model.slender_domain, model.slender_classes)
                                         if model.slender_gate else ()),
                               slender_margin=model.slender_margin,
                               distances=distances,
                               ranges=(size_gated(model.range_domain, model.range_classes)
                                       if model.range_gate else ()),
                               range_margin=model.range_margin)
        fired_pairs = tuple(sorted({(h[0], h[1]) for h in hits}, key=lambda t: t[1]))
        if best is None:
            out.append(Prediction(o, OTHER, fired=fired_pairs, refused=refused))
        else:
            klass, index, binds, text = best[:4]
            tp_fp = {i: (tp, fp) for i, _, tp, fp in model.stats}.get(index, (0, 0))
            out.append(Prediction(o, klass, text, index, binds, fired_pairs, laplace(*tp_fp),
                                  refused))
    return out


def _voted(per_member: list[list[Prediction]]) -> list[Prediction]:
    """The members' predictions (one list per member, objects in the same order) joined by
    the vote; ``fired`` names rules as ``(member, index)``, as :attr:`Members.stats` does."""
    from planerel.ilp.members import vote

    out = []
    for preds in zip(*per_member, strict=True):
        klass, n = vote([(p.klass, p.precision if p.rule else None) for p in preds])
        c = preds[n]
        fired = tuple((k, (m, i)) for m, p in enumerate(preds) for k, i in p.fired)
        out.append(Prediction(c.object_id, klass, c.rule, c.rule_index, dict(c.bindings), fired,
                              c.precision, c.refused, votes=tuple(preds), member=n))
    return out


def learn_members(descs, classes: Sequence[str], parts: dict, members: int, *,
                  work_dir=None, jobs: int | None = None, log=None, **kw) -> Members:
    """One theory per part of the scenes (:func:`learn_rules` on each, ``kw`` passed on).

    Parameters
    ----------
    parts : dict
        ``{scene id: part}`` (:func:`planerel.ilp.members.partition_scenes`), parts
        ``0 .. members - 1``.
    work_dir : path, optional
        Member ``n``'s Aleph files go to ``work_dir/n/aleph`` (``n`` from 1); default a
        temporary folder.
    jobs : int, optional
        Members learned at once (None: as many as cores), each one ``swipl`` at a time; the
        model does not depend on it.
    log : callable, optional
        Progress lines, ``[member n/K] ...``.
    """
    groups: list[list] = [[] for _ in range(members)]
    for d in descs:
        if d.scene_id not in parts:
            raise InputError(f"scene {d.scene_id} has no part")
        groups[parts[d.scene_id]].append(d)

    def one(n: int) -> Model:
        say = None if log is None else (lambda text, n=n: log(f"[member {n + 1}/{members}] {text}"))
        if say is not None:
            say(f"learning on {len(groups[n])} scenes")
        t0 = time.perf_counter()
        folder = None if work_dir is None else Path(work_dir) / str(n + 1) / "aleph"
        m = learn_rules(groups[n], classes, work_dir=folder, jobs=1, log=say, **kw)
        if say is not None:
            say(f"learned {len(m.clauses())} clause(s) in {time.perf_counter() - t0:.1f} s")
        return m

    from planerel.batch import resolve_jobs

    n_jobs = max(1, min(resolve_jobs(jobs), members))
    if n_jobs == 1:
        return Members(tuple(one(n) for n in range(members)))
    from concurrent.futures import ThreadPoolExecutor

    from planerel.children import stop_children, wait_result

    pool = ThreadPoolExecutor(n_jobs)      # each member's learners are swipl processes
    try:
        futures = [pool.submit(one, n) for n in range(members)]
        models = tuple(wait_result(f) for f in futures)
    except BaseException:  # a failed member, Ctrl-C, SIGTERM: stop the others' learners
        with stop_children():
            pool.shutdown(wait=True, cancel_futures=True)
        raise
    pool.shutdown()
    return Members(models)


def cross_validate(descs, classes: Sequence[str], *, folds: int = 10, seed: int = 0,
                   engine: str = "builtin", timeout: float = 120.0, settings: dict | None = None,
                   progress: bool | None = None, jobs: int | None = 1,
                   task: str | None = None, other_rules: bool = False,
                   keep_redundant: bool = False, decision: dict | None = None,
                   background=None) -> dict:
    """Stratified k-fold cross-validation of the whole learner on described scenes.

    Objects of class ``other`` (none of the classes) are split into the folds too: in training
    they are negatives for every class; in testing the right answer for them is ``other``.
    They are counted apart (``other``) so that ``accuracy`` and ``confusion`` keep their meaning.

    Returns
    -------
    dict
        ``accuracy``, ``per_class``, ``classes``, ``confusion`` (rows true class, columns
        predicted with ``other`` last), ``folds`` (per fold: test objects, predictions,
        rules, accuracy, seconds), ``predictions`` ({object: class}); with ``other`` objects
        also ``other`` ({n, rejected: share predicted ``other``, predicted: {class: n}}) and
        ``open_set_accuracy`` (all objects, ``other`` right when predicted ``other``).

    ``jobs`` folds run at once (None: all cores); the result does not depend on it.
    ``other_rules``, ``keep_redundant``, ``background``: as in :func:`learn_rules` (in each
    fold);
    ``decision``: decision settings each fold's model answers with (:func:`with_decision`).
    """
    from planerel.ilp.aleph_export import OTHER

    all_examples = [(o, k) for o, k in _examples(descs) if k in classes or k == OTHER]
    examples = [(o, k) for o, k in all_examples if k in classes]
    if not examples:
        raise InputError("no example objects of the requested classes")
    labels = [k for _, k in all_examples]
    fold_of = stratified_folds(labels, folds, seed)
    truth_of = dict(all_examples)
    scene_of = {o.id: d for d in descs for o in d.objects}
    predictions: dict[str, str] = {}

    def run_fold(f: int) -> dict:
        test = [o for (o, _), g in zip(all_examples, fold_of, strict=True) if g == f]
        test_set = set(test)
        train_descs = []
        for d in descs:
            keep = tuple(o for o in d.objects if o.id not in test_set)
            if keep:
                train_descs.append(replace(d, objects=keep))
        present = [k for k in classes if any(o.klass == k for d in train_descs for o in d.objects)]
        t0 = time.perf_counter()
        model = learn_rules(train_descs, present, engine=engine, timeout=timeout, settings=settings,
                            jobs=1, task=task, other_rules=other_rules,
                            keep_redundant=keep_redundant, background=background)
        model = with_decision(model, decision)
        test_descs = list({id(scene_of[o]): scene_of[o] for o in test}.values())
        preds = prolog_predict(model, test_descs, test, timeout=timeout)
        scored = [(truth_of[p.object_id], p.klass) for p in preds if truth_of[p.object_id] != OTHER]
        acc, _ = accuracy_scores([t for t, _ in scored], [q for _, q in scored], classes)
        return {"fold": f, "test": test, "predicted": [p.klass for p in preds],
                "accuracy": acc, "rules": model.clauses(),
                "seconds": round(time.perf_counter() - t0, 3),
                "_answers": [(p.object_id, p.klass) for p in preds]}

    # Folds are independent; each one's work is in SWI-Prolog child processes, so threads
    # run them in parallel.  Reports come back in fold order whatever the number of jobs.
    from planerel.batch import resolve_jobs

    n_jobs = max(1, min(resolve_jobs(jobs), folds))
    show = progress or (progress is None and sys.stderr.isatty())
    bar = None
    if show:
        from tqdm import tqdm

        bar = tqdm(total=folds, desc="folds", unit="fold", leave=False)
    try:
        if n_jobs == 1:
            fold_reports = []
            for f in range(folds):
                fold_reports.append(run_fold(f))
                if bar is not None:
                    bar.update(1)
        else:
            from concurrent.futures import ThreadPoolExecutor

            from planerel.children import stop_children, wait_result

            pool = ThreadPoolExecutor(n_jobs)
            try:
                futures = [pool.submit(run_fold, f) for f in range(folds)]
                fold_reports = []
                for fut in futures:
                    fold_reports.append(wait_result(fut))
                    if bar is not None:
                        bar.update(1)
            except BaseException:  # a failed fold, Ctrl-C, SIGTERM: stop the others' learners
                with stop_children():
                    pool.shutdown(wait=True, cancel_futures=True)
                raise
            pool.shutdown()
    finally:
        if bar is not None:
            bar.close()
    for rep in fold_reports:
        predictions.update(rep.pop("_answers"))
    out = score_objects(all_examples, predictions, classes)
    out.update(folds=fold_reports, predictions=predictions, k=folds, seed=seed,
               excluded=excluded_counts(descs))
    return out


def held_out_scores(model: Model | Members, dataset_dir, *, method: str = "regiongrow",
                    seg_params: dict | None = None, jobs: int | None = 1, cache=None,
                    progress: bool | None = None, timeout: float = 120.0,
                    scheduler=None) -> dict:
    """Accuracy of ``model`` on another data set (a held-out set: another seed, other world
    parameters), object by object, scored like :func:`cross_validate`: the set's ground-truth
    objects, each made of the segmented planes that mostly cover it
    (:func:`planerel.features.dataset.describe_truth_scene`), answered by the model's rules.

    Returns
    -------
    dict
        :func:`score_objects`' scores plus ``dataset``, ``n_scenes``, ``skipped``,
        ``predictions``, ``excluded`` (:func:`excluded_counts`: objects that are no example,
        by class and reason) and ``errors`` (:func:`~planerel.ilp.metrics.error_kinds`: the
        wrong answers split into lost decisions and objects the rules do not prove).

    A :class:`Members` model answers by its members' vote; ``errors`` then looks at the rules
    of every member.
    """
    descs, skipped = describe_scenes(dataset_dir, method=method, seg_params=seg_params,
                                     jobs=jobs, cache=cache, progress=progress,
                                     scheduler=scheduler)
    examples = heldout_examples(descs, model.classes, dataset_dir)
    preds = prolog_predict(model, descs, [o for o, _ in examples], timeout=timeout)
    return heldout_figures(descs, skipped, dataset_dir, model.classes, examples,
                           {p.object_id: p.klass for p in preds},
                           {p.object_id: p.fired for p in preds}, model.stats)


def heldout_examples(descs, classes, dataset_dir) -> list:
    """``(object id, class)`` of the held-out set's objects of ``classes`` or of class other.

    Raises
    ------
    InputError
        There is none.
    """
    examples = [(o, k) for o, k in _examples(descs) if k in classes or k == OTHER]
    if not examples:
        raise InputError(f"{dataset_dir}: the held-out set has no object of the model's classes "
                         f"({', '.join(classes)}) or of class other")
    return examples


def heldout_figures(descs, skipped, dataset_dir, classes, examples, predictions: dict,
                    fired: dict, stats) -> dict:
    """:func:`held_out_scores`' dict from the answers: :func:`score_objects`' figures plus
    ``dataset``, ``n_scenes``, ``skipped``, ``predictions``, ``excluded`` and ``errors``
    (``fired``: ``{object: ((class, rule), ...)}``, rules named as in ``stats``)."""
    out = score_objects(examples, predictions, classes)
    out.update(dataset=str(dataset_dir), n_scenes=len(descs), skipped=skipped,
               predictions=predictions, excluded=excluded_counts(descs),
               errors=error_kinds(examples, predictions, fired, stats))
    return out


def _classes_arg(classes, descs) -> tuple:
    from planerel.ilp.aleph_export import OTHER

    present = [k for k in DEFAULT_CLASSES if any(o.klass == k for d in descs for o in d.objects)]
    present += sorted({o.klass for d in descs for o in d.objects if o.klass} - set(present)
                      - {OTHER})
    if classes is None:
        classes = present
    classes = tuple(classes)
    missing = [k for k in classes if k not in present]
    if missing:
        raise InputError(f"class {', '.join(missing)} has no example in the data set "
                         f"(classes present: {', '.join(present) or 'none'})")
    n_other = sum(1 for d in descs for o in d.objects if o.klass == OTHER)
    if len(classes) < 2 and not (classes and n_other):
        raise InputError(f"learning needs at least two classes, or one and objects of class "
                         f"{OTHER!r} (its negatives); the data set has "
                         f"{', '.join(classes) or 'none'}")
    return classes


def evaluate_learning(dataset_dir, *, method: str = "regiongrow", seg_params: dict | None = None,
                      folds: int = 10, seed: int = 0, engine: str = "builtin",
                      timeout: float = 120.0, jobs: int | None = 1, classes=None,
                      cache=None, progress: bool | None = None) -> dict:
    """Cross-validated accuracy of rules learned from one segmentation method's planes, and
    the rules learned on all data (used by the report to compare SP / SNP / region growing).

    Returns
    -------
    dict
        The :func:`cross_validate` result plus ``rules`` (list of clause strings of the model
        trained on all data), ``method`` and ``skipped``.
    """
    descs, skipped = describe_scenes(dataset_dir, classes=classes, method=method,
                                     seg_params=seg_params, jobs=jobs, cache=cache,
                                     progress=progress)
    classes = _classes_arg(classes, descs)
    cv = cross_validate(descs, classes, folds=folds, seed=seed, engine=engine, timeout=timeout,
                        progress=progress, jobs=jobs)
    model = learn_rules(descs, classes, engine=engine, timeout=timeout)
    cv.update(rules=model.clauses(), method=method, skipped=skipped)
    return cv


# ----------------------------------------------------------------------------- model folder


def draw_confusion(path, confusion, classes, *, title: str = "") -> Path:
    """Write a confusion matrix as a PNG (rows: true class; columns: predicted)."""
    from PIL import Image, ImageDraw

    from planerel.atomic import atomic_path

    cols = confusion_columns(classes)
    cell, left, top = 70, 90, 60
    w, h = left + cell * len(cols) + 10, top + cell * len(classes) + 30
    img = Image.new("RGB", (w, h), "white")
    d = ImageDraw.Draw(img)
    d.text((10, 8), title or "confusion (rows: true, columns: predicted)", fill="black")
    total = max(1, max(sum(r) for r in confusion))
    for j, c in enumerate(cols):
        d.text((left + j * cell + 6, top - 18), c, fill="black")
    for i, r in enumerate(confusion):
        d.text((8, top + i * cell + cell // 2 - 6), classes[i], fill="black")
        for j, v in enumerate(r):
            shade = int(255 - 200 * v / total)
            colour = (shade, shade, 255) if cols[j] == classes[i] else (255, shade, shade)
            x0, y0 = left + j * cell, top + i * cell
            d.rectangle([x0, y0, x0 + cell - 2, y0 + cell - 2], fill=colour, outline="grey")
            d.text((x0 + cell // 2 - 6, y0 + cell // 2 - 6), str(v), fill="black")
    with atomic_path(path, suffix=".png") as tmp:
        img.save(tmp, format="PNG")
    return Path(path)


def learn_model(dataset_dir, out_dir, *, classes=None, engine: str = "auto", folds: int = 0,
                seed: int = 0, timeout: float = 120.0, jobs: int | None = None,
                method: str = "regiongrow", seg_params: dict | None = None, cache=None,
                progress: bool | None = None, log=print, scheduler=None,
                heldout=None, settings: dict | None = None, task: str | None = None,
                other_rules: bool = False, keep_redundant: bool = False,
                recipe: str | None = None, members: int = 1, prior: dict | None = None,
                extend_only: Sequence[str] | None = None, background=None) -> dict:
    """``planerel learn``: describe a data set, learn the class rules, optionally cross-validate,
    score the model on a held-out data set (``heldout``: :func:`held_out_scores`, in
    ``metrics["heldout"]``), and write a model folder.

    ``jobs`` worker processes describe the scenes (or the Dask ``scheduler``'s workers), and
    ``jobs`` cross-validation folds run at once; the result does not depend on either.
    ``settings`` (Aleph ``set/2`` values), ``task`` (a task file), ``other_rules`` and
    ``keep_redundant``, ``prior`` (a theory to extend) and ``extend_only`` (the classes it
    extends) go to :func:`learn_rules`.  ``recipe`` names a
    :mod:`planerel.ilp.recipes` entry (a task, settings and ``other_rules`` measured together);
    a task or setting given explicitly replaces the recipe's.  ``background`` (a path): a
    background file of the user's own, checked before any scene is described
    (:func:`planerel.ilp.background.read_background`); the task's ``modeb`` may name its
    predicates, the learners get its clauses, and the model folder carries a copy
    (``background.pl``, named with its SHA-256 in ``model.json``).

    The folder is built in a temporary sibling and renamed into place when complete, so a run
    that fails or is interrupted never leaves a half-written model.  It holds ``rules.pl``
    (loadable with ``prolog/compare.pl`` and ``prolog/derived.pl``), ``model.json`` (the
    segmentation, gravity and description settings it was learned with and the rules'
    precision, :mod:`planerel.ilp.model_settings`; ``classify`` reuses them), ``aleph/`` (the files
    the final model was learned from), ``metrics.json`` and, with folds, ``confusion.png``.

    ``members`` > 1 (``planerel learn --members K``): the scenes are described once and split
    into ``members`` disjoint parts, stratified by each scene's class in the manifest
    (:func:`planerel.ilp.members.partition_scenes`); one theory is learned per part
    (:func:`learn_members`, ``jobs`` parts at once) and written as a model folder of its own,
    ``members/N/``; the top-level ``model.json`` names the members and the vote, ``rules.pl``
    holds every member's rules for a reader (:meth:`Members.text`).  Cross-validation is
    refused with members (score a held-out set instead).

    Returns
    -------
    dict
        The metrics written to ``metrics.json``.
    """
    from planerel.atomic import atomic_dir, check_dir_target
    from planerel.ilp.recipes import apply_recipe, recipe_decision
    from planerel.io.writers import write_json

    out = Path(out_dir)
    task, settings, other_rules = apply_recipe(recipe, task=task, settings=settings,
                                               other_rules=other_rules)
    decision = recipe_decision(recipe)
    settings = settings or None
    # what would fail at the end fails first: the task, the settings, the model folder, the
    # held-out set
    from planerel.ilp.aleph_export import check_setting, check_task_vocabulary
    from planerel.ilp.learn import check_engine, check_timeout

    check_timeout(timeout)
    check_engine(engine)
    if background is not None:
        from planerel.ilp.background import read_background

        background = read_background(background, timeout=timeout)
    check_task_vocabulary(task, background)
    for name, value in (settings or {}).items():
        check_setting(name.rpartition(":")[2], value)
    check_dir_target(out, markers=("rules.pl", "metrics.json"))
    if heldout is not None:
        from planerel.features.dataset import load_manifest

        load_manifest(heldout)
    if prior is not None and (members > 1 or folds):
        raise InputError("extending a theory (--extend) learns one theory on the whole data set: "
                         "no --members, no --folds (the prior theory has seen every fold; "
                         "score a --heldout set instead)")
    if extend_only is not None and prior is None:  # (before the scenes are described)
        raise InputError("extend_only (--extend-only) needs a prior theory to extend "
                         "(--extend MODEL_DIR)")
    parts = _member_parts(dataset_dir, classes, members, folds)
    t0 = time.perf_counter()
    descs, skipped = describe_scenes(dataset_dir, classes=classes, method=method,
                                     seg_params=seg_params, jobs=jobs, cache=cache,
                                     progress=progress, scheduler=scheduler)
    classes = _classes_arg(classes, descs)
    t_describe = time.perf_counter() - t0
    for s in skipped:
        log(f"note: {s}")
    if parts is not None:
        return _learn_members_model(
            descs, classes, parts, members, out, dataset_dir=dataset_dir, method=method,
            seg_params=seg_params, seed=seed, settings=settings, task=task, recipe=recipe,
            other_rules=other_rules, keep_redundant=keep_redundant, engine=engine,
            timeout=timeout, jobs=jobs, cache=cache, progress=progress, log=log,
            scheduler=scheduler, heldout=heldout, skipped=skipped, t_describe=t_describe,
            decision=decision, background=background)
    with atomic_dir(out, markers=("rules.pl", "metrics.json")) as tmp:
        metrics: dict = {**_metrics_head(dataset_dir, classes, method, seg_params, seed,
                                         settings, task, recipe, other_rules, decision),
                         **_example_counts(descs, classes),
                         "skipped": skipped, "seconds": {"describe": round(t_describe, 3)}}
        if background is not None:
            metrics["background"] = background.where
        if folds:
            t1 = time.perf_counter()
            cv = cross_validate(descs, classes, folds=folds, seed=seed, engine=engine,
                                timeout=timeout, progress=progress, jobs=jobs,
                                settings=settings, task=task, other_rules=other_rules,
                                keep_redundant=keep_redundant, decision=decision,
                                background=background)
            metrics["cross_validation"] = cv
            metrics["seconds"]["cross_validation"] = round(time.perf_counter() - t1, 3)
            draw_confusion(tmp / "confusion.png", cv["confusion"], list(classes),
                           title=f"{folds}-fold cross-validation, accuracy {cv['accuracy']:.3f}")
        t2 = time.perf_counter()
        model = learn_rules(descs, classes, engine=engine, timeout=timeout, work_dir=tmp / "aleph",
                            jobs=jobs, log=None if progress is False else log,
                            settings=settings, task=task, other_rules=other_rules,
                            keep_redundant=keep_redundant, prior=prior, extend_only=extend_only,
                            background=background)
        model = with_decision(model, decision)
        metrics["seconds"]["learn"] = round(time.perf_counter() - t2, 3)
        if not any(model.rules.get(k) for k in classes):
            # classify refuses a model without a class rule: say so now, and write nothing
            raise InputError(f"no class learned a rule from {dataset_dir} ({len(descs)} scenes, "
                             f"classes {', '.join(classes)}); no model written (classify "
                             "refuses a model without rules); give more scenes of each class "
                             "or looser learner settings (--set)")
        if prior is not None:
            metrics["prior_rules"] = {k: list(v) for k, v in prior.items()}
        metrics["engine"] = model.engine
        metrics["rules"] = {k: list(v) for k, v in model.rules.items()}
        metrics["rule_stats"] = [list(s) for s in model.stats]
        metrics["uncovered"] = model.uncovered
        metrics["dropped_redundant"] = [list(d) for d in model.dropped]
        if heldout is not None:
            _score_heldout(metrics, model, heldout, method=method, seg_params=seg_params,
                           jobs=jobs, cache=cache, progress=progress, timeout=timeout,
                           scheduler=scheduler)
        header = (f"learned by planerel from {dataset_dir} ({len(descs)} scenes, "
                  f"segmentation: {method}, engine: {model.engine})"
                  + (f"\nextending a prior theory of {sum(len(v) for v in prior.values())} "
                     f"clause(s), kept first and unchanged (the clauses that theory's own "
                     f"learning left out are listed in its rules.pl)" if prior else ""))
        _write_model(tmp, model, method=method, seg_params=seg_params, header=header,
                     decision=decision)
        write_json(tmp / "metrics.json", metrics)
    return metrics


def _score_heldout(metrics: dict, model, heldout, **kw) -> None:
    """``metrics["heldout"]``: :func:`held_out_scores` of ``model`` on ``heldout`` (``kw``
    its keywords), and the seconds it took in ``metrics["seconds"]["heldout"]``."""
    t0 = time.perf_counter()
    metrics["heldout"] = held_out_scores(model, heldout, **kw)
    metrics["seconds"]["heldout"] = round(time.perf_counter() - t0, 3)


def _member_parts(dataset_dir, classes, members, folds) -> dict | None:
    """``{scene id: part}`` for ``members`` > 1 (None for a single model), from the
    manifest, before any scene is described; a bad ``members`` is refused here."""
    from planerel.ilp.members import check_members, partition_scenes

    if members == 1 and not isinstance(members, bool):
        return None
    if isinstance(members, int) and not isinstance(members, bool) and members > 1 and folds:
        raise InputError(f"--members {members} with --folds: cross-validation of a members "
                         "model is not supported; score it on a held-out set (--heldout)")
    from planerel.features.dataset import load_manifest

    # a scene of a class not learned is one of class other (describe_scenes)
    rows = [(r.scene_id, r.klass if classes is None or r.klass in classes else OTHER)
            for r in load_manifest(dataset_dir)]
    counts: dict[str, int] = {}
    for _sid, k in rows:
        if k != OTHER:
            counts[k] = counts.get(k, 0) + 1
    check_members(members, counts)
    return partition_scenes(rows, members)


def write_members(folder, model: Members, *, method: str, seg_params, header: str = "",
                  member_metrics: Sequence[dict] | None = None,
                  decision: dict | None = None) -> None:
    """Write a members model folder into ``folder`` (which exists): ``members/N/`` (each a
    model folder: ``rules.pl``, ``background.pl`` when learned with one, ``model.json``,
    ``metrics.json`` when ``member_metrics`` gives it), the top-level ``rules.pl`` (:meth:`Members.text`) and ``model.json`` (the
    settings, the member folders and the vote)."""
    from planerel.atomic import write_text
    from planerel.ilp.members import VOTE_RULE
    from planerel.ilp.model_settings import MODEL_FILE, training_settings
    from planerel.io.writers import write_json

    folder = Path(folder)
    k = len(model.models)
    for n, m in enumerate(model.models, start=1):
        sub = folder / "members" / str(n)
        sub.mkdir(parents=True, exist_ok=True)
        _write_model(sub, m, method=method, seg_params=seg_params, decision=decision,
                     header=f"member {n} of {k}" + (f"; {header}" if header else ""))
        if member_metrics is not None:
            write_json(sub / "metrics.json", member_metrics[n - 1])
    write_text(folder / "rules.pl", model.text(header))
    top = training_settings(method, seg_params, decision=decision)
    top["members"] = [f"members/{n}" for n in range(1, k + 1)]
    top["vote"] = VOTE_RULE
    write_json(folder / MODEL_FILE, top)


def _write_model(folder: Path, model: Model, *, method: str, seg_params, header: str,
                 decision: dict | None) -> None:
    """One model's files in ``folder``: ``rules.pl``, its background file when it has one
    (:data:`planerel.ilp.background.BACKGROUND_FILE`) and ``model.json``, each written
    atomically."""
    from planerel.atomic import write_bytes, write_text
    from planerel.ilp.background import BACKGROUND_FILE
    from planerel.ilp.model_settings import MODEL_FILE, training_settings
    from planerel.io.writers import write_json

    write_text(folder / "rules.pl", model.text(header))
    entry = None
    if model.background is not None:
        write_bytes(folder / BACKGROUND_FILE, model.background.text.encode("utf-8"))
        entry = {"file": BACKGROUND_FILE, "sha256": model.background.sha256}
    write_json(folder / MODEL_FILE, training_settings(method, seg_params, rule_stats=model.stats,
                                                      planar_domain=model.planar_domain,
                                                      proof_domain=model.proof_domain,
                                                      level_domain=model.level_domain,
                                                      size_domain=model.size_domain,
                                                      slender_domain=model.slender_domain,
                                                      range_domain=model.range_domain,
                                                      decision=decision, background=entry))


def _learn_members_model(descs, classes, parts, members, out, *, dataset_dir, method, seg_params,
                         seed, settings, task, recipe, other_rules, keep_redundant, engine,
                         timeout, jobs, cache, progress, log, scheduler, heldout, skipped,
                         t_describe, decision=None, background=None) -> dict:
    """:func:`learn_model` with ``members`` > 1: the members model folder."""
    from planerel.atomic import atomic_dir
    from planerel.ilp.members import VOTE_RULE
    from planerel.io.writers import write_json

    with atomic_dir(out, markers=("rules.pl", "metrics.json")) as tmp:
        t2 = time.perf_counter()
        model = learn_members(descs, classes, parts, members, work_dir=tmp / "members",
                              jobs=jobs, log=None if progress is False else log, engine=engine,
                              timeout=timeout, settings=settings, task=task,
                              other_rules=other_rules, keep_redundant=keep_redundant,
                              background=background)
        model = with_decision(model, decision)
        t_learn = round(time.perf_counter() - t2, 3)
        per_member, member_metrics = [], []
        for n, m in enumerate(model.models, start=1):
            part = [d for d in descs if parts[d.scene_id] == n - 1]
            ex = _examples(part)
            mm = {"dataset": str(dataset_dir), "member": n, "members": members,
                  "classes": list(classes), "method": method,
                  "seg_params": dict(seg_params or {}), "seed": seed,
                  "learner_settings": {k: str(v) for k, v in (settings or {}).items()},
                  "task": task or "modes_relational.pl", "recipe": recipe,
                  "other_rules": other_rules, "n_scenes": len(part),
                  "scenes": [d.scene_id for d in part],
                  "n_examples": sum(k in classes for _, k in ex),
                  "n_other": sum(k == OTHER for _, k in ex),
                  "seconds": {"learn": round(m.seconds, 3)}, "engine": m.engine,
                  "rules": {k: list(v) for k, v in m.rules.items()},
                  "rule_stats": [list(s) for s in m.stats], "uncovered": m.uncovered,
                  "dropped_redundant": [list(d) for d in m.dropped]}
            member_metrics.append(mm)
            per_member.append({k: mm[k] for k in ("member", "n_scenes", "n_examples", "n_other",
                                                  "seconds", "engine", "rules", "rule_stats")})
        metrics: dict = {**_metrics_head(dataset_dir, classes, method, seg_params, seed,
                                         settings, task, recipe, other_rules, decision),
                         "members": members, "vote": VOTE_RULE,
                         **_example_counts(descs, classes),
                         "skipped": skipped,
                         "seconds": {"describe": round(t_describe, 3), "learn": t_learn},
                         "engine": "; ".join(sorted({m.engine for m in model.models})),
                         "member_models": per_member}
        if background is not None:
            metrics["background"] = background.where
        if heldout is not None:
            _score_heldout(metrics, model, heldout, method=method, seg_params=seg_params,
                           jobs=jobs, cache=cache, progress=progress, timeout=timeout,
                           scheduler=scheduler)
        header = (f"learned by planerel from {dataset_dir} ({len(descs)} scenes in {members} "
                  f"parts, segmentation: {method}, engine: {metrics['engine']})")
        write_members(tmp, model, method=method, seg_params=seg_params, header=header,
                      member_metrics=member_metrics, decision=decision)
        write_json(tmp / "metrics.json", metrics)
    return metrics
