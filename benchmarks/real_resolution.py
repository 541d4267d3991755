"""Do the answers on real frames hold when the same frame comes at half (or double) resolution?

    .venv/bin/python benchmarks/real_resolution.py DIR [DIR ...] [--model out/model]
        [--mode decimate|median|double] [--param NAME=VALUE ...] [--json F]
        [--osd DIR] [--uois DIR] [--write DIR]

Each labelled set folder (a ``labels.json`` as :mod:`real_unseen` reads it) is classified twice
with one model: the frame as read, and the same frame resampled, its labelled and unscored
rectangles scaled with it; both are scored by :func:`real_unseen.score_frame`.  Printed: per set
boxes (staircases, ramps) found and false answers at both resolutions, and every labelled
object whose answer changed and every false answer that came or went.  ``--osd`` / ``--uois``
do the same for the point-annotated table-tops of :mod:`real_tabletop` (their points scaled).

Resampling (``--mode``):

* ``decimate`` (default): every second row and column of the organized cloud, starting at 0
  (:func:`planerel.io.cloud.subsample`, what ``planerel classify --subsample 2`` does).  The
  points kept are the sensor's own measurements, unchanged, and an invalid pixel stays invalid,
  so the only thing that changes is how many pixels an object covers: the test of thresholds
  counted in pixels, points or rows, without changing the noise.  Intrinsics ``fx/2, cx/2``
  (pixel ``2u`` becomes ``u``).
* ``median``: a 2x2 block median of the depth (the mean of the middle two), invalid when any of
  the four pixels is invalid (no depth is made up across a missing measurement or an edge that
  lost one side), back-projected through the block's centre: ``fx' = fx/2``,
  ``cx' = (cx + 0.5)/2 - 0.5``.  What a sensor's own binning or a user's ``cv2.resize`` with
  area averaging roughly does: half the pixels, and less noise a pixel.
* ``double``: nearest-neighbour 2x: each depth repeated over a 2x2 block, back-projected
  through the new pixels (``fx' = 2 fx``, ``cx' = 2 cx + 0.5``): four times the pixels, each
  block a small fronto-parallel plateau.

``--write DIR`` saves each resampled frame as ``DIR/SET/FRAME.npy`` (an ``(H, W, 3)`` XYZ
array) and ``DIR/SET/labels.json`` with the scaled rectangles and the scaled intrinsics, so
that ``/tmp/hunt36/diag.py`` and ``real_unseen.py`` can trace a changed answer on it.
"""

from __future__ import annotations

import argparse
import json
import os
import sys
from collections import Counter

import numpy as np
from real_unseen import CLASSES, read_labels, score_frame, totals

MODES = ("decimate", "median", "double")


def _rays(intr, h: int, w: int) -> tuple[np.ndarray, np.ndarray]:
    """``(x/z, y/z)`` of every pixel's ray, ``(H, W)`` each."""
    u = (np.arange(w, dtype=np.float64) - intr.cx) / intr.fx
    v = (np.arange(h, dtype=np.float64) - intr.cy) / intr.fy
    return np.broadcast_to(u[None, :], (h, w)), np.broadcast_to(v[:, None], (h, w))


def resample(cloud, mode: str):
    """The cloud at half (``decimate``, ``median``) or double (``double``) resolution.

    Parameters
    ----------
    cloud : planerel.io.cloud.Cloud
        An organized cloud (``median`` and ``double`` need its intrinsics).
    mode : str
        One of :data:`MODES` (module docstring).

    Returns
    -------
    Cloud
        The resampled cloud, with intrinsics scaled to match.

    Raises
    ------
    planerel.errors.InputError
        An unknown mode, an unorganized cloud, or no intrinsics for ``median`` / ``double``.
    """
    from planerel.errors import InputError
    from planerel.io.cloud import Cloud, Intrinsics, subsample

    if mode not in MODES:
        raise InputError(f"resampling mode must be one of {', '.join(MODES)}, got {mode!r}")
    if mode == "decimate":
        return subsample(cloud, 2)
    if not cloud.organized or cloud.intrinsics is None:
        raise InputError(f"{cloud.source or 'cloud'}: {mode} needs an organized cloud with intrinsics")
    z = np.asarray(cloud.xyz, dtype=np.float64)[..., 2]
    k = cloud.intrinsics
    if mode == "median":
        h, w = z.shape[0] // 2, z.shape[1] // 2
        blocks = z[:2 * h, :2 * w].reshape(h, 2, w, 2).transpose(0, 2, 1, 3).reshape(h, w, 4)
        bad = ~np.isfinite(blocks).all(axis=2)
        zz = np.sort(np.where(np.isfinite(blocks), blocks, 0.0), axis=2)
        znew = np.where(bad, np.nan, 0.5 * (zz[..., 1] + zz[..., 2]))
        intr = Intrinsics(w, h, k.fx / 2, k.fy / 2, (k.cx + 0.5) / 2 - 0.5, (k.cy + 0.5) / 2 - 0.5)
    else:
        znew = np.repeat(np.repeat(z, 2, axis=0), 2, axis=1)
        h, w = znew.shape
        intr = Intrinsics(w, h, k.fx * 2, k.fy * 2, 2 * k.cx + 0.5, 2 * k.cy + 0.5)
    rx, ry = _rays(intr, h, w)
    xyz = np.stack([rx * znew, ry * znew, znew], axis=-1)
    return Cloud(np.ascontiguousarray(xyz), intr, cloud.up, cloud.source, True)


