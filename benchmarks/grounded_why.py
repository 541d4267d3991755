"""What lies under the foot of a real box's face that ``tall_face/1``'s grounded test fails
(ground75, docs/objects.md "A box on a floor no plane took").  A measuring tool: nothing of it
is used by the classifier.

Usage::

    grounded_why.py DIR [DIR ...] [--model out/model] [--param N=V ...] [--aggregate]

``DIR`` as :mod:`box_causes` takes it.  Every labelled box whose cause (:func:`box_causes.cause`)
names ``grounded`` among the failed tests is taken through its closest face (the vertical plane
of its proposal failing fewest ``tall_face`` tests) and sorted by what lies under that face's
foot (:func:`under_foot`):

``grounded``
    the face passes the grounded test after all (a model setting changed since the cause);
``floor's level, floor_foot fails``
    a floor (the floor plane, or a feet level or speckle floor when there is none) lies level
    with the foot, but the columns under it or the face's fill fail :func:`floor_foot`;
``adjacent horizontal, not grounding``
    a horizontal plane adjacent to the face does not ground it (a seat, a tread, a rim);
``level ground no plane took, reaching R m``
    in half of its middle columns the level ground under its foot reaches ``R`` m in front
    of it (:func:`planerel.features.tall_face.level_reach`; ``R`` the model's
    ``tall_level_ground``, or ``skirt_step`` when that is off), with whether the scan has a
    floor plane and whether the face's top is out of view (the limits of
    :func:`~planerel.features.tall_face.level_ground`);
``nothing measured under the foot``
    in half of its columns the rows under its lowest pixel hold no depth (or the image ends);
``level points no plane took, reaching less``
    the first points measured under the foot lie level with it (within ``standing_foot``)
    in half of the columns that have any;
``another surface``
    the rest.

Each box also gets the median over its columns of how far that level ground reaches in front
of the foot (:func:`planerel.features.tall_face.level_reach`).  ``--aggregate`` prints only the
counts and the reaches' medians per kind, no frame named (for judge sets).
"""

from __future__ import annotations

import sys
from collections import Counter, defaultdict
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))


def under_foot(face, prof, labels, xyz, up, rows: int, tol: float) -> dict:
    """The first measured point under ``face``'s lowest pixel in each of its middle columns
    (within ``rows`` rows): ``{"columns", "nothing"`` (no depth there or the image ends),
    ``"level"`` (within ``tol`` of the foot's level, no farther out than the face plus
    0.08 m)``, "measured"}``."""
    from planerel.features.relations import FLOOR_FOOT_MARGIN

    r0, c0, r1, c1 = (int(v) for v in face.bbox)
    m = labels[r0:r1, c0:c1] == face.label
    cols = np.flatnonzero(m.any(axis=0))
    out = {"columns": 0, "nothing": 0, "level": 0, "measured": 0}
    if cols.size < 3:
        return out
    cut = FLOOR_FOOT_MARGIN * (cols[-1] - cols[0])
    cols = cols[(cols >= cols[0] + cut) & (cols <= cols[-1] - cut)]
    bottom = r0 + m.shape[0] - 1 - np.argmax(m[::-1, cols], axis=0)
    up = np.asarray(up, float)
    c = np.asarray(face.centroid, float)
    horiz = float(np.linalg.norm(c - (c @ up) * up))
    H = labels.shape[0]
    out["columns"] = int(cols.size)
    for col, rb in zip(cols + c0, bottom, strict=True):
        seg = xyz[rb + 1:min(H, rb + 1 + rows), col]
        ok = np.isfinite(seg).all(axis=1) & (seg[:, 2] > 0) if len(seg) else np.zeros(0, bool)
        if not ok.any():
            out["nothing"] += 1
            continue
        q = seg[int(np.argmax(ok))]
        out["measured"] += 1
        flat = float(np.linalg.norm(q - (q @ up) * up))
        if abs(float(q @ up) - prof.bottom) <= tol and flat <= horiz + 0.08:
            out["level"] += 1
    return out


