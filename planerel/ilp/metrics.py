"""Answers in, scores out: the open-set decision among the rules that fired (:func:`choose_class`,
by the Laplace precision of :func:`laplace`), stratified folds, confusion matrices and
accuracies (:func:`score_objects`).  Plain arithmetic on labels; no Prolog, no files.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from planerel.errors import InputError

__all__ = ["OTHER", "laplace", "takes_part", "choose_class", "error_kinds", "stratified_folds",
           "confusion_columns", "confusion_matrix", "accuracy_scores", "score_objects",
           "PLANAR_MARGIN", "PLANAR_GATE", "DecisionParams", "planar_domain", "gated_negatives",
           "Refusal", "planar_bound",
           "planar_refusals", "PROOF_MARGIN", "PROOF_GATE", "PROOF_MIN_POSITIVES", "proof_domain", "proof_bound", "ProofRefusal",
           "LEVEL_GATE", "horizontal_counts", "level_domain", "LevelRefusal", "level_refusals",
           "proof_refusals", "VETO_RATIO", "VetoRefusal", "veto_refusals", "FLIGHT_GATE",
           "FLIGHT_FRAGMENTS", "FLIGHT_CLASS", "FlightRefusal", "flight_refusals", "FOOT_GATE", "FOOT_ABOVE",
           "FOOT_BELOW", "FOOT_HIDDEN", "FOOT_FLOAT", "FOOT_CLASS", "FootRefusal", "foot_refusals",
           "SIDE_GATE", "SIDE_PLANES", "SideRefusal", "side_refusals",
           "FACET_GATE", "FACET_MIN", "FACET_MAX", "FACET_CLASS", "FacetRefusal", "facet_refusals",
           "UNSURE_GATE", "UNSURE_CLASS", "UNSURE_UPSIDE", "UnsureRefusal", "unsure_refusals",
           "FLIGHT_SIDE_GATE", "FlightSideRefusal",
           "SIZE_GATE", "SIZE_MARGIN",
           "SIZE_CLASSES", "size_gated", "proof_extent", "plane_extents", "size_domain", "SizeRefusal", "size_refusals",
           "SLENDER_GATE", "SLENDER_MARGIN", "SLENDER_CLASSES", "plane_slenderness",
           "proof_slenderness", "slender_domain", "SlenderRefusal", "slender_refusals",
           "RANGE_GATE", "RANGE_MARGIN", "RANGE_CLASSES", "plane_ranges", "proof_range",
           "range_domain", "RangeRefusal", "range_refusals", "decide"]

#: The answer "none of the classes": no rule fires, or every rule that fires is wrong more often
#: than right on the training objects (the class of the varied world's clutter, too).
OTHER = "other"
#: Former name of :data:`OTHER` (the answer used to be ``"unknown"``).
UNKNOWN = OTHER


def laplace(tp: int, fp: int) -> float:
    """Laplace estimate of a rule's precision, ``(tp + 1) / (tp + fp + 2)``."""
    return (tp + 1) / (tp + fp + 2)


def _refuse_hits(hits, stats: Sequence, refuse):
    """The hits a gate keeps, and its refusals: ``refuse(hit)`` is None for a hit kept, else
    the refusal that leaves it out; one refusal is reported per rule, and only for a rule
    that takes part in the decision (:func:`takes_part`; a rule that does not is left out
    all the same)."""
    table = {i: (tp, fp) for i, _, tp, fp in stats}
    kept, refused = [], {}
    for hit in hits:
        why = refuse(hit)
        if why is None:
            kept.append(hit)
        elif hit[1] not in refused and takes_part(*table.get(hit[1], (0, 0))):
            refused[hit[1]] = why
    return kept, tuple(refused.values())


def takes_part(tp: int, fp: int) -> bool:
    """Whether a rule with ``tp`` right and ``fp`` wrong training objects takes part in the
    decision: not when it was wrong at least as often as right (``fp >= tp``, ``fp > 0``)."""
    return not (fp > 0 and fp >= tp)


def choose_class(hits, stats: Sequence, classes: Sequence[str], cofire: Sequence = ()):
    """Pick one answer among the rules that fired (an open-set decision for one object).

    A rule's precision is its Laplace estimate :func:`laplace` on the training objects
    (``stats``, stored in the model; the ``other`` objects a rule covers count as its false
    positives).  A rule that was wrong at least as often as right in training (``fp >= tp``,
    ``fp > 0``: precision at most 0.5) does not count: an object it proves is at least as likely
    *not* of its class.  Of the rest, the highest precision wins; ties go to the rule that
    covered more training objects, then to the earlier class and rule.  Class frequencies play
    no part.  A rule without statistics (hand-written rules) counts with precision 0.5.  No rule
    left: ``None``, the answer :data:`OTHER` (none of the classes).

    When rules of two or more classes are left and ``cofire`` is given (``(i, j, class, n)``:
    ``n`` training objects of ``class`` on which rules ``i`` and ``j`` both fired, ``i < j``),
    each pair of classes is decided on the training objects where their rules fired together:
    the class with more of them wins the pair (the Laplace estimates ``(n_x + 1) / (n + 2)`` of
    the two classes on those objects compared); a pair without such objects, or with as many
    of each, is decided by the precision above.  The class that wins most pairs is the answer
    (ties: the precision order), with its most precise rule.  A box rule and a stairs rule of
    nearly equal precision that both prove a flight seen with one tread are then told apart by
    what the training objects proved by both were.
    """
    table = {i: (tp, fp) for i, _, tp, fp in stats}
    order = {k: n for n, k in enumerate(classes)}
    kept = []
    for hit in hits:
        tp, fp = table.get(hit[1], (0, 0))
        if not takes_part(tp, fp):
            continue
        kept.append((-laplace(tp, fp), -tp, order.get(hit[0], len(order)), hit[1], hit))
    if not kept:
        return None
    kept.sort(key=lambda t: t[:4])
    best_of = {}                             # class -> its best kept hit (precision order)
    for t in kept:
        best_of.setdefault(t[4][0], t)
    if len(best_of) < 2 or not cofire:
        return kept[0][-1]
    together: dict = {}
    for i, j, k, n in cofire:
        together.setdefault((min(i, j), max(i, j)), {})[k] = n
    rules_of: dict = {}
    for t in kept:
        rules_of.setdefault(t[4][0], set()).add(t[4][1])
    ranked = list(best_of)                   # classes in precision order
    wins = dict.fromkeys(ranked, 0)
    for x_pos, x in enumerate(ranked):
        for y in ranked[x_pos + 1:]:
            nx = ny = 0
            for a in rules_of[x]:
                for b in rules_of[y]:
                    counts = together.get((min(a, b), max(a, b)), {})
                    nx += counts.get(x, 0)
                    ny += counts.get(y, 0)
            wins[y if ny > nx else x] += 1   # equal counts: the more precise class x
    top = max(wins.values())
    winner = next(k for k in ranked if wins[k] == top)
    return best_of[winner][-1]


#: Default of :attr:`DecisionParams.planar_margin`.
PLANAR_MARGIN = 0.3
#: Default of :attr:`DecisionParams.planar_gate` (on since facets22: docs/objects.md).
PLANAR_GATE = True
#: Default of :attr:`DecisionParams.proof_margin`.
PROOF_MARGIN = 0.3
#: Default of :attr:`DecisionParams.proof_gate`.
PROOF_GATE = True
#: Default of :attr:`DecisionParams.proof_min_positives`.
PROOF_MIN_POSITIVES = 10
#: Default of :attr:`DecisionParams.veto_ratio`.
VETO_RATIO = 3.0
#: Default of :attr:`DecisionParams.level_gate`.
LEVEL_GATE = True
#: Default of :attr:`DecisionParams.flight_gate`.
FLIGHT_GATE = True
#: Default of :attr:`DecisionParams.flight_fragments`.
FLIGHT_FRAGMENTS = True
#: The class :func:`flight_refusals` asks a flight's steps of.
FLIGHT_CLASS = "stairs"
#: Default of :attr:`DecisionParams.size_gate`.
SIZE_GATE = True
#: Default of :attr:`DecisionParams.size_margin`.
SIZE_MARGIN = 0.2
#: Default of :attr:`DecisionParams.size_classes`.
SIZE_CLASSES = "box"
#: Default of :attr:`DecisionParams.slender_gate`.
SLENDER_GATE = True
#: Default of :attr:`DecisionParams.slender_margin`.
SLENDER_MARGIN = 0.5
#: Default of :attr:`DecisionParams.slender_classes`.
SLENDER_CLASSES = "box"
#: Default of :attr:`DecisionParams.range_gate`.
RANGE_GATE = True
#: Default of :attr:`DecisionParams.range_margin`.
RANGE_MARGIN = 1.0
#: Default of :attr:`DecisionParams.range_classes`.
RANGE_CLASSES = "box,stairs,ramp"
#: Default of :attr:`DecisionParams.foot_gate`.
FOOT_GATE = True
#: Default of :attr:`DecisionParams.foot_above` (metres).
FOOT_ABOVE = 0.15
#: Default of :attr:`DecisionParams.foot_below` (metres).
FOOT_BELOW = 0.06
#: Default of :attr:`DecisionParams.foot_hidden` (0..1).
FOOT_HIDDEN = 0.75
#: Default of :attr:`DecisionParams.foot_float` (metres).
FOOT_FLOAT = 1.0
#: The class :func:`foot_refusals` asks a sloping plane's low end of.
FOOT_CLASS = "ramp"
#: Default of :attr:`DecisionParams.side_gate`.
SIDE_GATE = True
#: The classes :func:`side_refusals` asks of, with the orientation of the proof planes it
#: looks at: a ramp's slope and a flight's treads are walked on, so a camera sees them from
#: above their planes.
SIDE_PLANES = {"ramp": "inclined", "stairs": "horizontal"}
#: Defaults of :attr:`DecisionParams.facet_gate`, ``facet_min``, ``facet_max`` (cube53).
FACET_GATE = True
FACET_MIN = 25.0
FACET_MAX = 70.0
#: Default of :attr:`DecisionParams.facet_bridge`.
FACET_BRIDGE = True
#: The class :func:`facet_refusals` asks of.
FACET_CLASS = "box"
#: Defaults of :attr:`DecisionParams.flight_side_gate` and its bounds (wall56).
FLIGHT_SIDE_GATE = True
FLIGHT_SIDE_THICK = 0.15
FLIGHT_SIDE_GAP = 0.35
FLIGHT_SIDE_REACH = 0.5
FLIGHT_SIDE_RISE = 0.2
FLIGHT_SIDE_ANGLE = 15.0
#: Defaults of :attr:`DecisionParams.pitch_gate` and ``pitch_tol`` (degrees; pitch71).
PITCH_GATE = True
PITCH_TOL = 3.0
#: The class :func:`pitch_refusals` refuses, and the class whose hit it asks for.
PITCH_CLASS, PITCH_FLIGHT = "ramp", "stairs"
#: Defaults of :attr:`DecisionParams.flight_trim` and its bounds (lead57).
FLIGHT_TRIM = True
FLIGHT_TRIM_ANGLE = 25.0
FLIGHT_TRIM_EDGE = 0.05
FLIGHT_TRIM_RISE = 0.2
#: Defaults of :attr:`DecisionParams.hang_gate` and its bounds (false57).
HANG_GATE = True
HANG_SHARE = 0.7
HANG_DROP = 0.12
HANG_LEVEL = 0.04
HANG_LINES = 8
#: Defaults of :attr:`DecisionParams.long_lying_gate` and its bound (fbox58).
LONG_LYING_GATE = True
LONG_LYING_LENGTH = 0.4
#: Defaults of :attr:`DecisionParams.slab_gate` and its bounds (slab101).
SLAB_GATE = True
SLAB_WIDTH = 0.13
SLAB_DROP = 0.5
#: Defaults of :attr:`DecisionParams.crowd_gate` and its bound (crowd88).
CROWD_GATE = True
CROWD_PLANES = 20
#: Default of :attr:`DecisionParams.far_gate` (lead61).
FAR_GATE = True
#: Defaults of :attr:`DecisionParams.narrow_face_gate` and its bound (fbox59).
NARROW_FACE_GATE = True
NARROW_FACE_RATIO = 6.5
#: Defaults of :attr:`DecisionParams.slope_parts_gate` and its bound (wave83).
SLOPE_PARTS_GATE = True
SLOPE_PARTS_TOL = 0.5
#: Defaults of :attr:`DecisionParams.cut_boxes`, ``cut_reach``, ``cut_margin``.
CUT_BOXES = True
CUT_REACH = 1.5
CUT_MARGIN = 0.02
CUT_CORNER = 0
CUT_PIECES = 15.0
CUT_SPLIT = False
#: Default of :attr:`DecisionParams.unsure_gate`.
UNSURE_GATE = True
#: The class :func:`unsure_refusals` refuses under an unconfirmed up.
UNSURE_CLASS = "ramp"
#: Default of :attr:`DecisionParams.unsure_upside`.
UNSURE_UPSIDE = True
#: Default of :attr:`DecisionParams.unsure_sparse` (sparse85).
UNSURE_SPARSE = True


