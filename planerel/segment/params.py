"""Parameters of the segmentation methods, with the paper's defaults, validated when built."""

from __future__ import annotations

import math
from dataclasses import dataclass, fields

import numpy as np

from planerel.errors import InputError

__all__ = [
    "RegionGrowParams",
    "RansacParams",
    "REFERENCE_PIXELS",
    "REFERENCE_MIN_REGION_SIZE",
    "scaled_min_region_size",
    "coerce_params",
    "PRESETS",
    "preset_values",
]

#: The paper's ``min_region_size`` (90 points) is for 160x120 images.
REFERENCE_PIXELS = 160 * 120
REFERENCE_MIN_REGION_SIZE = 90


def scaled_min_region_size(n_pixels: int, scale: float = 1.0) -> int:
    """``min_region_size`` for an image (or cloud) of ``n_pixels`` points: the paper's 90 at
    160x120, proportional to the pixel count (1440 at 640x480), times ``scale``, at least 3."""
    return max(3, int(round(scale * REFERENCE_MIN_REGION_SIZE * n_pixels / REFERENCE_PIXELS)))


#: Named parameter sets of region growing (docs/segmentation.md, "Presets"); each turns the
#: adaptation to the measured sensor noise off (``adapt=False``).  ``"kinect"``: the fixed
#: settings that were the default before the adaptation (Kinect-like depth: noise and
#: quantisation grow as z^2, so the normal window grows with depth beyond 2 m).
#: ``"structured-light"`` (alias ``"abw"``) is for high-resolution range images with a uniform
#: depth quantisation several times the pixel footprint (SegComp ABW: 1.3 mm steps, 0.5 mm
#: pixels): a fixed 3-pixel normal window, and smaller regions kept (a quarter of the automatic
#: size: 307 at 512x512), since such scenes hold small true faces.
PRESETS = {
    "kinect": {"adapt": False},
    # Algorithm 1 as the paper writes it (docs/segmentation.md, "The paper's algorithm"): theta
    # while the region is small, theta * angle_mf after; no seed test; one automatic delta per
    # image; none of planerel's additions (segment() also turns the post-processing off)
    "paper": {"angle_order": "paper", "seed_test": False, "delta_mode": "image",
              "refine": False, "leftover_planes": False, "adapt": False},
    "structured-light": {"normal_smooth": 3, "normal_radius": 3, "reference_depth": None,
                         "min_region_scale": 0.25, "adapt": False},
}
PRESETS["abw"] = PRESETS["structured-light"]


def preset_values(name) -> dict:
    """The parameter values of preset ``name`` (see :data:`PRESETS`)."""
    if not isinstance(name, str) or name.lower() not in PRESETS:
        raise InputError(f"unknown preset {name!r}; choose one of {', '.join(sorted(PRESETS))}")
    return dict(PRESETS[name.lower()])


#: ``far_theta``: the share of a second growing's region that must lie in depth the first left
#: in no plane beyond ``far_depth``
FAR_SHARE = 0.8

#: ``far_local``: the largest patch noise (m per metre of depth) of a candidate it keeps
#: (hunt71's dark risers: 0.005; a foliage or cloth surface is rougher)
FAR_LOCAL_NOISE = 0.008

#: ``small_scale``: the share of a second growing's region that must lie in depth the first left
#: in no plane nearer than ``far_depth`` (lower than FAR_SHARE: a small box's thin side face
#: grows a few pixels into the top's plane, which the first growing's completion took)
SMALL_SHARE = 0.6
#: ``small_scale``: the smallest ``merge_side`` of the small pass's second growing (hunt67: the
#: pooled merge test joins a block's top 2-4 cm over a board to the board)
SMALL_SIDE = 3.0
#: ``small_scale``: a small plane standing over a neighbour is parallel to it within this many
#: degrees ...
SMALL_PARALLEL = 10.0
#: ... and offset from it along its normal by at least this many times the looser plane's RMS
#: (a 2 cm block top over a RealSense board of RMS 1.5 mm: 13)
SMALL_RAISE = 5.0
#: ``small_scale``: a small plane is kept only when its pixels fill at least this share of
#: their convex hull in the image (solid103): a box's top or side is a convex patch (the
#: small pass's planes on the labelled real blocks fill 0.86-0.97; on the generated piles,
#: where blocks hide parts of each other, 0.44 and up, 6 of 58 under 0.6), a strip along a
#: board's edge that joined three Kinect cubes into one object fills 0.17 (hunt67)
SMALL_SOLID = 0.6