def factor(mode: str) -> float:
    """How pixel coordinates scale under ``mode``."""
    return 2.0 if mode == "double" else 0.5


def scaled_frame(frame: dict, f: float) -> dict:
    """``frame`` (a ``labels.json`` entry) with its rectangles scaled by ``f``."""
    out = dict(frame)
    out["objects"] = [dict(o, box=[v * f for v in o["box"]]) for o in frame.get("objects", [])]
    out["unscored"] = [[v * f for v in b] for b in frame.get("unscored", [])]
    return out


def _what(r: dict) -> tuple[list[str], list[str]]:
    """One string per labelled object (its answer) and per false answer, to diff two runs."""
    objs = [f"{o['class']} {'found' if o['found'] else 'missed'} (called "
            f"{', '.join(sorted(o['called'])) or 'nothing'}): {o['what'][:60]}" for o in r["objects"]]
    return objs, sorted(f"false {k} (rule {rule})" for k, rule, _ in r["false"])


def changes(full: dict, other: dict) -> list[str]:
    """What moved between the full-resolution row and the resampled one."""
    out = []
    fo, ff = _what(full)
    oo, of = _what(other)
    for a, b in zip(fo, oo, strict=True):
        if a != b:
            out.append(f"{a}  ->  {b.split(':')[0]}")
    cf, co = Counter(ff), Counter(of)
    out += [f"{x} gone" for x in sorted((cf - co).elements())]
    out += [f"{x} new" for x in sorted((co - cf).elements())]
    return out


def run_sets(folders, clf, mode: str, write: str | None = None) -> list[dict]:
    """Every labelled frame of ``folders`` at full resolution and resampled; one row per frame."""
    import planerel

    rows = []
    f = factor(mode)
    for folder in folders:
        doc = read_labels(folder)
        name = doc.get("set", os.path.basename(os.path.normpath(folder)))
        new_doc = {"set": name, "source": f"{doc.get('source', '')} (resampled: {mode})", "frames": []}
        for frame in doc["frames"]:
            path = os.path.join(folder, frame["file"])
            cloud = planerel.read(path, intrinsics=frame.get("intrinsics"),
                                  depth_scale=frame.get("depth_scale"))
            small = resample(cloud, mode)
            up = frame.get("up")
            up = None if up is None else np.asarray(up, float)
            stem = os.path.splitext(os.path.basename(path))[0]
            row = {"set": name, "frame": stem,
                   "shape": list(cloud.xyz.shape[:2]), "shape_resampled": list(small.xyz.shape[:2])}
            ans = clf.classify(cloud, scene_id="s", up=up)
            row["full"] = score_frame(ans, frame)
            row["full"]["objects_proposed"] = len(ans.objects)
            sframe = scaled_frame(frame, f)
            ans = clf.classify(small, scene_id="s", up=up)
            row["resampled"] = score_frame(ans, sframe)
            row["resampled"]["objects_proposed"] = len(ans.objects)
            row["changes"] = changes(row["full"], row["resampled"])
            rows.append(row)
            if write:
                d = os.path.join(write, name)
                os.makedirs(d, exist_ok=True)
                np.save(os.path.join(d, f"{stem}.npy"), np.asarray(small.xyz, np.float64))
                entry = {k: v for k, v in sframe.items() if k not in ("depth_scale",)}
                entry["file"] = f"{stem}.npy"
                if small.intrinsics is not None:
                    k = small.intrinsics
                    entry["intrinsics"] = f"{k.width},{k.height},{k.fx},{k.fy},{k.cx},{k.cy}"
                new_doc["frames"].append(entry)
            print(f"{name}/{stem}: {row['shape'][1]}x{row['shape'][0]} -> "
                  f"{row['shape_resampled'][1]}x{row['shape_resampled'][0]}: "
                  + ("; ".join(row["changes"]) or "the same"), flush=True)
        if write:
            with open(os.path.join(write, name, "labels.json"), "w") as fh:
                json.dump(new_doc, fh, indent=1)
    return rows


