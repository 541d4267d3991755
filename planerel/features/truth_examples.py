"""Which ground-truth objects of a synthetic scene are fair learning and test examples.

A scene's object is an example of its class only when what the pipeline sees of it could let
anyone decide the class:

* its planes (the segmented planes that mostly lie on it) match it: intersection over union
  of their pixels and the object's visible pixels >= ``min_iou``;
* a compact object (box, ``other``) is not mostly hidden: the share of its pixels that are
  seen (the rest occluded by nearer objects or outside the image) is >= ``min_visible``, when
  the scene records how many pixels the object would cover alone in an unbounded view
  (varied world).  Staircases and ramps are long: half of them reach out of the image, and
  the part seen still shows their steps or slope, which the next test asks for;
* its planes show what makes the class: a box two of its faces (top, sides or an open
  box's bottom: one face is a plain rectangle, as a door, a shelf's side or a wall), a staircase two steps (treads or
  risers), a ramp its slope; an ``other`` object any plane.

The other objects keep their planes in the scene's facts but are no example: they are left
out of training and of scoring, and counted with the reason (``SceneDescription.excluded``).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from planerel.errors import InputError

__all__ = ["ExampleRule", "REASONS", "judge_objects"]

#: Why an object is no example, in the order the tests run.
REASONS = ("no plane found", "planes do not match (IoU)", "mostly hidden", "one face",
           "fewer than two steps", "slope not seen")

#: Plane roles that show a class: per class the roles, how many distinct planes are needed,
#: the reason when fewer are shown, and whether they must share one role (two steps are two
#: treads or two risers: one tread and one riser are one step, shaped like a box).
_EVIDENCE = {
    "box": (("top", "face", "bottom"), 2, "one face", False),
    "stairs": (("tread", "riser"), 2, "fewer than two steps", True),
    "ramp": (("slope",), 1, "slope not seen", False),
}


@dataclass(frozen=True)
class ExampleRule:
    """Thresholds of :func:`judge_objects`.

    Parameters
    ----------
    min_iou : float
        Least intersection over union of an object's planes with its visible pixels.
    min_visible : float
        Least share of a compact object's pixels (alone, unbounded view) that is seen.
    compact : tuple of str
        The classes ``min_visible`` applies to.
    min_plane_pixels : int
        A ground-truth plane counts as shown when a segmented plane of the object lies
        mostly on it and covers at least this many of its pixels.
    box_faces : int
        2 (the default): a box is an example when it shows two of its faces; 1: also a box
        that shows one side face (a tall box whose top is out of view, a box seen face-on;
        a box showing only its top still is none).  A data set asks for 1 in its
        ``dataset.json`` (``"examples": {"box_faces": 1}``; the demo's training world,
        :func:`planerel.synth.training_world.generate_training_world`, face24).
    box_top_height : float
        m; 0 (the default): a box showing only its top is none.  Above 0: a box at most this
        high (its sidecar's ``params`` ``height``) that shows its top is an example even when
        no side of it is seen: a book or a flat box lying on a table, its 2-8 cm sides seen
        edge-on (``"examples": {"box_top_height": 0.12}``; the demo's training world, top25).
    side_faces : int
        0 (the default): a ramp is an example when its slope shows, a flight when two of its
        steps do.  1: also a ramp or a flight that shows one of its side faces and not those
        (seen from its side by a camera lower than its top; ``"examples": {"side_faces": 1}``,
        the demo's training world with its side-view part, ramp77).
    """

    min_iou: float = 0.5
    min_visible: float = 0.3
    min_plane_pixels: int = 10
    compact: tuple = ("box", "other")
    box_faces: int = 2
    box_top_height: float = 0.0
    side_faces: int = 0

    def __post_init__(self) -> None:
        for name in ("min_iou", "min_visible"):
            v = getattr(self, name)
            if isinstance(v, bool) or not isinstance(v, (int, float)) or not 0 <= v <= 1:
                raise InputError(f"{name.replace('_', ' ')} must be a number in [0, 1], got {v!r}")
        v = self.min_plane_pixels
        if isinstance(v, bool) or not isinstance(v, (int, np.integer)) or v < 1:
            raise InputError(f"min plane pixels must be a positive integer, got {v!r}")
        v = self.box_faces
        if isinstance(v, bool) or not isinstance(v, (int, np.integer)) or v not in (1, 2):
            raise InputError(f"box faces must be 1 or 2, got {v!r}")
        v = self.box_top_height
        if isinstance(v, bool) or not isinstance(v, (int, float)) or not 0 <= v < 10:
            raise InputError(f"box top height must be a number of metres in [0, 10), got {v!r}")
        v = self.side_faces
        if isinstance(v, bool) or not isinstance(v, (int, np.integer)) or v not in (0, 1):
            raise InputError(f"side faces must be 0 or 1, got {v!r}")


def judge_objects(labels, gt, meta: dict, groups, object_of_group, classes: dict,
                  rule: ExampleRule | None = None) -> dict:
    """The reason each ground-truth object is no example, or None when it is one.

    Parameters
    ----------
    labels, gt : ndarray, shape (H, W), int
        Described plane labels and ground-truth plane labels (-1 none).
    meta : dict
        The scene's sidecar (``planes`` with ``index``, ``role``, ``object_index``; ``objects``
        with ``index``, ``n_pixels`` and, in the varied world, ``n_pixels_full``).
    groups : sequence of tuple of int
        Plane labels per object (:func:`planerel.features.proposals.objects_from_truth`).
    object_of_group : sequence of int
        The ground-truth object index of each group.
    classes : dict
        ``{object index: class}`` of the objects to judge.
    rule : ExampleRule, optional

    Returns
    -------
    dict
        ``{object index: None or reason}`` (a reason of :data:`REASONS`) for every object of
        ``classes`` that has seen pixels.
    """
    rule = ExampleRule() if rule is None else rule
    lab = np.asarray(labels)
    gtl = np.asarray(gt)
    planes = meta.get("planes", [])
    n = max((int(p["index"]) for p in planes), default=-1) + 1
    obj_of_plane = np.full(n + 1, -1, np.int64)
    role_of_plane = [""] * (n + 1)
    for p in planes:
        k = int(p["index"])
        obj_of_plane[k] = int(p.get("object_index", 0))
        role_of_plane[k] = str(p.get("role", ""))
    gsafe = np.where((gtl >= 0) & (gtl < n), gtl, n)
    objpix = obj_of_plane[gsafe]
    info = {int(o["index"]): o for o in meta.get("objects") or [] if "index" in o}
    seen_px = np.bincount(objpix[objpix >= 0], minlength=max(classes, default=0) + 1)
    group_of = {int(k): tuple(g) for g, k in zip(groups, object_of_group, strict=True)}
    out = {}
    for k, klass in classes.items():
        if k >= len(seen_px) or seen_px[k] == 0:
            continue
        g = group_of.get(k)
        if not g:
            out[k] = "no plane found"
            continue
        mine = np.isin(lab, g)
        truth = objpix == k
        iou = (mine & truth).sum() / max(1, (mine | truth).sum())
        if iou < rule.min_iou:
            out[k] = "planes do not match (IoU)"
            continue
        full = info.get(k, {}).get("n_pixels_full")
        if full and klass in rule.compact and seen_px[k] < rule.min_visible * float(full):
            out[k] = "mostly hidden"
            continue
        evidence = _EVIDENCE.get(klass)
        if evidence is not None:
            roles, need, reason, same_role = evidence
            shown, shown_any = set(), set()
            for x in g:
                on = gsafe[(lab == x) & truth]
                if on.size:
                    best = np.bincount(on, minlength=n + 1)
                    q = int(best.argmax())
                    if best[q] >= rule.min_plane_pixels:
                        shown_any.add(q)
                        if role_of_plane[q] in roles:
                            shown.add(q)
            per_role = [sum(role_of_plane[q] == r for q in shown) for r in roles]
            one_side = (klass == "box" and rule.box_faces == 1 and "face" in roles
                        and per_role[roles.index("face")] >= 1)
            flat = (klass == "box" and rule.box_top_height > 0 and "top" in roles
                    and per_role[roles.index("top")] >= 1
                    and 0 < float((info.get(k, {}).get("params") or {}).get("height", 0.0))
                    <= rule.box_top_height)
            side = (klass in ("ramp", "stairs") and rule.side_faces == 1
                    and any(role_of_plane[q] == "side" for q in shown_any))
            if ((max(per_role) if same_role else sum(per_role)) < need
                    and not (one_side or flat or side)):
                out[k] = reason
                continue
        out[k] = None
    return out
