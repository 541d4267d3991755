"""The one exception hierarchy of planerel.

Every error a user can cause is a :class:`PlanerelError`; the CLI prints it as one line and
exits with code 2.  Subclasses say which stage failed:

``InputError``       bad files, shapes, values or parameters (also a ``ValueError``)
``PrologError``      SWI-Prolog missing, a Prolog file that does not load, a failed query
``LearnerError``     a learning run that failed or ran past its time limit
``DependencyError``  an optional component that is not installed; the message says how to install it
"""

from __future__ import annotations

__all__ = ["PlanerelError", "InputError", "PrologError", "LearnerError", "DependencyError"]


class PlanerelError(Exception):
    """Base class of every error planerel raises on purpose."""


class InputError(PlanerelError, ValueError):
    """A file, array or parameter the user gave is wrong; the message names it."""


class PrologError(PlanerelError):
    """SWI-Prolog is missing, a Prolog text does not load, or a query failed."""


class LearnerError(PlanerelError):
    """A learning run failed, timed out, or produced no usable output."""


class DependencyError(PlanerelError):
    """A needed program or package is missing; the message gives the install command."""
