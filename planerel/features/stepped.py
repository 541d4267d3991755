"""Split a segmented "plane" that is really the treads of a staircase seen from above.

Looking down a flight, the risers face away and each tread shows only a strip; on a depth
sensor's noise region growing can join the strips into one plane, which then measures as an
inclined plane at the flight's slope: a ramp (a whole 8-step flight on a Kinect-like frame at
2.3 m, two or four treads of flights 3-4 m away).  The points of such a plane are not spread
over its height as a slope's are: they sit on a few horizontal levels, one rise apart, with
almost nothing between them.  :func:`stepped_levels` finds those levels from a histogram of the
points' heights; :func:`split_stepped` gives each level a label of its own.
"""

from __future__ import annotations

import numpy as np

from planerel.features.planes import label_max

__all__ = ["stepped_levels", "split_stepped", "remeasure_stepped"]


#: :func:`stepped_levels`' defaults of ``bin_size``, ``dense``, ``max_thickness`` and
#: ``min_share``, and of ``min_level`` (:func:`split_stepped` takes them too)
_LEVEL_DEFAULTS = (0.01, 0.2, 0.08, 0.85)
_LEVEL_MIN = 0.01

#: Metres: :func:`split_stepped` looks only at inclined planes whose RMS residual
#: (``Plane.rms``) is at least this.  Treads one rise apart grown into one "plane" deviate from
#: it by a sawtooth a rise high (RMS about ``rise / sqrt(12)``, less where only the tread
#: strips near the nosings are seen): the planes split on the judge sets and the real
#: staircases had 13-21 mm, those of ``benchmarks/bench_stairs_from_above.py``'s Kinect-like
#: flights seen from above 7.0-11 mm.  A real slope's points lie on it within the sensor's
#: noise: the real Kinect and mOSD frames' inclined planes had 0.8-4.5 mm, among them each
#: Kinect frame's 36 000-point plane at 61 degrees, 1.6-1.9 mm, whose heights the level test
#: read in full and found no levels; 3.5 mm lies a factor of about 2 from both.  Not an exact
#: bound: a slope seen in bands (parts hidden at regular heights) lies on levels with a small
#: RMS, and is no longer split into "treads" (docs/benchmarks.md, "Twenty-fourth pass").
#: 0: every inclined plane is looked at.
SPLIT_MIN_RMS = 0.0035


def stepped_levels(heights: np.ndarray, rise=(0.08, 0.30), bin_size: float = _LEVEL_DEFAULTS[0],
                   dense: float = _LEVEL_DEFAULTS[1], max_thickness: float = _LEVEL_DEFAULTS[2],
                   min_share: float = _LEVEL_DEFAULTS[3], margin: float = 0.02,
                   min_level: float = _LEVEL_MIN) -> list[tuple[float, float]]:
    """Horizontal levels a set of point heights falls into, when it looks like treads.

    Parameters
    ----------
    heights : ndarray, shape (N,)
        Heights (``up . x``) of one plane's points, metres.
    rise : (float, float)
        Consecutive levels' middles must lie this far apart (metres).
    bin_size : float
        Histogram bin, metres.
    dense : float
        A bin is populated when it holds at least this share of the fullest bin within half
        the largest rise of it (and 3 points): near levels hold more points than far ones.
    max_thickness : float
        A level (a run of populated bins; runs less than half ``rise[0]`` apart are one) is at
        most this thick (metres): a tread's noise, not a slope.
    min_share : float
        The levels, each widened by ``margin`` metres up and down, hold at least this share
        of the points.
    margin : float
    min_level : float
        A level holds at least this share of the points (and 5 points).

    Returns
    -------
    list of (float, float)
        ``(low, high)`` height interval of each level, lowest first; empty when the heights are
        not two or more such levels (a slope's heights fill their range).
    """
    from planerel.features._relation_kernels import finite_range

    h = np.ascontiguousarray(heights, dtype=np.float64).reshape(-1)
    # the finite heights' count and range first (one compiled pass): most planes stop here
    return _levels(h, *finite_range(h), rise, bin_size, dense, max_thickness, min_share,
                   margin, min_level)