#: ``noisy_wide`` (noisy101): the second growing's angle (degrees; a face six times as noisy as
#: the frame turns its normals this far even over the wider window)
NOISY_THETA = 25.0
#: ``noisy_wide``: a candidate has at least this many times the first growing's least region
#: size (a time-of-flight camera's dark load or carton face: large)
NOISY_SIZE = 4.0
#: ``noisy_wide``: a candidate fits within this many times its own patch noise (noise correlated
#: over 5 px makes a flat face's whole RMS about twice what 8 px patches measure: dev_pal's
#: loads 2.0-2.1)
NOISY_LOCAL = 2.5

#: ``raised_min`` (raised102): a raised component has at least this share of the first
#: growing's least region size (a 2.5 cm cube's top 1 m under a 1280 x 720 RealSense: 530 px
#: against 1 080)
RAISED_SIZE = 0.25
#: ``raised_min``: a raised pixel stands over the support by this many times the depth noise at
#: its depth too (a Kinect v1's 3 mm at 1 m)
RAISED_SIGMAS = 5.0
#: ``raised_min``: the highest a raised pixel stands over the support (m): a tower of blocks,
#: not a shelf or a person
RAISED_MAX = 0.3
#: ``raised_min``: the top band reaches this far (m; or 4 noise sigmas when more) under the
#: component's 90th percentile height (a RealSense top is a dome: its rim 3-9 mm under its
#: centre, session 101)
RAISED_BAND = 0.008
#: ``raised_min``: the top band holds at least this share of its component (a box seen from
#: above is mostly its top; a bottle's, a fruit's or a bowl's upper band is a cap or crescent
#: of a gently sloping surface: 0.13-0.46 on hunt90's table clutter)
RAISED_SHARE = 0.5
#: ``raised_min``: the band's plane is parallel to the support within this many degrees (the
#: domed tops measure 3-10 degrees off the board)
RAISED_PARALLEL = 15.0
#: ``raised_min``: the band's plane fits within this RMS (m; or 3 noise sigmas when more): the
#: domed tops fit at 1.4-2.7 mm
RAISED_RMS = 0.004
#: ``raised_min``: the ring (px, from, to) outside the top band whose depth must lie ...
RAISED_RING = (3, 6)
#: ... this share of the top's height or more under the band's edge (a box's top ends in a
#: drop: hunt67/90's cubes 0.51 or more; a sphere's cap runs on into its slope: a 3 cm cap
#: 1 m away 0.33)
RAISED_DROP = 0.4
#: ``raised_min``: the top band encloses under this share of its own pixels (a cup's rim
#: encloses its inside)
RAISED_HOLES = 0.04
#: ``raised_min``: the support is the largest plane level within this many degrees
RAISED_LEVEL = 10.0

#: ``near_wide``: a near candidate's fit (RMS over the measured noise) may be up to this many
#: times the median fit of the first growing's near planes, when that is looser than
#: ``far_rms`` (a rippled sensor's planes fit at several times the 5 px noise estimate)
NEAR_RMS = 1.5
#: Default ``wide_fallback`` (up66): the first growing planes under 15 % of the valid depth
#: only on hunt45's R200 frames (0-6 %), an upside-down OAK-D's pallet front (11 %) and a D4xx
#: office at 2-4 m (8 %) among the real development frames; every other one 21 % or more
WIDE_FALLBACK = 0.15


def _num(owner: str, name: str, value, *, lo=None, hi=None, lo_open=False, hi_open=False) -> float:
    if isinstance(value, bool):
        raise InputError(f"{owner}: {name} must be a number, got {value!r}")
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise InputError(f"{owner}: {name} must be a number, got {value!r}") from None
    if not math.isfinite(v):
        raise InputError(f"{owner}: {name} must be finite, got {value!r}")
    if lo is not None and (v < lo or (lo_open and v == lo)):
        raise InputError(f"{owner}: {name} must be {'>' if lo_open else '>='} {lo}, got {value!r}")
    if hi is not None and (v > hi or (hi_open and v == hi)):
        raise InputError(f"{owner}: {name} must be {'<' if hi_open else '<='} {hi}, got {value!r}")
    return v


