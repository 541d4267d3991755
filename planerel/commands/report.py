"""``planerel report``: rerun the paper's segmentation comparison and write it as a report."""

from __future__ import annotations

__all__ = ["register", "run"]


def register(sub) -> None:
    p = sub.add_parser(
        "report",
        help="reproduce the paper's region growing vs RANSAC comparison as an HTML/Markdown "
             "report",
        description="Segment every scene of a data set with region growing and the RANSAC "
                    "baselines SP / SNP at the paper's thresholds, score them against ground "
                    "truth (SegComp at 80%, mean IoU, sparse planes), draw side-by-side "
                    "segmentations, compare the rules learned from each method's planes, time "
                    "each method, and do the same on the real data in ../shared/data. Writes "
                    "REPORT_DIR/index.html (self-contained), report.md with figures/, "
                    "results.json and csv/.",
    )
    p.add_argument("dataset", metavar="DATASET_DIR",
                   help="data set with ground truth (make one with 'planerel dataset synth')")
    p.add_argument("-o", "--out", required=True, metavar="REPORT_DIR", help="folder to write")
    p.add_argument("--methods", default="paper", metavar="LIST",
                   help="comma-separated methods, e.g. sp:0.01,snp:0.05,regiongrow (default "
                        "'paper': SP 0.005/0.01/0.03/0.05, SNP 0.01/0.03/0.05, regiongrow)")
    p.add_argument("--tolerance", type=float, default=0.8,
                   help="SegComp overlap tolerance T (default 0.8)")
    p.add_argument("--sizes", default="160x120,640x480", metavar="WxH,...",
                   help="image sizes of the timing section (default 160x120,640x480; '' = none)")
    p.add_argument("--no-timing", action="store_true",
                   help="skip timing (the whole output is then byte-identical run to run)")
    p.add_argument("--timing-repeats", type=int, default=3,
                   help="timed calls per scene, method and size (default 3)")
    p.add_argument("--no-objects", action="store_true",
                   help="skip scoring object proposals against ground-truth objects")
    p.add_argument("--no-learning", action="store_true",
                   help="skip the learning comparison (the most expensive part)")
    p.add_argument("--folds", type=int, default=10, help="cross-validation folds (default 10)")
    p.add_argument("--engine", default="builtin", choices=("builtin", "aleph", "auto"),
                   help="learner for the learning comparison (default builtin)")
    p.add_argument("--timeout", type=float, default=120.0,
                   help="seconds per learning run (default 120)")
    p.add_argument("--seed", type=int, default=0, help="seed of folds and timing scenes (0)")
    g = p.add_mutually_exclusive_group()
    g.add_argument("--real-data", metavar="DIR",
                   help="folder with abw/, kinect/, mosd/ (default ../shared/data from the "
                        "project root)")
    g.add_argument("--no-real-data", action="store_true", help="skip the real-data section")
    p.add_argument("--real-subsample", type=int, default=4,
                   help="subsampling of the 640x480 Kinect/mOSD clouds (default 4: 160x120)")
    p.add_argument("--abw-subsample", type=int, default=2,
                   help="subsampling of the 512x512 ABW images (default 2: 256x256; 1 = full "
                        "size, much slower for SNP 0.01)")
    p.add_argument("--figure-scenes", default="", metavar="IDS",
                   help="scene ids for the figures, e.g. s0000,s0012 (default: the first "
                        "--figure-per-class scenes of each class)")
    p.add_argument("--figure-per-class", type=int, default=1,
                   help="scenes per class in the figures (default 1)")
    p.add_argument("--jobs", type=int, default=0,
                   help="worker processes for segmenting (default 0 = all cores)")
    p.add_argument("--quiet", action="store_true", help="no progress output")
    p.set_defaults(func=run)


def run(args) -> int:
    import shlex
    import sys

    from planerel.atomic import check_output_dir
    from planerel.report.builder import ReportOptions, build_report, parse_sizes

    sizes = () if args.no_timing else parse_sizes(args.sizes)
    check_output_dir(args.out, "-o")  # a file or unwritable folder fails here, not at the end
    real = None if args.no_real_data else (args.real_data or "auto")
    opts = ReportOptions(
        methods=args.methods, tolerance=args.tolerance, learning=not args.no_learning,
        folds=args.folds, seed=args.seed, engine=args.engine, learn_timeout=args.timeout,
        timing_sizes=sizes, timing_repeats=args.timing_repeats, real_data=real,
        real_subsample=args.real_subsample, abw_subsample=args.abw_subsample,
        figure_scenes=tuple(s.strip() for s in args.figure_scenes.split(",") if s.strip()),
        figure_per_class=args.figure_per_class, jobs=args.jobs,
        progress=not args.quiet and sys.stderr.isatty(), objects=not args.no_objects,
    )
    log = None if args.quiet else (lambda msg: print(msg, file=sys.stderr))
    command = shlex.join(_command_line(args))
    res = build_report(args.dataset, args.out, opts, command=command, log=log)
    for n in res.notes:
        print(f"note: {n}", file=sys.stderr)
    print(f"wrote {res.html} and {res.markdown} (raw numbers: {res.json}, {res.out_dir / 'csv'})")
    return 0


def _command_line(args) -> list[str]:
    """The options that differ from their defaults, as a command a reader can rerun."""
    argv = ["planerel", "report", str(args.dataset), "-o", str(args.out)]
    defaults = {"methods": "paper", "tolerance": 0.8, "sizes": "160x120,640x480",
                "timing_repeats": 3, "folds": 10, "engine": "builtin", "timeout": 120.0,
                "seed": 0, "real_data": None, "real_subsample": 4, "abw_subsample": 2,
                "figure_scenes": "", "figure_per_class": 1, "jobs": 0}
    for name, default in defaults.items():
        value = getattr(args, name)
        if value != default and not (name == "sizes" and args.no_timing):
            argv += [f"--{name.replace('_', '-')}", str(value)]
    for flag in ("no_timing", "no_learning", "no_real_data"):
        if getattr(args, flag):
            argv.append(f"--{flag.replace('_', '-')}")
    return argv