@dataclass(frozen=True)
class DecisionParams:
    """Settings of the decision among the rules that fired (``model.json`` section ``decision``;
    ``classify --param decision.NAME=VALUE`` overrides).

    Attributes
    ----------
    planar_gate : bool
        Refuse a class for an object whose planar fraction lies below ``1 - planar_margin``
        times the lowest planar fraction of the class's training positives
        (:func:`planar_refusals`; the model keeps them, ``planar_domain``).  On by default
        since facets22: off at first (gate22), because on the table-top judge sets it also
        refused 7 boxes whose faces the facet test linked to a neighbouring object's planes;
        the facet test keeps such links out now and the gate refuses no box there
        (docs/objects.md, "(gate22)", "(facets22)").
    planar_margin : float
        The margin, a fraction of ``low`` (0..1): a class is refused below ``low * (1 -
        planar_margin)``.  0.3: the demo's boxes and ramps (every positive at 1.0) are
        refused below 0.7, under ``curved_below`` 0.8, and its stairs, whose positives reach
        down to 0.44 (a flight with a curved cluster merged in), below 0.31.  Until
        falsecls (2026-11-29) the margin was subtracted (``low - planar_margin``): the same
        bound for a class whose positives are all planar, but 0.14 for the demo's stairs,
        and real mugs, a bowl and a dome-topped can on a RealSense (planar fraction
        0.14-0.28) were ``stairs`` from their facets (docs/objects.md, "Real table-tops
        nobody on the team made").
    proof_gate : bool
        Refuse a rule on an object it proves only with planes far smaller than in all of its
        training proofs (:func:`proof_refusals`; the model keeps the proofs' scales,
        ``proof_domain``).  On by default (proof22): on the whole real mOSD set it leaves
        1 of 12 false ``stairs`` answers (piles proved from slivers) and no round object
        ``stairs``, with every box answer and the real staircases kept (docs/results.md,
        "The proof gate").
    proof_margin : float
        How far below the training proofs a rule still holds, as a share of their range on
        a log scale (:func:`proof_bound`, 0..1).  0.3: the demo's stairs rule 4 (treads of
        0.042-0.455 m^2) is refused under 0.021 m^2, its box rule 1 (faces of 0.0036-0.57
        m^2) under 0.0008.
    proof_min_positives : int
        The fewest true positives a rule's scales must rest on for the gate to use them.
    veto_ratio : float
        A rule for ``other`` (a veto: "none of the classes") is set aside for an object when a
        class rule left in the decision proves the object with planes more than ``veto_ratio``
        times larger than any proof of the veto binds (:func:`veto_refusals`; 0 = off).  3
        (veto22, 2026-11-29): a real stair's nosing (a 1-2 cm strip, 0.002-0.02 m^2) or a
        lip in front of its riser fired the varied world's vetoes ("an inclined plane shorter
        than 0.7 m", "two parallel vertical planes 5 cm apart") against stairs proofs made of
        treads and risers (0.04-0.23 m^2); with the ratio the varied models call 17 of 20
        real flights ``stairs`` instead of 5, and their held-out sets lose nothing
        (docs/results.md, "Vetoes proved through slivers").  Models without rules for
        ``other`` (the demo's) are not affected.
    level_gate : bool
        Refuse a class for an object with fewer horizontal planes than every one of the
        class's training positives (:func:`level_refusals`; the model keeps the least count,
        ``level_domain``), unless the object's faces make a flight's regular row
        (:func:`planerel.features.step_chains.flight_faces`: a flight seen from below shows risers
        only).  On by default (hunt25, 2026-11-30): every stairs positive of the demo's
        training world has a horizontal plane (a tread, 1-6 of them), and on real Kinect frames
        nobody on the team had seen, the demo's stairs rule 4 ("two parallel planes above a
        third, above a fourth") proved proposals of vertical planes only: a room wall with a
        banister's posts, a desk pedestal's faces (docs/objects.md, "Real frames nobody on the
        team had seen").  The demo's boxes and ramps have positives with no horizontal plane (a
        box seen as one face, a ramp's slope alone): no gate for them.
    flight_gate : bool
        Refuse ``stairs`` for an object whose faces show no staircase's steps
        (:func:`flight_refusals`; :func:`planerel.features.step_chains.flight_evidence`: a
        regular row of three faces, or steps of one flight's rise and run).  On by default
        (pile26, 2026-11-30): the demo's stairs rules ("two parallel planes, one above the
        other") took cartons packed on a pallet at three heights, boxes of two heights
        touching and a machine's faces for flights (docs/objects.md, "Carton piles and false
        answers on unseen frames").
    flight_fragments : bool
        With ``flight_gate``: a flight seen in fragments shows its steps too
        (:func:`planerel.features.step_chains.flight_fragments`: risers stacked one on the
        other whatever their width seen, treads the image border cuts; their steps one
        flight's).  On by default (flight48, 2026-12-01): the varied world's 160x120 flights
        come in fragments, and the gate refused 27-52 true ones a model (accept45); on the
        real development frames it admits no false flight (docs/results.md, "A flight seen in
        fragments").  False: the gate as pile26 built it.
    size_gate : bool
        Refuse a rule whose proof of an object binds a plane reaching further than ``1 +
        size_margin`` times the planes of the class's training proofs (a face's height,
        another plane's length: :func:`plane_extents`; :func:`size_refusals`; the model keeps
        the furthest, ``size_domain``).  On by default (fbox31, 2026-11-30): on
        real rooms nobody on the team had seen, the demo's box rules proved a dining table's
        2.2 m top with its apron (``skirt``), a wardrobe's 1.6 m side, an office cabinet's
        1.65 m side and a door's jamb (``tall_face``); the demo world's boxes are at most
        1.2 m long and no real box answer's proof plane is longer than 0.6 m
        (docs/objects.md, "False boxes on real rooms").
    slender_gate : bool
        Refuse a rule whose proof of an object binds a top (a horizontal or inclined plane)
        far more slender than any top of the class's training proofs: its ``plane_length``
        over its ``plane_width`` more than ``1 + slender_margin`` times theirs
        (:func:`plane_slenderness`; :func:`slender_refusals`; the model keeps the most slender,
        ``slender_domain``).  A box's top is a rectangle whose sides are of a box's
        proportions; the top of a thin wall, a parapet, a sill or a shelf's edge is a strip
        many times longer than wide.  On by default (slab36, 2026-12-01): on the independent
        development sets the demo's box rule ``skirt`` proved the 8 cm top strips of a
        staircase's side walls (0.95-1.37 m long: 11-16.5 times their width) with a face
        below them; the demo world's box proofs' tops are at most 5.97 times as long as wide,
        the independent sets' true boxes' 4.4, the real box answers' 7.9 (an mOSD flat box
        standing on its 2 cm edge) (docs/objects.md, "Thin walls and slabs are
        no boxes").  A wall's end face seen alone (``tall_face``, ``corner``) is not gated: a
        narrow face is a tall narrow box's too.
    slender_margin : float
        The share of the most slender training top a proof's top may exceed it by (>= 0).
        0.5: the demo's box proofs' tops reach 5.97, refused over 8.95; 0.2 would refuse the
        mOSD box standing on its edge (7.9); the slabs' tops start at 11.1.
    slender_classes : str
        The classes the slenderness gate holds for, comma-separated (``box``).
    range_gate : bool
        Refuse a rule whose proof of an object binds a plane farther from the sensor (its
        centroid's distance, the ``distance/2`` fact: :func:`plane_ranges`) than ``1 +
        range_margin`` times the farthest plane of the class's training proofs
        (:func:`range_refusals`; the model keeps the farthest, ``range_domain``).  The rules'
        facts at 15 m on stereo or densified LiDAR (coarse depth, planes cut into pieces,
        slopes smeared) are not what the learner saw: the model has no evidence there.  On by
        default (range40, 2026-12-01): on real outdoor frames the demo's ramp rule ("a plane
        of 0.53 m^2 or more at most 28 degrees steep") proved verges, lawns, a planting bed
        and road-side strips 10.5-17.4 m away (hunt35, hunt39, hunt40); the demo world's ramp
        proofs' planes lie 0.85-3.54 m away, the independent development sets' true ramps'
        0.59-3.93 m (docs/results.md, "Proofs farther away than any training proof").
    range_margin : float
        The share of the farthest training proof plane's range a proof may exceed it by
        (>= 0).  1.0: the demo's ramp proofs reach 3.54 m, refused beyond 7.07 m; the true
        ramps of the independent sets reach 3.93 m (a margin of 0.11 would keep them), the
        nearest far false ramp lies 10.49 m away (a margin up to 1.96 refuses it); 1.0 allows
        twice the training range.
    range_classes : str
        The classes the range gate holds for, comma-separated (``box,stairs,ramp``).  The
        demo's domains: box 4.08 m (refused beyond 8.16 m), stairs 2.90 m (5.79 m), ramp 3.54 m
        (7.07 m); the independent development sets' true answers reach 3.72, 3.94 and 3.93 m,
        the real frames' true ones less.  Named ``ramp`` alone the gate refuses the far false
        ramps of hunt35 (4) and hunt40 (1) and an unscored one of hunt39; with box and stairs
        it refuses as well a box and 6 stairs that the 6 cm-baseline stereo frames of hunt40
        gave 9.4-17.8 m away (disparity terraces), and loses no answer on any real or
        independent check (docs/results.md,
        "Proofs farther away than any training proof").  A flight or a box farther away than
        that is answered ``other``: the model has no evidence there.
    foot_gate : bool
        Refuse ``ramp`` for an object whose proof's inclined planes all stand on no floor
        (:func:`foot_refusals`; :func:`planerel.features.foot.slope_foot`): the plane's lowest
        point is more than ``foot_above`` over the floor's level with its low end in plain view
        (under ``foot_hidden`` of it next to the image border, missing depth or a nearer
        surface), or more than ``foot_below`` under the floor.  A ramp is a slope that rises
        from the floor.  On by default (ramp32, 2026-12-01): on real rooms nobody on the team
        had seen, the demo's ramp rule ("a plane of 0.53 m^2 or more at most 28 degrees
        steep") proved the top of a sofa's back, a far table top and far shelves the sensor
        bends (low ends 0.26-0.84 m over the floor, at most 47 % of the low end's outline
        hidden) and a far floor strip bent through the floor (0.11 m under it); the training
        world's and the independent generator's ramps stand on the floor or have their low
        end out of sight (docs/results.md, "A ramp stands on the floor").  Only classify,
        which has the scan's points, applies it.
    foot_above : float
        Metres over the floor a ramp's seen low end may lie (0.15: the floor's tolerance
        ``floor_tol`` 0.05 and as much again twice; the real false ramps' low ends lie
        0.26-0.84 m up).
    foot_below : float
        Metres under the floor a ramp's lowest point may lie (0.06: the independent
        generator's and the training world's ramps reach at most 0.026 m under it, the real
        far floor strip 0.11 m).
    foot_hidden : float
        The share of a low end's outline out of sight (0..1) from which its height says
        nothing: the plane may go on down to the floor behind (0.75: every training-world and
        independent ramp whose seen low end lies over 0.1 m up has 0.88-1.0 of it hidden, the
        real false ramps 0-0.47).
    foot_float : float
        Metres over the floor beyond which a ramp's seen low end is refused even when hidden:
        to reach the floor behind what hides it, a slope of at most 28 degrees would go on for
        twice that and more out of sight (1.0: the training world's ramps with a hidden low end
        reach 0.49 m up at most, the independent generator's 0.17 m; outdoor false ramps of
        hunt35, a tree's canopy and a far strip on densified LiDAR, 1.4-2.6 m up). 0: off.
    side_gate : bool
        Refuse ``ramp`` (``stairs``) for an object whose proof's inclined (horizontal)
        planes are all seen from below
        (:func:`side_refusals`): the normal turned to the sensor points down (``normal . up <
        0``), the camera is under the plane.  A ramp is walked on: its walked-on side faces
        up, and a camera sees that side only from above its plane; what a camera sees from
        below is an underside (a table's, a shelf's, a ceiling's).  No threshold: a plane at
        most 28 degrees steep has ``|normal . up| >= 0.88``, so the sign is never in doubt
        unless the up vector itself is wrong.  It holds with or without a floor in view (the
        foot gate needs one).  On by default (ramp44, 2026-12-01): a camera near the floor
        sees undersides and often no floor (the Kinect returns nothing at grazing incidence);
        on the independent low-camera ramps a gravity estimate read upside down called the
        floor a ramp seen from below.  A flight's treads are walked on too: ``stairs`` is
        refused when its proof's and its object's horizontal planes are all seen from below
        (built for hunt45's ceiling terraces seen from 0.1 m; since 16-bit no-data is read
        as such that ceiling proves no flight either way, so no real answer it refuses is
        measured), unless the proof's planes are all risers and a plane of the object lies
        under the camera's eye (a flight rising over a low robot's camera: riser73,
        ``under_eye`` of :func:`side_refusals`).  Only classify applies it.
    unsure_upside : bool
        With ``unsure_gate``, an estimated up read upside down (``gravity.flip``) counts as
        unconfirmed too, whatever its confidence and whether or not a floor plane is in view
        (under a wrong flip that "floor" is the ceiling seen from below).  up66: of the real
        development frames read upside down whose truth is known, six of eight are wrong;
        hunt58's lab (no floor) had a ceiling panel answered ``ramp``, and its office frame
        (the ceiling taken for the floor) one under ``wide_fallback``.
    unsure_sparse : bool
        With ``unsure_gate``, an estimated up that a floor measured only as speckle decided
        (``gravity.sparse_floor``, :attr:`~planerel.features.planes.PlaneSet.up_sparse_floor`)
        counts as unconfirmed too when no floor plane is in view, whatever its confidence: the
        speckle fit takes whatever unassigned points lie low in the image, and with no floor
        plane nothing else attests it.  sparse85: hunt57's workbench seen from 0.7 m (no floor
        in view) was read 18 degrees off by such a fit, at confidence 0.58, and its top answered
        ``ramp``.
    unsure_gate : bool
        Refuse ``ramp`` when the scene's up is an estimate flagged low-confidence
        (``gravity.low_confidence``) and no floor plane is in view (:func:`unsure_refusals`).
        A slope is inclined only against the up; a ramp rises from a floor.  With no floor
        nothing in the scene attests the up, and the estimator itself doubts it (no two
        directions cross-checked, or a rival reading 10 degrees or more away nearly as
        good): the "slope" may be the ground under a wrong up, and the foot gate, which
        needs a floor, cannot tell.  No threshold of its own.  On by default (ramp48,
        2026-12-01): hunt45's D435i 0.10 m over the floor (tub3_418, confidence 0.27, no
        floor: the near floor and two other planes inclined 23-26 degrees) gave 3 of the 6
        false ramps on the development frames (since ``gravity.near_floor`` rights that
        frame's up, the gate refuses nothing on the real development frames); with the
        estimated up on the independent
        development sets every true ramp answered under a low-confidence up (23 of 62) has
        a floor in view, and 4 false ones (a ramp taken for the ground, the floor then
        "inclined") have none.  A given or file up is never low: only an estimate (or the
        default level guess, confidence 0) is gated.  Only classify applies it.
    facet_gate : bool
        Refuse ``box`` for a proof whose upright plane is a facet of a round side
        (:func:`facet_refusals`, cube53, 2026-12-02): an adjacent upright plane of the same
        object meets it convexly, with level tops and bottoms (``face_pair``'s shape test),
        at ``facet_min``-``facet_max`` degrees, and no upright plane meets it at
        ``relations.face_pair_angle`` or more.  A can seen by a RealSense at 0.6-0.8 m shows
        its side as two or three planes 40-69 degrees apart under its cap; a box's two faces
        meet at 79-90 (the D435 rounds a small box's corner to 79-82), a box face's bevel strip
        at under 20.  Needs the scan's points (only :meth:`Classifier.classify` applies it).
    facet_min, facet_max : float
        Degrees: the angle range of :attr:`facet_gate`'s facet neighbour (25, 70).
    facet_bridge : bool
        A corner partner is no box corner when a third upright plane of the object is a facet
        neighbour of both (a round side's fan of three strips whose ends are 85 degrees
        apart: rs-booth 1025_test9's can).
    pitch_gate : bool
        On by default (pitch71, 2026-12-04).  No ``ramp`` for an object a ``stairs`` rule
        proves too when every sloping plane of the ramp's proof rises the way the object's
        own steps rise (within 30 degrees) at the flight's pitch (the arctangent of its
        steps' median rise over their median run, :func:`~planerel.features.object_measures.
        flight_measures`) within ``pitch_tol`` degrees: the flight's far part, whose treads
        and risers are too small to be planes there, grown as one surface along its nosings
        (dev_sr i0021: a flight of rise 0.168 m and run 0.338 m, pitch 26.4 degrees, its far
        part two planes of 26.4 and 26.2 degrees).  A ramp beside a flight at the flight's
        own pitch is then answered with the flight.  Only classify applies it
        (:func:`pitch_refusals`).
    pitch_tol : float
        Degrees (0..90).
    flight_side_gate : bool
        On by default (wall56, 2026-12-02).  No ``box`` for an object that runs beside a
        flight answered ``stairs`` in the same scan: a staircase's side wall, knee wall or
        string seen in part (its top strip over its end face, or its side cut by the image's
        border).  Measured by :func:`planerel.features.flight_side.beside_flight` against each
        ``stairs`` answer: the object is at most ``flight_side_thick`` across the flight
        (along its own upright face parallel to the run, if any), lies beyond the flight's
        lateral edge by at most ``flight_side_gap`` (and over it by at most 5 cm), within
        ``flight_side_reach`` of the flight's run interval, its top at least
        ``flight_side_rise`` over the flight's highest point, and each of its upright planes
        within ``flight_side_angle`` degrees of parallel or square to the run (no inclined
        plane).  The answer becomes ``other``.  Only classify applies it (it needs the scan's
        points and the other answers of the scan).
    flight_side_thick, flight_side_gap, flight_side_reach, flight_side_rise : float
        Metres (>= 0): 0.15, 0.35, 0.5, 0.2 (the independent stair sets' walls: 0.06-0.08
        thick, 0.00-0.25 beyond the treads' ends, tops 0.44-0.89 over the flight's).
    flight_side_angle : float
        Degrees in 0..90 (15; the walls refused: 0-9).
    flight_trim : bool
        On by default (lead57, 2026-12-02).  A ``stairs`` answer's proposal that holds a side
        of its flight (a wall, knee wall or string the flight runs along, merged with it) is
        cut to the flight: the side planes
        (:func:`planerel.features.flight_side.side_planes`: upright, in no ``stair_step``
        pair, within ``flight_trim_angle`` degrees of parallel to the run, at or beyond the
        treads' lateral edge, within ``flight_trim_edge`` m inside it, rising at least
        ``flight_trim_rise`` m over the treads' line along the run: not the flight's own
        stepped side face, which stays under its treads) are decided as an
        object of their own (the answer's ``cut_from``; a members model answers it
        ``other``), before the flight side gate.  The ``stairs`` answer, its rule and proof
        are unchanged; its planes are the rest.  Only classify applies it.
    flight_trim_angle : float
        Degrees in 0..90 (25; the walls cut on real frames: 0.8-9.8).
    flight_trim_edge, flight_trim_rise : float
        Metres (>= 0; 0.05, 0.2).
    hang_gate : bool
        On by default (false57).  No ``box`` for an object whose upright proof faces all
        hang: beneath each one's lower edge the camera sees, on at least ``hang_share`` of the
        image lines across it that show anything there, points farther than the edge by
        more than ``hang_drop`` and lower by more than ``hang_level`` (the space under a
        sofa's seat front, a desk's apron, a radiator), and no horizontal plane of the scan
        lies at the edge's level within ``hang_level`` and 0.3 m of it (a box standing on
        or overhanging the box below).  A face with fewer than ``hang_lines`` lines that
        show anything beneath it is not judged.  Measured by
        :func:`planerel.features.hang.face_hang` and :func:`~planerel.features.hang.supported`.
        The answer becomes ``other``.  Only classify applies it (it needs the scan's points).
    hang_share : float
        In 0..1 (0.7).
    hang_drop, hang_level : float
        Metres (>= 0): 0.12, 0.04.
    hang_lines : int
        Whole number >= 1 (8).
    long_lying_gate : bool
        On by default (fbox58).  No ``box`` for an object whose proof binds no upright
        plane and a top (horizontal or inclined) longer than ``long_lying_length``: a
        ``lying`` top seen alone, its sides unseen.  The box rule that proves a box by its
        lying top alone was meant for a book-size or flat box (its found tops on the real
        development frames are 0.11-0.23 m long); a flat carton 0.4 m long shows its sides
        and is proved by them.  Real frames nobody had tuned on answered ``box`` with such a
        top: a keyboard (0.49 m, tilted 7 degrees on a desk), a desk's foot bar on the floor
        (0.53 m), a corridor's floor strip (0.46 m) (docs/objects.md, "hunt58").  The answer
        becomes ``other``.  Only classify applies it.
    long_lying_length : float
        Metres (>= 0): 0.4.
    slab_gate : bool
        On by default (slab101, 2026-12-07).  No ``box`` for an object whose proof binds a top
        (a plane not upright) at most ``slab_width`` wide under whose edge an upright plane of
        the object, adjacent to it, reaches ``slab_drop`` or more below the top's level (and
        does not rise over it): the top strip of a wall, a door or a panel seen over its edge,
        not a box (:func:`planerel.features.slab.slab_edge`).  On the real development frames
        the right box answers with a top that narrow have upright faces at most 0.29 m long;
        the generated stairwells' side walls (an 8 cm cap, the wall 0.9-1.9 m below it) were
        false boxes where the flight was lost.  The answer becomes ``other``.  Only classify
        applies it.
    slab_width, slab_drop : float
        Metres (>= 0): 0.13, 0.5.
    crowd_gate : bool
        On by default (crowd88, 2026-12-06).  No ``box`` for an object of more than
        ``crowd_planes`` planes: a box shows at most three faces, which a real sensor's noise
        and labels cut into pieces, and what stands on it or against it joins it; a proposal
        of more planes than that is a piece of furniture with what it carries or a desk with
        everything on it.  On the real development frames the right box answers' proposals
        hold 1-18 planes (18: a pile of product boxes, ucn 000006; 5 answers of 8-10), the
        false ones 23-33 in six answers: a chest of drawers with a television and a console
        on it (three frames), a desk and all on it seen without a floor, a sofa's seat and
        front, a table-top's far edge with the background behind it (docs/objects.md, "Flat
        things and crowded proposals").  The answer becomes ``other``.  Only classify applies it.
    crowd_planes : int
        Whole number >= 1 (20).
    far_gate : bool
        On by default (lead61); it refuses something only when the segmentation's far
        growing (``far_theta``) added planes.  No ``box`` or ``ramp`` for an object whose proof
        binds a plane that only the far growing found: that growing joins depth at a wider
        angle than the first, to recover a far flight's treads and risers under the noise of
        2-4 m, and its planes are too coarse to prove a box's faces or a slope (on the
        development frames its planes alone made three false boxes, skirts on far background
        surfaces, and a false ramp, a 4-row strip of a floor 4.5 m away bent 5 degrees,
        docs/segmentation.md "Far planes").  The answer becomes ``other``; ``stairs`` may use
        them.  Only classify applies it.
    narrow_face_gate : bool
        On by default (fbox59).  No ``box`` for an object whose upright proof faces are all
        more than ``narrow_face_ratio`` times as tall as they are wide
        (:func:`planerel.features.face_shape.face_extent`: the spread of each face's points
        along ``up`` and along its horizontal axis): a post's, a door jamb's, a wall's end,
        a furniture side seen edge-on.  A box's upright faces are compact (the real
        development frames' found boxes reach 5.6, a product box's narrowest side; the
        independent sets' 3.9).  A face whose pixels reach the image's left or right column
        is not judged (its width is then a lower bound); an answer with no judged upright
        proof face keeps its class.  The answer becomes ``other``.  Only classify applies it.
    narrow_face_ratio : float
        Height over width (>= 0): 6.5.
    slope_parts_gate : bool
        On by default (wave83).  No ``ramp`` for an object whose sloping proof planes each
        have a part that does not slope as the whole does
        (:func:`planerel.features.slope_parts.slope_parts`: the plane's points cut in four by
        their medians along and across its downhill direction, each part's slope along that
        direction as a share of the whole's): a part's share more than ``slope_parts_tol``
        from 1.  A ramp is one flat slope; a far floor piece an active stereo camera's
        undulating depth tilted, or a floor strip grown into one plane with the foot of a
        wall, slopes only as a compromise of parts nearly level, steep or tilted the other
        way.  A plane too small to cut (20 points a part) or sloping under a degree is not
        judged; an answer with no judged sloping proof plane keeps its class.  The answer
        becomes ``other``.  Only classify applies it (docs/objects.md "A ramp's parts slope
        alike").
    slope_parts_tol : float
        The largest ``|share - 1|`` a part may show (>= 0): 0.5.  The demo model's 96 ramps
        answered on eleven independent sets show at most 0.24; 9 of its 12 ramps on no ramp
        there 0.52-2.4.
    cut_boxes : bool
        On by default (core49).  A proposal a box rule proves and a gate refuses ``box`` for,
        whose planes hold a box proof's seed (a ``skirt`` or ``face_pair`` pair; a lone
        ``tall_face`` or ``lying`` top seeds none) that is not the whole proposal:
        the solid of that seed (:func:`planerel.features.box_cut.box_solids`) is decided as
        an object of its own, with its own planar fraction and every gate; answered ``box``,
        it is cut from the proposal (the answer's ``cut_from``), and the rest of the proposal
        is decided again (it keeps the proposal's planar fraction and may keep its class or
        become ``other``, nothing else).  For a box merged with what it stands on or touches
        (core49, docs/objects.md "Boxes lost inside a merged proposal").  Only classify
        applies it (it needs the scan's points); the learner's decision does not.
    cut_reach : float
        Metres (>= 0): a solid grows only while the diagonal of its planes' bounding box
        stays within this.  1.5: the demo's box proofs reach at most 1.23 m.
    cut_margin : float
        Metres (>= 0): the proposal's unexplained pixels within this of the solid's planes'
        bounding box (and in their image rectangle) count against its planar fraction.
    cut_corner : int
        0 (off) or >= 2: a solid of this many planes or more (3: a top and two sides) is cut
        even when one of its faces is adjacent to the proposal's other planes at a facet's
        angle (a container with a toy brick touching it); with 0 no such solid is (two
        facets of a mug never are).  Off by default: 3 found one real box more (hunt33 ucn's
        container) and answered one false box more (hunt48 arkit-rooms, a crate's rim and a
        bed's edge) and one more false object on mOSD's test frames (docs/objects.md "Boxes
        lost inside a merged proposal").
    cut_pieces : float
        Degrees (0..90): two faces of a solid adjacent at a facet's angle
        (``curved.facet_min_angle``-``facet_max_angle``) but under this are pieces of one face
        the sensor's noise broke (hunt48's tops read 5-12 degrees off level; a food
        container's side in three pieces 2-7 degrees apart), not a round surface's strips,
        which make the solid none.
    cut_split : bool
        Off by default (split79; with ``cut_boxes``).  A proposal answered ``box`` whose planes
        hold two or more solids (:func:`~planerel.features.box_cut.box_solids`, sharing no
        plane; a solid is kept beside facets, as ``cut_corner`` 2 would) each answered
        ``box`` on its own, with every gate, by any box rule, is split into them: boxes
        packed or standing against each other that the proposal step joined (touching
        cartons, a stack).  One such solid leaves the answer
        whole (the proof may be the box's with what it stands on), and so do two whose tops
        are one surface (one box an occluder cuts in two, or two flush boxes).  The rest is
        decided again as with ``cut_boxes``.  Off: on, it found 2 more real boxes (hunt48,
        mOSD test61) and 6 more independent ones, and answered one false box more on a judge
        set of real staircase frames (docs/objects.md "Boxes packed in one proposal").
    size_margin : float
        The share of the furthest-reaching training proof plane a proof may exceed it by
        (>= 0).  0.2: the demo's box proofs reach at most 1.23 m (a 1.2 m box's top), refused
        over 1.48 m; the wardrobe's side (1.61 m high) is refused with any margin under 0.31.
    size_classes : str
        The classes the size gate holds for, comma-separated (``box``).  A box is a thing of
        bounded size; a staircase or a ramp is part of a building and as wide as the building
        makes it (the demo's flights are at most 1.6 m wide, real ones often wider), so their
        domains are kept in ``model.json`` but not used unless named here.
    """

    planar_gate: bool = PLANAR_GATE
    planar_margin: float = PLANAR_MARGIN
    proof_gate: bool = PROOF_GATE
    proof_margin: float = PROOF_MARGIN
    proof_min_positives: int = PROOF_MIN_POSITIVES
    veto_ratio: float = VETO_RATIO
    level_gate: bool = LEVEL_GATE
    flight_gate: bool = FLIGHT_GATE
    flight_fragments: bool = FLIGHT_FRAGMENTS
    size_gate: bool = SIZE_GATE
    size_margin: float = SIZE_MARGIN
    size_classes: str = SIZE_CLASSES
    slender_gate: bool = SLENDER_GATE
    slender_margin: float = SLENDER_MARGIN
    slender_classes: str = SLENDER_CLASSES
    range_gate: bool = RANGE_GATE
    range_margin: float = RANGE_MARGIN
    range_classes: str = RANGE_CLASSES
    foot_gate: bool = FOOT_GATE
    foot_above: float = FOOT_ABOVE
    foot_below: float = FOOT_BELOW
    foot_hidden: float = FOOT_HIDDEN
    foot_float: float = FOOT_FLOAT
    side_gate: bool = SIDE_GATE
    unsure_gate: bool = UNSURE_GATE
    unsure_upside: bool = UNSURE_UPSIDE
    unsure_sparse: bool = UNSURE_SPARSE
    facet_gate: bool = FACET_GATE
    facet_min: float = FACET_MIN
    facet_max: float = FACET_MAX
    facet_bridge: bool = FACET_BRIDGE
    pitch_gate: bool = PITCH_GATE
    pitch_tol: float = PITCH_TOL
    flight_side_gate: bool = FLIGHT_SIDE_GATE
    flight_side_thick: float = FLIGHT_SIDE_THICK
    flight_side_gap: float = FLIGHT_SIDE_GAP
    flight_side_reach: float = FLIGHT_SIDE_REACH
    flight_side_rise: float = FLIGHT_SIDE_RISE
    flight_side_angle: float = FLIGHT_SIDE_ANGLE
    flight_trim: bool = FLIGHT_TRIM
    flight_trim_angle: float = FLIGHT_TRIM_ANGLE
    flight_trim_edge: float = FLIGHT_TRIM_EDGE
    flight_trim_rise: float = FLIGHT_TRIM_RISE
    hang_gate: bool = HANG_GATE
    hang_share: float = HANG_SHARE
    hang_drop: float = HANG_DROP
    hang_level: float = HANG_LEVEL
    hang_lines: int = HANG_LINES
    long_lying_gate: bool = LONG_LYING_GATE
    long_lying_length: float = LONG_LYING_LENGTH
    slab_gate: bool = SLAB_GATE
    slab_width: float = SLAB_WIDTH
    slab_drop: float = SLAB_DROP
    crowd_gate: bool = CROWD_GATE
    crowd_planes: int = CROWD_PLANES
    far_gate: bool = FAR_GATE
    narrow_face_gate: bool = NARROW_FACE_GATE
    narrow_face_ratio: float = NARROW_FACE_RATIO
    slope_parts_gate: bool = SLOPE_PARTS_GATE
    slope_parts_tol: float = SLOPE_PARTS_TOL
    cut_boxes: bool = CUT_BOXES
    cut_reach: float = CUT_REACH
    cut_margin: float = CUT_MARGIN
    cut_corner: int = CUT_CORNER
    cut_pieces: float = CUT_PIECES
    cut_split: bool = CUT_SPLIT

    def __post_init__(self):
        for gate in ("planar_gate", "proof_gate", "level_gate", "flight_gate",
                     "flight_fragments", "size_gate", "slender_gate", "range_gate", "foot_gate",
                     "side_gate", "unsure_gate", "unsure_upside", "unsure_sparse", "facet_gate",
                     "facet_bridge", "cut_boxes", "cut_split", "pitch_gate",
                     "flight_side_gate", "flight_trim", "hang_gate", "long_lying_gate", "crowd_gate",
                     "slab_gate", "narrow_face_gate", "far_gate", "slope_parts_gate"):
            if not isinstance(getattr(self, gate), bool):
                raise InputError(f"decision.{gate} must be true or false, "
                                 f"got {getattr(self, gate)!r}")
        for name in ("planar_margin", "proof_margin", "foot_hidden", "hang_share"):
            m = getattr(self, name)
            if (isinstance(m, bool) or not isinstance(m, (int, float)) or not np.isfinite(m)
                    or not 0 <= m <= 1):
                raise InputError(f"decision.{name} must be a number in 0..1, got {m!r}")
        for name in ("size_classes", "slender_classes", "range_classes"):
            if not isinstance(getattr(self, name), str):
                raise InputError(f"decision.{name} must be class names separated by commas, "
                                 f"got {getattr(self, name)!r}")
        for name in ("foot_above", "foot_below", "foot_float"):
            m = getattr(self, name)
            if (isinstance(m, bool) or not isinstance(m, (int, float)) or not np.isfinite(m)
                    or m < 0):
                raise InputError(f"decision.{name} must be a number >= 0 (metres), got {m!r}")
        for name in ("size_margin", "slender_margin", "range_margin", "cut_reach", "cut_margin",
                     "flight_side_thick", "flight_side_gap", "flight_side_reach",
                     "flight_side_rise", "flight_trim_edge", "flight_trim_rise", "hang_drop",
                     "hang_level", "long_lying_length", "slab_width", "slab_drop",
                     "narrow_face_ratio", "slope_parts_tol"):
            m = getattr(self, name)
            if (isinstance(m, bool) or not isinstance(m, (int, float)) or not np.isfinite(m)
                    or m < 0):
                raise InputError(f"decision.{name} must be a number >= 0, got {m!r}")
        for name in ("facet_min", "facet_max", "flight_side_angle", "flight_trim_angle",
                     "pitch_tol"):
            m = getattr(self, name)
            if (isinstance(m, bool) or not isinstance(m, (int, float)) or not np.isfinite(m)
                    or not 0 <= m <= 90):
                raise InputError(f"decision.{name} must be a number of degrees in 0..90, "
                                 f"got {m!r}")
        if self.facet_min > self.facet_max:
            raise InputError(f"decision.facet_min ({self.facet_min!r}) must not exceed "
                             f"decision.facet_max ({self.facet_max!r})")
        m = self.cut_pieces
        if (isinstance(m, bool) or not isinstance(m, (int, float)) or not np.isfinite(m)
                or not 0 <= m <= 90):
            raise InputError(f"decision.cut_pieces must be a number of degrees in 0..90, "
                             f"got {m!r}")
        n = self.cut_corner
        if isinstance(n, bool) or not isinstance(n, int) or n < 0 or n == 1:
            raise InputError(f"decision.cut_corner must be 0 (off) or a whole number >= 2, "
                             f"got {n!r}")
        n = self.hang_lines
        if isinstance(n, bool) or not isinstance(n, int) or n < 1:
            raise InputError(f"decision.hang_lines must be a whole number >= 1, got {n!r}")
        n = self.crowd_planes
        if isinstance(n, bool) or not isinstance(n, int) or n < 1:
            raise InputError(f"decision.crowd_planes must be a whole number >= 1, got {n!r}")
        n = self.proof_min_positives
        if isinstance(n, bool) or not isinstance(n, int) or n < 1:
            raise InputError(f"decision.proof_min_positives must be a whole number >= 1, got {n!r}")
        r = self.veto_ratio
        if (isinstance(r, bool) or not isinstance(r, (int, float)) or not np.isfinite(r)
                or r < 0):
            raise InputError(f"decision.veto_ratio must be a number >= 0 (0: off), got {r!r}")


