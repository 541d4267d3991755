"""The on-disk data-set format: depth PNGs, JSON sidecars, ground-truth label PNGs, a manifest.

A data set is a folder::

    manifest.csv        one row per scene: scene_id,class,seed,width,height,depth,labels,meta
    dataset.json        how the set was made (optional for hand-made sets)
    s0000.depth.png     16-bit depth, units of 1/depth_scale metres (mm), 0 = missing
    s0000.gt.png        16-bit ground-truth plane labels: value = plane index + 1, 0 = none
    s0000.json          sidecar: intrinsics, depth_scale, up, pose, class, objects, planes, ...
    s0000.objects.png   (varied world) 16-bit ground-truth object index + 1, 0 = none

The sidecar makes ``planerel.io.readers.read("s0000.depth.png")`` find the intrinsics, depth scale and up
vector by itself.  The full description is in ``docs/formats.md`` ("Synthetic data sets").
"""

from __future__ import annotations

import csv
import io as _io
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from planerel.errors import InputError
from planerel.io.readers import read_json_object

__all__ = [
    "MANIFEST",
    "INFO",
    "MANIFEST_COLUMNS",
    "ManifestRow",
    "write_scene",
    "write_manifest",
    "write_dataset_info",
    "write_label_png",
    "load_manifest",
    "load_dataset_info",
    "load_scene",
    "load_metadata",
    "iter_scenes",
    "load_object_labels",
    "object_classes",
    "describe_truth_scene",
]

MANIFEST = "manifest.csv"
INFO = "dataset.json"
MANIFEST_COLUMNS = ("scene_id", "class", "seed", "width", "height", "depth", "labels", "meta")


@dataclass(frozen=True)
class ManifestRow:
    """One scene of a data set.

    Parameters
    ----------
    scene_id : str
        ``s0007``.
    klass : str
        The scene's class (``box``, ``stairs``, ``ramp``; any non-empty word for other sets).
    seed : int or None
        The seed that regenerates a synthetic scene (None when unknown).
    width, height : int
        Image size.
    depth, labels, meta : str
        File names, relative to the data-set folder; ``labels`` may be empty (no ground truth).
    """

    scene_id: str
    klass: str
    seed: int | None
    width: int
    height: int
    depth: str
    labels: str
    meta: str

    def __post_init__(self) -> None:
        if not self.scene_id or any(c in self.scene_id for c in "/\\,\n"):
            raise InputError(f"bad scene id {self.scene_id!r}")
        if not self.klass:
            raise InputError(f"scene {self.scene_id}: empty class")
        for name in ("width", "height"):
            v = getattr(self, name)
            if isinstance(v, bool) or not isinstance(v, (int, np.integer)) or v < 1:
                raise InputError(f"scene {self.scene_id}: {name} must be a positive integer, got {v!r}")
        if not self.depth or not self.meta:
            raise InputError(f"scene {self.scene_id}: the depth and meta file names are required")

    def to_csv(self) -> list:
        return [self.scene_id, self.klass, "" if self.seed is None else self.seed, self.width,
                self.height, self.depth, self.labels, self.meta]


# ----------------------------------------------------------------------- writing


def write_label_png(path, labels) -> Path:
    """Write an ``(H, W)`` int label image (-1 = none) as a 16-bit PNG holding ``label + 1``."""
    from PIL import Image

    from planerel.atomic import atomic_path

    lab = np.asarray(labels)
    if lab.ndim != 2 or lab.dtype.kind not in "iu":
        raise InputError(f"{path}: a label image must be 2-D integers, got {lab.dtype} {lab.shape}")
    if lab.size and (lab.min() < -1 or lab.max() > 65534):
        raise InputError(f"{path}: labels must lie in -1..65534 for a 16-bit PNG")
    img = Image.fromarray((lab.astype(np.int64) + 1).astype(np.uint16))
    with atomic_path(path, suffix=".png") as tmp:
        img.save(tmp, format="PNG")
    return Path(path)


def write_scene(out_dir, scene) -> ManifestRow:
    """Write one :class:`planerel.synth.generator.Scene`: depth PNG, label PNG and JSON sidecar.

    Returns
    -------
    ManifestRow
        The scene's manifest row (the manifest itself is written by :func:`write_manifest`).
    """
    from planerel.io.writers import write_depth_png, write_json

    out = Path(out_dir)
    sid = scene.scene_id
    depth_name, labels_name, meta_name = f"{sid}.depth.png", f"{sid}.gt.png", f"{sid}.json"
    meta = scene.metadata()
    meta["files"] = {"depth": depth_name, "labels": labels_name}
    write_depth_png(out / depth_name, scene.depth_mm)
    write_label_png(out / labels_name, scene.gt_labels)
    if getattr(scene, "world", "paper") != "paper":
        meta["files"]["objects"] = f"{sid}.objects.png"
        write_label_png(out / meta["files"]["objects"], scene.gt_objects)
    write_json(out / meta_name, meta)
    h, w = scene.depth_mm.shape
    return ManifestRow(sid, scene.klass, scene.seed, w, h, depth_name, labels_name, meta_name)


