"""Output check for speed work on the description (relations, proposals, curved clusters):
saves, then compares, everything ``describe_scene`` + ``scene_facts`` give on every shared real
frame and on synthetic scenes, with the same labels on both sides.

    .venv/bin/python benchmarks/same_facts.py --save /tmp/before.json         # on the old code
    PYTHONPATH=/tmp/refmain .venv/bin/python benchmarks/same_facts.py --save /tmp/before.json
    .venv/bin/python benchmarks/same_facts.py --compare /tmp/before.json      # on the new code

Scenes: the Kinect TIFFs and office1.pcd, the mOSD PCDs (``../shared/data``), and synthetic
scenes written once into ``--data`` (default ``/tmp/same_facts_data``) by ``planerel dataset
synth``: the varied world with seeds 5 and 11, each with the basic and the ToF sensor, and the
paper world with seed 9 and the structured-light sensor (``--n`` scenes a set, 320x240).  The
labels are ``segment(cloud)``'s, computed by ``--save`` and stored next to the JSON
(``.npz``), so both sides describe the same labels.  Compared per scene: the facts text, every
relation's full values (``repr``: exact floats), the objects (planes, planar fraction, curved,
a hash of the pixel mask), the support planes, the planes' measures and the label image after
the stepped split.  Exit status 1 when anything differs.

``--rel-tol 1e-9``: the relations' floats may differ by that much (relative); everything
else, the facts text included, must still be identical (for kernels that sum a dot product
in another order than numpy's matrix product).
"""

from __future__ import annotations

import argparse
import glob
import hashlib
import json
import math
import re
import sys
from pathlib import Path

import numpy as np
from _setup import data_dir, kinect_files

SETS = (("varied", 5, "basic"), ("varied", 5, "tof"), ("varied", 11, "basic"),
        ("varied", 11, "tof"), ("paper", 9, "structured-light"))


def _h(a) -> str:
    a = np.ascontiguousarray(a)
    return hashlib.sha1(str((a.dtype, a.shape)).encode() + a.tobytes()).hexdigest()[:16]


def _clouds(folder: Path, n: int, extra: tuple = ()):
    """``(name, cloud)`` of every scene checked (``extra``: more files read as they are)."""
    from planerel.cli import main as cli
    from planerel.features import dataset
    from planerel.io.readers import read

    for f in kinect_files():
        yield f"kinect {Path(f).name[6:28]}", read(f)
    f = data_dir("kinect") / "office1.pcd"
    if f.exists():
        yield "kinect office1.pcd", read(f)
    for f in sorted(glob.glob(str(data_dir("mosd") / "*.pcd"))):
        yield f"mosd {Path(f).name}", read(f)
    for f in extra:
        yield f"extra {f}", read(f)
    for world, seed, sensor in SETS:
        ds = folder / f"{world}-{seed}-{sensor}-{n}"
        if not (ds / "manifest.csv").exists() and not any(ds.glob("manifest*")):
            k = n // 3
            cli(["dataset", "synth", str(ds), "--world", world, "--sensor", sensor,
                 "--n-box", str(n - 2 * k), "--n-stairs", str(k), "--n-ramp", str(k),
                 "--subsample", "2", "--seed", str(seed), "--quiet"])
        for row in dataset.load_manifest(ds):
            cloud, _labels, _meta = dataset.load_scene(ds, row.scene_id)
            yield f"{ds.name}/{row.scene_id}", cloud


_FIELD = re.compile(r"(\w+)=([^,()]+)")


def _same_relations(a: list, b: list, tol: float) -> bool:
    """The relations' ``repr``s of both sides equal, their floats within ``tol`` (relative)."""
    if len(a) != len(b):
        return False
    for x, y in zip(a, b, strict=True):
        fx, fy = _FIELD.findall(x), _FIELD.findall(y)
        if [k for k, _ in fx] != [k for k, _ in fy]:
            return False
        for (_, vx), (_, vy) in zip(fx, fy, strict=True):
            if vx == vy:
                continue
            try:
                u, v = float(vx), float(vy)
            except ValueError:
                return False
            if not math.isclose(u, v, rel_tol=tol, abs_tol=0.0):
                return False
    return True


def _record(desc) -> dict:
    from planerel.features.facts import scene_facts

    facts = scene_facts(desc)
    return {
        "facts": "\n".join(line for name in facts for line in facts[name]),
        "relations": [repr(r) for r in desc.relations],
        "objects": [[o.id, list(o.planes), o.klass, repr(o.planar_fraction), o.curved,
                     None if o.mask is None else _h(np.asarray(o.mask))] for o in desc.objects],
        "support": [int(s) for s in desc.support],
        "planes": [[p.label, repr(p.orientation), _h(p.normal), _h(p.centroid), _h(p.hull3d),
                    repr(float(p.area))] for p in desc.planes],
        "labels": _h(desc.labels),
    }


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    g = ap.add_mutually_exclusive_group(required=True)
    g.add_argument("--save")
    g.add_argument("--compare")
    ap.add_argument("--data", default="/tmp/same_facts_data", help="folder of the synthetic sets")
    ap.add_argument("--n", type=int, default=12, help="scenes per synthetic set")
    ap.add_argument("--rel-tol", type=float, default=0.0,
                    help="relative tolerance of the relations' floats (0: exact)")
    ap.add_argument("--extra", nargs="*", default=[],
                    help="more real frames to check (e.g. 20 of /work/extdata/mosd)")
    args = ap.parse_args(argv)
    from planerel.features.facts import describe_scene
    from planerel.segment import segment

    folder = Path(args.data)
    folder.mkdir(parents=True, exist_ok=True)
    path = Path(args.save or args.compare)
    npz = path.with_suffix(".labels.npz")
    if args.save:
        out, labels = {}, {}
        for i, (name, cloud) in enumerate(_clouds(folder, args.n, tuple(args.extra))):
            lab = segment(cloud).labels
            labels[f"l{i}"] = lab
            out[name] = {"index": i, **_record(describe_scene(cloud, lab))}
            print(f"{name:45s} {len(out[name]['objects']):3d} objects")
        np.savez_compressed(npz, **labels)
        path.write_text(json.dumps(out))
        return 0
    ref = json.loads(path.read_text())
    saved = np.load(npz)
    bad = seen = 0
    for name, cloud in _clouds(folder, args.n, tuple(args.extra)):
        if name not in ref:
            print(f"{name:45s} not in {path}")
            bad += 1
            continue
        r = ref[name]
        seen += 1
        now = _record(describe_scene(cloud, saved[f"l{r['index']}"]))
        diff = [k for k in now if now[k] != r[k]
                and not (k == "relations" and args.rel_tol > 0
                         and _same_relations(now[k], r[k], args.rel_tol))]
        bad += bool(diff)
        print(f"{name:45s} {'identical' if not diff else 'DIFFER: ' + ', '.join(diff)}")
    missing = len(ref) - seen
    print(f"{seen} scenes compared, {bad} differ, {missing} of the saved scenes not seen")
    return 1 if bad or missing else 0


if __name__ == "__main__":
    sys.exit(main())
