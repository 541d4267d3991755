"""Readers for range images and point clouds.

:func:`read` picks the reader by the file's content (magic bytes) and, failing that, its
extension.  Every reader is public:

=====================  ================================================================
``read_depth_image``   16-bit PNG / TIFF depth frames (+ intrinsics from an argument, a
                       sidecar JSON, or the OpenNI/PCL XML that sits next to the frame)
``read_pcd``           PCD v0.7 ascii / binary / binary_compressed (LZF), organized or not
``read_ply``           PLY vertices (ascii or binary), put on an image grid
``read_npy``           ``.npy`` holding ``(H, W, 3)`` XYZ (metres) or ``(H, W)`` depth
``read_abw``           SegComp ABW ``.range`` structured-light images (Sun rasterfile)
``read_abw_gt``        their ``.gt-seg`` ground-truth label images
=====================  ================================================================

Unorganized clouds (PLY, PCD with ``HEIGHT 1``, ``(N, 3)`` ``.npy``) go back on their own pixel
grid when they are an exact pinhole back-projection (:func:`pinhole_grid`), else on an image grid
seen from the sensor (:func:`planerel.io.organize.organize`, said in a ``PlanerelWarning``);
``organize=False`` keeps them unorganized.

Libraries do the parsing where they read the format correctly (Pillow, tifffile, pypcd4,
plyfile); planerel adds validation and a clear :class:`~planerel.errors.InputError` that names
the file for anything wrong with it.  Before any pixel or point is allocated, the size a header
declares is checked against the file's size (where the format is not compressed) and against a
point limit (``max_points``, default :data:`DEFAULT_MAX_POINTS`, or ``$PLANEREL_MAX_POINTS``), so
a crafted or damaged header gives one sentence, never a ``MemoryError``.  Every public reader
turns any other failure (an ``OSError``, a library's own exception) into one
:class:`~planerel.errors.InputError` sentence naming the file.
"""

from __future__ import annotations

import functools
import json
import os
import re
import struct
import warnings
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np

from planerel.errors import InputError, PlanerelWarning
from planerel.io.cloud import (
    DEFAULT_DEPTH_SCALE,
    Cloud,
    Intrinsics,
    as_path,
    depth_to_cloud,
)

__all__ = [
    "read",
    "read_depth_image",
    "read_depth_array",
    "read_pcd",
    "read_pcd_field",
    "read_ply",
    "read_npy",
    "read_abw",
    "read_abw_gt",
    "read_label_image",
    "find_camera_info",
    "read_json_object",
    "estimate_intrinsics",
    "pinhole_grid",
    "resolve_intrinsics",
    "FORMATS",
    "DEFAULT_MAX_POINTS",
    "max_points_limit",
]

#: Points (pixels) a reader accepts by default: 20 million, 65x a 640x480 frame, ~0.5 GB of
#: float64 XYZ; the pipeline's working arrays take several times that.
DEFAULT_MAX_POINTS = 20_000_000

#: Extensions :func:`read` knows, with the reader it uses.
FORMATS = {
    ".png": "depth image (16-bit PNG)",
    ".tif": "depth image (16-bit TIFF)",
    ".tiff": "depth image (16-bit TIFF)",
    ".pcd": "PCD point cloud",
    ".ply": "PLY point cloud",
    ".npy": "numpy XYZ (H, W, 3) or depth (H, W)",
    ".range": "SegComp ABW range image",
}

_SUN_MAGIC = 0x59A66A95


# --------------------------------------------------------------------------- helpers


def max_points_limit(value=None) -> int:
    """The point limit in force: ``value``, else ``$PLANEREL_MAX_POINTS``, else
    :data:`DEFAULT_MAX_POINTS`."""
    if value is None:
        env = os.environ.get("PLANEREL_MAX_POINTS")
        if env:
            try:
                value = int(env)
            except ValueError:
                raise InputError(f"PLANEREL_MAX_POINTS={env!r} is not a whole number") from None
        else:
            value = DEFAULT_MAX_POINTS
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < 1:
        raise InputError(f"the point limit must be a positive whole number, got {value!r}")
    return int(value)


def _check_points(path, n: int, what: str, max_points=None) -> None:
    limit = max_points_limit(max_points)
    if n > limit:
        raise InputError(f"{path}: {what} declares {n:,} points, more than the limit of "
                         f"{limit:,}; raise it with --max-points (or PLANEREL_MAX_POINTS) if the "
                         "machine has the memory")


def _one_line(text: str, limit: int = 300) -> str:
    text = " ".join(str(text).split())
    return text if len(text) <= limit else text[: limit - 3] + "..."


def _reader(func):
    """Make a reader's every failure one :class:`InputError` sentence that names the file."""

    @functools.wraps(func)
    def wrapper(path, *args, **kwargs):
        try:
            return func(path, *args, **kwargs)
        except InputError as exc:
            msg = str(exc)
            if "\n" in msg or len(msg) > 400:
                raise InputError(_one_line(msg, 400)) from None
            raise
        except MemoryError:
            raise InputError(f"{path}: too large to read into memory; lower --max-points or "
                             "use a machine with more memory") from None
        except OSError as exc:
            where = exc.filename or path
            raise InputError(f"{where}: cannot read the file ({exc.strerror or exc})") from None
        except Exception as exc:  # a library's own exception on corrupt data
            raise InputError(f"{path}: not a readable {func.__name__[5:].replace('_', ' ')} "
                             f"file ({type(exc).__name__}: {_one_line(exc, 200)})") from None

    return wrapper


def _existing(path) -> Path:
    p = as_path(path)
    if not p.exists():
        raise InputError(f"{p}: no such file")
    if p.is_dir():
        raise InputError(f"{p}: is a folder, not a file")
    return p


def _sniff(path: Path) -> str | None:
    """The format named by the file's first bytes, or None."""
    with open(path, "rb") as fh:
        head = fh.read(64)
    if head.startswith(b"\x89PNG\r\n\x1a\n"):
        return ".png"
    if head[:4] in (b"II*\x00", b"MM\x00*", b"II+\x00", b"MM\x00+"):
        return ".tiff"
    if head.startswith(b"\x93NUMPY"):
        return ".npy"
    if head.startswith(b"ply"):
        return ".ply"
    if len(head) >= 4 and struct.unpack(">I", head[:4])[0] == _SUN_MAGIC:
        return ".range"
    text = head.lstrip()
    if text.startswith(b"# .PCD") or text.startswith(b"VERSION") or text.startswith(b"FIELDS"):
        return ".pcd"
    return None