def planar_domain(examples: Sequence, planar: dict, classes: Sequence[str]) -> tuple:
    """The planar fractions of each class's training positives: ``((class, low, high, n), ...)``.

    ``low`` is the *minimum* over the class's positive objects (not a quantile): every object
    the rules were counted right on lies inside the domain, so the gate of
    :func:`planar_refusals` never refuses an object as planar as a training positive and the
    rules' training statistics (``tp``, :func:`laplace`) hold under it unchanged.  ``n``
    counts the positives with a planar fraction; a class with none has no entry (no gate).

    Parameters
    ----------
    examples : sequence of (object id, class)
    planar : dict
        ``{object id: planar fraction or None}``.
    """
    out = []
    for k in classes:
        if k == OTHER:
            continue
        values = [planar.get(o) for o, c in examples if c == k]
        values = [float(v) for v in values if v is not None]
        if values:
            out.append((k, round(min(values), 4), round(max(values), 4), len(values)))
    return tuple(out)


@dataclass(frozen=True)
class Refusal:
    """A class whose rules proved an object and that the decision did not trust there: the
    object's planar fraction lies under ``bound = low * (1 - margin)``, ``low`` the least planar
    of the class's training positives."""

    klass: str
    planar_fraction: float
    low: float
    high: float
    margin: float

    @property
    def bound(self) -> float:
        """The planar fraction under which the class is refused: ``low * (1 - margin)``."""
        return planar_bound(self.low, self.margin)

    @property
    def reason(self) -> str:
        return (f"planar fraction {self.planar_fraction:.2f}, under "
                f"{self.bound:.2f}: training {self.klass} "
                f"{self.low:.2f}-{self.high:.2f}, margin {self.margin:g}")

    def to_dict(self) -> dict:
        return {"class": self.klass, "planar_fraction": round(self.planar_fraction, 3),
                "positives_low": self.low, "positives_high": self.high, "margin": self.margin,
                "reason": self.reason}


