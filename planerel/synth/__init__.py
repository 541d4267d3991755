"""Synthetic scenes: scene parameters and a seed in, data-set folders out.

In: classes, counts, camera and sensor ranges, a seed.  Out: scenes with depth, ground-truth labels
and object classes (:mod:`.generator`, re-exported here: ``from planerel.synth import
generate_dataset``), built from the shapes of :mod:`.geometry`, the sensor noise of
:mod:`.sensor`, whole rooms (:mod:`.world`, :mod:`.training_world`) and tilted-camera scenes
(:mod:`.gravity_scenes`).  Uses io, segment and features; nothing below imports it.
"""

from planerel.synth.generator import *  # noqa: F401,F403
from planerel.synth.generator import __all__  # noqa: F401