def _int(owner: str, name: str, value, lo: int) -> int:
    if isinstance(value, float) and math.isfinite(value) and value.is_integer():
        value = int(value)
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)):
        raise InputError(f"{owner}: {name} must be an integer, got {value!r}")
    if value < lo:
        raise InputError(f"{owner}: {name} must be >= {lo}, got {value!r}")
    return int(value)


def _bool(owner: str, name: str, value) -> bool:
    """A true/false parameter (numpy bools too); anything else is an :class:`InputError`."""
    if not isinstance(value, (bool, np.bool_)):
        raise InputError(f"{owner}: {name} must be true or false, got {value!r}")
    return bool(value)


def _auto_or(owner, name, value, conv):
    if isinstance(value, str):
        if value == "auto":
            return "auto"
        raise InputError(f"{owner}: {name} must be 'auto' or a number, got {value!r}")
    return conv(value)


@dataclass(frozen=True)
class RegionGrowParams:
    """Parameters of region growing (the paper's Algorithm 1) and of its normals.

    Parameters
    ----------
    theta : float
        Angle threshold in degrees between a candidate's normal and the region's base normal
        (paper: 15).  Must lie in (0, 90).
    delta : float or "auto"
        Distance threshold in metres between grid neighbours.  ``"auto"`` (paper): ``delta_factor``
        times the mean, over valid points, of each point's distance to its nearest adjacent grid
        neighbour.
    delta_factor : float
        Factor of the automatic delta (planerel's choice, see docs/segmentation.md): 6.
    delta_mode : {"depth", "image"}
        ``"image"``: one automatic delta per image (the paper).  ``"depth"`` (default): the same
        mean, taken per depth band, and an edge uses the band of its farther point, because
        neighbour spacing and sensor noise grow with depth.
    min_neighbour_num : int
        A point joins a region only when at least this many of its 8 grid neighbours lie within
        delta (paper: 4).
    base_update_step : int
        After the first ``num_initial_points`` points, the base normal is refreshed every this
        many added points (paper: 8).
    num_initial_points : int
        The base normal is refreshed at every added point until the region has this many (16).
    angle_mf : float
        Angle modifying factor (< 1): 0.5.  Where it applies depends on ``angle_order``.
    angle_order : {"auto", "paper", "reversed"}
        ``"paper"`` (Algorithm 1, lines 16-21): a candidate joins with an angle below ``theta``
        while the region has fewer than ``num_initial_points`` points, below
        ``theta * angle_mf`` after.  ``"reversed"`` (planerel's variant): ``theta * angle_mf``
        first, ``theta`` after.  ``"auto"`` (default): ``"paper"`` when planerel's additions
        are off (``refine=False``, and in :func:`planerel.segment.segment` also
        ``split=False``), ``"reversed"`` otherwise.
    seed_test : bool or "auto"
        planerel's seed test (not in the paper): a seed's delta-neighbours must all have
        normals within ``theta * angle_mf`` of its own.  ``"auto"``: as ``angle_order``
        (off exactly when the paper's order is used).
    min_region_size : int or "auto"
        Smallest region kept, in points.  ``"auto"``: 90 at 160x120, proportional to the number
        of pixels (1440 at 640x480), times ``min_region_scale``.
    normal_smooth, normal_radius : int or "auto"
        Normal estimation (see :mod:`planerel.segment.normals`).
    jump_factor : float
        Depth-jump threshold of the normals in pixel sizes (see :mod:`planerel.segment.normals`).
    reference_depth : float, None or "auto"
        Depth (m) at which the normal window has its nominal size; it grows with depth
        (see :mod:`planerel.segment.normals`).  None = fixed window.  ``"auto"``: 2 m, or None when the
        adaptation finds uniform depth noise.
    refine : bool
        planerel's boundary completion after growing (not in the paper; see docs): unassigned
        pixels next to a region join the region whose fitted plane is nearest, within
        ``refine_factor`` times the region's RMS residual.
    refine_factor : float
        See ``refine``: 3.
    refine_rounds : int or "auto"
        Breadth-first rounds of the completion; ``"auto"`` = normal_smooth + normal_radius + 2.
    knn : int
        Neighbours per point for unorganized clouds (normals and the growing graph).
    min_region_scale : float
        Factor of the automatic ``min_region_size`` (1; the ``"structured-light"`` preset: 0.25).
    leftover_planes : bool
        planerel's leftover step after completion (with ``refine``; not in the paper): a
        connected patch of still unassigned pixels of at least ``min_region_size`` whose
        least-squares plane has an RMS residual within ``refine_factor`` x the median RMS of the
        grown regions becomes a region (thin faces whose normals are all blended with their
        neighbours', e.g. far stair treads 3-4 pixels high).
    adapt : bool
        Measure the cloud's depth-noise model (:mod:`planerel.segment.noise`) and set the
        ``"auto"`` values of ``min_region_size``, the normal window and ``reference_depth``
        from it (:mod:`planerel.segment.adapt`); the planar post-processing uses the measured
        model too.  False: the fixed defaults (the ``kinect`` preset).
    wide_noise_window : bool
        Off by default (noise58, a trial: docs/segmentation.md "Correlated depth noise").  With
        ``adapt``, also measure the noise over 15 x 15 px patches (which sees noise correlated
        over a few pixels, as a stereo sensor's, that the 5 px patches miss) and widen an
        ``"auto"`` normal window, for every noise kind, to the uniform-noise rule's
        ``round(sqrt(12) p)`` (at most ``MAX_WINDOW``) of that estimate when it exceeds the
        window chosen otherwise.
    wide_fallback : float
        :data:`WIDE_FALLBACK` (0.15) by default since up66 (0 = off; srob59 made it, off:
        docs/segmentation.md "A wide window where the narrow one fails" and "The widest window
        where an R200's speckle leaves no patch to measure").  With ``adapt`` and
        post-processing, a segmentation that leaves more than ``1 - wide_fallback`` of the
        valid pixels in no plane (correlated depth noise the 5 px estimate misses makes most
        normals noise) is done again with ``wide_noise_window``, or, where the 15 px estimate
        gives no wider window (an R200's speckle leaves no 15 px patch), with the widest
        adaptive window ``MAX_WINDOW``; the one assigning more pixels is kept
        (``info["wide_fallback"]``: both shares).  Frames the narrow window segments are
        unchanged.
    far_theta : float
        30 degrees by default (lead61; 0 switches it off; added in step60: docs/objects.md
        "Why the step test fails a real flight"; docs/segmentation.md "Far planes").
        With ``adapt`` and post-processing, the cloud is grown again with this angle (degrees) and each
        region of that second growing lying for at least :data:`FAR_SHARE` of its pixels in
        depth the first left in no plane beyond ``far_depth`` becomes a plane there (steps at
        2-4 m under a stereo pair's correlated noise), when its least-squares plane's RMS is
        at most ``far_rms`` times the measured depth noise at its centroid's depth (a wide
        angle also joins curved and cluttered surfaces, which no plane fits at the noise).
        Nothing already in a plane changes.  ``info["far_planes"]``: the planes added;
        ``info["far_fit"]``: every candidate's RMS over the noise.
    far_depth : float
        Metres (1.5); see ``far_theta``.
    far_rms : float
        See ``far_theta`` (2.5, measured: docs/segmentation.md "Far planes").
    far_local : float
        2 (tof72; 0 switches it off), or a factor in [1, 10] (docs/segmentation.md "Dark
        surfaces of a time-of-flight camera").  A far candidate that fails ``far_rms`` is still a plane when
        its RMS is at most this many times its own noise, the median RMS of plane fits to its
        small patches (:func:`planerel.segment.patch_noise.patch_noise`), and that noise is
        above ``far_rms`` times the frame's measured noise (a frame that measured none keeps
        nothing this way) and at most :data:`FAR_LOCAL_NOISE` per metre of depth: flat at its
        own scale as at the patches', only noisier than the frame (a Kinect v2's dark risers).
        ``info["far_local"]``: the planes it added.
    far_wide : bool
        Off.  The second growing of ``far_theta`` (or, with ``far_theta`` 0, at ``theta``)
        uses ``wide_noise_window``'s 15 px normal window.
    small_scale : float
        0 (off) or a factor in (0, 1]; 0.35, with ``small_pitch`` 60, by default (small99:
        block tops seen from above; 0 before).  With ``adapt`` and post-processing, the cloud is grown
        again with a minimum region size of ``small_scale`` times the first growing's (its
        merges with the side test, at least :data:`SMALL_SIDE`), and each region of that growing
        lying for at least :data:`SMALL_SHARE` of its pixels in depth the first growing left in
        no plane nearer than ``far_depth`` becomes a plane there when its least-squares plane's
        RMS is within the near pass's bound (``far_rms`` noise sigmas, or
        :data:`NEAR_RMS` times the median fit of the first growing's near planes when looser;
        a frame that measured no noise is judged by the split test's sensor model) and it
        stands over a plane near it: parallel within :data:`SMALL_PARALLEL` degrees, offset by
        :data:`SMALL_RAISE` times the looser RMS (a small box's top seen from above, hunt67).
        Nothing already in a plane changes.  ``info["small_planes"]``: the planes added.
    small_corners : bool
        Off.  With ``small_scale``, also keep a small plane meeting another at a corner
        (touching a plane 60-120 degrees off its own: a small box's side face, small64); on the
        real development frames it took slivers of box tops seen nearly edge-on, which cost
        boxes their one-face rule (docs/segmentation.md).
    small_pitch : float
        60 (the default) or other degrees in (0, 90], or 0 (the small pass on every frame).
        With ``small_scale``, the small pass runs only on a frame whose camera looks down at
        least this steeply (the pitch of :func:`planerel.segment.segment`'s ``up``: a table, a
        bin or a tote seen from above, where block tops lie; small99, docs/segmentation.md
        "The small pass for views from above"); a call with no ``up`` runs no small pass
        unless this is 0.  ``info["view_pitch"]``: the pitch read.
    near_wide : float
        0 (off) or a factor in (1, 4] (near65, docs/segmentation.md "A wider normal window
        where near depth is left in no plane").  With ``adapt`` and post-processing, the cloud
        is grown again with the normal window (smooth and radius) this many times the first
        growing's, and each region of that growing lying for at least :data:`FAR_SHARE` of its
        pixels, and the first's minimum region size, in depth the first left in no plane nearer
        than ``far_depth`` becomes a plane there (a RealSense box's top whose ripples the
        first window follows), when its least-squares plane's RMS is at most ``far_rms`` times
        the measured depth noise, or :data:`NEAR_RMS` times the median of that ratio over the
        first growing's near planes when that is looser.  Nothing already in a plane changes.
        ``info["near_planes"]``: the planes added.
    raised_min : float
        0.012 m (raised102, on), 0 (off) or a height in (0, 0.1] m.  With ``small_scale`` and
        its ``small_pitch`` (a view from above), the depth the growings left in no plane
        nearer than ``far_depth`` and standing over the largest level plane (within
        :data:`RAISED_LEVEL` degrees of ``up``) by this much or more (and
        :data:`RAISED_SIGMAS` noise sigmas, at most :data:`RAISED_MAX`) falls into connected
        components of :data:`RAISED_SIZE` times the first growing's least region size or
        more; each component's top band (within :data:`RAISED_BAND` of its 90th percentile
        height), holding :data:`RAISED_SHARE` of it or more, fitting a plane within
        :data:`RAISED_RMS` and parallel to the support within :data:`RAISED_PARALLEL`
        degrees, ending in a drop (:data:`RAISED_DROP` of its height within
        :data:`RAISED_RING` px), no planed top's rim and enclosing under :data:`RAISED_HOLES`
        of itself as holes, becomes a plane: a block's top the sensor smoothed into a dome, whose
        normals turn through its rim so that no growing keeps it whole (docs/segmentation.md
        "Raised tops").  Nothing already in a plane changes.  ``info["raised_planes"]``: the
        planes added.
    noisy_wide : float
        4 (noisy101, on), 0 (off) or a factor in (1, 8].  With ``adapt`` and
        post-processing, where the first growing left :data:`NOISY_SIZE` times its minimum
        region size or more in no plane (at any depth), the cloud is grown again with the
        normal window this many times the first's and an angle of :data:`NOISY_THETA`, and each
        region of that growing lying for at least :data:`FAR_SHARE` of its pixels, and
        :data:`NOISY_SIZE` times the first's minimum region size, in that depth becomes a plane
        when it is noisier than the frame -- its RMS over ``far_rms`` times the measured noise
        (or the near pass's looser bound), so the first growing would have planed it were it
        not -- yet flat at its own scale: within :data:`NOISY_LOCAL` times its own patch noise,
        which lies over that bound and under :data:`FAR_LOCAL_NOISE` per metre of depth
        (``far_local``'s test).  A time-of-flight camera's dark faces (a wrapped pallet load, a
        carton: six times the frame's noise, a quarter of their pixels holes) grow no plane at
        the frame's window (docs/segmentation.md "Noisy faces grown at their own noise").
        Nothing already in a plane changes.  ``info["noisy_planes"]``: the planes added.
    """

    theta: float = 15.0
    delta: float | str = "auto"
    delta_factor: float = 6.0
    delta_mode: str = "depth"
    min_neighbour_num: int = 4
    base_update_step: int = 8
    num_initial_points: int = 16
    angle_mf: float = 0.5
    min_region_size: int | str = "auto"
    normal_smooth: int | str = "auto"
    normal_radius: int | str = "auto"
    jump_factor: float = 12.0
    reference_depth: float | None | str = "auto"
    refine: bool = True
    refine_factor: float = 3.0
    refine_rounds: int | str = "auto"
    knn: int = 16
    min_region_scale: float = 1.0
    leftover_planes: bool = True
    adapt: bool = True
    wide_noise_window: bool = False
    wide_fallback: float = WIDE_FALLBACK
    far_theta: float = 30.0
    far_depth: float = 1.5
    far_rms: float = 2.5
    far_wide: bool = False
    far_local: float = 2.0
    small_scale: float = 0.35
    small_corners: bool = False
    small_pitch: float = 60.0
    near_wide: float = 0.0
    noisy_wide: float = 4.0
    raised_min: float = 0.012
    angle_order: str = "auto"
    seed_test: bool | str = "auto"

    def __post_init__(self) -> None:
        o = "regiongrow"
        s = object.__setattr__
        s(self, "theta", _num(o, "theta (degrees)", self.theta, lo=0, hi=90, lo_open=True, hi_open=True))
        s(self, "delta", _auto_or(o, "delta", self.delta,
                                  lambda v: _num(o, "delta", v, lo=0, lo_open=True)))
        s(self, "delta_factor", _num(o, "delta_factor", self.delta_factor, lo=0, lo_open=True))
        if self.delta_mode not in ("depth", "image"):
            raise InputError(f"{o}: delta_mode must be 'depth' or 'image', got {self.delta_mode!r}")
        s(self, "min_neighbour_num", _int(o, "min_neighbour_num", self.min_neighbour_num, 0))
        if self.min_neighbour_num > 8:
            raise InputError(f"{o}: min_neighbour_num must be <= 8 (the grid has 8 neighbours), "
                             f"got {self.min_neighbour_num}")
        s(self, "base_update_step", _int(o, "base_update_step", self.base_update_step, 1))
        s(self, "num_initial_points", _int(o, "num_initial_points", self.num_initial_points, 1))
        s(self, "angle_mf", _num(o, "angle_mf", self.angle_mf, lo=0, hi=1, lo_open=True))
        s(self, "min_region_size", _auto_or(o, "min_region_size", self.min_region_size,
                                            lambda v: _int(o, "min_region_size", v, 1)))
        s(self, "normal_smooth", _auto_or(o, "normal_smooth", self.normal_smooth,
                                          lambda v: _int(o, "normal_smooth", v, 0)))
        s(self, "normal_radius", _auto_or(o, "normal_radius", self.normal_radius,
                                          lambda v: _int(o, "normal_radius", v, 1)))
        s(self, "jump_factor", _num(o, "jump_factor", self.jump_factor, lo=0, lo_open=True))
        if self.reference_depth == "auto":
            pass
        elif self.reference_depth is not None and self.reference_depth != "none":
            s(self, "reference_depth", _num(o, "reference_depth", self.reference_depth, lo=0,
                                            lo_open=True))
        else:
            s(self, "reference_depth", None)
        s(self, "refine", _bool(o, "refine", self.refine))
        s(self, "refine_factor", _num(o, "refine_factor", self.refine_factor, lo=0, lo_open=True))
        s(self, "refine_rounds", _auto_or(o, "refine_rounds", self.refine_rounds,
                                          lambda v: _int(o, "refine_rounds", v, 0)))
        s(self, "knn", _int(o, "knn", self.knn, 3))
        s(self, "leftover_planes", _bool(o, "leftover_planes", self.leftover_planes))
        s(self, "adapt", _bool(o, "adapt", self.adapt))
        s(self, "wide_noise_window", _bool(o, "wide_noise_window", self.wide_noise_window))
        s(self, "wide_fallback", _num(o, "wide_fallback", self.wide_fallback, lo=0, hi=1))
        s(self, "far_theta", _num(o, "far_theta (degrees)", self.far_theta, lo=0, hi=90,
                                  hi_open=True))
        s(self, "far_depth", _num(o, "far_depth", self.far_depth, lo=0))
        s(self, "far_rms", _num(o, "far_rms", self.far_rms, lo=0, lo_open=True))
        s(self, "far_wide", _bool(o, "far_wide", self.far_wide))
        s(self, "far_local", _num(o, "far_local", self.far_local, lo=0, hi=10))
        if 0 < self.far_local < 1:
            raise InputError(f"{o}: far_local must be 0 (off) or a factor in [1, 10], "
                             f"got {self.far_local!r}")
        s(self, "small_scale", _num(o, "small_scale", self.small_scale, lo=0, hi=1))
        s(self, "small_corners", _bool(o, "small_corners", self.small_corners))
        s(self, "small_pitch", _num(o, "small_pitch (degrees)", self.small_pitch, lo=0, hi=90))
        s(self, "near_wide", _num(o, "near_wide", self.near_wide, lo=0, hi=4))
        if 0 < self.near_wide <= 1:
            raise InputError(f"{o}: near_wide must be 0 (off) or a factor in (1, 4], "
                             f"got {self.near_wide!r}")
        s(self, "noisy_wide", _num(o, "noisy_wide", self.noisy_wide, lo=0, hi=8))
        if 0 < self.noisy_wide <= 1:
            raise InputError(f"{o}: noisy_wide must be 0 (off) or a factor in (1, 8], "
                             f"got {self.noisy_wide!r}")
        s(self, "raised_min", _num(o, "raised_min (m)", self.raised_min, lo=0, hi=0.1))
        s(self, "min_region_scale", _num(o, "min_region_scale", self.min_region_scale, lo=0,
                                         lo_open=True))
        if self.angle_order not in ("auto", "paper", "reversed"):
            raise InputError(f"{o}: angle_order must be 'auto', 'paper' or 'reversed', "
                             f"got {self.angle_order!r}")
        if self.seed_test != "auto":
            s(self, "seed_test", _bool(o, "seed_test", self.seed_test))

    def growing_variant(self, split: bool = False) -> tuple[str, bool]:
        """``(angle_order, seed_test)`` with ``"auto"`` resolved: the paper's rules
        (``("paper", False)``) when ``refine`` and ``split`` are both off, planerel's
        (``("reversed", True)``) otherwise."""
        paper = not self.refine and not split
        order = self.angle_order if self.angle_order != "auto" else (
            "paper" if paper else "reversed")
        seed = self.seed_test if self.seed_test != "auto" else (order == "reversed")
        return order, bool(seed)


