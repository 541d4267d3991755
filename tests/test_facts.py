"""Scene facts: loadable in swipl with no warnings, stable ids, bad input."""

from __future__ import annotations

import shutil
import subprocess

import numpy as np
import pytest
from scenes_analytic import box, floor, render, stairs, wall

from planerel.cli import main
from planerel.errors import InputError
from planerel.features.facts import PREDICATES, FactParams, describe_scene, facts_text, write_facts

SWIPL = shutil.which("swipl") or "/usr/bin/swipl"
pytestmark = pytest.mark.skipif(not shutil.which(SWIPL), reason="swipl not installed")

_HOOK = """
:- dynamic planerel_msg/1.
user:message_hook(Term, Kind, _) :-
    memberchk(Kind, [warning, error]), assertz(planerel_msg(Term)), fail.
"""


def swipl_query(tmp_path, files, goal: str) -> str:
    """Load ``files`` (after a hook that records warnings/errors), run ``goal``, return stdout;
    fail the test on any warning or error."""
    hook = tmp_path / "hook.pl"
    hook.write_text(_HOOK)
    loads = ", ".join(f"consult('{f}')" for f in files)
    prog = (f"{loads}, ( planerel_msg(M) -> print_message(error, format('msg ~q', [M])), halt(3)"
            f" ; true ), {goal}, halt")
    proc = subprocess.run([SWIPL, "-q", "-g", prog, "-t", "halt(4)", str(hook)],
                          capture_output=True, text=True, timeout=60)
    assert proc.returncode == 0, proc.stderr
    assert proc.stderr == "", proc.stderr
    return proc.stdout


def _scene(rects, **kw):
    cloud, lab, up, objs = render(rects, **kw)
    return cloud, lab, objs


def test_facts_load_and_answer_queries(tmp_path):
    from importlib.resources import files

    from planerel.prolog import __name__ as _pkg  # noqa: F401  (package exists)

    cloud, lab, objs = _scene([floor(), wall()] + stairs(0.3, 2.2, 3), pitch=25)
    d = describe_scene(cloud, lab, scene_id="s0007")
    path = write_facts(tmp_path / "s.pl", [d])
    derived = files("planerel.prolog").joinpath("derived.pl")
    out = swipl_query(tmp_path, [path, derived],
                      "findall(P, has_plane(s0007_o1, P), Ps), writeln(Ps), "
                      "aggregate_all(count, step_up(_, _), N), writeln(N), "
                      "rise(s0007_p03, s0007_p05, R), writeln(R), "
                      "(parallel(s0007_p03, s0007_p05) -> writeln(par) ; writeln(nopar))")
    lines = out.split()
    assert lines[0] == "[s0007_p02,s0007_p03,s0007_p04,s0007_p05,s0007_p06,s0007_p07]"
    assert int(lines[1]) >= 2
    assert float(lines[2]) == pytest.approx(0.17, abs=0.01)
    assert lines[3] == "par"
    text = path.read_text()
    assert "floor(s0007, s0007_p00)." in text
    assert "hull(s0007_p03, [[" in text and "plane_model(s0007_p03, [" in text


def test_deterministic_bytes_and_grouping():
    cloud, lab, _ = _scene([floor()] + box(0.0, 2.5, 0.5, 0.5, 0.4))
    a = facts_text([describe_scene(cloud, lab, scene_id="s0001"),
                    describe_scene(cloud, lab, scene_id="s0002")])
    b = facts_text([describe_scene(cloud, lab, scene_id="s0001"),
                    describe_scene(cloud, lab, scene_id="s0002")])
    assert a == b
    # every predicate's facts are contiguous (no discontiguous warnings)
    seen, last = set(), None
    for line in a.splitlines():
        if not line or line.startswith(("%", ":-")):
            continue
        name = line.split("(", 1)[0]
        if name != last:
            assert name not in seen, name
            seen.add(name)
            last = name
    assert {n for n, *_ in PREDICATES} >= seen


