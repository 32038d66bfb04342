"""gnssatt: attitude determination from GNSS signals and complementary sensors.

Every attitude estimator returns a result whose ``.rotation`` is a :class:`scipy.spatial.transform.Rotation`
mapping body-frame vectors into the reference frame in which the lines of sight or reference vectors were
given. Frames, Euler sequences, units and signs: ``docs/conventions.md``.
"""

from gnssatt import errors, magnetic, orbit, rinex, sim, tumble
from gnssatt._core import __version__
from gnssatt.ambiguity import (
    PartialFixResult,
    RatioTestResult,
    bootstrap_success_rate,
    lambda_decorrelate,
    lambda_ils,
    partial_fix,
    ratio_test,
    ratio_threshold_fixed_failure_rate,
)
from gnssatt.errors import (
    ConvergenceError,
    DegenerateGeometryError,
    GnssattError,
    GnssattWarning,
    InvalidInputError,
    NearDegenerateWarning,
)
from gnssatt.gyro_gnss import GyroGnssResult, gyro_gnss_filter, gyro_propagate
from gnssatt.likelihood import (
    AttitudePrior,
    BaselineDirection,
    LikelihoodAttitude,
    LikelihoodGrid,
    likelihood_grid,
    ml_attitude,
    ml_baseline,
    prior_from_velocity,
)
from gnssatt.magnetometer import YawResult, yaw_from_magnetometer
from gnssatt.matrix_method import MatrixAttitudeResult, matrix_attitude
from gnssatt.phase_attitude import phase_attitude_fixes
from gnssatt.tumble import RotationFit, TumbleModel, fit_rotation
from gnssatt.vector_attitude import TriadResult, WahbaResult, triad, wahba
from gnssatt.visibility import visibility_axis

__all__ = [
    "AttitudePrior",
    "BaselineDirection",
    "ConvergenceError",
    "DegenerateGeometryError",
    "GnssattError",
    "GnssattWarning",
    "GyroGnssResult",
    "InvalidInputError",
    "LikelihoodAttitude",
    "LikelihoodGrid",
    "MatrixAttitudeResult",
    "NearDegenerateWarning",
    "PartialFixResult",
    "RatioTestResult",
    "RotationFit",
    "TriadResult",
    "TumbleModel",
    "WahbaResult",
    "YawResult",
    "__version__",
    "bootstrap_success_rate",
    "errors",
    "fit_rotation",
    "gyro_gnss_filter",
    "gyro_propagate",
    "lambda_decorrelate",
    "lambda_ils",
    "likelihood_grid",
    "magnetic",
    "matrix_attitude",
    "ml_attitude",
    "ml_baseline",
    "orbit",
    "partial_fix",
    "phase_attitude_fixes",
    "prior_from_velocity",
    "ratio_test",
    "ratio_threshold_fixed_failure_rate",
    "rinex",
    "sim",
    "triad",
    "tumble",
    "visibility_axis",
    "wahba",
    "yaw_from_magnetometer",
]
