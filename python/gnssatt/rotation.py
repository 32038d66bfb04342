"""Rotation utilities of the Rust core, in the conventions of ``docs/conventions.md``.

Matrices are active body -> reference maps (like :meth:`scipy.spatial.transform.Rotation.as_matrix`);
Euler sequences are intrinsic (scipy's upper-case axes); quaternions are scalar-last ``[x, y, z, w]``.
scipy's :class:`~scipy.spatial.transform.Rotation` remains the public currency of results; these functions
exist so the papers' sequences can be checked against an implementation that is not scipy's.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

from gnssatt import _core
from gnssatt._arrays import float_array
from gnssatt.errors import InvalidInputError

__all__ = ["dcm_to_euler", "dcm_to_quat", "euler_to_dcm", "nearest_rotation", "quat_to_dcm"]


def _angles(angles: ArrayLike, degrees: bool) -> tuple[float, float, float]:
    a = float_array("angles", angles, ndim=1, shape="(3,)")
    if a.shape != (3,):
        raise InvalidInputError(f"expected angles of shape (3,), got {a.shape}")
    a = np.radians(a) if degrees else a
    return (float(a[0]), float(a[1]), float(a[2]))


def euler_to_dcm(seq: str, angles: ArrayLike, *, degrees: bool = False) -> NDArray[np.float64]:
    """Body -> reference matrix ``R_a1(angle1) R_a2(angle2) R_a3(angle3)`` of an intrinsic sequence such
    as ``"ZYX"`` (seeds 000, 002), ``"YZX"`` (seed 001, GOST normal frame) or ``"YZY"`` (seed 004)."""
    return _core.euler_to_dcm(seq, _angles(angles, degrees))


def dcm_to_euler(seq: str, dcm: ArrayLike, *, degrees: bool = False) -> NDArray[np.float64]:
    """Angles of an intrinsic sequence; the middle one in [-90, 90] deg (Tait-Bryan) or [0, 180] deg
    (proper Euler), the others in (-180, 180]."""
    angles = np.array(_core.dcm_to_euler(seq, float_array("dcm", dcm, ndim=2, shape="(3, 3)")))
    return np.degrees(angles) if degrees else angles


def quat_to_dcm(quat: ArrayLike) -> NDArray[np.float64]:
    """Matrix of a scalar-last quaternion ``[x, y, z, w]`` (normalised first)."""
    q = float_array("quat", quat, ndim=1, shape="(4,)")
    if q.shape != (4,):
        raise InvalidInputError(f"expected quat of shape (4,), got {q.shape}")
    return _core.quat_to_dcm((float(q[0]), float(q[1]), float(q[2]), float(q[3])))


def dcm_to_quat(dcm: ArrayLike) -> NDArray[np.float64]:
    """Scalar-last unit quaternion ``[x, y, z, w]`` with ``w >= 0``."""
    return np.array(_core.dcm_to_quat(float_array("dcm", dcm, ndim=2, shape="(3, 3)")))


def nearest_rotation(matrix: ArrayLike) -> NDArray[np.float64]:
    """The proper rotation closest to a 3 x 3 matrix in the Frobenius norm (determinant fixed to +1)."""
    return _core.nearest_rotation(float_array("matrix", matrix, ndim=2, shape="(3, 3)"))
