"""Options and helpers shared by the subcommands that read scans."""

from __future__ import annotations

import argparse
from pathlib import Path

from planerel.errors import InputError

__all__ = ["add_input_options", "add_batch_options", "read_input", "read_options", "inputs_of",
           "given_up", "given_camera_height", "add_camera_height_option", "check_input_options",
           "parse_vector", "parse_intrinsics", "sparse_note"]


def parse_vector(text: str, name: str = "vector") -> tuple[float, float, float]:
    """``"x,y,z"`` -> three floats, with a clear error."""
    try:
        values = tuple(float(v) for v in text.split(","))
    except ValueError:
        raise InputError(f"{name} must be three numbers like 0,-1,0; got {text!r}") from None
    if len(values) != 3:
        raise InputError(f"{name} must be three numbers like 0,-1,0; got {text!r}")
    return values


def given_up(args: argparse.Namespace):
    """The ``--up X,Y,Z`` of the command line as a unit ``(3,)`` array, or None; a clear
    one-line error for anything that is not three finite numbers, not all zero."""
    text = getattr(args, "up", None)
    if not text:
        return None
    import math

    import numpy as np

    values = parse_vector(text, "--up")
    if not all(math.isfinite(v) for v in values):
        raise InputError(f"--up must be three finite numbers like 0,-1,0; got {text!r}")
    norm = math.sqrt(sum(v * v for v in values))
    if norm == 0:
        raise InputError(f"--up must not be the zero vector; got {text!r}")
    return np.array(values) / norm


def given_camera_height(args: argparse.Namespace) -> float | None:
    """The ``--camera-height M`` of the command line in metres, or None; a clear one-line
    error for anything that is not a finite number above 0."""
    value = getattr(args, "camera_height", None)
    if value is None:
        return None
    from planerel.features.planes import check_camera_height

    try:
        return check_camera_height(value)
    except InputError as e:
        raise InputError(f"--camera-height: {e}") from None


def add_camera_height_option(parser: argparse.ArgumentParser) -> None:
    """``--camera-height`` for the commands that describe a scan (``describe``, ``classify``):
    the others would take it and do nothing with it."""
    g = parser.add_argument_group("the camera's pose")
    g.add_argument("--camera-height", type=float, metavar="M",
                   help="the camera's height over the floor in metres, when known (a robot's "
                        "mount): with no floor plane in view, a box face whose foot stands "
                        "that far under the camera is grounded (a camera on or near the floor "
                        "sees the floor at grazing incidence, where the sensor measures "
                        "little); give --up too for a level mount or a known tilt (default: "
                        "not known; docs/objects.md, 'A known camera height')")


def check_input_options(args: argparse.Namespace) -> None:
    """Check the reading options of :func:`add_input_options` before any work: a bad
    ``--subsample``, ``--depth-scale``, ``--max-points``, ``--intrinsics``, ``--up`` or
    ``--camera-height`` is one
    error about the option, not a failure of every input (which ``--keep-going`` would skip)."""
    import math

    k = getattr(args, "subsample", 1)
    if k is not None and (isinstance(k, bool) or not isinstance(k, int) or k < 1):
        raise InputError(f"--subsample must be a positive whole number (1 = every pixel), got {k!r}")
    scale = getattr(args, "depth_scale", None)
    if scale is not None and not (math.isfinite(scale) and scale > 0):
        raise InputError(f"--depth-scale must be a positive number of depth units per metre, "
                         f"got {scale!r}")
    limit = getattr(args, "max_points", None)
    if limit is not None and limit < 1:
        raise InputError(f"--max-points must be a positive whole number, got {limit!r}")
    from planerel.io.readers import max_points_limit

    max_points_limit(limit)  # also a bad $PLANEREL_MAX_POINTS
    parse_intrinsics(getattr(args, "intrinsics", None))
    given_up(args)
    given_camera_height(args)


_INTRINSICS_FORMS = "'kinect' or W,H,fx,fy,cx,cy (or a camera JSON file)"


