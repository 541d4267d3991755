"""docs/predicates.md says what the default task's modes are: a user writing rules of their own,
or reading an export, goes by it (ilp57: it named `nvertical`/`ninclined` as modes of the
default task and left out the types `slope`, `oblique`, `pfrac`)."""

from __future__ import annotations

import re
from pathlib import Path

from planerel.ilp.aleph_export import load_task

DOC = (Path(__file__).resolve().parents[1] / "docs" / "predicates.md").read_text()


def _section(start: str, end: str) -> str:
    i = DOC.index(start)
    return DOC[i:DOC.index(end, i)]


def test_every_predicate_of_every_task_has_a_row():
    rows = set(re.findall(r"^\| `([a-z_]+)/(\d)`", DOC, re.MULTILINE))
    for task in ("modes_relational.pl", "modes_pair.pl", "modes_sides.pl", "modes_slope.pl", "modes_facing.pl",
                 "modes_varied.pl", "modes_objects.pl"):
        _, _, preds, _ = load_task(task)
        missing = [f"{n}/{a}" for n, a in preds
                   if (n, str(a)) not in rows and n not in ("gteq", "lteq")]
        assert not missing, (task, missing)


def test_the_default_tasks_modes_and_types_as_documented():
    _, modes, _, _ = load_task("modes_relational.pl")
    body = _section("* **Body modes: the relations themselves.**", "* **Types keep joins")
    types = _section("* **Types keep joins meaningful**", "* **Settings**")
    compare = _section("## Comparisons (`prolog/compare.pl`)", "They work three ways")
    thresholds: dict[str, set] = {}
    for m in modes:
        name = re.match(r":- modeb\([^,]+, ([a-z_]+)\(", m).group(1)
        args = re.findall(r"([+\-#])([a-z_]+)", m)
        if name in ("gteq", "lteq"):
            thresholds.setdefault(args[0][1], set()).add(name)
            continue
        assert f"`{name}" in body, f"{name} is a mode of the default task; the Body modes bullet omits it"
        for _, t in args:
            assert f"`{t}`" in types, f"type {t} of {name} is not in the Types bullet"
    for name in ("nvertical", "ninclined"):
        assert not any(f" {name}(" in m for m in modes)
    both = sorted(t for t, ops in thresholds.items() if ops == {"gteq", "lteq"})
    listed = re.search(r"for every measure\s+T ∈ \{([^}]*)\}", compare).group(1)
    assert sorted(x.strip() for x in listed.split(",")) == both


def test_the_scene_id_row_gives_the_naming_rule():
    """ilp90: the Ids table said a scene id is the file name "up to its first dot"; the real
    Kinect frames (``frame_20121214T142256.068683_depth.tiff``) keep their dot.  Every example
    the row gives is what :func:`planerel.io.naming.scene_name` makes of the file name, and the
    quoted atom it shows is how the facts write it."""
    from planerel.features import terms
    from planerel.io.naming import scene_name

    row = next(ln for ln in DOC.splitlines() if ln.startswith("| scene |"))
    assert "first dot" not in row.split("until ilp90")[0]
    pairs = re.findall(r"`([^`]+)` → `([^`]+)`", row)
    assert len(pairs) >= 2
    for path, name in pairs:
        assert scene_name(path) == name
    quoted = re.findall(r"written `([^`]+)`", row)
    assert quoted == [str(terms.atom(pairs[-1][1]))]
