"""What a robot needs to know of a flight or a slope it was told about: rise, run, how many
rises are in view, which way it goes and how far it is (``measures`` of a ``stairs`` or
``ramp`` answer; docs/results.md "A flight's and a slope's measures").

The measures are read off the planes that made the class: a flight's ``stair_step/2`` pairs
(the scene's :attr:`~planerel.features.facts.SceneDescription.steps` among the object's
planes), a slope's inclined proof plane.  Every length is in metres, every angle in degrees;
directions are unit vectors in the sensor's frame (x right, y down, z forward for a depth
image).
"""

from __future__ import annotations

import math

import numpy as np

from planerel.features.step_chains import STAIR_RISE, STAIR_RUN, _step_kind, step_offset
from planerel.features.step_geometry import _tread_depth_axis

__all__ = ["flight_measures", "slope_measures"]


def _horizontal(v, up) -> np.ndarray:
    """``v`` (3,) with its component along the unit ``up`` removed."""
    v = np.asarray(v, float)
    return v - float(v @ up) * up


def _nearest(planes, labels) -> float | None:
    """Distance (m, to the millimetre) from the sensor to the nearest finite hull vertex of the
    planes ``labels``; None when they have none (JSON has no NaN)."""
    pts = [np.asarray(p.hull3d, float).reshape(-1, 3) for p in planes if p.label in labels]
    pts = np.concatenate([q for q in pts if q.size] or [np.empty((0, 3))])
    d = np.linalg.norm(pts[np.isfinite(pts).all(axis=1)], axis=1)
    return round(float(d.min()), 3) if d.size else None


#: ``going`` is ``"across"`` when the way a flight or slope rises lies more than this many
#: degrees off the level line of sight to it (a flight or a roll ramp seen from its side)
ACROSS_DEG = 60.0


def _going(direction, centre, up) -> str:
    """``"up"`` when ``direction`` (the way the flight or slope rises, level, unit) points
    away from the sensor along the level line of sight to ``centre``, ``"down"`` when it points
    towards it, ``"across"`` when it lies more than :data:`ACROSS_DEG` off that line."""
    sight = _horizontal(centre, up)
    n = float(np.linalg.norm(sight))
    if n < 1e-9:
        return "across"   # straight under or over the sensor: no way along the floor
    c = float(direction @ sight) / n
    limit = math.cos(math.radians(ACROSS_DEG))
    return "up" if c > limit else ("down" if c < -limit else "across")