def _intrinsics_file(text: str) -> tuple:
    """The camera of a JSON file: ``{width, height, fx, fy, cx, cy}``, a sidecar's
    ``{"intrinsics": {...}}``, or ``width``/``height`` with a 3x3 ``K`` (flat or nested, also
    ``k``, ``camera_matrix`` or ``camera_matrix.data``, as ROS camera_info writes it); checked
    by :func:`planerel.io.readers.resolve_intrinsics`, as every other camera is."""
    import numpy as np

    from planerel.io.readers import read_json_object, resolve_intrinsics

    data = read_json_object(text, "camera JSON given to --intrinsics")
    if isinstance(data.get("intrinsics"), dict):
        data = data["intrinsics"]
    w = data.get("width", data.get("image_width"))
    h = data.get("height", data.get("image_height"))
    K = next((data[k] for k in ("K", "k", "camera_matrix") if k in data), None)
    K = K.get("data") if isinstance(K, dict) else K
    if w is None or h is None or (K is None and not {"fx", "fy", "cx", "cy"} <= set(data)):
        raise InputError(f"--intrinsics {text}: it holds neither width, height, fx, fy, cx, cy "
                         "nor width, height and a 3x3 K")
    try:
        value = data if K is None else np.asarray(K, dtype=float).reshape(3, 3)
        i = resolve_intrinsics(value, int(w), int(h), where=f"--intrinsics {text}")
    except InputError:
        raise  # it names the option and the file already (user103: they were said twice)
    except (TypeError, ValueError) as exc:
        raise InputError(f"--intrinsics {text}: {exc}") from None
    return (i.width, i.height, i.fx, i.fy, i.cx, i.cy)


def parse_intrinsics(text: str | None):
    """``"kinect"``, ``"W,H,fx,fy,cx,cy"`` or a camera JSON file -> a value
    :func:`planerel.io.readers.read` accepts."""
    if text is None or text.lower() == "kinect":
        return text
    parts = text.split(",")
    if len(parts) != 6 and (text.lower().endswith(".json") or Path(text).is_file()):
        return _intrinsics_file(text)
    if len(parts) != 6:
        raise InputError(f"--intrinsics must be {_INTRINSICS_FORMS}; got {text!r}")
    try:
        w, h = int(parts[0]), int(parts[1])
        values = (w, h, *(float(p) for p in parts[2:]))
    except ValueError:
        raise InputError(f"--intrinsics must be {_INTRINSICS_FORMS}; got {text!r}") from None
    from planerel.io.cloud import Intrinsics

    try:  # a size under 1, a NaN or a focal length <= 0: one error about the option, not
        Intrinsics(*values)  # a failure of every input in turn (which --keep-going skips)
    except InputError as exc:
        raise InputError(f"--intrinsics {text!r}: {exc}") from None
    return values


def add_input_options(parser: argparse.ArgumentParser) -> None:
    """``--intrinsics``, ``--depth-scale``, ``--up``, ``--subsample`` for commands that read scans."""
    g = parser.add_argument_group("reading scans")
    g.add_argument("--intrinsics", metavar="kinect|W,H,fx,fy,cx,cy|FILE.json",
                   help="camera of depth images without a sidecar JSON / OpenNI XML: the "
                        "preset, six numbers, or a JSON file holding width, height, fx, fy, "
                        "cx, cy (or width, height and a 3x3 K; only the camera is read from "
                        "it) (default: the Kinect preset, scaled to the image size)")
    g.add_argument("--depth-scale", type=float, metavar="UNITS_PER_M",
                   help="depth units per metre (default: sidecar value, else 1000 for 16-bit "
                        "images, 1 for float images)")
    g.add_argument("--up", metavar="X,Y,Z", help="gravity-up vector in the camera frame, e.g. "
                   "0,-1,0 for a level camera (default: the file's own, e.g. 'up' in a sidecar "
                   "STEM.json, else estimated from the planes for any camera pitch and roll)")
    g.add_argument("--max-points", type=int, metavar="N",
                   help="refuse inputs that declare more than N points or pixels, before reading "
                        "them (default 20,000,000 or $PLANEREL_MAX_POINTS)")
    g.add_argument("--subsample", type=int, default=1, metavar="K",
                   help="keep every K-th row and column (the paper's 640x480 -> 160x120 is 4); "
                        "faster, but classify answers best at the sensor's own resolution: "
                        "at 2, real development frames gave 42 of 97 boxes against 44 and 26 "
                        "false boxes against 16 (docs/segmentation.md, 'The same frame at half "
                        "resolution')")
    g.add_argument("--no-organize", dest="organize", action="store_false",
                   help="keep an unorganized cloud (PLY, PCD with HEIGHT 1, (N, 3) .npy) "
                        "unorganized instead of putting it on an image grid seen from the "
                        "sensor (default; --intrinsics then gives the grid's camera): relations "
                        "that look through the image are then not found")


