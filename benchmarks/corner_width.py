"""For each ground-truth object of a synthetic data set: does any ``corner/2`` fact hold among
its planes with ``relations.corner_width`` W?  Counts by example class (``excl``: not an
example) for W = 0.08, 0.06, 0.05, 0.04, 0.03 m (product37, docs/objects.md "Product-size
boxes in the training world").

    nice .venv/bin/python benchmarks/corner_width.py DATASET
"""

import collections
import functools
import sys
from pathlib import Path

import planerel.features.facts as facts
from planerel.features.dataset import describe_truth_scene, load_manifest, load_scene
from planerel.features.relations import RelationParams
from planerel.segment import segment

WIDTHS = (0.08, 0.06, 0.05, 0.04, 0.03)


def main(argv=None) -> int:
    folder = Path((argv or sys.argv[1:])[0])
    orig = facts.describe_scene
    counts = collections.defaultdict(collections.Counter)
    try:
        for row in load_manifest(folder):
            cloud, gt, meta = load_scene(folder, row.scene_id)
            labels = segment(cloud).labels
            for w in WIDTHS:
                # describe_truth_scene imports describe_scene from facts at call time
                facts.describe_scene = functools.partial(
                    orig, relation_params=RelationParams(corner_width=w))
                desc = describe_truth_scene(cloud, labels, gt, meta, row.scene_id, row.klass)
                corner = {(r.a, r.b) for r in desc.relations if r.corner}
                for o in desc.objects:
                    planes = set(o.planes)
                    key = o.klass or "excl"
                    counts[key][w] += any(a in planes and b in planes for a, b in corner)
                    if w == WIDTHS[0]:
                        counts[key]["n"] += 1
    finally:
        facts.describe_scene = orig
    for key, c in sorted(counts.items()):
        print(f"{key}: {c['n']} objects; with a corner at W = "
              + ", ".join(f"{w}: {c[w]}" for w in WIDTHS))
    return 0


if __name__ == "__main__":
    sys.exit(main())
