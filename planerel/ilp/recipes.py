"""Named learning recipes: a task file, learner settings and ``--other-rules`` under one name.

The varied world (``planerel dataset synth --world varied``) is learned best with a task and a
dozen settings measured together (docs/results.md, issue 16's "facing cell").  Typing them out
is error-prone, so ``planerel learn --recipe varied`` (and :func:`planerel.ilp.pipeline.learn_model`
through :func:`apply_recipe`) stands for all of them.  Anything given explicitly wins: a
``--set NAME=VALUE`` replaces the recipe's value for NAME, ``--task`` its task file, and
``--other-rules`` can only add rules, never remove the recipe's.

A recipe is plain data; ``metrics.json`` records its name next to the settings it resolved to.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from planerel.errors import InputError

__all__ = ["Recipe", "RECIPES", "apply_recipe", "recipe_decision", "recipe_names"]


@dataclass(frozen=True)
class Recipe:
    """A task file, learner settings and whether to learn rules for ``other``.

    Attributes
    ----------
    name : str
        The name given to ``--recipe``.
    task : str
        Task file: a name in ``aleph/`` or a path.
    settings : dict
        Learner settings (``NAME`` or ``CLASS:NAME`` -> value as text, as ``--set`` takes them).
    other_rules : bool
        Learn rules for class ``other`` too.
    decision : dict
        Decision settings the model is written with (``NAME`` -> value, fields of
        :class:`~planerel.ilp.metrics.DecisionParams`): ``model.json``'s ``decision`` section,
        which ``classify`` reads (``--param decision.NAME=VALUE`` still overrides).
    doc : str
        One line on what it is for and where it is measured.
    """

    name: str
    task: str
    settings: dict = field(default_factory=dict)
    other_rules: bool = False
    decision: dict = field(default_factory=dict)
    doc: str = ""


#: The varied world's recipe: the facing task without thresholds on incline/2 and with over/2
#: (``modes_varied.pl``; docs/results.md, "The varied task as the recipe's default", 2026-11-30)
#: with the settings measured in docs/results.md ("Varied world at the session's end: the facing
#: cell" and "inclines in whole degrees", 2026-11-29): coverage with a high
#: noise bound and a sample of 8 seeds for the classes, thresholds counted per example and looked
#: ahead, a band's lower edge offered, cut-offs loosened by one standard error (not for other),
#: and rules for ``other`` learned with little noise.  No proof gate: the varied world is rendered
#: at 160x120, so its rules' smallest training proofs (0.007-0.012 m^2 for a box's top and side)
#: are bounded by planes 16 times the area a 640x480 frame resolves at the same range, and the
#: gate refused real boxes seen with a 2-3 cm strip of side; without it two --members 5 models answer the same or better on all nine
#: held-out sets and on every real set ("The varied task as the recipe's default").
VARIED = Recipe(
    name="varied",
    task="modes_varied.pl",
    settings={
        "evalfn": "coverage", "minpos": "8", "noise": "30", "samplesize": "8",
        "lazy_examples": "true", "lazy_lookahead": "true", "lazy_band": "true",
        "explore": "true", "cutoff_slack": "1.0",
        "other:noise": "5", "other:cutoff_slack": "off",
    },
    other_rules=True,
    decision={"proof_gate": False},
    doc="the varied world (--world varied, >= 600 scenes): --members 5 on 3 000 scenes holds "
        "out 0.963 pooled over nine held-out sets (docs/results.md)",
)

RECIPES: dict[str, Recipe] = {VARIED.name: VARIED}


def recipe_names() -> list[str]:
    """The recipes' names, sorted."""
    return sorted(RECIPES)


def apply_recipe(name: str | None, *, task: str | None = None, settings: dict | None = None,
                 other_rules: bool = False) -> tuple[str | None, dict, bool]:
    """Merge a recipe with what the caller gave explicitly.

    Parameters
    ----------
    name : str or None
        A recipe name (:data:`RECIPES`), or None for no recipe.
    task, settings, other_rules
        The caller's own values; a task or a setting given here replaces the recipe's.

    Returns
    -------
    (task, settings, other_rules)
        ``settings`` is a new dict.

    Raises
    ------
    InputError
        Unknown recipe name.
    """
    given = dict(settings or {})
    if name is None:
        return task, given, other_rules
    recipe = _recipe(name)
    return (task if task is not None else recipe.task, {**recipe.settings, **given},
            other_rules or recipe.other_rules)


def recipe_decision(name: str | None) -> dict:
    """The decision settings a recipe writes into its models (a new dict; empty for no recipe).

    Raises
    ------
    InputError
        Unknown recipe name.
    """
    return {} if name is None else dict(_recipe(name).decision)


def _recipe(name: str) -> Recipe:
    """The recipe called ``name``; an unknown name is an :class:`InputError`."""
    recipe = RECIPES.get(name)
    if recipe is None:
        raise InputError(f"unknown recipe {name!r}; choose from {', '.join(recipe_names())}")
    return recipe
