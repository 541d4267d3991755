"""``planerel dataset``: make and inspect data sets (``synth``, ``info``)."""

from __future__ import annotations

from planerel.errors import InputError

__all__ = ["register", "parse_size", "parse_range", "parse_world_ranges"]


def parse_size(text: str) -> tuple[int, int]:
    """``"640x480"`` -> ``(640, 480)``."""
    parts = text.lower().split("x")
    try:
        w, h = (int(p) for p in parts)
    except ValueError:
        raise InputError(f"--size must look like 640x480, got {text!r}") from None
    return w, h


def parse_range(text: str, name: str) -> tuple[float, float]:
    """``"0.5,1.5"`` -> ``(0.5, 1.5)``."""
    try:
        lo, hi = (float(p) for p in text.split(","))
    except ValueError:
        raise InputError(f"{name} must be two numbers like 0.5,1.5; got {text!r}") from None
    return lo, hi


def parse_world_ranges(items) -> dict:
    """``["steps=3,12", "descending=0.5"]`` -> ``{"steps": (3.0, 12.0), "descending": 0.5}``
    for :class:`planerel.synth.world.WorldRange` (which checks the values)."""
    import dataclasses

    from planerel.synth.world import WorldRange

    fields = {f.name for f in dataclasses.fields(WorldRange)}
    out = {}
    for item in items:
        name, sep, value = item.partition("=")
        name = name.strip().replace("-", "_")
        if not sep or name not in fields:
            raise InputError(f"--range must look like NAME=MIN,MAX with NAME one of "
                             f"{', '.join(sorted(fields))}; got {item!r}")
        parts = value.split(",")
        try:
            nums = [float(p) for p in parts]
        except ValueError:
            raise InputError(f"--range {name}: numbers expected, got {value!r}") from None
        if name in ("steps", "extra_objects"):
            if any(x != int(x) for x in nums):
                raise InputError(f"--range {name}: whole numbers expected, got {value!r}")
            nums = [int(x) for x in nums]
        if len(nums) == 1:
            out[name] = nums[0]
        elif len(nums) == 2:
            out[name] = tuple(nums)
        else:
            raise InputError(f"--range {name}: one number or MIN,MAX expected, got {value!r}")
    return out


def register(sub) -> None:
    p = sub.add_parser(
        "dataset",
        help="make a synthetic box/stairs/ramp data set with ground truth, or describe one",
        description="Data sets in planerel's format (docs/formats.md): per scene a 16-bit depth "
                    "PNG (mm), a JSON sidecar (camera, pose, up, class, true planes) and a "
                    "ground-truth plane-label PNG, plus manifest.csv.",
    )
    dsub = p.add_subparsers(dest="dataset_command", metavar="ACTION")
    s = dsub.add_parser(
        "synth",
        help="generate synthetic scenes (Kinect-like depth, exact ground truth)",
        description="Ray-cast box, stairs and ramp scenes (one object on a floor, 0-2 walls) from "
                    "a randomly placed Kinect-like camera and write them as a data set. The same "
                    "seed gives byte-identical files.",
    )
    s.add_argument("out_dir", metavar="OUT_DIR", help="folder to write (created if missing)")
    s.add_argument("--n-box", type=int, default=12, help="number of box scenes (default 12)")
    s.add_argument("--n-stairs", type=int, default=15, help="number of stairs scenes (default 15)")
    s.add_argument("--n-ramp", type=int, default=18, help="number of ramp scenes (default 18)")
    s.add_argument("--seed", type=int, default=0, help="random seed (default 0)")
    s.add_argument("--size", default="640x480", metavar="WxH",
                   help="full sensor size before subsampling (default 640x480)")
    s.add_argument("--subsample", type=int, default=4, metavar="K",
                   help="keep every K-th row and column (default 4: 640x480 -> 160x120)")
    s.add_argument("--camera-height", metavar="MIN,MAX",
                   help="camera height above the floor in metres (default 0.5,1.5)")
    s.add_argument("--camera-distance", metavar="MIN,MAX",
                   help="horizontal distance from the camera to the object's nearest point "
                        "(default 0.7,1.8)")
    s.add_argument("--range", action="append", default=[], metavar="NAME=MIN,MAX",
                   help="varied world: change one range of planerel.synth.world.WorldRange, e.g. "
                        "--range camera_pitch_deg=10,60 --range steps=3,12 (repeatable; for "
                        "held-out sets with shifted parameters)")
    s.add_argument("--max-range", type=float, metavar="M",
                   help="sensor maximum range in metres (default 4.5)")
    s.add_argument("--noise", type=float, metavar="C",
                   help="basic sensor: depth noise std = C * z^2 metres (default 0.0012; 0 = none)")
    s.add_argument("--world", choices=("paper", "varied"), default="paper",
                   help="paper (default): one object per scene, the paper-sized set; varied: "
                        "several objects and clutter (class other) per scene, camera 0.3-2 m "
                        "high pitched 0-75 deg and rolled, real stair and ramp dimensions, "
                        "descending stairs (docs/synthetic-world.md); --n-* count the scenes "
                        "by their primary object")
    s.add_argument("--sensor", choices=("basic", "structured-light", "tof", "laser"),
                   help="sensor model (docs/synthetic-world.md): basic (the paper world's "
                        "default), structured-light (the varied world's default) (Kinect v1: 1/8-px disparity, projector "
                        "shadows, flying pixels), tof (Kinect v2), laser")
    s.add_argument("--quiet", action="store_true", help="no progress bar")
    s.set_defaults(func=run_synth)
    i = dsub.add_parser("info", help="summarise a data set (scenes per class, planes per role)",
                        description="Read a data set's manifest and sidecars and print a summary.")
    i.add_argument("path", metavar="DIR", help="data-set folder")
    i.set_defaults(func=run_info)
    p.set_defaults(func=lambda args: _no_action(p))


