"""A box's top that is the edge of a slab: a wall's, a door's or a panel's top strip (slab101).

Seen from above its edge, a thin upright slab shows a box's faces: its narrow top strip and,
under that strip's long edge, its side going down.  The skirt rule proves such a pair a box.
A box with so narrow a top is short: on the real development frames the right box answers
whose proof binds a top at most 0.13 m wide have upright proof faces at most 0.29 m long
either way (a cereal box standing, a product box on its side).  A wall beside a staircase
(8 cm thick, its cap 0.7-1.5 m above the floor), a door's or a partition's top edge, a
bookcase's side seen from above reach far lower: 0.9-1.9 m on the generated stairwells of
``benchmarks/independent_scenes.py`` (``dev_stw``, ``dev_st``), where they were the false
boxes of scenes whose flight was lost.

:func:`slab_drop` measures one pair: how far an upright plane adjacent to a narrow top reaches
below the top's level, when the plane lies below the top (a wall's side under its cap), not
above it (a wall a box stands against, which rises over the box's top).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["SlabEdge", "slab_drop", "slab_edge"]


@dataclass(frozen=True)
class SlabEdge:
    """A narrow top and an upright plane reaching far below it (labels; metres)."""

    top: int
    face: int
    #: the top's width
    width: float
    #: how far the face reaches below the top's level (its 5th percentile height)
    drop: float


def _heights(xyz, labels, label, up) -> np.ndarray:
    p = xyz[labels == label]
    p = p[np.isfinite(p).all(axis=1)]
    return p @ up


def slab_drop(top_heights, face_heights, above: float = 0.05) -> float:
    """How far (m) a face whose points are at ``face_heights`` (along up) reaches below a top
    whose points are at ``top_heights``: the top's median level minus the face's 5th
    percentile, when the face's 95th percentile lies no more than ``above`` over that level
    (the face hangs under the top's edge), else 0 (it rises beside or over the top); 0 when
    either has no point."""
    top_heights = np.asarray(top_heights, dtype=np.float64)
    face_heights = np.asarray(face_heights, dtype=np.float64)
    if top_heights.size == 0 or face_heights.size == 0:
        return 0.0
    level = float(np.median(top_heights))
    lo, hi = np.percentile(face_heights, [5, 95])
    if hi > level + above:
        return 0.0
    return max(0.0, level - float(lo))


def slab_edge(planes, relations, top, faces, xyz, labels, width: float,
              drop: float) -> SlabEdge | None:
    """The first of ``faces`` (upright planes) adjacent to ``top`` that reaches ``drop`` metres
    or more below it (:func:`slab_drop`), when ``top`` is at most ``width`` metres wide; None
    otherwise.

    Parameters
    ----------
    planes : PlaneSet
        The scan's planes (``up``).
    relations : Relations
        Their pairwise relations (``adjacent``).
    top : Plane
        A plane that is not upright.
    faces : iterable of Plane
        Upright planes of the same object.
    xyz : ndarray (H, W, 3)
        The scan's organized points.
    labels : ndarray (H, W)
        The plane label of each pixel.
    width, drop : float
        Metres.
    """
    if top.width > width:
        return None
    up = np.asarray(planes.up, dtype=np.float64)
    up = up / np.linalg.norm(up)
    th = None
    for f in faces:
        try:
            if not relations.get(top.label, f.label).adjacent:
                continue
        except KeyError:
            continue
        th = _heights(xyz, labels, top.label, up) if th is None else th
        d = slab_drop(th, _heights(xyz, labels, f.label, up))
        if d >= drop:
            return SlabEdge(top.label, f.label, float(top.width), d)
    return None
