"""Why region growing leaves a labelled area of a real frame without a plane (wave50).

For each target (a labelled rectangle of a real development frame: the boxes that
``real_census.py --json`` scores "no plane in it", and any extra rectangles such as a floor),
prints one JSON line: the share of valid and unassigned pixels, the median depth, the noise
model (5x5-patch sigma at that depth, ``wave``), the settings region growing used (normal
window, minimum region, the median delta of the depth bands), the median RMS of 3-D plane fits
over square windows of 5 / 9 / 15 pixels lying in the rectangle (>= 90 % valid, grid step half
a window), how far the pixels' normals lie from their 15 px window's plane (median / 90 %
quantile, degrees), the share of valid pixels with fewer than ``min_neighbour_num`` (4)
delta-neighbours and the share passing the seed test (every delta-neighbour's normal within
``theta * angle_mf``); then, for the default (``split.wavy_leftover`` off, as main before
wave50) and one relaxed setting at a time, the share of the rectangle's valid pixels in
planes lying >= 50 % inside it (a floor target: in any plane) and the largest such plane's
share.  A setting that gives planes where the default gives none names the test that stops
the growth.

Usage::

    python benchmarks/real_census.py SET... --model MODEL --json census.json
    python benchmarks/no_plane_why.py --census census.json [--extra extra.json] [--aggregate]

``--aggregate`` prints only medians and counts over the targets (no frame names or values):
for a judge set, whose frames are not read one by one.

``--small-pass`` follows each target through the small pass (``small_scale`` 0.35, docs/
segmentation.md "Block tops seen from above") instead: the stage that loses it
(:func:`small_stage`: no region of the second growing mostly in the rectangle; the region not
lying in depth the first growing left free; its fit over the bound; not kept by the
standing-over test, and whether ``small_corners`` would keep it; kept).

``extra.json``: a list of ``{"set": DIR, "file": NAME, "rect": [x0, y0, x1, y1], "name": TEXT,
"kind": "floor"}``.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import sys
from collections import Counter

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

from real_unseen import rect_mask  # noqa: E402

import planerel  # noqa: E402
from planerel.segment import segment  # noqa: E402
from planerel.segment._workspace import _workspace  # noqa: E402

#: The default as main had it, then one relaxed setting at a time, then the default.
OFF = {"split.wavy_leftover": False}
VARIANTS = (("main", OFF), ("min_region_scale 0.25", {**OFF, "min_region_scale": 0.25}),
            ("theta 25", {**OFF, "theta": 25.0}), ("delta_factor 12", {**OFF, "delta_factor": 12.0}),
            ("min_neighbour_num 2", {**OFF, "min_neighbour_num": 2}),
            ("normal window 6", {**OFF, "normal_smooth": 6, "normal_radius": 6}),
            ("split off", {**OFF, "split": False}), ("small_scale 0.35", {"small_scale": 0.35, "small_pitch": 0.0}),
            ("default", {}))
#: Grid steps of the eight neighbours, in the delta graph's bit order.
DV = (0, 1, 1, 1, 0, -1, -1, -1)
DU = (1, -1, 0, 1, -1, 1, 0, -1)


def census_targets(path):
    """The census rows scored "no plane in it" as targets."""
    out = []
    for row in json.load(open(path)):
        if not row["stage"].startswith("no plane"):
            continue
        folder = row["set"] if os.path.isabs(row["set"]) else os.path.join("/work", row["set"])
        doc = json.load(open(os.path.join(folder, "labels.json")))
        names = [fr["file"] for fr in doc["frames"]
                 if os.path.splitext(fr["file"])[0] == row["frame"]]
        out.append({"set": folder, "file": names[0], "rect": row["box"],
                    "name": f"{row['set']} {row['frame']} box {row['box']}"})
    return out


def load(folder, name):
    doc = json.load(open(os.path.join(folder, "labels.json")))
    fr = [x for x in doc["frames"] if x["file"] == name][0]
    return planerel.read(os.path.join(folder, name), intrinsics=fr.get("intrinsics"),
                         depth_scale=fr.get("depth_scale"))


def window_fits(xyz, m, k):
    """``(rms, normal, y, x)`` of the 3-D plane fit of every k x k window inside ``m``."""
    ys, xs = np.nonzero(m)
    out = []
    st = max(1, k // 2)
    for y in range(ys.min(), ys.max() + 2 - k, st):
        for x in range(xs.min(), xs.max() + 2 - k, st):
            if not m[y:y + k, x:x + k].all():
                continue
            p = xyz[y:y + k, x:x + k].reshape(-1, 3)
            p = p[np.isfinite(p).all(1)]
            if len(p) < 0.9 * k * k:
                continue
            c = p - p.mean(0)
            ev, vec = np.linalg.eigh(c.T @ c / len(p))
            out.append((math.sqrt(max(ev[0], 0.0)), vec[:, 0], y, x))
    return out


def seedable(mask, nrm, cos_seed):
    """Pixels whose delta-neighbours' normals all lie within ``cos_seed`` of their own."""
    h, w = mask.shape
    ok = np.ones((h, w), bool)
    for b in range(8):
        has = ((mask >> b) & 1).astype(bool)
        sh = np.full_like(nrm, np.nan)
        dv, du = DV[b], DU[b]
        sh[max(0, -dv):h - max(0, dv), max(0, -du):w - max(0, du)] = \
            nrm[max(0, dv):h - max(0, -dv), max(0, du):w - max(0, -du)]
        dot = np.nan_to_num((nrm * sh).sum(2), nan=-2.0)
        ok &= ~has | (dot >= cos_seed)
    return ok