@_reader
def read(path, *, intrinsics=None, depth_scale: float | None = None, up=None,
         max_range: float | None = None, max_points: int | None = None,
         organize: bool = True) -> Cloud:
    """Read any supported file into a :class:`~planerel.io.cloud.Cloud`.

    Parameters
    ----------
    path : str or Path
        A depth image (``.png``, ``.tif``), cloud (``.pcd``, ``.ply``), ``.npy`` array or SegComp
        ``.range`` file.  The content decides the reader when it is recognisable; the extension
        otherwise.
    intrinsics : Intrinsics, 6-sequence, dict or "kinect", optional
        For depth images: overrides any sidecar; ``"kinect"`` is the Kinect preset scaled to the
        image size.  For unorganized clouds: the camera of the image grid they are put on
        (``"kinect"``: 640x480).
    depth_scale : float, optional
        Depth units per metre for depth images (default: sidecar / XML value, else 1000 for
        integer images and 1 for float images).
    up : 3-sequence, optional
        Gravity-up vector in the camera frame; overrides a sidecar's.
    max_range : float, optional
        Depth images only: depths beyond this many metres become invalid.
    max_points : int, optional
        Refuse files that declare more points (pixels) than this, before reading them
        (default :func:`max_points_limit`).
    organize : bool
        Put an unorganized cloud (PLY, PCD with HEIGHT 1, ``(N, 3)`` ``.npy``) that is no exact
        pinhole back-projection on an image grid seen from the sensor's origin
        (:func:`planerel.io.organize.organize`, with a :class:`PlanerelWarning` saying so);
        False keeps it ``(1, N, 3)`` unorganized.

    Raises
    ------
    InputError
        One sentence naming the file, for every way the file can be wrong (also an
        unorganized cloud that cannot be one view, unless ``organize=False``).
    """
    p = _existing(path)
    kind = _sniff(p) or p.suffix.lower()
    if kind in (".png", ".tif", ".tiff"):
        return read_depth_image(p, intrinsics=intrinsics, depth_scale=depth_scale, up=up,
                                max_range=max_range, max_points=max_points)
    if kind == ".pcd":
        return read_pcd(p, up=up, max_points=max_points, organize=organize,
                        intrinsics=intrinsics)
    if kind == ".ply":
        return read_ply(p, up=up, max_points=max_points, organize=organize,
                        intrinsics=intrinsics)
    if kind == ".npy":
        return read_npy(p, intrinsics=intrinsics, depth_scale=depth_scale, up=up,
                        max_points=max_points, organize=organize)
    if kind == ".range":
        return read_abw(p, max_points=max_points)
    known = ", ".join(sorted(FORMATS))
    raise InputError(f"{p}: unknown file type {p.suffix or '(no extension)'!r}; planerel reads {known}")


# --------------------------------------------------------------------------- intrinsics


def _frame_stems(path: Path) -> list[Path]:
    """Candidate sidecar stems: ``a/b_depth.png`` -> ``a/b_depth``, ``a/b``; ``s0.depth.png`` -> ``s0``."""
    stems = [path.with_suffix("")]
    name = stems[0].name
    for tail in ("_depth", ".depth", "-depth"):
        if name.endswith(tail):
            stems.append(stems[0].with_name(name[: -len(tail)]))
    return stems


def read_json_object(path, what: str = "JSON file") -> dict:
    """The JSON object stored in ``path``; :class:`InputError` naming the file and ``what``
    it should be when it is unreadable or not an object."""
    p = Path(path)
    try:
        data = json.loads(p.read_text(encoding="utf-8"))
    except (OSError, UnicodeDecodeError, json.JSONDecodeError) as exc:
        raise InputError(f"{p}: cannot read the {what} ({exc})") from None
    if not isinstance(data, dict):
        raise InputError(f"{p}: the {what} must hold a JSON object")
    return data


def _read_openni_xml(path: Path) -> dict:
    # OpenNI/PCL camera files hold several top-level elements (<rgb>, <depth>): wrap them.
    try:
        text = path.read_text(encoding="utf-8")
        root = ET.fromstring("<r>" + re.sub(r"<\?xml[^>]*\?>", "", text) + "</r>")
    except (OSError, UnicodeDecodeError, ET.ParseError) as exc:
        raise InputError(f"{path}: camera XML cannot be read ({exc})") from None
    node = root.find("depth")
    if node is None:
        node = root.find("*/depth")
    if node is None:
        raise InputError(f"{path}: camera XML has no <depth> element")

    def num(tag):
        el = node.find(tag)
        if el is None or el.text is None:
            raise InputError(f"{path}: camera XML lacks <{tag}> in <depth>")
        try:
            return float(el.text)
        except ValueError:
            raise InputError(f"{path}: <{tag}> is not a number: {el.text!r}") from None

    out = {"fx": num("focal_length_x"), "fy": num("focal_length_y"),
           "cx": num("principal_point_x"), "cy": num("principal_point_y")}
    if node.find("z_multiplication_factor") is not None:
        factor = num("z_multiplication_factor")
        if factor <= 0:
            raise InputError(f"{path}: z_multiplication_factor must be positive, got {factor}")
        out["depth_scale"] = 1.0 / factor
    return out


def _is_number(x) -> bool:
    return isinstance(x, (int, float)) and not isinstance(x, bool) and np.isfinite(x)


def _check_sidecar(js: Path, info: dict) -> None:
    """Types of a sidecar's values, so that an error names the JSON file."""
    intr = info.get("intrinsics")
    if intr is not None:
        if isinstance(intr, dict):
            values = [intr.get(k) for k in ("fx", "fy", "cx", "cy")]
            if not all(_is_number(v) for v in values):
                raise InputError(f"{js}: 'intrinsics' needs numbers fx, fy, cx, cy")
        elif not (isinstance(intr, list) and all(_is_number(v) for v in intr)):
            raise InputError(f"{js}: 'intrinsics' must be an object or a list of numbers")
    scale = info.get("depth_scale")
    if scale is not None and not (_is_number(scale) and scale > 0):
        raise InputError(f"{js}: 'depth_scale' must be a positive number, got {scale!r}")
    up = info.get("up")
    if up is not None and not (isinstance(up, list) and len(up) == 3
                               and all(_is_number(v) for v in up)):
        raise InputError(f"{js}: 'up' must be three numbers, got {up!r}")


def find_camera_info(path) -> dict:
    """Camera information stored next to a depth frame.

    Looks for a sidecar ``STEM.json`` (keys ``intrinsics`` {width, height, fx, fy, cx, cy},
    ``depth_scale``, ``up``) and then an OpenNI/PCL ``STEM.xml``, where STEM is the frame's name
    without its extension and without a trailing ``_depth`` / ``.depth``.

    Returns
    -------
    dict
        Possibly empty; keys among ``intrinsics`` (dict without size for XML), ``depth_scale``,
        ``up``, ``source``.
    """
    p = as_path(path)
    for stem in _frame_stems(p):
        js = stem.with_name(stem.name + ".json")
        if js.is_file():
            data = read_json_object(js, "sidecar JSON")
            out = {"source": str(js)}
            for key in ("intrinsics", "depth_scale", "up"):
                if data.get(key) is not None:
                    out[key] = data[key]
            _check_sidecar(js, out)
            if "up" in out:
                from planerel.io.cloud import unit_up

                out["up"] = unit_up(out["up"], f"{js}: 'up'")
            return out
    for stem in _frame_stems(p):
        xml = stem.with_name(stem.name + ".xml")
        if xml.is_file():
            info = _read_openni_xml(xml)
            out = {"source": str(xml), "intrinsics": {k: info[k] for k in ("fx", "fy", "cx", "cy")}}
            if "depth_scale" in info:
                out["depth_scale"] = info["depth_scale"]
            return out
    return {}


