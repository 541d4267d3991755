"""Outputs other tools open: labelled PCD, coloured PLY, plane meshes, scene graphs.

- :func:`write_pcd` -- PCD v0.7 binary (PCL's ``PointXYZRGBL``: ``x y z rgb label``), organized
  when the cloud is; readable by PCL, Open3D and pypcd4.
- :func:`write_segmentation_ply` -- the valid points coloured by plane, with an int ``label``.
- :func:`plane_mesh` / :func:`write_mesh` -- each plane's polygon (its hull in 3-D) as
  triangles, one colour per plane, as PLY or GLB (trimesh), for any 3-D viewer.
- :func:`scene_graph` / :func:`write_graph` -- planes as nodes, relations as edges (networkx),
  as GraphML or node-link JSON.
- :func:`input_colours` -- the colours a PCD / PLY scan carries, so outputs keep them.

Label convention of the PCD: ``label = plane + 1``, 0 = no plane (PCL's unsigned labels; the
same rule as the data sets' ground-truth PNGs).  The ``.labels.npy`` keeps -1 = unassigned.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from planerel.atomic import atomic_path, write_bytes
from planerel.errors import InputError

__all__ = ["pack_rgb", "unpack_rgb", "input_colours", "write_pcd", "write_segmentation_ply",
           "plane_colours", "plane_mesh", "write_mesh", "scene_graph", "write_graph"]

GREY = (128, 128, 128)


def pack_rgb(rgb) -> np.ndarray:
    """``(..., 3)`` uint8 -> ``(...)`` float32 holding ``0x00RRGGBB`` bits (PCL's ``rgb``)."""
    c = np.asarray(rgb, dtype=np.uint32)
    packed = (c[..., 0] << 16) | (c[..., 1] << 8) | c[..., 2]
    return packed.astype(np.uint32).view(np.float32)


def unpack_rgb(values) -> np.ndarray:
    """PCL ``rgb`` / ``rgba`` values (float32 bits or uint32) -> ``(..., 3)`` uint8."""
    v = np.asarray(values)
    if v.dtype == np.float32:
        v = v.view(np.uint32)
    v = v.astype(np.uint32)
    return np.stack([(v >> 16) & 255, (v >> 8) & 255, v & 255], axis=-1).astype(np.uint8)


def input_colours(path, shape: tuple[int, int], subsample: int = 1, *,
                  organize: bool = True, intrinsics=None) -> np.ndarray | None:
    """The per-point colours of a scan file, ``(H, W, 3)`` uint8 matching the read cloud's
    ``shape`` (after ``subsample``; an unorganized cloud's on the image grid the readers put
    it on, as ``organize`` and ``intrinsics`` say), or None when the file has none (depth
    images, XYZ arrays, clouds without colour fields) or they do not line up with the
    points."""
    from planerel.io.readers import _sniff

    p = Path(path)
    cols = None
    try:
        # the content names the format first, as planerel.io.read decides it (a PCD saved as
        # .ply was read as a PCD, then its colours looked for with plyfile: a traceback)
        low = _sniff(p) or p.suffix.lower()
        if low == ".pcd":
            from planerel.io.readers import read_pcd_field

            for name in ("rgb", "rgba"):
                try:
                    cols = unpack_rgb(read_pcd_field(p, name, organize=organize,
                                                     intrinsics=intrinsics))
                    break
                except InputError:
                    continue
        elif low == ".ply":
            from plyfile import PlyData, PlyParseError

            try:
                v = PlyData.read(str(p))["vertex"].data
            except PlyParseError:  # not a ValueError: the PLY's own errors say no colours
                return None
            names = v.dtype.names or ()
            if {"red", "green", "blue"} <= set(names):
                cols = np.stack([v["red"], v["green"], v["blue"]], axis=-1).astype(np.uint8)
                if organize and tuple(shape) != (1, len(cols)):
                    from planerel.io.readers import ply_grid_place

                    xyz = np.stack([np.asarray(v[c], np.float64) for c in "xyz"], axis=1)
                    cols = ply_grid_place(xyz, cols, 0, p, intrinsics)
                else:
                    cols = cols[None]
    except (OSError, ValueError, KeyError):  # InputError is a ValueError
        return None
    if cols is None:
        return None
    if subsample > 1 and cols.shape[0] > 1:
        cols = cols[::subsample, ::subsample]
    return cols if cols.shape[:2] == tuple(shape) else None


def write_pcd(path, xyz, *, colours=None, labels=None) -> Path:
    """Write a binary PCD v0.7: ``x y z`` float32, ``rgb`` (packed float) when colours are
    given and ``label`` uint32 when labels are given.

    Parameters
    ----------
    xyz : array_like, shape (H, W, 3) or (N, 3)
        Points in metres; NaN points are kept (an organized cloud keeps its grid).
    colours : array_like, shape (H, W, 3) or (N, 3), uint8, optional
    labels : array_like, shape (H, W) or (N,), int, optional
        planerel labels (-1 = none); written as ``label + 1`` (0 = none).
    """
    p = np.asarray(xyz, dtype=np.float64)
    if p.shape[-1] != 3 or p.ndim not in (2, 3):
        raise InputError(f"points must have shape (N, 3) or (H, W, 3), got {p.shape}")
    h, w = (p.shape[0], p.shape[1]) if p.ndim == 3 else (1, p.shape[0])
    n = h * w
    fields = [("x", "<f4"), ("y", "<f4"), ("z", "<f4")]
    if colours is not None:
        fields.append(("rgb", "<f4"))
    if labels is not None:
        fields.append(("label", "<u4"))
    rec = np.empty(n, dtype=fields)
    flat = p.reshape(-1, 3)
    rec["x"], rec["y"], rec["z"] = flat[:, 0], flat[:, 1], flat[:, 2]
    if colours is not None:
        c = np.asarray(colours).reshape(-1, 3)
        if len(c) != n:
            raise InputError(f"{len(c)} colours for {n} points")
        rec["rgb"] = pack_rgb(c)
    if labels is not None:
        lab = np.asarray(labels).reshape(-1)
        if len(lab) != n:
            raise InputError(f"{len(lab)} labels for {n} points")
        rec["label"] = np.where(lab >= 0, lab + 1, 0).astype(np.uint32)
    names = [f[0] for f in fields]
    types = ["F" if f[1].endswith("f4") else "U" for f in fields]
    header = "\n".join([
        "# .PCD v0.7 - Point Cloud Data file format (planerel)",
        "VERSION 0.7",
        "FIELDS " + " ".join(names),
        "SIZE " + " ".join("4" for _ in names),
        "TYPE " + " ".join(types),
        "COUNT " + " ".join("1" for _ in names),
        f"WIDTH {w}",
        f"HEIGHT {h}",
        "VIEWPOINT 0 0 0 1 0 0 0",
        f"POINTS {n}",
        "DATA binary",
    ]) + "\n"
    return write_bytes(path, header.encode("ascii") + rec.tobytes())


def plane_colours(labels) -> np.ndarray:
    """``(..., 3)`` uint8: each point in its plane's colour (:func:`planerel.io.writers.label_colours`,
    the colours of ``NAME.labels.png``), grey where no plane."""
    from planerel.io.writers import label_colours

    lab = np.asarray(labels)
    out = np.empty(lab.shape + (3,), dtype=np.uint8)
    out[...] = GREY
    pos = lab >= 0
    if pos.any():
        out[pos] = label_colours(int(lab.max()) + 1)[lab[pos]]
    return out


def write_segmentation_ply(path, xyz, labels) -> Path:
    """The valid points of a segmented cloud as a binary PLY: ``x y z``, the plane colours
    ``red green blue`` and an int ``label`` (-1 = none)."""
    from planerel.io.writers import write_ply

    return write_ply(path, xyz, colours=plane_colours(labels), labels=labels)


def plane_mesh(desc):
    """The planes of a described scene as one ``trimesh.Trimesh``: each plane's hull polygon
    in 3-D (``Plane.hull3d``, convex) as a triangle fan with its own vertices, coloured by
    plane (vertex colours, so PLY and GLB both keep them).

    Returns
    -------
    mesh : trimesh.Trimesh
    face_plane : ndarray (F,) int
        The plane label of each face.
    """
    import trimesh

    from planerel.io.writers import label_colours

    verts, faces, cols, face_plane = [], [], [], []
    n_labels = max((p.label for p in desc.planes), default=-1) + 1
    pal = label_colours(max(n_labels, 1))
    base = 0
    for p in desc.planes:
        poly = np.asarray(p.hull3d, dtype=float)
        if poly.ndim != 2 or len(poly) < 3:
            continue
        k = len(poly)
        verts.append(poly)
        faces.extend([base, base + i, base + i + 1] for i in range(1, k - 1))
        face_plane.extend([p.label] * (k - 2))
        rgba = np.append(pal[p.label], 255).astype(np.uint8)
        cols.append(np.repeat(rgba[None], k, axis=0))
        base += k
    if not verts:
        raise InputError(f"scene {desc.scene_id}: no plane polygon to write as a mesh")
    mesh = trimesh.Trimesh(vertices=np.vstack(verts), faces=np.asarray(faces),
                           vertex_colors=np.vstack(cols), process=False)
    return mesh, np.asarray(face_plane)


def write_mesh(path, desc) -> Path:
    """Write :func:`plane_mesh` as ``.ply`` (binary) or ``.glb``, chosen by the extension."""
    kind = Path(path).suffix.lower().lstrip(".")
    if kind not in ("ply", "glb"):
        raise InputError(f"{path}: a mesh is written as .ply or .glb")
    mesh, _ = plane_mesh(desc)
    return write_bytes(path, mesh.export(file_type=kind))


def scene_graph(desc):
    """The scene as a ``networkx.DiGraph``: one node per plane (id, orientation, area, incline,
    height, distance, n_points, normal and centroid components, floor, objects), one edge
    ``a -> b`` per ordered related pair, as in the facts (angle, gap, rise, parallel,
    perpendicular, adjacent, above, in_front_of, skirt, corner: ``rise(a, b)``, ``above(a, b)``, ...).
    Graph attributes: scene, up, up_source."""
    import networkx as nx

    g = nx.DiGraph(scene=desc.scene_id, up=",".join(f"{x:.6g}" for x in desc.planes.up),
                 up_source=str(desc.planes.up_source))
    objects: dict[int, list[str]] = {}
    for o in desc.objects:
        for lbl in o.planes:
            objects.setdefault(lbl, []).append(o.id)
    for p in desc.planes:
        g.add_node(desc.plane_id(p.label), label=int(p.label), orientation=p.orientation,
                   area=float(p.area), incline=float(p.incline), height=float(p.height),
                   distance=float(p.distance), n_points=int(p.n_points),
                   nx=float(p.normal[0]), ny=float(p.normal[1]), nz=float(p.normal[2]),
                   cx=float(p.centroid[0]), cy=float(p.centroid[1]), cz=float(p.centroid[2]),
                   floor=bool(p.label == desc.planes.floor),
                   objects=",".join(objects.get(p.label, [])))
    for r in desc.relations:
        g.add_edge(desc.plane_id(r.a), desc.plane_id(r.b), angle=float(r.angle), gap=float(r.gap), rise=float(r.rise),
                   parallel=bool(r.parallel), perpendicular=bool(r.perpendicular),
                   adjacent=bool(r.adjacent), above=bool(r.above),
                   in_front_of=bool(r.in_front_of), skirt=bool(r.skirt),
                   corner=bool(r.corner), facing=bool(r.facing))
    return g


def write_graph(path, desc) -> Path:
    """Write :func:`scene_graph` as GraphML (``.graphml``) or node-link JSON (``.json``)."""
    import networkx as nx

    from planerel.io.writers import write_json

    g = scene_graph(desc)
    low = str(path).lower()
    if low.endswith(".graphml"):
        with atomic_path(path, suffix=".graphml") as tmp:
            nx.write_graphml(g, str(tmp))
        return Path(path)
    if low.endswith(".json"):
        return write_json(path, nx.node_link_data(g, edges="links"))
    raise InputError(f"{path}: a scene graph is written as .graphml or .json")
