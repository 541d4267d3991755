"""Classify new scenes by logic query, with the planes that prove the answer.

For each scan: segment, describe (plane attributes, relations, object proposals), load the facts
into SWI-Prolog next to the model's rules, and ask which class each proposed object satisfies.
The answer names the rule that fired and the planes bound to its variables — what a robot that
plans to climb must see.

Prolog runs in process through pyswip (started on the first query, never at import), so it
must be used from the main thread.
"""

from __future__ import annotations

import contextlib
import functools
import itertools
import math
import re
import tempfile
import time
from dataclasses import dataclass, field, replace
from pathlib import Path

import numpy as np

from planerel.errors import InputError, PrologError
from planerel.ilp.prolog import (
    load_file,
    load_support,
    pl_path,
    query,
    unload_file,
    vocabulary_term,
)
from planerel.progress import progress_bar
from planerel.segment.params import WIDE_FALLBACK

__all__ = ["Classifier", "ObjectAnswer", "SceneAnswer", "explanation_image", "classify_dataset",
           "OTHER", "UNKNOWN"]

#: The answer "none of the classes" (see :func:`planerel.ilp.metrics.choose_class`).
OTHER = "other"
#: The class a merged proposal's solid is cut for (``decision.cut_boxes``).
BOX = "box"
#: Former name of :data:`OTHER`.
UNKNOWN = OTHER


def _binding_value(value):
    """A rule variable's binding for JSON: a number bound to a numeric variable (``B`` in
    ``oblique_share(A,B), lteq(B,0.1)``) as a number, a plane or object id as its string
    (user89: ``"B": "0.0"``)."""
    if isinstance(value, str) and _NUMBER.fullmatch(value):
        return int(value) if value.lstrip("+-").isdigit() else float(value)
    return value


_NUMBER = re.compile(r"[+-]?(\d+(\.\d*)?|\.\d+)([eE][+-]?\d+)?")


@dataclass(frozen=True)
class ObjectAnswer:
    """The answer for one object proposal.

    Attributes
    ----------
    object_id : str
        ``s0000_o1``.
    planes : tuple of str
        Plane ids of the proposal.
    labels : tuple of int
        Their labels in the segmentation.
    klass : str
        The class, or ``"other"`` (none of the classes: no rule fires, or only rules that were
        wrong at least as often as right on the training objects).
    rule : str or None
        The clause that proved the class.
    bindings : dict
        ``{variable: value}`` of the first proof of that clause.
    proof_planes : tuple of str
        The plane ids among the bindings: the planes that make the class.
    fired : tuple
        ``(class, rule index)`` of every rule that proved something about the object.
    rule_index : int or None
        Index of the chosen rule in the model (``planerel_rule_stats/4``).
    precision : float or None
        The chosen rule's Laplace precision on the training objects.
    planar_fraction : float or None
        Fraction of the object's points in flat planes (:mod:`planerel.features.curved`).
    curved : bool or None
        The planar fraction is below the model's ``curved.curved_below``: a round object.
    refused : tuple of Refusal, ProofRefusal, SizeRefusal, SlenderRefusal, RangeRefusal, LevelRefusal, FlightRefusal, FootRefusal, SideRefusal, UnsureRefusal, FacetRefusal, FlightSideRefusal, CrowdRefusal and VetoRefusal
        Classes whose rules proved the object and that the decision refused for it: its
        planar fraction lies under ``1 - decision.planar_margin`` times the least planar of
        the class's training positives (with ``decision.planar_gate``;
        :func:`planerel.ilp.metrics.planar_refusals`), a rule whose proof is made of planes far
        smaller than its training proofs' (:func:`~planerel.ilp.metrics.proof_refusals`), a
        class all of whose training positives had more horizontal planes than the object
        (:func:`~planerel.ilp.metrics.level_refusals`), a rule whose proof binds a plane far
        longer than its class's training proofs' (:func:`~planerel.ilp.metrics.size_refusals`),
        a rule whose proof binds a top far more slender than its class's training proofs'
        tops (:func:`~planerel.ilp.metrics.slender_refusals`), a rule whose proof binds a
        plane far farther from the sensor than its class's training proofs' planes
        (:func:`~planerel.ilp.metrics.range_refusals`), or a rule for ``other`` proved through planes far smaller than a class proof's
        (:func:`~planerel.ilp.metrics.veto_refusals`).  The answer is then the next class
        that holds, else ``other``.
    votes : tuple of ObjectAnswer
        A members model's answer (``planerel learn --members K``): each member's own answer,
        in member order; the class is their vote (:func:`planerel.ilp.members.vote`), the
        rule, bindings, proof planes, fired rules and refusals are :attr:`member`'s.  Empty
        for a single model.
    member : int or None
        The member (1-based) whose rule and proof are given (None: a single model).
    cut_from : str or None
        ``decision.cut_boxes``: this box was cut from that proposal (its id): the solid of a
        box proof's planes, decided as an object of its own (:mod:`planerel.features.box_cut`);
        its ``rule`` and ``proof_planes`` say which rule and planes.  ``decision.flight_trim``:
        these are the side planes of that ``stairs`` answer's flight (a wall it runs along),
        decided as an object of their own.
    cut_off : tuple of str
        The ids of the objects cut from this proposal (its ``planes`` are then the rest).
    measures : dict or None
        A ``stairs`` answer's flight (rise, run, rises in view, which way it goes, how far:
        :func:`~planerel.features.object_measures.flight_measures`) or a ``ramp`` answer's
        slope (:func:`~planerel.features.object_measures.slope_measures`); None for other
        classes or when the proof gives none.
    runner_up : ObjectAnswer or None
        The answer the decision gives with this answer's class left out, when that is a
        class (not ``other``): what a gate applied after the decision (``decision.crowd_gate``,
        ``decision.slope_parts_gate``, ...) falls back to when it refuses this class, as a
        refusal inside the decision does (the next class that holds).  None for a members
        model's vote.  Not part of :meth:`to_dict`.
    """

    object_id: str
    planes: tuple
    labels: tuple
    klass: str
    rule: str | None = None
    bindings: dict = field(default_factory=dict)
    proof_planes: tuple = ()
    fired: tuple = ()
    rule_index: int | None = None
    precision: float | None = None
    planar_fraction: float | None = None
    curved: bool | None = None
    refused: tuple = ()
    votes: tuple = ()
    member: int | None = None
    cut_from: str | None = None
    cut_off: tuple = ()
    measures: dict | None = None
    runner_up: ObjectAnswer | None = None

    def to_dict(self) -> dict:
        out = {"object": self.object_id, "class": self.klass, "rule": self.rule,
               "rule_index": self.rule_index,
               "precision": None if self.precision is None else round(self.precision, 4),
               "bindings": {k: _binding_value(v) for k, v in self.bindings.items()},
               "proof_planes": list(self.proof_planes),
               "planes": list(self.planes), "fired": [list(f) for f in self.fired],
               "planar_fraction": (None if self.planar_fraction is None
                                   else round(self.planar_fraction, 3)),
               "curved": self.curved, "refused": [r.to_dict() for r in self.refused]}
        if self.cut_from is not None:
            out["cut_from"] = self.cut_from
        if self.cut_off:
            out["cut_off"] = list(self.cut_off)
        if self.measures is not None:
            out["measures"] = dict(self.measures)
        if self.votes:
            out["member"] = self.member
            out["votes"] = [{"member": n, "class": v.klass, "rule": v.rule,
                             "rule_index": v.rule_index,
                             "precision": None if v.precision is None else round(v.precision, 4),
                             "proof_planes": list(v.proof_planes),
                             "refused": [r.to_dict() for r in v.refused]}
                            for n, v in enumerate(self.votes, start=1)]
        return out


@dataclass(frozen=True, eq=False)
class SceneAnswer:
    """Everything :meth:`Classifier.classify` found in one scan."""

    source: str | None
    scene_id: str
    labels: np.ndarray
    plane_ids: dict
    objects: tuple
    up_source: str
    seconds: float
    up_confidence: float = 1.0
    #: the up vector used, shape (3,), in the sensor's frame (None: not recorded)
    up_vector: tuple | None = None
    #: the estimate is flagged low (under ``gravity.low_confidence``; never for a given up)
    up_low: bool = False
    #: the estimate is the upside-down reading (``gravity.flip``)
    up_upside_down: bool = False
    #: the vote was not clear and the floor under the camera set the up (``gravity.near_floor``)
    up_near_floor: bool = False
    #: a floor measured only as speckle voted for the up (``gravity.sparse_floor``)
    up_sparse_floor: bool = False
    #: the floor plane's id (None: no floor plane in view, e.g. a camera near the floor or
    #: looking level over a desk; rules that need the ground, such as a box seen as one
    #: upright face, cannot hold then)
    floor: str | None = None
    #: the camera's height over the floor the caller gave, metres (None: not given)
    camera_height: float | None = None
    #: ``{plane id: geometry}`` of every plane (:func:`plane_geometry`), where the proof
    #: planes are (None: not recorded)
    geometry: dict | None = None
    #: the share of the scan's valid points that lie in a plane (None: not recorded)
    planar_share: float | None = None
    #: the segmentation grew the scan again with a wider window (``wide_fallback``)
    wide_fallback: bool = False
    #: what the scan says against what the caller gave (:func:`_input_disagreements`): a
    #: given up far from a confident estimate, a camera height far from the floor in view
    input_notes: tuple = ()

    @property
    def n_planes(self) -> int:
        return len(self.plane_ids)

    def to_dict(self) -> dict:
        up = None if self.up_vector is None else [round(float(v), 6) for v in self.up_vector]
        return {"input": self.source, "scene": self.scene_id, "n_planes": self.n_planes,
                "up": self.up_source, "up_confidence": round(self.up_confidence, 3),
                "up_vector": up, "up_low_confidence": self.up_low,
                "up_upside_down": self.up_upside_down, "up_near_floor": self.up_near_floor,
                "up_sparse_floor": self.up_sparse_floor,
                "floor": self.floor, "camera_height": self.camera_height,
                "objects": [o.to_dict() for o in self.objects],
                **({} if self.geometry is None else {"planes": self.geometry}),
                **({} if self.planar_share is None
                   else {"planar_share": round(self.planar_share, 4)}),
                **({"input_notes": list(self.input_notes)} if self.input_notes else {}),
                "seconds": round(self.seconds, 4)}

    def notes(self) -> list:
        """What the scan's frame leaves out, in words: a low-confidence up vector, no floor
        plane (empty when neither)."""
        out = []
        if self.up_low:
            how = ("; the planes' vote was unclear, so the floor under the camera set it"
                   if self.up_near_floor else "")
            out.append(f"the up vector is a guess (estimated, confidence {self.up_confidence:.2f}"
                       f"{how}): level and upright tests may be wrong; pass --up X,Y,Z when the "
                       "camera's up is known")
        if (self.planar_share is not None and self.planar_share < LOW_PLANAR_SHARE
                and not self.wide_fallback):
            out.append(f"only {100 * self.planar_share:.0f} % of the depth lies in a plane: "
                       "depth this rough at the adapted normal window (a stereo sensor's "
                       "correlated noise, an R200's speckle) gives normals of noise, and the "
                       "wider window's fallback is off here; --param "
                       f"wide_fallback={LOW_PLANAR_SHARE:g} (the default) grows such a scan "
                       "again with a wider window")
        if self.floor is None and self.plane_ids:
            out.append("no floor plane in view: " + (
                f"a box seen as one upright face stands on the floor {self.camera_height:g} m "
                "under the camera (--camera-height) or on none, and no slope's foot is checked"
                if self.camera_height is not None else
                "a box seen as one upright face cannot be proved (its foot needs the floor; "
                "pass --camera-height M when the camera's height over the floor is known), "
                "and no slope's foot is checked"))
        out.extend(self.input_notes)
        return out


