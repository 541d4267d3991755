"""How staircase detection on real frames degrades under sensor and calibration errors (srob58,
docs/objects.md "Staircases under perturbed depth").  A measuring tool.

Usage::

    stairs_robust.py [--stairs DIR] [--clouds FILE ...] [--sets DIR ...] [--model out/model]
        [--only NAME ...] [--seeds N] [--param NAME=VALUE ...] [--json F]

Frames: ``--stairs`` stair-perception's samples (``NNNN_depth.png``, :mod:`real_stairs`
intrinsics), ``--clouds`` organized staircase clouds without labels (elmasry's PCDs; their
intrinsics are fitted to the cloud), ``--sets`` labelled set folders (:mod:`real_unseen`).
An unlabelled frame's flight is the whole image (found when a ``stairs`` answer exists; every
``box``/``ramp`` answer is false).  Each frame's depth ``Z`` ``(H, W)`` (metres) and camera
are re-read under each perturbation and re-projected into a cloud:

``f x0.85 .. x1.15``   the cloud re-projected with ``fx, fy`` scaled (wrong intrinsics);
``cx+20``, ``cy+20``   the principal point off by 20 px;
``res /2``, ``res /4`` every 2nd / 4th pixel of each row and column, intrinsics scaled (the
                       labelled rectangles too);
``noise k``            ``Z + k Z^2 n``, ``n`` unit Gaussian noise smoothed over 4 px (a D4xx's
                       spatially correlated depth error), ``k`` in 1/m;
``quant q``            ``Z`` rounded to ``q`` m;
``holes p``            random blobs (noise smoothed over 1/40 of the image width, thresholded)
                       covering ``p`` of the valid pixels made invalid;
``z x s``              ``Z`` scaled by ``s`` (a depth-scale error).

The frame's ``up`` (when its labels give one) is kept.  Per perturbation it prints the flights
found (:func:`real_unseen.score_frame`), the false ``stairs``/``box``/``ramp`` answers, and for
every flight lost the stage :func:`stairs_census.flight_row` names.  Noise and holes are drawn
with ``--seeds`` seeds (0, 1, ...).
"""

from __future__ import annotations

import argparse
import glob
import json
import os
import sys
from collections import Counter
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))

STAIRS = "stairs"


def _smooth(field: np.ndarray, sigma: float) -> np.ndarray:
    """``field`` smoothed by a Gaussian of ``sigma`` px and scaled to unit standard deviation."""
    from scipy.ndimage import gaussian_filter

    s = gaussian_filter(field, sigma, mode="reflect")
    return s / max(float(s.std()), 1e-12)


def perturbations() -> list:
    """``[(name, function)]``; ``function(Z, (fx, fy, cx, cy), rng)`` gives
    ``(Z', (fx', fy', cx', cy'), step)``, ``step`` the pixel subsampling (1: none)."""
    out = [("none", lambda z, k, r: (z, k, 1))]
    for s in (0.85, 0.9, 1.1, 1.15):
        out.append((f"f x{s}", lambda z, k, r, s=s: (z, (k[0] * s, k[1] * s, k[2], k[3]), 1)))
    out.append(("cx+20", lambda z, k, r: (z, (k[0], k[1], k[2] + 20, k[3]), 1)))
    out.append(("cy+20", lambda z, k, r: (z, (k[0], k[1], k[2], k[3] + 20), 1)))
    for n in (2, 4):
        out.append((f"res /{n}", lambda z, k, r, n=n: (
            z[::n, ::n], (k[0] / n, k[1] / n, k[2] / n, k[3] / n), n)))
    for c in (0.002, 0.005):
        out.append((f"noise {c}", lambda z, k, r, c=c: (
            z + c * z ** 2 * _smooth(r.standard_normal(z.shape), 4.0), k, 1)))
    for q in (0.001, 0.01):
        out.append((f"quant {q}", lambda z, k, r, q=q: (np.round(z / q) * q, k, 1)))
    for p in (0.1, 0.3):
        def holes(z, k, r, p=p):
            f = _smooth(r.standard_normal(z.shape), max(2.0, z.shape[1] / 40))
            ok = np.isfinite(z)
            cut = np.quantile(f[ok], 1 - p)
            return np.where(ok & (f > cut), np.nan, z), k, 1
        out.append((f"holes {p}", holes))
    for s in (0.97, 1.03):
        out.append((f"z x{s}", lambda z, k, r, s=s: (z * s, k, 1)))
    return out


def frames(stairs_dir=None, clouds=(), sets=()) -> list:
    """``[(name, cloud, up, objects)]``: ``objects`` the labelled ones (``class``, ``box``),
    or one ``stairs`` rectangle over the whole image for an unlabelled frame."""
    from real_census import set_folders
    from real_stairs import INTRINSICS
    from real_unseen import read_frame, read_labels

    import planerel

    out = []

    def whole(c):
        h, w = c.shape
        return [{"class": STAIRS, "box": [0, 0, w, h], "what": "whole frame"}]

    if stairs_dir:
        for p in sorted(glob.glob(os.path.join(stairs_dir, "*_depth.png"))):
            c = planerel.read(p, intrinsics=INTRINSICS, depth_scale=1000)
            out.append((f"stair-perception/{Path(p).stem}", c, None, whole(c)))
    for p in clouds:
        c = planerel.read(p)
        out.append((f"{Path(p).parent.name}/{Path(p).stem}", c, None, whole(c)))
    for folder in set_folders(sets):
        doc = read_labels(str(folder))
        for fr in doc["frames"]:
            if not any(o["class"] == STAIRS for o in fr.get("objects", [])):
                continue
            c, up = read_frame(str(folder), fr)
            out.append((f"{folder.name}/{Path(fr['file']).stem}", c, up, fr["objects"]))
    return out


