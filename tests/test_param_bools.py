"""Every switch of the settings dataclasses takes True or False only (planerel.errors.check_bools)."""
import dataclasses

import pytest

from planerel.errors import InputError, check_bools
from planerel.features.curved import CurvedParams
from planerel.features.facts import FactParams
from planerel.features.raised import RaisedParams
from planerel.features.relations import ProposalParams, RelationParams
from planerel.features.stairfit import StairFitParams

CLASSES = (ProposalParams, RelationParams, CurvedParams, RaisedParams, StairFitParams, FactParams)


def _switches(cls):
    return [f.name for f in dataclasses.fields(cls) if f.type in (bool, "bool")]


@pytest.mark.parametrize("cls", CLASSES, ids=lambda c: c.__name__)
def test_every_switch_refuses_anything_but_a_bool(cls):
    names = _switches(cls)
    assert names, f"{cls.__name__} has no switch"
    for name in names:
        for bad in ("yes", 1, 0, None, "false"):
            with pytest.raises(InputError, match=rf"{name} must be (true or false|True or False)"):
                cls(**{name: bad})
        for good in (True, False):
            assert getattr(cls(**{name: good}), name) is good


def test_check_bools_names_the_field_and_value():
    @dataclasses.dataclass(frozen=True)
    class P:
        on: bool = True
        n: int = 1

    check_bools(P())
    check_bools(P(on=False, n=7))
    with pytest.raises(InputError, match=r"^on must be true or false, got 'no'$"):
        check_bools(P(on="no"))
