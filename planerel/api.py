"""The top-level Python API: ``planerel.read``, ``planerel.segment``, ``planerel.describe``,
``planerel.Classifier``.

Each function takes what the command line takes -- a file path, or a numpy array, or a
:class:`~planerel.io.cloud.Cloud` -- and the same camera presets as strings (``"kinect"`` or
``"W,H,fx,fy,cx,cy"``)::

    import numpy as np, planerel
    depth = np.load("depth_mm.npy")                       # (480, 640) uint16 millimetres
    cloud = planerel.read(depth, intrinsics="kinect")     # -> Cloud (metres, camera frame)
    with planerel.Classifier("out/model/rules.pl") as clf:
        print(clf.classify(cloud).objects)                # class, rule and proof planes
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from planerel.errors import InputError
from planerel.io.cloud import Cloud

__all__ = ["read", "segment", "describe"]


def _camera(intrinsics):
    """A string camera (``"kinect"``, ``"W,H,fx,fy,cx,cy"``) -> what the readers take."""
    if isinstance(intrinsics, str):
        from planerel.commands._common import parse_intrinsics

        return parse_intrinsics(intrinsics.strip())
    return intrinsics


def read(source, *, intrinsics=None, depth_scale: float | None = None, up=None,
         subsample: int = 1, max_range: float | None = None, organize: bool = True) -> Cloud:
    """A scan as a :class:`~planerel.io.cloud.Cloud`, from a file, an array or a cloud.

    Parameters
    ----------
    source : str, Path, ndarray or Cloud
        A file in any format planerel reads (docs/formats.md); an ``(H, W, 3)`` float array of
        XYZ points in metres (NaN = invalid); an ``(H, W)`` depth array (needs
        ``intrinsics``; integer arrays are millimetres and float arrays metres unless
        ``depth_scale`` says otherwise); or a Cloud (returned, subsampled when asked).
    intrinsics : str, Intrinsics, 6-sequence, dict or 3x3 K, optional
        ``"kinect"`` (scaled to the image size) or ``"W,H,fx,fy,cx,cy"`` as on the command
        line.  Files: overrides a sidecar.  XYZ arrays: recorded with the cloud; without
        it, fitted to the points as for an ``.npy`` file (:func:`planerel.io.readers.
        estimate_intrinsics`: exact, or approximate with a :class:`~planerel.errors.
        PlanerelWarning`, or none).
    depth_scale : float, optional
        Depth units per metre.
    up : 3-sequence, optional
        Gravity-up vector in the camera frame.
    subsample : int
        Keep every k-th row and column (intrinsics scaled to match).
    max_range : float, optional
        Depth images: depths beyond this many metres are invalid.
    organize : bool
        Put an unorganized cloud (a PLY, a PCD with HEIGHT 1, an ``(N, 3)`` ``.npy``, an
        unorganized Cloud) on an image grid seen from the sensor
        (:func:`planerel.io.organize.organize`, said in a
        :class:`~planerel.errors.PlanerelWarning`; ``intrinsics`` give its camera); False
        keeps it unorganized.

    Returns
    -------
    Cloud
    """
    from planerel.io import readers as io
    from planerel.io.cloud import depth_to_cloud
    from planerel.io.cloud import subsample as _sub

    camera = _camera(intrinsics)
    if isinstance(source, Cloud):
        cloud = source.with_up(up) if up is not None else source
        if organize and not cloud.organized:
            where = cloud.source or "cloud"
            grid = io._organize(np.asarray(cloud.xyz).reshape(-1, 3), where, camera)
            cloud = Cloud(grid.xyz, grid.intrinsics, cloud.up, cloud.source)
    elif isinstance(source, (str, Path)):
        cloud = io.read(source, intrinsics=camera, depth_scale=depth_scale, up=up,
                        max_range=max_range, organize=organize)
    elif isinstance(source, np.ndarray):
        arr = source
        if arr.ndim == 3 and arr.shape[2] == 3:
            if not np.issubdtype(arr.dtype, np.floating):
                raise InputError(f"an XYZ array must hold floats (metres), got dtype {arr.dtype}")
            xyz = np.array(arr, dtype=np.float64)
            # as for an .npy file: the intrinsics that reproduce the points (a warning when
            # only approximately), so the measures that project planes into the image hold
            intr = (io.resolve_intrinsics(camera, arr.shape[1], arr.shape[0], "XYZ array")
                    if camera is not None else io.estimate_intrinsics(
                        xyz, approximate=io.APPROX_FIT_PX, where="XYZ array"))
            if max_range is not None:
                with np.errstate(invalid="ignore"):
                    xyz[xyz[..., 2] > max_range] = np.nan
            cloud = Cloud(xyz, intr, up, None)
        elif arr.ndim == 2:
            if camera is None:
                raise InputError("a depth array needs intrinsics: intrinsics='kinect' or "
                                 "'W,H,fx,fy,cx,cy'")
            intr = io.resolve_intrinsics(camera, arr.shape[1], arr.shape[0], "depth array")
            scale = depth_scale if depth_scale is not None else (
                1.0 if arr.dtype.kind == "f" else 1000.0)
            cloud = depth_to_cloud(arr, intr, scale, up=up, max_range=max_range)
        else:
            raise InputError(f"an array scan must be (H, W) depth or (H, W, 3) XYZ, got shape "
                             f"{arr.shape}")
    else:
        raise InputError(f"cannot read a scan from a {type(source).__name__}; give a path, an "
                         "array or a Cloud")
    return _sub(cloud, subsample)


def segment(scan, method: str = "regiongrow", *, intrinsics=None, **params):
    """Segment a scan (path, array or Cloud, as :func:`read` takes) into planes.

    ``planerel.segment(...)`` is this function; ``planerel.segment.segment`` is the one that
    takes a Cloud only.  ``params`` are the method's parameters (docs/segmentation.md); ``up``
    among them (3 numbers) is the camera's up when known, which the small pass's
    ``small_pitch`` reads (else the scan's own or the estimated one).

    Returns
    -------
    Segmentation
        ``labels`` (H, W) int32 (-1 = unassigned) and ``planes``.
    """
    from planerel.features.facts import view_up
    from planerel.segment import segment as _segment

    cloud = scan if isinstance(scan, Cloud) else read(scan, intrinsics=intrinsics)
    up = params.pop("up", None)
    return _segment(cloud, method, up=view_up(cloud, up), **params)


def describe(scan, labels=None, *, scene_id: str | None = None, method: str = "regiongrow",
             intrinsics=None, up=None, camera_height=None):
    """Planes, relations and object proposals of a scan (what ``planerel describe`` writes).

    Parameters
    ----------
    scan : path, ndarray or Cloud
    labels : ndarray (H, W) int or path, optional
        Plane labels to use instead of segmenting.
    scene_id : str, optional
        Default: the file's scene name (:mod:`planerel.io.naming`), else ``"s0000"``.
    up : 3 numbers, optional
        Gravity up in the camera frame (default: the file's own, else estimated).
    camera_height : float, optional
        The camera's height over the floor, metres, when known
        (:func:`planerel.features.facts.describe_scene`).

    Returns
    -------
    SceneDescription
        ``facts()`` of it: :func:`planerel.features.facts.facts_text`.
    """
    from planerel.features.facts import describe_scene
    from planerel.io import readers as io
    from planerel.io.naming import scene_name

    cloud = scan if isinstance(scan, Cloud) else read(scan, intrinsics=intrinsics)
    if scene_id is None:
        scene_id = scene_name(scan) if isinstance(scan, (str, Path)) else "s0000"
    far = ()
    if labels is None:
        seg = segment(cloud, method, up=up)  # this module's segment: the up to view_up
        labels, far = seg.labels, seg.info.get("far_labels") or ()
    elif isinstance(labels, (str, Path)):
        labels = io.read_label_image(labels)
    return describe_scene(cloud, labels, scene_id=scene_id, up=up, far=far,
                          camera_height=camera_height)