def write_manifest(out_dir, rows) -> Path:
    """Write ``manifest.csv`` (header :data:`MANIFEST_COLUMNS`, ``\\n`` line ends)."""
    from planerel.atomic import write_text

    rows = list(rows)
    ids = [r.scene_id for r in rows]
    if len(set(ids)) != len(ids):
        dup = sorted({i for i in ids if ids.count(i) > 1})
        raise InputError(f"duplicate scene ids in the manifest: {', '.join(dup)}")
    buf = _io.StringIO()
    writer = csv.writer(buf, lineterminator="\n")
    writer.writerow(MANIFEST_COLUMNS)
    for r in rows:
        writer.writerow(r.to_csv())
    return write_text(Path(out_dir) / MANIFEST, buf.getvalue())


def write_dataset_info(out_dir, info: dict) -> Path:
    """Write ``dataset.json`` (how the set was made)."""
    from planerel.io.writers import write_json

    return write_json(Path(out_dir) / INFO, info)


# ----------------------------------------------------------------------- reading


def _folder(path) -> Path:
    try:
        p = Path(path)
    except TypeError:
        raise InputError(f"expected a data-set folder, got {path!r}") from None
    if not p.exists():
        raise InputError(f"{p}: data-set folder does not exist")
    if not p.is_dir():
        raise InputError(f"{p}: a data set is a folder (with {MANIFEST}), not a file")
    return p


def load_manifest(path) -> tuple[ManifestRow, ...]:
    """Read ``manifest.csv`` of a data-set folder.

    Raises
    ------
    InputError
        The folder or manifest is missing, the header is wrong, a row is malformed.
    """
    folder = _folder(path)
    mf = folder / MANIFEST
    if not mf.is_file():
        raise InputError(f"{folder}: not a data set (no {MANIFEST}); make one with "
                         "'planerel dataset synth DIR'")
    try:
        text = mf.read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as exc:
        raise InputError(f"{mf}: cannot read the manifest ({exc})") from None
    reader = csv.reader(_io.StringIO(text))
    try:
        header = next(reader)
    except StopIteration:
        raise InputError(f"{mf}: the manifest is empty") from None
    if tuple(header) != MANIFEST_COLUMNS:
        raise InputError(f"{mf}: manifest header must be {','.join(MANIFEST_COLUMNS)}, "
                         f"got {','.join(header)}")
    rows = []
    for lineno, rec in enumerate(reader, start=2):
        if not rec:
            continue
        if len(rec) != len(MANIFEST_COLUMNS):
            raise InputError(f"{mf}: line {lineno} has {len(rec)} fields, expected "
                             f"{len(MANIFEST_COLUMNS)}")
        sid, klass, seed, w, h, depth, labels, meta = rec
        try:
            seed_v = int(seed) if seed.strip() else None
            w_v, h_v = int(w), int(h)
        except ValueError:
            raise InputError(f"{mf}: line {lineno}: seed, width and height must be integers, "
                             f"got {seed!r}, {w!r}, {h!r}") from None
        try:
            rows.append(ManifestRow(sid, klass, seed_v, w_v, h_v, depth, labels, meta))
        except InputError as exc:
            raise InputError(f"{mf}: line {lineno}: {exc}") from None
    ids = [r.scene_id for r in rows]
    if len(set(ids)) != len(ids):
        raise InputError(f"{mf}: duplicate scene ids")
    if not rows:
        raise InputError(f"{mf}: the manifest lists no scene")
    return tuple(rows)


def load_dataset_info(path) -> dict:
    """``dataset.json`` of a data-set folder, or ``{}`` when the set has none."""
    folder = _folder(path)
    p = folder / INFO
    if not p.is_file():
        return {}
    return read_json_object(p, "data-set description")


def _row(folder: Path, scene_id: str) -> ManifestRow:
    for r in load_manifest(folder):
        if r.scene_id == scene_id:
            return r
    raise InputError(f"{folder}: no scene {scene_id!r} in {MANIFEST}")


