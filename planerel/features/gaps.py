"""What the image shows between two planes that do not touch in it.

Two parallel planes whose hulls come within a few centimetres but whose pixels neither touch
nor share an edge are either pieces of one surface with something in front of it between them
(a shelf's back panel seen above and below a board, a face behind a table leg) or two
surfaces with a gap between them (two boxes in a row: the floor seen between them, or a face
of one of them).  The pixels on the short image lines between the two planes tell which: an
occluder lies in front of both planes; a gap shows what is behind them or beside them.
"""

from __future__ import annotations

import numpy as np

__all__ = ["gap_in_front"]


def gap_in_front(labels, xyz, a: int, b: int, margin: float = 0.05, lines: int = 5,
                 max_outline: int = 200, window=None) -> float | None:
    """Fraction of the valid pixels between planes ``a`` and ``b`` that lie in front of both.

    Parameters
    ----------
    labels, xyz : ndarray, shapes (H, W) int and (H, W, 3) float
        The plane label image and the organized points (NaN where invalid).
    a, b : int
        The two labels.
    margin : float
        Metres at 1 m (scaled by the range): a pixel is in front when its range is below the
        smaller of the two end pixels' ranges by more than ``margin * max(1, range)``.
    lines : int
        The image lines looked at: between the ``lines`` closest pairs of outline pixels (one
        of each plane; every second outline pixel kept until at most ``max_outline`` are).
    max_outline : int
        Outline pixels per plane compared at most.
    window : (row0, col0, row1, col1), optional
        Pixel box holding both planes (their ``bbox`` joined): only it is looked at.

    Returns
    -------
    float or None
        In front / valid pixels on those lines (end pixels and pixels of ``a`` or ``b`` not
        counted); None when there are none (the planes touch, or only invalid pixels lie
        between them: nothing is known).
    """
    from planerel.features.planes import _boundary

    lab = np.asarray(labels)
    xyz = np.asarray(xyz)
    if window is not None:
        r0, c0, r1, c1 = (int(v) for v in window)
        lab, xyz = lab[r0:r1, c0:c1], xyz[r0:r1, c0:c1]
    edge = _boundary(lab)
    pa, pb = np.argwhere(edge & (lab == a)), np.argwhere(edge & (lab == b))
    if len(pa) == 0 or len(pb) == 0:
        return None
    while len(pa) > max_outline:
        pa = pa[::2]
    while len(pb) > max_outline:
        pb = pb[::2]
    d2 = ((pa[:, None, :] - pb[None, :, :]) ** 2).sum(-1)
    order = np.argsort(d2, axis=None)[:lines]

    def rng(r, c):
        return np.linalg.norm(np.asarray(xyz[r, c], float), axis=-1)

    n_valid = n_front = 0
    for k in order:
        i, j = np.unravel_index(k, d2.shape)
        (r0, c0), (r1, c1) = pa[i], pb[j]
        steps = int(max(abs(r1 - r0), abs(c1 - c0)))
        if steps < 2:
            continue
        t = np.arange(1, steps) / steps
        rr = np.rint(r0 + t * (r1 - r0)).astype(int)
        cc = np.rint(c0 + t * (c1 - c0)).astype(int)
        near = float(min(rng(r0, c0), rng(r1, c1)))
        if not np.isfinite(near):
            continue
        keep = (lab[rr, cc] != a) & (lab[rr, cc] != b)
        r = rng(rr[keep], cc[keep])
        r = r[np.isfinite(r)]
        n_valid += r.size
        n_front += int((r < near - margin * max(1.0, near)).sum())
    return n_front / n_valid if n_valid else None
