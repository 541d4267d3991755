"""corner_top_edge.py MODEL DIR...: every corner(B, C) pair as main finds it (corner_slope off),
with each face's top edge as planerel.features.solid.top_edge measures it (slope in degrees,
span and rms in metres, bins counted), the ground-truth class where the set has one and the
class answered (ramp42, docs/results.md "A ramp seen from its side").  DIR as
gentle_ramps.py."""

import os
import re
import sys

import numpy as np

from planerel.classify.classifier import Classifier
from planerel.features.facts import FactParams, describe_scene, facts_text
from planerel.ilp.aleph_export import PAIRS
from planerel.ilp.scenes import segment_cached

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from gentle_ramps_items import items  # noqa: E402

import planerel.features.relations as R
from planerel.features.solid import top_edge

R.sloped_top = lambda *a: False  # every corner main finds

model = sys.argv[1]
with Classifier(model) as clf:
    for d in sys.argv[2:]:
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
            ans = clf.answer_description(desc, xyz=cloud.xyz)
            text = facts_text([desc], FactParams(pairs=PAIRS, planner=False))
            pairs = set(
                tuple(sorted(x)) for x in re.findall(r"^corner\((\w+), (\w+)\)", text, re.M)
            )
            if not pairs:
                continue
            lab = np.asarray(desc.labels)
            xyz = np.asarray(cloud.xyz).reshape(lab.shape + (3,))
            upv = np.asarray(desc.planes.up, float)
            byid = {desc.plane_id(p.label): p for p in desc.planes}
            tr = None
            if truth is not None and truth[0].endswith(".npy"):
                tr = np.load(truth[0].replace(".npy", ".objects.npy"))
                meta = truth[1]
            elif truth is not None:
                from PIL import Image

                meta = truth[1]
                ob = meta.get("files", {}).get("objects")
                tr = (
                    np.asarray(Image.open(os.path.join(os.path.dirname(truth[0]), ob))).astype(int)
                    if ob
                    else None
                )
            for a, b in sorted(pairs):
                cls = "?"
                if tr is not None:
                    mm = np.isin(lab, [byid[a].label, byid[b].label])
                    vals, cnt = np.unique(tr[mm], return_counts=True)
                    k = int(vals[np.argmax(cnt)])
                    cls = next(
                        (o["class"] for o in meta.get("objects", []) if o["index"] == k), "bg"
                    )
                pred = [f"{x.klass}" for x in ans if a in x.planes or b in x.planes]
                out = []
                for pid in (a, b):
                    t = top_edge(byid[pid], upv, lab, xyz)
                    out.append(
                        f"{pid} none"
                        if t is None
                        else f"{pid} slope {t.slope:5.1f} span {t.span:.2f} n {t.n:2d} rms {t.rms:.3f}"
                    )
                print(
                    f"{name:45s} {cls:7s} pred {','.join(pred) or '-':8s} | {' | '.join(out)}",
                    flush=True,
                )