def resolve_intrinsics(value, width: int, height: int, where: str = "image") -> Intrinsics:
    """Turn a user's intrinsics (object, dict with or without size, 6-sequence, 3x3 K or
    ``"kinect"``) into :class:`Intrinsics` for a ``width x height`` image."""
    if isinstance(value, str):
        if value.lower() != "kinect":
            raise InputError(f"{where}: unknown intrinsics preset {value!r} (known: 'kinect')")
        try:
            return Intrinsics.kinect(width, height)
        except InputError as exc:
            raise InputError(f"{where}: {exc}") from None
    if isinstance(value, dict) and ("width" not in value or "height" not in value):
        value = {**value, "width": width, "height": height}
    try:
        arr = np.asarray(value, dtype=object) if not isinstance(value, (dict, Intrinsics)) else None
        if arr is not None and arr.shape == (3, 3):
            return Intrinsics.from_matrix(np.asarray(value, dtype=float), width, height)
        return Intrinsics.from_any(value)
    except (InputError, TypeError, ValueError) as exc:
        msg = str(exc)
        raise InputError(msg if msg.startswith(where) else f"{where}: {msg}") from None


#: px: the 90th percentile of a pinhole fit's residual up to which an organized cloud that is
#: no exact back-projection still gets the fitted intrinsics (with a warning): a Kinect v2's
#: SDK-undistorted points saved on its distorted pixel grid fit to 1.4-1.6 px (median),
#: 2.2-2.4 px (90 %), 3.5-4.0 px (95 %) (hunt33's kinect2box frames); a cloud that is no
#: pinhole image (stair-perception's IMU-levelled clouds) is 190 px off
APPROX_FIT_PX = 3.0


