"""Every labelled box of the real development frames that a model misses, by the cause that
loses it, and the found share by range, size and view (boxrec59, docs/objects.md "Real boxes
missed, cause by cause, by range, size and view").  A measuring tool: nothing of it is used by
the classifier.

Usage::

    box_causes.py DIR [DIR ...] [--model out/model] [--up-errors UP.json] [--param N=V ...]
                  [--json F]

``DIR`` as :mod:`real_census` takes it (a set folder with ``labels.json`` or a folder of
them).  Each frame is read, segmented, described and answered as the census does
(:func:`real_census.census_frame`: its stage per box), and each box gets one *cause*:

``found``
    answered ``box`` (as ``real_unseen.py`` scores it);
``no plane: no depth``
    under half of the rectangle's pixels have depth;
``no plane: unassigned``
    depth, but under 0.3 of the rectangle's pixels lie in any plane (noise, range, a round
    or cluttered surface: no region grows there);
``no plane: in a larger plane``
    the rectangle's plane pixels belong to planes mostly outside it (a flush front grown across
    boxes, a face grown into the floor or a wall);
``merged: pile``
    the proposal holding the box has :data:`PILE` (0.2) or more of its pixels in other labelled
    box rectangles (packed or stacked boxes in one proposal);
``merged: support``
    the rest of the merged ones (the box with what it stands on, leans on or lies in);
``gate refused (G)``
    a box rule proves the box's own proposal and the decision refuses it (the census's stage);
``other class (C)``
    the proposal is answered ``stairs`` or ``ramp``;
``rule: L``
    the proposal is the box's, no box rule fires; ``L`` the literal that fails on the closest
    candidate: for an upright plane the ``tall_face/1`` tests it fails
    (:func:`box_tests.tall_face_tests`, the plane failing fewest), else ``no upright face`` and
    why no plane is ``lying/1``'s top (``ground`` for a top of its size, ``a face tilted off
    vertical`` when a plane is inclined :data:`FACE_TILT` (45) degrees or more, else
    ``top size``).

Each box also gets its *range* (the rectangle's median distance), *size* (the rectangle's
larger side in metres at that range, through the camera's focal length), the *view* (how far
the camera's optical axis looks under the horizon by the scene's up, :func:`camera_pitch`:
``level`` under 20 degrees, ``oblique`` 20-50, ``above`` over 50) and, with ``--up-errors``
(``benchmarks/real_up_error.py --json``), the estimated up's error against that tool's truth:
``up wrong`` when it is over :data:`UP_WRONG` (10) degrees (a flag, not a cause: a box under a
wrong up is counted by the stage that loses it), and the view is then taken from that truth.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import sys
from collections import Counter
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))

#: Share of the holding proposal's pixels in other box rectangles that makes a merge a pile.
PILE = 0.2
#: Degrees of incline from which a plane counts as a face measured off vertical.
FACE_TILT = 45.0
#: Degrees of up error over which a frame's up is called wrong.
UP_WRONG = 10.0
RANGES = ((1.0, "< 1 m"), (2.0, "1-2 m"), (4.0, "2-4 m"), (math.inf, ">= 4 m"))
SIZES = ((0.1, "< 0.1 m"), (0.2, "0.1-0.2 m"), (0.4, "0.2-0.4 m"), (math.inf, ">= 0.4 m"))
VIEWS = ((20.0, "level"), (50.0, "oblique"), (math.inf, "above"))


def band(value, bands) -> str:
    """The name of the first band of ``bands`` (``(upper bound, name)``, rising) that
    ``value`` lies under; ``"?"`` for None or NaN."""
    if value is None or not np.isfinite(value):
        return "?"
    return next(name for hi, name in bands if value < hi)


def camera_pitch(up) -> float:
    """Degrees the optical axis (camera +z) looks under the horizon for the gravity ``up``
    (shape (3,), camera frame): 0 level, 90 straight down, negative looking up (the small
    pass's own measure, :func:`planerel.segment.view_pitch`)."""
    from planerel.segment import view_pitch

    return view_pitch(up)


def no_plane_cause(valid_share: float, plane_share: float) -> str:
    """The cause of a ``no plane in it`` box from its rectangle's share of pixels with depth
    and share in any plane (planes that lie mostly outside it: the census found none inside)."""
    if valid_share < 0.5:
        return "no plane: no depth"
    if plane_share < 0.3:
        return "no plane: unassigned"
    return "no plane: in a larger plane"


def rule_cause(closest, has_upright: bool, top_sized: bool, tilted: bool = False) -> str:
    """The literal that fails on a ``no rule fires`` box: ``closest`` is
    :func:`box_tests._box_rows`' closest ``tall_face`` (``{"plane", "fails"}`` or None),
    ``has_upright`` whether the proposal holds a vertical plane, ``top_sized`` whether one of
    its other planes passes ``lying/1``'s size and incline test, ``tilted`` whether one is
    inclined :data:`FACE_TILT` degrees or more (a face measured off vertical: no
    ``tall_face`` to test, as no ``lying`` top)."""
    if has_upright and closest is not None:
        return "rule: tall_face fails " + (" + ".join(closest["fails"]) or "nothing")
    if top_sized:
        return "rule: no upright face, lying fails ground"
    if tilted:
        return "rule: no upright face, a face tilted off vertical"
    return "rule: no upright face, lying fails top size"


def cause(row: dict, extra: dict) -> str:
    """One box's cause from its census ``row`` (:func:`real_census.census_frame`) and the
    ``extra`` measures :func:`frame_extras` adds (``valid``, ``in_planes``, ``pile``,
    ``closest``, ``upright``, ``top_sized``)."""
    st = row["stage"]
    if st == "found":
        return "found"
    if st == "no plane in it":
        return no_plane_cause(extra["valid"], extra["in_planes"])
    if st == "no proposal":
        return "no proposal"
    if st.startswith("merged"):
        return "merged: pile" if extra.get("pile", 0.0) >= PILE else "merged: support"
    if st.startswith(("gate refused", "other class")):
        return st
    return rule_cause(extra.get("closest"), extra.get("upright", False),
                      extra.get("top_sized", False), extra.get("tilted", False))


def frame_extras(desc, cloud, rows) -> list:
    """The measures :func:`cause` and the bands need, one dict per census row of one frame."""
    import box_tests
    from real_unseen import rect_mask

    lab = np.asarray(desc.labels)
    valid = np.asarray(cloud.valid)
    ps = desc.planes
    up = np.asarray(ps.up, float)
    pitch = camera_pitch(up)
    fx = cloud.intrinsics.fx if cloud.intrinsics is not None else None
    by_id = {o.id: o for o in desc.objects}
    boxes = [rect_mask(lab.shape, r["box"]) for r in rows]
    out = []
    for i, r in enumerate(rows):
        m = boxes[i]
        n = max(1, int(m.sum()))
        x0, y0, x1, y1 = r["box"]
        rng = r.get("range")
        e = {"valid": float((valid & m).sum()) / n, "in_planes": float((lab[m] >= 0).sum()) / n,
             "pitch": round(pitch, 1), "range": rng,
             "size": None if fx is None or rng is None else
             round(max(x1 - x0, y1 - y0) * rng / fx, 3)}
        o = by_id.get(r.get("proposal"))
        if o is not None and r["stage"] != "found":
            pm = np.isin(lab, list(o.planes))
            others = np.zeros_like(m)
            for j, mm in enumerate(boxes):
                if j != i:
                    others |= mm
            e["pile"] = float((pm & others & ~m).sum()) / max(1, int(pm.sum()))
        if r["stage"] == "no rule fires" and o is not None:
            lines, closest = box_tests._box_rows(desc, cloud, r, lab)
            e["closest"] = closest
            mine = [q for q in ps if q.label in set(o.planes)]
            e["upright"] = any(q.orientation == "vertical" for q in mine)
            e["top_sized"] = any("lying: size and incline True" in s for s in lines)
            e["tilted"] = any(q.orientation == "inclined" and q.incline >= FACE_TILT
                              for q in mine)
        out.append(e)
    return out


def frames(dirs, model: str, params=()):
    """Each frame of ``dirs`` with a labelled box, described and answered as the census does:
    yields ``(folder, frame, stem, cloud, desc, answers, rows)``, ``frame`` the labels' entry,
    ``answers`` the classifier's per proposal, ``rows`` the census's rows of the frame
    (:func:`real_census.census_frame`), each with its ``cause`` and the ``extras``
    (:func:`frame_extras`) it was taken from.  :func:`run`, ``grounded_why.py``,
    ``merge_why.py``."""
    from real_census import census_frame, set_folders
    from real_unseen import describe_frame, read_labels

    from planerel.classify.classifier import Classifier
    from planerel.commands.classify import _params

    with Classifier(model, seg_params=_params(list(params))) as clf:
        for folder in set_folders(dirs):
            for frame in read_labels(str(folder))["frames"]:
                if not any(o["class"] == "box" for o in frame.get("objects", [])):
                    continue
                cloud, desc = describe_frame(clf, str(folder), frame)
                answers = clf.answer_description(desc, xyz=cloud.xyz)
                these = census_frame(clf, desc, answers, frame, cloud.xyz)
                for r, e in zip(these, frame_extras(desc, cloud, these), strict=True):
                    r["cause"] = cause(r, e)
                    r["extras"] = e
                stem = os.path.splitext(os.path.basename(frame["file"]))[0]
                yield folder, frame, stem, cloud, desc, answers, these
                print(f"{folder.name}/{stem}", file=sys.stderr, flush=True)


def run(dirs, model: str, params=()) -> list:
    """One row per labelled box of ``dirs``: the census's row with ``cause``, ``range``,
    ``size``, ``pitch`` and the bands."""
    rows = []
    for folder, frame, stem, _, _, _, these in frames(dirs, model, params):
        for r in these:
            e = r.pop("extras")
            rows.append({"set": f"{folder.parent.name}/{folder.name}", "frame": stem,
                         "file": frame["file"], **r, "size": e["size"], "pitch": e["pitch"],
                         "range_band": band(r.get("range"), RANGES),
                         "size_band": band(e["size"], SIZES),
                         "view": band(e["pitch"], VIEWS)})
    return rows


def add_up_errors(rows, path: str) -> None:
    """Set ``up_error`` (degrees) and ``up_wrong`` on the rows whose frame
    ``real_up_error.py --json`` (``path``) measured, and take their ``pitch`` and ``view``
    from its truth (``pitch_estimated`` keeps the estimate's)."""
    frames = {f["frame"]: f for f in json.loads(Path(path).read_text())["frames"]}
    for r in rows:
        f = frames.get(f"{r['set']}/{r['file']}", {})
        e = f.get("error_deg")
        r["up_error"] = e
        r["up_wrong"] = None if e is None else bool(e > UP_WRONG)
        if f.get("truth") is not None:
            r["pitch_estimated"] = r["pitch"]
            r["pitch"] = round(camera_pitch(f["truth"]), 1)
            r["view"] = band(r["pitch"], VIEWS)


def tables(rows) -> str:
    """The summary: missed boxes by cause (with the up-wrong count), found / all by band."""
    out = []
    miss = [r for r in rows if r["cause"] != "found"]
    found = sum(r["cause"] == "found" for r in rows)
    out.append(f"boxes {len(rows)}, found {found}, missed {len(miss)}")
    out.append("| cause | missed | up wrong | sets |")
    out.append("|---|---|---|---|")
    for c, k in Counter(r["cause"] for r in miss).most_common():
        sel = [r for r in miss if r["cause"] == c]
        sets = Counter(r["set"].split("/")[1] for r in sel)
        out.append(f"| {c} | {k} | {sum(bool(r.get('up_wrong')) for r in sel)} | "
                   + ", ".join(f"{s} {n}" for s, n in sets.most_common()) + " |")
    for key, bands in (("range_band", RANGES), ("size_band", SIZES), ("view", VIEWS)):
        names = [b for _, b in bands] + ["?"]
        out.append(f"\n| {key} | " + " | ".join(names) + " |")
        out.append("|---" * (len(names) + 1) + "|")
        cells = []
        for b in names:
            sel = [r for r in rows if r[key] == b]
            cells.append(f"{sum(r['cause'] == 'found' for r in sel)}/{len(sel)}")
        out.append("| found / boxes | " + " | ".join(cells) + " |")
        top = Counter(r["cause"].split(" fails")[0].split(":")[0] for r in miss)
        for c, _ in top.most_common():
            cells = [str(sum(r[key] == b and r["cause"].split(" fails")[0].split(":")[0] == c
                             for r in miss)) for b in names]
            out.append(f"| {c} | " + " | ".join(cells) + " |")
    return "\n".join(out)


def parser(description: str, aggregate: str | None = None) -> argparse.ArgumentParser:
    """The command line of this tool and of those built on :func:`frames` (``DIR ...``,
    ``--model``, ``--param``; with ``aggregate``, an ``--aggregate`` switch helped so)."""
    ap = argparse.ArgumentParser(description=description)
    ap.add_argument("dirs", nargs="+")
    ap.add_argument("--model", default="out/model")
    ap.add_argument("--param", action="append", default=[], metavar="NAME=VALUE")
    if aggregate:
        ap.add_argument("--aggregate", action="store_true", help=aggregate)
    return ap


def main(argv=None) -> int:
    ap = parser(__doc__.split("\n")[0])
    ap.add_argument("--up-errors", help="benchmarks/real_up_error.py --json output")
    ap.add_argument("--json")
    a = ap.parse_args(argv)
    rows = run(a.dirs, a.model, a.param)
    if a.up_errors:
        add_up_errors(rows, a.up_errors)
    for r in rows:
        if r["cause"] != "found":
            up = "" if r.get("up_error") is None else f" up err {r['up_error']:.0f}"
            print(f"{r['set']} {r['frame']} | {r['what'][:50]} | {r['cause']} | range "
                  f"{r['range']} size {r['size']} pitch {r['pitch']}{up}")
    print(tables(rows))
    if a.json:
        Path(a.json).write_text(json.dumps(rows, indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main())