#: Under this share of its valid points in a plane, with ``wide_fallback`` off, a scan's note
#: points to it (up66; its default share)
LOW_PLANAR_SHARE = WIDE_FALLBACK

#: The classes the far gate refuses a proof through a far plane for (``decision.far_gate``).
FAR_GATED = (BOX, "ramp")


#: degrees: a given up this far from an estimate the planes make with confidence
#: :data:`UP_SURE` or more gets a note (user89: ``--up 0,1,0`` on a Kinect frame whose up the
#: planes give with confidence 0.97 lost its box without a word)
UP_DISAGREE_DEG = 30.0
UP_SURE = 0.8
#: a given camera height more than this share (and 0.3 m) off the floor plane's distance under
#: the camera gets a note
HEIGHT_DISAGREE = 0.5


def _input_disagreements(cloud, labels, planes, up, gravity_params) -> tuple:
    """Notes where the caller's ``--up`` or ``--camera-height`` disagrees with the scan: the
    given up more than :data:`UP_DISAGREE_DEG` from the up the planes give with confidence
    :data:`UP_SURE` or more (estimated only when an up is given: a few milliseconds), the
    given height more than :data:`HEIGHT_DISAGREE` of the floor plane's distance (and 0.3 m)
    off it.  The given values are used all the same; the note says what the scan says."""
    from planerel.features.gravity import up_from_cloud

    out = []
    if up is not None:
        est = up_from_cloud(cloud, labels, gravity_params)
        given = np.asarray(up, float) / np.linalg.norm(np.asarray(up, float))
        angle = math.degrees(math.acos(max(-1.0, min(1.0, float(given @ est.vector)))))
        if est.source == "estimated" and est.confidence >= UP_SURE and angle > UP_DISAGREE_DEG:
            v = ", ".join(f"{x:.2f}" for x in est.vector)
            out.append(f"the given up is {angle:.0f} degrees from the up the planes give "
                       f"([{v}], confidence {est.confidence:.2f}); it is used as given: check "
                       "--up's axes (the camera's x right, y down, z forward)")
    height = planes.camera_height
    if height is not None and planes.floor is not None:
        floor = next((p for p in planes if p.label == planes.floor), None)
        if floor is not None:
            below = -float(np.asarray(floor.centroid, float) @ np.asarray(planes.up, float))
            if abs(below - height) > max(0.3, HEIGHT_DISAGREE * below):
                out.append(f"--camera-height {height:g} m, but the floor plane in view lies "
                           f"{below:.2f} m under the camera; the given height is used")
    return tuple(out)


def _measured(answers, desc, plane_ids, params) -> tuple:
    """``answers`` with each ``stairs`` answer's flight and each ``ramp`` answer's slope
    measured (:mod:`planerel.features.object_measures`): the flight from the scene's
    ``stair_step/2`` pairs among the answer's planes, the slope from the largest of its proof
    planes that is not upright."""
    from planerel.features.object_measures import flight_measures, slope_measures
    from planerel.features.proposal_params import ProposalParams

    params = params or ProposalParams()
    label_of = {v: k for k, v in plane_ids.items()}
    by_label = {p.label: p for p in desc.planes}
    out = []
    for a in answers:
        m = None
        if a.klass == "stairs":
            m = flight_measures(desc.planes, a.labels, desc.steps, params.step_tread_axes,
                                params.step_tilts)
        elif a.klass == "ramp":
            cand = [by_label[label_of[x]] for x in a.proof_planes
                    if x in label_of and label_of[x] in by_label]
            cand = [p for p in cand if p.orientation != "vertical"]
            if cand:
                m = slope_measures(desc.planes, max(cand, key=lambda p: p.area).label)
        out.append(replace(a, measures=m) if m is not None else a)
    return tuple(out)


#: Degrees: a slope rises "the flight's way" when its level direction lies within this of the
#: direction the object's steps rise (``decision.pitch_gate``)
PITCH_WAY = 30.0


def _pitch_gate(desc, plane_ids, params):
    """``pitch_of(labels) -> pitch(plane id)`` for ``decision.pitch_gate``
    (:func:`~planerel.ilp.metrics.pitch_refusals`): for an object's planes ``labels``, a
    function giving an inclined plane's ``(incline, flight pitch)`` in degrees when it rises
    within :data:`PITCH_WAY` of the way the object's own steps rise (the scene's
    ``stair_step/2`` pairs among ``labels``, :func:`~planerel.features.object_measures.
    flight_measures`; the pitch is the arctangent of their median rise over median run), else
    None (an upright or level plane, another way, no steps or no run measured).  The flight is
    measured once an object, and only when asked."""
    from planerel.features.object_measures import flight_measures, slope_measures
    from planerel.features.proposal_params import ProposalParams

    params = params or ProposalParams()
    label_of = {v: k for k, v in plane_ids.items()}
    ps = desc.planes
    cos_way = math.cos(math.radians(PITCH_WAY))

    def pitch_of(labels):
        @functools.cache
        def flight():
            m = flight_measures(ps, labels, desc.steps, params.step_tread_axes, params.step_tilts)
            if m is None or not m["run_m"]:
                return None
            return math.degrees(math.atan2(m["rise_m"], m["run_m"])), np.asarray(m["direction"])

        def pitch(pid):
            lab = label_of.get(pid)
            if lab is None or lab not in labels or ps.by_label(lab).orientation != "inclined":
                return None
            f = flight()
            if f is None:
                return None
            slope = slope_measures(ps, lab)
            if slope is None or float(np.asarray(slope["direction"]) @ f[1]) < cos_way:
                return None
            return float(ps.by_label(lab).incline), f[0]

        return pitch

    return pitch_of


def _under_eye(planes, labels) -> bool:
    """Whether a plane ``labels`` of ``planes`` has its centroid under the camera's eye (the
    origin) along the planes' up (the side gate's ``under_eye``)."""
    up = np.asarray(planes.up, dtype=np.float64)
    return any(float(np.asarray(planes.by_label(lab).centroid, dtype=np.float64) @ up) < 0
               for lab in labels)


def _proof_plane_gate(desc, answers, xyz, klass: str, orientation: str, measure, refusal):
    """A decision gate on the proof planes of one orientation: each ``klass`` answer's proof
    planes of ``orientation`` are measured, ``measure(plane, up, xyz, labels)`` (None: the plane
    is not judged), and ``refusal(answer, measures)`` (over the judged planes, at least one)
    gives the refusal that turns it to ``other`` (:func:`_refuse`), or None to keep it.  The
    answers as they are when the description's labels do not index ``xyz``."""
    lab = desc.labels
    if lab is None or np.asarray(lab).shape != np.asarray(xyz).shape[:2]:
        return answers
    ids = {desc.plane_id(p.label): p for p in desc.planes}
    out = []
    for a in answers:
        if a.klass == klass:
            planes = [ids[i] for i in a.proof_planes if i in ids and ids[i].orientation == orientation]
            got = [m for m in (measure(p, desc.planes.up, xyz, lab) for p in planes) if m is not None]
            why = refusal(a, got) if got else None
            if why is not None:
                a = _refuse(a, why)
        out.append(a)
    return tuple(out)


#: the :class:`Classifier` attributes of the decision gates applied after the decision (the
#: box cut, the flight trim and :meth:`Classifier._answer_gates`) that a members model takes
#: from its first member (members93, cutm93)
_AFTER_VOTE = ("cut_boxes", "cut_split", "flight_trim", "flight_side", "hang", "long_lying",
               "slab", "crowd", "narrow_face", "far_gate", "slope_parts")


def _box_rules(a, chosen: bool = False) -> set:
    """The box rules that proved answer ``a`` (``chosen``: the box rule that answered it), as
    rule indices, or for a members model's vote as ``(member, index)`` over its votes (a rule
    index names a rule of one member only): what :meth:`Classifier._cut_boxes` compares."""
    if not a.votes:
        if chosen:
            return {a.rule_index} if a.klass == BOX else set()
        return {i for k, i in a.fired if k == BOX}
    if chosen:
        return {(n, v.rule_index) for n, v in enumerate(a.votes) if v.klass == BOX}
    return {(n, i) for n, v in enumerate(a.votes) for k, i in v.fired if k == BOX}


def _refuse(a, why):
    """The answer ``a`` refused by a decision gate applied after the decision, ``why`` (the
    gate's refusal) added to its refusals: its :attr:`~ObjectAnswer.runner_up` (the next
    class that holds, as a refusal inside the decision gives; fallback93) on the same planes,
    else ``other``."""
    refused = tuple(a.refused) + (why,)
    nxt = a.runner_up
    if nxt is not None:
        return replace(nxt, planes=a.planes, labels=a.labels, fired=a.fired, refused=refused,
                       cut_from=a.cut_from, cut_off=a.cut_off)
    return replace(a, klass=OTHER, rule=None, bindings={}, proof_planes=(), rule_index=None,
                   precision=None, refused=refused)