def _no_action(parser) -> int:
    parser.print_help()
    return 2


def run_synth(args) -> int:
    import dataclasses
    import sys
    import time

    from planerel.synth.generator import CameraRange, SensorModel, generate_dataset
    from planerel.synth.sensor import StructuredLight, sensor_profile
    from planerel.synth.world import WorldRange

    size = parse_size(args.size)
    cam_kwargs = {}
    if args.camera_height:
        cam_kwargs["height"] = parse_range(args.camera_height, "--camera-height")
    if args.camera_distance:
        if args.world != "paper":
            raise InputError("--camera-distance applies to the paper world; the varied world "
                             "places its objects 0.8-3.8 m from the camera")
        cam_kwargs["distance"] = parse_range(args.camera_distance, "--camera-distance")
    ranges = None
    if args.world == "paper":
        camera = CameraRange(**cam_kwargs)
    else:
        camera = None
        changes = {"camera_height": cam_kwargs["height"]} if "height" in cam_kwargs else {}
        changes.update(parse_world_ranges(args.range))
        ranges = WorldRange(**changes)
    if args.range and args.world == "paper":
        raise InputError("--range changes the varied world's ranges; add --world varied")
    default_sensor = SensorModel() if args.world == "paper" else StructuredLight()
    sensor = sensor_profile(args.sensor) if args.sensor else default_sensor
    changes = {}
    if args.max_range is not None:
        changes["max_range"] = args.max_range
    if args.noise is not None:
        if not isinstance(sensor, SensorModel):
            raise InputError(f"--noise sets the basic sensor's noise; the {args.sensor} sensor "
                             "has its own documented noise model")
        changes["noise"] = args.noise
    if changes:
        sensor = dataclasses.replace(sensor, **changes)
    t0 = time.perf_counter()
    out = generate_dataset(args.out_dir, n_box=args.n_box, n_stairs=args.n_stairs,
                           n_ramp=args.n_ramp, seed=args.seed, size=size,
                           subsample=args.subsample, sensor=sensor, camera=camera,
                           progress=not args.quiet and sys.stderr.isatty(), world=args.world,
                           ranges=ranges)
    n = args.n_box + args.n_stairs + args.n_ramp
    what = "" if args.world == "paper" else "primary object: "
    print(f"wrote {n} {args.world}-world scenes ({what}{args.n_box} box, {args.n_stairs} stairs, "
          f"{args.n_ramp} ramp) to {out} in {time.perf_counter() - t0:.1f} s")
    return 0


def run_info(args) -> int:
    from collections import Counter

    from planerel.features.dataset import load_dataset_info, load_manifest, load_metadata

    rows = load_manifest(args.path)
    info = load_dataset_info(args.path)
    classes = Counter(r.klass for r in rows)
    sizes = Counter(f"{r.width}x{r.height}" for r in rows)
    print(f"{args.path}: {len(rows)} scenes; " + ", ".join(f"{k} {v}" for k, v in sorted(classes.items()))
          + " (scenes by the class of their main object, manifest.csv); size "
          + ", ".join(sorted(sizes)))
    if info:
        print(f"made by {info.get('format', '?')}"
              + (f" with seed {info['seed']}" if info.get("seed") is not None else ""))
    roles = Counter()
    objects = Counter()
    seen = 0
    for r in rows:
        meta = load_metadata(args.path, r.scene_id)
        for pl in meta.get("planes", []):
            if pl.get("n_pixels", 1) > 0:
                roles[pl["role"]] += 1
                seen += 1
        for o in meta.get("objects", [])[1:]:
            if o.get("n_pixels", 1) > 0 and "kind" in o:
                objects[f"{o.get('class')} ({o['kind']})"] += 1
    print(f"{seen} visible ground-truth planes: " + ", ".join(f"{k} {v}" for k, v in sorted(roles.items())))
    if objects:
        print(f"{sum(objects.values())} ground-truth objects with pixels in view: "
              + ", ".join(f"{k} {v}" for k, v in sorted(objects.items())))
    print("planerel learn takes as examples only the objects whose segmented planes show their "
          "class, and says how many\nit left out and why (docs/formats.md, \"Counting objects\")")
    return 0
