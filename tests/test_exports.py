"""Outputs other tools open, read back with independent readers: labelled PCD (pypcd4),
coloured PLY (plyfile, trimesh), plane meshes (trimesh), scene graphs (networkx), and the
explanation image (>= 640 px wide, with a legend)."""

from __future__ import annotations

import json

import networkx as nx
import numpy as np
import pytest
import trimesh
from plyfile import PlyData, PlyElement
from pypcd4 import PointCloud

from planerel.cli import main
from planerel.io.writers import label_colours


@pytest.fixture(scope="module")
def scenes(tmp_path_factory):
    d = tmp_path_factory.mktemp("set")
    assert main(["dataset", "synth", str(d), "--n-box", "0", "--n-stairs", "1", "--n-ramp", "1",
                 "--seed", "5", "--quiet"]) == 0
    return d


def _pcd_fields(path):
    pc = PointCloud.from_path(str(path))
    return pc, {name: pc.pc_data[name] for name in pc.fields}


def test_segment_writes_labelled_pcd_and_coloured_ply(scenes, tmp_path):
    out = tmp_path / "seg"
    scan = scenes / "s0000.depth.png"
    assert main(["segment", str(scan), "-o", str(out)]) == 0
    labels = np.load(out / "s0000.labels.npy")
    h, w = labels.shape
    from planerel.io import readers as io

    xyz = io.read(scan).xyz
    pc, f = _pcd_fields(out / "s0000.pcd")
    assert list(pc.fields) == ["x", "y", "z", "rgb", "label"]
    assert (pc.metadata.width, pc.metadata.height) == (w, h)  # organized, NaN points kept
    got = np.stack([f["x"], f["y"], f["z"]], axis=-1).reshape(h, w, 3)
    assert np.allclose(got, xyz.astype(np.float32), equal_nan=True)
    assert np.array_equal(f["label"].reshape(h, w), np.where(labels >= 0, labels + 1, 0))
    # a depth image has no colours: the PCD's rgb is the plane colours (PCL packing 0x00RRGGBB)
    rgb = PointCloud.decode_rgb(f["rgb"]).reshape(h, w, 3)
    pal = label_colours(labels.max() + 1)
    on = labels >= 0
    assert np.array_equal(rgb[on], pal[labels[on]])
    # PLY: valid points only, coloured by plane, with the label
    v = PlyData.read(str(out / "s0000.ply"))["vertex"].data
    valid = np.isfinite(xyz).all(axis=2)
    assert len(v) == valid.sum()
    lab = labels[valid]
    assert np.array_equal(v["label"], lab)
    cols = np.stack([v["red"], v["green"], v["blue"]], axis=-1)
    assert np.array_equal(cols[lab >= 0], pal[lab[lab >= 0]])
    assert np.all(cols[lab < 0] == 128)
    m = trimesh.load(out / "s0000.ply")  # a second reader agrees on points and colours
    assert len(m.vertices) == valid.sum()
    assert np.array_equal(np.asarray(m.colors)[:, :3], cols)
    assert main(["segment", str(scan), "-o", str(tmp_path / "few"), "--formats", "npy"]) == 0
    assert [p.name for p in (tmp_path / "few").iterdir()] == ["s0000.labels.npy"]
    assert main(["segment", str(scan), "-o", str(tmp_path / "x"), "--formats", "las"]) == 2