def _num(v, digits: int = 4):
    v = float(v)
    return round(v, digits) if np.isfinite(v) else None


def plane_geometry(plane) -> dict:
    """Where a plane is, for a robot: ``centroid`` (m) and unit ``normal`` (towards the
    sensor) in the camera frame (x right, y down, z forward), ``area`` (m^2), ``length`` and
    ``width`` (m), ``orientation``, ``incline`` (degrees from level), ``height`` (m above the
    floor, None when unknown), ``distance`` (m from the sensor) and the pixel ``bbox``
    ``[row0, col0, row1, col1]`` (end-exclusive), from :class:`planerel.features.planes.Plane`."""
    return {"centroid": [_num(v) for v in plane.centroid],
            "normal": [_num(v) for v in plane.normal],
            "area": _num(plane.area), "length": _num(plane.length),
            "width": _num(plane.width), "orientation": plane.orientation,
            "incline": _num(plane.incline, 2), "height": _num(plane.height),
            "distance": _num(plane.distance), "bbox": [int(v) for v in plane.bbox]}


_MODEL_NUMBERS = itertools.count(1)


def _as_cloud(scan):
    """``scan`` when it is a Cloud; a scan file read (its sidecar's intrinsics); else an
    :class:`InputError` that says what to pass (an array needs ``planerel.read`` and its
    intrinsics)."""
    from planerel.io.cloud import Cloud

    if isinstance(scan, Cloud):
        return scan
    if isinstance(scan, (str, Path)) or hasattr(scan, "__fspath__"):
        from planerel.io.readers import read

        return read(scan)
    raise InputError(f"classify takes a Cloud or the path of a scan, got a {type(scan).__name__}; "
                     "make a Cloud with planerel.read(array, intrinsics=...)")


def check_gate_classes(overrides, classes) -> None:
    """``planerel classify``: a class named in ``--param decision.size_classes=...``
    (``slender_classes``, ``range_classes``) that the model has no rule for is an error, as
    an unknown class is in ``learn --set CLASS:NAME=VALUE`` (the gate would hold for a class
    that never answers, in silence).  An empty value (no class gated) passes; the
    :class:`Classifier` itself takes any names (the gate tests turn a gate off that way)."""
    for name, value in (overrides or {}).items():
        sec, _, key = str(name).partition(".")
        if sec != "decision" or key not in ("size_classes", "slender_classes", "range_classes"):
            continue
        unknown = [c.strip() for c in str(value).split(",") if c.strip() and c.strip() not in classes]
        if unknown:
            raise InputError(f"--param {name}={value}: {', '.join(map(repr, unknown))} "
                             f"{'is not a class' if len(unknown) == 1 else 'are not classes'} "
                             f"of the model ({', '.join(classes)})")


def _check_text(path: Path) -> None:
    """Refuse a rules file that is no UTF-8 text (an image or a .npy given as the model) in
    one line, before SWI-Prolog reads it and prints its own warnings about every byte."""
    try:
        data = path.read_bytes()
    except OSError as exc:
        raise InputError(f"{path}: cannot read the rules file ({exc.strerror or exc})") from None
    try:
        data.decode("utf-8")
        binary = b"\0" in data
    except UnicodeDecodeError:
        binary = True
    if binary:
        raise InputError(f"{path}: not a rules file (binary data, not UTF-8 text); give "
                         "MODEL_DIR or MODEL_DIR/rules.pl from planerel learn")


