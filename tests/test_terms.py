"""The Prolog term writer: quoting, numbers, refusals, and a round trip through real swipl."""

from __future__ import annotations

import math
import shutil
import subprocess

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from planerel.errors import InputError
from planerel.features import terms

SWIPL = shutil.which("swipl") or "/usr/bin/swipl"
needs_swipl = pytest.mark.skipif(not shutil.which(SWIPL), reason="swipl not installed")

# swipl reads the file and prints, per fact t(I, A, F): I, the code points of A, and F with
# the shortest representation that reads back as the same double.
_READER = r"""
main :- current_prolog_flag(argv, Argv), last(Argv, File),
    setup_call_cleanup(open(File, read, S), loop(S), close(S)).
loop(S) :- read_term(S, T, []),
    (   T == end_of_file -> true
    ;   T = t(I, A, F), atom(A), atom_codes(A, Cs),
        atomic_list_concat(Cs, ' ', CsText),
        (   integer(F) -> format("~w|~w|i~w~n", [I, CsText, F])
        ;   float(F) -> format("~w|~w|f~17g~n", [I, CsText, F])
        ),
        loop(S)
    ).
:- initialization((main, halt), main).
"""


def _swipl_read(tmp_path, text: str) -> list[tuple[int, str, object]]:
    src = tmp_path / "facts.txt"  # not .pl: swipl would load a .pl argument as a script
    src.write_text(text, encoding="utf-8")
    reader = tmp_path / "reader.pl"
    reader.write_text(_READER)
    proc = subprocess.run([SWIPL, str(reader), str(src)], capture_output=True, text=True,
                          timeout=30)
    assert proc.returncode == 0, proc.stderr
    assert proc.stderr == "", proc.stderr
    out = []
    for line in proc.stdout.splitlines():
        i, codes, value = line.split("|")
        name = "".join(chr(int(c)) for c in codes.split()) if codes else ""
        num = int(value[1:]) if value[0] == "i" else float(value[1:])
        out.append((int(i), name, num))
    return out


def test_plain_and_quoted_atoms():
    assert terms.atom("s0007_p03") == "s0007_p03"
    assert terms.atom("S0007") == "'S0007'"
    assert terms.atom("it's") == "'it\\'s'"
    assert terms.atom("a b") == "'a b'"
    assert terms.atom("") == "''"
    assert terms.atom("[]") == "'[]'"
    assert terms.atom("é") == "'\\xe9\\'"


def test_numbers_are_valid_prolog_floats():
    assert terms.number(3) == "3"
    assert terms.number(1e-5) == "1.0e-5"
    assert terms.number(2.5e300) == "2.5e300"
    assert terms.number(1.0) == "1.0"
    assert terms.number(-0.0) == "0.0"
    assert terms.number(0.123456789, round_to=4) == "0.1235"


@pytest.mark.parametrize("bad", [math.nan, math.inf, -math.inf])
def test_nan_and_inf_refused(bad):
    with pytest.raises(InputError, match="refusing to write"):
        terms.number(bad)
    with pytest.raises(InputError, match="refusing to write"):
        terms.fact("area", "p", bad)


def test_other_bad_values():
    with pytest.raises(InputError, match="boolean"):
        terms.number(True)
    with pytest.raises(InputError, match="surrogate"):
        terms.atom("a\ud800b")
    with pytest.raises(InputError, match="unassigned"):
        terms.atom("\U000d8000")
    with pytest.raises(InputError, match="must be a string"):
        terms.atom(3)


def test_fact_and_lists():
    assert terms.fact("hull", "p", [[1.0, 2.0, 3.0]]) == "hull(p, [[1.0, 2.0, 3.0]])."
    assert terms.fact("up", "s", [0.1, -0.2, 0.3], round_to=6) == "up(s, [0.1, -0.2, 0.3])."
    assert terms.directive("dynamic", terms.Term("foo/1")) == ":- dynamic(foo/1)."
    assert terms.plane_id("s0007", 3) == "s0007_p03"
    assert terms.plane_id("s0007", 123) == "s0007_p123"
    assert terms.object_id("s0007", 1) == "s0007_o1"
    assert terms.scene_id(7) == "s0007"


_atoms = st.text(alphabet=st.characters(blacklist_categories=("Cs",)).filter(
    lambda ch: not 0xD8000 <= ord(ch) <= 0xDFFFF), max_size=12)
_floats = st.floats(allow_nan=False, allow_infinity=False)
_ints = st.integers(min_value=-(2**70), max_value=2**70)


@needs_swipl
@settings(max_examples=25, deadline=None)
@given(st.lists(st.tuples(_atoms, st.one_of(_floats, _ints)), min_size=1, max_size=15))
def test_round_trip_through_swipl(tmp_path_factory, items):
    tmp = tmp_path_factory.mktemp("rt")
    text = "\n".join(terms.fact("t", i, name, value) for i, (name, value) in enumerate(items))
    back = _swipl_read(tmp, text + "\n")
    assert len(back) == len(items)
    for (_i, name, value), (name0, value0) in zip(back, items, strict=True):
        assert name == name0
        if isinstance(value0, int):
            assert value == value0
        else:
            assert isinstance(value, float)
            assert value == (0.0 if value0 == 0 else value0)
