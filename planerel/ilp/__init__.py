"""Stage 4, learning: facts in, rules out.

In: described scenes (Prolog facts and class labels).  Out: a model folder (``rules.pl``,
settings) learned by Aleph or planerel's own learner (:mod:`.learn`), from the task files of
:mod:`.aleph_export` / :mod:`.popper_export`; cross-validation and metrics in :mod:`.pipeline`;
the model's settings in :mod:`.model_settings`; a background file of the user's own
(``learn --background``) in :mod:`.background`.
"""