class Classifier:
    """Rules of a model, read as data into their own Prolog module, ready to classify scans.

    A model file is data, never code: it is read clause by clause with ``read_term`` and
    nothing in it runs.  Directives, heads that are not a class, class names that are built-in
    or library predicates, and rule bodies that call anything but planerel's vocabulary
    (``docs/predicates.md``) and safe built-ins (comparisons, arithmetic, type tests) are
    refused with an error naming the file and line.  Each classifier keeps its rules in a
    module of its own, so any number of them coexist in one process and each answers with
    its own rules.

    Parameters
    ----------
    rules : path
        A model file (``MODEL_DIR/rules.pl`` from ``planerel learn``, or the folder
        ``MODEL_DIR`` itself) holding clauses
        ``Class(Obj) :- ...`` or ``class(Obj, Class) :- ...`` and optional
        ``planerel_rule_stats/4`` facts.  The settings the model was learned with
        (``model.json`` next to it, :mod:`planerel.ilp.model_settings`) are used for scans.
        A background file of the user's own that ``model.json`` names (``background.pl``,
        ``learn --background``) is read and checked the same way, first, into the model's
        module: the rules may call its predicates.
    method : str, optional
        Segmentation method for scans (default: the model's, else ``regiongrow``).
    seg_params : dict, optional
        Overrides of the model's settings: segmentation parameters by name, description
        parameters as ``gravity.NAME``, ``planes.NAME``, ``relations.NAME``,
        ``proposals.NAME``, ``curved.NAME``, and the decision's as ``decision.NAME``
        (``decision.planar_gate``, ``decision.planar_margin``).  :attr:`warnings` lists those
        that differ from training.

    Raises
    ------
    InputError
        The file is missing or holds a clause that is refused; the model's background file
        is missing, changed since learning (its SHA-256) or holds a clause that is refused.
    PrologError
        The file is not valid Prolog text (syntax error; the message gives the line).
    """

    def __init__(self, rules, *, method: str | None = None, seg_params: dict | None = None,
                 _member: bool = False):
        from planerel.ilp.model_settings import read_settings, with_overrides

        if not isinstance(rules, (str, Path)) and not hasattr(rules, "__fspath__"):
            raise InputError(f"a model is a folder or its rules.pl file, got a "
                             f"{type(rules).__name__}")
        path = Path(rules)
        if path.is_dir() and (path / "rules.pl").is_file():
            path = path / "rules.pl"  # the model folder that `planerel learn -o` wrote
        if not path.is_file():
            raise InputError(f"{path}: no such rules file (give MODEL_DIR or MODEL_DIR/rules.pl)")
        self.rules_path = path
        _check_text(path)
        self.trained = read_settings(path)
        self.settings, warnings = with_overrides(self.trained, method=method,
                                                 overrides=seg_params)
        self.warnings = tuple(warnings)
        self.method = self.settings.method
        self.seg_params = dict(self.settings.seg_params)
        self._describe_kw = self.settings.describe_kwargs()
        from planerel.ilp.background import model_background

        #: the model's background file of the user's own (``learn --background``), checked
        #: against the SHA-256 model.json records; None for a model without one
        self.background_path = model_background(
            path, self.trained.background if self.trained is not None else None)
        # top_slope/2 is measured only for a model whose rules (or background) read it
        # (ramp77): a clause's line, not a comment (rules.pl lists the clauses learning left
        # out as comments)
        self._describe_kw["top_slope"] = any(
            "top_slope(" in ln for f in (path, self.background_path) if f is not None
            for ln in f.read_text(errors="replace").splitlines()
            if not ln.lstrip().startswith("%"))
        #: a members model's members (``planerel learn --members K``), each a Classifier of
        #: its own; empty for a single model
        self.members: tuple = ()
        from planerel.ilp.members import member_folders

        folders = member_folders(path)
        if folders is not None:
            self._init_members(folders, method, seg_params)
            return
        self.module = f"planerel_model_{next(_MODEL_NUMBERS)}"
        load_support()
        bg = "none" if self.background_path is None else pl_path(self.background_path)
        answer = query(f"planerel_load_model({self.module}, {pl_path(path)}, {bg}, "
                       f"{vocabulary_term()}, S), "
                       "(S = error(L, M) -> B = rules ; S = background_error(L, M) -> "
                       "B = background ; L = 0, M = '', B = ok)",
                       f"{path}: cannot read the model")[0]
        if _text(answer["M"]):
            line, msg = int(answer["L"]), _text(answer["M"])
            file = self.background_path if _text(answer["B"]) == "background" else path
            where = f"{file}:{line}" if line else f"{file}"
            if msg.startswith("syntax error"):
                raise PrologError(f"{where}: not a valid rules file: {msg}")
            raise InputError(f"{where}: {msg}")
        heads = tuple(dict.fromkeys(_text(r["C"]) for r in query(
            f"{self.module}:planerel_rule(_, C, _, _, _, _)", "reading the model")))
        # rules with head ``other`` prove "none of the classes" (learn_rules' other_rules):
        # they compete in the decision but are no class of the model
        self.classes = tuple(k for k in heads if k != OTHER)
        self.stats = tuple((int(r["I"]), _text(r["C"]), int(r["TP"]), int(r["FP"])) for r in query(
            f"{self.module}:planerel_stats(I, C, TP, FP)", "reading the rule statistics"))
        self.cofire = tuple((int(r["I"]), int(r["J"]), _text(r["C"]), int(r["N"])) for r in query(
            f"{self.module}:planerel_cofire(I, J, C, N)", "reading the rule statistics"))
        if not self.classes and not _member:
            # (a member of a members model may have learned none on its part: it answers
            # "other" in the vote, as in planerel learn's own scoring)
            raise InputError(f"{path}: the model has no rules")
        from planerel.ilp.metrics import size_gated

        decision = self.settings.decision_params()
        #: ``(class, low, high, n)`` the gate compares with (empty: no gate; the model keeps
        #: none, or ``decision.planar_gate`` is off)
        self.planar_domain = (self.settings.planar_domain if decision.planar_gate else ())
        self.planar_margin = decision.planar_margin
        #: ``(index, class, low, high, n)`` the proof gate compares with (empty: no gate)
        self.proof_domain = (self.settings.proof_domain if decision.proof_gate else ())
        self.proof_margin = decision.proof_margin
        self.proof_min_positives = decision.proof_min_positives
        #: ``(class, low, n)`` the level gate compares with (empty: no gate; the model keeps
        #: none, or ``decision.level_gate`` is off)
        self.level_domain = (self.settings.level_domain if decision.level_gate else ())
        #: ``(class, high, n)`` the size gate compares with (empty: no gate; the model keeps
        #: none, or ``decision.size_gate`` is off)
        self.size_domain = (size_gated(self.settings.size_domain, decision.size_classes)
                            if decision.size_gate else ())
        self.size_margin = decision.size_margin
        #: ``(class, high, n)`` the slenderness gate compares with (empty: no gate; the model
        #: keeps none, or ``decision.slender_gate`` is off)
        self.slender_domain = (size_gated(self.settings.slender_domain, decision.slender_classes)
                               if decision.slender_gate else ())
        self.slender_margin = decision.slender_margin
        #: ``(class, high, n)`` the range gate compares with (empty: no gate; the model keeps
        #: none, or ``decision.range_gate`` is off)
        self.range_domain = (size_gated(self.settings.range_domain, decision.range_classes)
                             if decision.range_gate else ())
        self.range_margin = decision.range_margin
        #: ``ramp`` only for a slope standing on the floor (:func:`~planerel.ilp.metrics.foot_refusals`;
        #: ``decision.foot_gate``): needs the scan's points, so only :meth:`classify` applies it
        self.foot_gate = decision.foot_gate
        self.foot_bounds = (decision.foot_above, decision.foot_below, decision.foot_hidden,
                            decision.foot_float)
        #: ``ramp`` (``stairs``) only for a slope (treads) seen from above (:func:`~planerel.ilp.metrics.side_refusals`;
        #: ``decision.side_gate``)
        self.side_gate = decision.side_gate
        #: no ``ramp`` under a low-confidence estimated up with no floor in view
        #: (:func:`~planerel.ilp.metrics.unsure_refusals`; ``decision.unsure_gate``): a scan's
        #: decision, as the foot and side gates
        self.unsure_gate = decision.unsure_gate
        #: ... and under an estimated up read upside down (``decision.unsure_upside``)
        self.unsure_upside = decision.unsure_upside
        #: ... and under an estimated up a speckle floor decided, no floor plane in view
        #: (``decision.unsure_sparse``)
        self.unsure_sparse = decision.unsure_sparse
        #: no ``box`` through an upright plane that is a facet of a round side
        #: (:func:`~planerel.ilp.metrics.facet_refusals`; ``decision.facet_gate``): ``(low,
        #: high)`` degrees, or None when off; a scan's decision, as the foot and side gates
        self.facet_gate = ((decision.facet_min, decision.facet_max) if decision.facet_gate
                           else None)
        self.facet_bridge = decision.facet_bridge
        #: no ``ramp`` at the pitch of the object's own flight when a ``stairs`` rule proves it
        #: too (:func:`~planerel.ilp.metrics.pitch_refusals`; ``decision.pitch_gate``): the
        #: tolerance in degrees, or None when off; a scan's decision, as the side gate
        self.pitch_tol = decision.pitch_tol if decision.pitch_gate else None
        #: a box inside a merged proposal decided on its own (``decision.cut_boxes``,
        #: :mod:`planerel.features.box_cut`): ``(reach, margin, corner, pieces)``, or None when off
        self.cut_boxes = ((decision.cut_reach, decision.cut_margin, decision.cut_corner,
                           decision.cut_pieces) if decision.cut_boxes else None)
        #: a proposal answered ``box`` holding two or more boxes of its own is split into
        #: them (``decision.cut_split``, with ``cut_boxes``)
        self.cut_split = decision.cut_split
        #: no ``box`` for an object running beside a flight answered ``stairs`` in the scan
        #: (``decision.flight_side_gate``, :mod:`planerel.features.flight_side`): ``(thick,
        #: gap, reach, rise, angle)``, or None when off; a scan's decision, as the foot gate
        self.flight_side = ((decision.flight_side_thick, decision.flight_side_gap,
                             decision.flight_side_reach, decision.flight_side_rise,
                             decision.flight_side_angle) if decision.flight_side_gate else None)
        #: a ``stairs`` answer's proposal cut to its flight (``decision.flight_trim``,
        #: :func:`~planerel.features.flight_side.side_planes`): ``(angle, edge, rise)``, or
        #: None when off
        self.flight_trim = ((decision.flight_trim_angle, decision.flight_trim_edge,
                             decision.flight_trim_rise) if decision.flight_trim else None)
        #: no ``box`` for an object whose upright proof faces hang over the space beneath
        #: them (``decision.hang_gate``, :mod:`planerel.features.hang`): ``(share, drop,
        #: level, lines)``, or None when off
        self.hang = ((decision.hang_share, decision.hang_drop, decision.hang_level,
                      decision.hang_lines) if decision.hang_gate else None)
        #: no ``box`` for an object proved by a top alone longer than a lying box's
        #: (``decision.long_lying_gate``): the bound in metres, or None when off
        self.long_lying = decision.long_lying_length if decision.long_lying_gate else None
        #: no ``box`` for an object whose proof's top is a slab's edge: narrow, an upright
        #: plane of the object reaching far below it (``decision.slab_gate``,
        #: :mod:`planerel.features.slab`): ``(width, drop)``, or None when off
        self.slab = (decision.slab_width, decision.slab_drop) if decision.slab_gate else None
        #: no ``box`` for an object of more planes than a box shows (``decision.crowd_gate``):
        #: the bound, or None when off
        self.crowd = decision.crowd_planes if decision.crowd_gate else None
        #: no ``box`` for an object whose upright proof faces are all far taller than wide
        #: (``decision.narrow_face_gate``, :mod:`planerel.features.face_shape`): the bound
        #: on height over width, or None when off
        self.narrow_face = decision.narrow_face_ratio if decision.narrow_face_gate else None
        #: no ``ramp`` for an object whose sloping proof planes each have a part that does
        #: not slope as the whole does (``decision.slope_parts_gate``,
        #: :mod:`planerel.features.slope_parts`): the bound on ``|share - 1|``, or None when off
        self.slope_parts = decision.slope_parts_tol if decision.slope_parts_gate else None
        #: no ``box`` or ``ramp`` proved through a plane only the far growing found
        #: (``decision.far_gate``; :meth:`_far_proofs`)
        self.far_gate = decision.far_gate
        #: ``stairs`` only for an object whose faces show a staircase's steps
        #: (:func:`~planerel.ilp.metrics.flight_refusals`; ``decision.flight_gate``, recorded
        #: in ``model.json`` since pile26 or given as a param: a model learned before decides
        #: as before)
        self.flight_gate = (decision.flight_gate
                            and "flight_gate" in self.settings.sections.get("decision", {}))
        #: that test reads a flight seen in fragments too (``decision.flight_fragments``,
        #: flight48: on unless the model or a param says false)
        self.flight_fragments = decision.flight_fragments
        #: vetoes (rules for ``other``) proved through far smaller planes than a class proof
        #: are set aside (0: off; nothing to set aside without rules for ``other``)
        self.veto_ratio = decision.veto_ratio if OTHER in heads else 0.0
        # the gate is on by default: a model without the domain (learned before gate22)
        # warns only when the gate is asked for (its model.json or ``decision.planar_gate``)
        asked = "planar_gate" in self.settings.sections.get("decision", {})
        if decision.planar_gate and asked and not self.settings.planar_domain:
            self.warnings += (f"{path.parent / 'model.json'} keeps no planar fractions of the "
                              "training positives (a model learned before they were kept): "
                              "decision.planar_gate refuses nothing",)
        recorded = self.trained.rule_stats if self.trained is not None else ()
        if recorded and sorted(recorded) != sorted(self.stats):
            # rules.pl cut short (a copy that stopped, a disk that filled) or rules.pl and
            # model.json of two different runs: it loads and answers with other rules and
            # precisions than the model learned, in silence (the rules' statistics, written
            # into both files by planerel learn, tell)
            n_rules = len(dict.fromkeys(int(r["I"]) for r in query(
                f"{self.module}:planerel_rule(I, _, _, _, _, _)", "reading the model")))
            self.warnings += (f"{path} does not match {path.parent / 'model.json'}: it holds "
                              f"{n_rules} rule(s) and {len(self.stats)} rule statistics, "
                              f"model.json was written with {len(recorded)} (rules.pl cut "
                              "short, edited, or copied from another model): the answers "
                              "are not the model's; copy the model folder again",)
        if self.trained is None and self.stats:
            # rules from planerel learn (they carry its statistics) without their settings
            self.warnings += (f"{path.parent / 'model.json'} is missing: the settings the rules "
                              "were learned with are unknown and planerel's defaults are used, "
                              "so the answers can differ from the model's; keep model.json "
                              "next to rules.pl",)

    def _init_members(self, folders, method, seg_params) -> None:
        """A members model: one Classifier per member; the scan is described once with the
        top-level settings (the members were learned on the same descriptions)."""
        members = []
        try:
            for folder in folders:
                members.append(Classifier(folder, method=method, seg_params=seg_params,
                                          _member=True))
        except BaseException:
            for m in members:
                m.close()
            raise
        self.members = tuple(members)
        self.module = "members"   # open; the members hold the Prolog modules
        self.classes = tuple(dict.fromkeys(k for m in members for k in m.classes))
        if not self.classes:
            self.close()
            raise InputError(f"{self.rules_path}: the model has no rules (none of its "
                             f"{len(members)} members learned one)")
        self.stats = ()
        self.cofire = ()
        self.planar_domain = self.proof_domain = self.level_domain = self.size_domain = ()
        self.slender_domain = self.range_domain = ()
        # the gates after the decision judge the vote's answer (its member's proof planes) as
        # a single model's (members93; the box cut decides its solids by the vote, cutm93):
        # the members were learned, and are read, with one model's settings, so the first
        # member's decision settings are the model's
        for name in _AFTER_VOTE:
            setattr(self, name, getattr(members[0], name))
        self.warnings = tuple(dict.fromkeys((*self.warnings, *(w for m in members
                                                                for w in m.warnings))))

    def close(self) -> None:
        """Forget this model's rules (the classifier cannot be used afterwards)."""
        if self.members:
            for m in self.members:
                m.close()
            self.module = None
            return
        if getattr(self, "module", None):
            query(f"planerel_unload_model({self.module})", "unloading the model")
            self.module = None

    def __enter__(self) -> Classifier:
        return self

    def __exit__(self, *exc) -> None:
        self.close()

    def classify(self, cloud, *, scene_id: str = "s0000", up=None,
                 camera_height=None) -> SceneAnswer:
        """Segment, describe and classify one cloud (a :class:`~planerel.io.cloud.Cloud`, as
        ``planerel.read`` returns, or the path of a scan file).

        ``up`` (3 numbers) and ``camera_height`` (metres over the floor) are the camera's pose
        when known: :func:`planerel.features.facts.describe_scene`'s.

        Returns
        -------
        SceneAnswer
            One :class:`ObjectAnswer` per object proposal (none when the scene has no object).
        """
        from planerel.features.facts import describe_scene, view_up
        from planerel.segment import planar_share, segment

        self._check_open()
        t0 = time.perf_counter()
        cloud = _as_cloud(cloud)
        cloud.require_points(3)
        seg = segment(cloud, self.method,
                      up=view_up(cloud, up, self._describe_kw.get("gravity_params")),
                      **dict(self.seg_params or {}))
        desc = describe_scene(cloud, seg.labels, scene_id=scene_id, up=up,
                              far=seg.info.get("far_labels") or (),
                              camera_height=camera_height, **self._describe_kw)
        plane_ids = {p.label: desc.plane_id(p.label) for p in desc.planes}
        answers = _measured(self.answer_description(desc, xyz=cloud.xyz), desc, plane_ids,
                            self._describe_kw.get("proposal_params"))
        # the labels the planes refer to (a stepped plane may have been split into levels)
        ps = desc.planes
        gravity = self._describe_kw.get("gravity_params")
        low = ps.up_low(None if gravity is None else gravity.low_confidence)
        return SceneAnswer(cloud.source, scene_id, desc.labels, plane_ids, answers,
                           ps.up_source, time.perf_counter() - t0, ps.up_confidence,
                           up_vector=tuple(float(v) for v in ps.up), up_low=bool(low),
                           up_upside_down=bool(ps.up_upside_down),
                           up_near_floor=bool(ps.up_near_floor),
                           up_sparse_floor=bool(ps.up_sparse_floor),
                           floor=None if ps.floor is None else plane_ids.get(ps.floor),
                           camera_height=ps.camera_height,
                           geometry={plane_ids[p.label]: plane_geometry(p) for p in ps},
                           planar_share=planar_share(cloud, seg.labels),
                           wide_fallback="wide_fallback" in seg.info,
                           input_notes=_input_disagreements(cloud, seg.labels, ps, up, gravity))

    def answer_description(self, desc, xyz=None) -> tuple:
        """The answers for the objects of a scene description, in its object order.

        Parameters
        ----------
        desc : planerel.features.facts.SceneDescription
            A scan's description with its object proposals (what :meth:`classify` makes), or
            a data-set scene's with its ground-truth objects
            (:func:`planerel.ilp.scenes.describe_scenes`: how :func:`evaluate_model` scores a
            model on a held-out set).
        xyz : ndarray, shape (H, W, 3), optional
            The scan's organized points (what the description's labels index): the foot gate
            (``decision.foot_gate``) looks at where a sloping plane's low end lies only with
            them.

        Returns
        -------
        tuple of ObjectAnswer
            One per object (empty when the description has none); a members model's answers
            are its members' vote, judged by the gates after the decision as a single model's
            answers are.
        """
        self._check_open()
        if not desc.objects:
            return ()
        plane_ids = {p.label: desc.plane_id(p.label) for p in desc.planes}
        with _scene_facts(desc, "scene"):
            if self.members:
                answers = tuple(_voted([m._answer(desc, plane_ids, xyz) for m in self.members]))
            else:
                answers = tuple(self._answer(desc, plane_ids, xyz))
        cut = self.cut_boxes is not None and xyz is not None and BOX in self.classes
        if cut:
            answers = self._cut_boxes(desc, answers, plane_ids, xyz)
        trim = self.flight_trim is not None and xyz is not None and "stairs" in self.classes
        if trim:
            answers = self._trim_flights(desc, answers, plane_ids, xyz)
        early = {a.object_id: len(a.refused) for a in answers}
        answers = self._gated(desc, answers, plane_ids, xyz, trim)
        if cut:
            # a box a gate after the decision refused is cut as one the decision's own gates
            # refused (cutpost94); what comes out meets those gates in turn
            late = {a.object_id for a in answers
                    if a.klass != BOX and a.object_id in early
                    and any(getattr(r, "klass", None) == BOX
                            for r in a.refused[early[a.object_id]:])}
            if late:
                answers = self._cut_late(desc, answers, plane_ids, xyz, trim, late)
        return answers

    def _cut_late(self, desc, answers, plane_ids, xyz, trim: bool, late: set) -> tuple:
        """``answers`` with the proposals ``late`` (answers a gate after the decision refused
        ``box`` for) cut by :meth:`_cut_boxes` and the result judged by :meth:`_gated`; a
        proposal none of whose cut solids stays ``box`` through those gates keeps its answer
        uncut (cutpost94)."""
        cut = self._cut_boxes(desc, answers, plane_ids, xyz, only=late)
        if len(cut) == len(answers):
            return answers
        cut = self._gated(desc, cut, plane_ids, xyz, trim)
        was = {a.object_id: a for a in answers}
        kept = {a.cut_from for a in cut if a.object_id not in was and a.klass == BOX}
        return tuple(was[a.object_id] if a.object_id in late - kept else a
                     for a in cut if a.object_id in was or a.cut_from in kept)

    def _gated(self, desc, answers, plane_ids, xyz, trim: bool) -> tuple:
        """``answers`` judged by :meth:`_answer_gates`: a gate that refuses a class falls back
        to the answer's runner-up (:func:`_refuse`), which the gates before it have not seen,
        so once more until no answer changes class (a flight fallen back to is trimmed, with
        ``trim``, as a flight decided at once is; trim94)."""
        for _ in range(len(self.classes)):
            before = [a.klass for a in answers]
            answers = self._answer_gates(desc, answers, xyz)
            changed = {a.object_id for a, k in zip(answers, before, strict=True)
                       if a.klass not in (OTHER, k)}
            if not changed:
                break
            if trim:
                answers = self._trim_flights(desc, answers, plane_ids, xyz, only=changed)
        return answers

    def _answer_gates(self, desc, answers, xyz) -> tuple:
        """The decision gates that judge each answer as it is (none makes objects), in
        order: flight sides, hanging, long lying, slab edges, crowded, narrow faces, far
        proofs, slope parts (:meth:`answer_description`)."""
        if self.flight_side is not None and xyz is not None and BOX in self.classes:
            answers = self._flight_sides(desc, answers, xyz)
        if self.hang is not None and xyz is not None and BOX in self.classes:
            answers = self._hanging(desc, answers, xyz)
        if self.long_lying is not None and BOX in self.classes:
            answers = self._long_lying(desc, answers)
        if self.slab is not None and xyz is not None and BOX in self.classes:
            answers = self._slabs(desc, answers, xyz)
        if self.crowd is not None and BOX in self.classes:
            answers = self._crowded(answers)
        if self.narrow_face is not None and xyz is not None and BOX in self.classes:
            answers = self._narrow_faces(desc, answers, xyz)
        if self.far_gate and desc.far:
            answers = self._far_proofs(desc, answers)
        if self.slope_parts is not None and xyz is not None and "ramp" in self.classes:
            answers = self._slope_parts(desc, answers, xyz)
        return answers

    def _trim_flights(self, desc, answers, plane_ids, xyz, only=None) -> tuple:
        """``decision.flight_trim``: each ``stairs`` answer (of the object ids ``only``, when
        given) whose proposal holds side planes of its flight
        (:func:`~planerel.features.flight_side.side_planes`) keeps the rest; the side planes
        are decided as an object of their own (a members model's by its vote), listed after
        it with ``cut_from``."""
        from planerel.features.facts import SceneObject
        from planerel.features.flight_side import side_planes

        angle, edge, rise = self.flight_trim
        proposals = {o.id for o in desc.objects}   # not a box cut_boxes made of a part
        out = []
        for a in answers:
            skip = a.klass != "stairs" or a.object_id not in proposals or (
                only is not None and a.object_id not in only)
            cut = () if skip else side_planes(
                desc.planes, a.labels, desc.steps, xyz, desc.labels, angle, edge, rise)
            proof = set(a.proof_planes)   # a plane a rule binds stays with the flight
            cut = tuple(x for x in cut if plane_ids.get(x) not in proof)
            if not cut:
                out.append(a)
                continue
            side = SceneObject(f"{a.object_id}_w1", cut, None, None, 1.0, False)
            b = self._answer_objects(desc, [side], plane_ids, xyz)[0]
            rest = tuple(x for x in a.labels if x not in set(cut))
            out.append(replace(a, labels=rest, planes=tuple(plane_ids[x] for x in rest),
                               cut_off=tuple(a.cut_off) + (side.id,)))
            out.append(replace(b, cut_from=a.object_id))
        return tuple(out)

    def _hanging(self, desc, answers, xyz) -> tuple:
        """``decision.hang_gate``: each ``box`` answer whose upright proof faces (those with
        at least ``hang_lines`` image lines showing anything beneath them) all hang
        (:func:`~planerel.features.hang.face_hang`) with no horizontal plane at their lower
        edge (:func:`~planerel.features.hang.supported`) becomes ``other``, with a
        :class:`~planerel.ilp.metrics.HangRefusal`."""
        from planerel.features.hang import face_hang, supported
        from planerel.ilp.metrics import HangRefusal

        share, drop, level, lines = self.hang
        planes = {p.label: p for p in desc.planes}
        ids = {desc.plane_id(p.label): p.label for p in desc.planes}
        lab = desc.labels
        if lab is None or np.asarray(lab).shape != np.asarray(xyz).shape[:2]:
            return answers
        out = []
        for a in answers:
            if a.klass == BOX:
                faces = [ids[i] for i in a.proof_planes
                         if i in ids and planes[ids[i]].orientation == "vertical"]
                hangs = [face_hang(f, desc.planes.up, desc.planes.floor_level, xyz, lab,
                                   drop=drop, level=level) for f in faces]
                hangs = [h for h in hangs if h is not None and h.seen >= lines]
                if hangs and all(h.share >= share for h in hangs) and not any(
                        supported(desc.planes, h, xyz, lab, level=level) for h in hangs):
                    why = HangRefusal(BOX, a.rule_index or 0,
                                      tuple(desc.plane_id(h.face) for h in hangs),
                                      min(h.share for h in hangs), max(h.bottom for h in hangs))
                    a = _refuse(a, why)
            out.append(a)
        return tuple(out)

    def _long_lying(self, desc, answers) -> tuple:
        """``decision.long_lying_gate``: each ``box`` answer whose proof planes hold no
        upright plane and a top longer than ``long_lying_length`` becomes ``other``, with a
        :class:`~planerel.ilp.metrics.LongLyingRefusal`."""
        from planerel.ilp.metrics import LongLyingRefusal

        ids = {desc.plane_id(p.label): p for p in desc.planes}
        out = []
        for a in answers:
            if a.klass == BOX:
                proof = [ids[i] for i in a.proof_planes if i in ids]
                tops = [p for p in proof if p.orientation != "vertical"]
                if tops and len(tops) == len(proof):
                    top = max(tops, key=lambda p: p.length)
                    if top.length > self.long_lying:
                        why = LongLyingRefusal(BOX, a.rule_index or 0, desc.plane_id(top.label),
                                               float(top.length), float(self.long_lying))
                        a = _refuse(a, why)
            out.append(a)
        return tuple(out)

    def _slabs(self, desc, answers, xyz) -> tuple:
        """``decision.slab_gate``: each ``box`` answer whose proof binds a top (a plane not
        upright) at most ``slab_width`` wide under which an upright plane of its object reaches
        ``slab_drop`` or more (:func:`~planerel.features.slab.slab_edge`) becomes ``other``,
        with a :class:`~planerel.ilp.metrics.SlabRefusal`."""
        from planerel.features.slab import slab_edge
        from planerel.ilp.metrics import SlabRefusal

        lab = desc.labels
        if lab is None or np.asarray(lab).shape != np.asarray(xyz).shape[:2]:
            return answers
        width, drop = self.slab
        ids = {desc.plane_id(p.label): p for p in desc.planes}
        by_label = {p.label: p for p in desc.planes}
        out = []
        for a in answers:
            if a.klass == BOX:
                tops = [ids[i] for i in a.proof_planes
                        if i in ids and ids[i].orientation != "vertical"]
                faces = [by_label[x] for x in a.labels
                         if x in by_label and by_label[x].orientation == "vertical"]
                for t in tops:
                    e = slab_edge(desc.planes, desc.relations, t, faces, xyz, lab, width, drop)
                    if e is not None:
                        a = _refuse(a, SlabRefusal(BOX, a.rule_index or 0, desc.plane_id(e.top),
                                                   desc.plane_id(e.face), e.width, e.drop))
                        break
            out.append(a)
        return tuple(out)

    def _crowded(self, answers) -> tuple:
        """``decision.crowd_gate``: each ``box`` answer whose object holds more than
        ``crowd_planes`` planes becomes ``other``, with a
        :class:`~planerel.ilp.metrics.CrowdRefusal`."""
        from planerel.ilp.metrics import CrowdRefusal

        return tuple(_refuse(a, CrowdRefusal(BOX, a.rule_index or 0, len(a.labels), self.crowd))
                     if a.klass == BOX and len(a.labels) > self.crowd else a for a in answers)

    def _far_proofs(self, desc, answers) -> tuple:
        """``decision.far_gate``: each ``box`` or ``ramp`` answer whose proof binds a plane of
        ``desc.far`` (found only by the segmentation's far growing) becomes ``other``, with a
        :class:`~planerel.ilp.metrics.FarPlaneRefusal`; ``stairs`` may use them."""
        from planerel.ilp.metrics import FarPlaneRefusal

        far = {desc.plane_id(lab) for lab in desc.far}
        out = []
        for a in answers:
            if a.klass in FAR_GATED:
                hit = tuple(i for i in a.proof_planes if i in far)
                if hit:
                    a = _refuse(a, FarPlaneRefusal(a.klass, a.rule_index or 0, hit))
            out.append(a)
        return tuple(out)

    def _narrow_faces(self, desc, answers, xyz) -> tuple:
        """``decision.narrow_face_gate``: each ``box`` answer whose upright proof faces that
        the image does not cut at its left or right all stand more than ``narrow_face_ratio``
        times as tall as they are wide (:func:`~planerel.features.face_shape.face_extent`)
        becomes ``other``, with a :class:`~planerel.ilp.metrics.NarrowFaceRefusal`."""
        from planerel.features.face_shape import face_extent
        from planerel.ilp.metrics import NarrowFaceRefusal

        def measure(face, up, xyz, lab):
            e = face_extent(face, up, xyz, lab)
            return e if e is not None and not e.cut else None

        def refusal(a, ext):
            if not all(e.ratio > self.narrow_face for e in ext):
                return None
            return NarrowFaceRefusal(BOX, a.rule_index or 0,
                                     tuple(desc.plane_id(e.face) for e in ext),
                                     min(e.ratio for e in ext), float(self.narrow_face))

        return _proof_plane_gate(desc, answers, xyz, BOX, "vertical", measure, refusal)

    def _slope_parts(self, desc, answers, xyz) -> tuple:
        """``decision.slope_parts_gate``: each ``ramp`` answer whose sloping proof planes
        (those :func:`~planerel.features.slope_parts.slope_parts` can judge) each have a part
        sloping more than ``slope_parts_tol`` off the whole's slope becomes ``other``, with a
        :class:`~planerel.ilp.metrics.SlopePartsRefusal`."""
        from planerel.features.slope_parts import slope_parts
        from planerel.ilp.metrics import SlopePartsRefusal

        def refusal(a, parts):
            if not all(q.worst > self.slope_parts for q in parts):
                return None
            return SlopePartsRefusal("ramp", a.rule_index or 0,
                                     tuple(desc.plane_id(q.plane) for q in parts),
                                     tuple(q.shares for q in parts), float(self.slope_parts))

        return _proof_plane_gate(desc, answers, xyz, "ramp", "inclined", slope_parts, refusal)

    def _flight_sides(self, desc, answers, xyz) -> tuple:
        """``decision.flight_side_gate``: each ``box`` answer that runs beside a flight
        answered ``stairs`` in the same scan (:func:`~planerel.features.flight_side.beside_flight`)
        becomes ``other``, with a :class:`~planerel.ilp.metrics.FlightSideRefusal`."""
        from planerel.features.flight_side import beside_flight, flight_geometry
        from planerel.ilp.metrics import FlightSideRefusal

        flights = [a for a in answers if a.klass == "stairs"]
        if not flights or not any(a.klass == BOX for a in answers):
            return answers
        thick, gap, reach, rise, angle = self.flight_side
        geometry = {}   # each flight's frame and points, measured once
        out = []
        for a in answers:
            if a.klass == BOX:
                for f in flights:
                    if set(f.labels) & set(a.labels):
                        continue
                    if f.object_id not in geometry:
                        geometry[f.object_id] = flight_geometry(desc.planes, f.labels, xyz,
                                                                desc.labels)
                    if geometry[f.object_id] is None:
                        continue
                    m = beside_flight(desc.planes, geometry[f.object_id], a.labels, xyz,
                                      desc.labels)
                    if m is not None and m.beside(thick, gap, reach, rise, angle):
                        why = FlightSideRefusal(BOX, a.rule_index or 0, f.object_id, m.thick,
                                                m.gap, m.rise)
                        a = _refuse(a, why)
                        break
            out.append(a)
        return tuple(out)

    def _answer_objects(self, desc, objects, plane_ids, xyz) -> list:
        """``objects`` (SceneObjects over ``desc``'s planes) answered as :meth:`_answer`
        answers a description's own."""
        sub = replace(desc, objects=tuple(objects))
        with _scene_facts(sub, "cut"):
            if self.members:
                return _voted([m._answer(sub, plane_ids, xyz) for m in self.members])
            return self._answer(sub, plane_ids, xyz)

    def _cut_boxes(self, desc, answers, plane_ids, xyz, only=None) -> tuple:
        """``decision.cut_boxes``: each proposal (of the object ids ``only``, when given; one
        not cut already) a box rule proves and a gate refuses ``box`` for, whose planes hold a
        box proof's solid (:func:`~planerel.features.box_cut.box_solids`) smaller than itself:
        the solids decided as objects of their own; those answered ``box`` by a rule that
        proved the proposal (largest first, sharing no plane) cut from it, and the rest
        decided again (its class or ``other``).  With ``decision.cut_split`` a proposal
        answered ``box`` is split so too, into two or more solids answered ``box`` by any box
        rule, no two with one top (:func:`~planerel.features.box_cut.one_box_in_pieces`);
        fewer leave it whole."""
        from planerel.features._defaults import defaults
        from planerel.features.box_cut import box_solids, cut_object, one_box_in_pieces
        from planerel.features.curved import CurvedParams
        from planerel.features.facts import SceneObject
        from planerel.ilp.metrics import FacetRefusal

        reach, margin, corner, pieces = self.cut_boxes
        cp = self._describe_kw.get("curved_params") or defaults(CurvedParams)
        facet = (cp.facet_min_angle, cp.facet_max_angle)
        subs, parent_of, rules_of, split = [], {}, {}, set()
        # the proposals as answered (a flight's trim or an earlier cut may have added parts)
        objects = {o.id: o for o in desc.objects}
        for a in answers:
            o = objects.get(a.object_id)
            if o is None or a.cut_from is not None or a.cut_off or (
                    only is not None and o.id not in only):
                continue
            # only where a box rule proves the proposal and a gate refuses it: a proposal no
            # box rule proves (a tall face beside a horizontal plane: ``nhorizontal(A,0)``
            # does not hold) is not cut for a rule that holds on a part of it, and one whose
            # box proof is answered another class unrefused (a flight's step) stays that class
            rules_of[o.id] = _box_rules(a)
            # a facet refusal (``decision.facet_gate``) is about the proposal's own round
            # side: cutting the proof's cap and facet from their neighbour facet would undo it
            if a.klass == BOX:
                # split79: a box answer is cut only into two or more boxes of its own
                if not self.cut_split or not rules_of[o.id]:
                    continue
                split.add(o.id)
            elif (not rules_of[o.id]
                    or not any(getattr(r, "klass", None) == BOX
                               and not isinstance(r, FacetRefusal)
                               for v in (a, *a.votes) for r in v.refused)):
                continue
            # two boxes set at an angle meet as a round surface's facets do: a split keeps a
            # solid beside them (each solid still passes every gate on its own)
            solids = box_solids(desc, o.planes, reach, facet, 2 if o.id in split else corner,
                                pieces)
            for k, solid in enumerate(solids, start=1):
                s = cut_object(desc, o, solid, f"{o.id}_c{k}", xyz, tiny_area=cp.tiny_area,
                               curved_below=cp.curved_below, margin=margin)
                subs.append(s)
                parent_of[s.id] = o.id
        if not subs:
            return answers
        taken: dict[str, list] = {}
        for s, a in zip(subs, self._answer_objects(desc, subs, plane_ids, xyz), strict=True):
            if a.klass != BOX or (parent_of[s.id] not in split
                                  and not _box_rules(a, chosen=True) & rules_of[parent_of[s.id]]):
                continue
            mine = taken.setdefault(parent_of[s.id], [])
            if any(set(s.planes) & set(b.labels) for b in mine):
                continue
            mine.append(replace(a, cut_from=parent_of[s.id]))
        # a box answer stays whole unless two or more boxes of its own come out of it, no
        # two of them one box in pieces (an occluder in front of it)
        taken = {k: v for k, v in taken.items()
                 if k not in split or (len(v) >= 2 and not one_box_in_pieces(
                     desc, [b.labels for b in v]))}
        if not taken:
            return answers
        rests = []
        for k, boxes in taken.items():
            o = objects[k]
            cut = {x for b in boxes for x in b.labels}
            rests.append(SceneObject(o.id, tuple(x for x in o.planes if x not in cut), None,
                                     o.mask, o.planar_fraction, o.curved))
        rest = {r.object_id: r for r in self._answer_objects(desc, rests, plane_ids, xyz)}
        out = []
        for a in answers:
            if a.object_id not in taken or a.cut_from is not None:
                out.append(a)
                continue
            r = rest[a.object_id]
            if r.klass not in (a.klass, OTHER):
                r = ObjectAnswer(r.object_id, r.planes, r.labels, OTHER, fired=r.fired,
                                 planar_fraction=r.planar_fraction, curved=r.curved,
                                 refused=r.refused)
            out.append(replace(r, cut_off=tuple(b.object_id for b in taken[a.object_id])))
            out.extend(taken[a.object_id])
        return tuple(out)

    def _check_open(self) -> None:
        if not self.module:
            raise InputError(f"{self.rules_path}: this classifier was closed")

    def _answer(self, desc, plane_ids, xyz=None) -> list:
        """Each object of ``desc`` (its facts loaded) answered by this model's rules (``xyz``:
        the scan's points, for the foot gate)."""
        from planerel.features.step_chains import flight_evidence, flight_faces
        from planerel.ilp.metrics import (
            SIDE_PLANES,
            UNSURE_CLASS,
            decide,
            horizontal_counts,
            plane_extents,
            plane_ranges,
            plane_slenderness,
        )

        answers = []
        levels = horizontal_counts((desc,))
        extents = (functools.cache(lambda: plane_extents((desc,))) if self.size_domain
                   else None)
        slender = (functools.cache(lambda: plane_slenderness((desc,))) if self.slender_domain
                   else None)
        distances = (functools.cache(lambda: plane_ranges((desc,))) if self.range_domain
                     else None)
        foot = None
        if self.foot_gate and xyz is not None and "ramp" in self.classes:
            from planerel.features.foot import slope_foot

            by_id = {pid: lab for lab, pid in plane_ids.items()}
            ps = desc.planes

            @functools.cache
            def foot(pid):
                lab = by_id.get(pid)
                if lab is None or ps.by_label(lab).orientation != "inclined":
                    return None
                return slope_foot(ps, lab, xyz, labels=desc.labels)
        side = None  # as the foot gate: classify's own (a scan's) decision, not the learner's
        if self.side_gate and xyz is not None and set(SIDE_PLANES) & set(self.classes):
            side_by_id = {pid: lab for lab, pid in plane_ids.items()}
            up_v = np.asarray(desc.planes.up, dtype=np.float64)

            def side(pid):
                lab = side_by_id.get(pid)
                if lab is None:
                    return None
                p = desc.planes.by_label(lab)
                return p.orientation, float(np.asarray(p.normal, dtype=np.float64) @ up_v)
        unsure = None  # as the foot gate: classify's own (a scan's) decision
        if self.unsure_gate and xyz is not None and UNSURE_CLASS in self.classes:
            gravity = self._describe_kw.get("gravity_params")
            if (desc.planes.floor is None
                    and desc.planes.up_low(None if gravity is None else gravity.low_confidence)):
                unsure = float(desc.planes.up_confidence)
            elif (self.unsure_sparse and desc.planes.floor is None
                  and desc.planes.up_sparse_floor and desc.planes.up_source == "estimated"):
                # a speckle fit of the image's low unassigned points decided the up, and no
                # floor plane attests it
                unsure = (float(desc.planes.up_confidence), False, True)
            elif (self.unsure_upside and desc.planes.up_upside_down
                  and desc.planes.up_source == "estimated"):
                # with or without a floor: under a wrong flip the "floor" is the ceiling
                unsure = (float(desc.planes.up_confidence), True)
        proposal_params = self._describe_kw.get("proposal_params")
        facet_angles = None
        if self.facet_gate is not None and xyz is not None and "box" in self.classes:
            from planerel.features._defaults import defaults
            from planerel.features.curved import CurvedParams

            cp = self._describe_kw.get("curved_params") or defaults(CurvedParams)
            facet_angles = _facet_angles(desc, xyz, plane_ids, cp.facet_max_width,
                                         cp.facet_wide_ratio,
                                         self.facet_gate if self.facet_bridge else None)
        pitch_of = None
        if self.pitch_tol is not None and {"ramp", "stairs"} <= set(self.classes):
            pitch_of = _pitch_gate(desc, plane_ids, proposal_params)
        for o in desc.objects:
            facet = None
            if facet_angles is not None:
                def facet(pid, mine=frozenset(o.planes), table=facet_angles):
                    return _facet_of(table(pid, mine), *self.facet_gate)
            hits = []
            # the proof scale only when the proof gate or the vetoes' ratio uses it
            scale_goal = (f", planerel_proof_scale({self.module}, {_obj_atom(o.id)}, I, S)"
                          if self.proof_domain or self.veto_ratio else ", S = none")
            for r in query(f"planerel_explain_text({self.module}, {_obj_atom(o.id)}, "
                            f"C, I, B, T){scale_goal}",
                            f"classifying {o.id}"):
                binds = _bindings(_text(r["B"]))
                scale = r["S"] if isinstance(r["S"], (int, float)) else None
                hits.append((_text(r["C"]), int(r["I"]), binds, _text(r["T"]), scale))

            # the decision on some of the hits (all of them, or the runner-up's: _decided)
            def decided(hs, o=o, facet=facet):
                return decide(hs, self.stats, self.classes, self.cofire,
                              planar_fraction=o.planar_fraction,
                              domain=self.planar_domain,
                              margin=self.planar_margin,
                              proofs=self.proof_domain,
                              proof_margin=self.proof_margin,
                              proof_min_positives=self.proof_min_positives,
                              veto_ratio=self.veto_ratio,
                              n_horizontal=levels.get(o.id),
                              levels=self.level_domain,
                              stepped=lambda o=o: flight_faces(desc.planes, o.planes,
                                                               proposal_params),
                              flight=(lambda o=o: flight_evidence(
                                  desc.planes, o.planes, proposal_params,
                                  fragments=self.flight_fragments))
                              if self.flight_gate else None,
                              extents=extents, sizes=self.size_domain,
                              size_margin=self.size_margin, slender=slender,
                              slenders=self.slender_domain,
                              slender_margin=self.slender_margin,
                              distances=distances, ranges=self.range_domain,
                              range_margin=self.range_margin, foot=foot,
                              foot_above=self.foot_bounds[0],
                              foot_below=self.foot_bounds[1],
                              foot_hidden=self.foot_bounds[2],
                              foot_float=self.foot_bounds[3], side=side,
                              treads=() if side is None else
                              [f[1] for f in (side(plane_ids.get(lab))
                                              for lab in o.planes)
                               if f is not None and f[0] == "horizontal"],
                              under_eye=side is not None
                              and any(h[0] == "stairs" for h in hs)
                              and _under_eye(desc.planes, o.planes),
                              unsure=unsure, facet=facet,
                              pitch=None if pitch_of is None else pitch_of(o.planes),
                              pitch_tol=self.pitch_tol or 0.0)
            fired = tuple(sorted({(h[0], h[1]) for h in hits}, key=lambda t: t[1]))
            pids = tuple(plane_ids[lab] for lab in o.planes)
            answers.append(self._decided(decided, hits, o, pids, fired, plane_ids))
        return answers

    def _decided(self, decided, hits, o, pids, fired, plane_ids) -> ObjectAnswer:
        """The answer ``decided(hits)`` (:func:`~planerel.ilp.metrics.decide` with the object's
        gates) gives object ``o``, with its runner-up: the answer without the chosen class's
        hits (a class, or None), for a gate after the decision to fall back to."""
        from planerel.ilp.metrics import laplace

        best, refused = decided(hits)
        if best is None:
            return ObjectAnswer(o.id, pids, o.planes, OTHER, fired=fired,
                                planar_fraction=o.planar_fraction, curved=o.curved,
                                refused=refused)
        klass, index, binds, rule = best[:4]
        proof = tuple(v for v in binds.values() if v in plane_ids.values())
        tp, fp = {i: (a, b) for i, _, a, b in self.stats}.get(index, (0, 0))
        rest = [h for h in hits if h[0] != klass]
        nxt = self._decided(decided, rest, o, pids, fired, plane_ids) if rest else None
        return ObjectAnswer(o.id, pids, o.planes, klass, rule, binds, proof, fired, index,
                            laplace(tp, fp), o.planar_fraction, o.curved, refused,
                            runner_up=nxt if nxt is not None and nxt.klass != OTHER else None)


