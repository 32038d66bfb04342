"""Exception classes of gnssatt.

Every error raised on user input is an :class:`InvalidInputError`, which is also a :class:`ValueError`, so
``except ValueError`` keeps working. Messages say what was expected and what was given.
"""

from __future__ import annotations

__all__ = [
    "ConvergenceError",
    "DegenerateGeometryError",
    "GnssattError",
    "GnssattWarning",
    "InvalidInputError",
    "NearDegenerateWarning",
]


class GnssattError(Exception):
    """Base class of every exception raised by gnssatt."""


class InvalidInputError(GnssattError, ValueError):
    """An argument has the wrong shape, a non-finite value, or is out of range."""


class DegenerateGeometryError(InvalidInputError):
    """The geometry (baselines, lines of sight, reference vectors) does not fix the answer."""


class ConvergenceError(GnssattError):
    """An iterative method did not converge."""


class GnssattWarning(UserWarning):
    """Base class of every warning issued by gnssatt."""


class NearDegenerateWarning(GnssattWarning):
    """The geometry nearly fails to fix the answer (nearly parallel vectors, a nearly vanishing divisor):
    the result is computed, but its errors are amplified by about the reciprocal of the quantity named."""