def measure(t):
    cloud = load(t["set"], t["file"])
    xyz = cloud.xyz
    m = rect_mask(xyz.shape[:2], t["rect"])
    valid = cloud.valid & m
    zz = float(np.median(xyz[..., 2][valid]))
    seg = segment(cloud, **OFF)
    mask = _workspace(*xyz.shape[:2]).mask.copy()  # the delta graph of that call
    info, nm, st = seg.info, seg.info["noise_model"], seg.info["settings"]
    nrm = np.asarray(seg.normals, float)
    nb = sum(((mask >> b) & 1).astype(int) for b in range(8))
    nval = np.isfinite(nrm).all(2)
    lab = np.asarray(seg.labels)
    r = {"name": t["name"], "px": int(m.sum()), "valid": round(float(valid.sum() / m.sum()), 2),
         "z": round(zz, 2)}
    sig = math.sqrt(nm["const_m"] ** 2 + (nm["quad_per_m"] * zz * zz) ** 2)
    r["model"] = f"{nm['kind']} sigma {1000 * sig:.2f} mm, wave {nm['wave']:.1f}"
    r["window/min/delta"] = (f"{st['normal_smooth']}/{st['normal_radius']} {info['min_region_size']} "
                             f"{1000 * info['delta']:.0f} mm")
    r["unassigned"] = round(float(((lab < 0) & valid).sum() / valid.sum()), 2)
    for k in (5, 9, 15):
        f = window_fits(xyz, valid, k)
        r[f"rms{k}"] = round(1000 * float(np.median([a[0] for a in f])), 2) if f else None
    angs = []
    for _rms, n, y, x in window_fits(xyz, valid, 15):
        nn = nrm[y:y + 15, x:x + 15].reshape(-1, 3)
        nn = nn[np.isfinite(nn).all(1)]
        angs.extend(np.degrees(np.arccos(np.clip(np.abs(nn @ n), 0, 1))).tolist())
    r["normals_off"] = f"{np.median(angs):.1f}/{np.percentile(angs, 90):.1f}" if angs else None
    r["few_neighbours"] = round(float((valid & (nb < 4)).sum() / valid.sum()), 2)
    ok = seedable(mask, nrm, math.cos(math.radians(7.5)))
    r["seedable"] = round(float((valid & nval & (nb >= 4) & ok).sum() / valid.sum()), 2)
    res = {}
    for name, kw in VARIANTS:
        lab2 = lab if name == "main" else np.asarray(segment(cloud, **kw).labels)
        ids, cnt = np.unique(lab2[valid & (lab2 >= 0)], return_counts=True)
        tot = big = 0
        for i, c in zip(ids, cnt, strict=True):
            if t.get("kind") == "floor" or c / (lab2 == i).sum() >= 0.5:
                tot += int(c)
                big = max(big, int(c))
        res[name] = f"{tot / valid.sum():.2f}/{big / valid.sum():.2f}"
    r["planes_in_rect"] = res
    return r


SMALL_STAGES = ("no region", "not free", "fit over bound", "not kept", "kept")


