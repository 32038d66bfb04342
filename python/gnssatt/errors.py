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
    "InternalError",
    "InvalidInputError",
    "InvalidTypeError",
    "NearDegenerateWarning",
    "RecordsSkippedWarning",
    "RinexError",
    "UnknownNameError",
    "WorkLimitError",
]


class GnssattError(Exception):
    """Base class of every exception raised by gnssatt."""


class InvalidInputError(GnssattError, ValueError):
    """An argument has the wrong shape, a non-finite value, or is out of range."""


class InvalidTypeError(InvalidInputError, TypeError):
    """An argument is of the wrong kind (complex, boolean, text or ``None`` where real numbers are expected);
    both a ``ValueError`` (as every input error here) and a ``TypeError`` (as Python's own type errors)."""


class DegenerateGeometryError(InvalidInputError):
    """The geometry (baselines, lines of sight, reference vectors) does not fix the answer."""


class WorkLimitError(InvalidInputError):
    """A requested amount of work or memory (candidates, samples, integration steps, grid cells) exceeds its
    documented limit; raised before any work starts, with the requested number and the limit."""


class UnknownNameError(InvalidInputError, KeyError):
    """A name (of an experiment, a model...) that is not among the known ones; the message lists them.

    Also a :class:`KeyError`, the error of a failed look-up, so ``except KeyError`` keeps working.
    """

    def __str__(self) -> str:
        # KeyError's str() is the repr of its argument (quotes around a message): a message reads better.
        return ValueError.__str__(self)


class ConvergenceError(GnssattError):
    """An iterative method did not converge, or a computation on valid input lost its accuracy (an integer
    overflow, a failed identity check, a diverging integration) and refuses to return a wrong answer."""


class InternalError(GnssattError, RuntimeError):
    """A defect in gnssatt itself: a Rust panic caught at the boundary. Please report it with the input that
    caused it; the message carries the panic's text."""


class RinexError(InvalidInputError):
    """A RINEX file cannot be read, or two files have nothing in common (no common epochs or satellites).

    Attributes
    ----------
    path
        The file, as given.
    line
        1-based line number where reading stopped, or None where the problem is not on one line.
    """

    def __init__(self, path: object, line: int | None, message: str) -> None:
        self.path = str(path)
        self.line = line
        self.message = message
        where = f"{self.path}, line {line}" if line is not None else self.path
        super().__init__(f"{where}: {message}")

    def __reduce__(self) -> tuple[type[RinexError], tuple[str, int | None, str]]:
        # picklable with its three arguments, so that it crosses process pools (gnssatt.montecarlo)
        return (type(self), (self.path, self.line, self.message))


class GnssattWarning(UserWarning):
    """Base class of every warning issued by gnssatt."""


class NearDegenerateWarning(GnssattWarning):
    """The geometry nearly fails to fix the answer (nearly parallel vectors, a nearly vanishing divisor):
    the result is computed, but its errors are amplified by about the reciprocal of the quantity named."""


class RecordsSkippedWarning(GnssattWarning):
    """Records of a valid file that cannot be used (a system or signal gnssatt does not use, an orbit it
    cannot propagate, an epoch cut by the end of the file) were left out; one warning per kind, naming the
    file, the records and their count (``docs/robustness.md``, "Real files")."""
