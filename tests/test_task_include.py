"""Task files that include another: ``:- planerel_include('FILE').`` (modes42).

planerel expands the directive where it stands when it reads a task (``load_task``,
``task_directives``); it is never written into ``STEM.b``, which the real Aleph reads.  The
shipped tasks are written as the four shared parts ``aleph/part1_relations.pl`` ..
``part4_thresholds.pl`` and their own lines; the order of the expanded lines is the order of the
bottom clause, so these tests also keep each task's own lines where they stood before the parts
(the ``.b`` files and the demo's rules were compared byte for byte then)."""

from __future__ import annotations

import os
import subprocess
import sys

import pytest

from planerel.errors import InputError, PlanerelError
from planerel.ilp.aleph_export import aleph_files, load_task, task_directives

TASKS = ("modes_relational.pl", "modes_pair.pl", "modes_sides.pl", "modes_slope.pl", "modes_facing.pl",
         "modes_varied.pl", "modes_objects.pl")
CORNER = ":- modeb(*, corner(+plane, -plane))."


def _write(folder, **files):
    for name, text in files.items():
        (folder / name).write_text(text)
    return folder


def test_the_included_lines_stand_where_the_directive_is(tmp_path):
    _write(tmp_path,
           **{"base.pl": ":- set(nodes, 10).\n:- modeb(1, a(+obj)).\n% a comment\n"
                         ":- modeb(1, b(+obj)).\n:- lazy_evaluate(lteq/2).\n",
              "ext.pl": "/* a task */\n:- modeb(1, x(+obj)).\n"
                        ":- planerel_include('base.pl').\n:- modeb(1, y(+obj)).\n"})
    sets, modes, preds, other = load_task(str(tmp_path / "ext.pl"))
    assert modes == [":- modeb(1, x(+obj)).", ":- modeb(1, a(+obj)).", ":- modeb(1, b(+obj)).",
                     ":- modeb(1, y(+obj))."]
    assert preds == [("x", 1), ("a", 1), ("b", 1), ("y", 1)]
    assert sets == [":- set(nodes, 10)."] and other == [":- lazy_evaluate(lteq/2)."]
    assert not any("planerel_include" in ln for ln in task_directives(str(tmp_path / "ext.pl")))


def test_a_task_of_ones_own_extends_a_shipped_one(tmp_path):
    """A bare name not beside the including file is planerel's aleph/ folder's file; one beside
    it wins."""
    mine = _write(tmp_path, **{"mine.pl": ":- planerel_include('modes_relational.pl').\n"
                                          ":- modeb(*, facing(+plane, -plane)).\n"}) / "mine.pl"
    default = task_directives("modes_relational.pl")
    assert task_directives(str(mine)) == default + [":- modeb(*, facing(+plane, -plane))."]
    _write(tmp_path, **{"modes_relational.pl": ":- modeb(1, z(+obj)).\n"})
    assert task_directives(str(mine)) == [":- modeb(1, z(+obj)).",
                                          ":- modeb(*, facing(+plane, -plane))."]


def test_a_missing_include_is_one_line_naming_file_and_line(tmp_path):
    task = _write(tmp_path, **{"t.pl": ":- modeb(1, a(+obj)).\n"
                                       ":- planerel_include('nope.pl').\n"}) / "t.pl"
    with pytest.raises(InputError, match=r"t\.pl:2: planerel_include: no task file 'nope\.pl' "
                                         r"\(looked for \S*nope\.pl and in planerel's "
                                         r"aleph/ folder\)") as e:
        load_task(str(task))
    assert "\n" not in str(e.value)
    # a name with a folder in it is looked up beside the including file only
    with pytest.raises(InputError, match="no task file 'sub/x.pl'"):
        load_task(str(_write(tmp_path, **{"u.pl": ":- planerel_include('sub/x.pl').\n"}) / "u.pl"))


def test_a_cyclic_include_is_one_line_with_the_cycle(tmp_path):
    _write(tmp_path, **{"a.pl": ":- modeb(1, a(+obj)).\n:- planerel_include('b.pl').\n",
                        "b.pl": "% b\n\n:- planerel_include('a.pl').\n",
                        "self.pl": ":- planerel_include('self.pl').\n"})
    with pytest.raises(InputError, match=r"b\.pl:3: planerel_include cycle: \S*a\.pl -> "
                                         r"\S*b\.pl -> \S*a\.pl$"):
        load_task(str(tmp_path / "a.pl"))
    with pytest.raises(PlanerelError, match=r"self\.pl:1: planerel_include cycle: \S*self\.pl -> "
                                            r"\S*self\.pl$"):
        load_task(str(tmp_path / "self.pl"))


