"""What a task file may hold, and what becomes of the rest (ilp90, a new user's pass).

A task file is read line by line and its ``:- ...`` lines are copied into ``STEM.b``.  Before
ilp90 a clause of a background predicate of one's own was left out of ``STEM.b`` without a
word, a directive over two lines was cut to its first line (a ``STEM.b`` with a syntax error),
a ``modeb`` with a ``%`` comment after its full stop was copied as an unknown directive with no
``determination``, and ``planerel learn`` learned a whole run with a ``modeb`` outside planerel's
vocabulary before refusing to write the model (docs/learner.md, "Background predicates of your
own")."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

from planerel.errors import InputError
from planerel.ilp.aleph_export import aleph_files, check_task_vocabulary, load_task, task_directives

sys.path.insert(0, str(Path(__file__).resolve().parent))
from test_task_include import descs  # noqa: E402,F401  (the fixture: a small described data set)

DEFAULT = ":- planerel_include('modes_relational.pl').\n"


def _task(tmp_path, text, name="mytask.pl"):
    p = tmp_path / name
    p.write_text(text)
    return str(p)


def test_a_clause_in_a_task_is_refused_with_file_and_line(tmp_path):
    task = _task(tmp_path, DEFAULT + ":- modeb(1, big(+plane)).\n\n"
                                     "big(P) :- area(P, A), A >= 0.5.\n")
    with pytest.raises(InputError, match=r"mytask\.pl:4: a task file holds directives only .*"
                                         r"'big\(P\) :- area\(P, A\), A >= 0\.5\.'") as e:
        load_task(task)
    assert "\n" not in str(e.value) and "Background predicates of your own" in str(e.value)


def test_a_directive_over_two_lines_is_refused(tmp_path):
    task = _task(tmp_path, DEFAULT + ":- modeb(1,\n    big(+plane)).\n")
    with pytest.raises(InputError, match=r"mytask\.pl:2: a directive of a task file must stand "
                                         r"on one line"):
        load_task(task)


def test_comments_of_every_kind_are_still_no_lines(tmp_path):
    task = _task(tmp_path, "/* a task\n   over lines */\n% a comment\n   \n"
                           ":- modeb(1, a(+obj)). /* inline */ % and more\n"
                           "/* one */ :- modeb(1, b(+obj)).\n")
    assert task_directives(task) == [":- modeb(1, a(+obj)).", ":- modeb(1, b(+obj))."]
    # the shipped tasks read as before: every line a directive ending in its full stop
    for name in ("modes_relational.pl", "modes_pair.pl", "modes_sides.pl", "modes_slope.pl",
                 "modes_facing.pl", "modes_varied.pl", "modes_objects.pl"):
        assert all(ln.startswith(":-") and ln.endswith(".") for ln in task_directives(name))
        check_task_vocabulary(name)


def test_a_modeb_with_a_comment_after_it_is_a_mode_with_its_determination(tmp_path, descs):  # noqa: F811
    task = _task(tmp_path, DEFAULT + ":- modeb(*, facing(+plane, -plane)).   % facing walls\n")
    _, modes, preds, other = load_task(task)
    assert modes[-1] == ":- modeb(*, facing(+plane, -plane))." and ("facing", 2) in preds
    assert not any("facing" in ln for ln in other)
    b = aleph_files(descs, "box", task=task)["box.b"]
    assert ":- determination(box/1, facing/2)." in b
    assert "% facing walls" not in b


def test_a_predicate_of_ones_own_by_a_one_line_directive_reaches_the_learner(tmp_path, descs):  # noqa: F811
    """The documented way: ``:- assertz((...)).`` on one line; the builtin learner reads it with
    no "mode declaration but no definition" warning and the predicate holds in the background."""
    from planerel.ilp.aleph_export import export_aleph
    from planerel.ilp.learn import learn

    task = _task(tmp_path, DEFAULT + ":- modeb(1, big(+plane)).\n"
                                     ":- assertz((big(P) :- area(P, A), A >= 0.05)).\n")
    export_aleph(descs, tmp_path / "out", "box", task=task)
    stem = tmp_path / "out" / "box"
    assert ":- assertz((big(P) :- area(P, A), A >= 0.05))." in (tmp_path / "out" / "box.b").read_text()
    res = learn(str(stem), engine="builtin", timeout=120)
    assert "no definition" not in res.output and "big/1" not in res.output.split("[theory]")[0]
    r = subprocess.run(["swipl", "-q", "-g",
                        f"consult('{stem}.b'), (big(_) -> writeln(yes) ; writeln(no)), halt",
                        "-t", "halt(1)"],
                       capture_output=True, text=True, timeout=120, cwd=tmp_path / "out")
    assert r.stdout.strip().endswith("yes"), r.stdout + r.stderr


@pytest.mark.parametrize("command", ["export-aleph", "learn"])
def test_the_commands_refuse_a_clause_before_describing(tmp_path, command):
    task = _task(tmp_path, DEFAULT + "big(P) :- area(P, A), A >= 0.5.\n")
    out = tmp_path / "out"
    args = ([str(tmp_path / "no_dataset"), str(out)] if command == "export-aleph"
            else [str(tmp_path / "no_dataset"), "-o", str(out)])
    r = subprocess.run([sys.executable, "-m", "planerel.cli", command, *args, "--task", task],
                       capture_output=True, text=True, timeout=120)
    assert r.returncode == 2
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1 and "mytask.pl:2: a task file holds directives only" in lines[0], r.stderr
    assert not out.exists()


def test_learn_refuses_a_mode_outside_the_vocabulary_before_describing(tmp_path):
    """export-aleph writes such a task (for Aleph by hand); learn, whose model classify must
    read, refuses it first instead of after the whole run."""
    task = _task(tmp_path, DEFAULT + ":- modeb(1, big(+plane)).\n"
                                     ":- assertz((big(P) :- area(P, A), A >= 0.5)).\n")
    with pytest.raises(InputError, match=r"mytask\.pl: modeb on big/1, which is not planerel's "
                                         r"vocabulary"):
        check_task_vocabulary(task)
    out = tmp_path / "model"
    r = subprocess.run([sys.executable, "-m", "planerel.cli", "learn", str(tmp_path / "no_dataset"),
                        "-o", str(out), "--task", task], capture_output=True, text=True, timeout=120)
    assert r.returncode == 2 and "modeb on big/1" in r.stderr and "no_dataset" not in r.stderr, r.stderr
    assert not out.exists()
