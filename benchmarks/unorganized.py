"""Real organized frames made unorganized, and what the product answers on them.

    .venv/bin/python benchmarks/unorganized.py DIR --model out/model [--only learn|test]
        [--variants organized,shuffled,voxel5,half] [--json F] [--verbose]
    .venv/bin/python benchmarks/unorganized.py --answers FILE... --model out/model

Users' clouds are often unorganized (filtered, voxel-downsampled, exported to PLY, merged).
planerel puts such a cloud on an image grid seen from the sensor
(:func:`planerel.io.organize.organize`); this script measures what that gives against the
organized originals.  Each frame of ``DIR`` (the mOSD PCDs, as ``benchmarks/real_mosd.py``
takes them) is written, in a temporary folder (never in the repository), as unorganized
binary PCDs (``HEIGHT 1``, fields ``x y z label``):

``shuffled``  its valid points (NaN dropped) in a random order, each coordinate jittered by
              N(0, 0.5 mm) (so no longer an exact back-projection: ``pinhole_grid`` does not
              put them back on the camera's grid);
``voxel5``    a 5 mm voxel grid filter of the valid points (the centroid of each occupied 5 mm
              cube, its label the most frequent one), as PCL's ``VoxelGrid`` leaves a cloud;
``half``      a random half of the ``shuffled`` points.

Each is read as the product reads it (``planerel.io.read``: the z-buffer grid, the labels on
the same grid by ``read_pcd_field``) and scored with real_mosd's ``frame`` and ``summarize``
(IoU >= 0.5 against the labels of the points that hold a pixel); ``organized`` is the original
file, in the same run.  Printed per variant: objects found, boxes answered ``box``, false
proposals, stairs / ramp answers, the ms a frame of reading (``planerel.io.read``, with the
grid) and of real_mosd's whole ``frame`` (reading the points and the labels, classifying,
describing again and scoring; after one untimed warm-up frame), and the ratios to
``organized``.  The random draws are seeded by the frame's name.

``--answers FILE...`` reads each file (any organized scan: ``../shared/data/kinect/office1.pcd``,
``../shared/data/mosd/*.pcd``), makes the same three variants (without labels) and prints the
class answers of each, with the grid and the ms its reading took, and those of the
``shuffled`` variant read unorganized (``--no-organize``, the behaviour before the grid).
"""
from __future__ import annotations

import argparse
import json
import sys
import tempfile
import time
import warnings
import zlib
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))

VARIANTS = ("organized", "shuffled", "voxel5", "half")
JITTER_M = 0.0005
VOXEL_M = 0.005


def _rng(name: str, variant: str) -> np.random.Generator:
    return np.random.default_rng(zlib.crc32(f"{name}/{variant}".encode()))


def make_variant(xyz: np.ndarray, label: np.ndarray | None, variant: str, name: str):
    """``(points (N, 3) float32, labels (N,) uint32 or None)`` of one unorganized variant of a
    frame's points ``xyz`` (any shape ``(..., 3)``, NaN invalid) and their ``label``."""
    pts = np.asarray(xyz, dtype=np.float64).reshape(-1, 3)
    ok = np.all(np.isfinite(pts), axis=1)
    pts = pts[ok]
    lab = None if label is None else np.asarray(label).reshape(-1)[ok]
    if variant in ("shuffled", "half"):
        rng = _rng(name, "shuffled")
        order = rng.permutation(len(pts))
        pts = pts[order] + rng.normal(0.0, JITTER_M, pts.shape)
        lab = None if lab is None else lab[order]
        if variant == "half":
            keep = _rng(name, "half").random(len(pts)) < 0.5
            pts, lab = pts[keep], (None if lab is None else lab[keep])
    elif variant == "voxel5":
        key = np.floor(pts / VOXEL_M).astype(np.int64)
        _, inv = np.unique(key, axis=0, return_inverse=True)
        inv = inv.ravel()
        n = np.bincount(inv)
        pts = np.stack([np.bincount(inv, pts[:, k]) / n for k in range(3)], axis=1)
        if lab is not None:
            # the most frequent label of each voxel (the smallest of equally frequent ones)
            pairs, counts = np.unique(np.stack([inv, lab.astype(np.int64)], axis=1), axis=0,
                                      return_counts=True)
            order = np.lexsort((pairs[:, 1], -counts, pairs[:, 0]))
            pairs = pairs[order]
            first = np.ones(len(pairs), bool)
            first[1:] = pairs[1:, 0] != pairs[:-1, 0]
            lab = np.zeros(len(pts), np.uint32)
            lab[pairs[first, 0]] = pairs[first, 1]
        order = _rng(name, "voxel5").permutation(len(pts))
        pts, lab = pts[order], (None if lab is None else lab[order])
    else:
        raise ValueError(variant)
    return pts.astype(np.float32), lab


