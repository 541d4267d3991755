"""The names split out of ``planerel/features/relations.py`` (split95) are still importable from
it, as the same objects: code written before the split keeps working (docs/architecture.md)."""

from __future__ import annotations

import importlib

import pytest

from planerel.features import relations


def test_every_moved_name_is_the_new_modules_object():
    assert len(relations._MOVED) > 100
    for name, module in relations._MOVED.items():
        new = importlib.import_module(f"planerel.features.{module}")
        assert name in vars(new), f"{name} is not defined in planerel.features.{module}"
        assert getattr(relations, name) is getattr(new, name), name


def test_the_old_import_statements_still_work():
    from planerel.features.lying import lying_tops as lying_new
    from planerel.features.proposal_params import ProposalParams as params_new
    from planerel.features.proposals import propose_objects as propose_new
    from planerel.features.relations import ProposalParams, lying_tops, propose_objects, tall_faces
    from planerel.features.tall_face import tall_faces as tall_new

    assert (tall_faces, lying_tops, propose_objects, ProposalParams) == (
        tall_new, lying_new, propose_new, params_new)


def test_the_public_names_are_unchanged_and_resolve():
    for name in relations.__all__:
        assert getattr(relations, name) is not None, name
    # the split's modules keep the public names they hold in their own __all__
    for module in set(relations._MOVED.values()):
        new = importlib.import_module(f"planerel.features.{module}")
        assert set(new.__all__) <= set(relations.__all__) | {"ProposalParams"}, module


def test_an_unknown_name_is_an_attribute_error():
    with pytest.raises(AttributeError, match="no attribute 'no_such_relation'"):
        relations.no_such_relation  # noqa: B018
    with pytest.raises(ImportError):
        from planerel.features.relations import no_such_relation  # noqa: F401