def test_input_colours_are_kept_in_segment_and_convert(tmp_path):
    """An organized coloured PCD written by pypcd4 keeps its colours through both commands."""
    h, w = 24, 32
    v, u = np.mgrid[0:h, 0:w].astype(np.float32)
    z = np.full((h, w), 1.5, np.float32)
    x, y = (u - 15.5) * z / 30.0, (v - 11.5) * z / 30.0
    colours = np.stack([u * 7 % 256, v * 11 % 256, (u + v) % 256], axis=-1).astype(np.uint8)
    rgb = PointCloud.encode_rgb(colours.reshape(-1, 3))
    pts = np.column_stack([x.ravel(), y.ravel(), z.ravel(), rgb])
    pc = PointCloud.from_points(pts, ("x", "y", "z", "rgb"), (np.float32,) * 4)
    pc.metadata.width, pc.metadata.height = w, h
    pc.save(str(tmp_path / "wall.pcd"))
    assert main(["segment", str(tmp_path / "wall.pcd"), "-o", str(tmp_path / "seg")]) == 0
    _, f = _pcd_fields(tmp_path / "seg" / "wall.pcd")
    assert np.array_equal(PointCloud.decode_rgb(f["rgb"]).reshape(h, w, 3), colours)
    assert main(["convert", str(tmp_path / "wall.pcd"), "-o", str(tmp_path / "c.pcd")]) == 0
    pc2, f2 = _pcd_fields(tmp_path / "c.pcd")
    assert list(pc2.fields) == ["x", "y", "z", "rgb"] and pc2.metadata.height == h
    assert np.array_equal(PointCloud.decode_rgb(f2["rgb"]).reshape(h, w, 3), colours)
    assert np.allclose(f2["z"], 1.5)
    assert main(["convert", str(tmp_path / "wall.pcd"), "-o", str(tmp_path / "c.ply")]) == 0
    vv = PlyData.read(str(tmp_path / "c.ply"))["vertex"].data
    assert np.array_equal(np.stack([vv["red"], vv["green"], vv["blue"]], -1),
                          colours.reshape(-1, 3))
    # a coloured PLY input keeps its colours in a PCD
    arr = np.empty(3, dtype=[("x", "f4"), ("y", "f4"), ("z", "f4"), ("red", "u1"),
                             ("green", "u1"), ("blue", "u1")])
    arr["x"], arr["y"], arr["z"] = [0, 1, 0], [0, 0, 1], [2, 2, 2]
    arr["red"], arr["green"], arr["blue"] = [255, 0, 0], [0, 255, 0], [0, 0, 255]
    PlyData([PlyElement.describe(arr, "vertex")]).write(str(tmp_path / "tri.ply"))
    assert main(["convert", str(tmp_path / "tri.ply"), "-o", str(tmp_path / "tri.pcd"),
                 "--no-organize"]) == 0
    _, f3 = _pcd_fields(tmp_path / "tri.pcd")
    assert PointCloud.decode_rgb(f3["rgb"]).tolist() == [[255, 0, 0], [0, 255, 0], [0, 0, 255]]
    # put on an image grid (the default, planerel.io.organize): each colour stays with its point
    assert main(["convert", str(tmp_path / "tri.ply"), "-o", str(tmp_path / "grid.pcd")]) == 0
    _, f4 = _pcd_fields(tmp_path / "grid.pcd")
    seen = np.isfinite(f4["z"])
    got = {(float(x), float(y)): c for x, y, c in zip(f4["x"][seen], f4["y"][seen],
                                                      PointCloud.decode_rgb(f4["rgb"][seen]).tolist(),
                                                      strict=True)}
    assert got == {(0.0, 0.0): [255, 0, 0], (1.0, 0.0): [0, 255, 0], (0.0, 1.0): [0, 0, 255]}


@pytest.mark.parametrize("fmt", ["ply", "glb"])
def test_describe_mesh_one_colour_per_plane_on_the_planes(scenes, tmp_path, fmt):
    from planerel.features.facts import describe_scene
    from planerel.io import readers as io
    from planerel.segment import segment

    scan = scenes / "s0001.depth.png"
    assert main(["describe", str(scan), "-o", str(tmp_path / "f.pl"), "--mesh", str(tmp_path),
                 "--mesh-format", fmt]) == 0
    cloud = io.read(scan)
    desc = describe_scene(cloud, segment(cloud).labels, scene_id="s0001")
    loaded = trimesh.load(tmp_path / f"s0001.planes.{fmt}", process=False)
    mesh = loaded.to_geometry() if isinstance(loaded, trimesh.Scene) else loaded
    polys = [np.asarray(p.hull3d) for p in desc.planes if len(p.hull3d) >= 3]
    assert len(mesh.faces) == sum(len(q) - 2 for q in polys)
    cols = np.asarray(mesh.visual.vertex_colors)[:, :3]
    pal = label_colours(max(p.label for p in desc.planes) + 1)
    start = 0
    for p in desc.planes:
        k = len(p.hull3d)
        if k < 3:
            continue
        vs = mesh.vertices[start:start + k]
        # every vertex of a plane's polygon lies on that plane, in that plane's colour
        assert np.abs((vs - p.centroid) @ p.normal).max() < 1e-4
        assert np.all(cols[start:start + k] == pal[p.label])
        start += k


def test_describe_graph_graphml_and_json(scenes, tmp_path):
    from planerel.features.facts import describe_scene
    from planerel.io import readers as io
    from planerel.segment import segment

    scan = scenes / "s0000.depth.png"
    for fmt in ("graphml", "json"):
        assert main(["describe", str(scan), "-o", str(tmp_path / "f.pl"), "--graph",
                     str(tmp_path), "--graph-format", fmt]) == 0
    cloud = io.read(scan)
    desc = describe_scene(cloud, segment(cloud).labels, scene_id="s0000")
    g1 = nx.read_graphml(tmp_path / "s0000.graphml")
    g2 = nx.node_link_graph(json.loads((tmp_path / "s0000.json").read_text()), edges="links")
    for g in (g1, g2):
        assert set(g.nodes) == {desc.plane_id(p.label) for p in desc.planes}
        assert g.number_of_edges() == len(desc.relations.pairs)
        for r in desc.relations:
            e = g.edges[desc.plane_id(r.a), desc.plane_id(r.b)]
            assert e["angle"] == pytest.approx(r.angle) and e["adjacent"] == r.adjacent
            assert e["rise"] == pytest.approx(r.rise) and e["above"] == r.above
            assert e["skirt"] == r.skirt and e["corner"] == r.corner
            assert e["facing"] == r.facing
        for p in desc.planes:
            node = g.nodes[desc.plane_id(p.label)]
            assert node["orientation"] == p.orientation
            assert node["area"] == pytest.approx(p.area)
        assert g.graph["scene"] == "s0000"


