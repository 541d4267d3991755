"""A learned model scored on a data set with ground truth (``planerel evaluate-model``).

``planerel learn --heldout HELD`` scores the rules it has just learned on a held-out set. This
module scores a model that already exists (a single or a members model folder) on any data set
in planerel's format, with the same objects and the same figures: each scene's ground-truth
objects, made of the segmented planes that mostly cover them
(:func:`planerel.ilp.scenes.describe_scenes`, with the segmentation method and parameters
the model was learned with, ``gt`` included), answered by the model's rules through :class:`~planerel.classify.Classifier`
(the path ``planerel classify`` takes, its decision and vote included), then counted by
:func:`planerel.ilp.metrics.score_objects`.  A user can so check a model on a set of their own
(another seed, other world parameters) without learning it again.
"""

from __future__ import annotations

from pathlib import Path

from planerel.errors import InputError
from planerel.progress import progress_bar

__all__ = ["evaluate_model"]


def evaluate_model(model, dataset_dir, *, jobs: int | None = 1, cache=None,
                   progress: bool | None = None, scheduler=None, params: dict | None = None) -> dict:
    """Open-set accuracy of a learned model on a data set, object by object.

    Parameters
    ----------
    model : path or Classifier
        A model folder (``planerel learn -o``; a members model too) or its ``rules.pl``, or
        an open :class:`~planerel.classify.Classifier` (left open).
    dataset_dir : path
        A data set with ground truth (``planerel dataset synth``).
    jobs : int or None
        Worker processes for segmenting and describing (None: all cores).
    cache : path, optional
        Segmentation cache (:func:`planerel.ilp.scenes.describe_scenes`).
    progress : bool, optional
        Progress bars on stderr (default: when stderr is a terminal).
    scheduler : str or distributed.Client, optional
        A Dask scheduler for the describing.
    params : dict, optional
        Decision settings to score the model with instead of its own, ``{"decision.NAME":
        value}`` (:class:`~planerel.ilp.metrics.DecisionParams`, as ``planerel classify
        --param`` takes them; only with a model folder, not an open classifier).  Nothing
        else: the scenes are described with the model's training settings.

    Returns
    -------
    dict
        What :func:`planerel.ilp.pipeline.held_out_scores` returns for the same model and set:
        :func:`~planerel.ilp.metrics.score_objects`' figures (``accuracy`` over the class
        objects, ``open_set_accuracy`` over all, ``per_class``, ``confusion``,
        ``open_set_confusion``, ...), ``dataset``, ``model``, ``n_scenes``, ``skipped``,
        ``predictions`` (``{object: class}``), ``excluded`` (objects that are no example, by
        class and reason), ``errors`` (:func:`~planerel.ilp.metrics.error_kinds`) and, with
        ``params``, ``params``.

    Raises
    ------
    InputError
        The model or the data set cannot be read, the set has no object of the model's
        classes or of class ``other``, or ``params`` holds a name that is not ``decision.*``.
    """
    from planerel.classify.classifier import Classifier
    from planerel.ilp.pipeline import heldout_examples, heldout_figures
    from planerel.ilp.scenes import describe_scenes

    own = not isinstance(model, Classifier)
    params = dict(params or {})
    bad = sorted(k for k in params if not str(k).startswith("decision."))
    if bad:
        raise InputError(f"evaluate-model takes decision settings only (decision.NAME=VALUE), "
                         f"got {', '.join(bad)}: the scenes are described with the model's "
                         f"training settings")
    if params and not own:
        raise InputError("decision settings go with a model folder, not an open classifier "
                         "(open it with them: Classifier(model, seg_params=...))")
    clf = Classifier(model, seg_params=params or None) if own else model
    try:
        # the training segmentation, as learn --heldout used it (a model learned on a data
        # set's ground-truth planes, method gt, is scored on the held-out set's own)
        trained = clf.trained
        method = trained.method if trained is not None else clf.method
        seg_params = dict(trained.seg_params) if trained is not None else clf.seg_params
        descs, skipped = describe_scenes(dataset_dir, method=method, seg_params=seg_params,
                                         jobs=jobs, cache=cache, progress=progress,
                                         scheduler=scheduler)
        examples = heldout_examples(descs, clf.classes, dataset_dir)
        answers = {}
        for d in progress_bar(descs, desc="answering", enabled=progress):
            for a in clf.answer_description(d):
                answers[a.object_id] = a
        predictions = {o: answers[o].klass for o, _ in examples}
        if clf.members:
            # a vote: each member's rules, named (member, index) as Members.stats names them
            stats = tuple(((n, i), k, tp, fp) for n, m in enumerate(clf.members)
                          for i, k, tp, fp in m.stats)
            fired = {o: tuple((k, (n, i)) for n, v in enumerate(answers[o].votes)
                              for k, i in v.fired) for o, _ in examples}
        else:
            stats = clf.stats
            fired = {o: answers[o].fired for o, _ in examples}
        out = heldout_figures(descs, skipped, dataset_dir, clf.classes, examples, predictions,
                              fired, stats)
        out["model"] = str(Path(clf.rules_path).parent)
        if params:
            out["params"] = params
        return out
    finally:
        if own:
            clf.close()