def planar_bound(low: float, margin: float = PLANAR_MARGIN) -> float:
    """The planar fraction under which :func:`planar_refusals` refuses a class whose least
    planar training positive is ``low``: ``low * (1 - margin)`` (falsecls; ``low - margin``
    before, the same for a class of fully planar positives, ``low`` = 1)."""
    return float(low) * (1.0 - float(margin))


def gated_negatives(examples: Sequence, planar: dict, domain: Sequence,
                    margin: float = PLANAR_MARGIN) -> dict:
    """The objects the planar gate refuses each class for: ``{class: frozenset of object ids}``.

    An object of another class (or ``other``) whose planar fraction lies under the class's
    :func:`planar_bound` is never answered that class, whatever its rules prove
    (:func:`planar_refusals`), so it is no negative its rules must leave out: a rule that
    would otherwise take a size bound or another literal only to exclude a few curved objects
    (a cylinder's top disc with a facet hanging below it is a ``skirt``) is learned without
    it, and the bound does not cut real boxes smaller than every training box (seed29,
    docs/results.md "The demo over training seeds 0-4").  The class's own positives are never
    left out (none lies under the bound: ``low`` is their minimum).

    Parameters
    ----------
    examples : sequence of (object id, class)
    planar : dict
        ``{object id: planar fraction or None}`` (an object without one is kept).
    domain : sequence of (class, low, high, n)
        :func:`planar_domain` of the same examples.
    """
    out = {}
    for k, low, _, _ in domain:
        bound = planar_bound(low, margin)
        out[k] = frozenset(o for o, c in examples
                           if c != k and planar.get(o) is not None and float(planar[o]) < bound)
    return out


def planar_refusals(hits, stats: Sequence, planar_fraction, domain: Sequence,
                    margin: float = PLANAR_MARGIN):
    """Leave out the hits of classes not trusted on an object so far off their positives.

    A class with an entry ``(class, low, high, n)`` in ``domain`` (:func:`planar_domain`) is
    refused for an object whose planar fraction is below ``low * (1 - margin)``
    (:func:`planar_bound`): its rules were only
    ever counted on objects at least ``low`` planar, and a rule that proves a curved object from
    two of its facets (a bowl's strips "one above another" for stairs) says nothing about it.
    No domain, no planar fraction, or a class without an entry: nothing is refused (a model
    learned before the domain was kept decides as before).

    Returns
    -------
    (list, tuple of Refusal)
        The hits left, and one :class:`Refusal` per refused class among the rules that take
        part in the decision (:func:`takes_part`), in the order of the hits.
    """
    if not domain or planar_fraction is None:
        return list(hits), ()
    bounds = {k: (lo, hi) for k, lo, hi, _ in domain}
    table = {i: (tp, fp) for i, _, tp, fp in stats}
    pf = float(planar_fraction)
    kept, refused = [], {}
    for hit in hits:
        k = hit[0]
        if k in bounds and pf < planar_bound(bounds[k][0], margin):
            if k not in refused and takes_part(*table.get(hit[1], (0, 0))):
                refused[k] = Refusal(k, pf, bounds[k][0], bounds[k][1], float(margin))
            continue
        kept.append(hit)
    return kept, tuple(refused.values())


def horizontal_counts(descs) -> dict:
    """``{object id: number of its horizontal planes}`` over scene descriptions (the value of
    the fact ``nhorizontal/2``, :func:`planerel.features.facts.scene_facts`)."""
    out = {}
    for d in descs:
        by_label = {p.label: p for p in d.planes}
        for o in d.objects:
            out[o.id] = sum(by_label[lbl].orientation == "horizontal" for lbl in o.planes
                            if lbl in by_label)
    return out


def level_domain(examples: Sequence, levels: dict, classes: Sequence[str]) -> tuple:
    """The fewest horizontal planes of each class's training positives: ``((class, low, n),
    ...)``.

    ``low`` is the minimum over the class's positive objects, so the gate of
    :func:`level_refusals` never refuses an object with as many horizontal planes as a
    training positive, and the rules' training statistics hold under it unchanged.  ``n``
    counts the positives with a count; a class with none has no entry (no gate), and neither
    has a class whose ``low`` is 0 (nothing to refuse).

    Parameters
    ----------
    examples : sequence of (object id, class)
    levels : dict
        ``{object id: number of horizontal planes (the fact nhorizontal/2) or None}``.
    """
    out = []
    for k in classes:
        if k == OTHER:
            continue
        values = [levels.get(o) for o, c in examples if c == k]
        values = [int(v) for v in values if v is not None]
        if values and min(values) > 0:
            out.append((k, min(values), len(values)))
    return tuple(out)


@dataclass(frozen=True)
class LevelRefusal:
    """A class whose rules proved an object with fewer horizontal planes than every training
    positive of the class has, and no flight's faces in a row (:func:`level_refusals`)."""

    klass: str
    horizontal: int
    low: int

    @property
    def reason(self) -> str:
        # the row of faces (a flight seen from below) is what would have let a stairs answer
        # through; for another class it only puzzles (ilp90: "refused round: ... flight's row")
        row = " and no faces in a flight's row" if self.klass == FLIGHT_CLASS else ""
        return (f"{self.horizontal} horizontal plane(s){row}: every training {self.klass} has "
                f"at least {self.low}")

    def to_dict(self) -> dict:
        return {"class": self.klass, "horizontal_planes": self.horizontal,
                "positives_low": self.low, "reason": self.reason}


