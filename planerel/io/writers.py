"""Writers for results: label images (``.npy`` and colour PNG), coloured PLY clouds, JSON.

Every writer is atomic (see :mod:`planerel.atomic`).
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np

from planerel.atomic import atomic_path, write_text
from planerel.errors import InputError

__all__ = [
    "label_colours",
    "colour_labels",
    "write_labels_npy",
    "write_labels_png",
    "write_depth_png",
    "write_ply",
    "write_json",
    "to_jsonable",
]


def _check_labels(labels) -> np.ndarray:
    lab = np.asarray(labels)
    if lab.ndim != 2:
        raise InputError(f"a label image must be 2-D (H, W), got shape {lab.shape}")
    if not np.issubdtype(lab.dtype, np.integer):
        raise InputError(f"a label image must hold integers, got dtype {lab.dtype}")
    return lab.astype(np.int32, copy=False)


def label_colours(n: int) -> np.ndarray:
    """``(n, 3)`` uint8 distinct colours: hues spaced by the golden ratio, fixed order."""
    i = np.arange(n)
    hue = (i * 0.618033988749895) % 1.0
    sat = np.where(i % 2 == 0, 0.85, 0.6)
    val = np.where(i % 3 == 2, 0.75, 0.95)
    h6 = hue * 6.0
    c = val * sat
    x = c * (1 - np.abs(h6 % 2 - 1))
    m = val - c
    sector = h6.astype(int) % 6
    z = np.zeros(n)
    r = np.choose(sector, [c, x, z, z, x, c])
    g = np.choose(sector, [x, c, c, x, z, z])
    b = np.choose(sector, [z, z, x, c, c, x])
    return np.round(np.stack([r + m, g + m, b + m], axis=1) * 255).astype(np.uint8)


def colour_labels(labels, depth=None) -> np.ndarray:
    """``(H, W, 3)`` uint8 picture of a label image.

    Labelled pixels get their label's colour, shaded by depth when ``depth`` (H, W) is given;
    unassigned pixels (-1) show the depth in grey; invalid depth is black.
    """
    lab = _check_labels(labels)
    h, w = lab.shape
    shade = np.ones((h, w))
    grey = np.zeros((h, w))
    if depth is not None:
        d = np.asarray(depth, dtype=float)
        if d.shape != lab.shape:
            raise InputError(f"depth shape {d.shape} differs from label shape {lab.shape}")
        ok = np.isfinite(d) & (d > 0)
        if ok.any():
            lo, hi = np.percentile(d[ok], [1, 99])
            t = np.clip((d - lo) / max(hi - lo, 1e-9), 0, 1)
            shade = np.where(ok, 1.0 - 0.45 * t, 0.0)
            grey = np.where(ok, 200.0 - 140.0 * t, 0.0)
    else:
        grey[:] = 128.0
    out = np.repeat(grey[:, :, None], 3, axis=2)
    pos = lab >= 0
    if pos.any():
        pal = label_colours(int(lab.max()) + 1).astype(float)
        out[pos] = pal[lab[pos]] * shade[pos][:, None]
    return np.clip(np.round(out), 0, 255).astype(np.uint8)


def write_labels_npy(path, labels) -> Path:
    """Write an ``(H, W)`` int32 label image as ``.npy`` (-1 = unassigned)."""
    lab = _check_labels(labels)
    with atomic_path(path, suffix=".npy") as tmp:
        np.save(tmp, lab, allow_pickle=False)
    return Path(path)


def write_labels_png(path, labels, depth=None) -> Path:
    """Write a colour PNG of a label image over a depth shading (see :func:`colour_labels`)."""
    from PIL import Image

    rgb = colour_labels(labels, depth)
    with atomic_path(path, suffix=".png") as tmp:
        Image.fromarray(rgb, mode="RGB").save(tmp, format="PNG")
    return Path(path)


def write_depth_png(path, depth_units) -> Path:
    """Write an ``(H, W)`` array of integer depth units (e.g. mm) as a 16-bit PNG."""
    from PIL import Image

    d = np.asarray(depth_units)
    if d.ndim != 2:
        raise InputError(f"a depth image must be 2-D, got shape {d.shape}")
    if np.issubdtype(d.dtype, np.floating):
        if not np.all(np.isfinite(d)):
            raise InputError("depth units must be finite (use 0 for invalid)")
        d = np.round(d)
    if d.min(initial=0) < 0 or d.max(initial=0) > 65534:
        raise InputError("depth units must lie in 0..65534 for a 16-bit PNG (0 and 65535 "
                         "are read back as no data)")
    img = Image.fromarray(d.astype(np.uint16))
    with atomic_path(path, suffix=".png") as tmp:
        img.save(tmp, format="PNG")
    return Path(path)


def write_ply(path, points, colours=None, labels=None) -> Path:
    """Write a binary little-endian PLY of points with optional colours and labels.

    Parameters
    ----------
    points : array_like, shape (N, 3) or (H, W, 3)
        Points; rows with NaN are skipped.
    colours : array_like, shape (N, 3) or (H, W, 3), uint8, optional
    labels : array_like, shape (N,) or (H, W), int, optional
        Written as an int32 ``label`` property.
    """
    from plyfile import PlyData, PlyElement

    p = np.asarray(points, dtype=np.float64)
    if p.shape[-1] != 3 or p.ndim not in (2, 3):
        raise InputError(f"points must have shape (N, 3) or (H, W, 3), got {p.shape}")
    p = p.reshape(-1, 3)
    keep = np.all(np.isfinite(p), axis=1)
    fields = [("x", "f4"), ("y", "f4"), ("z", "f4")]
    cols = {}
    if colours is not None:
        c = np.asarray(colours).reshape(-1, 3)
        if len(c) != len(p):
            raise InputError(f"{len(c)} colours for {len(p)} points")
        fields += [("red", "u1"), ("green", "u1"), ("blue", "u1")]
        cols.update(red=c[:, 0], green=c[:, 1], blue=c[:, 2])
    if labels is not None:
        lab = np.asarray(labels).reshape(-1)
        if len(lab) != len(p):
            raise InputError(f"{len(lab)} labels for {len(p)} points")
        fields.append(("label", "i4"))
        cols["label"] = lab
    arr = np.empty(int(keep.sum()), dtype=fields)
    arr["x"], arr["y"], arr["z"] = p[keep, 0], p[keep, 1], p[keep, 2]
    for name, values in cols.items():
        arr[name] = values[keep]
    with atomic_path(path, suffix=".ply") as tmp:
        PlyData([PlyElement.describe(arr, "vertex")], text=False).write(str(tmp))
    return Path(path)


def to_jsonable(obj):
    """Convert numpy scalars/arrays, tuples, paths and dataclasses to JSON-ready values."""
    import dataclasses

    if isinstance(obj, dict):
        return {str(k): to_jsonable(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [to_jsonable(v) for v in obj]
    if isinstance(obj, np.ndarray):
        return to_jsonable(obj.tolist())
    if isinstance(obj, np.integer):
        return int(obj)
    if isinstance(obj, np.floating):
        return float(obj)
    if isinstance(obj, np.bool_):
        return bool(obj)
    if isinstance(obj, Path):
        return str(obj)
    if dataclasses.is_dataclass(obj) and not isinstance(obj, type):
        return to_jsonable({f.name: getattr(obj, f.name) for f in dataclasses.fields(obj)})
    return obj


def write_json(path, data, *, indent: int = 2) -> Path:
    """Write ``data`` as JSON (sorted keys, NaN refused) atomically."""
    try:
        text = json.dumps(to_jsonable(data), indent=indent, sort_keys=True, allow_nan=False)
    except ValueError as exc:
        raise InputError(f"cannot write {path} as JSON: {exc}") from None
    return write_text(path, text + "\n")
