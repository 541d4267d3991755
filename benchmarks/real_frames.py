"""How cleanly real sensor frames segment: the Kinect frames and the mOSD scenes of
``../shared/data`` at 640x480 and subsampled by 2 and 4.

    .venv/bin/python benchmarks/real_frames.py [--param NAME=VALUE ...] [--png DIR]

Per frame and resolution (``segment()`` with the given parameters, default settings otherwise):

- ``regions``: regions found; ``big``: regions of at least 0.05 m^2 (hull area);
- ``in_big``: fraction of the valid pixels that lie in regions of at least 0.05 m^2;
- ``per_m2``: regions per square metre of segmented surface (regions / their summed hull area);
- ``support_pieces``: regions on the plane of the largest region (the floor, or mOSD's table):
  normals within 5 degrees of it and centroids within 3 cm of its plane, each holding at least
  0.5 % of the valid pixels (1 = the floor / table is one region);
- mOSD only, from the files' object labels (``label // 10`` >= 2 is an object; 1..9 the
  table): ``faces`` regions of at least 0.3 % of the image (0.05 % for the smaller objects'
  faces at /4 this is 2-3 pixels, so the threshold scales with the pixel count) lying at least
  80 % inside one object, per object; ``object_in_own`` the fraction of each object's pixels
  that lie in regions at least 80 % inside that object (the rest is unassigned or shared with
  the table or another object); ``table_largest`` the fraction of the table's pixels in the
  single region covering most of them; ``leaks``: regions with at least 20 % of their pixels
  on each of two of (table, object A, object B, ...).

With ``--png DIR`` the label images are written there (``NAME_sK.png``).  Run this file with
``PYTHONPATH`` pointing at another checkout to measure that code on the same frames.
"""

from __future__ import annotations

import argparse
import glob
import json
import math
import os
import sys
import time

import numpy as np


def _data_dir() -> str:
    from pathlib import Path

    return str(Path(__file__).resolve().parents[2] / "shared" / "data")


def _support_pieces(seg, cloud) -> int:
    valid = cloud.n_valid
    if not seg.planes:
        return 0
    big = max(seg.planes, key=lambda p: p.n_points)
    n = 0
    for p in seg.planes:
        if p.n_points < 0.005 * valid:
            continue
        ang = math.degrees(math.acos(min(1.0, abs(float(p.normal @ big.normal)))))
        dist = abs(float(big.normal @ p.centroid + big.offset))
        if ang <= 5.0 and dist <= 0.03:
            n += 1
    return n


def _areas(seg, cloud) -> dict:
    from planerel.features.planes import measure_planes

    ps = measure_planes(cloud, seg.labels, up=(0.0, -1.0, 0.0))
    return {p.label: p.area for p in ps}


def _mosd(seg, truth) -> dict:
    lab = seg.labels
    obj = np.where(truth >= 20, truth // 10, np.where(truth >= 1, 1, 0))  # 1 = table
    ids = [int(o) for o in np.unique(obj) if o >= 2]
    n_lab = seg.n_planes
    # (region, owner) pixel counts
    ok = lab >= 0
    owners = int(obj.max()) + 1
    cnt = np.bincount(lab[ok] * owners + obj[ok], minlength=n_lab * owners).reshape(n_lab, owners)
    size = cnt.sum(axis=1)
    min_face = 0.003 * lab.size
    out = {"faces": [], "object_in_own": [], "table_largest": None, "leaks": 0}
    for o in ids:
        inside = cnt[:, o] >= 0.8 * np.maximum(size, 1)
        out["faces"].append(int(np.sum(inside & (size >= min_face))))
        out["object_in_own"].append(round(float(cnt[inside, o].sum() / max(1, (obj == o).sum())), 3))
    table = int((obj == 1).sum())
    out["table_largest"] = round(float(cnt[:, 1].max() / table), 3) if table else None
    shares = cnt[:, 1:] >= 0.2 * np.maximum(size, 1)[:, None]
    out["leaks"] = int(np.sum(shares.sum(axis=1) >= 2))
    return out


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--param", action="append", default=[], metavar="NAME=VALUE")
    ap.add_argument("--png", default=None, metavar="DIR")
    ap.add_argument("--data", default=None, metavar="DIR")
    ap.add_argument("--json", default=None, metavar="FILE", help="also write the rows as JSON")
    args = ap.parse_args(argv)
    from planerel.io.cloud import subsample
    from planerel.io.readers import read, read_pcd_field
    from planerel.segment import segment

    params = {}
    for item in args.param:
        k, _, v = item.partition("=")
        params[k.strip()] = v.strip()
    data = args.data or _data_dir()
    files = sorted(glob.glob(os.path.join(data, "kinect", "*_depth.tiff")))
    files += sorted(glob.glob(os.path.join(data, "mosd", "learn*.pcd")))
    if not files:
        print(f"no Kinect / mOSD frames under {data}")
        return 0
    rows = []
    n_kinect = 0
    for f in files:
        name = os.path.basename(f).split(".")[0]
        if name.startswith("frame_"):
            n_kinect += 1
            name = f"kinect{n_kinect}"
        full = read(f)
        truth_full = read_pcd_field(f, "label").astype(np.int64) if f.endswith(".pcd") else None
        for k in (1, 2, 4):
            cloud = full if k == 1 else subsample(full, k)
            t0 = time.perf_counter()
            seg = segment(cloud, **params)
            ms = 1000 * (time.perf_counter() - t0)
            areas = _areas(seg, cloud)
            big = {lb for lb, a in areas.items() if a >= 0.05}
            in_big = float(np.isin(seg.labels, list(big)).sum()) / cloud.n_valid if big else 0.0
            row = {"frame": name, "sub": k, "regions": seg.n_planes, "big": len(big),
                   "in_big": round(in_big, 3),
                   "per_m2": round(seg.n_planes / max(sum(areas.values()), 1e-9), 2),
                   "support_pieces": _support_pieces(seg, cloud),
                   "ms": round(ms, 1)}
            if truth_full is not None:
                row.update(_mosd(seg, truth_full[::k, ::k]))
            rows.append(row)
            print(json.dumps(row))
            if args.png:
                from planerel.io.writers import write_labels_png

                os.makedirs(args.png, exist_ok=True)
                write_labels_png(os.path.join(args.png, f"{name}_s{k}.png"), seg.labels,
                                 cloud.depth)
    if args.json:
        with open(args.json, "w") as fh:
            json.dump(rows, fh, indent=1)
    return 0


if __name__ == "__main__":
    sys.exit(main())
