"""Defects a new user met (docs/robustness.md, "New-user walkthrough, 2026-11-28").

Each test runs the real command line (``planerel.cli.main`` or a subprocess): a bad option or
output path must fail at once, in one line through the exception hierarchy, naming what the
user typed, before any scan is read and without writing anything.
"""

from __future__ import annotations

import subprocess
import sys

import numpy as np
import pytest

from planerel.cli import main
from planerel.synth import generate_scene


def _run(*args, cwd=None):
    return subprocess.run([sys.executable, "-m", "planerel.cli", *map(str, args)],
                          capture_output=True, text=True, timeout=300, cwd=cwd)


def _one_error_line(r, *needles):
    assert r.returncode == 2, (r.returncode, r.stderr)
    err = [ln for ln in r.stderr.splitlines() if ln.strip()]
    assert len(err) == 1 and "Traceback" not in r.stderr, r.stderr
    for n in needles:
        assert n in err[0], err[0]
    return err[0]


@pytest.fixture(scope="module")
def scan(tmp_path_factory):
    """A small real scene (a box, 80x60) as an XYZ .npy: segmented in well under a second."""
    d = tmp_path_factory.mktemp("scan")
    path = d / "box.npy"
    np.save(path, np.asarray(generate_scene("box", seed=1, subsample=8).cloud.xyz))
    return path


@pytest.mark.parametrize("option, value, needle", [
    ("--subsample", "0", "--subsample must be a positive whole number"),
    ("--subsample", "-2", "--subsample must be a positive whole number"),
    ("--depth-scale", "-1000", "--depth-scale must be a positive number"),
    ("--max-points", "0", "--max-points must be a positive whole number"),
    ("--intrinsics", "1,2,3", "--intrinsics must be 'kinect' or W,H,fx,fy,cx,cy"),
])
def test_bad_reading_option_is_one_error_about_the_option(scan, tmp_path, option, value, needle):
    # before: --subsample 0 was taken as 1 without a word, and the other values failed every
    # input in turn, each message ending "(--keep-going goes on past bad inputs)" (which would
    # only have skipped every input)
    for cmd in (["segment", scan, "-o", tmp_path / "seg"],
                ["describe", scan, "-o", tmp_path / "f.pl"],
                ["convert", scan, "-o", tmp_path / "x.npy"]):
        line = _one_error_line(_run(*cmd, option, value), needle)
        assert "--keep-going" not in line
    assert not list(tmp_path.rglob("*.*")), list(tmp_path.rglob("*"))