def test_quoted_ids_zero_one_and_degenerate_planes(tmp_path):
    cloud, lab, _ = _scene([floor()] + box(0.0, 2.5, 0.5, 0.5, 0.4))
    none = describe_scene(cloud, np.full(lab.shape, -1, np.int32), scene_id="empty scene")
    one = describe_scene(cloud, np.where(lab == 0, 0, -1).astype(np.int32), scene_id="it's")
    deg_lab = np.full(lab.shape, -1, np.int32)
    v, u = np.nonzero(lab == 1)
    deg_lab[v[:3], u[:3]] = 4  # three points of one row: collinear
    deg = describe_scene(cloud, deg_lab, scene_id='a "q" \\ é')
    noflo = describe_scene(cloud, np.where(lab >= 1, lab, -1).astype(np.int32), scene_id="nofloor")
    path = write_facts(tmp_path / "odd.pl", [none, one, deg, noflo])
    out = swipl_query(tmp_path, [path],
                      "findall(S, scene(S), Ss), length(Ss, NS), writeln(NS), "
                      "findall(A, (scene_plane(S2, P), S2 == 'it\\'s', area(P, A)), As), writeln(As), "
                      "findall(F, floor(nofloor, F), Fs), writeln(Fs), "
                      "aggregate_all(count, scene_plane('empty scene', _), NE), writeln(NE), "
                      "aggregate_all(count, (scene_plane(S3, P3), sub_atom(S3, 0, 1, _, a), area(P3, 0.0)), ND), writeln(ND)")
    ns, areas, floors, ne, nd = out.split()
    assert ns == "4" and floors == "[]" and ne == "0" and nd == "1"
    assert float(areas.strip("[]")) > 1.0
    assert len(deg.planes) == 1 and deg.planes[0].degenerate


def test_pairs_option_and_errors():
    cloud, lab, _ = _scene([floor(), wall()] + box(0.0, 2.5, 0.5, 0.5, 0.4))
    d = describe_scene(cloud, lab, scene_id="s0001")
    all_pairs = facts_text([d], FactParams(pairs="all"))
    default = facts_text([d])
    none = facts_text([d], FactParams(pairs="none", planner=False))
    n = len(d.planes)
    assert all_pairs.count("\nangle(") == n * (n - 1)
    assert 0 < default.count("\nangle(") < n * (n - 1)
    assert "angle(" not in none and "hull(" not in none
    with pytest.raises(InputError, match="occurs twice"):
        facts_text([d, d])
    with pytest.raises(InputError, match="pairs must be"):
        FactParams(pairs="some")
    with pytest.raises(InputError, match="scene id"):
        describe_scene(cloud, lab, scene_id="")


def test_describe_command(tmp_path, capsys):
    cloud, lab, _ = _scene([floor(), wall()] + box(0.0, 2.5, 0.5, 0.5, 0.4))
    scan = tmp_path / "s0003.npy"
    np.save(scan, cloud.xyz)
    labels = tmp_path / "s0003.labels.npy"
    np.save(labels, lab)
    out = tmp_path / "out.pl"
    assert main(["describe", str(scan), "--labels", str(labels), "--up", "0,-1,0",
                 "-o", str(out)]) == 0
    text = out.read_text()
    assert "scene(s0003)." in text and "object(s0003, s0003_o1)." in text
    assert main(["describe", str(scan), str(scan), "-o", str(out)]) == 2
    assert "same scene name 's0003'" in capsys.readouterr().err


def test_oblique_share_counts_the_smaller_plane_of_each_oblique_adjacent_pair():
    from types import SimpleNamespace as NS

    from planerel.features.facts import oblique_share

    planes = {1: NS(area=2.0), 2: NS(area=1.0), 3: NS(area=1.0), 4: NS(area=0.5), 5: NS(area=9.0)}

    def rel(a, b, adjacent=True, parallel=False, perpendicular=False):
        return NS(a=a, b=b, adjacent=adjacent, parallel=parallel, perpendicular=perpendicular)

    box_like = [rel(1, 2, perpendicular=True), rel(2, 3, perpendicular=True),
                rel(1, 3, parallel=True)]
    assert oblique_share(planes, box_like, (1, 2, 3)) == 0.0
    # 1-2 oblique (2 counts: 1.0), 2-4 oblique (4 counts: 0.5), 1-4 not adjacent;
    # 2-5 oblique but 5 is not in the object: (1.0 + 0.5) / (2 + 1 + 0.5)
    faceted = [rel(1, 2), rel(2, 4), rel(1, 4, adjacent=False), rel(2, 5)]
    assert oblique_share(planes, faceted, (1, 2, 4)) == 1.5 / 3.5
    assert oblique_share(planes, faceted, (5,)) == 0.0