def estimate_intrinsics(xyz: np.ndarray, tolerance: float = 0.05, *,
                        approximate: float | None = None, where: str = "cloud") -> Intrinsics | None:
    """Pinhole intrinsics that reproduce an organized cloud, or None when none fits.

    Fits ``u = fx * x/z + cx`` and ``v = fy * y/z + cy`` by least squares over the valid pixels;
    accepted when the worst residual is below ``tolerance`` pixels (exact back-projections, as
    in PCL's organized clouds, fit to about 1e-4 px), or, when ``approximate`` is given, when
    90 % of the residuals are below ``approximate`` pixels: then a :class:`PlanerelWarning`
    names ``where`` and the fit's residuals (the measures that project planes into the image,
    such as a skirt's cover, need intrinsics; without them no box rule on a top and its side
    can hold).  With ``approximate`` given, a cloud that fits neither is warned about too (a
    cloud turned into another frame: no intrinsics, no projected measures).

    Parameters
    ----------
    xyz : ndarray, shape (H, W, 3)
    tolerance : float
        px: the worst residual of an exact back-projection.
    approximate : float, optional
        px: the 90th percentile of the residuals of an approximate one
        (:data:`APPROX_FIT_PX` when the readers ask); None: exact only.
    where : str
        The file named in the warning.
    """
    h, w = xyz.shape[:2]
    valid = np.all(np.isfinite(xyz), axis=2) & (xyz[:, :, 2] > 0)
    if valid.sum() < 10:
        return None
    vv, uu = np.nonzero(valid)
    step = max(1, len(uu) // 20000)
    vv, uu = vv[::step], uu[::step]
    p = xyz[vv, uu]
    a = p[:, 0] / p[:, 2]
    b = p[:, 1] / p[:, 2]
    if np.ptp(a) == 0 or np.ptp(b) == 0:
        return None
    ax = np.stack([a, np.ones_like(a)], axis=1)
    by = np.stack([b, np.ones_like(b)], axis=1)
    (fx, cx), *_ = np.linalg.lstsq(ax, uu.astype(float), rcond=None)
    (fy, cy), *_ = np.linalg.lstsq(by, vv.astype(float), rcond=None)
    res = np.maximum(np.abs(ax @ [fx, cx] - uu), np.abs(by @ [fy, cy] - vv))
    mirrored = fx <= 0 or fy <= 0  # x/z falling with the column: a mirrored or turned frame
    if not mirrored and res.max() <= tolerance:
        return Intrinsics(w, h, round(fx, 3), round(fy, 3), round(cx, 3), round(cy, 3))
    if approximate is None:
        return None
    p90 = float(np.percentile(res, 90))
    if mirrored or p90 > approximate:
        off = "its axes do not follow the grid" if mirrored else (
            f"90 % of them within {p90:.0f} px of the best fit")
        warnings.warn(
            f"{where}: the points are no pinhole image of their pixel grid ({off}: a cloud "
            f"turned into a robot's or a levelled frame?); its planes are found, but the measures "
            f"that project a plane into the image (a box's skirt) are not taken: give the "
            f"camera-frame cloud, or its depth image with --intrinsics", PlanerelWarning,
            stacklevel=2)
        return None
    warnings.warn(
        f"{where}: the points are no exact pinhole back-projection of their pixel grid; "
        f"using intrinsics fitted to them (fx {fx:.2f}, fy {fy:.2f}, cx {cx:.2f}, cy {cy:.2f}: "
        f"residual median {np.median(res):.2f} px, 90 % {p90:.2f} px); "
        f"give the camera's own with --intrinsics when known", PlanerelWarning, stacklevel=2)
    return Intrinsics(w, h, round(fx, 3), round(fy, 3), round(cx, 3), round(cy, 3))


def _grid_axis(s: np.ndarray, tolerance: float):
    """Integer pixel index ``k`` with ``k = f * s + c`` for every value of ``s`` (x/z or y/z of
    the valid points), with ``f`` and ``c`` fitted; None when no such grid fits."""
    srt = np.sort(s)
    gaps = np.diff(srt)
    # neighbouring columns differ by 1/f (>= 5e-5 for any f under 20 000 px); the float32
    # coordinates of one column scatter by ~1e-7
    big = gaps[gaps > 1e-5]
    if big.size < 2:
        return None
    k = np.rint((s - srt[0]) / np.median(big))
    a = np.stack([s, np.ones_like(s)], axis=1)
    (f, c), *_ = np.linalg.lstsq(a, k, rcond=None)
    if not (np.isfinite(f) and f > 0):
        return None
    fit = a @ [f, c]
    k = np.rint(fit)
    if np.abs(fit - k).max() > tolerance or k.min() < 0:
        return None
    return k.astype(np.int64), float(f), float(c)


def pinhole_grid(points: np.ndarray, tolerance: float = 0.05, max_side: int = 20000):
    """The pixel grid of an unorganized cloud that is an exact pinhole back-projection.

    PCL's tools drop a frame's invalid points and save what is left as an unorganized cloud
    (``HEIGHT 1``), as three frames of the mOSD set are; their points still lie on the camera's
    pixel rays.  Fits ``u = fx x/z + cx`` and ``v = fy y/z + cy`` with whole-pixel ``u, v``
    (the spacing of the distinct ``x/z`` and ``y/z`` values gives ``1/fx`` and ``1/fy``) and
    accepts the grid when every valid point is within ``tolerance`` pixels of its pixel and no
    two points share one.  The grid starts at the smallest pixel in use: a crop of the
    sensor's frame, with ``cx, cy`` counted from its corner.

    Parameters
    ----------
    points : ndarray, shape (N, 3)
        Points in metres (NaN or ``z <= 0``: invalid, left out).
    tolerance : float
        Worst distance of a point from its pixel, in pixels.
    max_side : int
        Largest grid side accepted.

    Returns
    -------
    (ndarray (N,) int64, ndarray (N,) int64, Intrinsics) or None
        Row and column of every point (-1 for invalid points) and the grid's intrinsics; None
        when the points are no pinhole grid (then the cloud stays unorganized).
    """
    p = np.asarray(points, dtype=np.float64).reshape(-1, 3)
    valid = np.all(np.isfinite(p), axis=1) & (p[:, 2] > 0)
    if valid.sum() < 100:
        return None
    q = p[valid]
    cols = _grid_axis(q[:, 0] / q[:, 2], tolerance)
    rows = _grid_axis(q[:, 1] / q[:, 2], tolerance) if cols is not None else None
    if rows is None:
        return None
    (u, fx, cx), (v, fy, cy) = cols, rows
    w, h = int(u.max()) + 1, int(v.max()) + 1
    if w > max_side or h > max_side or np.unique(v * w + u).size != u.size:
        return None
    r = np.full(len(p), -1, np.int64)
    c = np.full(len(p), -1, np.int64)
    r[valid], c[valid] = v, u
    return r, c, Intrinsics(w, h, round(fx, 3), round(fy, 3), round(cx, 3), round(cy, 3))


def _on_grid(values: np.ndarray, grid, fill) -> np.ndarray:
    """``values`` (N, ...) of an unorganized cloud placed on its :func:`pinhole_grid`."""
    r, c, intr = grid
    out = np.full((intr.height, intr.width) + values.shape[1:], fill, dtype=values.dtype)
    ok = r >= 0
    out[r[ok], c[ok]] = values[ok]
    return out


def _grid_camera(intrinsics, where: str):
    """A user's camera for the grid of an unorganized cloud (``"kinect"``: 640x480), or None."""
    if intrinsics is None:
        return None
    if isinstance(intrinsics, str):
        return resolve_intrinsics(intrinsics, 640, 480, where)
    if isinstance(intrinsics, dict) and ("width" not in intrinsics or "height" not in intrinsics):
        raise InputError(f"{where}: the intrinsics for an unorganized cloud need the image size "
                         "(width, height, fx, fy, cx, cy)")
    return resolve_intrinsics(intrinsics, 0, 0, where)


def _organize(points: np.ndarray, where: str, intrinsics=None, viewpoint=None, *,
              say: bool = True):
    """:func:`planerel.io.organize.organize` of an unorganized cloud's points, said in a
    :class:`PlanerelWarning` (``say``)."""
    from planerel.io.organize import organize

    grid = organize(points, _grid_camera(intrinsics, where), viewpoint=viewpoint, where=where)
    if say:
        warnings.warn(grid.note(where), PlanerelWarning, stacklevel=3)
    return grid


# --------------------------------------------------------------------------- depth images


@_reader
def read_depth_array(path, *, max_points: int | None = None) -> np.ndarray:
    """The raw pixel values of a depth PNG or TIFF, ``(H, W)``, as stored (uint16 usually).

    The image size in the header is checked against ``max_points`` before the pixels are
    decoded."""
    p = _existing(path)
    kind = _sniff(p) or p.suffix.lower()
    try:
        if kind in (".tif", ".tiff"):
            import logging

            import tifffile

            # tifffile logs each oddity of a damaged file; the one sentence below says it all
            logging.getLogger("tifffile").setLevel(logging.CRITICAL)
            with tifffile.TiffFile(p) as tif:
                if not tif.pages:
                    raise InputError(f"{p}: the TIFF holds no image")
                page = tif.pages[0]
                if len(tif.pages) > 1:  # a stack or a series: only its first page is the frame
                    warnings.warn(f"{p}: the TIFF holds {len(tif.pages)} pages; only the first "
                                  "is read (split the file to read the others)", PlanerelWarning,
                                  stacklevel=3)
                _check_points(p, int(np.prod(page.shape[:2])), "the TIFF", max_points)
                arr = page.asarray()
        elif kind == ".png":
            from PIL import Image

            with warnings.catch_warnings():  # the point limit below is the check that counts
                warnings.simplefilter("ignore", Image.DecompressionBombWarning)
                img = Image.open(p)
            with img:
                _check_points(p, img.width * img.height, "the PNG", max_points)
                img.load()
                arr = np.asarray(img)
        else:
            raise InputError(f"{p}: not a PNG or TIFF depth image")
    except InputError:
        raise
    except MemoryError:
        raise
    except Exception as exc:  # library errors on corrupt data vary by library
        raise InputError(f"{p}: cannot read the image ({type(exc).__name__}: "
                         f"{_one_line(exc, 200)})") from None
    if arr.ndim == 3 and arr.shape[2] == 1:  # one channel stored as (H, W, 1)
        arr = arr[:, :, 0]
    if arr.ndim != 2:
        raise InputError(f"{p}: a depth image must have one channel, got shape {arr.shape}")
    if not (np.issubdtype(arr.dtype, np.integer) or np.issubdtype(arr.dtype, np.floating)):
        raise InputError(f"{p}: depth pixels must be numbers, got dtype {arr.dtype}")
    if arr.dtype == np.uint8:
        raise InputError(f"{p}: an 8-bit image is not a depth image (expected 16-bit or float)")
    return arr


@_reader
def read_depth_image(path, *, intrinsics=None, depth_scale: float | None = None, up=None,
                     max_range: float | None = None, max_points: int | None = None) -> Cloud:
    """Read a 16-bit (or float) depth PNG/TIFF into an organized cloud.

    Intrinsics and depth scale come from the arguments, else a sidecar ``.json``, else an
    OpenNI/PCL ``.xml`` next to the frame (see :func:`find_camera_info`).

    Raises
    ------
    InputError
        Unreadable image, no intrinsics anywhere, bad depth scale, or no valid pixel.
    """
    p = _existing(path)
    raw = read_depth_array(p, max_points=max_points)
    h, w = raw.shape
    info = find_camera_info(p)
    intr_value = intrinsics if intrinsics is not None else info.get("intrinsics")
    if intr_value is None:
        raise InputError(
            f"{p}: no intrinsics for this depth image: pass intrinsics (e.g. --intrinsics kinect "
            "or width,height,fx,fy,cx,cy) or put a sidecar JSON / OpenNI XML next to it"
        )
    intr = resolve_intrinsics(intr_value, w, h,
                              str(p) if intrinsics is not None else info.get("source", str(p)))
    if depth_scale is None:
        depth_scale = info.get("depth_scale")
    if depth_scale is None:
        depth_scale = 1.0 if np.issubdtype(raw.dtype, np.floating) else DEFAULT_DEPTH_SCALE
    return depth_to_cloud(raw, intr, depth_scale, up=up if up is not None else info.get("up"),
                          source=str(p), max_range=max_range)


# --------------------------------------------------------------------------- PCD


_PCD_SIZES = {"F": (2, 4, 8), "I": (1, 2, 4, 8), "U": (1, 2, 4, 8)}
_PCD_DATA = ("ascii", "binary", "binary_compressed")


def _pcd_int(path, key: str, text: str) -> int:
    try:
        value = int(text)
    except ValueError:
        raise InputError(f"{path}: PCD {key} must be a whole number, got {text!r}") from None
    return value


def _check_pcd_header(path: Path, max_points=None) -> None:
    """Validate a PCD header and the size of its data before anything is allocated."""
    with open(path, "rb") as fh:
        head = fh.read(65536)
        size = os.fstat(fh.fileno()).st_size
    if not head.strip():
        raise InputError(f"{path}: the PCD file is empty")
    entries, offset = {}, 0
    data_kind = None
    for raw in head.splitlines(keepends=True):
        offset += len(raw)
        line = raw.decode("ascii", "replace").strip()
        if not line or line.startswith("#"):
            continue
        key, _, rest = line.partition(" ")
        entries[key.upper()] = rest.split()
        if key.upper() == "DATA":
            data_kind = (rest.split() or [""])[0].lower()
            break
    else:
        raise InputError(f"{path}: the PCD header ends before its DATA line (truncated or not "
                         "a PCD file)")
    if data_kind not in _PCD_DATA:
        raise InputError(f"{path}: PCD DATA must be {', '.join(_PCD_DATA)}; got {data_kind!r}")
    for key in ("FIELDS", "SIZE", "TYPE", "WIDTH", "HEIGHT"):
        if not entries.get(key):
            raise InputError(f"{path}: the PCD header has no {key} line")
    fields, sizes, types = entries["FIELDS"], entries["SIZE"], entries["TYPE"]
    counts = entries.get("COUNT") or ["1"] * len(fields)
    if not len(fields) == len(sizes) == len(types) == len(counts):
        raise InputError(f"{path}: PCD FIELDS, SIZE, TYPE and COUNT must have one entry per "
                         f"field ({len(fields)}, {len(sizes)}, {len(types)}, {len(counts)})")
    record = 0
    for f, sz, ty, ct in zip(fields, sizes, types, counts, strict=True):
        sz_i, ct_i = _pcd_int(path, "SIZE", sz), _pcd_int(path, "COUNT", ct)
        if ty not in _PCD_SIZES:
            raise InputError(f"{path}: PCD TYPE of field {f!r} must be F, I or U; got {ty!r}")
        if sz_i not in _PCD_SIZES[ty]:
            raise InputError(f"{path}: PCD field {f!r} has TYPE {ty} with SIZE {sz_i}; "
                             f"allowed sizes: {', '.join(map(str, _PCD_SIZES[ty]))}")
        if ct_i < 1:
            raise InputError(f"{path}: PCD COUNT of field {f!r} must be at least 1, got {ct_i}")
        record += sz_i * ct_i
    width = _pcd_int(path, "WIDTH", entries["WIDTH"][0])
    height = _pcd_int(path, "HEIGHT", entries["HEIGHT"][0])
    if width < 1 or height < 1:
        raise InputError(f"{path}: PCD WIDTH and HEIGHT must be positive, got {width}x{height}")
    points = _pcd_int(path, "POINTS", entries["POINTS"][0]) if entries.get("POINTS") else width * height
    if points != width * height:
        raise InputError(f"{path}: PCD header says {points} points but WIDTH x HEIGHT is "
                         f"{width}x{height}")
    _check_points(path, points, "the PCD header", max_points)
    payload = size - offset
    if data_kind == "binary":
        need = points * record
        if payload < need:
            raise InputError(f"{path}: truncated: the PCD header declares {points} points of "
                             f"{record} bytes ({need} bytes), the file holds {payload}")
        if payload > need + 1 and not _zero_padding(path, offset + need, payload - need):
            raise InputError(f"{path}: the PCD data holds {payload} bytes but the header declares "
                             f"{need} ({points} points of {record} bytes): SIZE or TYPE is wrong")
    elif data_kind == "binary_compressed":
        with open(path, "rb") as fh:
            fh.seek(offset)
            sizes8 = fh.read(8)
        if len(sizes8) < 8:
            raise InputError(f"{path}: truncated: the compressed PCD data has no size header")
        compressed, uncompressed = struct.unpack("<II", sizes8)
        if uncompressed != points * record:
            raise InputError(f"{path}: the compressed PCD data unpacks to {uncompressed} bytes but "
                             f"the header declares {points * record}")
        if compressed > payload - 8:
            raise InputError(f"{path}: truncated: {payload - 8} bytes of compressed PCD data, "
                             f"{compressed} declared")
    elif payload < points * len(fields):  # ascii: at least one character per value
        raise InputError(f"{path}: truncated: {payload} bytes of text for {points} points")


# PCL's binary writer maps whole memory pages, so its files can end in up to a page of zero
# bytes after the declared points (for example Kinect v2 clouds saved by PCL 1.8); PCL's own
# reader ignores them.
_PCD_MAX_PADDING = 65536


def _zero_padding(path: Path, start: int, length: int) -> bool:
    """True when the ``length`` bytes of ``path`` from ``start`` are a writer's page padding:
    fewer than ``_PCD_MAX_PADDING`` and all zero."""
    if length >= _PCD_MAX_PADDING:
        return False
    with open(path, "rb") as fh:
        fh.seek(start)
        tail = fh.read(length)
    return len(tail) == length and not any(tail)


def _load_pcd(path: Path, max_points=None):
    import pypcd4

    _check_pcd_header(path, max_points)
    try:
        pc = pypcd4.PointCloud.from_path(path)
    except Exception as exc:  # pypcd4/pydantic/lzf raise many types on corrupt files
        raise InputError(f"{path}: not a readable PCD file ({type(exc).__name__}: "
                         f"{_one_line(exc, 200)})") from None
    md = pc.metadata
    if md.width * md.height != md.points or pc.pc_data.shape[0] != md.points:
        raise InputError(
            f"{path}: PCD header says {md.points} points ({md.width}x{md.height}) "
            f"but the data holds {pc.pc_data.shape[0]}"
        )
    return pc


def _sidecar_up(path: Path):
    """The ``up`` of a sidecar ``STEM.json`` next to a cloud file, or None (only the JSON
    sidecar is read: clouds carry their own geometry)."""
    from planerel.io.cloud import unit_up

    for stem in _frame_stems(path):
        js = stem.with_name(stem.name + ".json")
        if js.is_file():
            data = read_json_object(js, "sidecar JSON")
            if data.get("up") is None:
                return None
            _check_sidecar(js, {"up": data["up"]})
            return unit_up(data["up"], f"{js}: 'up'")
    return None


@_reader
def read_pcd(path, *, up=None, max_points: int | None = None, regrid: bool = True,
             organize: bool = True, intrinsics=None) -> Cloud:
    """Read a PCD file (ascii, binary or binary_compressed).

    An organized cloud (HEIGHT > 1) keeps its ``(H, W)`` grid, and its intrinsics are recovered
    by :func:`estimate_intrinsics` when the points are an exact pinhole back-projection.
    An unorganized cloud whose valid points are such a back-projection (a depth camera's frame
    saved without its invalid points) is put back on its pixel grid (:func:`pinhole_grid`;
    ``regrid=False`` keeps it as it is); any other unorganized cloud becomes ``(1, N, 3)`` with
    ``organized=False`` when ``organize`` (or ``regrid``: the cloud as stored) is False; else
    it is put on an image grid seen from
    the sensor (its ``VIEWPOINT`` when that is not the identity; ``intrinsics`` when given):
    :func:`planerel.io.organize.organize`, said in a :class:`PlanerelWarning`.  The up vector
    is ``up``, else the ``up`` of a sidecar ``STEM.json``, else unknown.
    """
    p = _existing(path)
    pc = _load_pcd(p, max_points)
    md = pc.metadata
    missing = [f for f in ("x", "y", "z") if f not in md.fields]
    if missing:
        raise InputError(f"{p}: PCD has no {'/'.join(missing)} field (fields: {' '.join(md.fields)})")
    xyz = np.asarray(pc.numpy(("x", "y", "z")), dtype=np.float64)
    organized = md.height > 1
    xyz = xyz.reshape(md.height, md.width, 3) if organized else xyz.reshape(1, -1, 3)
    if xyz.size == 0:
        raise InputError(f"{p}: PCD holds no points")
    intr = estimate_intrinsics(xyz, approximate=APPROX_FIT_PX, where=str(p)) if organized else None
    grid = pinhole_grid(xyz[0]) if regrid and not organized else None
    if grid is not None:
        xyz, intr, organized = _on_grid(xyz[0], grid, np.nan), grid[2], True
    elif regrid and organize and not organized:
        og = _pcd_organize(pc, xyz[0], p, intrinsics)
        xyz, intr, organized = og.xyz, og.intrinsics, True
    return Cloud(xyz, intr, up if up is not None else _sidecar_up(p), str(p), organized)


def _pcd_organize(pc, points: np.ndarray, p: Path, intrinsics, say: bool = True):
    """An unorganized PCD's image grid: from its VIEWPOINT when that is not the identity,
    or, when that puts the points behind the sensor but the stored frame does not, from the
    stored frame (said)."""
    from planerel.io.organize import is_identity_viewpoint

    vp = getattr(pc.metadata, "viewpoint", None)
    if vp is None or is_identity_viewpoint(vp):
        return _organize(points, str(p), intrinsics, say=say)
    try:
        return _organize(points, str(p), intrinsics, vp, say=say)
    except InputError as exc:
        try:
            grid = _organize(points, str(p), intrinsics, say=False)
        except InputError:
            raise exc from None
        if say:
            warnings.warn(f"{p}: its VIEWPOINT {' '.join(f'{v:g}' for v in vp)} puts points "
                          "behind the sensor or beyond one view; the points are used as stored "
                          "(camera frame)", PlanerelWarning, stacklevel=3)
            warnings.warn(grid.note(str(p)), PlanerelWarning, stacklevel=3)
        return grid


@_reader
def read_pcd_field(path, name: str, *, regrid: bool = True, organize: bool = True,
                   intrinsics=None) -> np.ndarray:
    """One field of a PCD file (e.g. ``label``), shaped ``(H, W)`` as :func:`read_pcd` shapes
    the points with the same arguments (``(1, N)`` if unorganized; on the recovered or the
    z-buffer grid, with 0 or NaN where no point is, when :func:`read_pcd` regrids or organizes
    the cloud: each pixel's value is its point's)."""
    p = _existing(path)
    pc = _load_pcd(p)
    md = pc.metadata
    if name not in md.fields:
        raise InputError(f"{p}: PCD has no field {name!r} (fields: {' '.join(md.fields)})")
    values = np.asarray(pc.pc_data[name])
    if md.height == 1 and regrid:
        pts = np.asarray(pc.numpy(("x", "y", "z")), dtype=np.float64)
        grid = pinhole_grid(pts)
        fill = np.nan if values.dtype.kind == "f" else 0
        if grid is not None:
            return _on_grid(values, grid, fill)
        if organize:
            return _pcd_organize(pc, pts, p, intrinsics, say=False).place(values, fill)
    return values.reshape(md.height, md.width)


# --------------------------------------------------------------------------- PLY and NPY


_PLY_SIZES = {"char": 1, "uchar": 1, "int8": 1, "uint8": 1, "short": 2, "ushort": 2,
              "int16": 2, "uint16": 2, "int": 4, "uint": 4, "int32": 4, "uint32": 4,
              "float": 4, "float32": 4, "double": 8, "float64": 8}


def _check_ply_header(path: Path, max_points=None) -> None:
    """Element counts of a PLY header against the point limit and the file's size."""
    with open(path, "rb") as fh:
        head = fh.read(65536)
        size = os.fstat(fh.fileno()).st_size
    end = head.find(b"end_header")
    if not head.startswith(b"ply") or end < 0:
        raise InputError(f"{path}: not a PLY file (no 'ply' ... 'end_header' header)")
    offset = head.find(b"\n", end)
    offset = (offset + 1) if offset >= 0 else len(head)
    fmt, total_min = None, 0
    elements: list[list] = []  # [name, count, fixed record size or None]
    for raw in head[:end].decode("ascii", "replace").splitlines():
        words = raw.split()
        if not words:
            continue
        if words[0] == "format" and len(words) >= 2:
            fmt = words[1]
        elif words[0] == "element" and len(words) >= 3:
            try:
                count = int(words[2])
            except ValueError:
                raise InputError(f"{path}: PLY element {words[1]!r} has no whole-number count "
                                 f"({words[2]!r})") from None
            if count < 0:
                raise InputError(f"{path}: PLY element {words[1]!r} has a negative count {count}")
            elements.append([words[1], count, 0])
        elif words[0] == "property" and elements and len(words) >= 3:
            if words[1] == "list" or words[1] not in _PLY_SIZES or elements[-1][2] is None:
                elements[-1][2] = None  # variable-size records: at least one byte each
            else:
                elements[-1][2] += _PLY_SIZES[words[1]]
    vertex = [e for e in elements if e[0] == "vertex"]
    if vertex:
        _check_points(path, vertex[0][1], "the PLY header", max_points)
    for _name, count, record in elements:
        per = (record or 1) if fmt and fmt.startswith("binary") else 2  # ascii: value + space
        total_min += count * per
    if total_min > size - offset:
        raise InputError(f"{path}: truncated: the PLY header declares at least {total_min} bytes "
                         f"of data, the file holds {size - offset}")


@_reader
def read_ply(path, *, up=None, max_points: int | None = None, organize: bool = True,
             intrinsics=None) -> Cloud:
    """Read the vertices of a PLY file (ascii or binary): put on an image grid seen from the
    sensor's origin (:func:`planerel.io.organize.organize`, ``intrinsics`` when given, said in
    a :class:`PlanerelWarning`; a vertex list that is an exact pinhole back-projection goes
    back on its own grid, :func:`pinhole_grid`), or with ``organize=False`` an unorganized
    cloud ``(1, N, 3)``.  The up vector is ``up``, else the ``up`` of a sidecar
    ``STEM.json``, else unknown."""
    from plyfile import PlyData

    p = _existing(path)
    _check_ply_header(p, max_points)
    try:
        ply = PlyData.read(str(p))
        vertex = ply["vertex"]
        xyz = np.stack([np.asarray(vertex[c], dtype=np.float64) for c in ("x", "y", "z")], axis=1)
    except KeyError as exc:
        raise InputError(f"{p}: PLY has no vertex {exc.args[0]!r}") from None
    except Exception as exc:  # plyfile raises several types on corrupt files
        raise InputError(f"{p}: not a readable PLY file ({type(exc).__name__}: "
                         f"{_one_line(exc, 200)})") from None
    if len(xyz) == 0:
        raise InputError(f"{p}: PLY holds no vertices")
    up_ = up if up is not None else _sidecar_up(p)
    if organize:
        grid = pinhole_grid(xyz)
        if grid is not None:
            return Cloud(_on_grid(xyz, grid, np.nan), grid[2], up_, str(p))
        og = _organize(xyz, str(p), intrinsics)
        return Cloud(og.xyz, og.intrinsics, up_, str(p))
    return Cloud(xyz.reshape(1, -1, 3), None, up_, str(p), organized=False)


def ply_grid_place(points: np.ndarray, values: np.ndarray, fill, path, intrinsics=None):
    """``values`` ``(N, ...)`` of a PLY's vertices ``points`` on the image grid
    :func:`read_ply` puts them on (its own pinhole grid, else the z-buffer grid)."""
    grid = pinhole_grid(points)
    if grid is not None:
        return _on_grid(np.asarray(values), grid, fill)
    return _organize(points, str(path), intrinsics, say=False).place(values, fill)


def _load_npy(path: Path, max_points=None) -> np.ndarray:
    """``np.load`` after checking the header's shape against the file's size and the limit."""
    fmt = np.lib.format
    with open(path, "rb") as fh:
        try:
            version = fmt.read_magic(fh)
            if version == (1, 0):
                shape, fortran, dtype = fmt.read_array_header_1_0(fh)
            else:
                shape, fortran, dtype = fmt._read_array_header(fh, version)
        except (ValueError, EOFError, SyntaxError, TypeError) as exc:
            raise InputError(f"{path}: not a readable .npy array ({_one_line(exc, 200)})") from None
        offset = fh.tell()
        size = os.fstat(fh.fileno()).st_size
    if dtype.hasobject:
        raise InputError(f"{path}: .npy must hold a numeric array, got dtype {dtype}")
    n = int(np.prod(shape, dtype=object)) if shape else 1
    points = n // shape[-1] if len(shape) == 3 and shape[-1] else n
    _check_points(path, points, "the .npy header", max_points)
    if n * dtype.itemsize != size - offset:
        raise InputError(f"{path}: the .npy header declares {shape} {dtype} "
                         f"({n * dtype.itemsize} bytes) but the file holds {size - offset}")
    try:
        return np.load(path, allow_pickle=False)
    except (ValueError, OSError, EOFError) as exc:
        raise InputError(f"{path}: not a readable .npy array ({_one_line(exc, 200)})") from None


@_reader
def read_npy(path, *, intrinsics=None, depth_scale: float | None = None, up=None,
             max_points: int | None = None, organize: bool = True) -> Cloud:
    """Read a ``.npy`` array: ``(H, W, 3)`` XYZ in metres (NaN invalid), ``(H, W)`` depth, or
    ``(N, 3)`` XYZ points (an unorganized cloud, as ``np.save(points)`` writes it).

    A depth array needs intrinsics (argument or sidecar); its scale defaults to 1 for float
    arrays (metres) and 1000 for integer arrays (millimetres).  An XYZ array gets intrinsics
    from the argument or, if it is an exact pinhole back-projection, from the points.  A point
    list that is a depth frame's back-projection is put back on its pixel grid, as
    :func:`read_pcd` does; any other is put on an image grid seen from the sensor's origin
    (:func:`planerel.io.organize.organize`, with ``intrinsics`` when given, said in a
    :class:`PlanerelWarning`), or with ``organize=False`` stays ``(1, N, 3)`` with
    ``organized=False``.  An ``(N, 3)`` array is always read as points (never as a depth image
    three pixels wide).
    """
    p = _existing(path)
    arr = _load_npy(p, max_points)
    if not isinstance(arr, np.ndarray) or arr.dtype.kind not in "iuf":
        raise InputError(f"{p}: .npy must hold a numeric array, got dtype {getattr(arr, 'dtype', '?')}")
    if arr.ndim == 2 and arr.shape[1] == 3:
        if arr.shape[0] == 0:
            raise InputError(f"{p}: .npy holds no points (shape {arr.shape})")
        xyz = np.asarray(arr, dtype=np.float64)
        info = find_camera_info(p)
        up_ = up if up is not None else info.get("up")
        grid = pinhole_grid(xyz)
        if grid is not None:
            return Cloud(_on_grid(xyz, grid, np.nan), grid[2], up_, str(p))
        if organize:
            og = _organize(xyz, str(p), intrinsics)
            return Cloud(og.xyz, og.intrinsics, up_, str(p))
        return Cloud(xyz.reshape(1, -1, 3), None, up_, str(p), organized=False)
    if arr.ndim == 3 and arr.shape[2] == 3:
        info = find_camera_info(p)
        value = intrinsics if intrinsics is not None else info.get("intrinsics")
        h, w = arr.shape[:2]
        where = str(p) if intrinsics is not None else info.get("source", str(p))
        intr = resolve_intrinsics(value, w, h, where) if value is not None else estimate_intrinsics(
            np.asarray(arr, dtype=np.float64), approximate=APPROX_FIT_PX, where=str(p))
        return Cloud(arr, intr, up if up is not None else info.get("up"), str(p))
    if arr.ndim == 2:
        info = find_camera_info(p)
        value = intrinsics if intrinsics is not None else info.get("intrinsics")
        if value is None:
            raise InputError(f"{p}: a depth array needs intrinsics (argument or sidecar JSON)")
        where = str(p) if intrinsics is not None else info.get("source", str(p))
        intr = resolve_intrinsics(value, arr.shape[1], arr.shape[0], where)
        if depth_scale is None:
            depth_scale = info.get("depth_scale")
        if depth_scale is None:
            depth_scale = 1.0 if arr.dtype.kind == "f" else DEFAULT_DEPTH_SCALE
        return depth_to_cloud(arr, intr, depth_scale, up=up if up is not None else info.get("up"),
                              source=str(p))
    raise InputError(f"{p}: .npy must hold (H, W, 3) XYZ, (H, W) depth or (N, 3) points, "
                     f"got shape {arr.shape}")


# --------------------------------------------------------------------------- SegComp ABW

# Calibrations from the SegComp tools (see ../shared/data/README.md); units are millimetres.
_ABW_CAL1 = {"offset": 785.410786, "scal": 0.773545, "f": -1610.981722, "c": 1.4508}
_ABW_CAL2 = {"offset": 771.016866, "scal": 0.791686, "f": -1586.072821, "c": 1.4508}
_ABW_CAL1_IMAGES = {0, 19, 21, 25, 27, 28, 29}
_ABW_LAST_IMAGE = 29  # SegComp's ABW images are numbered 0..29; no calibration beyond


def _read_sun_raster(path: Path, max_points=None) -> np.ndarray:
    """``(H, W)`` uint8 pixels of an 8-bit Sun rasterfile without colour map."""
    with open(path, "rb") as fh:
        header = fh.read(32)
    if len(header) < 32:
        raise InputError(f"{path}: too short for a Sun rasterfile ({len(header)} bytes)")
    magic, width, height, depth, length, _type, maptype, maplength = struct.unpack(">8I", header)
    if magic == _SUN_MAGIC and depth == 8:
        _check_points(path, width * height, "the raster header", max_points)
    data = path.read_bytes()
    if magic != _SUN_MAGIC:
        raise InputError(f"{path}: not a Sun rasterfile (magic {magic:#x})")
    if depth != 8:
        raise InputError(f"{path}: expected 8 bits per pixel, got {depth}")
    if width == 0 or height == 0:
        raise InputError(f"{path}: empty image {width}x{height}")
    row = width + (width % 2)  # rows are padded to 16 bits
    start = 32 + maplength
    need = row * height
    if len(data) - start < need:
        raise InputError(f"{path}: truncated: {len(data) - start} pixel bytes for {width}x{height}")
    pix = np.frombuffer(data, dtype=np.uint8, count=need, offset=start).reshape(height, row)
    return pix[:, :width].copy()


def _abw_calibration(path: Path) -> dict:
    m = re.search(r"(\d+)\.(range|gt-seg)$", path.name)
    if not m:
        raise InputError(
            f"{path}: cannot tell the ABW image number (and so its calibration) from the name; "
            "expected e.g. abw.test.6.range"
        )
    number = int(m.group(1))
    if number > _ABW_LAST_IMAGE:
        raise InputError(f"{path}: SegComp has no ABW image {number} (they are numbered 0 to "
                         f"{_ABW_LAST_IMAGE}), so its calibration is unknown; rename the file "
                         "after the SegComp image it is")
    return _ABW_CAL1 if number in _ABW_CAL1_IMAGES else _ABW_CAL2


@_reader
def read_abw(path, *, max_points: int | None = None) -> Cloud:
    """Read a SegComp ABW ``.range`` image as an organized cloud in metres.

    The SegComp formula gives X right, Y up and Z towards the sensor in millimetres with the
    sensor at distance ``v/SCAL + OFFSET``; planerel's camera frame is x = X, y = -Y,
    z = v/SCAL + OFFSET, which is exactly a pinhole camera with fx = |F|, fy = C|F|,
    cx = cy = 255 (a rigid motion of the SegComp points, so planes stay planes).
    Pixels with v == 0 are invalid.
    """
    p = _existing(path)
    cal = _abw_calibration(p)
    v = _read_sun_raster(p, max_points).astype(np.float64)
    h, w = v.shape
    f = abs(cal["f"])
    z = v / cal["scal"] + cal["offset"]
    r = np.arange(h, dtype=np.float64)[:, None]
    c = np.arange(w, dtype=np.float64)[None, :]
    xyz = np.empty((h, w, 3))
    xyz[:, :, 0] = (c - 255.0) * z / f
    xyz[:, :, 1] = (r - 255.0) / cal["c"] * z / f
    xyz[:, :, 2] = z
    xyz /= 1000.0
    xyz[v == 0] = np.nan
    if not np.any(v > 0):
        raise InputError(f"{p}: every pixel is invalid (no range measurement)")
    intr = Intrinsics(w, h, f, cal["c"] * f, 255.0, 255.0)
    return Cloud(xyz, intr, None, str(p))


@_reader
def read_abw_gt(path, *, max_points: int | None = None) -> np.ndarray:
    """SegComp ground truth ``.gt-seg`` as ``(H, W)`` int32 labels: plane labels (>= 10) kept,
    everything else (background, shadow, unlabelled) set to -1."""
    p = _existing(path)
    lab = _read_sun_raster(p, max_points).astype(np.int32)
    lab[lab < 10] = -1
    return lab


@_reader
def read_label_image(path, *, max_points: int | None = None) -> np.ndarray:
    """A label image as ``(H, W)`` int32 with -1 = none, from any of: ``.npy`` int array,
    a 16-bit label PNG of a planerel data set (value = label + 1, 0 = none), or a SegComp
    ``.gt-seg`` file."""
    p = _existing(path)
    kind = _sniff(p) or p.suffix.lower()
    if kind == ".npy":
        lab = _load_npy(p, max_points)
        if lab.ndim != 2 or lab.dtype.kind not in "iu":
            raise InputError(f"{p}: a label array must be 2-D integers, got {lab.dtype} {lab.shape}")
        return lab.astype(np.int32)
    if kind == ".range" or p.name.endswith(".gt-seg"):
        return read_abw_gt(p, max_points=max_points)
    if kind == ".png":
        from PIL import Image

        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", Image.DecompressionBombWarning)
                img = Image.open(p)
            with img:
                _check_points(p, img.width * img.height, "the PNG", max_points)
                arr = np.asarray(img)
        except InputError:
            raise
        except Exception as exc:
            raise InputError(f"{p}: cannot read the label image ({_one_line(exc, 200)})") from None
        if arr.ndim != 2 or arr.dtype.kind not in "iu":
            raise InputError(f"{p}: a label PNG must be single-channel integers, got {arr.dtype} {arr.shape}")
        return arr.astype(np.int32) - 1
    raise InputError(f"{p}: not a label image (.npy, label .png or SegComp .gt-seg)")
