"""Make a training data set (docs/formats.md, "Synthetic data sets") from your own frames and
pixel rectangles around their objects, for ``planerel learn`` and ``planerel export-aleph``.

    python examples/label_frames.py FRAMES_DIR OUT_DIR

``FRAMES_DIR/labels.json`` names the frames and their objects in the format of
docs/formats.md, "Hand-labelled real frames"::

    {"frames": [{"file": "desk1_depth.png", "intrinsics": "640,480,520.9,521.0,325.1,249.7",
                 "depth_scale": 5000,
                 "objects": [{"class": "box", "box": [x0, y0, x1, y1]}]}]}

(``intrinsics`` and ``depth_scale`` as ``--intrinsics`` and ``--depth-scale`` take them, or
left out when the frame has a sidecar, an OpenNI XML or is a cloud that carries its camera;
any class name works; a frame with no object is a scene of negatives only.)

Each frame is segmented with planerel's default region growing and its planes grouped into
object proposals as ``planerel describe`` groups them.  A proposal takes the class of the
rectangle that holds more than half of its pixels, every other proposal is class ``other``
(a negative of every class), and the planes nobody proposes (floor, walls) are the
environment.  Those planes become the scene's ground truth: ``sNNNN.gt.png`` (plane label + 1),
and in the sidecar each plane's normal, offset, object and role -- ``top``/``face`` for a box,
``tread``/``riser`` for stairs, ``slope`` for a ramp, from its orientation: ``planerel learn``
takes a box as an example only when two of its planes are a top or faces, stairs when two
treads or two risers are seen, a ramp when a slope is (docs/formats.md).  The depth is written
as a 16-bit PNG in millimetres with the camera in the sidecar, so any input format works.

Check the proposals before learning: ``labels.json``'s rectangles only name the proposals the
segmentation made.  A box whose planes are merged with what it stands on is not learned as a
box (``planerel learn`` prints how many objects it learned from and why it left any out).
"""

from __future__ import annotations

import argparse
import csv
import json
import re
import sys
from pathlib import Path

import numpy as np

#: The role of a plane by its orientation, per class (see the module docstring).
ROLES = {
    "box": {"horizontal": "top", "vertical": "face", "inclined": "face"},
    "stairs": {"horizontal": "tread", "vertical": "riser", "inclined": "side"},
    "ramp": {"horizontal": "top", "vertical": "side", "inclined": "slope"},
}


#: A class name: a lower-case Prolog atom (``box``, ``stairs``, ``ramp`` or one of yours);
#: ``Box`` would be a class of its own and a Prolog variable
CLASS_NAME = re.compile(r"[a-z][a-z0-9_]*")


def check_frames(frames: list, folder: Path) -> None:
    """Refuse, before anything is written, a ``labels.json`` whose frames or objects are not
    what :func:`label_frame` needs: a missing frame file, a class that is not a lower-case
    Prolog atom (``"Box"``), a rectangle that is not four numbers ``x0 < x1``, ``y0 < y1``
    (user89: each passed in silence, or failed after part of the data set was written)."""
    from planerel.errors import InputError

    for n, f in enumerate(frames):
        where = f"labels.json frame {n}"
        if not isinstance(f, dict) or not isinstance(f.get("file"), str):
            raise InputError(f"{where}: needs a 'file'")
        if not (folder / f["file"]).is_file():
            raise InputError(f"{where}: {folder / f['file']}: no such file")
        objects = f.get("objects") or []
        if not isinstance(objects, list):
            raise InputError(f"{where} ({f['file']}): 'objects' must be a list")
        for o in objects:
            klass = o.get("class") if isinstance(o, dict) else None
            if not isinstance(klass, str) or not CLASS_NAME.fullmatch(klass):
                raise InputError(f"{where} ({f['file']}): class {klass!r} is not a lower-case "
                                 "name (box, stairs, ramp, or one of yours: a-z, 0-9, _)")
            box = o.get("box")
            ok = (isinstance(box, list) and len(box) == 4
                  and all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in box))
            if not ok or not (box[0] < box[2] and box[1] < box[3]):
                raise InputError(f"{where} ({f['file']}): {klass} rectangle {box!r} is not "
                                 "[x0, y0, x1, y1] with x0 < x1 and y0 < y1 (pixels)")


def _class_of(mask: np.ndarray, objects: list) -> str:
    """The class of the labelled rectangle holding more than half of ``mask``'s pixels."""
    n = int(mask.sum())
    for o in objects:
        x0, y0, x1, y1 = (int(v) for v in o["box"])
        if n and mask[max(0, y0):y1, max(0, x0):x1].sum() > 0.5 * n:
            return str(o["class"])
    return "other"