def _levels(h, n, lo, hi, rise, bin_size, dense, max_thickness, min_share, margin,
            min_level) -> list[tuple[float, float]]:
    """:func:`stepped_levels` of the heights ``h`` (1-D float64) whose finite count, min and
    max are ``n``, ``lo``, ``hi`` (:func:`planerel.features._relation_kernels.finite_range`)."""
    from planerel.features._relation_kernels import level_bins

    if n < 20 or hi - lo < rise[0]:
        return []
    if n < h.size:
        h = h[np.isfinite(h)]
    lo = float(lo)
    nb = int((hi - lo) / bin_size) + 1
    w = int(0.5 * rise[1] / bin_size) + 1
    counts, pop = level_bins(h, lo, float(bin_size), nb, w, float(dense))
    runs = []
    k = 0
    while k < nb:
        if not pop[k]:
            k += 1
            continue
        j = k
        while j + 1 < nb and pop[j + 1]:
            j += 1
        runs.append((k, j))
        k = j + 1
    # a run of a few stray points is no level (far treads hold a few % of the points); runs
    # less than half the smallest rise apart are one level broken by a sparse bin
    merged = []
    for a, b in runs:
        if counts[a:b + 1].sum() < max(5, min_level * h.size):
            continue
        if merged and a - merged[-1][1] - 1 < 0.5 * rise[0] / bin_size:
            merged[-1] = (merged[-1][0], b)
        else:
            merged.append((a, b))
    runs = merged
    if len(runs) < 2:
        return []
    levels = [(lo + a * bin_size, lo + (b + 1) * bin_size) for a, b in runs]
    if any(b - a > max_thickness for a, b in levels):
        return []
    near = np.zeros(h.size, bool)
    for a, b in levels:
        near |= (h >= a - margin) & (h <= b + margin)
    if near.mean() < min_share:
        return []
    mids = [0.5 * (a + b) for a, b in levels]
    steps = np.diff(mids)
    if not all(rise[0] <= s <= rise[1] for s in steps):
        return []
    return levels


def _box_points(lab, xyz, label: int, box) -> np.ndarray:
    """``xyz[box][lab[box] == label]`` (``(N, 3)`` float64, row-major) gathered by a compiled
    pass into an array numpy allocates (the same values in the same kind of array, so the
    heights' matrix product is numpy's own as before)."""
    from planerel.features._relation_kernels import box_label_count, box_label_fill

    H, W = lab.shape
    r0, r1, _ = box[0].indices(H)
    c0, c1, _ = box[1].indices(W)
    lab = np.ascontiguousarray(lab)
    xyz = np.asarray(xyz)
    if xyz.dtype != np.float64 or r1 <= r0 or c1 <= c0:
        return np.asarray(xyz[box][lab[box] == label], dtype=np.float64)
    out = np.empty((box_label_count(lab, int(label), r0, c0, r1, c1), 3))
    box_label_fill(lab, xyz, int(label), r0, c0, r1, c1, out)
    return out


def _box_heights_range(lab, xyz, label: int, box, up):
    """``(h, n, lo, hi)``: :func:`_box_heights` and its finite count, min and max
    (:func:`planerel.features._relation_kernels.finite_range`) in the heights' own pass."""
    from planerel.features._relation_kernels import box_label_heights_range, finite_range

    H, W = lab.shape
    r0, r1, _ = box[0].indices(H)
    c0, c1, _ = box[1].indices(W)
    xyz = np.asarray(xyz)
    if xyz.dtype != np.float64 or r1 <= r0 or c1 <= c0:
        h = np.ascontiguousarray(_box_heights(lab, xyz, label, box, up), dtype=np.float64)
        return (h, *finite_range(h))
    return box_label_heights_range(np.ascontiguousarray(lab), xyz, int(label), r0, c0, r1, c1,
                                   np.asarray(up, np.float64))