def set_totals(rows: list[dict], which: str) -> dict:
    """:func:`real_unseen.totals` of one side (``full`` or ``resampled``) of ``rows``."""
    return totals([r[which] for r in rows])


def line(t: dict) -> str:
    return (", ".join(f"{k} {t[f'{k}_found']}/{t[f'{k}_labelled']}" for k in CLASSES
                      if t[f"{k}_labelled"])
            + "; false " + "/".join(str(t[f"false_{k}"]) for k in CLASSES))


def run_tabletop(clf, mode: str, osd: str | None, uois: str | None) -> dict:
    """The table-tops of :mod:`real_tabletop` at both resolutions: summaries and changed points."""
    import real_tabletop as tt

    todo = tt.frames(osd, uois)
    full = [tt.frame(clf, *t) for t in todo]
    f = factor(mode)
    read0, truth0 = tt.read_frame, dict(tt.TRUTH)
    try:
        tt.read_frame = lambda path, intr: resample(read0(path, intr), mode)
        tt.TRUTH.update({k: [(int(round(x * f)), int(round(y * f)), kind, name)
                              for x, y, kind, name in v] for k, v in truth0.items()})
        small = [tt.frame(clf, *t) for t in todo]
    finally:
        tt.read_frame = read0
        tt.TRUTH.clear()
        tt.TRUTH.update(truth0)
    moved = []
    for a, b in zip(full, small, strict=True):
        for p, q in zip(a["points"], b["points"], strict=True):
            if p["answer"] != q["answer"]:
                moved.append(f"{a['frame']} {p['name']} ({p['kind']}): {p['answer']} -> {q['answer']}")
    return {"full": tt.summarize(full), "resampled": tt.summarize(small), "changes": moved}


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("folders", nargs="*", metavar="DIR", help="set folders holding labels.json")
    ap.add_argument("--model", default="out/model")
    ap.add_argument("--mode", choices=MODES, default="decimate")
    ap.add_argument("--param", action="append", default=[], metavar="NAME=VALUE")
    ap.add_argument("--osd", help="real_tabletop.py's OSD folder")
    ap.add_argument("--uois", help="real_tabletop.py's uois folder")
    ap.add_argument("--write", metavar="DIR", help="save the resampled frames and labels here")
    ap.add_argument("--json", help="write the rows and totals here")
    a = ap.parse_args(argv)
    from planerel.classify.classifier import Classifier
    from planerel.commands.classify import _params

    out = {"mode": a.mode}
    with Classifier(a.model, seg_params=_params(a.param)) as clf:
        rows = run_sets(a.folders, clf, a.mode, a.write) if a.folders else []
        if a.osd or a.uois:
            out["tabletop"] = run_tabletop(clf, a.mode, a.osd, a.uois)
    res = "half" if factor(a.mode) < 1 else "double"
    for name in dict.fromkeys(r["set"] for r in rows):
        part = [r for r in rows if r["set"] == name]
        n = sum(len(r["changes"]) for r in part)
        print(f"{name}: full {line(set_totals(part, 'full'))} | {res} ({a.mode}) "
              f"{line(set_totals(part, 'resampled'))} | {n} answers changed")
    if rows:
        print(f"all sets: full {line(set_totals(rows, 'full'))} | {res} ({a.mode}) "
              f"{line(set_totals(rows, 'resampled'))} | "
              f"{sum(len(r['changes']) for r in rows)} answers changed ({len(rows)} frames)")
    if "tabletop" in out:
        t = out["tabletop"]
        for side in ("full", "resampled"):
            s = t[side]
            print(f"table-tops {side}: boxes `box` {s['boxes_box']}/{s['boxes']}, other `box` "
                  f"{s['other_box']}/{s['other']}, round stairs/ramp {s['round_stairs_ramp']}/"
                  f"{s['round']}; answers box {s['box_answers']}, stairs {s['stairs_answers']}, "
                  f"ramp {s['ramp_answers']}")
        for c in t["changes"]:
            print(f"  table-top {c}")
    if a.json:
        from planerel.atomic import write_text

        out["rows"] = rows
        if rows:
            out["totals"] = {"full": set_totals(rows, "full"), "resampled": set_totals(rows, "resampled")}
        write_text(a.json, json.dumps(out, indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main())