def load_metadata(path, scene_id: str) -> dict:
    """The JSON sidecar of one scene, checked: it must hold ``intrinsics``, ``depth_scale`` and a
    ``planes`` list whose entries have ``index``, ``id``, ``normal``, ``offset``, ``role``."""
    folder = _folder(path)
    row = _row(folder, scene_id)
    return _read_meta(folder / row.meta, row)


def _read_meta(p: Path, row: ManifestRow) -> dict:
    if not p.is_file():
        raise InputError(f"{p}: sidecar of scene {row.scene_id} is missing")
    meta = read_json_object(p, "scene sidecar")
    for key in ("intrinsics", "depth_scale"):
        if key not in meta:
            raise InputError(f"{p}: the scene sidecar lacks {key!r}")
    planes = meta.get("planes", [])
    if not isinstance(planes, list):
        raise InputError(f"{p}: 'planes' must be a list")
    for i, pl in enumerate(planes):
        if not isinstance(pl, dict) or any(k not in pl for k in ("index", "id", "normal", "offset", "role")):
            raise InputError(f"{p}: plane {i} must have index, id, normal, offset and role")
        if pl["index"] != i:
            raise InputError(f"{p}: plane {i} has index {pl['index']}; planes must be in index order")
    meta.setdefault("class", row.klass)
    meta.setdefault("scene_id", row.scene_id)
    return meta


def load_scene(path, scene_id: str):
    """Read one scene of a data set.

    Parameters
    ----------
    path : str or Path
        The data-set folder.
    scene_id : str
        ``s0007``.

    Returns
    -------
    cloud : Cloud
        ``(H, W, 3)`` with the sidecar's intrinsics and up vector; ``source`` is the depth file.
    labels : ndarray, shape (H, W), int32, or None
        Ground-truth plane index per pixel, -1 = none (None when the set has no labels).
    meta : dict
        The sidecar (class, pose, up, planes with normal/offset/role/object, params, ...).

    Raises
    ------
    InputError
        Missing folder, manifest, scene, file; a corrupt file; sizes that disagree.
    """
    folder = _folder(path)
    return _load_row(folder, _row(folder, scene_id))


def _load_row(folder: Path, row: ManifestRow):
    from planerel.io import readers as io

    scene_id = row.scene_id
    meta = _read_meta(folder / row.meta, row)
    depth_path = folder / row.depth
    if not depth_path.is_file():
        raise InputError(f"{depth_path}: depth image of scene {scene_id} is missing")
    cloud = io.read_depth_image(depth_path, intrinsics=meta["intrinsics"],
                                depth_scale=meta["depth_scale"], up=meta.get("up"))
    h, w = cloud.shape
    if (w, h) != (row.width, row.height):
        raise InputError(f"{depth_path}: image is {w}x{h} but {MANIFEST} says "
                         f"{row.width}x{row.height}")
    labels = None
    if row.labels:
        lp = folder / row.labels
        if not lp.is_file():
            raise InputError(f"{lp}: ground-truth labels of scene {scene_id} are missing")
        labels = io.read_label_image(lp)
        if labels.shape != (h, w):
            raise InputError(f"{lp}: label image is {labels.shape[1]}x{labels.shape[0]} but the "
                             f"depth image is {w}x{h}")
        n = len(meta.get("planes", []))
        if labels.size and labels.max() >= n:
            raise InputError(f"{lp}: label {int(labels.max())} but the sidecar lists {n} planes")
    return cloud, labels, meta


def load_object_labels(path, scene_id: str):
    """The per-pixel ground-truth object index of one scene, ``(H, W)`` int32 (0 = the
    environment, k = object k of the sidecar's ``objects``, -1 = none), from the scene's
    ``objects`` image (varied world) or else from its plane labels and the planes' objects.
    None when the scene has no ground truth."""
    from planerel.io import readers as io

    folder = _folder(path)
    row = _row(folder, scene_id)
    meta = _read_meta(folder / row.meta, row)
    name = (meta.get("files") or {}).get("objects")
    if name:
        p = folder / name
        if not p.is_file():
            raise InputError(f"{p}: object labels of scene {scene_id} are missing")
        lab = io.read_label_image(p)
        if lab.shape != (row.height, row.width):
            raise InputError(f"{p}: object image is {lab.shape[1]}x{lab.shape[0]} but "
                             f"{MANIFEST} says {row.width}x{row.height}")
        return lab
    if not row.labels:
        return None
    _cloud, labels, meta = _load_row(folder, row)
    obj = np.array([int(p.get("object_index", 0)) for p in meta.get("planes", [])] or [0],
                   dtype=np.int32)
    return np.where(labels >= 0, obj[np.maximum(labels, 0)], -1).astype(np.int32)


