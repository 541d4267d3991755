"""The demo model's training world: the paper-sized scenes plus a Kinect-like room with clutter.

The paper-sized set (:func:`planerel.synth.generator.generate_dataset`, one object per scene) has no object
that is none of the classes, so rules learned from it only need to tell box, stairs and ramp
apart: plane counts do that, and they fire on anything with one inclined plane (a laptop lid, an
edge fragment) or one horizontal plane (a cylinder's top).  The demo model is learned from both:

* the paper-sized scenes, ``s0000 ..`` (the same scenes as ``generate_dataset`` with the same
  seed), and
* scenes of the varied world (:mod:`planerel.synth.world`) with the structured-light sensor and
  :data:`KINECT_ROOM` ranges: a hand-held or robot-mounted Kinect 0.6-1.6 m above the floor
  looking 20-60 degrees down at boxes 0.12-1.2 m, staircases of 2-6 steps (most seen from
  above, going down), ramps, and
  one to three more objects per scene, most of them clutter (tables, chairs, cylinders, laptops,
  small tilted plates, shelves, doors) whose objects are labelled ``other``: negatives for every
  class.

The scenes of one data set share one folder and one manifest; the varied scenes continue the
numbering (``s0045 ..`` after 45 paper scenes) and use seeds :func:`planerel.synth.generator.scene_seed`
``(seed + 1, i)``, so both parts are deterministic and independent of each other's size.
"""

from __future__ import annotations

from pathlib import Path

from planerel.errors import InputError

__all__ = ["KINECT_ROOM", "generate_training_world"]

#: Ranges of the Kinect-like part (others: :class:`planerel.synth.world.WorldRange` defaults).
KINECT_ROOM = {
    "camera_height": (0.6, 1.6),
    "camera_pitch_deg": (20.0, 60.0),
    "object_range": (0.8, 3.0),
    "extra_objects": (1, 3),
    "box_size": (0.12, 1.2),
    "box_height": (0.08, 0.9),
    "steps": (2, 6),
    "descending": 0.6,
}


def generate_training_world(out_dir, *, paper=(12, 15, 18), room=(30, 30, 30), seed: int = 0,
                            size=(640, 480), subsample: int = 4, ranges=None) -> Path:
    """Write one data set: ``paper`` box/stairs/ramp scenes of the paper-sized world, then
    ``room`` box/stairs/ramp scenes (primary object) of the Kinect-like varied world.

    Parameters
    ----------
    out_dir : path
        The data set folder (replaced whole).
    paper, room : (int, int, int)
        Scene counts (box, stairs, ramp) of each part.
    seed : int
        Seed of the paper part; the room part uses ``seed + 1``.
    size, subsample
        As for :func:`planerel.synth.generator.generate_dataset`.
    ranges : WorldRange, optional
        The room part's ranges (default :data:`KINECT_ROOM`).

    Returns
    -------
    Path
        ``out_dir``.
    """
    from planerel.atomic import atomic_dir
    from planerel.features.dataset import write_dataset_info, write_manifest, write_scene
    from planerel.synth.generator import (
        CLASSES,
        SensorModel,
        _check_seed,
        _check_size,
        generate_scene,
        scene_seed,
    )
    from planerel.synth.sensor import StructuredLight
    from planerel.synth.world import WorldRange, generate_world_scene

    seed = _check_seed(seed)
    counts = {}
    for name, part in (("paper", paper), ("room", room)):
        try:
            n = [int(x) for x in part]
        except (TypeError, ValueError):
            raise InputError(f"{name} counts must be three integers (box, stairs, ramp), "
                             f"got {part!r}") from None
        if len(n) != 3 or min(n) < 0 or any(int(x) != x for x in part):
            raise InputError(f"{name} counts must be three non-negative integers (box, stairs, "
                             f"ramp), got {part!r}")
        counts[name] = dict(zip(CLASSES, n, strict=True))
    if not sum(counts["paper"].values()) + sum(counts["room"].values()):
        raise InputError("a data set needs at least one scene (all counts are 0)")
    ranges = WorldRange(**KINECT_ROOM) if ranges is None else ranges
    paper_sensor, room_sensor = SensorModel(), StructuredLight()
    jobs = ([("paper", k) for k in CLASSES for _ in range(counts["paper"][k])]
            + [("room", k) for k in CLASSES for _ in range(counts["room"][k])])
    n_paper = sum(counts["paper"].values())
    rows = []
    with atomic_dir(Path(out_dir), markers=("manifest.csv", "dataset.json")) as tmp:
        for i, (part, kind) in enumerate(jobs):
            sid = f"s{i:04d}"
            if part == "paper":
                scene = generate_scene(kind, scene_seed(seed, i), size, subsample, scene_id=sid,
                                       sensor=paper_sensor)
            else:
                scene = generate_world_scene(kind, scene_seed(seed + 1, i - n_paper), size,
                                             subsample, scene_id=sid, sensor=room_sensor,
                                             ranges=ranges)
            rows.append(write_scene(tmp, scene))
        write_manifest(tmp, rows)
        write_dataset_info(tmp, {
            "format": "planerel-synth-dataset", "version": 1, "seed": seed,
            "world": "paper+kinect-room", "counts": counts,
            "size": list(_check_size(size)), "subsample": int(subsample),
            "sensor": {"paper": paper_sensor.to_dict(), "room": room_sensor.to_dict()},
            "world_ranges": ranges.to_dict(),
        })
    return Path(out_dir)
