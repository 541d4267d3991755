"""Real staircases nobody on the team made: Kinect v2 frames with the sensor's own gravity.

    .venv/bin/python benchmarks/real_stairs.py [DIR] [--clouds FILE ...] [--model out/model]
        [--param NAME=VALUE ...] [--json F]

``DIR`` holds the sample frames of the public repository Shiaoming/stair-perception (BSD-3,
``samples/``; get it with ``git clone https://github.com/Shiaoming/stair-perception`` and give
its ``samples`` folder; the files are never copied into planerel):

* ``NNNN_depth.png``: a Kinect v2 depth frame, 512x424, 16-bit millimetres, 0 = no depth;
* ``NNNN_cloud.pcd``: the same frame as an organized cloud (PCL binary, page-padded) in the
  capture rig's IMU-levelled frame: its points are the depth frame's camera-frame points
  rotated (no translation), and its x axis points down (the floor lies at one x: 0.97-1.00 m
  in ``0000``, 0.59-0.60 m in ``0001``);
* ``NNNN_imu.txt``: the IMU's Euler angles (the first is the camera's pitch, degrees).

``--clouds`` adds organized clouds of other staircases (no gravity truth), e.g. the two
320x240 Kinect clouds of moatazelmasry2/stair_perception ``pcds/`` (no licence file: research
use): a terrazzo flight seen from 0.6-0.8 m, two treads and two risers, no floor in view.

``0000`` looks steeply down (about 76 degrees) at a two-step carpeted flight with rounded
nosings, a leg and a shoe on its lower step; ``0001`` looks along a five-step flight of the
same kind from 0.6 m up (about 27 degrees down), with furniture behind it.  Both have one
staircase and nothing else of the classes: the ground truth is "the flight is one proposal
answered ``stairs``, and nothing is answered ``box`` or ``ramp``".

Per frame the script prints:

* gravity: the angle between planerel's estimated up and the levelled frame's up (the
  rotation found by orthogonal Procrustes between the depth frame's camera points, with the
  intrinsics below, and the cloud's points), and the pitch both give against the IMU's;
* every proposal answered a class, with its planes' heights above the floor and its planar
  fraction, and the horizontal planes of at least 0.05 m^2 above the floor that are in no
  stairs proposal (a tread left out of the flight).

The Kinect v2 intrinsics of these frames, ``512,424,365.32,365.32,254.67,208.54``, were fitted
to the cloud files (least squares of the back-projected depth against the cloud: 0.3 mm median
residual; every frame gives the same values).
"""

from __future__ import annotations

import argparse
import glob
import json
import math
import os
import sys

import numpy as np

INTRINSICS = "512,424,365.32,365.32,254.67,208.54"


def levelled_up(cloud, pcd: str) -> np.ndarray | None:
    """Up ``(3,)`` in the camera frame from the levelled cloud file, or None when absent."""
    from planerel.io import readers

    if not os.path.exists(pcd):
        return None
    level = readers.read(pcd).xyz.reshape(-1, 3)
    cam = np.asarray(cloud.xyz, float).reshape(-1, 3)
    ok = np.isfinite(cam).all(1) & np.isfinite(level).all(1) & (np.abs(level).sum(1) > 0)
    if ok.sum() < 100:
        return None
    # orthogonal Procrustes: level ~ R @ cam
    u, _, vt = np.linalg.svd(level[ok].T @ cam[ok])
    R = u @ np.diag([1.0, 1.0, np.linalg.det(u @ vt)]) @ vt
    return -R.T[:, 0]  # the levelled frame's x axis points down


def imu_pitch(path: str) -> float | None:
    """The first Euler angle of a stair-perception ``NNNN_imu.txt`` (degrees)."""
    if not os.path.exists(path):
        return None
    lines = [ln for ln in open(path).read().splitlines() if ln and ln[0] in "-0123456789"]
    return float(lines[0].split(",")[0]) if lines else None


def pitch_down(up) -> float:
    """Degrees the optical axis (camera +z) points below the horizontal."""
    return math.degrees(math.asin(max(-1.0, min(1.0, -float(np.asarray(up)[2])))))