def level_refusals(hits, stats: Sequence, n_horizontal, domain: Sequence, stepped=False):
    """Leave out the hits of classes whose training positives all had more horizontal planes
    than the object has.

    A class with an entry ``(class, low, n)`` in ``domain`` (:func:`level_domain`) is refused
    for an object with fewer than ``low`` horizontal planes, unless ``stepped``: a stairs rule
    that says "two parallel planes above a third, above a fourth" was only ever counted on
    flights with a tread in view, and said of a wall and the posts before it, or a cabinet's
    faces, it says nothing about stairs.  A flight seen from below (its risers in a regular
    row, :func:`planerel.features.step_chains.flight_faces`; ``stepped`` true, or a callable
    asked only when the count is short) is the structure the positives showed from another
    side, and is not refused: the independent judge sets hold such flights, ``stairs`` by the
    same rule.  No domain, no count, or a class without an entry: nothing is refused (a model
    learned before the domain was kept decides as before).

    Returns
    -------
    (list, tuple of LevelRefusal)
        The hits left, and one :class:`LevelRefusal` per refused class among the rules that
        take part in the decision (:func:`takes_part`).
    """
    if not domain or n_horizontal is None:
        return list(hits), ()
    lows = {k: lo for k, lo, _ in domain}
    table = {i: (tp, fp) for i, _, tp, fp in stats}
    nh = int(n_horizontal)
    if not any(h[0] in lows and nh < lows[h[0]] for h in hits):
        return list(hits), ()
    if callable(stepped):
        stepped = stepped()
    if stepped:
        return list(hits), ()
    kept, refused = [], {}
    for hit in hits:
        k = hit[0]
        if k in lows and nh < lows[k]:
            if k not in refused and takes_part(*table.get(hit[1], (0, 0))):
                refused[k] = LevelRefusal(k, nh, int(lows[k]))
            continue
        kept.append(hit)
    return kept, tuple(refused.values())


def plane_extents(descs) -> dict:
    """``{plane id: extent}`` (m) over scene descriptions: how far each plane reaches where a
    box's size is bounded.  A vertical plane's extent is its height (the span of its hull
    along ``up``): a row of boxes side by side makes one long front, but no face taller than
    its boxes; any other plane's is ``plane_length/2`` (the long side of its hull's minimum
    rectangle).  Both are lower bounds for a plane the view cuts."""
    out = {}
    for d in descs:
        up = np.asarray(d.planes.up, dtype=float)
        for p in d.planes:
            extent = float(p.length)
            hull = np.asarray(p.hull3d, dtype=float)
            if p.orientation == "vertical" and hull.ndim == 2 and len(hull) >= 2:
                h = hull @ up
                extent = float(h.max() - h.min())
            out[d.plane_id(p.label)] = extent
    return out


def _proof_max(bindings: dict, measure: dict):
    """The largest of ``measure`` (``{plane id: value}``) over the planes a proof binds, or
    None when it binds none of them."""
    values = [measure[v] for v in (bindings or {}).values() if isinstance(v, str) and v in measure]
    return max(values) if values else None


def proof_extent(bindings: dict, extents: dict):
    """The largest extent among the planes a proof binds (m; :func:`plane_extents`), or None
    when the proof binds no plane of ``extents``."""
    return _proof_max(bindings, extents)


def size_domain(fired: dict, truth: dict, extents: dict) -> tuple:
    """How far the planes reach that each class's rules proved its training positives with
    (:func:`plane_extents`): ``((class, high, n), ...)``.

    A positive's extent is the least, over the hits of its class, of :func:`proof_extent`
    (its most compact proof); ``high`` is the largest extent over the class's positives, so
    the gate of :func:`size_refusals` refuses no proof as compact as a training one and the
    rules' ``tp`` hold under it; ``n`` counts the positives with an extent.

    Parameters
    ----------
    fired : dict
        ``{object: [(class, index, bindings, text, scale), ...]}``.
    truth : dict
        ``{object: class}`` of the training objects.
    extents : dict
        ``{plane id: extent}`` (:func:`plane_extents`).
    """
    return _proof_domain(fired, truth, extents)


def _proof_domain(fired: dict, truth: dict, measure: dict) -> tuple:
    """``((class, high, n), ...)``: per class, the largest over its training positives of
    the least :func:`_proof_max` of ``measure`` over the positive's hits of its class
    (:func:`size_domain`, :func:`slender_domain`, :func:`range_domain`); ``n`` the positives
    with a value."""
    per: dict = {}
    for obj, hits in fired.items():
        k = truth.get(obj)
        if k is None or k == OTHER:
            continue
        values = [_proof_max(h[2], measure) for h in hits if h[0] == k]
        values = [v for v in values if v is not None]
        if values:
            per.setdefault(k, []).append(min(values))
    return tuple((k, round(max(v), 4), len(v)) for k, v in sorted(per.items()))


def size_gated(domain: Sequence, classes: str = SIZE_CLASSES) -> tuple:
    """The entries of a :func:`size_domain` whose class is among ``classes`` (comma-separated
    names, :attr:`DecisionParams.size_classes`): the domain the size gate uses."""
    names = {c.strip() for c in str(classes).split(",") if c.strip()}
    return tuple(e for e in domain if e[0] in names)


class _Bounded:
    """What a gate with a training domain refused over: ``bound = high * (1 + margin)``
    (:class:`SizeRefusal`, :class:`SlenderRefusal`, :class:`RangeRefusal`)."""

    high: float
    margin: float

    @property
    def bound(self) -> float:
        """The value over which the rule is refused: ``high * (1 + margin)``."""
        return self.high * (1.0 + self.margin)


@dataclass(frozen=True)
class SizeRefusal(_Bounded):
    """A rule whose proof of an object binds a plane reaching far further than any plane of
    the class's training proofs (:func:`size_refusals`; a face's height, another plane's
    length: :func:`plane_extents`)."""

    klass: str
    rule: int
    extent: float
    high: float
    margin: float

    @property
    def reason(self) -> str:
        return (f"rule {self.rule} proves it with a plane reaching {self.extent:.2f} m, over "
                f"{self.bound:.2f} m: the training {self.klass} proofs' planes reach at most "
                f"{self.high:.2f} m, margin {self.margin:g}")

    def to_dict(self) -> dict:
        return {"class": self.klass, "rule": self.rule, "proof_extent": round(self.extent, 4),
                "proofs_high": self.high, "margin": self.margin, "reason": self.reason}


def size_refusals(hits, stats: Sequence, extents, domain: Sequence,
                  margin: float = SIZE_MARGIN, min_positives: int = PROOF_MIN_POSITIVES):
    """Leave out the hits whose proof binds a plane reaching far further than the planes of
    the class's training proofs.

    A class with an entry ``(class, high, n)`` in ``domain`` (:func:`size_domain`, measured on
    at least ``min_positives`` positives) refuses a hit of its class whose
    :func:`proof_extent` (a face's height, another plane's length: :func:`plane_extents`)
    exceeds ``high * (1 + margin)``.  Extents are lower bounds (a plane the view cuts goes
    on), so a plane reaching further than that is larger than any plane a training positive
    was proved with: a dining table's 2 m top over its apron (``skirt``), a wardrobe's 1.6 m
    side or a door's jamb seen to the image's top (``tall_face``) say "box" of something no
    box of the training world is the size of (docs/objects.md, "False boxes on real
    rooms").  No domain, no extents or a class without an entry: nothing is refused.

    Parameters
    ----------
    extents : dict or callable
        ``{plane id: extent}`` (:func:`plane_extents`), or a callable returning it
        (asked only when a class with an entry fired).

    Returns
    -------
    (list, tuple of SizeRefusal)
        The hits left, and one :class:`SizeRefusal` per refused rule that takes part in the
        decision (:func:`takes_part`).
    """
    return _bound_refusals(hits, stats, extents, domain, margin, min_positives, SizeRefusal)


def _bound_refusals(hits, stats: Sequence, measure, domain: Sequence, margin: float,
                    min_positives: int, refusal):
    """The hits left and the ``refusal(class, rule, value, high, margin)`` of every rule
    (taking part in the decision) whose proof's :func:`_proof_max` of ``measure`` (a dict, or
    a callable asked only when a gated class fired) exceeds its class's ``high * (1 +
    margin)`` in ``domain`` (classes measured on at least ``min_positives`` positives):
    :func:`size_refusals`, :func:`slender_refusals`, :func:`range_refusals`."""
    if not domain or measure is None:
        return list(hits), ()
    highs = {k: float(hi) for k, hi, n in domain if n >= min_positives}
    if not any(h[0] in highs for h in hits):
        return list(hits), ()
    if callable(measure):
        measure = measure()

    def refuse(hit):
        k = hit[0]
        if k not in highs:
            return None
        value = _proof_max(hit[2], measure)
        if value is None or value <= highs[k] * (1.0 + float(margin)):
            return None
        return refusal(k, hit[1], float(value), highs[k], float(margin))

    return _refuse_hits(hits, stats, refuse)


def plane_slenderness(descs) -> dict:
    """``{plane id: slenderness}`` over scene descriptions: each *top*'s (a horizontal or
    inclined plane's) ``plane_length`` over its ``plane_width`` (the sides of its hull's
    minimum rectangle).  Vertical planes have none: a narrow face is a tall narrow box's as
    well as a wall's end.  A plane the view cuts along its length is a lower bound (it is
    more slender still); one cut across its width is measured more slender than it is."""
    out = {}
    for d in descs:
        for p in d.planes:
            if p.orientation == "vertical":
                continue
            out[d.plane_id(p.label)] = float(p.length) / max(float(p.width), 1e-3)
    return out


def proof_slenderness(bindings: dict, slender: dict):
    """The largest slenderness among the tops a proof binds (:func:`plane_slenderness`), or
    None when the proof binds no top."""
    return _proof_max(bindings, slender)


def slender_domain(fired: dict, truth: dict, slender: dict) -> tuple:
    """How slender the tops are that each class's rules proved its training positives with
    (:func:`plane_slenderness`): ``((class, high, n), ...)``, as :func:`size_domain`.

    A positive's slenderness is the least, over the hits of its class that bind a top, of
    :func:`proof_slenderness`; ``high`` is the largest over the class's positives, so the gate
    of :func:`slender_refusals` refuses no proof whose top is as compact as a training one's;
    ``n`` counts the positives proved with a top."""
    return _proof_domain(fired, truth, slender)


@dataclass(frozen=True)
class SlenderRefusal(_Bounded):
    """A rule whose proof of an object binds a top far more slender than any top of the
    class's training proofs (:func:`slender_refusals`): a thin wall's or a slab's strip."""

    klass: str
    rule: int
    slenderness: float
    high: float
    margin: float

    @property
    def reason(self) -> str:
        return (f"rule {self.rule} proves it with a top {self.slenderness:.1f} times as long as "
                f"wide, over {self.bound:.1f}: the training {self.klass} proofs' tops reach "
                f"{self.high:.1f}, margin {self.margin:g} (a thin wall's or a slab's strip)")

    def to_dict(self) -> dict:
        return {"class": self.klass, "rule": self.rule,
                "proof_slenderness": round(self.slenderness, 4), "proofs_high": self.high,
                "margin": self.margin, "reason": self.reason}


def slender_refusals(hits, stats: Sequence, slender, domain: Sequence,
                     margin: float = SLENDER_MARGIN, min_positives: int = PROOF_MIN_POSITIVES):
    """Leave out the hits whose proof binds a top far more slender than the tops of the
    class's training proofs.

    A class with an entry ``(class, high, n)`` in ``domain`` (:func:`slender_domain`, measured
    on at least ``min_positives`` positives) refuses a hit of its class whose
    :func:`proof_slenderness` exceeds ``high * (1 + margin)``: the top strip of an 8 cm thick
    wall seen with its side or its end face below it (``skirt``) says "box" of something no
    box of the training world is the shape of (docs/objects.md, "Thin walls and slabs are no
    boxes").  No domain, no slenderness, or a class without an entry: nothing is refused.

    Parameters
    ----------
    slender : dict or callable
        ``{plane id: slenderness}`` (:func:`plane_slenderness`), or a callable returning it
        (asked only when a class with an entry fired).

    Returns
    -------
    (list, tuple of SlenderRefusal)
        The hits left, and one :class:`SlenderRefusal` per refused rule that takes part in
        the decision (:func:`takes_part`).
    """
    return _bound_refusals(hits, stats, slender, domain, margin, min_positives, SlenderRefusal)


def plane_ranges(descs) -> dict:
    """``{plane id: range}`` (m) over scene descriptions: each plane's centroid distance from
    the sensor (the ``distance/2`` fact)."""
    return {d.plane_id(p.label): float(p.distance) for d in descs for p in d.planes}


def proof_range(bindings: dict, ranges: dict):
    """The farthest from the sensor among the planes a proof binds (m; :func:`plane_ranges`),
    or None when the proof binds no plane of ``ranges``."""
    return _proof_max(bindings, ranges)


def range_domain(fired: dict, truth: dict, ranges: dict) -> tuple:
    """How far from the sensor the planes lie that each class's rules proved its training
    positives with (:func:`plane_ranges`): ``((class, high, n), ...)``, as :func:`size_domain`.

    A positive's range is the least, over the hits of its class, of :func:`proof_range` (its
    nearest proof's farthest plane); ``high`` is the largest over the class's positives, so
    the gate of :func:`range_refusals` refuses no proof made as near as a training one; ``n``
    counts the positives with a range."""
    return _proof_domain(fired, truth, ranges)


@dataclass(frozen=True)
class RangeRefusal(_Bounded):
    """A rule whose proof of an object binds a plane farther from the sensor than any plane
    of the class's training proofs, by more than the margin (:func:`range_refusals`): the
    rule's facts were never seen that far away, where depth is coarse and planes are cut."""

    klass: str
    rule: int
    distance: float
    high: float
    margin: float

    @property
    def reason(self) -> str:
        return (f"rule {self.rule} proves it with a plane {self.distance:.2f} m from the "
                f"sensor, over {self.bound:.2f} m: the training {self.klass} proofs' planes "
                f"lie at most {self.high:.2f} m away, margin {self.margin:g} (no evidence "
                f"that far)")

    def to_dict(self) -> dict:
        return {"class": self.klass, "rule": self.rule,
                "proof_distance": round(self.distance, 4), "proofs_high": self.high,
                "margin": self.margin, "reason": self.reason}


