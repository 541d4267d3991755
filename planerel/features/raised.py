"""Objects lying in a support plane: pixels of the floor (or a table top) that lie above it.

Region growing joins a surface 1-3 cm above the floor to the floor when the step between them
is within its tolerance: an open box's bottom (1 cm up, inside its walls), a laptop's base, a
plate.  Their pixels then sit in a support plane and no proposal holds them.  The rule
(:func:`raised_clusters`, parameters :class:`RaisedParams`):

1. For each horizontal support plane (the floor, horizontal planes of at least
   ``support_min_area``) the height of every one of its pixels above the plane's fit is
   averaged over a ``(2 smooth_px + 1)^2`` window (the plane's own pixels only).
2. A pixel is *raised* when that mean is above ``max(min_rise, k_sigma * s(z))``, ``s(z)``
   the standard error of the window mean at the pixel's depth: the plane's residual spread
   modelled as ``a z^2`` (structured-light noise grows with the square of the depth; ``a``
   from the median absolute residual) divided by the square root of the window's pixels.
3. Raised pixels, opened by ``open_px`` pixels, are grouped as
   :func:`planerel.features.curved.unexplained_clusters` groups points (4-neighbours within
   ``edge_depth * max(1, z)`` in 3-D); a group is kept when its surface area is at least
   ``min_area`` m^2, it holds at most ``max_share`` of the plane's pixels, and its median
   height stands ``min_rise`` above the lower tenth of the plane's pixels in a ring ``ring_px``
   wide around it that are not raised themselves (none: the group is walled in): a slow bend of a real floor (a sensor's depth distortion) lifts the ring
   as much as the group, an object lying on the floor ends at a step.

4. A kept group grows into the neighbouring plane pixels whose window mean is above half
   the limit, by as many steps as the opening and the window took off (``open_px +
   smooth_px + 1``).
5. Groups of one support plane that meet after growing (``merge_grown``: their pixels overlap
   or are 4-neighbours) become one group, unless together they hold more than ``max_share``
   of the plane's pixels.  One surface comes out in several groups where bands of it stay
   under the limit: a sensor's depth steps (disparity quantization, several centimetres at
   3 m) cross a far, nearly flat surface in lines, and the window means of the lower side of
   each step fall under the limit (seed 33 ``s0004``: an open box's bottom 1 cm up at 3.2 m
   came out in four groups along such lines, joined back to one by their grown pixels).

:func:`planerel.features.facts.describe_scene` joins each group to every proposal whose planes
touch it in the grid and in 3-D (an open box's inner walls; a laptop's lid), or makes it a
proposal of its own (a plate).  Its pixels count as flat in the planar fraction.

6. A group that no proposal's planes touch joins the cluster of points no plane explains
   (:mod:`planerel.features.curved`) that touches it, in the grid and in 3-D, at the most
   pixel pairs (``join_clusters``): the inner walls of an open box far away are often not
   segmented (seed 33 ``s0004``: a 13 cm open box at 3.2 m, its far inner wall a cluster of
   272 pixels touching its raised bottom).  A group touching no such cluster is a proposal
   of its own, as before.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from planerel.errors import InputError, check_bools
from planerel.features._defaults import defaults
from planerel.features.curved import CurvedObject, _pitches_at, _shift_all, _touching_labels
from planerel.features.planes import label_max

__all__ = ["RaisedParams", "raised_clusters"]


@dataclass(frozen=True)
class RaisedParams:
    """Parameters of :func:`raised_clusters` (see the module docstring for the rule).

    Parameters
    ----------
    min_rise : float
        Metres: the smallest height above the support plane that counts, and the smallest
        step between a group and the ring around it.
    k_sigma : float
        A window mean counts when above this many standard errors of the plane's noise at
        its depth.
    smooth_px : int
        Pixels: half-width of the averaging window.
    open_px : int
        Pixels: radius of the morphological opening of the raised pixels.
    ring_px : int
        Pixels: width of the ring of support pixels around a group that its step is
        measured against.
    edge_depth : float
        Metres at 1 m (scaled by the depth): grid neighbours farther apart are not connected.
    min_area : float
        m^2: smallest surface area of a group that is kept.
    max_share : float
        A group holding more than this fraction of its support plane's pixels is a bend of
        that plane, not an object.
    enabled : bool
        False: no groups.
    merge_grown : bool
        Rule step 5: groups of one plane that meet after growing become one.
    join_clusters : bool
        Rule step 6: a group no proposal's planes touch joins a cluster of unexplained points
        that touches it (:func:`with_raised`).
    """

    min_rise: float = 0.006
    k_sigma: float = 4.0
    smooth_px: int = 2
    open_px: int = 2
    ring_px: int = 4
    edge_depth: float = 0.02
    min_area: float = 0.005
    max_share: float = 0.25
    enabled: bool = True
    merge_grown: bool = True
    join_clusters: bool = True

    def __post_init__(self) -> None:
        for name in ("min_rise", "k_sigma", "edge_depth", "min_area", "max_share"):
            v = getattr(self, name)
            if isinstance(v, bool) or not isinstance(v, (int, float)) or not np.isfinite(v) or v < 0:
                raise InputError(f"{name} must be a number >= 0, got {v!r}")
        for name in ("smooth_px", "open_px", "ring_px"):
            v = getattr(self, name)
            if isinstance(v, bool) or not isinstance(v, int) or not 0 <= v <= 16:
                raise InputError(f"{name} must be an integer number of pixels in 0..16, got {v!r}")
        check_bools(self)


def _raised_on(plane, xyz: np.ndarray, lab: np.ndarray, f: int, up: np.ndarray,
               params: RaisedParams):
    """The plane's pixels, its raised and weakly raised pixels (bool) and every pixel's height
    above it (0 off it), on the grid of every ``f``-th pixel of ``plane.bbox`` (rule steps 1-2)."""
    from planerel.features._raised_kernels import raised_noise_pixels, raised_pixels
    from planerel.features._relation_kernels import median

    n = np.asarray(plane.normal, float)
    if float(n @ up) < 0:
        n = -n
    d0 = float(np.asarray(plane.centroid, float) @ n)
    r0, c0, r1, c1 = plane.bbox
    H, W = -(-(r1 - r0) // f), -(-(c1 - c0) // f)
    if (xyz.dtype == np.float64 and 0 <= r0 and 0 <= c0 and r1 <= lab.shape[0]
            and c1 <= lab.shape[1]):
        # the noise scale measured in the same pass over the grid (raised_noise_pixels: the
        # values _noise_values gives, the same median)
        return raised_noise_pixels(xyz, lab, int(plane.label), r0, c0, H, W, f, n, d0,
                                   float(params.min_rise), float(params.k_sigma),
                                   int(params.smooth_px), 5)
    # the noise scale a of h ~ a z^2, from every fifth pixel of the grid (robust: MAD; one
    # compiled pass, :func:`_noise_values`)
    vals = _noise_values(xyz, lab, int(plane.label), (r0, c0, r1, c1), 5 * f, n, d0)
    a = 1.4826 * float(median(vals)) if vals.size else 0.0
    return raised_pixels(xyz, lab, int(plane.label), r0, c0, H, W, f, n, d0, a,
                         float(params.min_rise), float(params.k_sigma), int(params.smooth_px))


def _noise_values(xyz, lab, label: int, bbox, step: int, n, d0: float) -> np.ndarray:
    """``|p . n - d0| / max(|z|, 0.1)^2`` of the finite-depth points ``p`` of ``label`` on
    every ``step``-th pixel of ``bbox`` (numpy's slicing of the box), row-major; the kernel
    :func:`planerel.features._raised_kernels.noise_values` for float64 points and a box
    inside the image, numpy otherwise (the same values within rounding)."""
    from planerel.features._raised_kernels import noise_values

    r0, c0, r1, c1 = (int(v) for v in bbox)
    H, W = lab.shape
    if (xyz.dtype == np.float64 and 0 <= r0 and 0 <= c0 and step > 0):
        return noise_values(xyz, lab, label, r0, c0, min(r1, H), min(c1, W), step,
                            np.asarray(n, np.float64), float(d0))
    ps = xyz[r0:r1:step, c0:c1:step][lab[r0:r1:step, c0:c1:step] == label]
    ps = ps[np.isfinite(ps[:, 2])]
    zs = np.maximum(np.abs(ps[:, 2]), 0.1)
    return np.abs(ps @ n - d0) / zs ** 2


def _grow(m: np.ndarray, weak: np.ndarray, steps: int) -> np.ndarray:
    """``m`` grown by up to ``steps`` 4-neighbour steps into ``weak`` pixels (hysteresis: the
    opening and the window cut a small group's outline)."""
    for _ in range(steps):
        g = m.copy()
        g[1:] |= m[:-1]
        g[:-1] |= m[1:]
        g[:, 1:] |= m[:, :-1]
        g[:, :-1] |= m[:, 1:]
        g &= weak
        g |= m
        if (g == m).all():
            break
        m = g
    return m


def _merge_meeting(masks: list, cap: float) -> list:
    """Masks (one plane's grown groups, in order) whose pixels overlap or are 4-neighbours
    joined into one (rule step 5), in the place of the first; a join whose pixels would exceed
    ``cap`` is not made (a bend of the plane, not an object)."""
    out = [m.copy() for m in masks]
    changed = True
    while changed:
        changed = False
        for i in range(len(out)):
            if out[i] is None:
                continue
            near = _grow(out[i], np.ones_like(out[i]), 1)
            for j in range(i + 1, len(out)):
                if out[j] is None or not (near & out[j]).any():
                    continue
                both = out[i] | out[j]
                if int(np.count_nonzero(both)) > cap:
                    continue
                out[i], out[j] = both, None
                near = _grow(out[i], np.ones_like(out[i]), 1)
                changed = True
    return [m for m in out if m is not None]


#: No label dropped (:func:`planerel.features._curved_kernels.open_pixels`' ``drop``).
_NO_DROP = np.zeros(0, np.bool_)


def raised_clusters(cloud, labels, planes, support=(), params: RaisedParams | None = None):
    """Groups of support-plane pixels lying above their plane (the module's rule).

    Parameters
    ----------
    cloud : Cloud
        Organized cloud ``(H, W, 3)``.
    labels : ndarray, shape (H, W), int
        Plane labels, -1 unassigned.
    planes : PlaneSet
        The measured planes (``up`` and each plane's fit).
    support : iterable of int
        Support plane labels; the horizontal ones are searched.

    Returns
    -------
    list of ndarray (H, W) bool
        One mask per group, ordered by their first pixel (row-major).
    """
    from planerel.features._curved_kernels import list_areas, list_components, open_pixel_list
    from planerel.segment._label_kernels import mask_pixels

    params = params or defaults(RaisedParams)
    if not params.enabled:
        return []
    xyz = np.ascontiguousarray(cloud.xyz, dtype=np.float64)
    lab = np.ascontiguousarray(labels)
    if lab.shape != xyz.shape[:2]:
        raise InputError(f"labels {lab.shape} and cloud {xyz.shape[:2]} differ in shape")
    up = np.asarray(planes.up, float)
    byl = {p.label: p for p in planes}
    f = max(1, lab.shape[1] // 320)
    found = []
    for s in sorted(set(support)):
        p = byl.get(s)
        if p is None or p.orientation != "horizontal":
            continue
        # the plane's pixel box only (a table top is a part of the image), every f-th pixel
        # of it: a 640x480 frame is searched at 320x240 (the window then spans 10 pixels),
        # the groups found are taken back to every pixel and grown there
        r0, c0, r1, c1 = p.bbox
        box = (slice(r0, r1), slice(c0, c1))
        on, raw, weak, h = _raised_on(p, xyz, lab, f, up, params)
        # the raw pixels' list (a few of the grid's pixels, most often none) opened from the
        # list (open_pixel_list: the pixels of open_mask(raw), row-major, from the rows' runs
        # without passes over the whole grid), less any pixel not of the plane (none: raw is
        # on the plane)
        rows, cols = mask_pixels(raw)
        if not len(rows):
            continue
        rows, cols = open_pixel_list(rows, cols, raw.view(np.uint8), _NO_DROP, raw.shape[0],
                                     raw.shape[1], int(params.open_px))
        keep = on[rows, cols]
        rows, cols = rows[keep], cols[keep]
        if not len(rows):
            continue
        bx = xyz[r0:r1:f, c0:c1:f]
        # the groups from the raised pixels' list (a few % of the grid: list_components, the
        # components of the mask numbered as grid_components numbers them, and list_areas,
        # the same sums in the same order), not from maps of the whole grid
        comp, k = list_components(rows, cols, bx, float(params.edge_depth), on.shape[0])
        pitch = _pitches_at(bx, rows, cols)
        area = list_areas(bx, rows, cols, comp, pitch[0], pitch[1], k)
        n_on = int(np.count_nonzero(on))
        mine = []
        for c in np.nonzero(area >= params.min_area)[0]:
            sel = comp == c
            if int(np.count_nonzero(sel)) > params.max_share * n_on:
                continue
            m = np.zeros(on.shape, bool)
            m[rows[sel], cols[sel]] = True
            # grown by ring_px in the group's box widened by ring_px (nothing grows past it)
            g0 = max(0, int(rows[sel].min()) - params.ring_px)
            g1 = int(rows[sel].max()) + params.ring_px + 1
            h0 = max(0, int(cols[sel].min()) - params.ring_px)
            h1 = int(cols[sel].max()) + params.ring_px + 1
            box_g = (slice(g0, g1), slice(h0, h1))
            part = m[box_g]
            for axis in (0, 1):
                part = _shift_all(part, params.ring_px, axis, False)
            # the ring: plane pixels around the group that are not raised themselves (an open
            # box's bottom, walled in, has none: nothing of the plane around it to bend); they
            # mix the group's edge, which the window mean left below the limit, with the plane
            # around it, hence the ring's lower tenth: a Kinect floor's bend (frame 3 at 1.2 m,
            # 7 mm up) stands 4 mm above its ring, an open box's 1 cm bottom 9-14 mm
            # (the group and its ring lie in the widened box: their heights taken from it, the
            # same values in the same row-major order as from the whole grid)
            ring = part & on[box_g] & ~raw[box_g]
            hb = h[box_g]
            if ring.any() and float(np.median(hb[m[box_g]])
                                    - np.percentile(hb[ring], 10)) < params.min_rise:
                continue
            steps = params.open_px + params.smooth_px + 1
            if f > 1:
                on_full = lab[box] == s
                m, wk = (np.repeat(np.repeat(x, f, 0), f, 1)[:r1 - r0, :c1 - c0] & on_full
                         for x in (m, weak))
                steps *= f
            else:
                wk = weak
            mine.append(_grow(m, wk, steps))
        if params.merge_grown and len(mine) > 1:
            mine = _merge_meeting(mine, params.max_share * int(np.count_nonzero(lab[box] == s)))
        for g in mine:
            full = np.zeros(lab.shape, bool)
            full[box] = g
            found.append(full)
    found.sort(key=lambda m: int(np.flatnonzero(m.ravel())[0]))
    return found


def join_raised(groups, masks, labels, xyz, edge_depth: float = 0.02, min_touch: int = 3):
    """Join each raised group to the proposals whose planes touch it.

    Parameters
    ----------
    groups : sequence of sequence of int
        Plane labels per proposal.
    masks : sequence of ndarray (H, W) bool
        Raised groups (:func:`raised_clusters`).
    labels : ndarray, shape (H, W), int
        Plane labels.
    xyz : ndarray, shape (H, W, 3)
        Organized points.
    edge_depth : float
        Metres at 1 m: a plane's pixel touches a group's within two grid steps and this 3-D
        distance (scaled by the depth).
    min_touch : int
        Fewest such pixel pairs for a plane to touch.

    Returns
    -------
    (list of tuple of int, list of ndarray or None, list of ndarray)
        The proposals (those a group joined are one proposal now, in the place of the first),
        each one's raised pixels (None: none), and the groups that touch no proposal.
    """
    groups = [tuple(g) for g in groups]
    extra: list = [None] * len(groups)
    alone = []
    lab = np.asarray(labels)
    owner = {x: k for k, g in enumerate(groups) for x in g}
    nlab = label_max(lab) + 1 if masks else 0  # once for every group's touching planes
    for m in masks:
        touch = _touching_labels(m, lab, xyz, edge_depth, nlab)
        ks = sorted({owner[x] for x, n in touch.items() if n >= min_touch and x in owner})
        if not ks:
            alone.append(m)
            continue
        k0 = ks[0]
        for k in ks[1:]:
            groups[k0] = tuple(sorted(set(groups[k0]) | set(groups[k])))
            if extra[k] is not None:
                extra[k0] = extra[k] if extra[k0] is None else extra[k0] | extra[k]
            groups[k], extra[k] = (), None
        for x in groups[k0]:
            owner[x] = k0
        extra[k0] = m if extra[k0] is None else extra[k0] | m
    keep = [k for k, g in enumerate(groups) if g]
    return [groups[k] for k in keep], [extra[k] for k in keep], alone


def with_raised(cobjs, groups, extra, alone, curved_below: float = 0.8, xyz=None,
                edge_depth: float = 0.02, min_touch: int = 3):
    """Add the raised pixels to the objects of :func:`planerel.features.curved.curved_objects`
    (matched by their planes), as flat points of the planar fraction; the groups that stand
    alone become objects of their own (planar fraction 1) after them.

    With ``xyz`` (rule step 6, ``RaisedParams.join_clusters``), a group that stands alone
    joins instead the object whose points no plane explains (its cluster's pixels) touch it
    at ``min_touch`` or more grid neighbour pairs within ``edge_depth * max(1, z)`` (the one
    with the most such pairs): an open box whose bottom is raised and whose inner walls were
    not segmented."""
    out = list(cobjs)
    if xyz is not None and alone and any(c.mask is not None for c in out):
        H, W = np.asarray(alone[0]).shape
        owner = np.full((H, W), -1, np.int64)
        for k, c in enumerate(out):
            if c.mask is not None:
                owner[np.asarray(c.mask, bool) & (owner < 0)] = k
        left = []
        for m in alone:
            touch = {k: n for k, n in _touching_labels(m, owner, xyz, edge_depth).items()
                     if n >= min_touch}
            if not touch:
                left.append(m)
                continue
            k = max(sorted(touch), key=lambda x: touch[x])
            c = out[k]
            nb = int((m & ~c.mask).sum())
            frac = (c.planar_fraction * c.n_points + nb) / max(c.n_points + nb, 1)
            out[k] = CurvedObject(c.planes, c.mask | m, float(frac), bool(frac < curved_below),
                                  int(c.n_points + nb))
            owner[m & (owner < 0)] = k
        alone = left
    for g, e in zip(groups, extra, strict=True):
        if e is None:
            continue
        for k, c in enumerate(out):
            if set(g) <= set(c.planes):
                nb = int((e & ~c.mask).sum()) if c.mask is not None else int(e.sum())
                frac = (c.planar_fraction * c.n_points + nb) / max(c.n_points + nb, 1)
                mask = e if c.mask is None else c.mask | e
                out[k] = CurvedObject(c.planes, mask, float(frac), bool(frac < curved_below),
                                      int(c.n_points + nb))
                break
    for m in alone:
        out.append(CurvedObject((), m, 1.0, False, int(m.sum())))
    return out