def _box_heights(lab, xyz, label: int, box, up) -> np.ndarray:
    """``_box_points(lab, xyz, label, box) @ up`` in one compiled pass without the points
    (:func:`planerel.features._relation_kernels.box_label_heights`: plain-order dot products,
    within rounding of numpy's)."""
    from planerel.features._relation_kernels import box_label_heights

    H, W = lab.shape
    r0, r1, _ = box[0].indices(H)
    c0, c1, _ = box[1].indices(W)
    xyz = np.asarray(xyz)
    if xyz.dtype != np.float64 or r1 <= r0 or c1 <= c0:
        return _box_points(lab, xyz, label, box) @ up
    return box_label_heights(np.ascontiguousarray(lab), xyz, int(label), r0, c0, r1, c1,
                             np.asarray(up, np.float64))


def split_stepped(xyz: np.ndarray, labels: np.ndarray, planes, rise=(0.08, 0.30),
                  margin: float = 0.02, min_rms: float = SPLIT_MIN_RMS):
    """Relabel every inclined plane whose points lie on tread-like levels, one label a level.

    Parameters
    ----------
    xyz : ndarray, shape (H, W, 3)
        Organized points (NaN invalid).
    labels : ndarray, shape (H, W), int
        Plane labels, -1 unassigned.
    planes : PlaneSet
        The measured planes of ``labels`` (their orientation and the up vector).
    rise : (float, float)
        Metres between consecutive levels (:func:`stepped_levels`).
    margin : float
        Points up to this far outside a level's interval (metres) join it; points between
        levels become unassigned.
    min_rms : float
        Metres: planes whose ``rms`` is less are not looked at (:data:`SPLIT_MIN_RMS`; 0: all).

    Returns
    -------
    (ndarray, dict) or None
        The new ``(H, W)`` int32 label image (the lowest level keeps the plane's label, the
        others get new labels after the largest one) and ``{new label: split label}``; None
        when no plane was split.
    """
    up = np.asarray(planes.up, float)
    lab = np.asarray(labels)
    out = None
    parent = {}
    nxt = None  # the next new label, found at the first split
    for p in planes:
        if p.orientation != "inclined" or p.is_floor or p.rms < min_rms:
            continue  # (a plane as flat as a slope: no sawtooth of treads, SPLIT_MIN_RMS)
        # the planes' own label image: the plane's pixel box holds all its pixels (the same
        # points, in the same order)
        box = ((slice(p.bbox[0], p.bbox[2]), slice(p.bbox[1], p.bbox[3]))
               if labels is planes.labels else (slice(None), slice(None)))
        # the heights and their range in one pass (stepped_levels' first test)
        h, n, lo, hi = _box_heights_range(lab, xyz, p.label, box, up)
        levels = _levels(h, n, lo, hi, rise, *_LEVEL_DEFAULTS, margin, _LEVEL_MIN)
        if not levels:
            continue
        m = lab[box] == p.label
        if out is None:
            out = lab.astype(np.int32, copy=True)
            nxt = label_max(lab) + 1
        new = np.full(h.shape, -1, np.int32)
        for k, (a, b) in enumerate(levels):
            new[(h >= a - margin) & (h <= b + margin)] = p.label if k == 0 else nxt
            if k > 0:
                parent[nxt] = p.label
                nxt += 1
        out[box][m] = new
    return None if out is None else (out, parent)


def remeasure_stepped(cloud, planes, rise=(0.08, 0.30), plane_params=None):
    """:func:`split_stepped` on measured planes, and the planes measured again when a plane was
    split (with the same up vector, its source and confidence kept).

    Returns
    -------
    (PlaneSet, dict)
        The planes (the given ones when nothing was split) and ``{new label: split label}``.
    """
    from planerel.features.planes import measure_planes  # (looked up at each call: see facts)

    got = split_stepped(cloud.xyz, planes.labels, planes, rise)
    if got is None:
        return planes, {}
    lab, parent = got
    again = measure_planes(cloud, lab, planes.up, plane_params)
    return again.with_up_of(planes), parent
