"""Stage 3, features: segmentation in, Prolog facts out.

In: a ``Cloud`` and its ``(H, W)`` plane labels.  Out: measured planes (:mod:`.planes`, with the
gravity up of :mod:`.gravity`), plane relations (:mod:`.relations`; ``tall_face/1`` in
:mod:`.tall_face`, ``lying/1`` in :mod:`.lying`), object proposals (:mod:`.proposals`, their
settings :mod:`.proposal_params`, the step chains :mod:`.step_chains`, :mod:`.curved` for round
surfaces), and the scene's Prolog facts (:mod:`.facts`, written with
:mod:`.terms`).  Also the data-set folder (:mod:`.dataset`: scenes, ground truth, their
descriptions), which ground-truth objects are fair examples (:mod:`.truth_examples`) and the
object-level scoring of proposals against ground truth (:mod:`.object_eval`).
"""
