"""Which join rules of the object proposals hold a real box merged with other things: for each
labelled box that :mod:`box_causes` calls ``merged`` (with what it stands on, or with other
boxes), the rules of :func:`planerel.features.proposals.propose_objects` whose pairs join a
plane inside its rectangle to a plane of the same proposal outside it.  A measuring tool:
nothing of it is used by the classifier.

Usage::

    merge_why.py DIR [DIR ...] [--model out/model] [--param N=V ...] [--aggregate]

``DIR`` as :mod:`box_causes` takes it.  A proposal's plane is *inside* when half of its pixels
lie in the box's rectangle.  Each pair is named by its rule (``convex_pairs``,
``split_panel_pairs``, ``cavity_pairs``, ...; :data:`join_reasons.RULES`) and the two planes'
orientations (``hv`` a horizontal and a vertical plane, ``iv`` an inclined and a vertical one,
...).  ``--aggregate`` prints only the counts (boxes per rule and orientations), no frame named
(for judge sets).  Measured in docs/objects.md "A box on a floor no plane took" (ground75).
"""

from __future__ import annotations

import sys
from collections import Counter
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))


def joins_across(rules, orientation: dict, inside: set, outside: set) -> set:
    """``{(rule, orientations)}`` of the pairs in ``rules`` (``[(rule name, {(a, b), ...})]``,
    :func:`join_reasons._instrument`'s log) that join a label of ``inside`` to one of
    ``outside``; ``orientations`` the two planes' first letters, sorted (``orientation``:
    ``{label: "horizontal" | "vertical" | "inclined"}``, ``?`` for a label not in it)."""
    out = set()
    for name, pairs in rules:
        for x, y in pairs:
            if (x in inside and y in outside) or (y in inside and x in outside):
                o = "".join(sorted(orientation.get(x, "?")[0] + orientation.get(y, "?")[0]))
                out.add((name, o))
    return out


def run(dirs, model: str, params=()) -> list:
    """One row per merged box of ``dirs``: set, frame, what, cause and ``joins`` (sorted
    ``[rule, orientations]``)."""
    import join_reasons
    from box_causes import frames
    from real_unseen import rect_mask

    log: list = []
    calls: list = []
    join_reasons._instrument(log, calls)
    rows = []
    for folder, _, stem, _, desc, answers, these in frames(dirs, model, params):
        if calls:
            planes, rules = calls[-1]
            orientation = {q.label: q.orientation for q in planes}
            lab = np.asarray(desc.labels)
            for r in these:
                if not r["cause"].startswith("merged"):
                    continue
                a = next(x for x in answers if x.object_id == r["proposal"])
                m = rect_mask(lab.shape, r["box"])
                inside, outside = set(), set()
                for k in a.labels:
                    pl = lab == k
                    (inside if (pl & m).sum() >= 0.5 * pl.sum() else outside).add(int(k))
                joins = joins_across(rules, orientation, inside, outside)
                rows.append({"set": f"{folder.parent.name}/{folder.name}", "frame": stem,
                             "what": r["what"], "cause": r["cause"],
                             "joins": sorted([n, o] for n, o in joins)})
        calls.clear()  # the next frame's proposals only
    return rows


def table(rows) -> str:
    """Boxes per (rule, orientations), no frame named."""
    n = Counter((j[0], j[1]) for r in rows for j in r["joins"])
    lines = [f"merged boxes: {len(rows)}; with no join across their rectangle: "
             f"{sum(not r['joins'] for r in rows)}", "",
             "| rule | planes | boxes |", "|---|---|---|"]
    lines += [f"| {k[0]} | {k[1]} | {v} |" for k, v in n.most_common()]
    return "\n".join(lines)


def main(argv=None) -> int:
    from box_causes import parser

    a = parser(__doc__.split("\n")[0], "counts only, no frame named (for judge sets)").parse_args(argv)
    rows = run(a.dirs, a.model, a.param)
    if not a.aggregate:
        for r in rows:
            print(f"{r['set']} {r['frame']} | {r['what'][:50]} | {r['cause']} | "
                  + (", ".join(f"{n} {o}" for n, o in r["joins"]) or "-"))
    print(table(rows))
    return 0


if __name__ == "__main__":
    sys.exit(main())
