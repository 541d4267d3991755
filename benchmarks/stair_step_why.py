"""Why ``stair_step/2`` holds for no pair of a flight's faces: the step test, sub-test by
sub-test (step60, docs/objects.md "Why the step test fails a real flight").  A measuring tool.

Usage::

    stair_step_why.py DIR [DIR ...] [--model out/model] [--param NAME=VALUE ...] [--json F]
        [--aggregate]

It runs :func:`stairs_census.census` and, for each flight at the stage ``no stair_step``
(treads or risers lie in it, but no pair of them is a step), puts every pair of its treads
(and of its risers) through the sub-tests of the step test in the order the code asks them
(:func:`planerel.features.step_chains.step_chain_pairs` with the parameters
:func:`planerel.features.stair_step.stair_steps` passes, then the plan-view overlap):

``cut by border``
    a tread the image border cuts along its length is no candidate;
``area ratio``
    the larger face at most ``max_ratio`` (3) times the smaller;
``rise``
    the higher face's centroid :data:`~planerel.features.step_chains.STAIR_RISE` above the lower's;
``normals``
    normals within ``concave_tol`` degrees;
``run``
    the horizontal offset (across the treads' long axis, along a riser's normal)
    :data:`~planerel.features.step_chains.STAIR_RUN`;
``too deep``
    each face at most one run deep (tread) or one rise high (riser): no landing, no floor;
``overlap across``
    their extents across the step direction overlap by ``step_overlap`` (interval IoU);
``plan overlap``
    their footprints seen from above overlap by less than
    :data:`~planerel.features.plan_overlap.OVER_SHARE` of the larger (no shelf's boards).

Every sub-test is measured for every pair (no short cut), so a flight's *closest* pair is the
one that passes most (ties: the one whose first failure comes latest).  Output: the census's
lines, then ``why-all {sub-test: flights}`` (the first sub-test the closest pair fails, a
flight counted once) and ``why-any {sub-test: flights}`` (every sub-test the closest pair
fails), with the measured values per flight unless ``--aggregate``.
"""

from __future__ import annotations

import json
import math
import sys
from collections import Counter
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))

TESTS = ("cut by border", "area ratio", "rise", "normals", "run", "too deep",
         "overlap across", "plan overlap")


def pair_tests(planes, lo, hi, params, cut=frozenset()) -> list:
    """The step test's sub-tests on two faces of one kind.

    Parameters
    ----------
    planes : PlaneSet
    lo, hi : Plane
        Two treads or two risers (any order: the lower is taken as ``lo``).
    params : ProposalParams
    cut : set of int
        Labels of treads the image border cuts along their length.

    Returns
    -------
    list of (str, bool, float)
        ``(sub-test, passes, measured value)`` in :data:`TESTS` order.
    """
    from planerel.features.plan_overlap import OVER_SHARE, plan_overlap
    from planerel.features.relations import (
        STAIR_RISE,
        STAIR_RUN,
        _across_overlap,
        _step_kind,
        step_offset,
    )
    from planerel.features.step_geometry import _tread_depth_axis

    if lo.height > hi.height:
        lo, hi = hi, lo
    up = np.asarray(planes.up, float)
    kind = _step_kind(lo, params.step_tilt)
    out = []
    out.append(("cut by border", not (kind == "tread" and ({lo.label, hi.label} & set(cut))),
                float(len({lo.label, hi.label} & set(cut)))))
    ratio = max(lo.area, hi.area) / max(min(lo.area, hi.area), 1e-12)
    out.append(("area ratio", ratio <= 3.0, ratio))
    dv = float(hi.height - lo.height)
    out.append(("rise", STAIR_RISE[0] <= dv <= STAIR_RISE[1], dv))
    cosang = abs(float(np.asarray(lo.normal, float) @ np.asarray(hi.normal, float)))
    ang = math.degrees(math.acos(min(1.0, cosang)))
    out.append(("normals", cosang >= math.cos(math.radians(params.concave_tol)), ang))
    dist, direction = step_offset(lo, hi, kind, up, (lambda q: _tread_depth_axis(q, up))
                                  if params.step_tread_axes else None)
    out.append(("run", STAIR_RUN[0] <= dist <= STAIR_RUN[1], dist))
    axis = direction if kind == "tread" else up
    limit = STAIR_RUN[1] if kind == "tread" else STAIR_RISE[1]
    deep = max(float(np.ptp(np.asarray(q.hull3d, float) @ axis)) for q in (lo, hi))
    out.append(("too deep", deep <= limit, deep))
    ov = float(_across_overlap(lo, hi, up, direction))
    out.append(("overlap across", ov >= (params.step_overlap or 0.5), ov))
    po = float(plan_overlap(lo.hull3d, hi.hull3d, planes.up))
    out.append(("plan overlap", po < OVER_SHARE, po))
    return out


def closest_pair(planes, labels, params) -> dict | None:
    """The pair of ``labels``' treads (or risers) that passes most sub-tests.

    Returns
    -------
    dict or None
        ``{"pair": (lo, hi), "kind", "first": first failing sub-test or "passes all",
        "fails": [sub-tests failed], "values": {sub-test: value}}``; None with no pair.
    """
    from planerel.features.relations import _step_kind
    from planerel.features.step_geometry import _cut_lengthwise

    by_label = {p.label: p for p in planes}
    faces = [by_label[k] for k in labels if k in by_label]
    kinds = {q.label: _step_kind(q, params.step_tilt) for q in faces}
    cut = _cut_lengthwise([q for q in faces if kinds[q.label] == "tread"],
                          params.cut_long_side, getattr(planes, "labels", None))
    best, best_key = None, None
    for i, a in enumerate(faces):
        for b in faces[i + 1:]:
            if kinds[a.label] is None or kinds[a.label] != kinds[b.label]:
                continue
            tests = pair_tests(planes, a, b, params, cut)
            oks = [ok for _n, ok, _v in tests]
            first = next((j for j, ok in enumerate(oks) if not ok), len(oks))
            key = (sum(oks), first, -a.label, -b.label)
            if best_key is None or key > best_key:
                best_key = key
                fails = [n for n, ok, _v in tests if not ok]
                best = {"pair": (int(a.label), int(b.label)), "kind": kinds[a.label],
                        "first": fails[0] if fails else "passes all", "fails": fails,
                        "values": {n: round(v, 3) for n, _ok, v in tests}}
    return best


def aggregate(rows) -> tuple[Counter, Counter]:
    """``(first, any)``: flights at ``no stair_step`` counted by their closest pair's first
    failing sub-test, and by every sub-test it fails."""
    first, anyf = Counter(), Counter()
    for r in rows:
        w = r.get("why")
        if r.get("stage") != "no stair_step" or w is None:
            continue
        first[w["first"]] += 1
        anyf.update(w["fails"] or ["passes all"])
    return first, anyf


def main(argv=None) -> int:
    from stairs_census import census_cli

    a, rows = census_cli("stair_step_why", __doc__.split("\n")[0], argv, why=True)
    if a is None:
        return rows
    print("all", len(rows), dict(Counter(r["stage"] for r in rows).most_common()))
    first, anyf = aggregate(rows)
    print("why-all", dict(first.most_common()))
    print("why-any", dict(anyf.most_common()))
    if not a.aggregate:
        for r in rows:
            if r.get("why") is not None:
                print(json.dumps({k: r[k] for k in ("set", "frame", "why") if k in r}))
    if a.json:
        Path(a.json).write_text(json.dumps(rows, indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main())
