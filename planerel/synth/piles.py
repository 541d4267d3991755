"""The training world's pile part: cartons packed side by side in a pile of two heights.

Issue 16 names "touching boxes of two heights become stairs": a pallet of cartons seen from
above (the real RealSense frames of ``smart_palletizer``, docs/objects.md "Carton piles and
false answers on unseen frames", pile26) is two levels of merged carton tops, one above the
other, which every stairs rule of the demo's model took for a step.  The training world had
boxes standing apart only.  This part draws piles of touching cartons as one object of class
``box``: a proposal covering several touching cartons is a box (the pile is what a robot
picks from or drives around; the cartons of one height merge into one top to any depth-only
segmentation, so a proposal cannot be split into its cartons).

A pile (:data:`PILE_SETTINGS`) is a grid of ``rows x cols`` cartons of one footprint, packed
with gaps of at most a few millimetres, in two heights: a low level and a high level one
carton height or a taller carton's difference above it.  The high cartons are either whole
rows (the front rows two cartons high, the back row one: the real pallet's layout) or one
corner block.  Seen from a camera looking down at it (40-90 degrees) from 1.1-2.4 m above the
floor, as a palletising robot's or a person's.
"""

from __future__ import annotations

from planerel.errors import InputError

__all__ = ["PILE_SETTINGS", "pile_geometry", "generate_pile_scene"]

#: Ranges of the pile part (metres, degrees): camera height above the floor and pitch down,
#: distance from the camera to the pile's centre, carton footprint (length, width), carton
#: height, rows and columns of the grid, the high level's rise over the low one as a multiple
#: of the carton height (1: stacked two high) or an absolute rise (a taller carton), and the
#: widest gap between touching cartons.
PILE_SETTINGS = {
    "camera": (1.1, 2.4),
    "pitch": (40.0, 90.0),
    "distance": (1.2, 2.6),
    "length": (0.25, 0.5),
    "width": (0.2, 0.4),
    "height": (0.12, 0.4),
    "rows": (2, 4),
    "cols": (2, 4),
    "taller": (0.06, 0.3),
    "stacked_share": 0.5,
    "gap": (0.0, 0.006),
}


def pile_geometry(rows: int, cols: int, length: float, width: float, heights, *,
                  gap: float = 0.0, object_index: int = 1):
    """Cartons on a ``rows x cols`` grid, each an axis-aligned cuboid standing on z = 0 with its
    own height, centred on the local origin.

    Parameters
    ----------
    rows, cols : int
        Grid size (rows along local y, columns along local x).
    length, width : float
        Carton footprint along x and y, metres.
    heights : (rows, cols) array_like of float
        Each carton's height (a stack of cartons is one cuboid: the seam between them is no
        depth edge).
    gap : float
        Space between neighbouring cartons, metres (0: touching).
    object_index : int

    Returns
    -------
    planerel.synth.geometry.Geometry
        Tops (role ``top``) and side faces (role ``face``) of every carton.
    """
    import numpy as np

    from planerel.synth import geometry as sg

    h = np.asarray(heights, float)
    if h.shape != (int(rows), int(cols)) or not np.all(np.isfinite(h)) or np.any(h <= 0):
        raise InputError(f"pile heights must be a ({rows}, {cols}) array of positive numbers, "
                         f"got {np.asarray(heights).tolist()!r}")
    if not (length > 0 and width > 0 and gap >= 0):
        raise InputError(f"pile cartons need a positive length and width and a gap >= 0, got "
                         f"{length!r}, {width!r}, {gap!r}")
    b = sg._Builder(object_index)
    x_span, y_span = cols * length + (cols - 1) * gap, rows * width + (rows - 1) * gap
    for i in range(rows):
        y0 = -y_span / 2 + i * (width + gap)
        for j in range(cols):
            x0 = -x_span / 2 + j * (length + gap)
            sg._cuboid(b, x0, x0 + length, y0, y0 + width, 0.0, float(h[i, j]))
    return b.build()


