"""A model of several members: theories learned on disjoint parts of one training set, and
the vote that joins their answers (``planerel learn --members K``; docs/learner.md, "Members:
a vote of theories").

Most of a single model's errors on held-out scenes are the learner's variance between
training draws (docs/results.md); theories learned on disjoint parts and joined by a vote
average much of it out.  This module holds the pure parts: how the scenes are split
(:func:`partition_scenes`), the check of ``K`` (:func:`check_members`), the vote
(:func:`vote`) and how a members model folder is recognised (:func:`member_folders`).

A members model folder::

    MODEL/model.json         the settings (as a single model's) plus "members" and "vote"
    MODEL/rules.pl           every member's rules under a comment header (for a reader)
    MODEL/metrics.json
    MODEL/members/1/ ...     each a normal model folder (rules.pl, model.json, aleph/,
    MODEL/members/K/          metrics.json) that planerel classify also reads on its own
"""

from __future__ import annotations

import json
from collections.abc import Sequence
from pathlib import Path

from planerel.errors import InputError

__all__ = ["OTHER", "VOTE_RULE", "check_members", "partition_scenes", "vote", "member_folders"]

OTHER = "other"

#: The vote, in words (written into a members model's model.json).
VOTE_RULE = ("plurality of the members' answers; a tie goes to the tied class whose members' "
             "chosen rules have the larger summed Laplace precision (an 'other' that no rule "
             "answered counts 0), then to 'other', then to the class of the first member; the "
             "rule, bindings and proof planes come from the winning class's member with the "
             "highest precision (the first of equals)")


def check_members(members, class_counts: dict) -> int:
    """``members`` as an int, or a one-line :class:`InputError` when it is not a whole
    number of at least 1 or when a class has fewer scenes than parts.

    ``class_counts``: ``{class: number of scenes whose primary object is of it}``, for the
    classes to be learned.
    """
    if isinstance(members, bool) or not isinstance(members, int):
        raise InputError(f"--members takes a whole number of at least 1, got {members!r}")
    if members < 1:
        raise InputError(f"--members takes a whole number of at least 1, got {members}")
    if members > 1:
        short = {k: n for k, n in class_counts.items() if n < members}
        if short:
            k, n = min(short.items(), key=lambda kv: (kv[1], kv[0]))
            raise InputError(f"--members {members}: class {k} has only {n} scene(s), fewer "
                             f"than the {members} parts (every part needs one of each class)")
    return members


def partition_scenes(scenes: Sequence[tuple[str, str]], members: int) -> dict[str, int]:
    """Split scenes into ``members`` disjoint parts, stratified by class.

    Parameters
    ----------
    scenes : sequence of (scene id, class)
        In manifest order (the class: the scene's primary object's).
    members : int

    Returns
    -------
    dict
        ``{scene id: part}``, parts ``0 .. members - 1``: a scene's rank among the scenes of
        its class (in the order given), modulo ``members``.  Deterministic; every part gets
        ``n // members`` or one more scenes of each class.
    """
    rank: dict[str, int] = {}
    out: dict[str, int] = {}
    for sid, klass in scenes:
        if sid in out:
            raise InputError(f"scene {sid} is listed twice")
        r = rank.get(klass, 0)
        out[sid] = r % members
        rank[klass] = r + 1
    return out


def vote(answers: Sequence[tuple[str, float | None]]) -> tuple[str, int]:
    """Join the members' answers for one object.

    Parameters
    ----------
    answers : sequence of (class, precision)
        Each member's answer in member order: its class (or ``other``) and the Laplace
        precision of the rule it chose (None: ``other`` answered by no rule; counts 0).

    Returns
    -------
    (class, member)
        The class most members answer (ties: :data:`VOTE_RULE`) and the index of the member
        whose answer is given: the one of that class with the highest precision.
    """
    if not answers:
        raise InputError("a vote needs at least one answer")
    count: dict[str, int] = {}
    summed: dict[str, float] = {}
    for klass, prec in answers:
        count[klass] = count.get(klass, 0) + 1
        summed[klass] = summed.get(klass, 0.0) + (prec or 0.0)
    top = max(count.values())
    tied = [k for k in count if count[k] == top]          # in order of the first member
    if len(tied) > 1:
        best = max(summed[k] for k in tied)
        tied = [k for k in tied if summed[k] == best]
    winner = OTHER if OTHER in tied else tied[0]
    member = max((i for i, (k, _) in enumerate(answers) if k == winner),
                 key=lambda i: (answers[i][1] or 0.0, -i))
    return winner, member


def member_folders(rules_path) -> list[Path] | None:
    """The member folders of a members model (``model.json`` next to ``rules_path`` naming
    ``members``), or None for a single model.

    Raises
    ------
    InputError
        ``members`` is not a list of folders that hold a ``rules.pl``.
    """
    path = Path(rules_path).parent / "model.json"
    if not path.is_file():
        return None
    try:
        data = json.loads(path.read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return None   # read_settings says what is wrong with it
    if not isinstance(data, dict) or "members" not in data:
        return None
    names = data["members"]
    if not isinstance(names, list) or not names or not all(isinstance(n, str) for n in names):
        raise InputError(f"{path}: 'members' must be a list of member folders")
    out = []
    for n in names:
        folder = (path.parent / n).resolve()
        if not folder.is_relative_to(path.parent.resolve()) or not (folder / "rules.pl").is_file():
            raise InputError(f"{path}: member {n!r} is no model folder inside the model "
                             "(it needs a rules.pl)")
        out.append(folder)
    return out