def camera(cloud) -> tuple:
    """``(fx, fy, cx, cy)`` of an organized cloud: its intrinsics, else fitted to its points."""
    from planerel.io.readers import estimate_intrinsics

    k = cloud.intrinsics or estimate_intrinsics(np.asarray(cloud.xyz), approximate=0.5)
    if k is None:
        raise ValueError(f"{cloud.source}: no intrinsics and none fit")
    return (k.fx, k.fy, k.cx, k.cy)


def run_one(clf, cloud, up, objects, fn, rng) -> list:
    """Flights of one perturbed frame: ``[dict]`` (``found``, ``stage``, ...) and the false
    answers, as ``(rows, false)``."""
    from real_unseen import rect_mask, score_frame
    from stairs_census import flight_row

    from planerel.features.facts import describe_scene
    from planerel.ilp.scenes import segment_cached
    from planerel.io.cloud import depth_to_cloud

    z0 = np.asarray(cloud.depth, float)
    z, (fx, fy, cx, cy), step = fn(z0, camera(cloud), rng)
    z = np.where(np.isfinite(z) & (z > 0), z, 0.0)
    h, w = z.shape
    c = depth_to_cloud(z, (w, h, fx, fy, cx, cy), depth_scale=1.0)
    objs = [dict(o, box=[v / step for v in o["box"]]) for o in objects]
    labels = segment_cached(c, method=clf.method, params=clf.seg_params)
    desc = describe_scene(c, labels, scene_id="s", up=up, **clf._describe_kw)
    answers = clf.answer_description(desc, xyz=c.xyz)
    fake = type("A", (), {"labels": np.asarray(desc.labels), "objects": answers})
    scored = score_frame(fake(), {"objects": objs})
    rows = []
    for o, s in zip(objs, scored["objects"], strict=True):
        if o["class"] != STAIRS:
            continue
        m = rect_mask((h, w), o["box"])
        r = flight_row(clf, desc, answers, m, s["found"], desc_xyz=c.xyz)
        rows.append({"found": s["found"], "stage": r["stage"], "called": s["called"],
                     "treads": r["treads"], "risers": r["risers"], "steps": r["steps_inside"]})
    return rows, [f[0] for f in scored["false"]]


def measure(model: str, frame_list, only=(), seeds: int = 1, params=()) -> list:
    """One row per (perturbation, seed, frame, flight); ``params`` ``NAME=VALUE`` settings
    (as ``planerel classify --param``)."""
    from planerel.classify.classifier import Classifier
    from planerel.commands.classify import _params

    out = []
    with Classifier(model, seg_params=_params(list(params))) as clf:
        for name, fn in perturbations():
            if only and name not in only and name != "none":
                continue
            random = name.startswith(("noise", "holes"))
            for seed in range(seeds if random else 1):
                for fname, cloud, up, objects in frame_list:
                    rng = np.random.default_rng(seed)
                    rows, false = run_one(clf, cloud, up, objects, fn, rng)
                    for i, r in enumerate(rows):
                        out.append({"perturbation": name, "seed": seed, "frame": fname,
                                    "flight": i, **r, "false": false if i == 0 else []})
                    print(f"{name} s{seed} {fname}: "
                          f"{' '.join(r['stage'] for r in rows)}; false {false}",
                          file=sys.stderr, flush=True)
    return out


def table(rows) -> list:
    """Per perturbation: flights found of judged, false answers by class, lost stages."""
    lines = []
    for name in dict.fromkeys(r["perturbation"] for r in rows):
        these = [r for r in rows if r["perturbation"] == name]
        found = sum(r["found"] for r in these)
        false = Counter(k for r in these for k in r["false"])
        lost = Counter(r["stage"] for r in these if not r["found"])
        who = sorted({r["frame"] for r in these if not r["found"]})
        lines.append(f"{name:12s} found {found}/{len(these)}  false stairs {false['stairs']} "
                     f"box {false['box']} ramp {false['ramp']}  lost {dict(lost)} {who}")
    return lines


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--stairs", help="stair-perception's samples folder")
    ap.add_argument("--clouds", nargs="*", default=[], metavar="FILE")
    ap.add_argument("--sets", nargs="*", default=[], metavar="DIR")
    ap.add_argument("--model", default="out/model")
    ap.add_argument("--only", nargs="*", default=[], metavar="NAME")
    ap.add_argument("--seeds", type=int, default=1)
    ap.add_argument("--param", action="append", default=[], metavar="NAME=VALUE")
    ap.add_argument("--json")
    a = ap.parse_args(argv)
    fl = frames(a.stairs, a.clouds, a.sets)
    if not fl:
        ap.error("no staircase frames: give --stairs, --clouds or --sets")
    rows = measure(a.model, fl, a.only, a.seeds, a.param)
    print("\n".join(table(rows)))
    if a.json:
        Path(a.json).write_text(json.dumps(rows, indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main())
