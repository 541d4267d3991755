"""Why are small box tops fitted off level?  For each named top plane of a labelled real frame:
its residuals by distance from its boundary, its normal refitted on the interior (eroded by
1-3 px), robustly (trimmed, Huber, RANSAC + refit) and on its points away from its cube's
upright faces, and a column section through it (top44, docs/segmentation.md "Small tops
fitted off level (top44)").

    nice .venv/bin/python benchmarks/small_tops.py SETDIR --model MODEL [--profile]
        [FRAME:TOP:FACE[,FACE...] ...]

``FRAME`` is a file of ``SETDIR/labels.json``, ``TOP`` and ``FACE`` are plane ids (``s_pNN``)
as ``planerel describe`` names them with ``MODEL``'s segmentation.  The default list is
hunt43's rs-booth cubes with main f7cbe8b's ``out/model`` (four missed tops, six found).
Inclines are degrees from the scene's up; every fit but ``pca``, ``huber`` and ``ransac`` is
planerel's own (:func:`planerel.features.disparity_fit.disparity_normals`).
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

import numpy as np
from scipy import ndimage

import planerel
from planerel.classify.classifier import Classifier
from planerel.features.disparity_fit import disparity_normals
from planerel.features.facts import describe_scene
from planerel.ilp.scenes import segment_cached

#: hunt43 rs-booth: (frame, top, the cube's upright faces, found by main's model)
DEFAULT = (
    "booth_1021_test1_depth.npy:s_p38:s_p30,s_p31:miss",
    "booth_1025_test1_depth.npy:s_p22:s_p11,s_p13:miss",
    "booth_test10_depth.npy:s_p14:s_p18:miss",
    "booth_test10_depth.npy:s_p15:s_p18:miss",
    "booth_test10_depth.npy:s_p30:s_p09:found",
    "booth_1020_test1_depth.npy:s_p19:s_p20,s_p21:found",
    "booth_1020_test4_depth.npy:s_p20:s_p21:found",
    "booth_1021_test4_depth.npy:s_p16:s_p17,s_p20:found",
    "booth_1025_test5_depth.npy:s_p25:s_p19:found",
    "booth_test15_depth.npy:s_p18:s_p21,s_p22:found",
)


def _incline(n, up) -> float:
    return float(np.degrees(np.arccos(min(1.0, abs(float(n @ up)) / float(np.linalg.norm(n))))))


def _pca(P):
    c = P.mean(0)
    return np.linalg.eigh(np.cov((P - c).T))[1][:, 0], c


def _disparity(xyz, mask):
    n, ok = disparity_normals(xyz, np.where(mask, 0, -1).astype(np.int32), np.array([0]))
    return n[0] if ok[0] else None


def _huber(P, k=1.345, iters=20):
    n, c = _pca(P)
    for _ in range(iters):
        r = (P - c) @ n
        s = 1.4826 * np.median(np.abs(r - np.median(r))) + 1e-9
        a = np.abs(r) / (k * s)
        w = np.where(a <= 1, 1.0, 1.0 / np.maximum(a, 1e-12))
        c = (w[:, None] * P).sum(0) / w.sum()
        n = np.linalg.eigh(((P - c) * w[:, None]).T @ (P - c))[1][:, 0]
    return n


def _ransac(P, thr, iters=500, seed=0):
    rng = np.random.default_rng(seed)
    best = np.zeros(len(P), bool)
    for _ in range(iters):
        s = P[rng.choice(len(P), 3, replace=False)]
        n = np.cross(s[1] - s[0], s[2] - s[0])
        if np.linalg.norm(n) < 1e-12:
            continue
        inl = np.abs((P - s[0]) @ (n / np.linalg.norm(n))) < thr
        if inl.sum() > best.sum():
            best = inl
    return _pca(P[best])[0], float(best.mean())


def measure(xyz, valid, desc, top, faces, profile=False) -> dict:
    """Fits of one top plane; prints its column section when ``profile``."""
    lab = np.asarray(desc.labels)
    up = np.asarray(desc.planes.up, float)
    by = {desc.plane_id(q.label): q for q in desc.planes}
    p = by[top]
    m = (lab == p.label) & valid
    P = xyz[m]
    d = ndimage.distance_transform_cdt(np.pad(m, 1), metric="chessboard")[1:-1, 1:-1]
    res = (P @ p.normal + p.offset) * 1000
    ring, inner = d[m] == 1, d[m] >= 5
    out = dict(px=int(m.sum()), fitted=p.incline, rms=p.rms * 1000,
               ring_rms=float(np.sqrt((res[ring] ** 2).mean())),
               inner_rms=float(np.sqrt((res[inner] ** 2).mean())) if inner.any() else float("nan"))
    for e in (1, 2, 3):
        me = m & (d > e)
        n = _disparity(xyz, me) if me.sum() >= 10 else None
        out[f"eroded{e}"] = _incline(n, up) if n is not None else float("nan")
    n0, c0 = _pca(P)
    r = np.abs((P - c0) @ n0)
    out["trim80"] = _incline(_pca(P[r <= np.quantile(r, 0.8)])[0], up)
    out["huber"] = _incline(_huber(P), up)
    nr, share = _ransac(P, 0.002)
    out["ransac2"], out["ransac2_share"] = _incline(nr, up), share
    away = np.full(m.shape, np.inf)
    for f in faces:
        q = by[f]
        away = np.minimum(away, np.abs(xyz @ q.normal + q.offset))
    for mm in (10, 20):
        mk = m & (away >= mm / 1000)
        n = _disparity(xyz, mk) if mk.sum() >= 30 else None
        out[f"away{mm}"] = _incline(n, up) if n is not None else float("nan")
        out[f"away{mm}_px"] = int(mk.sum())
    # the depth beyond the top's far edge: the 8 rows over each of its columns' first row
    rows, cols = np.nonzero(m)
    band = np.zeros_like(m)
    for c in np.unique(cols):
        r = rows[cols == c].min()
        band[max(0, r - 8):r, c] = True
    out["beyond_invalid"] = float(1.0 - valid[band].mean()) if band.any() else float("nan")
    if profile:
        r0, c0_, r1, c1 = p.bbox
        cm = (c0_ + c1) // 2
        view = P.mean(0)
        h = view - (view @ up) * up
        h /= np.linalg.norm(h)
        print(f"   section: columns {cm - 6}-{cm + 6}; T = the top, o = another plane, "
              "u = unassigned, blank = no depth; s = horizontal distance along the view, "
              "z = height along up (medians)")
        for row in range(max(0, r0 - 12), min(lab.shape[0], r1 + 12)):
            L, V = lab[row, cm - 6:cm + 7], valid[row, cm - 6:cm + 7]
            marks = "".join(" " if not v else "T" if x == p.label else "u" if x < 0 else "o"
                            for x, v in zip(L, V, strict=True))
            if V.any():
                Q = xyz[row, cm - 6:cm + 7][V]
                print(f"   row {row:3d} |{marks}| s {np.median(Q @ h) * 1000:6.1f} "
                      f"z {np.median(Q @ up) * 1000:7.1f} mm")
            else:
                print(f"   row {row:3d} |{marks}|")
        z = xyz @ up * 1000
        ref = float(np.quantile(z[m], 0.9))
        print(f"   heights over the top, mm below its highest tenth ({ref:.1f}), medians of 4x4 px "
              f"blocks (rows {r0}-{r1}, far at the top; columns {c0_}-{c1}; '.' = < 4 px)")
        for row in range(r0, r1, 4):
            cells = []
            for col in range(c0_, c1, 4):
                b = m[row:row + 4, col:col + 4]
                cells.append(f"{np.median(z[row:row + 4, col:col + 4][b]) - ref:4.0f}"
                             if b.sum() >= 4 else "   .")
            print(f"   {row:3d} " + "".join(cells))
    return out


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("set", type=Path)
    ap.add_argument("tops", nargs="*", default=list(DEFAULT))
    ap.add_argument("--model", required=True)
    ap.add_argument("--profile", action="store_true")
    a = ap.parse_intermixed_args(argv)
    doc = json.loads((a.set / "labels.json").read_text())
    frames = {fr["file"]: fr for fr in doc["frames"]}
    cache = {}
    print("frame top (state): px, incline as fitted; RMS mm (1-px ring / >= 5 px in); "
          "eroded 1/2/3 px; trimmed 80 %; Huber; RANSAC 2 mm (inliers); >= 10 / 20 mm from "
          "the faces (px); invalid share of the 8 rows beyond its far edge")
    with Classifier(a.model) as clf:
        for spec in a.tops:
            parts = spec.split(":")
            name, top, faces = parts[0], parts[1], parts[2].split(",") if len(parts) > 2 else []
            state = parts[3] if len(parts) > 3 else ""
            if name not in cache:
                fr = frames[name]
                cloud = planerel.read(a.set / name, intrinsics=fr.get("intrinsics"),
                                      depth_scale=fr.get("depth_scale"))
                labels = segment_cached(cloud, method=clf.method, params=clf.seg_params)
                cache[name] = (cloud, describe_scene(cloud, labels, scene_id="s", up=None,
                                                     **clf._describe_kw))
            cloud, desc = cache[name]
            print(f"{name} {top} ({state})")
            o = measure(cloud.xyz, cloud.valid, desc, top, faces, a.profile)
            print(f"   {o['px']} px, {o['fitted']:.1f}; RMS {o['rms']:.1f} ({o['ring_rms']:.1f} / "
                  f"{o['inner_rms']:.1f}); eroded {o['eroded1']:.1f} / {o['eroded2']:.1f} / "
                  f"{o['eroded3']:.1f}; trimmed {o['trim80']:.1f}; Huber {o['huber']:.1f}; "
                  f"RANSAC {o['ransac2']:.1f} ({o['ransac2_share']:.0%}); away "
                  f"{o['away10']:.1f} ({o['away10_px']}) / {o['away20']:.1f} ({o['away20_px']}); "
                  f"beyond the far edge {o['beyond_invalid']:.0%} invalid")
    return 0


if __name__ == "__main__":
    sys.exit(main())
