"""gnssatt: attitude determination from GNSS signals and complementary sensors.

Every attitude estimator returns a result whose ``.rotation`` is a :class:`scipy.spatial.transform.Rotation`
mapping body-frame vectors into the reference frame in which the lines of sight or reference vectors were
given. Frames, Euler sequences, units and signs: ``docs/conventions.md``.
"""

from gnssatt import errors, magnetic
from gnssatt._core import __version__
from gnssatt.errors import (
    ConvergenceError,
    DegenerateGeometryError,
    GnssattError,
    GnssattWarning,
    InvalidInputError,
    NearDegenerateWarning,
)
from gnssatt.magnetometer import YawResult, yaw_from_magnetometer
from gnssatt.matrix_method import MatrixAttitudeResult, matrix_attitude
from gnssatt.vector_attitude import TriadResult, WahbaResult, triad, wahba

__all__ = [
    "ConvergenceError",
    "DegenerateGeometryError",
    "GnssattError",
    "GnssattWarning",
    "InvalidInputError",
    "MatrixAttitudeResult",
    "NearDegenerateWarning",
    "TriadResult",
    "WahbaResult",
    "YawResult",
    "__version__",
    "errors",
    "magnetic",
    "matrix_attitude",
    "triad",
    "wahba",
    "yaw_from_magnetometer",
]