def flight_measures(planes, labels, steps, tread_axes: bool = True,
                    tilt=12.0) -> dict | None:
    """A flight's measures from its step pairs.

    Parameters
    ----------
    planes : PlaneSet
        The scene's measured planes (``up`` set).
    labels : iterable of int
        The object's planes.
    steps : iterable of (int, int)
        ``(lower, higher)`` step pairs (the scene's ``stair_step/2`` pairs); those with both
        planes among ``labels`` count.
    tread_axes : bool
        Measure a tread step's run across the treads (``ProposalParams.step_tread_axes``).
    tilt : float or (float, float)
        Degrees off level (off vertical) within which a face is a tread (a riser):
        ``ProposalParams.step_tilts``.

    Returns
    -------
    dict or None
        ``rise_m`` and ``run_m`` (medians over the steps, a pair more than one stair rise
        apart counted as the rises it spans: :func:`_spans`; the run over those within
        :data:`~planerel.features.step_chains.STAIR_RUN`, None when none is: an open-riser
        row's treads, seen as strips, do not show it), ``steps`` (the pairs measured),
        ``rises_seen`` (rises between the lowest and the highest tread in a step, or riser
        when that spans more), ``climb_m`` (their height apart), ``width_m`` (the median
        extent of the step faces across the flight), ``going`` (``"up"``: the flight rises
        away from the sensor, ``"down"``: it falls away, ``"across"``: it runs across the
        line of sight, :data:`ACROSS_DEG`), ``direction`` (unit (3,) in the sensor's frame,
        the way it rises, level), ``distance_m`` (to the nearest step face; None when no hull
        point is finite); None with no step pair among ``labels``.
    """
    mine = set(int(x) for x in labels)
    pairs = [(int(a), int(b)) for a, b in steps if int(a) in mine and int(b) in mine]
    if not pairs:
        return None
    up = np.asarray(planes.up, float)
    by_label = {p.label: p for p in planes}

    def axis(q):
        return _tread_depth_axis(q, up)

    rises, runs, dirs = [], [], []
    of_kind: dict = {}   # kind -> its faces' labels (a tread's and a riser's levels differ)
    for a, b in pairs:
        lo, hi = by_label[a], by_label[b]
        if lo.height > hi.height:
            lo, hi = hi, lo
        kind = _step_kind(lo, tilt) or "tread"
        of_kind.setdefault(kind, set()).update((a, b))
        dist, direction = step_offset(lo, hi, kind, up, axis if tread_axes else None)
        rises.append(float(hi.height - lo.height))
        runs.append(float(dist))
        dirs.append(np.asarray(direction, float))
    # a pair two rises apart (an open-riser row's slabs with the one between not seen) is
    # that many steps: its rise and run each spread over them
    spans = _spans(rises)
    rises = [r / k for r, k in zip(rises, spans, strict=True)]
    runs = [r / k for r, k in zip(runs, spans, strict=True)]
    # one way for the flight: the steps' directions summed after turning each to the first's
    ref = dirs[0]
    total = sum((d if float(d @ ref) >= 0 else -d) for d in dirs)
    direction = _horizontal(total, up)
    n = float(np.linalg.norm(direction))
    direction = direction / n if n > 0 else ref
    faces = sorted({x for pr in pairs for x in pr})
    rise = float(np.median(rises))
    climb = max(float(np.ptp([by_label[x].height for x in labs])) for labs in of_kind.values())
    across = np.cross(up, direction)
    widths = [float(np.ptp(np.asarray(by_label[x].hull3d, float) @ across)) for x in faces]
    centre = np.mean([np.asarray(by_label[x].centroid, float) for x in faces], axis=0)
    runs = [r for r in runs if STAIR_RUN[0] <= r <= STAIR_RUN[1]]
    return {"rise_m": round(rise, 3),
            "run_m": round(float(np.median(runs)), 3) if runs else None,
            "steps": len(pairs), "rises_seen": int(round(climb / rise)) if rise > 0 else 0,
            "climb_m": round(climb, 3), "width_m": round(float(np.median(widths)), 3),
            "going": _going(direction, centre, up),
            "direction": [round(float(v), 4) for v in direction],
            "distance_m": _nearest(planes, faces)}


def _spans(rises) -> list[int]:
    """How many rises each of ``rises`` (m, one a step pair) spans: 1 within one stair rise
    (:data:`~planerel.features.step_chains.STAIR_RISE`'s upper bound), else the whole number
    nearest its ratio to the median of those within it (at least 2; with none, as many as
    that bound needs).  An open-riser row's pair may span two rises when the slab between is
    not seen (walrus-stairs: rises 0.153 and 0.308 m, the median was 0.231)."""
    top = STAIR_RISE[1]
    single = [r for r in rises if r <= top]
    ref = float(np.median(single)) if single else None
    out = []
    for r in rises:
        if r <= top:
            out.append(1)
        elif ref:
            out.append(max(2, int(round(r / ref))))
        else:
            out.append(max(2, math.ceil(r / top)))
    return out


def slope_measures(planes, label) -> dict | None:
    """A slope's measures from its inclined plane ``label``.

    Returns
    -------
    dict or None
        ``slope_deg`` (the plane's incline), ``length_m`` and ``width_m`` (its seen hull's
        rectangle), ``going`` (``"up"``: it rises away from the sensor, ``"down"``: it falls
        away, ``"across"``: it rises across the line of sight), ``direction`` (unit (3,),
        level, the way it rises), ``distance_m`` (to its nearest hull point, or None); None
        when the plane is not found or is level.
    """
    p = next((q for q in planes if q.label == label), None)
    if p is None:
        return None
    up = np.asarray(planes.up, float)
    n = np.asarray(p.normal, float)
    n = n if float(n @ up) >= 0 else -n     # the face's upward normal
    downhill = _horizontal(n, up)           # a slope's upward normal leans downhill
    size = float(np.linalg.norm(downhill))
    if size < 1e-9:
        return None
    direction = -downhill / size
    return {"slope_deg": round(math.degrees(math.acos(min(1.0, float(n @ up)))), 1),
            "length_m": round(float(p.length), 3), "width_m": round(float(p.width), 3),
            "going": _going(direction, np.asarray(p.centroid, float), up),
            "direction": [round(float(v), 4) for v in direction],
            "distance_m": _nearest(planes, {p.label})}
