"""Time of relations + object proposals with and without the concave-edge split, in one run.

    .venv/bin/python benchmarks/bench_proposals.py [--repeat N] [--synth N]

Frames: the mOSD frames of ``../shared/data/mosd`` (640x480) and N cluttered varied-world
scenes (320x240, 2-3 extra objects, seed 22).  Each frame is segmented once; then
``describe_scene`` (measure planes, relate, propose) runs with ``split_concave=False,
min_border_area=0, border_wall_area=0, wall_behind=1, floor_gap=1, raised_objects=False,
ramp_tilt=0``
(the reference: plain connected components, the proposals before issue 22), with
``cavities=False, cut_apart_parallel=False, ramp_tilt=0`` (the defaults before the concave
cavities, the cut of parallel faces apart and the shallow-ramp test, main at a760b49), with
``occluded_channels=False, cavity_skip_walls=False`` (the defaults before the occluded channels
and walls kept out of cavities, main at c3a6d74), with ``split_panels=False,
occluded_pieces=False, side_wall_members=0, cut_long_side=False, apart_edge=0`` and
``CurvedParams(join_area=0)`` (the defaults before the sixth pass, main at c986474), with
``shared_top=False`` and ``CurvedParams(regrow_px=0)`` (the defaults before the seventh
pass, main at 09f30bd), with ``concave_cut=0`` (the defaults before the eighth pass, main at
ec6f66b), with ``stacked_boards=False, riser_max=0.45`` (the defaults before the tenth pass,
main at 99e83eb; the earlier variants have these too), with ``stacked_faces=0`` and
``CurvedParams(join_facets=False, near_depth=0.0)`` (the defaults before tabletop22, main at 456e27b; the
earlier variants have these too, and ``side_wall_follow=0``: synth22q's one side wall whose top
follows the flight; synth22q's raised groups, ``RaisedParams``, are the same in every variant;
every variant but the defaults also has synth22r's ``riser_floor=False, skip_missing=False`` and
``CurvedParams(bridge_area=0)``) and the defaults, interleaved, ``--repeat`` times; the median per frame is summed.
Printed: ms per frame of each and its ratio to the reference, and the proposals' found rate /
false proposals per frame (planerel.features.object_eval).  For the synthetic scenes a second
line, ``fair``, scores them without the objects the learner calls mostly hidden (a box or
clutter object under 30 % of it seen: :func:`planerel.features.object_eval.mostly_hidden`);
the first line counts every object with a visible pixel, as before.
"""

from __future__ import annotations

import argparse
import json
import statistics
import sys
import tempfile
import time