def frame(clf, depth: str) -> dict:
    """The figures of one frame: a stair-perception ``NNNN_depth.png`` (its levelled cloud
    and IMU file beside it) or an organized cloud file (``--clouds``: no gravity truth)."""
    import planerel
    from planerel.features.facts import describe_scene
    from planerel.ilp.scenes import segment_cached

    folder = os.path.dirname(depth)
    if depth.endswith("_depth.png"):
        stem = os.path.basename(depth)[: -len("_depth.png")]
        cloud = planerel.read(depth, intrinsics=INTRINSICS, depth_scale=1000)
    else:
        stem = os.path.splitext(os.path.basename(depth))[0]
        cloud = planerel.read(depth)
    labels = segment_cached(cloud, method=clf.method, params=clf.seg_params)
    desc = describe_scene(cloud, labels, scene_id=stem, **clf._describe_kw)
    ans = clf.classify(cloud, scene_id=stem)
    byl = {p.label: p for p in desc.planes}
    up = np.asarray(desc.planes.up, float)
    truth = levelled_up(cloud, os.path.join(folder, f"{stem}_cloud.pcd"))
    out = {"frame": stem, "planes": len(desc.planes), "objects": len(ans.objects),
           "up_source": desc.planes.up_source,
           "pitch_estimated": round(pitch_down(up), 2),
           "pitch_imu": imu_pitch(os.path.join(folder, f"{stem}_imu.txt"))}
    if truth is not None:
        out["gravity_error_deg"] = round(math.degrees(math.acos(
            min(1.0, abs(float(up @ truth)) / float(np.linalg.norm(truth))))), 2)
        out["pitch_levelled"] = round(pitch_down(truth / np.linalg.norm(truth)), 2)
    answered, in_stairs = [], set()
    for o in ans.objects:
        if o.klass == "other":
            continue
        labs = [lab for lab in o.labels if lab in byl]
        if o.klass == "stairs":
            in_stairs.update(labs)
        answered.append({"object": o.object_id, "class": o.klass, "rule": o.rule,
                         "planar_fraction": o.planar_fraction,
                         "treads_m": sorted(round(byl[x].height, 3) for x in labs
                                            if byl[x].orientation == "horizontal"),
                         "planes": len(labs)})
    out["answered"] = answered
    out["stairs"] = sum(a["class"] == "stairs" for a in answered)
    out["box_or_ramp"] = sum(a["class"] in ("box", "ramp") for a in answered)
    out["treads_left_out"] = sorted(
        round(p.height, 3) for p in desc.planes
        if p.orientation == "horizontal" and p.area >= 0.05 and p.height >= 0.05
        and p.label not in in_stairs)
    return out


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("folder", nargs="?", help="stair-perception's samples/ folder")
    ap.add_argument("--clouds", nargs="+", default=[], metavar="FILE",
                    help="organized staircase clouds too (e.g. moatazelmasry2/stair_perception's "
                         "pcds/*.pcd: a stone flight seen close, no floor in view)")
    ap.add_argument("--model", default="out/model")
    ap.add_argument("--param", action="append", default=[], metavar="NAME=VALUE")
    ap.add_argument("--json", help="write the figures here")
    a = ap.parse_args(argv)
    from planerel.classify.classifier import Classifier
    from planerel.commands.classify import _params

    depths = sorted(glob.glob(os.path.join(a.folder, "*_depth.png"))) if a.folder else []
    if a.folder and not depths:
        print(f"{a.folder}: no NNNN_depth.png frames (stair-perception's samples/ folder)",
              file=sys.stderr)
        return 2
    depths += a.clouds
    if not depths:
        ap.error("give stair-perception's samples/ folder or --clouds FILE ...")
    with Classifier(a.model, seg_params=_params(a.param)) as clf:
        rows = [frame(clf, d) for d in depths]
    for r in rows:
        g = r.get("gravity_error_deg")
        print(f"{r['frame']}: {r['planes']} planes, {r['objects']} objects; up {r['up_source']}"
              f"{'' if g is None else f', {g} deg from the levelled frame'}; pitch down "
              f"{r['pitch_estimated']} (levelled {r.get('pitch_levelled')}, IMU {r['pitch_imu']})")
        for x in r["answered"]:
            print(f"  {x['object']}: {x['class']}  planar fraction {x['planar_fraction']:.2f}, "
                  f"{x['planes']} planes, horizontal at {x['treads_m']} m")
        print(f"  stairs answers {r['stairs']}, box/ramp answers {r['box_or_ramp']}, "
              f"horizontal planes >= 0.05 m^2 outside a stairs answer at {r['treads_left_out']} m")
    ok = sum(r["stairs"] == 1 and r["box_or_ramp"] == 0 and not r["treads_left_out"] for r in rows)
    print(f"frames whose flight is one stairs answer and nothing else a class: {ok} of {len(rows)}")
    if a.json:
        with open(a.json, "w") as fh:
            json.dump(rows, fh, indent=1)
    return 0


if __name__ == "__main__":
    sys.exit(main())