def jobs_option(text: str) -> int:
    """``--jobs``: a whole number of workers, 0 for all cores (user103: ``-j -1`` passed
    without a word where the scenes were too few for workers)."""
    try:
        n = int(text)
    except ValueError:
        n = -1
    if n < 0:
        raise argparse.ArgumentTypeError(f"a whole number of worker processes (0: all cores), "
                                         f"got {text!r}")
    return n


def add_batch_options(parser: argparse.ArgumentParser, *, keep_going: bool = True) -> None:
    """``--jobs``, ``--scheduler`` and ``--keep-going`` for commands that loop over scenes."""
    g = parser.add_argument_group("batches")
    g.add_argument("-j", "--jobs", type=jobs_option, default=None, metavar="N",
                   help="worker processes (default or 0: all cores; 1 = this process only)")
    g.add_argument("--scheduler", metavar="tcp://HOST:8786",
                   help="run the scenes on a Dask cluster instead of local processes "
                        "(needs planerel[dask]; the workers must see the input and output "
                        "paths, docs/batches.md)")
    if keep_going:
        g.add_argument("-k", "--keep-going", action="store_true",
                       help="go on past inputs that fail: write the good ones' results and a "
                            "list of the failures, exit status 1 if any failed")


def read_options(args: argparse.Namespace) -> argparse.Namespace:
    """The command's options without its function: small and picklable, for worker processes
    (every reading option :func:`read_input` looks at travels with it)."""
    return argparse.Namespace(**{k: v for k, v in vars(args).items() if k != "func"})


def inputs_of(args: argparse.Namespace):
    """The command's inputs with folders and globs expanded."""
    from planerel.batch import expand_inputs

    return expand_inputs(args.inputs)


def read_input(path, args: argparse.Namespace):
    """Read one scan with the options of :func:`add_input_options`.

    Depth images with no camera information anywhere fall back to the Kinect preset, and
    the fallback is printed.  Unorganized clouds are put on an image grid unless
    ``--no-organize`` (:func:`planerel.io.organize.organize`; a ``note:`` says so).  ``--up`` is checked here but not put into the cloud: the
    commands pass :func:`given_up` on, so the source of the up vector stays known
    (``given`` vs ``file``).
    """
    import sys

    from planerel.io import readers as io
    from planerel.io.cloud import subsample
    from planerel.io.naming import scene_name

    intr = parse_intrinsics(getattr(args, "intrinsics", None))
    given_up(args)
    kwargs = dict(depth_scale=getattr(args, "depth_scale", None),
                  max_points=getattr(args, "max_points", None),
                  organize=getattr(args, "organize", True))
    try:
        cloud = io.read(path, intrinsics=intr, **kwargs)
    except InputError as exc:
        if intr is not None or "no intrinsics" not in str(exc) and "needs intrinsics" not in str(exc):
            raise
        try:
            cloud = io.read(path, intrinsics="kinect", **kwargs)
        except InputError as exc2:
            if "no Kinect preset" not in str(exc2):
                raise
            # not a note then an error about a preset the user never asked for: say what to do
            raise InputError(f"{path}: no camera information, and the image is no Kinect size "
                             "(640x480 or a whole-number part of it): give --intrinsics "
                             "W,H,fx,fy,cx,cy or a camera JSON file, or a sidecar "
                             f"{scene_name(path)}.json beside it") from None
        print(f"note: {path}: no camera information; assuming Kinect intrinsics", file=sys.stderr)
    _note_unused_intrinsics(path, cloud, intr)
    _note_field_of_view(path, cloud)
    k = getattr(args, "subsample", 1) or 1
    full = cloud
    cloud = subsample(full, k)
    if k > 1 and cloud.n_valid < 3 <= full.n_valid:
        # the file has points; the subsample left (almost) none: name the option, not the file
        (h, w), (h2, w2) = full.xyz.shape[:2], cloud.xyz.shape[:2]
        raise InputError(f"{path}: --subsample {k} leaves {cloud.n_valid} valid point"
                         f"{'' if cloud.n_valid == 1 else 's'} of {full.n_valid:,} ({w}x{h} -> "
                         f"{w2}x{h2}; need at least 3): give a smaller --subsample")
    _check_far_depth(path, cloud)
    return cloud


