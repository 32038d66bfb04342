"""gnssatt: attitude determination from GNSS signals and complementary sensors.

Every attitude estimator returns a result whose ``.rotation`` is a :class:`scipy.spatial.transform.Rotation`
mapping body-frame vectors into the reference frame in which the lines of sight or reference vectors were
given. Frames, Euler sequences, units and signs: ``docs/conventions.md``.

Submodules and the names re-exported here are imported on first use (PEP 562), so that ``import gnssatt``
costs little more than numpy and :mod:`scipy.spatial.transform` (``benches/python/import_time.py``): the
simulator, :mod:`scipy.stats` and matplotlib load only when something needs them.
"""

from __future__ import annotations

import importlib
from typing import TYPE_CHECKING, Any

from gnssatt._core import __version__

if TYPE_CHECKING:  # what the lazy table below provides, spelled out for type checkers and IDEs
    from gnssatt import ambiguity, attitude, errors, gnss, magnetic, orbit, rinex, sim
    from gnssatt.ambiguity import (
        IlsBatchResult,
        PartialFixResult,
        RatioTestResult,
        bootstrap_success_rate,
        lambda_decorrelate,
        lambda_ils,
        lambda_ils_batch,
        partial_fix,
        ratio_test,
        ratio_threshold_fixed_failure_rate,
    )
    from gnssatt.attitude.dynamics import RotationFit, TumbleModel, fit_rotation
    from gnssatt.attitude.gyro_gnss import GyroGnssResult, gyro_gnss_filter, gyro_propagate
    from gnssatt.attitude.likelihood import (
        AttitudePrior,
        BaselineDirection,
        BaselineSeries,
        LikelihoodAttitude,
        LikelihoodAttitudeSeries,
        LikelihoodGrid,
        likelihood_grid,
        ml_attitude,
        ml_attitude_series,
        ml_baseline,
        ml_baseline_series,
        prior_from_velocity,
    )
    from gnssatt.attitude.magnetometer import YawResult, yaw_from_magnetometer
    from gnssatt.attitude.matrix_method import MatrixAttitudeResult, matrix_attitude
    from gnssatt.attitude.phase_attitude import phase_attitude_fixes
    from gnssatt.attitude.visibility import visibility_axis
    from gnssatt.attitude.wahba import TriadResult, WahbaResult, triad, wahba
    from gnssatt.errors import (
        ConvergenceError,
        DegenerateGeometryError,
        GnssattError,
        GnssattWarning,
        InvalidInputError,
        NearDegenerateWarning,
    )
    from gnssatt.gnss.position import PositionSeries, position_from_rinex

_SUBMODULES = frozenset({"ambiguity", "attitude", "errors", "gnss", "magnetic", "orbit", "rinex", "sim"})

# Module defining each re-exported name; tests/test_lazy_import.py checks it against the block above.
_EXPORTS: dict[str, str] = {
    name: module
    for module, names in {
        "ambiguity": (
            "IlsBatchResult",
            "PartialFixResult",
            "RatioTestResult",
            "bootstrap_success_rate",
            "lambda_decorrelate",
            "lambda_ils",
            "lambda_ils_batch",
            "partial_fix",
            "ratio_test",
            "ratio_threshold_fixed_failure_rate",
        ),
        "errors": (
            "ConvergenceError",
            "DegenerateGeometryError",
            "GnssattError",
            "GnssattWarning",
            "InvalidInputError",
            "NearDegenerateWarning",
        ),
        "attitude.gyro_gnss": ("GyroGnssResult", "gyro_gnss_filter", "gyro_propagate"),
        "attitude.likelihood": (
            "AttitudePrior",
            "BaselineDirection",
            "BaselineSeries",
            "LikelihoodAttitude",
            "LikelihoodAttitudeSeries",
            "LikelihoodGrid",
            "likelihood_grid",
            "ml_attitude",
            "ml_attitude_series",
            "ml_baseline",
            "ml_baseline_series",
            "prior_from_velocity",
        ),
        "attitude.magnetometer": ("YawResult", "yaw_from_magnetometer"),
        "attitude.matrix_method": ("MatrixAttitudeResult", "matrix_attitude"),
        "attitude.phase_attitude": ("phase_attitude_fixes",),
        "attitude.dynamics": ("RotationFit", "TumbleModel", "fit_rotation"),
        "attitude.wahba": ("TriadResult", "WahbaResult", "triad", "wahba"),
        "attitude.visibility": ("visibility_axis",),
        "gnss.position": ("PositionSeries", "position_from_rinex"),
    }.items()
    for name in names
}

__all__ = [
    "AttitudePrior",
    "BaselineDirection",
    "BaselineSeries",
    "ConvergenceError",
    "DegenerateGeometryError",
    "GnssattError",
    "GnssattWarning",
    "GyroGnssResult",
    "IlsBatchResult",
    "InvalidInputError",
    "LikelihoodAttitude",
    "LikelihoodAttitudeSeries",
    "LikelihoodGrid",
    "MatrixAttitudeResult",
    "NearDegenerateWarning",
    "PartialFixResult",
    "PositionSeries",
    "RatioTestResult",
    "RotationFit",
    "TriadResult",
    "TumbleModel",
    "WahbaResult",
    "YawResult",
    "__version__",
    "ambiguity",
    "attitude",
    "bootstrap_success_rate",
    "errors",
    "fit_rotation",
    "gnss",
    "gyro_gnss_filter",
    "gyro_propagate",
    "lambda_decorrelate",
    "lambda_ils",
    "lambda_ils_batch",
    "likelihood_grid",
    "magnetic",
    "matrix_attitude",
    "ml_attitude",
    "ml_attitude_series",
    "ml_baseline",
    "ml_baseline_series",
    "orbit",
    "partial_fix",
    "phase_attitude_fixes",
    "position_from_rinex",
    "prior_from_velocity",
    "ratio_test",
    "ratio_threshold_fixed_failure_rate",
    "rinex",
    "sim",
    "triad",
    "visibility_axis",
    "wahba",
    "yaw_from_magnetometer",
]


def __getattr__(name: str) -> Any:
    """Import a submodule or a re-exported name on first access (PEP 562) and cache it in the package."""
    if name in _SUBMODULES:
        value: Any = importlib.import_module(f"{__name__}.{name}")
    elif name in _EXPORTS:
        value = getattr(importlib.import_module(f"{__name__}.{_EXPORTS[name]}"), name)
    else:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(__all__))