def write_variant(path: Path, pts: np.ndarray, lab: np.ndarray | None) -> None:
    import pypcd4

    if lab is None:
        pc = pypcd4.PointCloud.from_xyz_points(pts)
    else:
        pc = pypcd4.PointCloud.from_points([pts[:, 0], pts[:, 1], pts[:, 2], lab.astype(np.uint32)],
                                           ("x", "y", "z", "label"),
                                           (np.float32, np.float32, np.float32, np.uint32))
    pc.save(path, encoding=pypcd4.Encoding.BINARY)


def _read_raw(path: Path):
    import pypcd4

    pc = pypcd4.PointCloud.from_path(path)
    xyz = np.asarray(pc.numpy(("x", "y", "z")), dtype=np.float64)
    lab = np.asarray(pc.pc_data["label"]) if "label" in pc.metadata.fields else None
    return xyz, lab


def _read_ms(path: Path, organize: bool = True) -> tuple[float, object]:
    from planerel.io import readers as io

    t0 = time.perf_counter()
    cloud = io.read(path, organize=organize)
    return 1000 * (time.perf_counter() - t0), cloud


def mosd(a) -> int:
    import real_mosd

    from planerel.classify.classifier import Classifier
    from planerel.commands.classify import _params

    key = real_mosd.category
    paths = []
    for p in Path(a.folder).glob("*.pcd"):
        try:
            split = key(p.stem)[0]
        except ValueError:
            continue
        if not a.only or split == a.only:
            paths.append(p)
    paths.sort(key=lambda p: (p.stem.rstrip("0123456789"), int(p.stem.lstrip("learnts"))))
    if a.limit:
        paths = paths[: a.limit]
    if not paths:
        print(f"{a.folder}: no mOSD frames (learnN.pcd, testN.pcd)", file=sys.stderr)
        return 2
    variants = [v.strip() for v in a.variants.split(",") if v.strip()]
    results = {v: {"frames": [], "rows": [], "read_ms": [], "grid": []} for v in variants}
    with tempfile.TemporaryDirectory(prefix="planerel-unorganized-") as tmp, \
            Classifier(a.model, seg_params=_params(a.param)) as clf:
        for v in variants:
            if v != "organized":
                (Path(tmp) / v).mkdir()
        real_mosd.frame(clf, paths[0])  # warm-up (Prolog, kernels): not timed
        for p in paths:
            xyz, lab = _read_raw(p)
            for v in variants:
                if v == "organized":
                    q = p
                else:
                    q = Path(tmp) / v / p.name
                    write_variant(q, *make_variant(xyz, lab, v, p.stem))
                ms, cloud = _read_ms(q)
                t0 = time.perf_counter()
                fr, rows = real_mosd.frame(clf, q)
                fr["frame_ms"] = 1000 * (time.perf_counter() - t0)
                r = results[v]
                r["frames"].append(fr)
                r["rows"] += rows
                r["read_ms"].append(ms)
                r["grid"].append([cloud.shape[1], cloud.shape[0], cloud.n_valid])
                if v != "organized":
                    q.unlink()
                if a.verbose:
                    print(f"{p.stem} {v}: {cloud.shape[1]}x{cloud.shape[0]}, found "
                          f"{fr['found']}/{fr['objects']}, false {fr['false']}, answers "
                          f"{fr['answers']} [read {ms:.0f} ms, frame {fr['frame_ms']:.0f} ms]",
                          flush=True)
    out = {}
    for v in variants:
        r = results[v]
        s = real_mosd.summarize(r["frames"], r["rows"])
        s["read_ms_per_frame"] = float(np.mean(r["read_ms"]))
        s["frame_ms_per_frame"] = float(np.mean([f["frame_ms"] for f in r["frames"]]))
        s["grid_median"] = [float(np.median([g[i] for g in r["grid"]])) for i in range(3)]
        out[v] = s
    base = out.get("organized")
    print(f"{len(paths)} mOSD frames ({a.folder}); model {a.model}")
    for v, s in out.items():
        w, h, n = s["grid_median"]
        line = (f"{v:10s} objects found {s['found']}/{s['objects']}, boxes `box` "
                f"{s['boxes_box']}/{s['boxes']}, false {s['false']} ({s['false_per_frame']:.2f} a "
                f"frame), stairs {s['stairs_answers']} ramp {s['ramp_answers']}; median grid "
                f"{w:.0f}x{h:.0f} with {n:.0f} points; read {s['read_ms_per_frame']:.0f} ms, frame "
                f"{s['frame_ms_per_frame']:.0f} ms")
        if base is not None and v != "organized":
            line += (f"; ratio to organized: found {s['found'] / max(base['found'], 1):.3f}, "
                     f"boxes {s['boxes_box'] / max(base['boxes_box'], 1):.3f}, false "
                     f"{s['false'] / max(base['false'], 1):.2f}, time "
                     f"{s['frame_ms_per_frame'] / max(base['frame_ms_per_frame'], 1e-9):.2f}")
        print(line)
    if a.json:
        with open(a.json, "w") as fh:
            json.dump({"summary": out, "frames": {v: results[v]["frames"] for v in variants},
                       "grid": {v: results[v]["grid"] for v in variants}}, fh, indent=1)
    return 0