def kind_of(desc, cloud, face) -> tuple[str, float]:
    """``(kind, reach)`` of a vertical plane ``face`` of ``desc`` (the module docstring's kinds;
    ``reach`` the median over its columns of :func:`level_reach`, m, ``nan`` when none)."""
    import box_tests

    from planerel.features import relations as R
    from planerel.features.solid import face_profile_of, level_under

    ps, p = desc.planes, desc.relations.params
    lab = np.asarray(desc.labels)
    up = np.asarray(ps.up, float)
    prof = face_profile_of(face, up, lab, cloud.xyz, p.profile_points)
    got = R.level_reach(face, prof, lab, cloud.xyz, up, p.standing_foot)
    fin = got[np.isfinite(got)]
    reach = float(np.median(fin)) if fin.size else float("nan")
    tests = dict((n, ok) for n, ok, _ in box_tests.tall_face_tests(ps, desc.relations, cloud,
                                                                   face.label))
    if tests.get("grounded"):
        return "grounded", reach

    def profile(q):
        return face_profile_of(q, up, lab, cloud.xyz, p.profile_points)

    def shaped(a):
        return R.tall_shaped(a, p, lab, cloud.xyz, up, noise=R.tall_noise(cloud, p))

    floor, _ = box_tests._floor_for_tall(ps, p, cloud, profile, shaped)
    level = None if floor is None else level_under(floor, face.centroid, up)
    if level is not None and abs(level - prof.bottom) <= p.tall_floor_fit:
        return "floor's level, floor_foot fails", reach
    by_label = {q.label: q for q in ps}
    if any(r.adjacent and r.a == face.label and by_label.get(r.b) is not None
           and by_label[r.b].orientation == "horizontal" for r in R.adjacent_only(desc.relations)):
        return "adjacent horizontal, not grounding", reach
    where = "no floor plane" if ps.floor is None else "a floor plane elsewhere"
    step = p.tall_level_ground if p.tall_level_ground > 0 else p.skirt_step
    if got.size and int((got >= step).sum()) >= p.tall_floor_share * got.size:
        if R._reaches_top_row(face, 2 + R.BLANK_MARGIN_MAX):
            where += ", its top out of view"
        return f"level ground no plane took, reaching {step:.2f} m ({where})", reach
    rows = max(3, int(round(R.FLOOR_FOOT_ROWS * lab.shape[0])))
    u = under_foot(face, prof, lab, cloud.xyz, up, rows, p.standing_foot)
    if u["nothing"] >= 0.5 * max(1, u["columns"]):
        return "nothing measured under the foot", reach
    if u["level"] >= 0.5 * max(1, u["measured"]):
        return f"level points no plane took, reaching less ({where})", reach
    return "another surface", reach


def run(dirs, model: str, params=()) -> list:
    """One row per labelled box of ``dirs`` that fails the grounded test: the census's row with
    ``kind`` and ``reach``."""
    from box_causes import frames

    rows = []
    for folder, _, stem, cloud, desc, _, these in frames(dirs, model, params):
        by_pid = {desc.plane_id(q.label): q for q in desc.planes}
        for r in these:
            if "grounded" not in r["cause"]:
                continue
            kind, reach = kind_of(desc, cloud, by_pid[r["extras"]["closest"]["plane"]])
            rows.append({"set": f"{folder.parent.name}/{folder.name}", "frame": stem,
                         "what": r["what"], "cause": r["cause"], "kind": kind,
                         "reach": None if not np.isfinite(reach) else round(reach, 3),
                         "range": r.get("range")})
    return rows


def table(rows) -> str:
    """Counts and the reaches' medians per kind (no frame named)."""
    n = Counter(r["kind"] for r in rows)
    reach = defaultdict(list)
    for r in rows:
        if r["reach"] is not None:
            reach[r["kind"]].append(r["reach"])
    lines = ["| under the face's foot | boxes | level ground's reach in front (m; median per box) |",
             "|---|---|---|"]
    for k, v in n.most_common():
        got = sorted(reach[k])
        lines.append(f"| {k} | {v} | {', '.join(f'{x:.2f}' for x in got) or '-'} |")
    return "\n".join(lines)


def main(argv=None) -> int:
    from box_causes import parser

    a = parser(__doc__.split("\n")[0], "counts and medians only, no frame named (for judge sets)").parse_args(argv)
    rows = run(a.dirs, a.model, a.param)
    if not a.aggregate:
        for r in rows:
            reach = "-" if r["reach"] is None else f"{r['reach']:.2f} m"
            print(f"{r['set']} {r['frame']} | {r['what'][:50]} | {r['cause']} | {r['kind']} | "
                  f"reach {reach} | range {r['range']}")
    print(f"boxes failing the grounded test: {len(rows)}")
    print(table(rows))
    return 0


if __name__ == "__main__":
    sys.exit(main())