def object_classes(meta: dict, default: str | None = None) -> dict:
    """``{object index: class}`` of a scene's sidecar for its objects (index >= 1): from its
    ``objects`` list, else ``default`` (the scene's class) for every object its planes name."""
    out = {}
    for o in meta.get("objects") or []:
        try:
            k = int(o["index"])
        except (KeyError, TypeError, ValueError):
            continue
        if k >= 1 and o.get("class"):
            out[k] = str(o["class"])
    if not out:
        klass = default if default is not None else meta.get("class")
        for p in meta.get("planes", []):
            k = int(p.get("object_index", 0))
            if k >= 1 and klass:
                out[k] = klass
    return out


def describe_truth_scene(cloud, labels, gt, meta: dict, scene_id: str,
                         default_class: str | None = None, rule=None, far=()):
    """Describe one data-set scene with its ground-truth objects as the examples.

    Segmented (or ground-truth) planes join the ground-truth object whose planes they mostly
    cover (:func:`planerel.features.proposals.objects_from_truth`); every object gets its own class from
    the sidecar (:func:`object_classes`: ``box``, ``stairs``, ``ramp`` or ``other``), so a scene
    of the varied world gives one example per object.  An object whose planes do not let one
    decide its class (:func:`planerel.features.truth_examples.judge_objects`: planes not matching it,
    mostly hidden, a box showing one face, ...) keeps its planes but no class, and is listed
    in the description's ``excluded`` with the reason.

    Parameters
    ----------
    cloud : Cloud
    labels, gt : ndarray, shape (H, W), int
        Plane labels to describe (a segmentation or ``gt``) and the ground-truth plane labels.
    meta : dict
        The scene's sidecar.
    scene_id : str
    default_class : str, optional
        Class of the objects when the sidecar has no ``objects`` list (the manifest's class).
    rule : planerel.features.truth_examples.ExampleRule, optional
        Which objects are examples (default thresholds when None).
    far : iterable of int, optional
        The far growing's planes among ``labels`` (:func:`planerel.features.facts.describe_scene`'s
        ``far``: the up estimate reads the labels without them, as classify's does).

    Returns
    -------
    planerel.features.facts.SceneDescription
    """
    from dataclasses import replace

    from planerel.features.facts import describe_scene
    from planerel.features.proposals import objects_from_truth
    from planerel.features.truth_examples import judge_objects

    obj_of = {int(p["index"]): (int(p.get("object_index", 0)) if int(p.get("object_index", 0)) > 0 else -1)
              for p in meta.get("planes", [])}
    groups = objects_from_truth(labels, gt, obj_of)
    classes = object_classes(meta, default_class)
    lab = np.asarray(labels)
    gtl = np.asarray(gt)
    n = max(obj_of, default=-1) + 1
    obj_map = np.array([obj_of.get(k, -1) for k in range(n)] + [-1], dtype=np.int64)
    class_of_label = {}
    object_of_group = []
    for g in groups:
        mask = np.isin(lab, g) & (gtl >= 0)
        objs = obj_map[np.where(mask, np.minimum(gtl, n), n)[mask]]
        objs = objs[objs >= 0]
        k = int(np.bincount(objs).argmax()) if objs.size else -1
        object_of_group.append(k)
        for x in g:
            class_of_label[int(x)] = classes.get(k, default_class)
    verdict = judge_objects(lab, gtl, meta, groups, object_of_group,
                            {k: c for k, c in classes.items() if c}, rule)
    object_of_label = {}
    for g, k in zip(groups, object_of_group, strict=True):
        for x in g:
            object_of_label[int(x)] = k
            if verdict.get(k):
                class_of_label[int(x)] = None
    # a data set with side-face examples (ramp77) has its upright planes' top edges measured
    desc = describe_scene(cloud, labels, scene_id=scene_id, objects=groups, klass=default_class,
                          far=far, top_slope=bool(rule is not None and rule.side_faces))
    objs = tuple(replace(o, klass=class_of_label.get(o.planes[0], default_class))
                 for o in desc.objects)
    # the described object's id; an object none of whose planes was found has none
    described = {object_of_label.get(o.planes[0]): o.id for o in desc.objects}
    excluded = tuple((described.get(k), classes[k], why)
                     for k, why in sorted(verdict.items()) if why)
    return replace(desc, objects=objs, excluded=excluded)


def iter_scenes(path, klass: str | None = None):
    """Yield ``(row, cloud, labels, meta)`` for every scene (of one class when given),
    in manifest order."""
    folder = _folder(path)
    for row in load_manifest(folder):
        if klass is None or row.klass == klass:
            cloud, labels, meta = _load_row(folder, row)
            yield row, cloud, labels, meta
