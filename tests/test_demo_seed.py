"""``examples/demo.py --seed N``: the seeds it derives, and the argument's checks.

The default (0) must give the shipped model's seeds (``make demo`` unchanged); N moves only the
generator seeds of the paper-sized set and the training world, never the held-out set's, and
the training worlds of two different N share no generator seed (each world uses its seed, seed
+ 1 and seed + 2).  The runs themselves are measured in docs/results.md "The demo model over
training-world seeds" (minutes each: not run here).
"""

from __future__ import annotations

import importlib.util
from pathlib import Path

import pytest

from planerel.errors import InputError, PlanerelError

ROOT = Path(__file__).resolve().parents[1]


@pytest.fixture(scope="module")
def demo():
    spec = importlib.util.spec_from_file_location("planerel_demo_seed", ROOT / "examples" / "demo.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def test_default_is_the_shipped_seeds(demo):
    assert demo.seeds() == demo.seeds(0) == {"train": 0, "world": 0, "heldout": 1000,
                                             "folds": 0, "learner": 0}


def test_seed_moves_training_data_only(demo):
    for n in range(1, demo.MAX_SEED + 1):
        s = demo.seeds(n)
        assert s["train"] == s["world"] == 10 * n
        assert (s["heldout"], s["folds"], s["learner"]) == (1000, 0, 0)


def test_worlds_share_no_generator_seed(demo):
    used = {}
    for n in range(demo.MAX_SEED + 1):
        w = demo.seeds(n)["world"]
        for part in (w, w + 1, w + 2):  # paper, room, round parts
            assert part not in used, f"--seed {n} and --seed {used.get(part)} share seed {part}"
            assert part < demo.seeds(n)["heldout"]
            used[part] = n


@pytest.mark.parametrize("bad", [-1, 100, 1.0, True, "3"])
def test_bad_seed_is_an_input_error(demo, bad):
    with pytest.raises(InputError, match="--seed"):
        demo.seeds(bad)


def test_bad_seed_on_the_command_line_exits_2_before_any_work(demo, tmp_path, capsys):
    assert demo.main(["--seed", "100", "--out", str(tmp_path / "out")]) == 2
    assert "--seed must be an integer from 0 to 99" in capsys.readouterr().err
    assert not (tmp_path / "out").exists()
    assert issubclass(InputError, PlanerelError)


def test_bad_round_on_the_command_line_exits_2_before_any_work(demo, tmp_path, capsys):
    assert demo.main(["--round", "-1", "--out", str(tmp_path / "out")]) == 2
    assert "--round must be a non-negative integer, got -1" in capsys.readouterr().err
    assert not (tmp_path / "out").exists()