def _facet_angles(desc, xyz, plane_ids, wide_width: float = 0.05, wide_ratio: float = 1.5,
                  bridge=None):
    """``angles(plane id, object's plane labels) -> (facet angles, corner)`` for a scene: the
    angles (degrees) to the plane of every adjacent upright plane of the object that meets it
    as ``face_pair``'s shape test asks (widths, level tops and bottoms, convex), and whether
    one of them meets it at ``relations.face_pair_angle`` or more (a box's corner); ``((),
    False)`` for a plane that is not upright (:attr:`~planerel.ilp.metrics.DecisionParams.facet_gate`).

    As in :func:`planerel.features.curved.facet_planes`, strips of one round surface are alike
    in width: a neighbour below the corner angle counts only when the wider of the two is under
    ``wide_width`` m or less than ``wide_ratio`` times the narrower (``curved.facet_max_width``,
    ``curved.facet_wide_ratio``); a box face with a bevel strip along its edge is no facet.
    With ``bridge`` ``(low, high)`` degrees (``decision.facet_bridge``), a corner partner is no
    corner when a third plane of the object meets both, each as such a facet at ``low``-``high``
    degrees: the two ends of a round side's fan of three strips, not two faces of a box."""
    from planerel.features.solid import face_profile_of, is_face_pair

    ps = desc.planes
    p = desc.relations.params
    up = np.asarray(ps.up, dtype=np.float64)
    by_id = {pid: lab for lab, pid in plane_ids.items()}
    profile = functools.cache(lambda lab: face_profile_of(ps.by_label(lab), up, ps.labels, xyz))

    @functools.cache
    def links(lab, mine):
        """``((other, angle, corner), ...)`` over the object's upright planes ``lab`` meets."""
        a = ps.by_label(lab)
        out = []
        for other in sorted(mine):
            if other == lab:
                continue
            b = ps.by_label(other)
            if b is None or b.orientation != "vertical":
                continue
            r = desc.relations.get(lab, other)
            if r is None or not r.adjacent:
                continue
            if not is_face_pair(a, b, profile(lab), profile(other), p.face_pair_level,
                                p.face_pair_width, p.face_pair_level_share):
                continue
            if r.angle < p.face_pair_angle:
                wide, narrow = max(a.width, b.width), min(a.width, b.width)
                if wide >= wide_width and wide >= wide_ratio * narrow:
                    continue
            out.append((other, float(r.angle), r.angle >= p.face_pair_angle))
        return tuple(out)

    def facets(lab, mine):
        low, high = bridge
        return {o for o, ang, c in links(lab, mine) if not c and low <= ang <= high}

    @functools.cache
    def angles(pid, mine):
        lab = by_id.get(pid)
        if lab is None or lab not in mine or ps.by_label(lab).orientation != "vertical":
            return (), False
        mine_links = links(lab, mine)
        own = facets(lab, mine) if bridge is not None else set()
        # (``own`` empty: no bridge, or no facet neighbour to bridge through)
        corner = any(c and not (own and own & facets(other, mine))
                     for other, _ang, c in mine_links)
        return tuple(ang for _o, ang, _c in mine_links), corner

    return angles