def small_stage(cloud, rect, small_scale=0.35, seg=None):
    """``(stage, measures)``: where the small pass (``small_scale``) loses the box in ``rect``
    ((x0, y0, x1, y1)) of ``cloud``, the pass's own steps (:func:`planerel.segment.
    _small_growing`, ``_free_regions``, ``_small_kept``) run on the first growing ``seg``
    (default :func:`segment` of the cloud).  ``stage`` is one of :data:`SMALL_STAGES`; the
    region followed is the second growing's with the most pixels in the rectangle among those
    lying half or more in it.  ``measures``: its pixels, free share, fit over the noise and
    bound, whether ``small_corners`` keeps it, and the angle (degrees) to the closest plane
    within the standing-over reach."""
    import dataclasses

    import planerel.segment as S
    from planerel.segment.params import SMALL_SHARE

    seg = seg if seg is not None else segment(cloud)
    p = dataclasses.replace(seg.params, small_scale=small_scale)
    free = S._near_free(cloud, seg, p.far_depth)
    size = max(1, round(small_scale * int(seg.info.get("min_region_size", 0) or 0)))
    wl, sigma = S._small_growing(cloud, seg, p, None, size)
    m = rect_mask(wl.shape, rect) & np.asarray(cloud.valid)
    ids, cnt = np.unique(wl[m & (wl >= 0)], return_counts=True)
    total = np.bincount(wl[wl >= 0], minlength=int(ids.max()) + 1 if len(ids) else 0)
    mostly = [(c, i) for i, c in zip(ids.tolist(), cnt.tolist(), strict=True) if c >= 0.5 * total[i]]
    if not mostly:
        return "no region", {"largest_in_rect": int(cnt.max()) if len(cnt) else 0}
    r = max(mostly)[1]
    reg = wl == r
    out = {"px": int(total[r]), "free": round(float((reg & free).sum() / total[r]), 2)}
    one = np.where(reg, wl, -1)  # the region alone, through the pass's own tests
    bound = S._near_rms_max(seg, p, sigma)
    lab2, added, fit = S._free_regions(cloud, seg, one, free, size, bound, SMALL_SHARE, sigma)
    out["bound"] = round(float(bound), 2)
    if fit:
        out["fit"] = fit[0]
    if not fit:
        return "not free", out
    if not added:
        return "fit over bound", out
    # kept or not among every candidate of the pass, as the pass judges them (a block's top
    # may stand over, or meet at a corner, another block's new plane)
    n = len(seg.planes)
    full, added_all, _fit = S._free_regions(cloud, seg, wl, free, size, bound, SMALL_SHARE, sigma)
    label = int(full[reg & free].max())

    def keeps(corners):
        kept_lab = S._small_kept(cloud, seg, full, added_all, corners=corners)[0]
        return bool((kept_lab[full == label] >= n).any())

    kept = keeps(False)
    out["corners_keep"] = keeps(True)
    from scipy.ndimage import binary_dilation

    own = full == label
    ring = binary_dilation(own, iterations=2 + S._window(seg)) & (full >= 0) & ~own
    near = np.unique(full[ring]).tolist()
    if near:
        def normal(k):
            if k < n:
                return np.asarray(seg.planes[k].normal, float)
            pts = np.asarray(cloud.xyz)[full == k].astype(float)
            return np.linalg.svd(pts - pts.mean(0), full_matrices=False)[2][-1]

        nj = normal(label)
        out["closest_angle"] = round(min(math.degrees(math.acos(min(1.0, abs(float(
            nj @ normal(k)))))) for k in near), 1)
    return ("kept" if kept else "not kept"), out


def _num(v):
    """The leading number of a measured value (``"1.2/3.4"`` -> 1.2), None if there is none."""
    if isinstance(v, (int, float)):
        return float(v)
    try:
        return float(str(v).split("/")[0].split()[0])
    except (ValueError, IndexError):
        return None


def aggregate(rows) -> list[str]:
    """Lines of medians (with the 10-90 % range) over the targets, and per setting the
    number of targets whose rectangle's valid depth lies half or more in planes."""
    out = [f"targets {len(rows)}"]
    if not rows:
        return out
    for key in ("px", "valid", "z", "unassigned", "rms5", "rms9", "rms15", "normals_off",
                "few_neighbours", "seedable"):
        v = [x for x in (_num(r.get(key)) for r in rows) if x is not None]
        if v:
            out.append(f"{key}: median {np.median(v):.3g} (10-90 % {np.percentile(v, 10):.3g}"
                       f"-{np.percentile(v, 90):.3g}, {len(v)} values)")
    sig = [_num(r["model"].split("sigma")[1]) for r in rows]
    out.append(f"noise sigma at the box (mm): median {np.median(sig):.3g}")
    out.append("window/min/delta: " + ", ".join(sorted({r["window/min/delta"] for r in rows})))
    for name, _kw in VARIANTS:
        share = [_num(r["planes_in_rect"][name]) for r in rows]
        out.append(f"{name}: in planes >= 0.5 for {sum(s >= 0.5 for s in share)} of {len(rows)}, "
                   f"median share {np.median(share):.2f}")
    return out


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--census", help="real_census.py --json output")
    ap.add_argument("--extra", help="a JSON list of further targets")
    ap.add_argument("--small-pass", action="store_true",
                    help="the stage of the small pass (small_scale 0.35) that loses each target")
    ap.add_argument("--aggregate", action="store_true",
                    help="print only medians and counts over the targets (for a judge set)")
    a = ap.parse_args(argv)
    targets = (census_targets(a.census) if a.census else []) + \
        (json.load(open(a.extra)) if a.extra else [])
    if a.small_pass:
        stages, measures = Counter(), {}
        for t in targets:
            st, ms = small_stage(load(t["set"], t["file"]), t["rect"])
            stages[st] += 1
            stages["  small_corners keeps"] += bool(ms.get("corners_keep"))
            for k, v in ms.items():
                measures.setdefault(k, []).append(float(v))
            if not a.aggregate:
                print(json.dumps({"name": t["name"], "stage": st, **ms}), flush=True)
        print(f"targets {len(targets)}: " + ", ".join(f"{k} {v}" for k, v in stages.items()))
        for k, v in measures.items():
            print(f"{k}: median {np.median(v):.3g} ({len(v)} values)")
        return
    rows = []
    for t in targets:
        rows.append(measure(t))
        if not a.aggregate:
            print(json.dumps(rows[-1]), flush=True)
    if a.aggregate:
        print("\n".join(aggregate(rows)))


if __name__ == "__main__":
    main()
