"""gentle_ramps.py MODEL DIR...: every plane of 0.5 m^2 or more (MINAREA) that is no floor, faces
up with the camera above it and is inclined MAXINC degrees or less (default 10): its incline,
its tilt against the floor's own plane (rel), its points' 1st/99th percentile heights over that
plane (low, high), its least distance to the floor's points (adj), its farthest depth and the
measured depth noise there (ramp42, docs/results.md "A ramp seen from its side; gentle ramps
against the floor").  DIR: an independent set (i*.npy), a labelled real set (labels.json), a
synthetic data set (s*.json) or a folder of .pcd clouds."""

import json
import math
import os
import sys

import numpy as np

from planerel.classify.classifier import Classifier
from planerel.features.facts import describe_scene
from planerel.features.planes import _measured_noise
from planerel.ilp.scenes import segment_cached

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from gentle_ramps_items import items  # noqa: E402

model = sys.argv[1]
dirs = sys.argv[2:]
MAXINC = float(os.environ.get("MAXINC", 10))
MINAREA = float(os.environ.get("MINAREA", 0.5))


with Classifier(model) as clf:
    for d in dirs:
        for name, load, truth, up in items(d):
            cloud = load()
            labels = segment_cached(cloud, method=clf.method, params=clf.seg_params)
            desc = describe_scene(
                cloud,
                labels,
                scene_id="s",
                up=None if up is None else np.asarray(up, float),
                **clf._describe_kw,
            )
            ps = desc.planes
            upv = np.asarray(ps.up)
            lab = np.asarray(desc.labels)
            xyz = np.asarray(cloud.xyz).reshape(lab.shape + (3,))
            floor = next((p for p in ps if p.is_floor), None)
            noise = None
            for p in ps:
                if p.is_floor or p.area < MINAREA or p.incline > MAXINC:
                    continue
                pts = xyz[lab == p.label]
                pts = pts[np.isfinite(pts).all(1)]
                # camera above and plane facing up: camera's height over the plane
                cam_h = -float(
                    (pts.mean(0)) @ upv
                )  # camera at origin; height of camera over centroid along up
                if cam_h <= 0:
                    continue
                if noise is None:
                    noise = _measured_noise(cloud) or False
                zfar = float(pts[:, 2].max())
                sig = float(noise.sigma(zfar)) if noise else float("nan")
                tilt_allow = (
                    math.degrees(math.atan(2 * sig / p.width))
                    if noise and p.width > 0
                    else float("nan")
                )
                cls = ""
                if truth is not None:
                    path, meta = truth
                    on = os.path.exists(path.replace(".npy", ".objects.npy"))
                    if path.endswith(".npy") and on:
                        t = np.load(path.replace(".npy", ".objects.npy"))
                        vals, cnt = np.unique(t[lab == p.label], return_counts=True)
                        k = int(vals[np.argmax(cnt)])
                        cls = next(
                            (o["class"] for o in meta.get("objects", []) if o["index"] == k),
                            f"bg{k}",
                        )
                        cls += (
                            ":{:.2f}".format(meta.get("params", {}).get("angle_deg", float("nan")))
                            if cls == "ramp"
                            else ""
                        )
                    else:
                        cls = meta.get("class", "")
                        a = [o for o in json.dumps(meta).split('"angle_deg": ')[1:]]
                        if a:
                            cls += ":" + a[0].split(",")[0][:5]
                rel = low = high = adj = fl_inc = float("nan")
                if floor is not None:
                    fn = np.asarray(floor.normal, float)
                    fn = fn if fn @ upv > 0 else -fn
                    fpts = xyz[lab == floor.label]
                    fpts = fpts[np.isfinite(fpts).all(1)]
                    fc = fpts.mean(0)
                    pn = np.asarray(p.normal, float)
                    pn = pn if pn @ upv > 0 else -pn
                    rel = math.degrees(math.acos(min(1, abs(float(fn @ pn)))))
                    h = (pts - fc) @ fn
                    low, high = np.percentile(h, 1), np.percentile(h, 99)
                    fl_inc = floor.incline
                    sub = fpts[:: max(1, len(fpts) // 3000)]
                    sp = pts[:: max(1, len(pts) // 1500)]
                    dd = np.sqrt(((sp[:, None, :] - sub[None, :, :]) ** 2).sum(-1)).min()
                    adj = float(dd)
                print(
                    f"{name:55s} p{p.label:<3d} {p.orientation[:5]:5s} inc {p.incline:5.2f} area {p.area:5.2f} w {p.width:4.2f} zfar {zfar:5.2f} sig {sig * 1000:5.1f}mm allow {tilt_allow:4.1f} | floor {'-' if floor is None else floor.label} finc {fl_inc:4.2f} rel {rel:5.2f} low {low:+.3f} high {high:+.3f} adj {adj:.3f} | {cls}",
                    flush=True,
                )