def range_refusals(hits, stats: Sequence, ranges, domain: Sequence,
                   margin: float = RANGE_MARGIN, min_positives: int = PROOF_MIN_POSITIVES):
    """Leave out the hits whose proof binds a plane farther from the sensor than the planes
    of the class's training proofs.

    A class with an entry ``(class, high, n)`` in ``domain`` (:func:`range_domain`, measured on
    at least ``min_positives`` positives) refuses a hit of its class whose
    :func:`proof_range` exceeds ``high * (1 + margin)``: the demo's ramp rule ("a plane of
    0.53 m^2 or more at most 28 degrees steep") proved far verges, lawns and road strips
    10.5-17.4 m away on stereo and densified LiDAR, where the training world's ramps lie at
    most 3.54 m away, and its stairs rule proved disparity terraces of a loading hall 9-18 m
    away (docs/results.md, "Proofs farther away than any training proof").  No
    domain, no ranges, or a class without an entry: nothing is refused.

    Parameters
    ----------
    ranges : dict or callable
        ``{plane id: range}`` (:func:`plane_ranges`), or a callable returning it (asked only
        when a class with an entry fired).

    Returns
    -------
    (list, tuple of RangeRefusal)
        The hits left, and one :class:`RangeRefusal` per refused rule that takes part in the
        decision (:func:`takes_part`).
    """
    return _bound_refusals(hits, stats, ranges, domain, margin, min_positives, RangeRefusal)


@dataclass(frozen=True)
class FlightRefusal:
    """``stairs`` proved of an object whose faces show no staircase's steps
    (:func:`flight_refusals`)."""

    klass: str

    @property
    def reason(self) -> str:
        return ("no faces in a flight's row and no steps of one flight's rise and run "
                "(a pile of several heights, boxes touching, no step at all)")

    def to_dict(self) -> dict:
        return {"class": self.klass, "reason": self.reason}


def flight_refusals(hits, stats: Sequence, flight=None):
    """Leave out the ``stairs`` hits of an object whose faces show no staircase's steps.

    A stairs rule of the demo's model says "two parallel planes, one above the other" (with a
    third and fourth below, or a level lower one): every flight it was counted on showed its
    steps in a regular row or the two steps of a short flight, but a pile of cartons at three
    heights, boxes of two heights touching or a machine's faces satisfy it too.  ``flight``:
    None (the gate off), a bool, or a callable asked only when a stairs hit is there
    (:func:`planerel.features.step_chains.flight_evidence` of the object's planes).

    Returns
    -------
    (list, tuple of FlightRefusal)
        The hits left, and one :class:`FlightRefusal` when stairs is refused by a rule that
        takes part in the decision (:func:`takes_part`).
    """
    if flight is None or not any(h[0] == FLIGHT_CLASS for h in hits):
        return list(hits), ()
    if callable(flight):
        flight = flight()
    if flight:
        return list(hits), ()
    table = {i: (tp, fp) for i, _, tp, fp in stats}
    kept = [h for h in hits if h[0] != FLIGHT_CLASS]
    counted = any(takes_part(*table.get(h[1], (0, 0))) for h in hits if h[0] == FLIGHT_CLASS)
    return kept, ((FlightRefusal(FLIGHT_CLASS),) if counted else ())


@dataclass(frozen=True)
class FootRefusal:
    """``ramp`` proved of an object whose sloping proof plane stands on no floor
    (:func:`foot_refusals`)."""

    klass: str
    rule: int
    low: float
    hidden: float
    above: float
    below: float
    #: the bound past which a hidden low end is refused too (0: none)
    float_: float = 0.0

    @property
    def reason(self) -> str:
        if self.low < 0:
            return (f"rule {self.rule} proves it with a sloping plane reaching {-self.low:.2f} m "
                    f"under the floor (more than {self.below:.2f} m)")
        if self.float_ > 0 and self.low > self.float_:
            return (f"rule {self.rule} proves it with a sloping plane whose low end lies "
                    f"{self.low:.2f} m over the floor (more than {self.float_:.2f} m: it cannot "
                    f"reach the floor out of sight; {self.hidden:.0%} of it hidden)")
        return (f"rule {self.rule} proves it with a sloping plane whose low end lies "
                f"{self.low:.2f} m over the floor (more than {self.above:.2f} m) in plain view "
                f"({self.hidden:.0%} of it out of sight)")

    def to_dict(self) -> dict:
        return {"class": self.klass, "rule": self.rule, "low": round(self.low, 4),
                "hidden": round(self.hidden, 3), "above": self.above, "below": self.below,
                "float": self.float_, "reason": self.reason}


def foot_refusals(hits, stats: Sequence, foot=None, above: float = FOOT_ABOVE,
                  below: float = FOOT_BELOW, hidden: float = FOOT_HIDDEN,
                  float_: float = FOOT_FLOAT):
    """Leave out the ``ramp`` hits whose proof's sloping planes all stand on no floor.

    A ramp rises from the floor: its slope's low end meets the floor's level.  A hit of
    :data:`FOOT_CLASS` is refused when every plane of its proof that ``foot`` measures (the
    inclined ones) has its lowest point more than ``below`` under the floor, or more than
    ``above`` over it with under ``hidden`` of its low end out of sight, or more than
    ``float_`` over it however much is out of sight (0: no such bound)
    (:class:`planerel.features.foot.Foot`).  A proof without a measured plane is kept.

    Parameters
    ----------
    foot : callable or None
        ``foot(plane id) -> Foot or None`` (None for a plane that is not inclined or not
        measured); None: the gate is off.

    Returns
    -------
    (list, tuple of FootRefusal)
        The hits left, and one :class:`FootRefusal` per refused rule that takes part in the
        decision (:func:`takes_part`).
    """
    if foot is None or not any(h[0] == FOOT_CLASS for h in hits):
        return list(hits), ()

    def refuse(hit):
        if hit[0] != FOOT_CLASS:
            return None
        feet = [f for f in (foot(v) for v in dict(hit[2]).values()) if f is not None]
        bad = [f for f in feet
               if f.low < -float(below) or (f.low > float(above) and f.hidden < float(hidden))
               or (float_ > 0 and f.low > float(float_))]
        if not feet or len(bad) != len(feet):
            return None
        f = max(bad, key=lambda f: abs(f.low))
        return FootRefusal(FOOT_CLASS, hit[1], f.low, f.hidden, float(above), float(below),
                           float(float_))

    return _refuse_hits(hits, stats, refuse)


@dataclass(frozen=True)
class SideRefusal:
    """``ramp`` (``stairs``) proved of an object whose sloping (level) proof planes are all
    seen from below (:func:`side_refusals`)."""

    klass: str
    rule: int
    #: the proof plane's ``normal . up`` (normal turned to the sensor) nearest to facing up
    facing: float

    @property
    def reason(self) -> str:
        what = ("level planes", "no flight's treads") if self.klass == "stairs" else \
            ("a sloping plane", "no walked-on slope")
        return (f"rule {self.rule} proves it with {what[0]} the camera sees from below "
                f"(normal towards the sensor . up = {self.facing:.2f} at most): an underside, "
                f"{what[1]}")

    def to_dict(self) -> dict:
        return {"class": self.klass, "rule": self.rule, "facing": round(self.facing, 4),
                "reason": self.reason}


def side_refusals(hits, stats: Sequence, side=None, treads=(), under_eye: bool = False):
    """Leave out the ``ramp`` and ``stairs`` hits whose proof's walked-on planes are all seen
    from below.

    A ramp's slope and a flight's treads are walked on: their walked-on side faces up, and a
    camera sees that side only from above the plane.  A plane the camera sees from below (its
    normal, turned to the sensor, points down) is an underside: a table's, a shelf's, a
    ceiling's (a ceiling's disparity terraces seen from 0.1 m, hunt45).  A hit of a class of
    :data:`SIDE_PLANES` is refused when every plane of its proof of that class's orientation
    (inclined for ``ramp``, horizontal for ``stairs``) has ``side(plane) < 0``; for
    ``stairs`` the object's own level planes (``treads``) count too, since a flight's rule may
    bind its risers only.  A proof without such a measured plane is kept.

    Parameters
    ----------
    side : callable or None
        ``side(plane id) -> (orientation, float) or None``: the plane's orientation and its
        ``normal . up`` with the normal turned to the sensor (None for a plane not measured);
        None: the gate is off.
    treads : sequence of float
        ``normal . up`` (normal turned to the sensor) of the object's horizontal planes.
    under_eye : bool
        Some plane of the object lies (its centroid) under the camera's eye: then ``stairs``
        proved by risers only (every measured proof plane vertical) is not refused.  A flight
        rising before a low camera (a robot's, 0.3 m up) has its lower risers under the eye
        and shows no tread from above (those under the eye are seen edge on); the stair fit of
        its far part (:mod:`planerel.features.stairfit`) puts level pieces on its risers' top
        edges, which are seen from below.  A ceiling's or a shelf's underside lies wholly over
        the eye; a scene read with a wrong up proves its "steps" with tilted planes
        (riser73: dev_lows i0012; hunt57 sg-lab-box).

    Returns
    -------
    (list, tuple of SideRefusal)
        The hits left, and one :class:`SideRefusal` per refused rule that takes part in the
        decision (:func:`takes_part`).
    """
    if side is None or not any(h[0] in SIDE_PLANES for h in hits):
        return list(hits), ()

    def refuse(hit):
        want = SIDE_PLANES.get(hit[0])
        if want is None:
            return None
        measured = [m for m in (side(v) for v in dict(hit[2]).values()) if m is not None]
        facing = [m[1] for m in measured if m[0] == want]
        if hit[0] == "stairs":
            if under_eye and measured and all(m[0] == "vertical" for m in measured):
                return None  # a flight's risers rising over a low camera's eye (riser73)
            facing += [float(f) for f in treads]
        if not facing or max(facing) >= 0:
            return None
        return SideRefusal(hit[0], hit[1], float(max(facing)))

    return _refuse_hits(hits, stats, refuse)


@dataclass(frozen=True)
class PitchRefusal:
    """``ramp`` proved with sloping planes at the pitch of the flight a ``stairs`` rule proves
    of the same object (:func:`pitch_refusals`)."""

    klass: str
    rule: int
    #: the proof's sloping plane farthest off the flight's pitch: its incline (degrees)
    incline: float
    #: the flight's pitch (degrees) from the object's steps
    pitch: float

    @property
    def reason(self) -> str:
        return (f"rule {self.rule} proves it with a slope of {self.incline:.1f} degrees, the "
                f"pitch of the flight the object's own steps make ({self.pitch:.1f}): the "
                f"flight's far part seen as one surface")

    def to_dict(self) -> dict:
        return {"class": self.klass, "rule": self.rule, "incline": round(self.incline, 2),
                "pitch": round(self.pitch, 2), "reason": self.reason}


def pitch_refusals(hits, stats: Sequence, pitch=None, tol: float = PITCH_TOL):
    """Leave out the ``ramp`` hits whose sloping proof planes all lie at the pitch of the flight
    a ``stairs`` hit proves of the same object.

    A flight seen from far shows its near steps as treads and risers and its far part, whose
    faces are too small to be planes, as one surface along its nosings: a plane rising the
    flight's way at the flight's pitch (the arctangent of rise over run).  A hit of
    :data:`PITCH_CLASS` is refused when a hit of :data:`PITCH_FLIGHT` is among ``hits`` and
    every plane of its proof that ``pitch`` measures lies within ``tol`` degrees of the
    flight's pitch.  A proof without a measured plane is kept.

    Parameters
    ----------
    pitch : callable or None
        ``pitch(plane id) -> (incline, flight pitch) or None`` in degrees (None for a plane
        that is not inclined, that rises another way than the object's steps, or when the
        object's steps give no pitch); None: the gate is off.
    tol : float
        Degrees.

    Returns
    -------
    (list, tuple of PitchRefusal)
        The hits left, and one :class:`PitchRefusal` per refused rule that takes part in the
        decision (:func:`takes_part`).
    """
    if (pitch is None or not any(h[0] == PITCH_CLASS for h in hits)
            or not any(h[0] == PITCH_FLIGHT for h in hits)):
        return list(hits), ()

    def refuse(hit):
        if hit[0] != PITCH_CLASS:
            return None
        measured = [m for m in (pitch(v) for v in dict(hit[2]).values()) if m is not None]
        if not measured:
            return None
        worst = max(measured, key=lambda m: abs(m[0] - m[1]))
        if abs(worst[0] - worst[1]) > float(tol):
            return None
        return PitchRefusal(PITCH_CLASS, hit[1], float(worst[0]), float(worst[1]))

    return _refuse_hits(hits, stats, refuse)


@dataclass(frozen=True)
class UnsureRefusal:
    """``ramp`` proved in a scene whose up is a low-confidence estimate with no floor in view,
    an estimate read upside down, or one a speckle floor decided with no floor plane in view
    (:func:`unsure_refusals`)."""

    klass: str
    rule: int
    #: the up estimate's confidence (under ``gravity.low_confidence``, or any when
    #: ``upside_down`` or ``sparse_floor``)
    confidence: float
    #: the estimate is the upside-down reading (``decision.unsure_upside``)
    upside_down: bool = False
    #: the estimate is a speckle floor's, no floor plane in view (``decision.unsure_sparse``)
    sparse_floor: bool = False

    @property
    def reason(self) -> str:
        if self.sparse_floor:
            return (f"rule {self.rule} proves it with a slope measured against an up that a "
                    f"floor seen only as speckle decided ({self.confidence:.2f}), and no floor "
                    f"plane is in view: nothing confirms that speckle is the floor; pass --up "
                    f"when the camera's pose is known")
        if self.upside_down:
            return (f"rule {self.rule} proves it with a slope measured against an up estimated "
                    f"upside down ({self.confidence:.2f}): such a reading is most often wrong "
                    f"(its floor a ceiling), and nothing confirms the slope under it; pass --up "
                    f"when the camera is mounted upside down")
        return (f"rule {self.rule} proves it with a slope measured against an up estimated "
                f"with low confidence ({self.confidence:.2f}) and no floor in view: nothing "
                f"confirms that the plane is not the ground itself under a wrong up")

    def to_dict(self) -> dict:
        return {"class": self.klass, "rule": self.rule,
                "confidence": round(self.confidence, 4), "upside_down": self.upside_down,
                "sparse_floor": self.sparse_floor, "reason": self.reason}


