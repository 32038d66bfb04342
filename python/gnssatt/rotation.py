"""Rotation utilities of the Rust core, in the conventions of ``docs/conventions.md``.

Matrices are active body -> reference maps (like :meth:`scipy.spatial.transform.Rotation.as_matrix`);
Euler sequences are intrinsic (scipy's upper-case axes); quaternions are scalar-last ``[x, y, z, w]``.
scipy's :class:`~scipy.spatial.transform.Rotation` remains the public currency of results; these functions
exist so the papers' sequences can be checked against an implementation that is not scipy's.

The GOST 20058-80 angles of Bunyaeva et al. (:func:`rotation_from_euler`, :func:`euler_from_rotation`) live
here, below both the estimator that searches them (:mod:`gnssatt.attitude.likelihood`) and the simulator that
writes their truth.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.spatial.transform import Rotation

from gnssatt import _core
from gnssatt._arrays import checked_array, choice, flag, instance, shaped

__all__ = [
    "ENU_FROM_NORMAL",
    "SEQUENCES",
    "dcm_to_euler",
    "dcm_to_quat",
    "euler_from_rotation",
    "euler_to_dcm",
    "nearest_rotation",
    "quat_to_dcm",
    "rotation_from_euler",
    "wrap_rad",
]

#: The intrinsic sequences, upper case only: scipy reads lower case as extrinsic, which these are not.
SEQUENCES = (
    *("XYZ", "XZY", "YXZ", "YZX", "ZXY", "ZYX"),  # Tait-Bryan
    *("XYX", "XZX", "YXY", "YZY", "ZXZ", "ZYZ"),  # proper Euler
)


def _seq(seq: str) -> str:
    return choice("seq", seq, SEQUENCES)


def _angles(angles: ArrayLike, degrees: bool) -> tuple[float, float, float]:
    a = shaped("angles", angles, "(3,)", (3,))
    a = np.radians(a) if flag("degrees", degrees) else a
    return (float(a[0]), float(a[1]), float(a[2]))


def _dcm(dcm: ArrayLike) -> NDArray[np.float64]:
    return shaped("dcm", dcm, "(3, 3)", (3, 3))


def euler_to_dcm(seq: str, angles: ArrayLike, *, degrees: bool = False) -> NDArray[np.float64]:
    """Body -> reference matrix ``R_a1(angle1) R_a2(angle2) R_a3(angle3)`` of an intrinsic sequence such
    as ``"ZYX"`` (Ryzhkov and Oliinyk; Ryzhkov and Holembiovskyi), ``"YZX"`` (Bunyaeva et al., GOST normal
    frame) or ``"YZY"`` (Belokonov et al.).

    Raises
    ------
    InvalidInputError
        ``seq`` not one of :data:`SEQUENCES`, a wrong shape or non-finite values
        (:class:`~gnssatt.errors.InvalidTypeError` for values of the wrong kind, a ``degrees`` that is not a
        bool).
    """
    return _core.euler_to_dcm(_seq(seq), _angles(angles, degrees))


def dcm_to_euler(seq: str, dcm: ArrayLike, *, degrees: bool = False) -> NDArray[np.float64]:
    """Angles of an intrinsic sequence; the middle one in [-90, 90] deg (Tait-Bryan) or [0, 180] deg
    (proper Euler), the others in (-180, 180].

    Raises
    ------
    InvalidInputError
        ``seq`` not one of :data:`SEQUENCES`, a wrong shape or non-finite values, a ``dcm`` that is not
        orthogonal to 1e-6
        (:class:`~gnssatt.errors.InvalidTypeError` for values of the wrong kind, a ``degrees`` that is not a
        bool).
    """
    seq, m, degrees = _seq(seq), _dcm(dcm), flag("degrees", degrees)
    angles = np.array(_core.dcm_to_euler(seq, m))
    return np.degrees(angles) if degrees else angles


def quat_to_dcm(quat: ArrayLike) -> NDArray[np.float64]:
    """Matrix of a scalar-last quaternion ``[x, y, z, w]`` (normalised first).

    Raises
    ------
    InvalidInputError
        A wrong shape, non-finite values or a zero quaternion (:class:`~gnssatt.errors.InvalidTypeError`
        for values that are not real numbers).
    """
    q = shaped("quat", quat, "(4,)", (4,))
    return _core.quat_to_dcm((float(q[0]), float(q[1]), float(q[2]), float(q[3])))


def dcm_to_quat(dcm: ArrayLike) -> NDArray[np.float64]:
    """Scalar-last unit quaternion ``[x, y, z, w]`` with ``w >= 0``.

    Raises
    ------
    InvalidInputError
        A wrong shape, non-finite values or a ``dcm`` that is not orthogonal to 1e-6
        (:class:`~gnssatt.errors.InvalidTypeError` for values that are not real numbers).
    """
    return np.array(_core.dcm_to_quat(_dcm(dcm)))


def nearest_rotation(matrix: ArrayLike) -> NDArray[np.float64]:
    """The proper rotation closest to a 3 x 3 matrix in the Frobenius norm (determinant fixed to +1).

    Raises
    ------
    InvalidInputError
        A wrong shape or non-finite values (:class:`~gnssatt.errors.InvalidTypeError` for values that are
        not real numbers).
    DegenerateGeometryError
        A matrix whose nearest rotation is not unique (rank below 2, e.g. zero).
    """
    m = shaped("matrix", matrix, "(3, 3)", (3, 3))
    # the nearest rotation of c M is that of M for any c > 0: scale to entries of order one, so that the
    # core's products neither overflow nor underflow
    big = float(np.max(np.abs(m)))
    return _core.nearest_rotation(m / big if big > 0.0 else m)


def wrap_rad(x: Any) -> NDArray[np.float64]:
    """Angles (rad, any shape, finite) wrapped to [-pi, pi).

    Parameters
    ----------
    x
        Angles, rad, any shape.

    Returns
    -------
    ndarray
        ``x`` wrapped to [-pi, pi), same shape.

    Raises
    ------
    InvalidInputError
        Non-finite or non-numeric values.

    Examples
    --------
    >>> import numpy as np
    >>> from gnssatt.rotation import wrap_rad
    >>> np.round(wrap_rad([np.pi, 1.5 * np.pi, -0.5]), 4)
    array([-3.1416, -1.5708, -0.5   ])
    """
    arr = checked_array("x", x, ndim=tuple(range(33)), shape="(...)")
    return (arr + np.pi) % (2.0 * np.pi) - np.pi


#: Rows of ``R_normal`` reordered (N, U, E) -> (E, N, U): the GOST normal frame of Bunyaeva et al. into ENU.
ENU_FROM_NORMAL = np.array([[0.0, 0.0, 1.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]])


def rotation_from_euler(euler_gost_deg: ArrayLike) -> Rotation:
    """Body -> ENU rotation of eq. (5) angles ``(psi, theta, phi)`` in degrees, (3,) or (n, 3): the GOST
    ``YZX`` sequence in the normal frame (``docs/conventions.md``, ``euler_gost_deg``). Also importable
    from :mod:`gnssatt.attitude.likelihood`, its former home.

    Raises
    ------
    InvalidInputError
        Wrong shape or non-finite angles (:class:`~gnssatt.errors.InvalidTypeError` for values that are not
        real numbers).
    """
    angles = shaped("euler_gost_deg", euler_gost_deg, "(3,) or (n, 3)", (3,), (None, 3))
    r_normal = Rotation.from_euler("YZX", angles, degrees=True).as_matrix()
    return Rotation.from_matrix(ENU_FROM_NORMAL @ r_normal)


def euler_from_rotation(rotation: Rotation) -> NDArray[np.float64]:
    """Eq. (5) angles ``(psi, theta, phi)`` in degrees of a body -> ENU rotation (single or a stack): the
    inverse of :func:`rotation_from_euler`. Also importable from :mod:`gnssatt.attitude.likelihood`.

    Raises
    ------
    InvalidTypeError
        ``rotation`` is not a scipy :class:`~scipy.spatial.transform.Rotation`.
    """
    r = instance("rotation", rotation, Rotation, "a scipy Rotation")
    r_normal = ENU_FROM_NORMAL.T @ r.as_matrix()
    return np.asarray(Rotation.from_matrix(r_normal).as_euler("YZX", degrees=True))