def test_explanation_image_is_wide_with_a_legend(scenes, tmp_path):
    from PIL import Image

    from planerel.classify.classifier import Classifier
    from planerel.classify.explain_render import binding_colours

    rules = tmp_path / "rules.pl"
    rules.write_text("ramp(A) :- has_plane(A, B), orientation(B, inclined).\n")
    out = tmp_path / "cls"
    scan = scenes / "s0001.depth.png"  # the ramp scene, 160x120
    assert main(["classify", str(rules), str(scan), "-o", str(out)]) == 0
    img = np.asarray(Image.open(out / "s0001.classified.png").convert("RGB"))
    assert img.shape[1] >= 640
    pic_h = 480  # 160x120 scaled by 4 to 640x480
    assert img.shape[0] > pic_h + 40  # a legend below the picture
    from planerel.io import readers as io

    with Classifier(rules) as clf:
        ans = clf.classify(io.read(scan), scene_id="s0001")
    (obj,) = [o for o in ans.objects if o.klass == "ramp"]
    swatch = binding_colours(ans)[(ans.objects.index(obj), obj.proof_planes[0])]
    legend = img[pic_h:]
    assert np.any(np.all(legend == swatch, axis=-1))  # the inclined plane's swatch


def test_a_rule_binding_no_plane_still_shows_its_object(scenes, tmp_path):
    """user89: a rule on the object alone (``nplanes(A,N)``) proves no plane; the picture
    colours the object's planes, the legend says so, and a number bound to a variable is a
    number in the JSON."""
    from PIL import Image

    from planerel.classify.explain_render import binding_colours, legend_rows, shown_planes

    rules = tmp_path / "rules.pl"
    rules.write_text("ramp(A) :- ninclined(A, B), gteq(B, 1).\n")
    out = tmp_path / "cls"
    scan = scenes / "s0001.depth.png"  # the ramp scene, 160x120
    assert main(["classify", str(rules), str(scan), "-o", str(out), "--json"]) == 0
    doc = json.loads((out / "s0001.classified.json").read_text())
    (obj,) = [o for o in doc["objects"] if o["class"] == "ramp"]
    assert obj["proof_planes"] == [] and obj["planes"]
    assert isinstance(obj["bindings"]["B"], int) and obj["bindings"]["B"] >= 1
    from planerel.classify.classifier import Classifier
    from planerel.io import readers as io

    with Classifier(rules) as clf:
        ans = clf.classify(io.read(scan), scene_id="s0001")
    n, o = next((n, o) for n, o in enumerate(ans.objects) if o.klass == "ramp")
    assert shown_planes(o) == tuple(o.planes)
    from planerel.classify.explain_render import _picture

    pic = _picture(ans, io.read(scan).depth).astype(float)
    for label, pid in zip(o.labels, o.planes, strict=True):
        swatch = np.array(binding_colours(ans)[(n, pid)], float)
        mean = pic[np.asarray(ans.labels) == label].mean(axis=0)
        # 0.75 of the plane's colour over the shading: within a quarter of the range
        assert np.all(np.abs(mean - swatch) < 0.25 * 255 + 1), (pid, mean, swatch)
    legend = [t for t, _ in legend_rows(ans)]
    assert any("binds no plane" in t for t in legend)
    assert (out / "s0001.classified.png").exists()
    Image.open(out / "s0001.classified.png").verify()


def test_the_legend_says_what_the_text_says_of_a_refused_object():
    """user89: the text said "refused box: planar fraction ..." while the picture said "no
    rule fires"; the legend now gives the refusal in the text's words, and the objects no
    rule proves share one line instead of one each (38 lines on a room frame)."""
    from planerel.classify.classifier import ObjectAnswer, SceneAnswer
    from planerel.classify.explain_render import explanation_picture, legend_rows
    from planerel.ilp.metrics import Refusal

    refusal = Refusal("box", 0.37, 0.9, 1.0, 0.2)
    refused = ObjectAnswer("s_o1", ("s_p01",), (1,), "other", fired=(("box", 4),),
                           refused=(refusal,))
    quiet = [ObjectAnswer(f"s_o{k}", (f"s_p0{k}",), (k,), "other") for k in (2, 3, 4)]
    labels = np.array([[0, 1], [2, 3], [4, 4]])
    ans = SceneAnswer(source=None, scene_id="s", labels=labels,
                      plane_ids={k: f"s_p0{k}" for k in range(5)},
                      objects=(refused, *quiet), up_source="given", seconds=0.0)
    text = [t for t, _ in legend_rows(ans)]
    assert text[0] == "s_o1: other"
    assert any(t.strip() == f"refused box: {refusal.reason}" for t in text)
    assert not any("no rule fires" in t and "s_o1" in t for t in text)
    assert text[-1] == "s_o2, s_o3, s_o4: other, no rule fires (planes tinted blue-grey)"
    img = explanation_picture(ans, np.ones((3, 2)))
    assert img.ndim == 3 and img.shape[1] >= 640
