"""Why the stairfit stage fits no staircase to a flight's unexplained pixels: the test each of
its clusters fails (wave82, docs/objects.md "A stereo pair as wavy as a real D4xx").  A
measuring tool.

Usage::

    stairfit_why.py DIR [DIR ...] [--model out/model] [--param NAME=VALUE ...] [--json F]
        [--aggregate]

It runs :func:`stairs_census.census` and, for every flight, the stairfit stage
(:func:`planerel.features.stairfit._stepped_cluster_labels`, rule steps 1-5 of its module) on
the planes it is given in ``describe_scene`` (measured, and split where stepped), asking for
its verdicts.  Per flight: ``unassigned`` (the share of the flight's valid pixels in no
plane), ``wave`` (the frame's :attr:`planerel.segment.noise.NoiseModel.wave`: an active stereo
camera's undulation, 3 or more) and its ``clusters``: the :data:`TOP` candidate clusters with
most pixels in it (``pixels`` in the flight, ``size``, ``plane``: a segmented inclined plane,
not unexplained pixels), each with the first test it fails: ``narrow`` (no direction spans the
least width), ``slope``, ``taken`` (by a flight fitted before), ``plane`` (a plane explains the
points as well as a profile), ``no fit``, ``resolve`` (on a wavy frame, a rise under the
noise bands of its levels), ``inliers`` (under ``min_inliers`` of its points on
the profile), ``faces``, ``face width``, or ``kept``, and the measures it got that far
(``slope``, ``plane`` and ``share`` within the truncation, ``faces``, ``rise``, ``run``).
Clusters under ``min_pixels`` are ``small``.

``--aggregate`` prints only the counts by found or not and the largest cluster's verdict, and
the lost flights' waves and inlier shares (for judge sets: no frame names).
"""

from __future__ import annotations

import json
import sys
from collections import Counter
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))

#: Clusters reported per flight (most pixels in it first) and the least pixels in it.
TOP = 3
MIN_IN = 50


#: The last frame's stairfit verdicts (a frame with two flights is fitted once).
_LAST: dict = {}


def frame_verdicts(clf, cloud, labels, up) -> tuple:
    """``(planes, why)``: the planes the stairfit stage is given in ``describe_scene``
    (:func:`planerel.features.facts.measured_planes` with the classifier's settings) and the
    stage's verdicts on them; the last frame's again for the same cloud."""
    from planerel.features.facts import measured_planes
    from planerel.features.relations import ProposalParams
    from planerel.features.stairfit import _stepped_cluster_labels

    if _LAST.get("cloud") is cloud:
        return _LAST["got"]
    kw = clf._describe_kw
    planes, _ = measured_planes(cloud, labels, up, kw.get("plane_params"),
                                kw.get("gravity_params"),
                                kw.get("proposal_params") or ProposalParams())
    why: dict = {}
    _stepped_cluster_labels(cloud, planes, why=why)
    _LAST.update(cloud=cloud, got=(planes, why))
    return planes, why


def flight_clusters(clf, cloud, labels, desc, mask) -> dict:
    """:func:`stairs_census.census`'s ``extra``: the stairfit verdicts of the clusters in one
    flight (``mask``, ``(H, W)`` bool)."""
    from planerel.segment.noise import estimate_noise

    planes, why = frame_verdicts(clf, cloud, labels, desc.planes.up)
    valid = np.asarray(cloud.valid) & mask
    lab = np.asarray(planes.labels)
    out = {"unassigned": round(float((valid & (lab < 0)).sum()) / max(1, int(valid.sum())), 2),
           "wave": round(float(estimate_noise(cloud, waviness=True).wave), 2), "clusters": []}
    if "clusters" not in why:
        return out
    rows, cols, ids, n_comp, sizes = why["clusters"]
    inside = np.bincount(ids[mask[rows, cols]], minlength=len(sizes))
    for c in np.argsort(-inside, kind="stable")[:TOP]:
        if inside[c] < MIN_IN:
            break
        test, measures = why["verdicts"].get(int(c), ("small", {}))
        out["clusters"].append({"pixels": int(inside[c]), "size": int(sizes[c]),
                                "plane": bool(c >= n_comp), "test": test, **measures})
    return out


def aggregate(rows) -> tuple[Counter, list]:
    """``(verdicts, lost)``: flights by found or not and their largest cluster's test, and the
    lost flights' ``(wave, largest cluster's test, its inlier share or None)``."""
    verdicts, lost = Counter(), []
    for r in rows:
        top = r["clusters"][0] if r.get("clusters") else None
        test = top["test"] if top else "no cluster"
        found = r["stage"] == "found"
        verdicts[("found" if found else "lost", test)] += 1
        if not found:
            lost.append((r.get("wave"), test, top.get("share") if top else None))
    return verdicts, sorted(lost, key=lambda t: (t[0] is None, t[0] or 0.0))


def main(argv=None) -> int:
    from stairs_census import census_cli

    a, rows = census_cli("stairfit_why", __doc__.split("\n")[0], argv, extra=flight_clusters)
    if a is None:
        return rows
    verdicts, lost = aggregate(rows)
    print("all", len(rows), dict(Counter(r["stage"] for r in rows).most_common()))
    print("largest cluster", {f"{k[0]}: {k[1]}": v for k, v in sorted(verdicts.items())})
    print("lost (wave, test, share)", lost)
    if not a.aggregate:
        for r in rows:
            print(json.dumps({k: r[k] for k in ("set", "frame", "stage", "unassigned", "wave",
                                                "clusters") if k in r}))
    if a.json:
        Path(a.json).write_text(json.dumps(rows, indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main())