def label_frame(path: Path, frame: dict, scene_id: str, out: Path) -> list:
    """Write one scene of the data set; returns its manifest row."""
    import planerel
    from planerel.errors import InputError
    from planerel.io.writers import write_depth_png, write_json

    cloud = planerel.read(path, intrinsics=frame.get("intrinsics"),
                          depth_scale=frame.get("depth_scale"), up=frame.get("up"))
    if cloud.intrinsics is None or not cloud.organized:
        raise InputError(f"{path}: no camera: give the frame's intrinsics in labels.json")
    h, w = cloud.shape
    for o in frame.get("objects") or []:
        x0, y0, x1, y1 = o["box"]
        if x1 <= 0 or y1 <= 0 or x0 >= w or y0 >= h:
            raise InputError(f"{path}: the {o['class']} rectangle {o['box']} lies outside the "
                             f"{w}x{h} image")
    labels = planerel.segment(cloud).labels
    desc = planerel.describe(cloud, labels, scene_id=scene_id)
    objects = [{"index": 0, "id": f"{scene_id}_o0", "class": "environment"}]
    object_of, class_of = {}, {}
    for k, o in enumerate(desc.objects, start=1):
        klass = _class_of(np.isin(labels, o.planes), frame.get("objects") or [])
        objects.append({"index": k, "id": f"{scene_id}_o{k}", "class": klass})
        for p in o.planes:
            object_of[p], class_of[p] = k, klass
    for o in frame.get("objects") or []:
        if not any(_class_of(np.isin(labels, d.planes), [o]) == o["class"]
                   for d in desc.objects):
            print(f"note: {path}: no proposal lies mostly in the {o['class']} rectangle "
                  f"{o['box']}: that object is not learned (its planes are merged with what it "
                  "touches, or it has none; check the segmentation)", file=sys.stderr)
    planes = []
    for p in desc.planes:
        role = ROLES.get(class_of.get(p.label, ""), {}).get(p.orientation, "surface")
        planes.append({"index": int(p.label), "id": f"{scene_id}_p{p.label:02d}",
                       "normal": [float(v) for v in p.normal], "offset": float(p.offset),
                       "role": role, "object_index": object_of.get(p.label, 0),
                       "n_pixels": int((labels == p.label).sum())})
    known = {int(p.label) for p in desc.planes}
    gt = np.where(np.isin(labels, list(known)), labels + 1, 0).astype(np.uint16)
    depth = np.nan_to_num(np.asarray(cloud.depth), nan=0.0) * 1000.0
    depth[(depth < 0) | (depth > 65534)] = 0
    write_depth_png(out / f"{scene_id}.depth.png", depth)
    from PIL import Image

    Image.fromarray(gt).save(out / f"{scene_id}.gt.png")
    named = [o["class"] for o in objects[1:] if o["class"] != "other"]
    klass = named[0] if named else "other"
    i = cloud.intrinsics
    meta = {"scene_id": scene_id, "class": klass, "source": str(path),
            "intrinsics": i.to_dict(), "depth_scale": 1000, "objects": objects,
            "planes": planes, "files": {"depth": f"{scene_id}.depth.png",
                                        "labels": f"{scene_id}.gt.png"}}
    if cloud.up is not None:
        meta["up"] = [float(v) for v in cloud.up]
    write_json(out / f"{scene_id}.json", meta)
    h, w = labels.shape
    print(f"{path}: {scene_id}: {len(desc.planes)} planes, proposals "
          + (", ".join(f"{o['id']} {o['class']}" for o in objects[1:]) or "none"))
    return [scene_id, klass, 0, w, h, f"{scene_id}.depth.png", f"{scene_id}.gt.png",
            f"{scene_id}.json"]


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("frames", type=Path, help="folder holding the frames and labels.json")
    ap.add_argument("out", type=Path, help="data-set folder to write (must not exist)")
    args = ap.parse_args(argv)
    from planerel.errors import PlanerelError
    from planerel.io.readers import read_json_object

    try:
        spec = read_json_object(args.frames / "labels.json", "labels file")
        frames = spec.get("frames")
        if not isinstance(frames, list) or not frames:
            raise PlanerelError(f"{args.frames / 'labels.json'}: no 'frames' list")
        if args.out.exists():
            raise PlanerelError(f"{args.out}: exists; give a new folder")
        check_frames(frames, args.frames)
        from planerel.atomic import atomic_dir

        # the data set appears whole or not at all: a frame that fails leaves no folder
        with atomic_dir(args.out) as tmp:
            rows = [label_frame(args.frames / f["file"], f, f"s{n:04d}", tmp)
                    for n, f in enumerate(frames)]
            with open(tmp / "manifest.csv", "w", newline="") as fh:
                w = csv.writer(fh)
                w.writerow(["scene_id", "class", "seed", "width", "height", "depth", "labels",
                            "meta"])
                w.writerows(rows)
            (tmp / "dataset.json").write_text(json.dumps(
                {"format": "examples/label_frames.py", "source": str(args.frames)},
                indent=1) + "\n")
    except PlanerelError as exc:
        print(f"label_frames: error: {exc}", file=sys.stderr)
        return 2
    print(f"{len(rows)} scenes -> {args.out} (planerel dataset info {args.out}; "
          f"planerel learn {args.out} -o MODEL)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
