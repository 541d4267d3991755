"""Scenes to Prolog facts: the relational description an ILP system learns from.

:func:`describe_scene` measures the planes of one scene (:mod:`planerel.features.planes`), relates them
(:mod:`planerel.features.relations`) and groups them into objects (ground truth when given, else
proposals); :func:`facts_text` writes any number of described scenes as one Prolog text with
every fact of a predicate together, predicates in the fixed order of :data:`PREDICATES`, scenes
in the order given, planes by label, pairs by ``(p, q)``: the same input gives the same bytes.
The vocabulary, with types, units and Aleph modes, is in ``docs/predicates.md``.

Ids: scene ``s0007``; plane ``s0007_p03`` (its label, two digits or more); object ``s0007_o1``
(objects numbered from 1 in order).  Any scene id is allowed; ids that are not plain Prolog
atoms are quoted by :mod:`planerel.features.terms`.

Described pairs: every ordered pair of planes within one object, and every ordered pair of
adjacent planes anywhere in the scene (``FactParams.pairs`` selects other sets).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field, replace
from pathlib import Path

import numpy as np

from planerel.errors import InputError, check_bools
from planerel.features import terms
from planerel.features._defaults import defaults
from planerel.features.curved import CurvedParams
from planerel.features.lying import lying_tops
from planerel.features.plan_overlap import over_pairs
from planerel.features.planes import label_max
from planerel.features.proposal_params import ProposalParams
from planerel.features.proposals import propose_objects, support_planes
from planerel.features.raised import RaisedParams, join_raised, raised_clusters, with_raised
from planerel.features.relations import relate, skirts_within_objects
from planerel.features.solid import inclined_beside, top_slopes
from planerel.features.stair_step import stair_steps
from planerel.features.stairfit import StairFitParams, _remeasure_stepped_clusters, join_groups
from planerel.features.stepped import remeasure_stepped
from planerel.features.tables import leg_objects, table_objects
from planerel.features.tall_face import tall_faces

__all__ = [
    "PREDICATES",
    "FactParams",
    "SceneObject",
    "SceneDescription",
    "describe_scene",
    "oblique_share",
    "scene_facts",
    "truncated_planes",
    "facts_text",
    "write_facts",
    "FactsWriter",
    "up_comment",
    "DIGITS_M",
    "DIGITS_DEG",
    "DIGITS_INCLINE",
]

#: Decimal places written for metres and square metres (0.1 mm) and for degrees.
DIGITS_M = 4
DIGITS_DEG = 2
#: Decimal places written for a plane's ``incline`` and ``slope`` (its angle to gravity): whole
#: degrees.  The up vector is estimated (docs/gravity.md: p95 0.15 degrees, up to 2) and a small
#: plane's own fit tilts it by up to a few degrees, so decimals of a degree there are the fit's
#: noise, not the object's shape; written with them, the learner placed cut-offs among them
#: ("a facing wall of incline at most 89.8": vertical walls at 90.0 left out; docs/results.md,
#: cut16).  ``angle`` (between two planes, not against gravity) keeps ``DIGITS_DEG``.
DIGITS_INCLINE = 0

#: The vocabulary, in the order facts are written: (name, arity, argument types, meaning).
PREDICATES: tuple[tuple[str, int, str, str], ...] = (
    ("scene", 1, "scene", "a scene"),
    ("scene_plane", 2, "scene, plane", "the plane belongs to the scene"),
    ("floor", 2, "scene, plane", "the scene's floor plane"),
    ("up", 2, "scene, [x, y, z]", "gravity up in the camera frame (unit vector)"),
    ("object", 2, "scene, obj", "an object (ground truth or proposal) of the scene"),
    ("has_plane", 2, "obj, plane", "the plane belongs to the object"),
    ("support", 1, "plane", "a support plane (floor, floor-level plane, large wall)"),
    ("nplanes", 2, "obj, int", "number of planes of the object"),
    ("nhorizontal", 2, "obj, int", "number of horizontal planes of the object"),
    ("nvertical", 2, "obj, int", "number of vertical planes of the object"),
    ("ninclined", 2, "obj, int", "number of inclined planes of the object"),
    ("planar_fraction", 2, "obj, 0..1", "fraction of the object's points in flat planes (planerel.features.curved)"),
    ("curved", 1, "obj", "planar fraction below curved_below: a round object (planerel.features.curved)"),
    ("oblique_share", 2, "obj, 0..1", "share of the object's area in planes that meet a larger "
     "plane of the object at an oblique angle (curved or faceted surfaces)"),
    ("orientation", 2, "plane, horizontal|vertical|inclined", "orientation class"),
    ("incline", 2, "plane, deg", "angle between plane and horizontal, 0..90"),
    ("slope", 2, "plane, deg", "incline of an inclined plane (neither horizontal nor vertical); "
     "no fact for the others"),
    ("area", 2, "plane, m2", "convex-hull area"),
    ("plane_length", 2, "plane, m", "long side of the hull's minimum rotated rectangle (of the "
     "part in view: a lower bound when the plane is not seen whole)"),
    ("plane_width", 2, "plane, m", "short side of that rectangle (likewise)"),
    ("seen_length", 2, "plane, m", "plane_length of a plane seen whole: not cut by the image "
     "border, not partly hidden by a nearer surface (truncated_planes)"),
    ("seen_width", 2, "plane, m", "plane_width of a plane seen whole"),
    ("tall_face", 1, "plane", "a vertical rectangle standing on the ground (the floor or a table "
     "at its foot), nothing beside it taller, its top at or above the sensor's eye level or "
     "out of view: a box seen so shows no top (planerel.features.tall_face.tall_faces)"),
    ("lying", 1, "plane", "a level or tilted (<= 30 deg) plane at most 0.6 m long lying on a "
     "larger horizontal plane adjacent to it, 1.5-12 cm over it: the top of a book or a flat "
     "box lying on a table, its sides edge-on (planerel.features.lying.lying_tops)"),
    ("top_slope", 2, "plane, deg", "slope from level of an upright plane's top edge where the "
     "camera sees it straight over 0.5 m or more, the plane lying under it (at most 2 times "
     "as high as the edge's rise): a ramp's side face seen from lower than its top rises "
     "with the ramp (planerel.features.solid.top_slopes)"),
    ("height", 2, "plane, m", "centroid height above the floor / lowest support"),
    ("distance", 2, "plane, m", "distance from the sensor to the centroid"),
    ("npoints", 2, "plane, int", "number of points"),
    ("rms", 2, "plane, m", "RMS point-to-plane residual"),
    ("plane_model", 3, "plane, [x, y, z], [nx, ny, nz]", "centroid (m) and unit normal towards the sensor"),
    ("hull", 2, "plane, [[x, y, z], ...]", "3-D convex-hull vertices (m), counter-clockwise seen from the sensor"),
    ("angle", 3, "plane, plane, deg", "angle between the planes, 0..90"),
    ("parallel", 2, "plane, plane", "angle within the parallel tolerance"),
    ("perpendicular", 2, "plane, plane", "angle within the perpendicular tolerance of 90"),
    ("adjacent", 2, "plane, plane", "touch in the image grid or hulls within the adjacency gap"),
    ("gap", 3, "plane, plane, m", "closest distance between the 3-D hulls"),
    ("rise", 3, "plane, plane, m", "how far the second centroid is above the first"),
    ("above", 2, "plane, plane", "first centroid above the second by more than the tolerance"),
    ("over", 2, "plane, plane", "both horizontal, the first above the second, their footprints "
     "seen from above overlapping by at least half the larger one: a shelf's boards, not a "
     "flight's treads (planerel.features.plan_overlap)"),
    ("skirt", 2, "plane, plane", "the second (vertical) hangs below the first (horizontal) as a "
     "box's side below its top (planerel.features.solid)"),
    ("corner", 2, "plane, plane", "vertical walls of one solid meeting at a right angle, "
     "tops level (planerel.features.solid)"),
    ("face_pair", 2, "plane, plane", "vertical walls of one solid meeting at an outside corner "
     "(>= 85 deg), tops level and bottoms level, narrow walls allowed (2 cm): a box seen level "
     "as two faces (planerel.features.solid.is_face_pair)"),
    ("stair_step", 2, "plane, plane", "two parallel treads or risers of one object, the second "
     "one stair step (0.08-0.25 m) above and (0.15-0.45 m) beyond the first, overlapping across "
     "(planerel.features.stair_step.stair_steps)"),
    ("facing", 2, "plane, plane", "parallel vertical walls, not adjacent, tops level, "
     "overlapping along the walls: the two sides of one solid or open box (planerel.features.solid)"),
    ("in_front_of", 2, "plane, plane", "first nearer the sensor along the horizontal view direction"),
)
_ARITY = {name: arity for name, arity, _, _ in PREDICATES}
_PLANNER = ("plane_model", "hull")
_PAIRS = ("object+adjacent", "object", "adjacent", "all", "none")


@dataclass(frozen=True)
class FactParams:
    """What :func:`scene_facts` writes.

    Parameters
    ----------
    pairs : str
        Described pairs: ``"object+adjacent"`` (default: all pairs within an object and the
        adjacent pairs of the scene), ``"object"``, ``"adjacent"``, ``"all"``, ``"none"``.
    planner : bool
        Write ``plane_model/3`` and ``hull/2`` (for robot planners, not for the learner).
    planes : str
        ``"all"`` planes of the scene, or only the planes of ``"objects"``.
    """

    pairs: str = "object+adjacent"
    planner: bool = True
    planes: str = "all"

    def __post_init__(self) -> None:
        if self.pairs not in _PAIRS:
            raise InputError(f"pairs must be one of {', '.join(_PAIRS)}; got {self.pairs!r}")
        if self.planes not in ("all", "objects"):
            raise InputError(f"planes must be 'all' or 'objects', got {self.planes!r}")
        check_bools(self)


@dataclass(frozen=True)
class SceneObject:
    """An object of a scene: its id, its plane labels, and its class when known.

    ``mask`` holds the pixels no flat plane explains that belong to the object (``(H, W)``
    bool, or None), ``planar_fraction`` the fraction of its points in flat planes and
    ``curved`` whether that is below the threshold (:mod:`planerel.features.curved`; None: not measured).
    """

    id: str
    planes: tuple
    klass: str | None = None
    mask: object = field(default=None, compare=False, repr=False)
    planar_fraction: float | None = None
    curved: bool | None = None

    def __post_init__(self) -> None:
        if not isinstance(self.id, str) or not self.id:
            raise InputError(f"an object id must be a non-empty string, got {self.id!r}")
        object.__setattr__(self, "planes", tuple(int(p) for p in self.planes))


@dataclass(frozen=True, eq=False)
class SceneDescription:
    """One described scene: planes, relations, objects."""

    scene_id: str
    planes: object  # PlaneSet
    relations: object  # Relations
    objects: tuple
    source: str | None = None
    proposed: bool = True
    support: tuple = field(default=())
    #: Ground-truth objects that are no example: ``(object id or None when no plane of it
    #: was found, class, reason)`` (:func:`planerel.features.dataset.describe_truth_scene`).
    excluded: tuple = field(default=())
    #: Labels of the planes not seen whole (:func:`truncated_planes`): their outline meets the
    #: image border or a nearer surface hides part of them, so their extent is a lower bound
    #: and ``seen_length`` / ``seen_width`` are not written for them.
    truncated: frozenset = field(default=frozenset())
    #: Labels of the vertical planes standing on the ground with their top out of sight
    #: (:func:`planerel.features.tall_face.tall_faces`: ``tall_face/1``).
    tall: frozenset = field(default=frozenset())
    #: Labels of the planes lying on a larger horizontal plane as a flat thing's top
    #: (:func:`planerel.features.lying.lying_tops`: ``lying/1``).
    lying: frozenset = field(default=frozenset())
    #: ``(lower, higher)`` labels of two planes of one object one stair step apart
    #: (:func:`planerel.features.stair_step.stair_steps`: ``stair_step/2``).
    steps: frozenset = field(default=frozenset())
    #: ``((label, degrees), ...)`` of the upright planes whose exposed top edge is seen straight
    #: over half a metre or more, and its slope from level
    #: (:func:`planerel.features.solid.top_slopes`: ``top_slope/2``, ramp77).
    top_slope: tuple = field(default=())
    #: Labels of the planes found only by the far growing of the segmentation
    #: (``far_theta``; :func:`planerel.segment.segment`'s ``info["far_labels"]``), when the
    #: caller gives them (:func:`describe_scene`'s ``far``): the far gate's provenance.
    far: frozenset = field(default=frozenset())

    @property
    def labels(self):
        """``(H, W)`` int32 label image the planes refer to: the one given, with invalid points
        unassigned, the levels of split stepped planes (:mod:`planerel.features.stepped`)
        labelled apart and, when proposing, the treads and risers fitted to unassigned flights
        (:mod:`planerel.features.stairfit`)."""
        return self.planes.labels

    def plane_id(self, label: int) -> str:
        """``s0007_p03`` for label 3."""
        return terms.plane_id(self.scene_id, label)


def describe_scene(cloud, labels, *, scene_id: str = "s0000", up=None, objects=None,
                   klass: str | None = None, plane_params=None, relation_params=None,
                   proposal_params=None, gravity_params=None,
                   curved_params=None, far=(), camera_height=None,
                   top_slope: bool = False) -> SceneDescription:
    """Measure, relate and group the planes of one scene.

    Parameters
    ----------
    cloud : Cloud
        Organized cloud ``(H, W, 3)``.
    labels : ndarray, shape (H, W), int
        Plane labels (ground truth or segmentation), -1 unassigned.  A plane whose points lie
        on tread-like levels is split into one plane a level unless
        ``proposal_params.split_stepped`` is False (:func:`planerel.features.stepped.split_stepped`;
        the result's ``labels`` is the label image after that; the levels of a plane in a given
        object join that object).
    scene_id : str
        Scene id (``s0007``); plane and object ids derive from it.
    up : 3 numbers, optional
        Gravity up; default the cloud's sidecar value, else estimated.
    objects : sequence of sequences of int, optional
        Plane labels per object (e.g. from :func:`planerel.features.proposals.objects_from_truth`);
        default: :func:`planerel.features.proposals.propose_objects`.  Labels without a measured plane
        are dropped; objects left empty are dropped.
    klass : str, optional
        Class of the objects (for training data: the scene's class).
    plane_params, relation_params, proposal_params, gravity_params, curved_params : optional
        :class:`~planerel.features.planes.PlaneParams`, :class:`~planerel.features.relations.RelationParams`,
        :class:`~planerel.features.proposal_params.ProposalParams`, :class:`~planerel.features.gravity.GravityParams`,
        :class:`~planerel.features.curved.CurvedParams` (defaults when None; a model's are in its
        ``model.json``).  Proposals also take the clusters of points no flat plane explains
        (:func:`planerel.features.curved.curved_objects`); every object gets its planar fraction.
    far : iterable of int, optional
        Labels of ``labels``' planes that only the segmentation's far growing found
        (``far_theta``; :func:`planerel.segment.segment`'s ``info["far_labels"]``).  The up
        estimate reads the labels without them (a low camera's far floor and walls grown at the
        wide angle are pieces too small and bent to vote for gravity, lead61), and the
        description's ``far`` holds the planes lying for half their pixels or more in them
        (the far gate's provenance).
    top_slope : bool
        Measure the top edges of the objects' upright planes (``top_slope/2``, ramp77; about
        1 ms a frame): asked by a data set with side-face examples
        (:func:`planerel.features.dataset.describe_truth_scene`), a model whose rules use
        it (:class:`planerel.classify.Classifier`) and ``planerel describe --top-slope``;
        otherwise no ``top_slope`` fact is written.
    camera_height : float, optional
        The camera's height over the floor, metres, when known (a robot's mount; give ``up``
        too when the camera is level or its tilt is known): with no floor plane in view, an
        upright face whose foot stands that far under the eye is grounded
        (:attr:`~planerel.features.planes.PlaneSet.camera_height`).  Default: not known.

    Returns
    -------
    SceneDescription
    """
    # (curved_objects, join_parts and open_wall_objects looked up in their modules at each
    # call, as measure_planes is in measured_planes, the rest imported with this module:
    # benchmarks/ab_describe.py times measure_planes there, tests stand in for the other three)
    from planerel.features.curved import curved_objects

    if not isinstance(scene_id, str) or not scene_id:
        raise InputError(f"a scene id must be a non-empty string, got {scene_id!r}")

    # the defaults made once (each construction validates every field)
    pp = proposal_params or defaults(ProposalParams)
    cp = curved_params or defaults(CurvedParams)
    far = sorted({int(v) for v in far})
    far_mask = np.isin(np.asarray(labels), far) if far else None
    planes, parent = measured_planes(cloud, labels, up, plane_params, gravity_params, pp,
                                     far_mask=far_mask, camera_height=camera_height)
    flights = []
    pixels = None  # the stairfit stage's unexplained pixels, when curved can open from them
    if objects is None and cp.stepped_clusters:
        # a far flight the region grower left unassigned: its treads and risers from the
        # stepped profile of its points
        before = planes
        planes, flights, pixels = _remeasure_stepped_clusters(cloud, planes, plane_params)
        if (planes is not before or parent or defaults(StairFitParams).tiny_area != cp.tiny_area
                or not cp.enabled):
            pixels = None
    # the face profiles the skirt tests measure, asked again by the curved stage's flat faces
    profiles: dict = {}
    rel = relate(planes, cloud, relation_params, profiles)
    # the planes cut by the border or hidden in part (their outline pixels and the points
    # around them): here, right after the relations' grid touch test read the same pixels'
    # neighbourhoods (0.17-0.18 ms a frame on the real frames against 0.24-0.26 at the end)
    cut = truncated_planes(planes.labels, np.asarray(cloud.xyz, float))
    # the vertical planes standing on the ground with their top out of sight (their profiles
    # mostly measured by the skirt tests against the floor or the table they stand on)
    tall = tall_faces(planes, rel, cloud, profiles, gravity_params)
    support = tuple(support_planes(planes, pp, rel, cloud))
    # the tops of flat things lying on a table or the floor, their sides edge-on
    lying = lying_tops(planes, rel, support, cloud)
    known = {p.label for p in planes}
    if objects is None:
        groups = propose_objects(planes, rel, pp, cloud, support)
        if flights:
            groups = join_groups(groups, [f - set(support) for f in flights])
        proposed = True
    else:
        groups = []
        for g in objects:
            g = {int(x) for x in g}
            g |= {k for k, v in parent.items() if v in g}  # the levels of a split plane
            kept = tuple(sorted(g & known))
            if kept:
                groups.append(kept)
        proposed = False
    raised = None
    if proposed and pp.raised_objects:
        # objects the segmentation left in the floor (an open box's bottom, a laptop's base)
        lab = planes.labels if (parent or flights) else labels
        groups, extra, alone = join_raised(groups, raised_clusters(cloud, lab, planes, support),
                                           lab, np.asarray(cloud.xyz, float))
        raised = (groups, extra, alone)
    # proposals take the clusters of unexplained points; given objects keep their planes
    cobjs = curved_objects(planes, rel, groups, cloud if proposed else None,
                           planes.labels if (parent or flights) else labels, support, cp,
                           pixels, profiles, _label_bound(labels, planes, parent or flights))
    if raised is not None:
        rp = defaults(RaisedParams)
        cobjs = with_raised(cobjs, *raised, cp.curved_below,
                            np.asarray(cloud.xyz, float) if rp.join_clusters else None,
                            rp.edge_depth)
    if proposed and cp.enabled and cp.join_parts:
        # unassigned parts touching one proposal only (a chair's legs): joined to it
        from planerel.features.curved import join_parts

        cobjs = join_parts(cobjs, cloud.xyz, planes.labels if (parent or flights) else labels,
                           cp.edge_depth)
    if proposed and pp.table_legs > 0 and support:
        # a table standing in the room: its top support for what stands on it, and an object
        cobjs = table_objects(planes, support, cobjs, pp, cp.curved_below,
                              np.asarray(cloud.xyz, float))
    if proposed and pp.legs_apart > 0:
        # a table's or a chair's legs seen without its top: one object
        cobjs = leg_objects(planes, cobjs, pp, cp.curved_below, np.asarray(cloud.xyz, float))
    if proposed and pp.open_walls:
        # an open object's near wall (its outside) and far wall (its inside): one object
        from planerel.features.open_walls import open_wall_objects

        cobjs = open_wall_objects(planes, cobjs, pp, cp.curved_below, np.asarray(cloud.xyz, float))
    objs = tuple(SceneObject(terms.object_id(scene_id, k + 1), c.planes, klass, c.mask,
                             c.planar_fraction, c.curved)
                 for k, c in enumerate(cobjs))
    # a skirt denied only by another object's step (a box on a box) is one after all
    rel = skirts_within_objects(rel, [o.planes for o in objs], planes, support)
    by_label = {p.label: p for p in planes}
    steps = frozenset(s for o in objs
                      for s in stair_steps(planes, o.planes, pp, by_label, cloud.xyz))
    # the slope of each upright face's top edge seen over half a metre, for the objects' planes:
    # a wedge's side rises (ramp77)
    slopes = (top_slopes(planes, planes.labels, cloud.xyz,
                         only={x for o in objs for x in o.planes},
                         beside=inclined_beside(planes, rel)) if top_slope else ())
    desc = SceneDescription(scene_id, planes, rel, objs, getattr(cloud, "source", None),
                            proposed, support, truncated=cut, tall=tall, lying=lying,
                            steps=steps, top_slope=slopes)
    if far_mask is not None:
        desc = replace(desc, far=far_planes(desc, far_mask))
    return desc


def view_up(cloud, up=None, gravity_params=None):
    """:func:`planerel.segment.segment`'s ``up`` for the small pass's ``small_pitch``
    (small99): a function of the segmentation so far that gives the up :func:`describe_scene`
    will describe the scene with: ``up`` when given, else the cloud's own (a sidecar's), else
    estimated from that segmentation's planes, the far growing's left out as
    :func:`describe_scene` leaves them out (:func:`planerel.features.gravity.resolve_up`).
    Called only when the pass asks (``small_scale`` and ``small_pitch`` set).

    Returns
    -------
    callable
        ``f(seg) -> ndarray, shape (3,)``.
    """
    def read(seg):
        from planerel.features.gravity import resolve_up

        lab = np.asarray(seg.labels)
        far = tuple(seg.info.get("far_labels") or ())
        if far:
            lab = np.where(np.isin(lab, far), -1, lab)
        return np.asarray(resolve_up(cloud, lab, up, gravity_params).vector, float)

    return read


def measured_planes(cloud, labels, up, plane_params, gravity_params, proposal_params, *,
                    far_mask=None, camera_height=None):
    """The planes of ``labels`` measured as :func:`describe_scene` measures them before its
    stairfit stage: with gravity (the planes ``far_mask`` covers left out of its estimate) and,
    with ``proposal_params.split_stepped``, treads grown into one sloping plane split apart
    (:func:`planerel.features.stepped.remeasure_stepped`).

    Returns
    -------
    (PlaneSet, dict)
        The planes and each split plane's parent label.
    """
    from planerel.features.planes import measure_planes  # (looked up at each call: see above)

    pp = proposal_params
    planes = measure_planes(cloud, labels, up, plane_params, gravity_params,
                            gravity_labels=None if far_mask is None
                            else np.where(far_mask, -1, labels), camera_height=camera_height)
    if not pp.split_stepped:
        return planes, {}
    # treads joined into one sloping "plane" (a flight seen from above) come apart
    return remeasure_stepped(cloud, planes, (pp.step_rise_min, pp.step_rise_max), plane_params)


def far_planes(desc, far_mask) -> frozenset:
    """Labels of ``desc``'s planes lying for half their pixels or more in ``far_mask``.

    Parameters
    ----------
    desc : SceneDescription
        Its label image may differ from the segmentation's (stepped planes split into
        levels, fitted treads), hence the pixel share rather than the labels themselves.
    far_mask : ndarray, shape (H, W), bool
        The pixels of the planes the segmentation's far growing added.
    """
    lab = np.asarray(desc.labels)
    if lab.shape != np.asarray(far_mask).shape:
        return frozenset()
    keep = lab >= 0
    n = int(lab.max()) + 1 if keep.any() else 0
    total = np.bincount(lab[keep], minlength=n)
    inside = np.bincount(lab[keep & far_mask], minlength=n)
    return frozenset(int(i) for i in np.flatnonzero((total > 0) & (2 * inside >= total)))


def _label_bound(labels, planes, split) -> int | None:
    """More than every label ``labels`` holds at a valid pixel (:func:`curved_objects`'
    ``label_bound``), without a pass over it: ``planes.labels`` is ``labels`` at every valid
    pixel (:func:`~planerel.features.planes.measure_planes` copies it as int32 and sets the
    invalid pixels to -1) and remembers its largest label.  None (the curved stage takes the
    image's own) when the planes were split again (``split``: their labels are the ones
    asked) or when ``labels`` may hold values int32 does not (their copy then differs)."""
    lab = np.asarray(labels)
    if split or planes.labels is None or lab.dtype.kind not in "iu" or lab.dtype.itemsize > 4 \
            or (lab.dtype.kind == "u" and lab.dtype.itemsize == 4):
        return None
    return label_max(planes.labels) + 1


#: :func:`truncated_planes`' defaults: a neighbour nearer by more than ``TRUNC_JUMP * max(1,
#: range)`` within ``TRUNC_BAND`` pixels hides the plane there; a plane is cut when such
#: pixels are at least ``TRUNC_SHARE`` of its outline, or when it comes within
#: ``TRUNC_BORDER`` pixels of the image border.
TRUNC_JUMP = 0.05
TRUNC_BAND = 2
TRUNC_SHARE = 0.10
TRUNC_BORDER = 1


def truncated_planes(labels, xyz, *, jump: float = TRUNC_JUMP, band: int = TRUNC_BAND,
                     share: float = TRUNC_SHARE, border: int = TRUNC_BORDER) -> frozenset:
    """Labels of the planes not seen whole: cut by the image border or partly hidden.

    A plane's hull measures what is in view.  Where its outline is the image border or an
    occluding edge (a valid point of another label, or of none, within ``band`` pixels along
    a row or column, nearer to the sensor by more than ``jump * max(1, range)``), the plane
    may go on behind: its length and width are lower bounds, not sizes (a tread half hidden
    by the riser in front looks as thin as a table's edge).  Such a plane is cut when it
    reaches within ``border`` pixels of the image border, or when the hidden pixels are at
    least ``share`` of its outline pixels (pixels with a 4-neighbour outside the plane).

    Parameters
    ----------
    labels : ndarray, shape (H, W), int
        Plane labels, -1 (or any negative) unassigned.
    xyz : ndarray, shape (H, W, 3), float
        Organized points; NaN invalid.

    Returns
    -------
    frozenset of int
    """
    from planerel.features._truncated_kernels import truncated_at, truncation_counts
    from planerel.features.planes import _listed_boundary_pixels  # (a test stands in for it)

    lab = np.asarray(labels)
    if lab.ndim != 2 or lab.size == 0:
        return frozenset()
    top = label_max(lab)  # remembered for a PlaneSet's labels (measure_planes took it)
    if top < 0:
        return frozenset()
    pts = np.ascontiguousarray(xyz, dtype=np.float64)
    if pts.shape != lab.shape + (3,):
        raise InputError(f"truncated_planes: points of shape {pts.shape} for labels of shape {lab.shape}")
    ints = np.ascontiguousarray(lab if lab.dtype in (np.int32, np.int64) else lab.astype(np.int64))
    args = (float(jump), max(0, int(band)), max(0, int(border)), top + 1)
    # the outline pixels are the label image's boundary pixels: when measure_planes listed
    # them (a PlaneSet's labels), only those are visited, else one pass finds them
    listed = _listed_boundary_pixels(lab)
    if listed is not None:
        cut, present = truncated_at(ints, pts, listed[0], listed[1], args[0], args[1], args[2],
                                    float(share), args[3])
    else:
        n_out, n_hid, at_edge, present = truncation_counts(ints, pts, *args)
        cut = at_edge | ((n_out > 0) & (n_hid >= share * np.maximum(n_out, 1)))
    return frozenset(int(k) for k in np.nonzero(cut & present)[0])


def _oblique_min_width(relations) -> float:
    """The relations' ``oblique_min_width`` (0 for a plain sequence of relations)."""
    params = getattr(relations, "params", None)
    return float(getattr(params, "oblique_min_width", 0.0))


def oblique_share(planes_by_label, relations, labels, min_width: float = 0.0) -> float:
    """Share of an object's plane area in planes that meet another plane of the object at an
    oblique angle: adjacent, neither parallel nor perpendicular (the tolerances of
    :class:`~planerel.features.relations.RelationParams`), and no larger than that plane.

    The faces of a box meet at right angles (0); the facets of a cylinder or a bowl, or a
    tilted lid on its base, meet obliquely.  Only the smaller plane of each such pair counts,
    so a sliver at a box's edge adds its own small area, not the face it touches.

    A plane narrower than ``min_width`` (``plane_width``, m) does not count at all: a real
    box's rounded edge or a side seen edge-on segments as a strip 1.5-2 cm wide whose normal
    the fit cannot tell about its long axis (mOSD learn1, learn3, learn5: strips of
    0.0020-0.0051 m^2 at 71-88 degrees made three boxes' shares 0.028-0.074, and varied models
    learned "box needs at most 0.02" from sharp synthetic edges).  The callers pass
    :attr:`~planerel.features.relations.RelationParams.oblique_min_width` (2.5 cm).

    Parameters
    ----------
    planes_by_label : dict
        ``{label: Plane}`` (``area`` in m^2).
    relations : iterable of Relation
        The scene's pair relations (``a``, ``b``, ``adjacent``, ``parallel``, ``perpendicular``).
    labels : sequence of int
        The object's planes.
    min_width : float
        Planes narrower than this (m) are left out (0: none).

    Returns
    -------
    float
        In ``[0, 1]``; 0 for an object without area.
    """
    own = set(labels)
    total = sum(planes_by_label[k].area for k in own)
    if total <= 0:
        return 0.0
    smaller = set()
    for r in relations:
        if (r.a < r.b and r.a in own and r.b in own and r.adjacent and not r.parallel
                and not r.perpendicular):
            pa, pb = planes_by_label[r.a], planes_by_label[r.b]
            k, p = (r.a, pa) if pa.area <= pb.area else (r.b, pb)
            if min_width <= 0 or p.width >= min_width:
                smaller.add(k)
    return float(min(1.0, sum(planes_by_label[k].area for k in smaller) / total))


def _described_pairs(desc: SceneDescription, mode: str) -> list:
    if mode == "none":
        return []
    same_object: set[tuple[int, int]] = set()
    if mode in ("object", "object+adjacent"):
        for o in desc.objects:
            for a in o.planes:
                for b in o.planes:
                    if a != b:
                        same_object.add((a, b))
    out = []
    for r in desc.relations:
        if mode == "all" or (r.a, r.b) in same_object or (mode != "object" and r.adjacent):
            out.append(r)
    return out


def scene_facts(desc: SceneDescription, params: FactParams | None = None) -> dict[str, list[str]]:
    """The facts of one scene, by predicate name (values: lines ``name(args).``, in order)."""
    params = params or FactParams()
    out: dict[str, list[str]] = {name: [] for name, _, _, _ in PREDICATES}
    F = terms.fact
    S = desc.scene_id
    pid = desc.plane_id
    pset = desc.planes
    in_objects = {lbl for o in desc.objects for lbl in o.planes}
    planes = [p for p in pset if params.planes == "all" or p.label in in_objects]
    kept = {p.label for p in planes}
    out["scene"].append(F("scene", S))
    for p in planes:
        out["scene_plane"].append(F("scene_plane", S, pid(p.label)))
    if pset.floor is not None and pset.floor in kept:
        out["floor"].append(F("floor", S, pid(pset.floor)))
    out["up"].append(F("up", S, [float(x) for x in pset.up], round_to=6))
    by_label = {p.label: p for p in pset}
    for o in desc.objects:
        out["object"].append(F("object", S, o.id))
        for lbl in o.planes:
            out["has_plane"].append(F("has_plane", o.id, pid(lbl)))
        ors = [by_label[lbl].orientation for lbl in o.planes]
        out["nplanes"].append(F("nplanes", o.id, len(o.planes)))
        out["nhorizontal"].append(F("nhorizontal", o.id, ors.count("horizontal")))
        out["nvertical"].append(F("nvertical", o.id, ors.count("vertical")))
        out["ninclined"].append(F("ninclined", o.id, ors.count("inclined")))
        if o.planar_fraction is not None:
            out["planar_fraction"].append(F("planar_fraction", o.id, o.planar_fraction,
                                            round_to=3))
        if o.curved:
            out["curved"].append(F("curved", o.id))
        out["oblique_share"].append(F("oblique_share", o.id,
                                      oblique_share(by_label, desc.relations, o.planes,
                                                    _oblique_min_width(desc.relations)),
                                      round_to=3))
    for lbl in desc.support:
        if lbl in kept:
            out["support"].append(F("support", pid(lbl)))
    m, dg = DIGITS_M, DIGITS_DEG
    slope_of = dict(desc.top_slope)
    for p in planes:
        i = pid(p.label)
        out["orientation"].append(F("orientation", i, p.orientation))
        out["incline"].append(F("incline", i, p.incline, round_to=DIGITS_INCLINE))
        if p.orientation == "inclined":
            out["slope"].append(F("slope", i, p.incline, round_to=DIGITS_INCLINE))
        out["area"].append(F("area", i, p.area, round_to=m))
        out["plane_length"].append(F("plane_length", i, p.length, round_to=m))
        out["plane_width"].append(F("plane_width", i, p.width, round_to=m))
        if p.label not in desc.truncated:
            out["seen_length"].append(F("seen_length", i, p.length, round_to=m))
            out["seen_width"].append(F("seen_width", i, p.width, round_to=m))
        if p.label in desc.tall:
            out["tall_face"].append(F("tall_face", i))
        if p.label in desc.lying:
            out["lying"].append(F("lying", i))
        if p.label in slope_of:
            out["top_slope"].append(F("top_slope", i, slope_of[p.label],
                                      round_to=DIGITS_INCLINE))
        out["height"].append(F("height", i, p.height, round_to=m))
        out["distance"].append(F("distance", i, p.distance, round_to=m))
        out["npoints"].append(F("npoints", i, p.n_points))
        out["rms"].append(F("rms", i, p.rms, round_to=6))
        if params.planner:
            out["plane_model"].append(F("plane_model", i, [float(x) for x in p.centroid],
                                        terms.plist([float(x) for x in p.normal], round_to=6),
                                        round_to=m))
            out["hull"].append(F("hull", i, [[float(x) for x in v] for v in p.hull3d], round_to=m))
    described = [r for r in _described_pairs(desc, params.pairs)
                 if r.a in kept and r.b in kept]
    over = over_pairs(pset, described)
    for r in described:
        a, b = pid(r.a), pid(r.b)
        out["angle"].append(F("angle", a, b, r.angle, round_to=dg))
        if r.parallel:
            out["parallel"].append(F("parallel", a, b))
        if r.perpendicular:
            out["perpendicular"].append(F("perpendicular", a, b))
        if r.adjacent:
            out["adjacent"].append(F("adjacent", a, b))
        out["gap"].append(F("gap", a, b, r.gap, round_to=m))
        out["rise"].append(F("rise", a, b, r.rise, round_to=m))
        if r.above:
            out["above"].append(F("above", a, b))
            if (r.a, r.b) in over:
                out["over"].append(F("over", a, b))
        if r.skirt:
            out["skirt"].append(F("skirt", a, b))
        if r.corner:
            out["corner"].append(F("corner", a, b))
        if getattr(r, "face_pair", False):
            out["face_pair"].append(F("face_pair", a, b))
        if (r.a, r.b) in desc.steps:
            out["stair_step"].append(F("stair_step", a, b))
        if r.facing:
            out["facing"].append(F("facing", a, b))
        if r.in_front_of:
            out["in_front_of"].append(F("in_front_of", a, b))
    if not params.planner:
        for name in _PLANNER:
            out[name] = []
    return out


def _merge(descs: Sequence[SceneDescription], params: FactParams) -> dict[str, list[str]]:
    seen: set[str] = set()
    merged: dict[str, list[str]] = {name: [] for name, _, _, _ in PREDICATES}
    for d in descs:
        if d.scene_id in seen:
            raise InputError(f"scene id {d.scene_id!r} occurs twice; give every scene its own id")
        seen.add(d.scene_id)
        for name, lines in scene_facts(d, params).items():
            merged[name].extend(lines)
    return merged


_DEFAULT_HEADER = "planerel scene facts; vocabulary: docs/predicates.md"


def _comment_lines(text: str) -> str:
    """``text`` as Prolog comment lines (ASCII, one ``%`` line per line of text)."""
    out = []
    for line in text.splitlines():
        out.append("% " + "".join(ch if 32 <= ord(ch) < 127 else "?" for ch in line) + "\n")
    return "".join(out)


def up_comment(desc: SceneDescription) -> str:
    """``s0001: up [0.012, -0.766, -0.643] estimated, confidence 0.78`` (for the header)."""
    return f"{desc.scene_id}: {desc.planes.up_estimate.describe()}"


def _preamble(params: FactParams, header: str | None, declare: bool,
              comments: bool = True) -> tuple[list[str], list[str]]:
    """The header comment (``header`` or the default one; none when not ``comments``) and
    declaration lines, and the predicate names in file order."""
    lines = _comment_lines(header or _DEFAULT_HEADER).splitlines() if comments else []
    names = [n for n, _, _, _ in PREDICATES if params.planner or n not in _PLANNER]
    if declare:
        decl = ", ".join(f"{n}/{_ARITY[n]}" for n in names)
        lines.append(f":- dynamic(({decl})).")
        lines.append(f":- multifile(({decl})).")
    return lines, names


def facts_text(descs: Sequence[SceneDescription], params: FactParams | None = None, *,
               header: str | None = None, declare: bool = True) -> str:
    """All facts of the scenes as one loadable Prolog text.

    The header comment ends with one line per scene on its up vector (:func:`up_comment`:
    where it came from and how sure it is).  Every predicate of the vocabulary is declared ``dynamic`` and ``multifile`` (so queries
    about a relation no scene has fail instead of raising, and several fact files can be
    loaded together); facts are grouped by predicate.  An empty list of scenes gives a
    text with the declarations only.
    """
    params = params or FactParams()
    if isinstance(descs, SceneDescription):
        descs = [descs]
    descs = list(descs)
    merged = _merge(descs, params)
    text = "\n".join([header or _DEFAULT_HEADER, *(up_comment(d) for d in descs)])
    lines, names = _preamble(params, text, declare)
    for name in names:
        if merged[name]:
            lines.append("")
            lines.extend(merged[name])
    return "\n".join(lines) + "\n"


def write_facts(path, descs, params: FactParams | None = None, *, header: str | None = None):
    """Write :func:`facts_text` to ``path`` atomically; return the path."""
    from planerel.atomic import write_text

    return write_text(path, facts_text(descs, params, header=header))



class FactsWriter:
    """Write the facts of many scenes one scene at a time, with memory flat in their number.

    The file is byte for byte what :func:`write_facts` writes for the same scenes in the same
    order (facts grouped by predicate): each scene's lines are appended to one spool file per
    predicate in a temporary folder next to ``path``; :meth:`close` joins them into ``path``
    atomically.  Used as a context manager, an exception discards everything.

    Parameters
    ----------
    path : path
        The facts file to write.
    params : FactParams, optional
    header : str, optional
        The comment at the top of the file.
    """

    def __init__(self, path, params: FactParams | None = None, *, header: str | None = None):
        import tempfile

        self.path = Path(path)
        self.params = params or FactParams()
        self.header = header
        folder = self.path.parent if str(self.path.parent) else Path(".")
        try:
            folder.mkdir(parents=True, exist_ok=True)
            self._dir = tempfile.TemporaryDirectory(prefix=f".{self.path.name}.", dir=folder)
        except OSError as exc:
            raise InputError(f"cannot write {self.path}: {exc.strerror}") from None
        self._spool: dict = {}
        self._seen: set[str] = set()
        self.n_scenes = 0

    def add(self, scene) -> None:
        """Append one scene: a :class:`SceneDescription`, or ``(scene_id, facts)`` with the
        ``facts`` of :func:`scene_facts` (what a worker process sends back; then also give its
        :func:`up_comment` to :meth:`note_up`)."""
        if isinstance(scene, SceneDescription):
            sid, facts = scene.scene_id, scene_facts(scene, self.params)
            self.note_up(up_comment(scene))
        else:
            sid, facts = scene
        if sid in self._seen:
            raise InputError(f"scene id {sid!r} occurs twice; give every scene its own id")
        self._seen.add(sid)
        for name, lines in facts.items():
            if not lines:
                continue
            fh = self._spool.get(name)
            if fh is None:
                fh = self._spool[name] = open(Path(self._dir.name) / name, "w+", encoding="utf-8")
            fh.write("\n".join(lines) + "\n")
        self.n_scenes += 1

    def note(self, text: str) -> None:
        """A comment line for the top of the file, below the header (e.g. how one scene was
        segmented); kept on disk like the facts."""
        fh = self._spool.get(None)
        if fh is None:
            fh = self._spool[None] = open(Path(self._dir.name) / "_notes", "w+", encoding="utf-8")
        fh.write(_comment_lines(text))

    def note_up(self, text: str) -> None:
        """The scene's up-vector comment (:func:`up_comment`), listed below the notes."""
        fh = self._spool.get("_up")
        if fh is None:
            fh = self._spool["_up"] = open(Path(self._dir.name) / "_up", "w+", encoding="utf-8")
        fh.write(_comment_lines(text))

    def close(self) -> Path:
        """Join the spools into the facts file; return its path."""
        import shutil

        from planerel.atomic import atomic_path

        head = _comment_lines(self.header or _DEFAULT_HEADER)
        lines, names = _preamble(self.params, None, True, comments=False)
        try:
            with atomic_path(self.path, suffix=".pl") as tmp, open(tmp, "w", encoding="utf-8") as out:
                out.write(head)
                for key in (None, "_up"):
                    notes = self._spool.get(key)
                    if notes is not None:
                        notes.seek(0)
                        shutil.copyfileobj(notes, out)
                out.write("\n".join(lines) + "\n")
                for name in names:
                    fh = self._spool.get(name)
                    if fh is None:
                        continue
                    out.write("\n")
                    fh.seek(0)
                    shutil.copyfileobj(fh, out)
        finally:
            self.discard()
        return self.path

    def discard(self) -> None:
        """Remove the spool files (nothing is written to ``path``)."""
        for fh in self._spool.values():
            fh.close()
        self._spool.clear()
        self._dir.cleanup()

    def __enter__(self):
        return self

    def __exit__(self, exc_type, exc, tb) -> None:
        if exc_type is None:
            self.close()
        else:
            self.discard()