def _note_unused_intrinsics(path, cloud, given) -> None:
    """A note when ``--intrinsics`` (:func:`parse_intrinsics`' six numbers) was given and the
    scan was read with another camera: an organized cloud (a PCD, an ``(H, W, 3)`` ``.npy``)
    carries its own points, so the option does not change them (user89: it was ignored
    without a word)."""
    import sys

    import numpy as np

    if not isinstance(given, tuple) or cloud.intrinsics is None:  # None or "kinect"
        return
    c = cloud.intrinsics
    have = np.array([c.width, c.height, c.fx, c.fy, c.cx, c.cy], float)
    if not np.allclose(have, np.asarray(given, float), rtol=1e-6, atol=1e-6):
        print(f"note: {path}: an organized cloud carries its own points; --intrinsics is not "
              f"used (its grid's camera: {c.width}x{c.height}, fx {c.fx:g}, fy {c.fy:g}, "
              f"cx {c.cx:g}, cy {c.cy:g})", file=sys.stderr)


#: Fields of view (degrees) outside which a depth image's camera is most likely mistyped: a
#: focal length given in metres (0.0036 for 3.6 mm) spans nearly 180 degrees, one in
#: micrometres a hundredth of a degree; real depth cameras span about 30-120.
FOV_RANGE = (1.0, 170.0)


def _note_field_of_view(path, cloud) -> None:
    """A note when the camera a scan was read with spans a field of view outside
    :data:`FOV_RANGE` (user103: ``--intrinsics 640,480,0.0036,...`` ran without a word and
    gave 967 proposals)."""
    import sys

    c = cloud.intrinsics
    if c is None:
        return
    fov = c.field_of_view()
    lo, hi = FOV_RANGE
    if not all(lo <= f <= hi for f in fov):
        print(f"note: {path}: its camera (fx {c.fx:g}, fy {c.fy:g} px at {c.width}x{c.height}) "
              f"spans {fov[0]:.3g} x {fov[1]:.3g} degrees; focal lengths are pixels (a "
              "depth camera's span 30-120 degrees): check --intrinsics", file=sys.stderr)


#: Share of measured pixels under which a frame that gives no plane is said to be too sparse.
SPARSE_SHARE = 0.5


def sparse_note(cloud, n_planes: int) -> str | None:
    """A note for an organized frame that gave no plane and holds a depth at under
    :data:`SPARSE_SHARE` of its pixels (a frame with most pixels missing); else None."""
    if n_planes or not cloud.organized:
        return None
    h, w = cloud.xyz.shape[:2]
    share = cloud.n_valid / max(1, h * w)
    if share >= SPARSE_SHARE:
        return None
    return (f"no plane found: only {100 * share:.1f} % of the pixels hold a depth "
            f"({cloud.n_valid:,} of {h * w:,}); region growing grows planes over neighbouring "
            "measured pixels, so scattered or few points give none")


#: Median depth (metres) beyond which a scan is most likely not in metres (a float image of
#: millimetres read as metres: the Kinect frames' median of ~1.2 m becomes ~1.2 km).
FAR_MEDIAN_M = 100.0
#: Median depth (metres) beyond which a scan is refused: no depth sensor measures so far (a
#: lidar's 200-300 m included); millimetres read as metres stay under it, a depth scale of
#: 1e-6 does not.
FAR_LIMIT_M = 1e5


def _check_far_depth(path, cloud) -> None:
    """Refuse a scan whose median depth is beyond :data:`FAR_LIMIT_M` (an InputError naming
    ``--depth-scale``), and print a note when it is beyond :data:`FAR_MEDIAN_M`: the depth unit
    is probably wrong (nothing is changed)."""
    import sys

    import numpy as np

    if cloud.n_valid == 0:
        return
    z = np.asarray(cloud.xyz)[..., 2]
    step = max(1, int((z.size / 20000) ** 0.5))  # a grid sample: a few ms on any scan
    sample = z[::step, ::step] if z.shape[0] > 1 else z[:, ::step * step]
    sample = sample[np.isfinite(sample)]
    if not sample.size:
        sample = z[np.isfinite(z)]
    med = float(np.median(np.abs(sample)))
    if med > FAR_LIMIT_M:
        # (segmenting it ran out of memory or overflowed a kernel's integers: user103)
        raise InputError(f"{path}: the median depth is {med:.3g} m, beyond any depth sensor's "
                         "range; planerel works in metres: check --depth-scale (the raw value "
                         "is divided by it: 1000 for millimetres) or the cloud's unit")
    if med > FAR_MEDIAN_M:
        print(f"note: {path}: the median depth is {med:,.0f} m; planerel works in metres: if "
              "the values are millimetres, give --depth-scale 1000 (depth images) or convert "
              "the cloud to metres", file=sys.stderr)
