"""The exceptions of :mod:`subdiv` (raised by its compiled core, ``subdiv._subdiv``)."""

from typing import Optional

__all__ = ["SubdivError", "InputError", "NotConvergedError"]


class SubdivError(Exception):
    """Base class of every error :mod:`subdiv` raises itself (file system errors are
    :class:`OSError`). Raised as such only for an internal error (please report it)."""


class InputError(SubdivError, ValueError):
    """Bad input: a malformed mesh or mesh file, a bad option, a mesh the method cannot take
    (the message says why and which method works). The command line's exit code 2."""


class NotConvergedError(SubdivError, RuntimeError):
    """No acceptable result: the solver stopped before the tolerance, or the measured error
    exceeds it. The command line's exit code 3.

    Attributes:
        iterations: iterations the solver performed (``None`` when no iterative solver ran,
            e.g. a singular system found by a direct solver, or the measured error check).
        residual: the residual or measured error reached, relative to the bounding-box
            diagonal d (``None`` when unknown).
    """

    def __init__(self, message: str, iterations: Optional[int] = None, residual: Optional[float] = None):
        super().__init__(message)
        self.iterations = iterations
        self.residual = residual


# Shown as subdiv.InputError etc. in tracebacks: the public names.
for _cls in (SubdivError, InputError, NotConvergedError):
    _cls.__module__ = "subdiv"
del _cls
