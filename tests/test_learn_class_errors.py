"""A learner that fails inside ``planerel learn`` is named with its class (ilp90).

``make demo --engine aleph`` (``examples/demo.py``) stopped with "Aleph failed:
error(evaluation_error(zero_divisor), ...)": the real Aleph's division by zero in
``maxlength_neg_ok/4`` on the base world's box task (300 scenes, ``samplesize`` 8), but the
message did not say which class's learner it was, so a user could not tell what to change (a
``--set box:...``, or ``--engine builtin``).  A timeout already named its class."""

from __future__ import annotations

import pytest

from planerel.errors import LearnerError
from planerel.ilp import pipeline as P
from planerel.synth.generator import generate_dataset


def test_a_failed_learner_names_its_class_and_leaves_no_model(tmp_path, monkeypatch):
    ds = tmp_path / "train"
    generate_dataset(ds, n_box=2, n_stairs=2, n_ramp=2, seed=3, size=(640, 480), subsample=8)
    # a PLANEREL_ALEPH that names another Prolog file: the real driver, swipl and the file fail
    notes = tmp_path / "notes.pl"
    notes.write_text("hello(world).\n")
    monkeypatch.setenv("PLANEREL_ALEPH", str(notes))
    out = tmp_path / "model"
    with pytest.raises(LearnerError, match=r"^learning the box rules: Aleph failed: .*"
                                           r"notes\.pl defines no read_all/1"):
        P.learn_model(ds, out, method="gt", jobs=1, engine="aleph", cache="none")
    assert not out.exists()
