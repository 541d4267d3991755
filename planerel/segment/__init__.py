"""Planar segmentation: region growing (the paper's Algorithm 1, default) and the RANSAC
baselines SP (plane) and SNP (plane with normals).

>>> from planerel.segment import segment
>>> seg = segment(cloud)                                  # doctest: +SKIP
>>> seg.labels            # (H, W) int32, -1 = unassigned  # doctest: +SKIP
>>> seg.planes[0].normal, seg.planes[0].offset            # doctest: +SKIP

See docs/segmentation.md for the algorithm, every parameter and the measured quality and speed.
"""

from __future__ import annotations

from planerel.errors import InputError
from planerel.segment.params import RansacParams, RegionGrowParams, coerce_params
from planerel.segment.result import Segmentation, SegPlane, fit_planes

__all__ = [
    "segment",
    "METHODS",
    "Segmentation",
    "SegPlane",
    "RegionGrowParams",
    "RansacParams",
    "fit_planes",
    "make_params",
]

#: Method names :func:`segment` accepts.
METHODS = ("regiongrow", "sp", "snp")


def make_params(method: str = "regiongrow", **params):
    """The parameter dataclass of ``method`` built from keyword values (strings from the command
    line are converted); unknown names raise :class:`InputError`.  Region growing also takes
    ``preset`` (``"kinect"`` = the defaults, ``"structured-light"`` / ``"abw"``: see
    :data:`planerel.segment.params.PRESETS`); explicit values override the preset's."""
    if method not in METHODS:
        raise InputError(f"unknown segmentation method {method!r}; choose one of {', '.join(METHODS)}")
    if method == "regiongrow":
        preset = params.pop("preset", None)
        if preset is not None:
            from planerel.segment.params import preset_values

            params = {**preset_values(preset), **params}
        return coerce_params(RegionGrowParams, params)
    return coerce_params(RansacParams, params)


def segment(cloud, method: str = "regiongrow", *, normals=None, **params) -> Segmentation:
    """Segment a cloud into planes.

    Parameters
    ----------
    cloud : Cloud
        Organized ``(H, W, 3)`` or unorganized ``(1, N, 3)`` cloud (metres, NaN invalid).
    method : {"regiongrow", "sp", "snp"}
        Region growing (the paper's Algorithm 1), RANSAC plane (SP) or RANSAC plane with
        normals (SNP).
    normals : ndarray, shape (H, W, 3), optional
        Precomputed normals (regiongrow, snp).
    **params
        Fields of :class:`RegionGrowParams` (regiongrow) or :class:`RansacParams` (sp, snp);
        or ``params=<dataclass instance>``; regiongrow also ``preset="structured-light"``.

    Returns
    -------
    Segmentation
        ``labels`` (H, W) int32 with -1 unassigned and ``planes`` (normal towards the sensor,
        ``offset > 0``, ``n_points``, ``centroid``, ``rms``).

    Raises
    ------
    InputError
        No / one valid point, all points on a line, bad or unknown parameters.
    """
    from planerel.cloud import Cloud

    if not isinstance(cloud, Cloud):
        raise InputError(f"segment: expected a planerel Cloud, got {type(cloud).__name__}")
    given = params.pop("params", None)
    if given is not None:
        if params:
            raise InputError("segment: give either params=<dataclass> or keyword parameters, not both")
        p = given
    else:
        p = make_params(method, **params)
    if method == "regiongrow":
        from planerel.segment.regiongrow import region_grow

        return region_grow(cloud, p, normals=normals)
    if method not in METHODS:
        raise InputError(f"unknown segmentation method {method!r}; choose one of {', '.join(METHODS)}")
    from planerel.segment.ransac import ransac_segment

    return ransac_segment(cloud, p, normals=normals if method == "snp" else None,
                          use_normals=(method == "snp"))