from _setup import cluttered_set, data_dir


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--synth", type=int, default=15, help="synthetic scenes (0 = none)")
    ap.add_argument("--seed", type=int, default=22, help="seed of the synthetic scenes")
    ap.add_argument("--no-mosd", action="store_true", help="leave the mOSD frames out")
    args = ap.parse_args(argv)
    from planerel.features.curved import CurvedParams
    from planerel.features.facts import describe_scene
    from planerel.features.object_eval import (
        MISS_KINDS,
        frame_truth,
        miss_breakdown,
        mostly_hidden,
        proposal_image,
        score_objects,
        summarize,
    )
    from planerel.features.relations import ProposalParams
    from planerel.segment import segment

    data = data_dir("mosd")
    inputs = sorted(data.glob("*.pcd")) if data.is_dir() and not args.no_mosd else []
    tmp = tempfile.TemporaryDirectory()
    if args.synth:
        inputs.append(cluttered_set(tmp.name, args.synth, seed=args.seed))
    frames = []
    hidden = {}
    for path in inputs:
        if path.is_dir():
            from planerel.features import dataset

            for row in dataset.load_manifest(path):
                meta = json.loads((path / row.meta).read_text())
                hidden[f"{path.name}/{row.scene_id}"] = mostly_hidden(meta)
        for name, cloud, truth, ty in frame_truth(path):
            frames.append((name, cloud, segment(cloud).labels, truth, ty))
    # the tenth pass's rules off, and tabletop22's stacked faces
    OLD10 = dict(stacked_boards=False, riser_max=0.45, stacked_faces=0.0, side_wall_follow=0.0,  # noqa: N806
                 riser_floor=False, skip_missing=False)
    variants = {"before (components)": ProposalParams(split_concave=False, min_border_area=0, border_wall_area=0,
                                                    wall_behind=1, floor_gap=1.0, raised_objects=False,
                                                    ramp_tilt=0.0, split_panels=False,
                                                    occluded_pieces=False, side_wall_members=0,
                                                    cut_long_side=False, apart_edge=0, shared_top=False,
                                                    concave_cut=0.0, **OLD10),
                "before 4th pass": ProposalParams(cavities=False, cut_apart_parallel=False, ramp_tilt=0.0,
                                                  split_panels=False, occluded_pieces=False,
                                                  side_wall_members=0, cut_long_side=False,
                                                  apart_edge=0, shared_top=False, concave_cut=0.0, **OLD10),
                "before 5th pass": ProposalParams(occluded_channels=False, cavity_skip_walls=False,
                                                  split_panels=False, occluded_pieces=False,
                                                  side_wall_members=0, cut_long_side=False,
                                                  apart_edge=0, shared_top=False, concave_cut=0.0, **OLD10),
                "before 6th pass": ProposalParams(split_panels=False, occluded_pieces=False,
                                                  side_wall_members=0, cut_long_side=False,
                                                  apart_edge=0, shared_top=False, concave_cut=0.0, **OLD10),
                "before 7th pass": ProposalParams(shared_top=False, concave_cut=0.0, **OLD10),
                "before 8th pass": ProposalParams(concave_cut=0.0, **OLD10),
                "before 10th pass": ProposalParams(**OLD10),
                "before tabletop22": ProposalParams(stacked_faces=0.0, riser_floor=False,
                                                   skip_missing=False),
                "defaults": ProposalParams()}
    # the curved clusters' parameters of each variant (the sixth pass's one-plane join, the
    # seventh pass's clusters grown back)
    curved = {k: CurvedParams(join_area=0.0, regrow_px=0, join_facets=False, near_depth=0.0,
                              bridge_area=0.0) for k in variants}
    curved["before 7th pass"] = CurvedParams(regrow_px=0, join_facets=False, near_depth=0.0, bridge_area=0.0)
    curved["before 8th pass"] = CurvedParams(join_facets=False, near_depth=0.0, bridge_area=0.0)
    curved["before 10th pass"] = CurvedParams(join_facets=False, near_depth=0.0, bridge_area=0.0)
    curved["before tabletop22"] = CurvedParams(join_facets=False, near_depth=0.0, bridge_area=0.0)
    curved["defaults"] = CurvedParams()
    times = {k: [] for k in variants}
    scores = {k: {"mosd": [], "synth": [], "fair": []} for k in variants}
    misses = {k: {"mosd": [], "synth": []} for k in variants}
    for name, cloud, labels, truth, ty in frames:
        per = {k: [] for k in variants}
        for _ in range(args.repeat):
            for k, pp in variants.items():
                t0 = time.perf_counter()
                d = describe_scene(cloud, labels, proposal_params=pp, curved_params=curved[k])
                per[k].append(1000 * (time.perf_counter() - t0))
        for k, pp in variants.items():
            times[k].append(statistics.median(per[k]))
            d = describe_scene(cloud, labels, proposal_params=pp, curved_params=curved[k])
            img = proposal_image(d.labels, [o.planes for o in d.objects], [o.mask for o in d.objects])
            group = "synth" if "/" in name else "mosd"
            sc = score_objects(img, truth, name=name, types=ty)
            scores[k][group].append(sc)
            if group == "synth":
                scores[k]["fair"].append(score_objects(img, truth, name=name, types=ty,
                                                       ignore=hidden.get(name, ())))
            misses[k][group].append((sc, img, truth, labels, d.support))
    ref = sum(times["before (components)"])
    for k in variants:
        t = sum(times[k])
        print(f"{k:22s} describe+propose {t / len(frames):7.1f} ms/frame  ratio {t / ref:.3f}")
        for g in ("mosd", "synth", "fair"):
            if scores[k][g]:
                s = summarize(scores[k][g])
                print(f"    {g:5s}: {s['frames']} frames, found {s['found']}/{s['objects']} "
                      f"({100 * s['found_rate']:.1f} %), false {s['false_per_frame']:.2f}/frame, "
                      f"merged {s['merged']}, split {s['split']}")
                if g == "fair":
                    continue
                for t, c in sorted(miss_breakdown(misses[k][g]).items()):
                    kinds = ", ".join(f"{x} {c[x]}" for x in MISS_KINDS if c.get(x))
                    print(f"        {t:8s} found {c.get('found', 0)}/{sum(c.values())}"
                          f"{'; missed: ' + kinds if kinds else ''}")
    tmp.cleanup()
    return 0


if __name__ == "__main__":
    sys.exit(main())
