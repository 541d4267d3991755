"""planerel: range images and point clouds to planes, relations and Prolog facts for ILP.

The top level is the five-line API (:mod:`planerel.api`)::

    cloud = planerel.read(depth_array, intrinsics="kinect")   # or a path, or an XYZ array
    seg = planerel.segment(cloud)                             # planes
    desc = planerel.describe(cloud)                           # planes, relations, objects
    with planerel.Classifier("out/model/rules.pl") as clf:
        answer = clf.classify(cloud)                          # class, rule, proof planes

The stages live in their own modules (``planerel.io.readers``, ``planerel.synth.generator``,
``planerel.segment``, ...).  Importing planerel does no work: numba compiles nothing and Prolog
starts only when a query needs it.
"""

import sys as _sys
import types as _types

import planerel.segment as _segment_package
from planerel._version import __version__
from planerel.api import describe, read
from planerel.api import segment as _segment_api
from planerel.errors import (
    DependencyError,
    InputError,
    LearnerError,
    PlanerelError,
    PrologError,
)
from planerel.io.cloud import Cloud, Intrinsics


class _CallableModule(_types.ModuleType):
    """``planerel.segment`` is a package and, called, :func:`planerel.api.segment`."""

    def __call__(self, scan, method: str = "regiongrow", **kwargs):
        return _segment_api(scan, method, **kwargs)


_segment_package.__class__ = _CallableModule
segment = _sys.modules["planerel.segment"]


def __getattr__(name: str):
    if name == "Classifier":  # imported on first use: it needs pyswip, not at import time
        from planerel.classify.classifier import Classifier

        return Classifier
    raise AttributeError(f"module 'planerel' has no attribute {name!r}")


__all__ = [
    "__version__",
    "read",
    "segment",
    "describe",
    "Classifier",
    "Cloud",
    "Intrinsics",
    "PlanerelError",
    "InputError",
    "PrologError",
    "LearnerError",
    "DependencyError",
]