def unsure_refusals(hits, stats: Sequence, unsure=None):
    """Leave out the ``ramp`` hits of a scene whose up is unconfirmed.

    A slope is inclined only against the up vector, and a ramp rises from a floor.  When the
    up is an estimate the estimator flags as low-confidence and no floor plane is in view,
    nothing confirms that a large "inclined" plane is not the ground itself seen under a
    wrong up (a camera 0.1 m over the floor whose estimate a far, bent floor wins: hunt45).
    Every hit of :data:`UNSURE_CLASS` is then refused.

    Parameters
    ----------
    unsure : float, (float, bool), (float, bool, bool) or None
        The up estimate's confidence when the scene's up is low-confidence and it has no
        floor plane, ``(confidence, True)`` when the estimate is read upside down
        (``decision.unsure_upside``), ``(confidence, False, True)`` when a speckle floor
        decided it and no floor plane is in view (``decision.unsure_sparse``); None: the gate
        is off or the scene's up is not in doubt.

    Returns
    -------
    (list, tuple of UnsureRefusal)
        The hits left, and one :class:`UnsureRefusal` per refused rule that takes part in the
        decision (:func:`takes_part`).
    """
    if unsure is None or not any(h[0] == UNSURE_CLASS for h in hits):
        return list(hits), ()
    # a bare confidence, (confidence, upside down) or (confidence, upside down, speckle floor);
    # the flags left out are False
    parts = tuple(unsure) if isinstance(unsure, tuple) else (unsure,)
    conf, upside, sparse = parts + (False,) * (3 - len(parts))
    return _refuse_hits(hits, stats, lambda hit: UnsureRefusal(UNSURE_CLASS, hit[1], float(conf),
                                                               bool(upside), bool(sparse))
                        if hit[0] == UNSURE_CLASS else None)


def proof_domain(fired: dict, truth: dict) -> tuple:
    """How large the planes are that each rule proved its training positives with:
    ``((index, class, low, high, n), ...)`` per rule of a class (not :data:`OTHER`).

    A hit's proof scale (its fifth element, ``planerel_proof_scale/4`` in
    ``prolog/classify.pl``) is the largest, over the rule's proofs of the object, of the
    smallest area among the planes a proof binds (m^2).  ``low`` is the minimum over the
    objects of the rule's class it proves (its true positives), so the gate of
    :func:`proof_refusals` refuses no proof as large as a training one and the rule's
    ``tp`` holds under it.  A rule without a true positive with a scale has no entry.

    Parameters
    ----------
    fired : dict
        ``{object: [(class, index, bindings, text, scale), ...]}``.
    truth : dict
        ``{object: class}`` of the training objects.
    """
    scales: dict = {}
    for obj, hits in fired.items():
        for hit in hits:
            k, i = hit[0], hit[1]
            scale = hit[4] if len(hit) > 4 else None
            if k != OTHER and truth.get(obj) == k and scale is not None:
                scales.setdefault((i, k), []).append(float(scale))
    return tuple((i, k, round(min(v), 5), round(max(v), 5), len(v))
                 for (i, k), v in sorted(scales.items()))


@dataclass(frozen=True)
class ProofRefusal:
    """A rule that proved an object only with planes far smaller than in any of its training
    proofs: the object's proof scale lies under ``bound`` (:func:`proof_bound`)."""

    klass: str
    rule: int
    scale: float
    low: float
    high: float
    margin: float

    @property
    def bound(self) -> float:
        """The proof scale (m^2) under which the rule is refused (:func:`proof_bound`)."""
        return proof_bound(self.low, self.high, self.margin)

    @property
    def reason(self) -> str:
        return (f"rule {self.rule} proves it with planes of {self.scale:.4f} m^2, under "
                f"{self.bound:.4f}: its training {self.klass} proofs {self.low:.4f}-"
                f"{self.high:.4f} m^2, margin {self.margin:g}")

    def to_dict(self) -> dict:
        return {"class": self.klass, "rule": self.rule, "proof_scale": round(self.scale, 5),
                "proofs_low": self.low, "proofs_high": self.high, "margin": self.margin,
                "reason": self.reason}


def proof_bound(low: float, high: float, margin: float = PROOF_MARGIN) -> float:
    """The proof scale under which :func:`proof_refusals` refuses a rule whose training proofs
    span ``low``-``high`` m^2: the range widened below by ``margin`` of its width on a log
    scale, ``low * (low / high) ** margin``.

    A rule whose training proofs span two orders of magnitude (the demo's box rule: faces of
    6 cm to 75 cm) says little about where its smallest positives end, and gets a wide margin
    (0.0036 -> 0.0008 m^2); one whose proofs keep a physical scale (treads of a flight: one
    order) a narrow one (0.042 -> 0.021 m^2).  0 when ``low`` or ``high`` is not positive.
    """
    low, high = float(low), float(high)
    if low <= 0 or high <= 0:
        return 0.0
    return low * (low / high) ** float(margin)


def proof_refusals(hits, stats: Sequence, domain: Sequence, margin: float = PROOF_MARGIN,
                   min_positives: int = PROOF_MIN_POSITIVES):
    """Leave out the hits whose proof is made of planes far smaller than the rule's training
    proofs.

    A rule with an entry ``(index, class, low, high, n)`` in ``domain`` (:func:`proof_domain`)
    is refused for an object whose proof scale (the hit's fifth element) is below
    :func:`proof_bound`: the rule was only ever counted right on proofs of planes at least
    ``low`` m^2, and "a plane parallel to and above another" said of two slivers of a pile of
    tins is not what it learned (docs/results.md, "The proof gate").  An entry counts only when it was
    measured on at least ``min_positives`` true positives: the least of a handful of proofs
    says little about where the rule's positives end.  No domain, no entry or no scale:
    nothing is refused.

    Returns
    -------
    (list, tuple of ProofRefusal)
        The hits left, and one :class:`ProofRefusal` per refused rule that takes part in the
        decision (:func:`takes_part`).
    """
    if not domain:
        return list(hits), ()
    bounds = {i: (k, lo, hi) for i, k, lo, hi, n in domain if n >= min_positives}
    table = {i: (tp, fp) for i, _, tp, fp in stats}
    kept, refused = [], []
    for hit in hits:
        scale = hit[4] if len(hit) > 4 else None
        entry = bounds.get(hit[1])
        if entry is not None and scale is not None and entry[0] == hit[0]:
            k, lo, hi = entry
            if float(scale) < proof_bound(lo, hi, margin):
                if takes_part(*table.get(hit[1], (0, 0))):
                    refused.append(ProofRefusal(k, hit[1], float(scale), lo, hi, float(margin)))
                continue
        kept.append(hit)
    return kept, tuple(refused)


@dataclass(frozen=True)
class VetoRefusal:
    """A rule for ``other`` set aside for an object because a class rule proves the object with
    planes more than ``ratio`` times larger than any proof of the veto binds."""

    rule: int
    scale: float
    by_class: str
    by_rule: int
    by_scale: float
    ratio: float
    klass: str = OTHER

    @property
    def reason(self) -> str:
        return (f"rule {self.rule} proves it only with planes of {self.scale:.4f} m^2; "
                f"{self.by_class} rule {self.by_rule} proves it with planes of "
                f"{self.by_scale:.4f} m^2, more than {self.ratio:g} times larger")

    def to_dict(self) -> dict:
        return {"class": self.klass, "rule": self.rule, "proof_scale": round(self.scale, 5),
                "by_class": self.by_class, "by_rule": self.by_rule,
                "by_scale": round(self.by_scale, 5), "ratio": self.ratio, "reason": self.reason}


def veto_refusals(hits, stats: Sequence, ratio: float = VETO_RATIO):
    """Set aside the rules for ``other`` (vetoes) that prove an object only through planes far
    smaller than a class rule's proof of it.

    Every scanned object has slivers: a stair's nosing and the lip before its riser, a box's
    rounded edge, mixed pixels along a depth edge.  A veto learned from synthetic clutter
    ("an inclined plane shorter than 0.7 m") fires on such a sliver of a real flight; a class
    rule proves the same object through its treads and risers.  The sliver says little
    against them.  A veto hit whose proof scale (the hit's fifth element, the largest over
    its proofs of the smallest plane a proof binds; :func:`proof_refusals`) times ``ratio``
    is below the largest proof scale of a class hit that takes part (:func:`takes_part`) is
    left out; a veto proved through planes as large as the class proof's (a chair's seat, a
    shelf board) or through no plane at all (``curved(A)``) still counts.  ``ratio`` 0 or
    no class hit with a scale: nothing is set aside.

    Returns
    -------
    (list, tuple of VetoRefusal)
        The hits left, and one :class:`VetoRefusal` per veto set aside that takes part.
    """
    if not ratio:
        return list(hits), ()
    table = {i: (tp, fp) for i, _, tp, fp in stats}
    top = None
    for hit in hits:
        scale = hit[4] if len(hit) > 4 else None
        if (hit[0] != OTHER and scale is not None and takes_part(*table.get(hit[1], (0, 0)))
                and (top is None or float(scale) > top[2])):
            top = (hit[0], hit[1], float(scale))
    if top is None:
        return list(hits), ()
    kept, refused = [], []
    for hit in hits:
        scale = hit[4] if len(hit) > 4 else None
        if hit[0] == OTHER and scale is not None and float(scale) * ratio < top[2]:
            if takes_part(*table.get(hit[1], (0, 0))):
                refused.append(VetoRefusal(hit[1], float(scale), *top, float(ratio)))
            continue
        kept.append(hit)
    return kept, tuple(refused)


@dataclass(frozen=True)
class FacetRefusal:
    """``box`` proved through an upright plane that is a facet of a round side
    (:func:`facet_refusals`)."""

    klass: str
    rule: int
    #: the proof's plane and its facet neighbour's angle to it (degrees)
    plane: str
    angle: float

    @property
    def reason(self) -> str:
        return (f"rule {self.rule} proves it with the upright plane {self.plane}, which meets "
                f"another upright plane of the object at {self.angle:.1f} degrees, convex and "
                f"level, and no plane at a box's corner angle: a facet of a round side")

    def to_dict(self) -> dict:
        return {"class": self.klass, "rule": self.rule, "plane": self.plane,
                "angle": round(self.angle, 2), "reason": self.reason}


@dataclass(frozen=True)
class FlightSideRefusal:
    """``box`` for an object that runs beside a flight answered ``stairs`` in the same scan
    (``decision.flight_side_gate``, :func:`planerel.features.flight_side.beside_flight`)."""

    klass: str
    rule: int
    #: the ``stairs`` answer's object id
    flight: str
    thick: float
    gap: float
    rise: float

    @property
    def reason(self) -> str:
        return (f"rule {self.rule} proves it, but it runs beside the flight {self.flight}: "
                f"{self.thick:.2f} m across it, {self.gap:.2f} m beyond its treads' ends, its "
                f"top {self.rise:.2f} m over the flight's: the flight's side wall")

    def to_dict(self) -> dict:
        return {"class": self.klass, "rule": self.rule, "flight": self.flight,
                "thick": round(self.thick, 3), "gap": round(self.gap, 3),
                "rise": round(self.rise, 3), "reason": self.reason}


@dataclass(frozen=True)
class HangRefusal:
    """``box`` for an object whose upright proof faces hang over the space beneath them
    (``decision.hang_gate``, :func:`planerel.features.hang.face_hang`)."""

    klass: str
    rule: int
    #: the hanging faces' plane ids
    faces: tuple
    #: the least hanging share among them
    share: float
    #: the highest lower edge among them, metres over the floor
    bottom: float

    @property
    def reason(self) -> str:
        return (f"rule {self.rule} proves it, but its upright faces {', '.join(self.faces)} "
                f"hang: beneath their lower edges ({self.bottom:.2f} m up) the camera sees "
                f"farther, lower points on {self.share:.0%} of the lines or more, and no "
                f"horizontal plane carries them")

    def to_dict(self) -> dict:
        return {"class": self.klass, "rule": self.rule, "faces": list(self.faces),
                "share": round(self.share, 3), "bottom": round(self.bottom, 3),
                "reason": self.reason}


@dataclass(frozen=True)
class LongLyingRefusal:
    """``box`` for an object proved by a top alone that is longer than a lying box's
    (``decision.long_lying_gate``)."""

    klass: str
    rule: int
    #: the top's plane id
    top: str
    #: its length, metres
    length: float
    #: the gate's bound, metres
    bound: float

    @property
    def reason(self) -> str:
        return (f"rule {self.rule} proves it by the top {self.top} alone (no upright face), "
                f"but that top is {self.length:.2f} m long, over {self.bound:.2f} m: a flat "
                f"box that long shows its sides")

    def to_dict(self) -> dict:
        return {"class": self.klass, "rule": self.rule, "top": self.top,
                "length": round(self.length, 3), "bound": self.bound, "reason": self.reason}


@dataclass(frozen=True)
class SlabRefusal:
    """``box`` for an object whose proof's top is a slab's edge: narrow, with an upright plane
    of the object reaching far below it (``decision.slab_gate``,
    :func:`planerel.features.slab.slab_edge`)."""

    klass: str
    rule: int
    #: the top's plane id
    top: str
    #: the upright plane's id
    face: str
    #: the top's width, metres
    width: float
    #: how far the face reaches below the top, metres
    drop: float

    @property
    def reason(self) -> str:
        return (f"rule {self.rule} proves it, but its top {self.top} is {self.width:.2f} m wide "
                f"and {self.face} reaches {self.drop:.2f} m below it: the edge of a wall, a "
                f"door or a panel, not a box")

    def to_dict(self) -> dict:
        return {"class": self.klass, "rule": self.rule, "top": self.top, "face": self.face,
                "width": round(self.width, 3), "drop": round(self.drop, 3),
                "reason": self.reason}


