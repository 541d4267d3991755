"""The segmentation's depth-noise estimate at several patch sizes, on real frames and under
added white or spatially correlated noise (noise58, docs/segmentation.md "Correlated depth
noise").  A measuring tool; nothing in the segmentation reads it.

Usage::

    noise_scales.py [--sets DIR ...] [--clouds FILE ...] [--stairs DIR]
        [--perturb FRAME_NAME ...] [--seeds N] [--json F]

Per frame, :func:`planerel.segment.noise.estimate_noise` is run with ``patch`` 5 (the
segmentation's), 11 and 15; each gives ``sigma`` at the frame's median depth (the 5 px
model's), its quantile-to-median factor corrected to the patch's degrees of freedom.  The
correlated part is ``sqrt(s15^2 - s5^2)`` (0 when negative).  ``win`` is the normal window the
adaptation's rule for uniform noise gives (``max(nominal, min(8, round(sqrt(12) p)))``, ``p``
the noise in pixel footprints) from ``s5`` and from ``s15``; the adaptation applies that rule
only to kind ``uniform``.  ``win_used`` is the window the normals use at the median depth (kind
``z2`` and ``none``: the nominal window, grown in proportion to depth beyond 2 m).

``--perturb`` names frames (``set/stem``) that are also measured under ``Z + k Z^2 n`` with
``n`` unit white noise or unit noise smoothed over 2 and 4 px (as
:mod:`stairs_robust`), ``k`` 0.002 and 0.005 /m, seeds 0..N-1.
"""

from __future__ import annotations

import argparse
import json
import math
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))

PATCHES = (5, 11, 15)


def _qtm(k: int) -> float:
    """Median / QUANTILE-quantile ratio of a pure-noise ``k`` x ``k`` patch's std."""
    from scipy.stats import chi2

    from planerel.segment.noise import QUANTILE

    dof = k * k - 3
    return math.sqrt(chi2.ppf(0.5, dof) / chi2.ppf(QUANTILE, dof))


def measure_cloud(cloud) -> dict:
    """``{kind, z, s5, s11, s15, corr, wave, win5, win15, win_used}`` of one organized cloud
    (sigmas in mm at the 5 px model's median depth)."""
    from planerel.segment.adapt import MAX_WINDOW, adapt_params
    from planerel.segment.noise import QUANTILE_TO_MEDIAN, estimate_noise
    from planerel.segment.normals import auto_normal_scale
    from planerel.segment.params import RegionGrowParams

    m5 = estimate_noise(cloud, waviness=True)
    z = m5.z_median
    out = {"kind": m5.kind, "z": round(z, 3), "wave": round(m5.wave, 2)}
    h, w = cloud.shape
    nom = max(auto_normal_scale(w))
    for k in PATCHES:
        m = m5 if k == 5 else estimate_noise(cloud, patch=k)
        s = float(m.sigma(z)) * _qtm(k) / QUANTILE_TO_MEDIAN if m.reliable else float("nan")
        out[f"s{k}"] = round(1000 * s, 2)
    c2 = out["s15"] ** 2 - out["s5"] ** 2
    out["corr"] = round(math.sqrt(c2), 2) if c2 > 0 else 0.0
    foot = 1000 * z * m5.pixel_angle if z > 0 else float("nan")
    for k in (5, 15):
        p = out[f"s{k}"] / foot if foot > 0 else 0.0
        out[f"win{k}"] = max(nom, min(MAX_WINDOW, int(round(math.sqrt(12.0) * p)))) \
            if np.isfinite(p) else nom
    p, _ = adapt_params(RegionGrowParams(), m5, (h, w))
    s0 = nom if p.normal_smooth == "auto" else int(p.normal_smooth)
    zref = p.reference_depth
    # the window the normals use at the median depth (grown beyond zref, never shrunk)
    out["win_used"] = s0 if not zref else min(4 * s0, max(s0, int(round(s0 * z / zref))))
    return out


def _smooth(field, sigma):
    from stairs_robust import _smooth as sm

    return sm(field, sigma) if sigma > 0 else field / max(float(field.std()), 1e-12)


def perturbed(cloud, k: float, sigma: float, seed: int):
    """``cloud``'s depth plus ``k Z^2 n`` (``n`` unit noise smoothed over ``sigma`` px; 0:
    white), re-projected with the cloud's camera."""
    from stairs_robust import camera

    from planerel.io.cloud import depth_to_cloud

    z0 = np.asarray(cloud.depth, float)
    n = _smooth(np.random.default_rng(seed).standard_normal(z0.shape), sigma)
    zz = z0 + k * z0 ** 2 * n
    zz = np.where(np.isfinite(zz) & (zz > 0), zz, 0.0)
    h, w = zz.shape
    fx, fy, cx, cy = camera(cloud)
    return depth_to_cloud(zz, (w, h, fx, fy, cx, cy), depth_scale=1.0)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--sets", nargs="*", default=[])
    ap.add_argument("--clouds", nargs="*", default=[])
    ap.add_argument("--stairs", default=None)
    ap.add_argument("--perturb", nargs="*", default=[])
    ap.add_argument("--seeds", type=int, default=1)
    ap.add_argument("--json", default=None)
    a = ap.parse_args(argv)
    from real_census import set_folders
    from real_unseen import read_frame, read_labels
    from stairs_robust import frames

    rows = []
    cols = ["kind", "z", "s5", "s11", "s15", "corr", "wave", "win5", "win15", "win_used"]
    print("| frame | " + " | ".join(cols) + " |")
    print("|---" * (len(cols) + 1) + "|")

    def show(name, r):
        rows.append(dict(r, frame=name))
        print(f"| {name} | " + " | ".join(str(r[c]) for c in cols) + " |", flush=True)

    todo = [(n, c) for n, c, _, _ in frames(a.stairs, a.clouds, ())]
    for folder in set_folders(a.sets):
        for fr in read_labels(str(folder))["frames"]:
            c, _ = read_frame(str(folder), fr)
            todo.append((f"{folder.name}/{Path(fr['file']).stem}", c))
    for name, c in todo:
        try:
            show(name, measure_cloud(c))
        except Exception as e:  # a frame the estimate cannot read: say so, go on
            print(f"| {name} | error: {e} |")
        if name in a.perturb:
            for k in (0.002, 0.005):
                for sig in (0.0, 2.0, 4.0):
                    for seed in range(a.seeds):
                        r = measure_cloud(perturbed(c, k, sig, seed))
                        r["added"] = round(1000 * k * r["z"] ** 2, 2)
                        show(f"{name} +k{k} s{sig:g} seed{seed} (added {r['added']})", r)
    if a.json:
        Path(a.json).write_text(json.dumps(rows, indent=1))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