def test_describe_to_a_folder_fails_before_any_work(scan, tmp_path, capsys):
    # before: the scan was segmented and described, then the rename onto the folder failed
    # with a message naming a hidden temporary file (".o.k2q88u2f.pl -> o: Is a directory")
    (tmp_path / "out").mkdir()
    assert main(["describe", str(scan), "-o", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err
    assert "-o " in err and "is a folder; give a file name" in err
    assert "planes" not in err and ".tmp" not in err and err.count("\n") == 1
    assert list((tmp_path / "out").iterdir()) == []
    # an empty name was "Device or resource busy" about "..kkztnyzq.pl -> ."
    r = _run("describe", scan, "-o", "", cwd=tmp_path)
    _one_error_line(r, "-o needs a file name")


def test_output_file_inside_a_file_or_unwritable_folder(scan, tmp_path):
    blocker = tmp_path / "a_file"
    blocker.write_text("x")
    _one_error_line(_run("describe", scan, "-o", blocker / "f.pl"), "is a file, not a folder")
    _one_error_line(_run("convert", scan, "-o", "/proc/planerel-test.npy"), "cannot write in /proc")
    assert blocker.read_text() == "x"


def test_induce_rules_to_a_folder_fails_before_learning(tmp_path):
    from pathlib import Path

    stem = Path(__file__).parent / "ilp" / "trains"
    (tmp_path / "rules").mkdir()
    r = _run("induce", stem, "--rules", tmp_path / "rules")
    _one_error_line(r, "--rules", "is a folder; give a file name")
    assert "accuracy" not in r.stdout  # refused before the learning run, not after


def test_evaluate_objects_json_to_a_folder(tmp_path):
    (tmp_path / "j").mkdir()
    ds = tmp_path / "ds"
    assert main(["dataset", "synth", str(ds), "--n-box", "1", "--n-stairs", "0", "--n-ramp", "0",
                 "--subsample", "8", "--quiet"]) == 0
    r = _run("evaluate-objects", ds, "--json", tmp_path / "j")
    _one_error_line(r, "--json", "is a folder; give a file name")
    assert r.stdout == ""


def test_classify_output_that_is_a_file(scan, tmp_path):
    # before: "cannot create folder ...: File exists (--keep-going goes on past bad inputs)",
    # raised per scan after the model was loaded
    blocker = tmp_path / "out"
    blocker.write_text("x")
    rules = tmp_path / "rules.pl"
    rules.write_text("box(A) :- nvertical(A, B), B >= 2.\n")
    r = _run("classify", rules, scan, "-o", blocker)
    _one_error_line(r, "-o", "exists and is not a folder")
    assert "--keep-going" not in r.stderr


def test_convert_refuses_an_all_nan_cloud(tmp_path):
    # before: an all-NaN cloud was written as a PLY with 0 points and exit status 0
    np.save(tmp_path / "nan.npy", np.full((6, 8, 3), np.nan))
    r = _run("convert", tmp_path / "nan.npy", "-o", tmp_path / "x.ply")
    _one_error_line(r, "nan.npy", "no valid point")
    assert not (tmp_path / "x.ply").exists()


def test_learn_bad_segmentation_parameter_fails_once_up_front(tmp_path):
    # before: every scene failed in turn ("scene s0000: unknown parameter(s) ...") and the
    # message advised --keep-going, which learn does not have; --method gt ignored --param
    ds = tmp_path / "ds"
    assert main(["dataset", "synth", str(ds), "--n-box", "1", "--n-stairs", "1", "--n-ramp", "1",
                 "--subsample", "8", "--quiet"]) == 0
    cache = tmp_path / "cache"
    r = _run("learn", ds, "-o", tmp_path / "m", "--param", "nosuch=1", "--cache", cache)
    line = _one_error_line(r, "unknown parameter(s) nosuch")
    assert "--keep-going" not in line and "scene s0000" not in line
    _one_error_line(_run("learn", ds, "-o", tmp_path / "m", "--param", "split=maybe"),
                    "split must be true or false")
    _one_error_line(_run("learn", ds, "-o", tmp_path / "m", "--method", "gt", "--param",
                         "theta=5"), "do not apply to the ground-truth planes")
    assert not (tmp_path / "m").exists() and not cache.exists()


def test_batch_hint_only_for_commands_with_keep_going():
    from planerel.batch import run_batch
    from planerel.errors import InputError

    with pytest.raises(InputError) as e:
        list(run_batch(_fail, [1], jobs=1, label=str, hint=None))
    assert str(e.value) == "1: refused"
    with pytest.raises(InputError, match=r"^1: refused \(--keep-going goes on"):
        list(run_batch(_fail, [1], jobs=1, label=str))


def _fail(task):
    from planerel.errors import InputError

    raise InputError("refused")


def test_help_and_messages_read_right(capsys):
    # report's description printed "SegComp at 80%%" (argparse does not %-format descriptions)
    with pytest.raises(SystemExit):
        main(["report", "--help"])
    assert "%%" not in capsys.readouterr().out
    # a range with no upper bound read "in [0.0, None]"
    assert main(["dataset", "synth", "/nonexistent-planerel", "--noise", "-1"]) == 2
    err = capsys.readouterr().err
    assert "None" not in err and "sensor noise must be a finite number >= 0.0" in err


def test_noise_cloud_message_does_not_claim_only_the_scene_fact(tmp_path, capsys):
    # an XYZ array of random points has no plane but (each point far from the next) thousands
    # of unexplained-point objects; the line said "only the scene fact is written" anyway
    rng = np.random.default_rng(0)
    np.save(tmp_path / "noise.npy", rng.uniform(0.5, 3.0, (60, 80, 3)))
    assert main(["describe", str(tmp_path / "noise.npy"), "-o", str(tmp_path / "f.pl")]) == 0
    err = capsys.readouterr().err
    text = (tmp_path / "f.pl").read_text()
    n_obj = text.count("\nobject(")
    assert "0 planes" in err
    assert ("only the scene fact" in err) == (n_obj == 0)


def test_float_depth_in_millimetres_gets_a_note(tmp_path):
    # a float TIFF of millimetres is read as metres (the documented default): the Kinect frame
    # then lies ~1 km away and segments into other planes without a word; now a note says so
    tifffile = pytest.importorskip("tifffile")
    depth_m = np.asarray(generate_scene("box", seed=1, subsample=8).depth_mm, float) / 1000.0
    tifffile.imwrite(tmp_path / "mm.tiff", (depth_m * 1000.0).astype(np.float32))
    tifffile.imwrite(tmp_path / "m.tiff", depth_m.astype(np.float32))
    r = _run("segment", tmp_path / "mm.tiff", "-o", tmp_path / "o", "--intrinsics", "kinect")
    assert r.returncode == 0 and "median depth is" in r.stderr and "--depth-scale 1000" in r.stderr
    for extra in ([], ["--depth-scale", "1000"]):
        f = "m.tiff" if not extra else "mm.tiff"
        r = _run("segment", tmp_path / f, "-o", tmp_path / "o2", "--intrinsics", "kinect", *extra)
        assert r.returncode == 0 and "median depth" not in r.stderr, r.stderr


def test_classify_says_when_a_cloud_is_unorganized(scan, tmp_path, capsys):
    # read with --no-organize (else it is put on an image grid, tests/test_organize.py),
    # describe refuses an unorganized cloud (its relations need the image grid); classify
    # takes it and says what is missing instead of answering as if nothing were
    assert main(["convert", str(scan), "-o", str(tmp_path / "box_points.ply")]) == 0
    rules = tmp_path / "rules.pl"
    rules.write_text("box(A) :- nvertical(A, B), B >= 2.\n")
    capsys.readouterr()
    assert main(["classify", str(rules), str(tmp_path / "box_points.ply"), str(scan), "-j", "1",
                 "--no-organize"]) == 0
    out = capsys.readouterr().out
    ply, npy = out.split(str(scan) + ":")
    assert "note: an unorganized cloud" in ply and "skirt/2" in ply
    assert "unorganized" not in npy
    assert main(["describe", str(tmp_path / "box_points.ply"), "-o", str(tmp_path / "f.pl"),
                 "--no-organize"]) == 2
    assert "needs an organized cloud" in capsys.readouterr().err
    assert not (tmp_path / "f.pl").exists()


def test_same_name_clash_suggests_ids_only_where_it_exists(scan, tmp_path, capsys):
    # classify and segment said "(rename one, or give --ids)"; only describe has --ids
    other = tmp_path / "box.npy"
    other.write_bytes(scan.read_bytes())
    rules = tmp_path / "rules.pl"
    rules.write_text("box(A) :- nvertical(A, B), B >= 2.\n")
    for argv, ids in ((["classify", str(rules)], False), (["segment", "-o", str(tmp_path / "o")],
                                                          False),
                      (["describe", "-o", str(tmp_path / "f.pl")], True)):
        assert main([*argv, str(scan), str(other)]) == 2
        err = capsys.readouterr().err
        assert "same scene name 'box'" in err and ("--ids" in err) == ids, err


def test_file_names_that_are_not_utf8(scan, tmp_path):
    # classify with any argument that is not UTF-8 (a file or -o folder named in Latin-1)
    # failed with "pyswip cannot load SWI-Prolog ...; install it with: sudo apt-get install
    # swi-prolog-nox" (pyswip encodes sys.argv when imported); a scan so named is now refused
    # by name, and an output folder so named works
    import os

    rules = tmp_path / "rules.pl"
    rules.write_text("box(A) :- nvertical(A, B), B >= 2.\n")
    bad = os.fsencode(tmp_path) + b"/scan\xff.npy"
    with open(bad, "wb") as fh:
        fh.write(scan.read_bytes())
    env = {**os.environ, "LC_ALL": "C.UTF-8"}
    exe = [sys.executable, "-m", "planerel.cli"]
    r = subprocess.run([*exe, "classify", str(rules), bad], capture_output=True, timeout=300,
                       env=env)
    err = r.stderr.decode("utf-8", "replace")
    assert r.returncode == 2 and "not valid UTF-8" in err and "install" not in err, err
    out = os.fsencode(tmp_path) + b"/out\xff"
    r = subprocess.run([*exe, "classify", str(rules), str(scan), "-o", out], capture_output=True,
                       timeout=300, env=env)
    assert r.returncode == 0, r.stderr
    assert os.path.exists(out + b"/box.classified.json")
    r = subprocess.run([*exe, "describe", bad, "-o", str(tmp_path / "f.pl")], capture_output=True,
                       timeout=300, env=env)
    assert r.returncode == 2 and b"--ids" in r.stderr and not (tmp_path / "f.pl").exists()
    r = subprocess.run([*exe, "describe", bad, "-o", str(tmp_path / "f.pl"), "--ids", "scan_1"],
                       capture_output=True, timeout=300, env=env)
    assert r.returncode == 0 and "scene(scan_1)." in (tmp_path / "f.pl").read_text()
    swipl = subprocess.run(["swipl", "-q", "-g", f"consult('{tmp_path / 'f.pl'}'),halt"],
                           capture_output=True, text=True, timeout=60)
    assert swipl.returncode == 0 and swipl.stderr == ""


def test_model_without_its_settings_warns(scan, tmp_path, capsys):
    # a model folder copied without model.json classified with planerel's defaults in silence
    # (the demo model then called an mOSD cylinder a box); rules written by hand (no training
    # statistics) have no settings to lose and stay quiet
    ds = tmp_path / "ds"
    assert main(["dataset", "synth", str(ds), "--n-box", "2", "--n-stairs", "2", "--n-ramp", "2",
                 "--subsample", "8", "--quiet"]) == 0
    model = tmp_path / "model"
    assert main(["learn", str(ds), "-o", str(model), "--engine", "builtin", "-j", "1",
                 "--cache", "none"]) == 0
    r = _run("classify", model, scan)  # (a process each: classify keeps loaded models)
    assert r.returncode == 0 and "model.json" not in r.stderr
    (model / "model.json").unlink()
    r = _run("classify", model, scan)
    assert r.returncode == 0 and "model.json is missing" in r.stderr
    rules = tmp_path / "rules.pl"
    rules.write_text("box(A) :- nvertical(A, B), B >= 2.\n")
    r = _run("classify", rules, scan)
    assert r.returncode == 0 and "warning" not in r.stderr


def test_scheduler_address_that_is_not_one(scan, tmp_path):
    # a traceback ending "ValueError: missing port number in address 'garbage'"
    pytest.importorskip("distributed")
    r = _run("segment", scan, "-o", tmp_path / "o", "--scheduler", "garbage")
    _one_error_line(r, "--scheduler garbage: not a scheduler address", "tcp://HOST:8786")


def test_learn_and_report_refuse_their_outputs_before_the_work(tmp_path):
    # learn described every scene (and with --heldout learned every class) before finding
    # that the model folder or the held-out set was wrong; report ran to the end (minutes)
    # before writing into a file; dataset synth named its hidden temporary folder
    ds = tmp_path / "ds"
    assert main(["dataset", "synth", str(ds), "--n-box", "1", "--n-stairs", "1", "--n-ramp", "1",
                 "--subsample", "8", "--quiet"]) == 0
    blocker = tmp_path / "file"
    blocker.write_text("x")
    cache = tmp_path / "cache"
    for argv, needle in (
            (["learn", ds, "-o", blocker], "exists and is not a folder"),
            (["learn", ds, "-o", blocker / "m"], "is a file, not a folder"),
            (["learn", ds, "-o", tmp_path / "m", "--heldout", tmp_path], "not a data set"),
            (["learn", ds, "-o", tmp_path / "m", "--classes", ","], "--classes names no class"),
            (["report", ds, "-o", blocker, "--no-learning", "--no-real-data"],
             "exists and is not a folder")):
        r = _run(*argv, "--cache", cache) if argv[0] == "learn" else _run(*argv)
        line = _one_error_line(r, needle)
        assert "segmenting" not in r.stderr and "learned" not in r.stderr, r.stderr
        assert ".tmp" not in line
    assert not cache.exists() and not (tmp_path / "m").exists()
    r = _run("dataset", "synth", "/proc/planerel-x", "--n-box", "1", "--quiet")
    _one_error_line(r, "cannot write /proc/planerel-x")
    assert ".tmp" not in r.stderr


def test_bad_max_points_variable_is_one_error(scan, tmp_path):
    import os

    r = subprocess.run([sys.executable, "-m", "planerel.cli", "segment", str(scan), "-o",
                        str(tmp_path / "o")], capture_output=True, text=True, timeout=120,
                       env={**os.environ, "PLANEREL_MAX_POINTS": "abc"})
    line = _one_error_line(r, "PLANEREL_MAX_POINTS='abc' is not a whole number")
    assert "--keep-going" not in line


def test_aleph_variable_naming_another_file(tmp_path, monkeypatch):
    # "Aleph failed: error(existence_error(procedure,read_all/1),...)" and nothing else
    from pathlib import Path

    from planerel.errors import LearnerError
    from planerel.ilp.learn import learn

    other = tmp_path / "notes.pl"
    other.write_text("hello(world).\n")
    monkeypatch.setenv("PLANEREL_ALEPH", str(other))
    with pytest.raises(LearnerError, match=r"PLANEREL_ALEPH=.*notes\.pl defines no read_all/1"):
        learn(Path(__file__).parent / "ilp" / "trains", engine="aleph")


def test_cloud_and_segmentation_print_in_one_line():
    # at a Python prompt `cloud` and `planerel.segment(cloud)` printed their arrays whole
    # (hundreds of lines of NaN for a 640x480 frame)
    import planerel

    sc = generate_scene("box", seed=1, subsample=4)
    cloud = planerel.read(sc.depth_mm, intrinsics="kinect")
    text = repr(cloud)
    assert "\n" not in text and len(text) < 300 and text.startswith("Cloud(120x160, ")
    assert f"{cloud.n_valid} valid points" in text
    seg = planerel.segment(cloud)
    text = repr(seg)
    assert "\n" not in text and text.startswith(f"Segmentation(method='regiongrow', "
                                                f"{len(seg.planes)} planes, labels 120x160")


def test_describe_mesh_and_graph_folders_checked_first(scan, tmp_path):
    # a file given as --graph / --mesh failed per scan, after segmenting it, with the
    # --keep-going hint
    blocker = tmp_path / "file"
    blocker.write_text("x")
    for option in ("--graph", "--mesh"):
        r = _run("describe", scan, "-o", tmp_path / "f.pl", option, blocker)
        line = _one_error_line(r, option, "exists and is not a folder")
        assert "--keep-going" not in line and "planes" not in r.stderr
    assert not (tmp_path / "f.pl").exists()


def test_half_written_files_of_killed_workers_are_removed(scan, tmp_path):
    # Ctrl-C on `classify -o DIR -j 2` (workers are SIGKILLed mid-write) left hidden files like
    # ".learn0.classified.png.9v3rp5n9.png" in DIR for good; temporary files now carry their
    # writer's pid, and segment / classify remove those of dead processes, before and after
    # their batch (also after an interrupt)
    import os

    dead = subprocess.Popen(["true"])
    dead.wait()
    out = tmp_path / "seg"
    out.mkdir()
    stale = out / f".box.labels.png.tmp-{dead.pid}-abc123.png"
    live = out / f".other.png.tmp-{os.getpid()}-def456.png"
    mine = out / ".notes.txt"
    for f in (stale, live, mine):
        f.write_bytes(b"partial")
    assert main(["segment", str(scan), "-o", str(out), "--formats", "png"]) == 0
    assert not stale.exists() and live.exists() and mine.exists()
    assert (out / "box.labels.png").is_file()
    # the temporary name carries the pid
    from planerel.atomic import atomic_path

    with atomic_path(out / "x.txt") as tmp:
        assert tmp.name.startswith(f".x.txt.tmp-{os.getpid()}-")
        tmp.write_text("done")
    live.unlink()
    rules = tmp_path / "rules.pl"
    rules.write_text("box(A) :- nvertical(A, B), B >= 2.\n")
    cls = tmp_path / "cls"
    cls.mkdir()
    stale2 = cls / f".box.classified.png.tmp-{dead.pid}-zz.png"
    stale2.write_bytes(b"partial")
    assert main(["classify", str(rules), str(scan), "-o", str(cls)]) == 0
    assert sorted(p.name for p in cls.iterdir()) == ["box.classified.json", "box.classified.png"]


def test_learn_refuses_a_cache_folder_it_cannot_write(tmp_path):
    # the cache skipped an unwritable folder silently: every run segmented again, unexplained
    blocker = tmp_path / "file"
    blocker.write_text("x")
    ds = tmp_path / "ds"  # need not exist: the cache is checked first, and leaves nothing
    for cache, needle in ((blocker, "--cache"), (blocker / "sub", "cannot create folder"),
                          ("/proc/planerel-cache", "/proc/planerel-cache")):
        r = _run("learn", ds, "-o", tmp_path / "m", "--cache", cache)
        _one_error_line(r, needle)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["file"]
    # a writable cache that does not exist yet passes the check without being left behind
    r = _run("learn", ds, "-o", tmp_path / "m", "--cache", tmp_path / "c" / "d")
    assert r.returncode == 2 and "--cache" not in r.stderr, r.stderr
    assert not (tmp_path / "c").exists()


@pytest.fixture(scope="module")
def depth_png(tmp_path_factory):
    """A 160x120 16-bit depth PNG in millimetres: a block 0.2 m in front of a wall 1 m away."""
    from PIL import Image

    d = tmp_path_factory.mktemp("png") / "scan_depth.png"
    z = np.full((120, 160), 1000, np.uint16)
    z[40:80, 50:100] = 800
    Image.fromarray(z).save(d)
    return d


@pytest.mark.parametrize("cmd", ["describe", "segment"])
@pytest.mark.parametrize("focal", ["1e300", "1e-300"])
def test_focal_lengths_beyond_any_camera_are_one_error(depth_png, tmp_path, cmd, focal):
    # user103: ZeroDivisionError tracebacks from segment/noise.py and segment/normals.py
    # (classify reads its scans the same way, commands/_common.read_input)
    out = tmp_path / ("f.pl" if cmd == "describe" else "o")
    args = [cmd, depth_png, "-o", out, "--intrinsics", f"160,120,{focal},{focal},80,60"]
    _one_error_line(_run(*args), "focal lengths are pixels", f"fx={float(focal):g}")
    assert not out.exists()


def test_a_depth_scale_beyond_any_range_is_one_error(depth_png, tmp_path):
    # user103: --depth-scale 1e-30 ended in a numba TypingError (describe) or exit 0
    # (segment); 1e-6 in "out of memory"
    for scale in ("1e-30", "1e-6"):
        for cmd, out in (("describe", tmp_path / "f.pl"), ("segment", tmp_path / "o")):
            r = _run(cmd, depth_png, "-o", out, "--intrinsics", "160,120,120,120,80,60",
                     "--depth-scale", scale)
            err = [ln for ln in r.stderr.splitlines() if ln.strip() and not ln.startswith("note:")]
            assert r.returncode == 2 and len(err) == 1 and "Traceback" not in r.stderr, r.stderr
            assert "beyond any depth sensor's range" in err[0] and "--depth-scale" in err[0]
            assert not out.exists() or not any(out.iterdir())


def test_a_focal_length_in_metres_gets_a_note(depth_png, tmp_path):
    # user103: fx 0.0036 (3.6 mm) ran without a word and gave hundreds of proposals
    r = _run("segment", depth_png, "-o", tmp_path / "o", "--intrinsics",
             "160,120,0.0036,0.0036,80,60")
    assert r.returncode == 0, r.stderr
    assert "spans 180 x 180 degrees" in r.stderr and "check --intrinsics" in r.stderr
    r = _run("segment", depth_png, "-o", tmp_path / "o2", "--intrinsics", "160,120,120,120,80,60")
    assert r.returncode == 0 and "degrees" not in r.stderr, r.stderr


def test_an_output_name_ending_in_a_slash_is_refused(depth_png, tmp_path):
    # user103: "-o k.pl/" wrote over the file k.pl; "-o new/" made a file named "new"
    old = tmp_path / "k.pl"
    old.write_text("keep\n")
    for args in (["describe", depth_png, "-o", f"{old}/"],
                 ["describe", depth_png, "-o", f"{tmp_path / 'new'}/"],
                 ["convert", depth_png, "-o", f"{tmp_path / 'x.ply'}/"]):
        _one_error_line(_run(*args, "--intrinsics", "160,120,120,120,80,60"),
                        "ends in a slash", "give a file name")
    assert old.read_text() == "keep\n"
    assert not (tmp_path / "new").exists() and not (tmp_path / "x.ply").exists()


def test_segment_never_writes_over_a_users_cloud(depth_png, tmp_path):
    # user103: segment scan_depth.png -o . named its labelled cloud scan.pcd and replaced the
    # user's scan.pcd beside it (no input of that run)
    import shutil

    scan = tmp_path / "scan_depth.png"
    shutil.copy(depth_png, scan)
    mine = tmp_path / "scan.pcd"
    text = ("# .PCD v0.7\nVERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\n"
            "WIDTH 1\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS 1\nDATA ascii\n0 0 1\n")
    mine.write_text(text)
    intr = ["--intrinsics", "160,120,120,120,80,60"]
    _one_error_line(_run("segment", scan.name, "-o", ".", *intr, cwd=tmp_path),
                    "scan.pcd exists and is a point cloud without planerel's labels")
    assert mine.read_text() == text and not (tmp_path / "scan.labels.npy").exists()
    mine.unlink()
    for _ in range(2):  # its own labelled outputs it writes again
        r = _run("segment", scan.name, "-o", ".", *intr, cwd=tmp_path)
        assert r.returncode == 0, r.stderr
    assert "label" in (tmp_path / "scan.pcd").read_text(errors="replace")[:400]


def test_jobs_must_be_a_whole_number_of_workers(depth_png, tmp_path):
    # user103: -j -1 passed without a word where the scenes were too few for workers
    for cmd in (["segment", depth_png, "-o", tmp_path / "o"], ["learn", tmp_path, "-o", tmp_path / "m"],
                ["evaluate-model", tmp_path, tmp_path]):
        for bad in ("-1", "two"):
            r = _run(*cmd, "-j", bad)
            assert r.returncode == 2 and "Traceback" not in r.stderr, r.stderr
            assert "a whole number of worker processes (0: all cores)" in r.stderr, r.stderr
    assert not (tmp_path / "o").exists() and not (tmp_path / "m").exists()


def test_a_camera_file_s_error_names_it_once(depth_png, tmp_path):
    # user103: "--intrinsics cam.json: --intrinsics cam.json: focal lengths must be positive"
    cam = tmp_path / "cam.json"
    cam.write_text('{"width": 160, "height": 120, "fx": -1, "fy": 120, "cx": 80, "cy": 60}')
    line = _one_error_line(_run("segment", depth_png, "-o", tmp_path / "o", "--intrinsics", cam),
                           "focal lengths must be positive")
    assert line.count(str(cam)) == 1, line