def _facet_of(found, low: float, high: float):
    """The facet gate's verdict on one plane from :func:`_facet_angles`' ``(angles, corner)``:
    the first angle in ``low``-``high`` degrees when the plane has no corner partner, else None."""
    angles, corner = found
    if corner:
        return None
    return next((a for a in angles if low <= a <= high), None)


@contextlib.contextmanager
def _scene_facts(desc, prefix: str):
    """The Prolog facts of scene description ``desc`` loaded for the ``with`` block (written to
    a temporary file named with ``prefix``, unloaded and removed after it)."""
    from planerel.children import temp_prefix
    from planerel.features.facts import FactParams, facts_text
    from planerel.ilp.aleph_export import PAIRS

    text = facts_text([desc], FactParams(pairs=PAIRS, planner=False))
    with tempfile.NamedTemporaryFile("w", suffix=".pl", prefix=temp_prefix(prefix),
                                     delete=False) as fh:
        fh.write(text)
        facts = Path(fh.name)
    try:
        load_file(facts, "cannot load the scene facts")
        yield
    finally:
        unload_file(facts, "cannot unload the scene facts")
        facts.unlink(missing_ok=True)


def _voted(per_member: list) -> list:
    """The members' answers (one list per member, objects in the same order) joined by the
    vote (:func:`planerel.ilp.members.vote`)."""
    from planerel.ilp.members import vote

    out = []
    for answers in zip(*per_member, strict=True):
        klass, n = vote([(a.klass, a.precision if a.rule else None) for a in answers])
        out.append(replace(answers[n], klass=klass, votes=tuple(answers), member=n + 1,
                           runner_up=None))
    return out