def test_an_included_file_is_checked_as_the_task_is(tmp_path):
    _write(tmp_path, **{"h.pl": "\n:- modeh(1, box(+obj)).\n",
                        "t.pl": ":- modeb(1, a(+obj)).\n:- planerel_include('h.pl').\n",
                        "bad.pl": ":- modeb(1, a(+obj)).\n:- planerel_include(h).\n",
                        "empty.pl": ":- planerel_include('h0.pl').\n", "h0.pl": "% nothing\n"})
    with pytest.raises(InputError, match=r"h\.pl:2: the task file must not hold modeh"):
        load_task(str(tmp_path / "t.pl"))
    with pytest.raises(InputError, match=r"bad\.pl:2: planerel_include takes one file name in "
                                         "single quotes"):
        load_task(str(tmp_path / "bad.pl"))
    with pytest.raises(InputError, match=r"empty\.pl: no modeb declarations"):
        load_task(str(tmp_path / "empty.pl"))


@pytest.mark.parametrize("command", ["export-aleph", "learn"])
def test_the_commands_refuse_a_bad_include_in_one_line_before_describing(tmp_path, command):
    _write(tmp_path, **{"a.pl": ":- planerel_include('a.pl').\n",
                        "m.pl": ":- modeb(1, a(+obj)).\n:- planerel_include('gone.pl').\n"})
    for task, what in (("a.pl", "planerel_include cycle"),
                       ("m.pl", "m.pl:2: planerel_include: no task file 'gone.pl'")):
        out = tmp_path / f"out_{task}"
        args = ([str(tmp_path / "no_dataset"), str(out)] if command == "export-aleph"
                else [str(tmp_path / "no_dataset"), "-o", str(out)])
        r = subprocess.run([sys.executable, "-m", "planerel.cli", command, *args,
                            "--task", str(tmp_path / task)],
                           capture_output=True, text=True, timeout=120)
        assert r.returncode == 2
        lines = r.stderr.strip().splitlines()
        assert len(lines) == 1 and what in lines[0], r.stderr
        assert not out.exists()


def test_shipped_tasks_keep_their_own_lines_where_they_stood():
    """The parts are cut where the tasks differ: each task's own modeb lines stand where they
    stood when the tasks were whole files (pair41's face_pair/2 after corner/2, before
    stair_step/2; facing/2 after corner/2; the incline thresholds after the rise thresholds)."""
    rel, pair = task_directives("modes_relational.pl"), task_directives("modes_pair.pl")
    face_pair = ":- modeb(*, face_pair(+plane, -plane))."
    at = rel.index(CORNER) + 1
    assert pair == rel[:at] + [face_pair] + rel[at:]
    assert rel[at] == ":- modeb(*, stair_step(+plane, -plane))."
    # ramp77's side-view task: modes_pair.pl with top_slope/2 after lying/1, its thresholds last
    sides = task_directives("modes_sides.pl")
    ly = pair.index(":- modeb(1, lying(+plane)).") + 1
    assert sides == (pair[:ly] + [":- modeb(1, top_slope(+plane, -topslope))."] + pair[ly:]
                     + [":- modeb(1, gteq(+topslope, #topslope)).",
                        ":- modeb(1, lteq(+topslope, #topslope))."])
    for name in ("modes_facing.pl", "modes_varied.pl"):
        lines = task_directives(name)
        assert lines[lines.index(CORNER) + 1] == ":- modeb(*, facing(+plane, -plane))."
    for name in ("modes_relational.pl", "modes_slope.pl", "modes_facing.pl"):
        lines = task_directives(name)
        assert lines[lines.index(":- modeb(1, lteq(+rise, #rise)).") + 1] == \
            ":- modeb(1, gteq(+incline, #incline))."
    # the parts are no tasks of their own, and every shipped task reads
    for name in TASKS:
        assert load_task(name)[1]
        assert all(ln.startswith(":-") and "planerel_include" not in ln
                   for ln in task_directives(name))


@pytest.fixture(scope="module")
def descs(tmp_path_factory):
    from planerel.ilp.aleph_export import describe_dataset
    from planerel.synth.generator import generate_dataset

    d = tmp_path_factory.mktemp("ds") / "ds"
    generate_dataset(d, n_box=2, n_stairs=2, n_ramp=2, seed=3, size=(640, 480), subsample=8)
    descs, skipped = describe_dataset(d)
    assert skipped == []
    return descs


def test_the_b_file_holds_the_expanded_lines_and_no_include(descs):
    b = aleph_files(descs, "box", task="modes_pair.pl")["box.b"]
    assert "planerel_include" not in b
    modes = [ln for ln in b.splitlines() if ln.startswith(":- modeb(")]
    assert modes == [ln for ln in task_directives("modes_pair.pl") if ln.startswith(":- modeb(")]
    assert b.count(":- lazy_evaluate(") == 2 and b.count(":- set(search, ") == 1


@pytest.mark.real_aleph
@pytest.mark.skipif(not os.environ.get("PLANEREL_ALEPH"),
                    reason="PLANEREL_ALEPH not set (path to the real aleph.pl)")
def test_the_real_aleph_reads_a_task_written_with_includes(tmp_path, descs):
    from planerel.ilp.aleph_export import export_aleph
    from planerel.ilp.learn import learn

    export_aleph(descs, tmp_path, "stairs", task="modes_pair.pl")
    res = learn(str(tmp_path / "stairs"), engine="aleph", timeout=120)
    assert res.rules, res.output
    assert res.train.tp == 2
