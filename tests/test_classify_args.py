"""``planerel classify`` says which argument is wrong when the model and the scans are mixed
up (user89: a forgotten model said "the following arguments are required: INPUT", swapped
arguments "MODEL: the folder holds no scan")."""

from __future__ import annotations

import pytest

from planerel.cli import main


@pytest.fixture(scope="module")
def setup(tmp_path_factory):
    d = tmp_path_factory.mktemp("cls")
    assert main(["dataset", "synth", str(d / "set"), "--n-box", "1", "--n-stairs", "0",
                 "--n-ramp", "0", "--seed", "4", "--quiet"]) == 0
    model = d / "model"
    model.mkdir()
    (model / "rules.pl").write_text("box(A) :- nplanes(A, N), gteq(N, 1).\n")
    scan = d / "set" / "s0000.depth.png"
    facts = d / "s.pl"
    assert main(["describe", str(scan), "-o", str(facts)]) == 0
    return model, scan, facts, d / "set"


@pytest.mark.parametrize("case,said", [
    ("forgotten", "is a scan, not a model; the model comes first"),
    ("swapped", "is a scan, not a model; the model comes first"),
    ("facts", "is a facts file from planerel describe, not a model"),
    ("scans folder", "holds no rules.pl, so it is no model"),
    ("no input", "no INPUT: give one or more scans after the model"),
])
def test_mixed_up_arguments_are_named(setup, case, said, capsys):
    model, scan, facts, folder = setup
    args = {"forgotten": [str(scan)], "swapped": [str(scan), str(model)],
            "facts": [str(facts), str(scan)], "scans folder": [str(folder), str(scan)],
            "no input": [str(model)]}[case]
    assert main(["classify", *args]) == 2
    err = capsys.readouterr().err
    assert said in err and "planerel classify MODEL INPUT" in err
    assert err.count("\n") == 1  # one line, no usage dump, no traceback


def test_the_right_order_still_classifies(setup, capsys):
    model, scan, _, _ = setup
    assert main(["classify", str(model), str(scan)]) == 0
    assert ": box" in capsys.readouterr().out