#: where one "Name\tValue" line of planerel_explain_text's bindings starts: a Prolog variable
#: name and a tab (a value, a scene's plane id, may hold line breaks of its file's name)
_BINDING_START = re.compile(r"(?:^|\n)(?=[A-Z_][A-Za-z0-9_]*\t)")


def _bindings(text: str) -> dict[str, str]:
    """The ``{variable: value}`` of planerel_explain_text's bindings text."""
    return dict(line.split("\t", 1) for line in _BINDING_START.split(text) if "\t" in line)


def _obj_atom(name: str) -> str:
    from planerel.features.terms import atom

    return atom(name)


def _text(value) -> str:
    if isinstance(value, bytes):
        return value.decode("utf-8", "replace")
    return str(value)


def explanation_image(answer: SceneAnswer, depth) -> np.ndarray:
    """``(H, W, 3)`` uint8 picture: the proof planes of each classified object in bright
    colours, the object's other planes tinted, everything else shaded grey by depth."""
    from planerel.io.writers import colour_labels, label_colours

    lab = np.asarray(answer.labels)
    grey = colour_labels(np.full_like(lab, -1), depth).astype(float)
    out = grey.copy()
    pal = label_colours(max(1, len(answer.objects) * 4 + 4)).astype(float)
    inv = {v: k for k, v in answer.plane_ids.items()}
    for n, o in enumerate(answer.objects):
        if o.klass == OTHER:
            for lab_id in o.labels:
                m = lab == lab_id
                out[m] = 0.7 * grey[m] + 0.3 * np.array([120, 120, 160])
            continue
        for lab_id in o.labels:
            m = lab == lab_id
            out[m] = 0.5 * grey[m] + 0.5 * np.array([255, 255, 255])
        for k, pid in enumerate(o.proof_planes):
            m = lab == inv[pid]
            out[m] = 0.25 * grey[m] + 0.75 * pal[(n * 4 + k) % len(pal)]
    return np.clip(np.round(out), 0, 255).astype(np.uint8)