def _draw_pile(rng):
    """A pile's grid, carton size and heights (:data:`PILE_SETTINGS`) and its params."""
    import numpy as np

    s = PILE_SETTINGS
    rows = int(rng.integers(s["rows"][0], s["rows"][1] + 1))
    cols = int(rng.integers(s["cols"][0], s["cols"][1] + 1))
    length, width = float(rng.uniform(*s["length"])), float(rng.uniform(*s["width"]))
    low = float(rng.uniform(*s["height"]))
    stacked = bool(rng.random() < s["stacked_share"])
    high = 2 * low if stacked else low + float(rng.uniform(*s["taller"]))
    heights = np.full((rows, cols), low)
    if rng.random() < 0.5:  # whole rows high (the front rows of the real pallet)
        k = int(rng.integers(1, rows))
        heights[k:, :] = high
    else:  # one corner block high
        a, c = int(rng.integers(1, rows + 1)), int(rng.integers(1, cols + 1))
        if a == rows and c == cols:
            c = cols - 1 if cols > 1 else c
            a = rows - 1 if c == cols else a
        heights[:a, :c] = high
    gap = float(rng.uniform(*s["gap"]))
    params = {"rows": rows, "cols": cols, "length": length, "width": width, "low": low,
              "high": high, "stacked": stacked, "gap": gap, "height": high,
              "layout": heights.tolist()}
    return pile_geometry(rows, cols, length, width, heights, gap=gap), params


def generate_pile_scene(seed: int, size=(640, 480), subsample: int = 4, *,
                        scene_id: str = "s0000", sensor=None, min_object_fraction: float = 0.03):
    """One scene of the pile part: a pile of touching cartons of two heights (object 1, class
    ``box``) on the floor, seen from above by the Kinect-like sensor.

    Drawn again until the pile covers ``min_object_fraction`` of the image.  Returns a
    :class:`planerel.synth.generator.Scene` as :func:`planerel.synth.world.generate_world_scene`
    does; its object's ``params`` hold the grid, the carton size and both heights.
    """
    import numpy as np

    from planerel.synth import geometry as sg
    from planerel.synth import world as sw
    from planerel.synth.generator import _scene_setup
    from planerel.synth.sensor import StructuredLight

    seed, w, h, intr = _scene_setup("box", seed, size, subsample)
    sensor = StructuredLight() if sensor is None else sensor
    rng = np.random.default_rng(seed)
    s = PILE_SETTINGS
    for _attempt in range(300):
        cam_h = float(rng.uniform(*s["camera"]))
        pitch = float(rng.uniform(*s["pitch"]))
        pose = sw._camera_pose(cam_h, pitch, float(rng.uniform(-10, 10)))
        anchor = sw._floor_point(rng, pose, intr, *s["distance"], region=(0.35, 0.65, 0.35, 0.75))
        if anchor is None:
            continue
        geom, params = _draw_pile(rng)
        yaw = float(rng.uniform(-180, 180))
        lay = sw._Layout()
        lay.add(sg.place(geom, yaw, anchor[:2], 0.0),
                {"class": "box", "kind": "carton pile", "params": params},
                sw._place_fp(sw._footprint(geom), yaw, anchor))
        parts = [sg.floor_geometry(10.0)]
        infos = [{"index": 0, "id": f"{scene_id}_o0", "class": "environment", "kind": "floor"}]
        sw._add_objects(parts, infos, lay, scene_id)
        world = sg.combine(*parts)
        scene_params = {"world": "pile", "camera": {"height": cam_h, "pitch_deg": pitch},
                        "size": [w, h], "subsample": int(subsample)}
        scene = sw.render_box_scene(world, pose, intr, sensor, rng, infos, scene_params,
                                    scene_id=scene_id, seed=seed,
                                    min_object_fraction=min_object_fraction)
        if scene is not None:
            return scene
    raise InputError(f"could not make a carton-pile scene (seed {seed})")