@dataclass(frozen=True)
class RansacParams:
    """Parameters of the RANSAC baselines SP (plane) and SNP (plane with normals).

    Parameters
    ----------
    threshold : float
        Inlier distance in metres (paper: SP 0.005 / 0.01 / 0.03 / 0.05, SNP 0.01 / 0.03 / 0.05).
    normal_weight : float
        SNP only: weight ``w`` of the normal term; a point's distance to a plane is
        ``w * angle(normal, plane normal) + (1 - w) * |point-plane distance|`` (paper: 0.1).
    max_iterations : int
        Hypotheses per extracted plane at most (1000, PCL's common setting).
    probability : float
        Stop drawing hypotheses once a plane at least as good would have been drawn with this
        probability (0.99, PCL's default).
    min_region_size : int or "auto"
        Extraction stops when fewer points remain or the best plane has fewer inliers.
    max_planes : int
        Extraction stops after this many planes (100).
    score_sample : int
        Hypotheses are scored on a seeded random sample of this many remaining points; the best
        is then evaluated on all of them (20000).
    seed : int
        Seed of the random generator: same input, same seed, same planes.
    knn : int
        Neighbours per point for normals of unorganized clouds (SNP).
    """

    threshold: float = 0.01
    normal_weight: float = 0.1
    max_iterations: int = 1000
    probability: float = 0.99
    min_region_size: int | str = "auto"
    max_planes: int = 100
    score_sample: int = 20000
    seed: int = 0
    knn: int = 16
    normal_smooth: int | str = "auto"
    normal_radius: int | str = "auto"
    jump_factor: float = 12.0

    def __post_init__(self) -> None:
        o = "ransac"
        s = object.__setattr__
        s(self, "threshold", _num(o, "threshold", self.threshold, lo=0, lo_open=True))
        s(self, "normal_weight", _num(o, "normal_weight", self.normal_weight, lo=0, hi=1))
        s(self, "max_iterations", _int(o, "max_iterations", self.max_iterations, 1))
        s(self, "probability", _num(o, "probability", self.probability, lo=0, hi=1,
                                    lo_open=True, hi_open=True))
        s(self, "min_region_size", _auto_or(o, "min_region_size", self.min_region_size,
                                            lambda v: _int(o, "min_region_size", v, 1)))
        s(self, "max_planes", _int(o, "max_planes", self.max_planes, 1))
        s(self, "score_sample", _int(o, "score_sample", self.score_sample, 3))
        s(self, "seed", _int(o, "seed", self.seed, 0))
        s(self, "knn", _int(o, "knn", self.knn, 3))
        s(self, "normal_smooth", _auto_or(o, "normal_smooth", self.normal_smooth,
                                          lambda v: _int(o, "normal_smooth", v, 0)))
        s(self, "normal_radius", _auto_or(o, "normal_radius", self.normal_radius,
                                          lambda v: _int(o, "normal_radius", v, 1)))
        s(self, "jump_factor", _num(o, "jump_factor", self.jump_factor, lo=0, lo_open=True))