def answers(a) -> int:
    from planerel.classify.classifier import Classifier
    from planerel.commands.classify import _params

    with tempfile.TemporaryDirectory(prefix="planerel-unorganized-") as tmp, \
            Classifier(a.model, seg_params=_params(a.param)) as clf:
        for f in a.answers:
            p = Path(f)
            xyz, _ = _read_raw(p)
            for v in (*VARIANTS, "shuffled --no-organize"):
                if v == "organized":
                    q = p
                else:
                    q = Path(tmp) / f"{p.stem}.pcd"
                    write_variant(q, *make_variant(xyz, None, v.split()[0], p.stem))
                ms, cloud = _read_ms(q, organize=not v.endswith("--no-organize"))
                ans = clf.classify(cloud, scene_id=p.stem)
                shape = (f"{cloud.shape[1]}x{cloud.shape[0]} grid" if cloud.organized
                         else "no grid")
                print(f"{p.name} {v:10s} {shape}, "
                      f"{int(np.isfinite(xyz).all(axis=-1).sum()) if v == 'organized' else cloud.n_valid} "
                      f"points on it; read {ms:.0f} ms, classify {1000 * ans.seconds:.0f} ms: "
                      f"{', '.join(o.klass for o in ans.objects) or '(no object)'}", flush=True)
    return 0


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("folder", nargs="?", help="folder of the mOSD PCDs (learnN.pcd, testN.pcd)")
    ap.add_argument("--answers", nargs="+", metavar="FILE",
                    help="print the class answers of these scans and their variants instead")
    ap.add_argument("--only", choices=("learn", "test"), help="one half of the set")
    ap.add_argument("--limit", type=int, help="the first N frames only")
    ap.add_argument("--variants", default=",".join(VARIANTS),
                    help=f"comma-separated, of {', '.join(VARIANTS)} (default: all)")
    ap.add_argument("--model", default="out/model")
    ap.add_argument("--param", action="append", default=[], metavar="NAME=VALUE")
    ap.add_argument("--json", help="write every frame's figures here")
    ap.add_argument("--verbose", action="store_true", help="print each frame's line")
    a = ap.parse_args(argv)
    from planerel.errors import PlanerelWarning

    warnings.simplefilter("ignore", PlanerelWarning)  # each grid's note; the script prints it
    if a.answers:
        return answers(a)
    if not a.folder:
        ap.error("give the mOSD folder, or --answers FILE...")
    bad = set(a.variants.split(",")) - set(VARIANTS)
    if bad:
        ap.error(f"unknown variants {sorted(bad)}; known: {', '.join(VARIANTS)}")
    return mosd(a)


if __name__ == "__main__":
    sys.exit(main())
