"""One valid call per public function of gnssatt, and what its arguments mean to the tests: the one table
the intake tests (``test_intake_models``, ``test_intake_estimators``) and the hostile suite
(``hostile/inventory.py``) read.

``CALLS[name]`` (merged from ``estimators``, ``models`` and ``files``) is a :class:`Call`: ``build()``
returns fresh keyword arguments of a call that must succeed (each test kind checks that it does before
mutating it), ``args`` the :class:`Arg` of each argument with a special meaning (a work count, documented
non-finite input, ...), ``nan_output`` / ``nan_fields`` which outputs may be non-finite. What each test kind
does with them (which mutants, which error) stays beside that test kind.
"""

from __future__ import annotations

from . import estimators, files, models, other_estimators, other_models
from .spec import NO_ARG, WORK_TINY_STEP, Arg, Call, resolve

CALLS: dict[str, Call] = {**estimators.CALLS, **models.CALLS, **files.CALLS}
#: Classes, methods and second forms of public functions, keyed by the intake tests' names.
OTHER_CALLS: dict[str, Call] = {**other_estimators.CALLS, **other_models.CALLS}

__all__ = ["CALLS", "NO_ARG", "OTHER_CALLS", "WORK_TINY_STEP", "Arg", "Call", "resolve"]