def coerce_params(cls, params: dict):
    """Build ``cls`` from keyword parameters, naming unknown ones in the user's words
    (:func:`planerel.parameters.unknown_parameters`); strings from the command line ("15",
    "auto", "true") become numbers / booleans."""
    names = {f.name for f in fields(cls)}
    unknown = sorted(set(params) - names)
    if unknown:
        from planerel.parameters import section_of, unknown_parameters

        section = section_of(cls)
        if section is None:  # a class no --param section holds: name it
            raise InputError(f"unknown parameter(s) {', '.join(unknown)} for {cls.__name__}")
        raise unknown_parameters(section, unknown)
    # fields whose values are words (delta_mode, angle_order) keep them
    words = {f.name for f in fields(cls) if isinstance(f.default, str) and f.default != "auto"
             or f.name == "angle_order"}
    out = {}
    for k, v in params.items():
        if isinstance(v, str) and k in words:
            v = v.strip().lower()
        elif isinstance(v, str) and v != "auto":
            low = v.strip().lower()
            if low in ("none", "null"):
                v = None
            elif low in ("true", "yes", "on"):
                v = True
            elif low in ("false", "no", "off"):
                v = False
            else:
                try:
                    v = int(low)
                except ValueError:
                    try:
                        v = float(low)
                    except ValueError:
                        raise InputError(f"parameter {k} must be a number, 'auto' or true/false; "
                                         f"got {v!r}") from None
        out[k] = v
    return cls(**out)