def classify_dataset(classifier: Classifier, dataset_dir, *, out_dir=None,
                     progress: bool | None = None) -> dict:
    """Classify every scene of a data set with ground truth and score the answers.

    A scene's answer is the class given to the object proposal that overlaps the scene's
    ground-truth object (object 1: the primary object of a varied-world scene) most
    (intersection over union of their pixels); ``other`` when no
    proposal overlaps it or no rule fires.  With ``out_dir``, writes per scene
    ``ID.classified.png`` and ``ID.classified.json``.

    Returns
    -------
    dict
        ``accuracy``, ``per_class``, ``classes``, ``confusion`` (rows true class, columns
        predicted, ``other`` last), ``scenes`` (per scene: id, class, predicted, rule, proof
        planes, IoU of the chosen proposal), ``proposal_match`` (fraction of scenes whose best
        proposal covers the true object with IoU >= 0.8), ``ms_per_scene``.
    """

    from planerel.features.dataset import iter_scenes
    from planerel.ilp.metrics import accuracy_scores, confusion_matrix

    rows = []
    times = []
    it = progress_bar(iter_scenes(dataset_dir), desc="classifying", enabled=progress)
    for row, cloud, gt, meta in it:
        ans = classifier.classify(cloud, scene_id=row.scene_id)
        times.append(ans.seconds)
        # the scene's object: object 1 (in a varied-world scene the primary object, whose
        # class is the manifest's; the others are scored by cross-validation, not here)
        obj_planes = {int(p["index"]) for p in meta.get("planes", [])
                      if int(p.get("object_index", 0)) == 1}
        truth = np.isin(gt, list(obj_planes)) if gt is not None else None
        best, best_iou = None, 0.0
        for o in ans.objects:
            mask = np.isin(ans.labels, list(o.labels))
            if truth is None:
                continue
            inter = np.count_nonzero(mask & truth)
            iou = inter / max(1, np.count_nonzero(mask | truth))
            if iou > best_iou:
                best, best_iou = o, iou
        rows.append({"scene": row.scene_id, "class": row.klass,
                     "predicted": best.klass if best else OTHER,
                     "rule": best.rule if best else None,
                     "proof_planes": list(best.proof_planes) if best else [],
                     "iou": round(best_iou, 3), "objects": len(ans.objects)})
        if out_dir is not None:
            from PIL import Image

            from planerel.atomic import atomic_path
            from planerel.io.writers import write_json

            out = Path(out_dir)
            with atomic_path(out / f"{row.scene_id}.classified.png", suffix=".png") as tmp:
                Image.fromarray(explanation_image(ans, cloud.depth)).save(tmp, format="PNG")
            write_json(out / f"{row.scene_id}.classified.json", ans.to_dict())
    classes = [k for k in classifier.classes]
    classes += sorted({r["class"] for r in rows} - set(classes))
    truth = [r["class"] for r in rows]
    pred = [r["predicted"] for r in rows]
    acc, per = accuracy_scores(truth, pred, classes)
    matched = [r["iou"] >= 0.8 for r in rows]
    return {"accuracy": acc, "per_class": per, "classes": classes,
            "confusion": confusion_matrix(truth, pred, classes), "scenes": rows,
            "proposal_match": sum(matched) / len(matched) if matched else None,
            "ms_per_scene": round(1000 * float(np.median(times)), 2) if times else None}
