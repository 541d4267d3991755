"""Gravity: the up vector of a scene in the camera frame, for any camera pitch and roll.

Where the up vector comes from (:func:`resolve_up`), in this order:

``given``      the caller's ``up`` argument (the CLI's ``--up``)
``file``       the cloud's own ``up`` (a sidecar ``STEM.json`` next to a depth image, PCD, PLY
               or NPY file, or a synthetic scene)
``estimated``  :func:`estimate_gravity` from the scene's planes
``default``    nothing to estimate from: a level camera's up, ``(0, -1, 0)``, confidence 0

Estimate.  Man-made scenes are made of planes that are either horizontal (floors, treads,
table and box tops) or vertical (walls, risers, box faces).  Every large plane votes:

- *candidates*: the normal of each large plane (it might be horizontal), the cross product
  of each pair of large planes at least ``min_pair_deg`` from parallel (both might be
  vertical), and for each plane the direction in it closest to the image's up axis (it might
  be the only vertical plane, seen with no roll);
- *score* of a candidate ``u``: the area of the planes that are horizontal with respect to
  ``u`` (normal within ``tol_deg`` of ``u``) plus ``vertical_weight`` times the area of the
  vertical ones (normal within ``tol_deg`` of perpendicular), with a smooth kernel
  ``1 - (angle / tol_deg)^2``, times a roll prior: a candidate that would mean a camera rolled
  by more than ``max_roll_deg`` is penalised (only as far as the roll is defined: looking
  straight down it is not);
- the best candidate is *refined* by least squares over its consistent planes (horizontal
  normals parallel to up, vertical normals perpendicular to it), twice with a shrinking
  tolerance.

Nothing restricts the pitch: a camera looking straight ahead and one looking steeply down a
staircase are handled alike (no cone around the camera's down axis).

Sign.  Up points to the side of the image's top (``up . (0, -1, 0) > 0``: the camera is not
upside down) when that is well defined; when the camera looks (nearly) straight down it points
to the sensor's side of the largest horizontal planes (the camera is above the floor).

Drafted walls (``GravityParams.mirror_pairs``).  A tote's or bin's walls lean out by a draft
angle, so seen from above none of them is vertical within ``tol_deg``.  Two walls facing each
other, leaning alike from a level floor below them, vote for their mirror axis (the bisector of
their normals) as a horizontal plane of their area does: a symmetric pair fixes one direction,
as a horizontal plane does (docs/gravity.md, "A bin seen from above").

Near the floor (``GravityParams.mirror_pairs_near``, ``steep_support``).  A camera a few
centimetres over a floor sees the floor as a small plane and the sensor's far planes, bent, as
many m^2.  A mirror pair's walls vote with their near weight (a tote is seen from within
reach), and a reading in which the camera looks down by more than ``steep_pitch_deg`` counts
its vertical votes only up to ``steep_support`` times its horizontal ones (a camera looking
steeply down sees what is under it; docs/gravity.md, "A camera near the floor: which reading
wins").  When the vote is still not clear (a flagged estimate), the floor the camera stands
over decides: the largest plane seen from above within ``near_floor`` metres of the camera and
``near_floor_deg`` of the estimate sets the up (docs/gravity.md, "The floor under a low
camera").

Upside down (``GravityParams.flip``).  A camera mounted upside down sees the floor and the tops
of things on the image's top side, where an upright camera sees ceilings.  The same estimate is
made for the frame turned by 180 degrees about the optical axis, from the near planes only
(within about ``max_height`` of the camera: a stereo sensor's far planes are its least
reliable), and turned back; it replaces the upright estimate when it points to the image's
bottom and the camera is above at least ``flip_ratio`` times as much horizontal area under it
as under the upright one, and at least ``flip_min_area`` (docs/gravity.md, "A camera held
upside down").

Confidence in [0, 1]: ``sqrt(explained) * separation * checked`` where ``explained`` is the
fraction of the voting area consistent with the estimate; ``separation = min(1, 2 (1 - rival /
best))`` with ``rival`` the best score of a candidate more than ``2 tol_deg`` (10 degrees) away
(another reading of the same scene: a wall taken for the floor, a ramp for the ground); ``checked`` is 1 when the consistent planes
point in two directions at least ``min_pair_deg`` apart (up is cross-checked: a floor and a
wall, two walls), 0.6 when they are parallel horizontal planes (a floor and stair treads),
0.4 for a single horizontal plane, 0.2 when they are all parallel and vertical (up within the
plane is then only the roll prior's guess).  Estimates below ``GravityParams.low_confidence`` (0.5) are flagged
(:attr:`UpEstimate.low_confidence`): a single plane always is.

Inputs.  With a label image the planes are least-squares fits of the labelled regions (area
from their spread: ``12 sqrt(l1 l2)`` for the two in-plane eigenvalues, exact for a
rectangle); without one, per-pixel normals on a coarse grid are grouped into dominant
directions (greedy mode seeking on the sphere, 5-degree radius) which then vote the same way.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import numpy as np

from planerel.errors import InputError
from planerel.io.cloud import unit_up

__all__ = [
    "GravityParams",
    "UpEstimate",
    "estimate_gravity",
    "up_from_cloud",
    "resolve_up",
    "estimate_up",
    "unit_up",
    "DEFAULT_UP",
    "SOURCES",
]

#: Up of a level camera in the optical frame (x right, y down, z forward).
DEFAULT_UP = (0.0, -1.0, 0.0)
#: Degrees: a speckle floor (``GravityParams.sparse_floor``) within this of the planes'
#: estimate adds only its fitting noise and does not vote; a segmented plane within this of it
#: (and :data:`SPARSE_SAME_OFFSET` of its offset) is that floor already.
SPARSE_AGREE_DEG = 10.0
#: Metres: see :data:`SPARSE_AGREE_DEG`.
SPARSE_SAME_OFFSET = 0.05
#: Where an up vector came from.
SOURCES = ("given", "file", "estimated", "default")


@dataclass(frozen=True)
class GravityParams:
    """Parameters of :func:`estimate_gravity`.

    Parameters
    ----------
    tol_deg : float
        A plane within this many degrees of horizontal (or vertical) w.r.t. a candidate is
        consistent with it.
    min_area : float
        Planes smaller than this many m^2 do not vote.
    min_points : int
        Regions with fewer valid points do not vote.
    max_planes : int
        The largest this many planes make candidates (all voting planes are scored).
    vertical_weight : float
        A vertical plane's vote relative to a horizontal one's (a vertical plane is consistent
        with a whole circle of directions, a horizontal one with a single direction).
    max_roll_deg : float
        Roll of the camera about its optical axis up to which no penalty applies.
    max_up_pitch_deg : float
        Angle of the optical axis above the horizon up to which no penalty applies (cameras
        look ahead or down; looking steeply up is penalised, looking down never is).
    max_height : float
        Horizontal surfaces (floors, treads, tables, room ceilings) lie within this many metres
        of the camera; a plane farther away counts less and less as a horizontal candidate
        (1-metre scale), so a far wall seen head-on is not taken for a floor below a camera
        looking straight down.  Raise it for sensors mounted high above the ground.
    min_pair_deg : float
        Two planes make a cross-product candidate when at least this far from parallel.
    low_confidence : float
        Estimates with a lower confidence are flagged.
    flip : bool
        Consider a camera held upside down (:func:`_flipped`): the estimate of the frame turned
        by 180 degrees about the optical axis, from the near planes only, replaces the upright
        one when it has the camera above clearly more horizontal area.
    flip_ratio : float
        The upside-down reading needs this many times the horizontal area seen from above (the
        camera over it) that the upright reading has.
    flip_min_area : float
        ... and at least this many m^2 of it (near planes, see ``max_height``); the default is
        ``min_area``'s, a single voting plane's.
    flip_min_tilt_deg : float
        ... and its up must point to the image's bottom by at least this many degrees (its
        component along the image's down axis at least ``sin`` of it).  Within that angle of
        the optical axis a camera looks straight down, its roll is undefined and upside down
        means nothing: the upright reading's sign rule (the camera above the horizontal planes)
        decides there.  5 (ramp44): on the independent low-camera set dev_low a level camera
        facing a wall over a grazing floor had its correct upright estimate replaced by an
        "upside-down" reading that took the wall for the floor (up 0.3 and 1.4 degrees to the
        image's bottom: 90 degrees off); the turned pose sweep's steepest upside-down camera
        (pitch 80, roll 20) points 9.4 degrees to it.  0: the rule before (any positive
        component).
    mirror_pairs : bool
        Two planes that face each other across a cavity, each tilted by the same angle between
        ``tol_deg`` and ``max_draft_deg`` from vertical w.r.t. their bisector, with a plane
        level w.r.t. that bisector below both (the drafted walls and floor of a tote or bin
        seen from above), vote for the bisector as a horizontal plane of their area does
        (:func:`_mirror_pairs`; docs/gravity.md, "A bin seen from above").  Needs the planes'
        centroids (the label path); ``False``: the estimate before.
    max_draft_deg : float
        The largest tilt from vertical of such a wall.
    mirror_pairs_near : bool
        A mirror pair's walls vote with their near weight (faded as the horizontal votes are
        by ``max_height``, and by their centroids' range as the upside-down reading's are): a
        tote or bin is seen from within reach.  ``True`` (grav45): on a D435i 0.10 m over a
        corridor floor, an 8.7 m^2 wall 4.1 m away paired with a far fragment 5.3 m away (both
        bent by the sensor) voted for their bisector, 50 degrees from the floor's normal, over
        the segmented floor (docs/gravity.md, "A camera near the floor: which reading wins").
        ``False``: the rule before (far walls vote with their whole area).
    steep_pitch_deg : float
        A reading in which the camera looks down by more than this many degrees ...
    steep_support : float
        ... counts its vertical votes only up to this many times its horizontal ones (mirror
        pairs included): a camera looking steeply down sees what is under it, so a reading
        explained by vertical planes alone is no such view.  2 (grav45): on a D435i 0.10 m over
        a corridor floor, pitched 10 degrees up, "looking straight down" won with 15.3 m^2 of
        vertical votes (the corridor's walls, vertical under it as under the true up, and far
        pieces the sensor bent to right angles with the optical axis) against 0.4 m^2 of
        horizontal ones, over the floor reading (docs/gravity.md, "A camera near the floor:
        which reading wins").  0: the rule before (no cap).
    near_floor : float
        A flagged estimate (below ``low_confidence``) gives way to the floor the camera stands
        over: the largest plane within ``near_floor_deg`` of the estimated up, seen from above
        (the camera on its normal's side), at most this many metres from the camera (its
        plane offset) and of at least ``near_floor_area`` m^2 sets the up (its normal).  A
        camera a few centimetres to a few decimetres over a floor sees that floor near and
        measured well, and the sensor's far walls and floor, bent by its range error, as many
        more m^2 (docs/gravity.md, "The floor under a low camera").  0: off (the estimate as
        voted).
    near_floor_area : float
        The least area of that plane, m^2.
    near_floor_deg : float
        The largest angle between that plane's normal and the flagged estimate, degrees.
    sparse_floor : float
        A floor measured only as speckle votes too (:func:`speckle_floor`): a camera a few
        decimetres over a floor sees it at grazing incidence, where structured light and
        active stereo return scattered pixels that no region grows over.  The unassigned
        valid points of the image's lower half are fitted by a plane (a seeded RANSAC within
        ``sparse_floor_tol`` m) whose normal lies within ``sparse_floor_deg`` of the image's
        up axis and which passes at most this many metres under the camera; when enough of
        them fit it (``sparse_floor_share``, at least ``sparse_floor_min`` of the image's
        pixels) over at least ``sparse_floor_reach`` m of range and ``sparse_floor_area``
        m^2 of extent, it votes as a plane of that extent, but only when the planes' own
        estimate is more than :data:`SPARSE_AGREE_DEG` from it and no segmented plane of
        ``near_floor_area`` is that floor already (within :data:`SPARSE_AGREE_DEG` and
        :data:`SPARSE_SAME_OFFSET`).  0: off (only segmented planes vote).
    sparse_floor_deg : float
        The largest angle between that floor's normal and the image's up axis, degrees.
    sparse_floor_tol : float
        The inlier distance, m.
    sparse_floor_share : float
        The least share of the lower half's unassigned points that fit it.
    sparse_floor_min : float
        The least number of inliers, as a share of the image's pixels.
    sparse_floor_reach : float
        The least spread of the inliers' ranges (2nd to 98th percentile), m.
    sparse_floor_area : float
        The least extent of that floor, m^2 (measured as a segmented plane's area is): a floor
        under a low camera reaches metres away; unassigned points of a cluttered table seen
        from close by fit planes of well under a square metre.
    sparse_floor_flip_share : float
        ``sparse_floor_share`` when the planes' estimate reads the camera upside down
        (``UpEstimate.upside_down``: a ceiling taken for the floor): a floor in the image's
        lower half contradicts that reading, so a smaller share of the speckle suffices.
        Equal to ``sparse_floor_share``: no difference.
    sparse_floor_tries : int
        The seeded three-point hypotheses of that fit.  A floor holding a share ``s`` of the
        points is hit by about ``tries * s**3`` of them (4.5 at 256 tries and ``s`` 0.26).
    refine_range : float
        Metres (grav53).  In the least-squares refinement after the vote, each plane's weight
        is its area times ``min(1, (refine_range / range)^2)``, ``range`` its centroid's
        distance from the camera: beyond it a plane counts by about its pixels, not its area,
        so far pieces a depth sensor bends by a few degrees do not tilt the up away from the
        near floor or table.  The vote, the reading and the confidence are unchanged; it needs
        the planes' ranges (the label path).  0 = the refinement before.
    """

    tol_deg: float = 5.0
    min_area: float = 0.01
    min_points: int = 30
    max_planes: int = 24
    vertical_weight: float = 0.5
    max_roll_deg: float = 35.0
    max_up_pitch_deg: float = 20.0
    max_height: float = 3.0
    min_pair_deg: float = 30.0
    low_confidence: float = 0.5
    flip: bool = True
    flip_ratio: float = 2.0
    flip_min_area: float = 0.01
    flip_min_tilt_deg: float = 5.0
    mirror_pairs: bool = True
    max_draft_deg: float = 30.0
    mirror_pairs_near: bool = True
    steep_pitch_deg: float = 60.0
    steep_support: float = 2.0
    near_floor: float = 0.35
    near_floor_area: float = 0.3
    near_floor_deg: float = 30.0
    sparse_floor: float = 0.35
    sparse_floor_deg: float = 35.0
    sparse_floor_tol: float = 0.02
    sparse_floor_share: float = 0.3
    sparse_floor_min: float = 0.002
    sparse_floor_reach: float = 0.5
    sparse_floor_area: float = 1.5
    sparse_floor_flip_share: float = 0.2
    sparse_floor_tries: int = 256
    refine_range: float = 1.5

    def __post_init__(self) -> None:
        checks = (("tol_deg", 0.5, 20.0), ("min_area", 0.0, 100.0), ("vertical_weight", 0.0, 1.0),
                  ("max_roll_deg", 0.0, 90.0), ("max_up_pitch_deg", 0.0, 90.0),
                  ("max_height", 0.1, 1000.0), ("min_pair_deg", 5.0, 85.0),
                  ("low_confidence", 0.0, 1.0), ("flip_ratio", 1.0, 1000.0),
                  ("flip_min_area", 0.0, 100.0), ("flip_min_tilt_deg", 0.0, 45.0),
                  ("max_draft_deg", 0.0, 45.0), ("steep_pitch_deg", 0.0, 90.0),
                  ("steep_support", 0.0, 1000.0), ("near_floor", 0.0, 10.0),
                  ("near_floor_area", 0.0, 1000.0), ("near_floor_deg", 0.0, 60.0),
                  ("sparse_floor", 0.0, 10.0), ("sparse_floor_deg", 0.0, 90.0),
                  ("sparse_floor_tol", 0.001, 1.0), ("sparse_floor_share", 0.0, 1.0),
                  ("sparse_floor_min", 0.0, 1.0), ("sparse_floor_reach", 0.0, 100.0), ("sparse_floor_area", 0.0, 1000.0),
                  ("sparse_floor_flip_share", 0.0, 1.0), ("refine_range", 0.0, 1000.0))
        for name, lo, hi in checks:
            v = getattr(self, name)
            if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v) \
                    or not lo <= v <= hi:
                raise InputError(f"gravity {name} must be a number in [{lo}, {hi}], got {v!r}")
        for name in ("flip", "mirror_pairs", "mirror_pairs_near"):
            if not isinstance(getattr(self, name), bool):
                raise InputError(f"gravity {name} must be true or false, got {getattr(self, name)!r}")
        for name in ("min_points", "max_planes", "sparse_floor_tries"):
            v = getattr(self, name)
            if isinstance(v, bool) or not isinstance(v, int) or v < 3:
                raise InputError(f"gravity {name} must be an integer >= 3, got {v!r}")


@dataclass(frozen=True, eq=False)
class UpEstimate:
    """An up vector, where it came from and how sure it is.

    Attributes
    ----------
    vector : ndarray, shape (3,)
        Unit gravity-up in the camera frame (x right, y down, z forward).
    source : str
        One of :data:`SOURCES`.
    confidence : float
        In [0, 1]; 1 for a given or file vector, 0 for the default.
    n_planes : int
        Planes that voted (estimates only).
    low_confidence : bool
        ``confidence`` below :attr:`GravityParams.low_confidence`.
    upside_down : bool
        The estimate is the upside-down reading (:attr:`GravityParams.flip`).
    near_floor : bool
        The vote was not clear and the floor under the camera set the vector
        (:attr:`GravityParams.near_floor`).
    sparse_floor : bool
        A floor measured only as speckle voted and changed the reading
        (:attr:`GravityParams.sparse_floor`).
    """

    vector: np.ndarray
    source: str
    confidence: float
    n_planes: int = 0
    low_confidence: bool = False
    upside_down: bool = False
    near_floor: bool = False
    sparse_floor: bool = False

    def __post_init__(self) -> None:
        if self.source not in SOURCES:
            raise InputError(f"up source must be one of {SOURCES}, got {self.source!r}")
        v = unit_up(self.vector, "up vector")
        v.setflags(write=False)
        object.__setattr__(self, "vector", v)
        object.__setattr__(self, "confidence", float(min(1.0, max(0.0, self.confidence))))

    def to_dict(self) -> dict:
        """``{"vector": [x, y, z], "source": ..., "confidence": ...}`` (rounded for JSON)."""
        out = {"vector": [round(float(x), 6) + 0.0 for x in self.vector], "source": self.source,
               "confidence": round(self.confidence, 3)}
        if self.source == "estimated":
            out["n_planes"] = self.n_planes
            out["low_confidence"] = self.low_confidence
            if self.upside_down:
                out["upside_down"] = True
            if self.near_floor:
                out["near_floor"] = True
            if self.sparse_floor:
                out["sparse_floor"] = True
        return out

    def describe(self) -> str:
        """``up [0.01, -0.62, -0.78] estimated, confidence 0.78`` (one line)."""
        vec = ", ".join(f"{x:.3f}" for x in self.vector)
        text = f"up [{vec}] {self.source}, confidence {self.confidence:.2f}"
        return (text + (" (low)" if self.low_confidence else "")
                + (", camera upside down" if self.upside_down else "")
                + (", from the floor under the camera" if self.near_floor else "")
                + (", with the floor's speckle" if self.sparse_floor else ""))


# ----------------------------------------------------------------------------- the estimate


def _kernel(angle_deg: np.ndarray, tol: float) -> np.ndarray:
    return np.clip(1.0 - (angle_deg / tol) ** 2, 0.0, None)


def _angles(cands: np.ndarray, normals: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Degrees from horizontal and from vertical of each plane w.r.t. each candidate,
    both ``(C, N)``."""
    d = np.clip(np.abs(cands @ normals.T), 0.0, 1.0)
    from_h = np.degrees(np.arccos(d))
    return from_h, 90.0 - from_h


def _orient(c: np.ndarray) -> np.ndarray:
    """Sign convention for candidates before the prior: towards the image top, else backwards
    along the optical axis (a camera looking down rather than up)."""
    c = np.array(c, dtype=np.float64)
    key = np.where(np.abs(c[:, 1]) > 1e-9, -c[:, 1], -c[:, 2])
    c[key < 0] *= -1
    return c


def _pose_prior(cands: np.ndarray, params: GravityParams) -> np.ndarray:
    """``(C,)`` factor in (0, 1] from the camera pose a candidate implies: 1 up to
    ``max_roll_deg`` of roll and ``max_up_pitch_deg`` of looking up, then falling off (20-degree
    scale).  The roll term fades out as the roll becomes undefined (camera looking straight
    down)."""
    proj = np.hypot(cands[:, 0], cands[:, 1])
    roll = np.degrees(np.arctan2(np.abs(cands[:, 0]), -cands[:, 1]))  # 0..180
    excess = np.maximum(roll - params.max_roll_deg, 0.0)
    p_roll = np.exp(-((excess / 20.0) ** 2))
    defined = np.clip(proj / math.sin(math.radians(20.0)), 0.0, 1.0)
    # up_cam = (., -cos(pitch) cos(roll), -sin(pitch)) for a camera pitched down by `pitch`
    pitch = np.degrees(np.arcsin(np.clip(-cands[:, 2], -1.0, 1.0)))
    excess = np.maximum(-pitch - params.max_up_pitch_deg, 0.0)
    p_pitch = np.exp(-((excess / 20.0) ** 2))
    return (1.0 - defined * (1.0 - p_roll)) * p_pitch


def _candidates(normals: np.ndarray, weights: np.ndarray, params: GravityParams) -> np.ndarray:
    order = np.argsort(-weights, kind="stable")[: params.max_planes]
    top = normals[order]
    cands = [top, np.array([DEFAULT_UP])]
    k = top.shape[0]
    if k >= 2:
        idx = np.arange(k)
        i, j = np.nonzero(idx[:, None] < idx[None, :])
        cr = np.cross(top[i], top[j])
        s = np.linalg.norm(cr, axis=1)
        ok = s >= math.sin(math.radians(params.min_pair_deg))
        if ok.any():
            cands.append(cr[ok] / s[ok, None])
    # each plane taken as the only vertical one, seen with no roll
    img_up = np.array(DEFAULT_UP)
    perp = img_up - (top @ img_up)[:, None] * top
    s = np.linalg.norm(perp, axis=1)
    ok = s > 0.2
    if ok.any():
        cands.append(perp[ok] / s[ok, None])
    return _orient(np.concatenate(cands, axis=0))


def _height_factor(offsets: np.ndarray, params: GravityParams) -> np.ndarray:
    """``(N,)`` plausibility in (0, 1] that a plane this far from the camera is horizontal."""
    excess = np.maximum(offsets - params.max_height, 0.0)
    return np.exp(-(excess ** 2))


def _mirror_pairs(n: np.ndarray, cent, params: GravityParams):
    """Drafted walls facing each other: ``(I, J, B)``, plane indices and the unit bisector of
    each pair's normals (oriented to the sensor, as the normals are), or ``None``.

    A pair qualifies when the angle between its normals is ``180 - 2 d`` for a draft ``d``
    between ``tol_deg`` (below that both walls are vertical to the bisector already) and
    ``max_draft_deg``; the walls face each other: each normal points towards the other
    plane's centroid (a cavity seen from inside, not a ridge or a box's corner seen from
    outside); and a plane level w.r.t. their bisector (within ``tol_deg``) lies lower along
    it than both walls' centroids: the container's floor.  The bisector is then the one up
    for which both walls lean out alike from a level floor: the mirror axis of a tote's or
    bin's walls."""
    if not params.mirror_pairs or cent is None or n.shape[0] < 2:
        return None
    cent = np.asarray(cent, dtype=np.float64)
    k = n.shape[0]
    i, j = np.nonzero(np.arange(k)[:, None] < np.arange(k)[None, :])
    cos_ij = np.einsum("ij,ij->i", n[i], n[j])
    lo = math.cos(math.radians(180.0 - 2.0 * params.tol_deg))
    hi = math.cos(math.radians(180.0 - 2.0 * params.max_draft_deg))
    d = cent[j] - cent[i]
    facing = (np.einsum("ij,ij->i", n[i], d) > 0) & (np.einsum("ij,ij->i", n[j], -d) > 0)
    ok = (cos_ij >= lo) & (cos_ij <= hi) & facing
    if not ok.any():
        return None
    i, j = i[ok], j[ok]
    b = n[i] + n[j]
    b /= np.linalg.norm(b, axis=1)[:, None]
    # the container's floor: a plane level w.r.t. the bisector, lower than both walls' middles
    level = np.abs(b @ n.T) >= math.cos(math.radians(params.tol_deg))  # (P, N)
    below_i = np.einsum("pk,nk->pn", b, cent) < np.einsum("pk,pk->p", b, cent[i])[:, None]
    below_j = np.einsum("pk,nk->pn", b, cent) < np.einsum("pk,pk->p", b, cent[j])[:, None]
    floor = (level & below_i & below_j).any(axis=1)
    if not floor.any():
        return None
    return i[floor], j[floor], b[floor]


def _pair_votes(cands, weights, pairs, params) -> np.ndarray:
    """``(C,)``: the area of the planes that belong to a mirror pair whose bisector is within
    ``tol_deg`` of the candidate (each plane once, through the kernel of its best pair)."""
    out = np.zeros(cands.shape[0])
    if pairs is None:
        return out
    i, j, b = pairs
    ang = np.degrees(np.arccos(np.clip(np.abs(cands @ b.T), 0.0, 1.0)))
    k = _kernel(ang, params.tol_deg)  # (C, P)
    for p in np.unique(np.concatenate([i, j])):
        sel = (i == p) | (j == p)
        out += weights[p] * k[:, sel].max(axis=1)
    return out


def _scores(cands, normals, weights, hweights, params, pairs=None, pair_weights=None, cap=True):
    """``(C,)`` score of each candidate: horizontal votes (mirror pairs included) plus vertical
    ones, times the pose prior; with ``cap``, a candidate looking down by more than
    ``steep_pitch_deg`` counts its vertical votes only up to ``steep_support`` times its
    horizontal ones."""
    from_h, from_v = _angles(cands, normals)
    tol = params.tol_deg
    pw = hweights if pair_weights is None else pair_weights
    level = _kernel(from_h, tol) @ hweights + _pair_votes(cands, pw, pairs, params)
    upright = params.vertical_weight * (_kernel(from_v, tol) @ weights)
    if cap and params.steep_support > 0:  # looking steeply down: something must be under it
        pitch = np.degrees(np.arcsin(np.clip(-cands[:, 2], -1.0, 1.0)))
        steep = pitch > params.steep_pitch_deg
        upright = np.where(steep, np.minimum(upright, params.steep_support * level), upright)
    return (level + upright) * _pose_prior(cands, params)


def _refine(c: np.ndarray, normals, weights, hweights, params, rf=None) -> np.ndarray:
    if rf is not None:  # near planes, measured best, set the vector (``refine_range``)
        weights, hweights = weights * rf, hweights * rf
    for tol in (params.tol_deg, 0.6 * params.tol_deg):
        from_h, from_v = (a[0] for a in _angles(c[None], normals))
        h = from_h <= tol
        v = from_v <= tol
        if not (h.any() or v.any()):
            break
        m = np.zeros((3, 3))
        if h.any():
            nh = normals[h]
            m -= np.einsum("k,ki,kj->ij", hweights[h], nh, nh)
            m += np.eye(3) * hweights[h].sum()
        if v.any():
            nv = normals[v]
            m += params.vertical_weight * np.einsum("k,ki,kj->ij", weights[v], nv, nv)
        vals, vecs = np.linalg.eigh(m)
        # the smallest eigenvalue must be clearly alone, else the planes leave up undetermined
        if vals[1] - vals[0] < 1e-3 * max(vals[2], 1e-12):
            break
        new = vecs[:, 0]
        c = new if new @ c >= 0 else -new
    return c


def _choose_sign(c: np.ndarray, normals, weights, params) -> np.ndarray:
    """Up towards the image top when defined, else towards the sensor side of horizontal planes."""
    if abs(c[1]) >= math.sin(math.radians(12.0)):
        return c if c[1] < 0 else -c
    from_h, _ = _angles(c[None], normals)
    h = from_h[0] <= params.tol_deg
    if h.any():
        side = float(np.sum(weights[h] * np.sign(normals[h] @ c)))
        if side != 0:
            return c if side > 0 else -c
    return c if c[2] <= 0 else -c


def estimate_gravity(normals, weights, offsets=None, params: GravityParams | None = None,
                     ranges=None, centroids=None) -> UpEstimate:
    """Estimate the up vector from oriented plane normals and their areas.

    Parameters
    ----------
    normals : array_like, shape (N, 3)
        Unit plane normals, each oriented towards the sensor.
    weights : array_like, shape (N,)
        Plane areas (m^2) or any non-negative weights.
    offsets : array_like, shape (N,), optional
        Distance from the camera centre to each plane, metres (``normal . x + offset = 0``);
        planes farther than ``params.max_height`` count less as horizontal.  Default: all near.
    params : GravityParams, optional
    ranges : array_like, shape (N,), optional
        Distance from the camera to each plane's centroid, metres: only the planes within
        about ``params.max_height`` (1-metre scale) vote for the upside-down reading
        (``params.flip``).  Default: ``offsets``.
    centroids : array_like, shape (N, 3), optional
        Each plane's centroid, metres: walls facing each other across a cavity, tilted alike,
        vote for their bisector (``params.mirror_pairs``).  Default: no such votes.

    Returns
    -------
    UpEstimate
        ``source == "estimated"``; ``"default"`` with confidence 0 when no plane votes.
    """
    params = params or GravityParams()
    n = np.asarray(normals, dtype=np.float64).reshape(-1, 3)
    w = np.asarray(weights, dtype=np.float64).reshape(-1)
    if n.shape[0] != w.shape[0]:
        raise InputError(f"estimate_gravity needs one weight per normal, got {n.shape[0]} normals "
                         f"and {w.shape[0]} weights")
    d = np.zeros(n.shape[0]) if offsets is None else np.asarray(offsets, dtype=np.float64).reshape(-1)
    if d.shape[0] != n.shape[0]:
        raise InputError(f"estimate_gravity needs one offset per normal, got {n.shape[0]} normals "
                         f"and {d.shape[0]} offsets")
    hw = w * _height_factor(np.abs(d), params)
    if ranges is None:
        near = hw
    else:
        r = np.asarray(ranges, dtype=np.float64).reshape(-1)
        if r.shape[0] != n.shape[0]:
            raise InputError(f"estimate_gravity needs one range per normal, got {n.shape[0]} "
                             f"normals and {r.shape[0]} ranges")
        near = hw * _height_factor(np.abs(r), params)
    rf = None
    if ranges is not None and params.refine_range > 0:
        r = np.maximum(np.abs(np.asarray(ranges, dtype=np.float64).reshape(-1)), 1e-6)
        rf = np.minimum(1.0, (params.refine_range / r) ** 2)
    cent = None
    if centroids is not None:
        cent = np.asarray(centroids, dtype=np.float64).reshape(-1, 3)
        if cent.shape[0] != n.shape[0]:
            raise InputError(f"estimate_gravity needs one centroid per normal, got {n.shape[0]} "
                             f"normals and {cent.shape[0]} centroids")
    est = _estimate(n, w, hw, params, near, cent, rf)
    if offsets is None:
        return est
    return _near_floor(est, n, w, d, params)


def _near_floor(est: UpEstimate, n, w, d, params: GravityParams) -> UpEstimate:
    """``est``, or, when it is flagged, the normal of the floor the camera stands over
    (:attr:`GravityParams.near_floor`): ``n`` ``(N, 3)`` normals oriented to the sensor, ``w``
    ``(N,)`` areas, ``d`` ``(N,)`` plane offsets (m)."""
    if params.near_floor <= 0 or est.source != "estimated" or not est.low_confidence:
        return est
    length = np.linalg.norm(n, axis=1)
    ok = np.isfinite(length) & (length > 0) & np.isfinite(w) & np.isfinite(d)
    if not ok.any():
        return est
    unit = np.zeros_like(n)
    unit[ok] = n[ok] / length[ok, None]
    up = np.asarray(est.vector, dtype=np.float64)
    cand = ok & (unit @ up >= math.cos(math.radians(params.near_floor_deg))) \
        & (np.abs(d) <= params.near_floor) & (w >= params.near_floor_area)
    if not cand.any():
        return est
    k = int(np.argmax(np.where(cand, w, -np.inf)))
    # the floor's pieces (within tol_deg of the largest), by area
    same = cand & (unit @ unit[k] >= math.cos(math.radians(params.tol_deg)))
    v = (w[same, None] * unit[same]).sum(axis=0)
    return dataclasses.replace(est, vector=v / np.linalg.norm(v), near_floor=True)


def _estimate(n, w, hw, params: GravityParams, near=None, cent=None, rf=None) -> UpEstimate:
    """:func:`estimate_gravity` with the horizontal weights ``hw`` given; ``near`` (default
    ``hw``) are the weights of the upside-down reading (:func:`_flipped`); ``cent`` the
    planes' centroids (:func:`_mirror_pairs`), optional; ``rf`` each plane's weight factor in
    the refinement (``refine_range``), optional."""
    near = hw if near is None else near
    length = np.linalg.norm(n, axis=1)
    keep = np.isfinite(length) & (length > 0) & np.isfinite(w) & (w > 0) & np.isfinite(hw)
    n = n[keep] / length[keep, None]
    w = w[keep]
    hw = hw[keep]
    near = np.where(np.isfinite(near[keep]), near[keep], 0.0)
    if cent is not None:
        cent = cent[keep]
    if rf is not None:
        rf = rf[keep]
    if n.shape[0] == 0:
        return UpEstimate(np.array(DEFAULT_UP), "default", 0.0, 0, True)
    upright = _upright(n, w, hw, params, _mirror_pairs(n, cent, params),
                       near if params.mirror_pairs_near else None, rf=rf)
    if not params.flip:
        return upright
    return _flipped(upright, n, near, params, cent, rf=rf)


#: Turning the camera by 180 degrees about its optical axis negates x and y.
_TURN = np.array([-1.0, -1.0, 1.0])


def _seen_from_above(c: np.ndarray, n: np.ndarray, hw: np.ndarray, params: GravityParams) -> float:
    """Area (``hw``) of the planes horizontal w.r.t. up ``c`` that the camera sees from above
    (the normal, oriented to the sensor, along ``c``): floors, tables, tops."""
    along = n @ c
    h = np.degrees(np.arccos(np.clip(np.abs(along), 0.0, 1.0))) <= params.tol_deg
    return float(hw[h & (along > 0)].sum())


def _flipped(upright: UpEstimate, n, hw, params: GravityParams, cent=None, rf=None) -> UpEstimate:
    """The upright estimate, or the upside-down one when the planes say so.

    The upside-down reading is the upright estimate of the frame turned by 180 degrees about
    the optical axis (so the pose prior reads the turned camera as it reads an upright one),
    turned back, from the planes near enough to be floors (``hw``: far planes, where a sensor's
    range error is large, do not vote).  It replaces the upright reading only when

    - it points to the image's bottom (the camera is upside down) by at least
      ``flip_min_tilt_deg`` (looking straight down, upside down is no different from upright);
    - its axis is the upright reading's (within ``2 tol_deg``: only the sign is in question),
      or it explains the near planes better than the upright reading does, each judged by its
      own pose prior (the upright reading of an upside-down camera looking steeply down is
      "looking up", which the prior refuses, so it takes a wall for the floor);
    - the camera is above at least ``flip_ratio`` times as much near horizontal area under it
      as under the opposite sign and as under the upright reading (and ``flip_min_area``): a
      camera sees floors, tables and box tops from above; held upside down, it sees them on
      the image's top side, where an upright camera would see ceilings.
    """
    if upright.source != "estimated":
        return upright
    keep = hw > 0
    if not keep.any():
        return upright
    nk, wk = n[keep], hw[keep]
    pairs = _mirror_pairs(nk, None if cent is None else cent[keep], params)
    turned_pairs = None if pairs is None else (pairs[0], pairs[1], pairs[2] * _TURN)
    turned = _upright(nk * _TURN, wk, wk, params, turned_pairs,
                      rf=None if rf is None else rf[keep])
    if turned.source != "estimated":
        return upright
    c = np.array(turned.vector) * _TURN
    if c[1] <= math.sin(math.radians(params.flip_min_tilt_deg)):
        return upright  # not upside down after all, or looking straight down (roll undefined)
    u = np.array(upright.vector)
    if abs(float(c @ u)) < math.cos(math.radians(2.0 * params.tol_deg)):
        s_flip = float(_scores(_orient((c * _TURN)[None]), nk * _TURN, wk, wk, params,
                               turned_pairs)[0])
        s_up = float(_scores(_orient(u[None]), nk, wk, wk, params, pairs)[0])
        if s_flip <= s_up:
            return upright
    above_flip = _seen_from_above(c, n, hw, params)
    rival = max(_seen_from_above(-c, n, hw, params), _seen_from_above(u, n, hw, params))
    if above_flip < max(params.flip_min_area, params.flip_ratio * rival):
        return upright
    return UpEstimate(c, "estimated", turned.confidence, upright.n_planes, turned.low_confidence,
                      upside_down=True)


#: A candidate within this many degrees of the optical axis has an image-up component that is
#: noise (:func:`_looking_down`).
AXIS_ORIENT_DEG = 12.0
#: An upright plane keeps a near-axis candidate oriented by the image's top only when its
#: normal lies within this many degrees of the image's top (a floor strip under a level camera
#: facing a wall), not one facing the image's bottom (a wall behind a board seen from above,
#: which the image's top reading makes a ceiling with no floor under the camera) nor one
#: facing sideways (a tower's side: upright in both readings) (:func:`_looking_down`, axis102)
AXIS_FLOOR_DEG = 45.0


def _looking_down(cands: np.ndarray, n: np.ndarray, params: GravityParams) -> np.ndarray:
    """``cands`` plus, for each candidate within :data:`AXIS_ORIENT_DEG` of the optical axis
    that :func:`_orient` turned towards the camera looking up, its negation (the camera
    looking down), when no plane upright to it faces the image's top (within
    :data:`AXIS_FLOOR_DEG`).

    A board seen from straight above has a normal whose image-up component is a few
    thousandths either way; by its sign :func:`_orient` read the camera as looking straight
    up, the pose prior refused that, and the board became a wall (tote67: hunt67's armlab
    frames, 90 degrees off).  With an upright plane facing the image's top in view (a level
    camera facing a wall over a strip of floor) the image's top orients it as before; upright
    planes facing the image's bottom or sideways (the wall behind a board and the sides of
    cube towers on it, hunt90 lk-armlab stacks, 91 degrees off before axis102) do not keep
    it."""
    on_axis = (np.abs(cands[:, 2]) >= math.cos(math.radians(AXIS_ORIENT_DEG))) & (cands[:, 2] > 0)
    if not on_axis.any():
        return cands
    _, from_v = _angles(cands[on_axis], n)
    floorish = -n[:, 1] >= math.sin(math.radians(AXIS_FLOOR_DEG))
    alone = ~((from_v <= params.tol_deg) & floorish[None, :]).any(axis=1)
    if not alone.any():
        return cands
    return np.concatenate([cands, -cands[on_axis][alone]], axis=0)


def _upright(n, w, hw, params: GravityParams, pairs=None, pair_w=None, rf=None) -> UpEstimate:
    """The estimate for a camera that is not upside down (unit normals, positive weights;
    ``pairs``: :func:`_mirror_pairs`'s; ``pair_w``: the walls' votes for their bisector,
    default ``hw``: :func:`_estimate` gives the near weights, so that only walls within about
    ``max_height`` of the camera vote as a tote's or bin's drafted walls)."""
    cands = _candidates(n, w, params)
    if pairs is not None:
        cands = np.concatenate([cands, _orient(pairs[2])], axis=0)
    cands = _looking_down(cands, n, params)
    score = _scores(cands, n, w, hw, params, pairs, pair_w)
    best = int(np.argmax(score))
    c = _refine(cands[best], n, w, hw, params, rf)
    c = _choose_sign(c / np.linalg.norm(c), n, hw, params)
    # confidence
    s_best = float(_scores(_orient(c[None]), n, w, hw, params, pairs, pair_w)[0])
    s_best = max(s_best, float(score[best]))
    far = np.abs(cands @ c) < math.cos(math.radians(2.0 * params.tol_deg))
    # the rival as the planes alone rank it: a steep reading the cap refused still says the
    # planes fit another reading (the cap picks the winner, it does not add certainty)
    raw = _scores(cands, n, w, hw, params, pairs, pair_w, cap=False) \
        if params.steep_support > 0 else score
    rival = float(raw[far].max()) if far.any() else 0.0
    from_h, from_v = (a[0] for a in _angles(c[None], n))
    h = from_h <= params.tol_deg
    v = from_v <= params.tol_deg
    if pairs is not None:  # walls of a mirror pair about the estimate are explained
        near_b = np.degrees(np.arccos(np.clip(np.abs(pairs[2] @ c), 0.0, 1.0))) <= params.tol_deg
        v[pairs[0][near_b]] = True
        v[pairs[1][near_b]] = True
    explained = float(w[h | v].sum() / w.sum())
    ratio = rival / s_best if s_best > 0 else 1.0
    # cross-checked: the consistent planes point in two directions at least min_pair_deg apart
    cons = n[h | v]
    gram = np.abs(cons @ cons.T)
    if (gram < math.cos(math.radians(params.min_pair_deg))).any():
        checked = 1.0
    elif h.any():  # parallel horizontal planes (floor and treads) / a single plane
        checked = 0.6 if h.sum() >= 2 else 0.4
    else:  # one vertical direction: up within it is the roll prior's guess
        checked = 0.2
    conf = math.sqrt(explained) * min(1.0, 2.0 * (1.0 - ratio)) * checked
    return UpEstimate(c, "estimated", conf, int(n.shape[0]), conf < params.low_confidence)


# ------------------------------------------------------------------------ from a cloud


def _planes_from_labels(cloud, labels, params: GravityParams):
    """Oriented normals ``(K, 3)``, areas ``(K,)``, offsets ``(K,)``, centroid ranges
    ``(K,)`` and centroids ``(K, 3)`` of the labelled regions that may vote."""
    from planerel.features.labels import _moments, check_labels

    xyz = cloud.xyz
    lab = check_labels(labels, xyz.shape[:2]).copy()
    lab[~cloud.valid] = -1
    nlab = int(lab.max()) + 1 if lab.size else 0
    if nlab <= 0:
        return np.zeros((0, 3)), np.zeros(0), np.zeros(0), np.zeros(0), np.zeros((0, 3))
    counts, cent, cov, _ = _moments(xyz, lab, nlab)
    ok = counts >= params.min_points
    if not ok.any():
        return np.zeros((0, 3)), np.zeros(0), np.zeros(0), np.zeros(0), np.zeros((0, 3))
    vals, vecs = np.linalg.eigh(cov[ok])
    vals = np.maximum(vals, 0.0)
    nrm = vecs[:, :, 0].copy()
    flip = np.einsum("ij,ij->i", nrm, cent[ok]) > 0
    nrm[flip] *= -1
    area = 12.0 * np.sqrt(vals[:, 1] * vals[:, 2])
    offset = -np.einsum("ij,ij->i", nrm, cent[ok])
    reach = np.linalg.norm(cent[ok], axis=1)
    flat = np.sqrt(vals[:, 0]) <= 0.25 * np.sqrt(vals[:, 1])
    keep = flat & (area >= params.min_area)
    return nrm[keep], area[keep], offset[keep], reach[keep], cent[ok][keep]


def speckle_floor(cloud, labels, axis=DEFAULT_UP, max_deg: float | None = None,
                  params: GravityParams | None = None):
    """A floor under a low camera that only speckle measures (:attr:`GravityParams.sparse_floor`):
    a plane through the unassigned valid points of the image's lower half.

    Parameters
    ----------
    cloud : Cloud
        Organized ``(H, W, 3)``.
    labels : array_like, shape (H, W)
        Plane labels, -1 unassigned.
    axis : array_like, shape (3,)
        The floor's normal lies within ``max_deg`` of it: the image's up axis (the default)
        for the estimate, the estimated up when it is known.
    max_deg : float, optional
        Default ``params.sparse_floor_deg``.
    params : GravityParams, optional

    Returns
    -------
    tuple or None
        ``(normal (3,), area, offset, range, centroid (3,))`` of the floor: its unit normal
        oriented to the sensor, its extent (m^2), the camera's height over it (m), its inliers'
        centroid and that centroid's range (m); ``None`` when ``params.sparse_floor`` is 0 or
        no such floor is found.
    """
    from planerel.features.labels import check_labels

    params = params or GravityParams()
    if params.sparse_floor <= 0:
        return None
    max_deg = params.sparse_floor_deg if max_deg is None else max_deg
    xyz = cloud.xyz
    H, W = xyz.shape[:2]
    lab = check_labels(labels, (H, W))
    low = slice(H // 2, H)
    free = np.flatnonzero(cloud.valid[low] & (lab[low] < 0))
    need = params.sparse_floor_min * H * W
    if free.size < max(30.0, need):
        return None
    stride = max(1, free.size // 20000)
    # every stride-th free point, gathered by index: the same points as taking them all and
    # then every stride-th, without copying the rest (most of this function's time before)
    pts = xyz[low].reshape(-1, 3)[free[::stride]]
    # ``sparse_floor_tries`` seeded three-point hypotheses at once, scored on at most 4000 of the points
    rng = np.random.default_rng(0)
    tri = pts[rng.integers(0, pts.shape[0], size=(params.sparse_floor_tries, 3))]
    nrm = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    length = np.linalg.norm(nrm, axis=1)
    good = length > 1e-12
    nrm = nrm[good] / length[good, None]
    d = -np.einsum("ij,ij->i", nrm, tri[good, 0])
    turn = d < 0  # orient to the sensor: the camera (origin) on the normal's side
    nrm[turn], d[turn] = -nrm[turn], -d[turn]
    axis = np.asarray(axis, dtype=np.float64) / np.linalg.norm(axis)
    keep = (nrm @ axis >= math.cos(math.radians(max_deg))) & (d <= params.sparse_floor)
    if not keep.any():
        return None
    nrm, d = nrm[keep], d[keep]
    sample = pts[:: max(1, pts.shape[0] // 4000)]
    count = (np.abs(sample @ nrm.T + d) <= params.sparse_floor_tol).sum(axis=0)
    k = int(np.argmax(count))
    nrm, d = nrm[k], float(d[k])
    for _ in range(2):  # least squares on the inliers
        inl = np.abs(pts @ nrm + d) <= params.sparse_floor_tol
        if inl.sum() < 3:
            return None
        c = pts[inl].mean(axis=0)
        nrm = np.linalg.eigh(np.cov((pts[inl] - c).T))[1][:, 0]
        d = -float(nrm @ c)
        if d < 0:
            nrm, d = -nrm, -d
    inl = np.abs(pts @ nrm + d) <= params.sparse_floor_tol
    n_in = int(inl.sum()) * stride
    if nrm @ axis < math.cos(math.radians(max_deg)) or d > params.sparse_floor or n_in < need \
            or inl.mean() < params.sparse_floor_share:
        return None
    p = pts[inl]
    r = np.linalg.norm(p, axis=1)
    lo, hi = np.percentile(r, [2, 98])
    if hi - lo < params.sparse_floor_reach:
        return None
    # its extent, as a segmented plane's area is measured (12 sqrt of the in-plane variances)
    cent = p.mean(axis=0)
    vals = np.maximum(np.linalg.eigvalsh(np.cov((p - cent).T)), 0.0)
    area = 12.0 * math.sqrt(vals[1] * vals[2])
    if area < params.sparse_floor_area:
        return None
    return nrm, area, d, float(np.linalg.norm(cent)), cent


def _grid_directions(cloud, params: GravityParams):
    """Dominant surface directions of an organized cloud without labels: ``(K, 3)`` oriented
    unit normals, the area ``(K,)`` each covers, the part of it near enough to the camera to
    be horizontal (see ``max_height``) and the part of that within about ``max_height`` of the
    camera (the upside-down reading's votes)."""
    empty = np.zeros((0, 3)), np.zeros(0), np.zeros(0), np.zeros(0)
    xyz = cloud.xyz
    W = xyz.shape[1]
    step = max(1, W // 80)
    g = xyz[::step, ::step]
    if g.shape[0] < 5 or g.shape[1] < 5:
        return empty
    dx = g[2:-2, 4:] - g[2:-2, :-4]
    dy = g[4:, 2:-2] - g[:-4, 2:-2]
    ctr = g[2:-2, 2:-2].reshape(-1, 3)
    cr = np.cross(dx, dy).reshape(-1, 3)
    with np.errstate(invalid="ignore"):
        lx = np.linalg.norm(dx, axis=2).reshape(-1)
        ly = np.linalg.norm(dy, axis=2).reshape(-1)
        length = np.linalg.norm(cr, axis=1)
        depth = np.linalg.norm(ctr, axis=1)
        # no depth jump inside the 4-cell window: both spans short for their distance
        reach = 4.0 * step * depth / (cloud.intrinsics.fx if cloud.intrinsics else 525.0)
        good = np.isfinite(length) & (length > 0) & (lx < 4 * reach) & (ly < 4 * reach)
    nrm = cr[good] / length[good, None]
    ctr = ctr[good]
    area = length[good] / 16.0  # |dx x dy| spans 4 x 4 grid cells
    if nrm.shape[0] == 0:
        return empty
    flip = np.einsum("ij,ij->i", nrm, ctr) > 0
    nrm[flip] *= -1
    harea = area * _height_factor(-np.einsum("ij,ij->i", nrm, ctr), params)
    narea = harea * _height_factor(depth[good], params)
    # greedy mode seeking: densest direction (5 deg), its members' mean, remove, repeat
    cos5 = math.cos(math.radians(5.0))
    out = []
    left = np.ones(nrm.shape[0], dtype=bool)
    total = float(area.sum())
    for _ in range(params.max_planes):
        idx = np.flatnonzero(left)
        if idx.size == 0 or float(area[idx].sum()) < 0.03 * total:
            break
        seeds = idx if idx.size <= 300 else idx[np.linspace(0, idx.size - 1, 300).astype(int)]
        dens = ((nrm[seeds] @ nrm[idx].T) >= cos5).astype(np.float64) @ area[idx]
        d = nrm[seeds[int(np.argmax(dens))]]
        for _ in range(2):
            mem = idx[(nrm[idx] @ d) >= cos5]
            m = (nrm[mem] * area[mem, None]).sum(axis=0)
            d = m / np.linalg.norm(m)
        mem = idx[(nrm[idx] @ d) >= cos5]
        out.append((d, float(area[mem].sum()), float(harea[mem].sum()), float(narea[mem].sum())))
        left[mem] = False
    if not out:
        return empty
    return (np.array([o[0] for o in out]), np.array([o[1] for o in out]),
            np.array([o[2] for o in out]), np.array([o[3] for o in out]))


def up_from_cloud(cloud, labels=None, params: GravityParams | None = None) -> UpEstimate:
    """Estimate the up vector of an organized cloud (its own ``up`` is ignored).

    Parameters
    ----------
    cloud : Cloud
        Organized ``(H, W, 3)``.
    labels : array_like, shape (H, W), optional
        Plane labels (-1 unassigned); without them, per-pixel normals on a coarse grid.
    params : GravityParams, optional

    Returns
    -------
    UpEstimate
    """
    params = params or GravityParams()
    if labels is not None:
        normals, weights, offsets, ranges, cent = _planes_from_labels(cloud, labels, params)
        est = estimate_gravity(normals, weights, offsets, params, ranges, cent)
        sparse = speckle_floor(cloud, labels, params=params if not est.upside_down else
                               dataclasses.replace(params, sparse_floor_share=min(
                                   params.sparse_floor_share, params.sparse_floor_flip_share)))
        # a speckle floor the planes' estimate agrees with adds nothing but its fitting noise;
        # a segmented plane that is that floor already votes for it
        agree = math.cos(math.radians(SPARSE_AGREE_DEG))
        if sparse is None or float(np.dot(est.vector, sparse[0])) >= agree \
                or ((normals @ sparse[0] >= agree)
                    & (np.abs(offsets - sparse[2]) <= SPARSE_SAME_OFFSET)
                    & (weights >= params.near_floor_area)).any():
            return est
        est = estimate_gravity(np.vstack([normals, sparse[0][None]]), np.append(weights, sparse[1]),
                               np.append(offsets, sparse[2]), params, np.append(ranges, sparse[3]),
                               np.vstack([cent, sparse[4][None]]))
        return dataclasses.replace(est, sparse_floor=True)
    normals, weights, hweights, near = _grid_directions(cloud, params)
    return _estimate(normals, weights, hweights, params, near)


def resolve_up(cloud, labels=None, up=None, params: GravityParams | None = None) -> UpEstimate:
    """The up vector to use: ``up`` (``given``), else ``cloud.up`` (``file``), else estimated
    from the planes (``estimated``), else the level camera's (``default``)."""
    if up is not None:
        return UpEstimate(unit_up(up, "up vector"), "given", 1.0)
    if getattr(cloud, "up", None) is not None:
        return UpEstimate(unit_up(cloud.up, "cloud up vector"), "file", 1.0)
    return up_from_cloud(cloud, labels, params)


def estimate_up(cloud, labels=None, params: GravityParams | None = None) -> np.ndarray:
    """Just the vector of :func:`up_from_cloud` (``(3,)``, unit)."""
    return np.array(up_from_cloud(cloud, labels, params).vector)