@dataclass(frozen=True)
class CrowdRefusal:
    """``box`` for an object of more planes than a box shows (``decision.crowd_gate``)."""

    klass: str
    rule: int
    #: the object's number of planes
    planes: int
    #: the gate's bound
    bound: int

    @property
    def reason(self) -> str:
        return (f"rule {self.rule} proves it, but the object holds {self.planes} planes, over "
                f"{self.bound}: a box shows at most three faces; so many planes are furniture "
                f"with what it carries, or a desk with everything on it")

    def to_dict(self) -> dict:
        return {"class": self.klass, "rule": self.rule, "planes": self.planes,
                "bound": self.bound, "reason": self.reason}


@dataclass(frozen=True)
class FarPlaneRefusal:
    """``box`` or ``ramp`` for an object proved through a plane that only the segmentation's
    far growing found (``decision.far_gate``)."""

    klass: str
    rule: int
    #: the far planes' ids among the proof's
    planes: tuple

    @property
    def reason(self) -> str:
        return (f"rule {self.rule} proves it through {', '.join(self.planes)}, found only by "
                f"the far growing (far_theta): too coarse a plane to prove a {self.klass}")

    def to_dict(self) -> dict:
        return {"class": self.klass, "rule": self.rule, "planes": list(self.planes),
                "reason": self.reason}


@dataclass(frozen=True)
class SlopePartsRefusal:
    """``ramp`` for an object whose sloping proof planes each have a part that does not slope
    as the whole does (``decision.slope_parts_gate``,
    :func:`planerel.features.slope_parts.slope_parts`)."""

    klass: str
    rule: int
    #: the judged sloping proof planes' ids
    planes: tuple
    #: each plane's parts' slopes as shares of its whole's, in ``planes``' order
    shares: tuple
    #: the gate's bound on ``|share - 1|``
    bound: float

    @property
    def reason(self) -> str:
        worst = min((max(sh, key=lambda v: abs(v - 1.0)) for sh in self.shares),
                    key=lambda v: abs(v - 1.0))
        return (f"rule {self.rule} proves it through {', '.join(self.planes)}, but a part of "
                f"each slopes {worst:.2f} times as steeply as the whole (more than "
                f"{self.bound:g} off): no one flat slope")

    def to_dict(self) -> dict:
        return {"class": self.klass, "rule": self.rule, "planes": list(self.planes),
                "shares": [[round(v, 3) for v in sh] for sh in self.shares],
                "bound": self.bound, "reason": self.reason}


@dataclass(frozen=True)
class NarrowFaceRefusal:
    """``box`` for an object whose upright proof faces are all far taller than wide
    (``decision.narrow_face_gate``, :func:`planerel.features.face_shape.face_extent`)."""

    klass: str
    rule: int
    #: the narrow faces' plane ids
    faces: tuple
    #: the least height over width among them
    ratio: float
    #: the gate's bound
    bound: float

    @property
    def reason(self) -> str:
        return (f"rule {self.rule} proves it, but its upright faces {', '.join(self.faces)} "
                f"are {self.ratio:.1f} times as tall as wide or more, over {self.bound:g}: "
                f"a post's, a jamb's or a wall's end, not a box's side")

    def to_dict(self) -> dict:
        return {"class": self.klass, "rule": self.rule, "faces": list(self.faces),
                "ratio": round(self.ratio, 3), "bound": self.bound, "reason": self.reason}


def facet_refusals(hits, stats: Sequence, facet=None):
    """Leave out the ``box`` hits whose proof binds an upright plane that is a facet of a round
    side (``decision.facet_gate``).

    Parameters
    ----------
    facet : callable or None
        ``facet(plane id) -> float or None``: the angle (degrees) of the plane's facet
        neighbour when it has one and no box-corner partner (see
        :attr:`DecisionParams.facet_gate`), else None; None: the gate is off.

    Returns
    -------
    (list, tuple of FacetRefusal)
        The hits left, and one :class:`FacetRefusal` per refused rule that takes part in the
        decision (:func:`takes_part`).
    """
    if facet is None or not any(h[0] == FACET_CLASS for h in hits):
        return list(hits), ()

    def refuse(hit):
        if hit[0] != FACET_CLASS:
            return None
        for v in dict(hit[2]).values():
            a = facet(v)
            if a is not None:
                return FacetRefusal(hit[0], hit[1], str(v), float(a))
        return None

    return _refuse_hits(hits, stats, refuse)


def decide(hits, stats: Sequence, classes: Sequence[str], cofire: Sequence = (), *,
           planar_fraction=None, domain: Sequence = (), margin: float = PLANAR_MARGIN,
           proofs: Sequence = (), proof_margin: float = PROOF_MARGIN,
           proof_min_positives: int = PROOF_MIN_POSITIVES, veto_ratio: float = 0.0,
           n_horizontal=None, levels: Sequence = (), stepped=False, flight=None,
           extents=None, sizes: Sequence = (), size_margin: float = SIZE_MARGIN,
           slender=None, slenders: Sequence = (), slender_margin: float = SLENDER_MARGIN,
           distances=None, ranges: Sequence = (), range_margin: float = RANGE_MARGIN,
           foot=None, foot_above: float = FOOT_ABOVE, foot_below: float = FOOT_BELOW,
           foot_hidden: float = FOOT_HIDDEN, foot_float: float = FOOT_FLOAT, side=None,
           treads=(), under_eye: bool = False, unsure=None, facet=None, pitch=None,
           pitch_tol: float = PITCH_TOL):
    """The open-set decision for one object: :func:`foot_refusals` (``foot``; None, the
    default, off), :func:`side_refusals` (``side``, and the object's ``treads`` and
    ``under_eye``; None, the default, off), :func:`unsure_refusals` (``unsure``; None, the
    default, off),
    :func:`facet_refusals` (``facet``; None, the default, off), :func:`pitch_refusals`
    (``pitch`` and ``pitch_tol``; None, the default, off), :func:`proof_refusals` (with
    ``proofs``, the
    model's :func:`proof_domain`), :func:`size_refusals` (``sizes``, the model's
    :func:`size_domain`, and the scene's plane ``extents``), :func:`slender_refusals`
    (``slenders``, the model's :func:`slender_domain`, and the scene's tops' ``slender``),
    :func:`range_refusals` (``ranges``, the model's :func:`range_domain`, and the scene's
    planes' ``distances``),
    :func:`planar_refusals` (``domain``),
    :func:`level_refusals` (``levels``, the model's :func:`level_domain`, and the object's
    ``n_horizontal`` and ``stepped``), :func:`flight_refusals` (``flight``; None, the
    default here, off), :func:`veto_refusals`
    (``veto_ratio``; 0, the default here, off: callers pass the model's setting), then
    :func:`choose_class` among the hits left.  The classifier and the learner's own scoring
    (:func:`planerel.ilp.pipeline.prolog_predict`, whichever engine learned the rules) decide
    with it.

    Returns
    -------
    (hit or None, tuple of Refusal, ProofRefusal, SizeRefusal, SlenderRefusal, RangeRefusal,
    LevelRefusal, FlightRefusal, FootRefusal, SideRefusal, UnsureRefusal,
    FacetRefusal, PitchRefusal and VetoRefusal)
        The chosen hit (None: :data:`OTHER`) and the rules and classes refused.
    """
    kept, small = proof_refusals(hits, stats, proofs, proof_margin, proof_min_positives)
    kept, large = size_refusals(kept, stats, extents, sizes, size_margin, proof_min_positives)
    kept, thin = slender_refusals(kept, stats, slender, slenders, slender_margin,
                                  proof_min_positives)
    kept, far = range_refusals(kept, stats, distances, ranges, range_margin,
                               proof_min_positives)
    kept, refused = planar_refusals(kept, stats, planar_fraction, domain, margin)
    kept, flat = level_refusals(kept, stats, n_horizontal, levels, stepped)
    kept, steps = flight_refusals(kept, stats, flight)
    kept, feet = foot_refusals(kept, stats, foot, foot_above, foot_below, foot_hidden,
                               foot_float)
    kept, under = side_refusals(kept, stats, side, treads, under_eye)
    kept, doubt = unsure_refusals(kept, stats, unsure)
    kept, round_ = facet_refusals(kept, stats, facet)
    kept, pitched = pitch_refusals(kept, stats, pitch, pitch_tol)
    kept, vetoes = veto_refusals(kept, stats, veto_ratio)
    return (choose_class(kept, stats, classes, cofire),
            small + large + thin + far + refused + flat + steps + feet + under + doubt
            + round_ + pitched + vetoes)


def error_kinds(examples: Sequence, predictions: dict, fired: dict, stats: Sequence) -> dict:
    """Why each wrong answer is wrong: the decision among the rules, or the rules themselves.

    Parameters
    ----------
    examples : sequence of (object id, true class)
        Class objects and ``other`` objects (none of the classes).
    predictions : dict
        ``{object id: answer}``.
    fired : dict
        ``{object id: ((class, rule index), ...)}``: the rules that proved something about
        the object (:attr:`planerel.ilp.pipeline.Prediction.fired`).
    stats : sequence
        ``(index, class, tp, fp)`` per rule (the model's); only rules that take part in the
        decision (:func:`takes_part`) are looked at.

    Returns
    -------
    dict
        ``{kind: n}`` over the wrong answers, with kinds ``decision`` (a rule of the true
        class, or an ``other`` rule for an ``other`` object, fired and lost the decision),
        ``unproved`` (no rule of the true class fired: the class rules miss the object) and
        ``unvetoed`` (an ``other`` object proved only by class rules); ``n`` (examples) and
        ``decision_bound``: the share of objects that are ``other`` or proved by a rule of
        their class, the most any decision among the same rules can score (``other`` is
        always an answer it may give); only new or better rules lift it.
    """
    table = {i: (tp, fp) for i, _, tp, fp in stats}
    out = {"decision": 0, "unproved": 0, "unvetoed": 0}
    n = 0
    for obj, truth in examples:
        n += 1
        if predictions[obj] == truth:
            continue
        proved = {k for k, i in fired.get(obj, ()) if takes_part(*table.get(i, (0, 0)))}
        if truth in proved:
            out["decision"] += 1
        else:
            out["unvetoed" if truth == OTHER else "unproved"] += 1
    out["n"] = n
    out["decision_bound"] = (n - out["unproved"]) / n if n else 0.0
    return out


# ----------------------------------------------------------------------------- evaluation


def stratified_folds(labels: Sequence[str], k: int, seed: int = 0) -> list[int]:
    """Fold number (0..k-1) of every example: each class is shuffled with ``seed`` and dealt
    round-robin, continuing where the previous class stopped, so folds differ in size by at
    most one and every class is spread as evenly as it can be."""
    if isinstance(k, bool) or not isinstance(k, int) or k < 2:
        raise InputError(f"the number of folds must be an integer >= 2, got {k!r}")
    if k > len(labels):
        raise InputError(f"{k} folds for {len(labels)} examples: use at most {len(labels)} folds")
    rng = np.random.default_rng(seed)
    fold = [0] * len(labels)
    nxt = 0
    for klass in sorted(set(labels)):
        idx = [i for i, lab in enumerate(labels) if lab == klass]
        for i in rng.permutation(idx):
            fold[int(i)] = nxt % k
            nxt += 1
    return fold


def confusion_columns(classes: Sequence[str]) -> list[str]:
    """The predicted-class columns of a confusion matrix: ``classes``, then ``other`` (once,
    also when ``other`` is a true class of the rows)."""
    return list(classes) + ([] if OTHER in classes else [OTHER])


def confusion_matrix(truth: Sequence[str], pred: Sequence[str], classes: Sequence[str]):
    """Rows: true class (``classes`` order); columns: predicted, ``other`` last
    (:func:`confusion_columns`)."""
    cols = confusion_columns(classes)
    m = [[0] * len(cols) for _ in classes]
    for t, p in zip(truth, pred, strict=True):
        m[list(classes).index(t)][cols.index(p if p in cols else OTHER)] += 1
    return m


def accuracy_scores(truth, pred, classes):
    """Overall accuracy and ``{class: accuracy}`` (None for a class with no example)."""
    n = len(truth)
    acc = sum(t == p for t, p in zip(truth, pred, strict=True)) / n if n else 0.0
    per = {}
    for k in classes:
        idx = [i for i, t in enumerate(truth) if t == k]
        per[k] = sum(pred[i] == k for i in idx) / len(idx) if idx else None
    return acc, per




def score_objects(examples: Sequence, predictions: dict, classes: Sequence[str]) -> dict:
    """Score the answers for objects of known class.

    Parameters
    ----------
    examples : sequence of (object id, true class)
        Class objects and ``other`` objects (none of the classes; others are ignored).
    predictions : dict
        ``{object id: answer}`` for every example.
    classes : sequence of str

    Returns
    -------
    dict
        ``accuracy``, ``per_class``, ``classes``, ``confusion`` and ``n_examples`` over the
        class objects; with ``other`` objects also ``other`` ({n, rejected: share answered
        ``other``, predicted: {answer: n}}), ``open_set_accuracy`` (all objects, ``other``
        right when answered ``other``), ``open_set_per_class`` and ``open_set_confusion``
        (rows and columns ``classes`` then ``other``).
    """
    from planerel.ilp.aleph_export import OTHER as OTHER_CLASS

    examples = [(o, k) for o, k in examples if k in classes or k == OTHER_CLASS]
    kept = [(o, k) for o, k in examples if k in classes]
    truth = [k for _, k in kept]
    pred = [predictions[o] for o, _ in kept]
    acc, per = accuracy_scores(truth, pred, classes)
    out = {"accuracy": acc, "per_class": per, "classes": list(classes),
           "confusion": confusion_matrix(truth, pred, classes), "n_examples": len(kept)}
    others = [o for o, k in examples if k == OTHER_CLASS]
    if others:
        got = [predictions[o] for o in others]
        counts = {k: got.count(k) for k in [*classes, OTHER] if got.count(k)}
        rejected = got.count(OTHER)
        out["other"] = {"n": len(others), "rejected": rejected / len(others), "predicted": counts}
        right = sum(t == p for t, p in zip(truth, pred, strict=True)) + rejected
        out["open_set_accuracy"] = right / (len(kept) + len(others))
        rows = [*classes, OTHER]
        all_truth, all_pred = truth + [OTHER] * len(others), pred + got
        out["open_set_per_class"] = accuracy_scores(all_truth, all_pred, rows)[1]
        out["open_set_confusion"] = confusion_matrix(all_truth, all_pred, rows)
    return out
