"""planerel: range images and point clouds to planes, relations and Prolog facts for ILP.

The top-level namespace is small on purpose; the stages live in their own modules
(``planerel.io``, ``planerel.synth``, ``planerel.segment``, ...).  Importing planerel does no
work: Prolog is started only when a query needs it.
"""

from planerel._version import __version__
from planerel.cloud import Cloud, Intrinsics
from planerel.errors import (
    DependencyError,
    InputError,
    LearnerError,
    PlanerelError,
    PrologError,
)

__all__ = [
    "__version__",
    "Cloud",
    "Intrinsics",
    "PlanerelError",
    "InputError",
    "PrologError",
    "LearnerError",
    "DependencyError",
]
