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
from gnssatt._arrays import (
    MAX_BATCH_ROWS,
    MAX_BATCH_VALUES,
    batch_limit,
    checked_array,
    flag,
    instance,
    shaped,
)

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

    Parameters
    ----------
    seq
        The intrinsic sequence, one of :data:`SEQUENCES` (upper case).
    angles
        (3,) the three angles, in sequence order; radians, or degrees with ``degrees``.
    degrees
        Read ``angles`` in degrees (default False: radians).

    Returns
    -------
    numpy.ndarray
        (3, 3) the body -> reference rotation matrix.

    Raises
    ------
    InvalidInputError
        ``seq`` not one of :data:`SEQUENCES`, a wrong shape or non-finite values
        (:class:`~gnssatt.errors.InvalidTypeError` for values of the wrong kind, a ``degrees`` that is not a
        bool).

    Examples
    --------
    A quarter turn about Z maps the body X axis onto the reference Y axis:

    >>> import numpy as np
    >>> from gnssatt.rotation import euler_to_dcm
    >>> np.round(euler_to_dcm("ZYX", [90.0, 0.0, 0.0], degrees=True), 12) + 0.0
    array([[ 0., -1.,  0.],
           [ 1.,  0.,  0.],
           [ 0.,  0.,  1.]])
    """
    return _core.euler_to_dcm(seq, _angles(angles, degrees))


def dcm_to_euler(seq: str, dcm: ArrayLike, *, degrees: bool = False) -> NDArray[np.float64]:
    """Angles of an intrinsic sequence; the middle one in [-90, 90] deg (Tait-Bryan) or [0, 180] deg
    (proper Euler), the others in (-180, 180].

    Parameters
    ----------
    seq
        The intrinsic sequence, one of :data:`SEQUENCES` (upper case).
    dcm
        (3, 3) body -> reference rotation matrix, orthogonal to 1e-6.
    degrees
        Return degrees (default False: radians).

    Returns
    -------
    numpy.ndarray
        (3,) the angles in sequence order, radians or degrees.

    Raises
    ------
    InvalidInputError
        ``seq`` not one of :data:`SEQUENCES`, a wrong shape or non-finite values, a ``dcm`` that is not
        orthogonal to 1e-6
        (:class:`~gnssatt.errors.InvalidTypeError` for values of the wrong kind, a ``degrees`` that is not a
        bool).

    Examples
    --------
    The inverse of :func:`euler_to_dcm` within the ranges above:

    >>> import numpy as np
    >>> from gnssatt.rotation import dcm_to_euler, euler_to_dcm
    >>> m = euler_to_dcm("ZYX", [30.0, -20.0, 10.0], degrees=True)
    >>> np.round(dcm_to_euler("ZYX", m, degrees=True), 9)
    array([ 30., -20.,  10.])
    """
    m, degrees = _dcm(dcm), flag("degrees", degrees)
    angles = np.array(_core.dcm_to_euler(seq, m))
    return np.degrees(angles) if degrees else angles


def quat_to_dcm(quat: ArrayLike) -> NDArray[np.float64]:
    """Matrix of a scalar-last quaternion ``[x, y, z, w]`` (normalised first).

    Parameters
    ----------
    quat
        (4,) scalar-last quaternion, any non-zero norm.

    Returns
    -------
    numpy.ndarray
        (3, 3) the rotation matrix of the normalised quaternion.

    Raises
    ------
    InvalidInputError
        A wrong shape, non-finite values or a zero quaternion (:class:`~gnssatt.errors.InvalidTypeError`
        for values that are not real numbers).

    Examples
    --------
    ``[0, 0, 1, 1]`` normalised is a quarter turn about Z (half-angle 45 deg):

    >>> import numpy as np
    >>> from gnssatt.rotation import quat_to_dcm
    >>> np.round(quat_to_dcm([0.0, 0.0, 1.0, 1.0]), 12) + 0.0
    array([[ 0., -1.,  0.],
           [ 1.,  0.,  0.],
           [ 0.,  0.,  1.]])
    """
    q = shaped("quat", quat, "(4,)", (4,))
    return _core.quat_to_dcm((float(q[0]), float(q[1]), float(q[2]), float(q[3])))


def dcm_to_quat(dcm: ArrayLike) -> NDArray[np.float64]:
    """Scalar-last unit quaternion ``[x, y, z, w]`` with ``w >= 0``.

    Parameters
    ----------
    dcm
        (3, 3) rotation matrix, orthogonal to 1e-6.

    Returns
    -------
    numpy.ndarray
        (4,) the unit quaternion, ``w >= 0`` (of the two signs, the one with the non-negative scalar).

    Raises
    ------
    InvalidInputError
        A wrong shape, non-finite values or a ``dcm`` that is not orthogonal to 1e-6
        (:class:`~gnssatt.errors.InvalidTypeError` for values that are not real numbers).

    Examples
    --------
    A half turn about X:

    >>> import numpy as np
    >>> from gnssatt.rotation import dcm_to_quat
    >>> np.round(dcm_to_quat(np.diag([1.0, -1.0, -1.0])), 12) + 0.0
    array([1., 0., 0., 0.])
    """
    return np.array(_core.dcm_to_quat(_dcm(dcm)))


def nearest_rotation(matrix: ArrayLike) -> NDArray[np.float64]:
    """The proper rotation closest to a 3 x 3 matrix in the Frobenius norm (determinant fixed to +1).

    Parameters
    ----------
    matrix
        (3, 3) any real matrix of rank 2 or more, e.g. an estimate of a rotation spoiled by noise.

    Returns
    -------
    numpy.ndarray
        (3, 3) the nearest proper rotation matrix.

    Raises
    ------
    InvalidInputError
        A wrong shape or non-finite values (:class:`~gnssatt.errors.InvalidTypeError` for values that are
        not real numbers).
    DegenerateGeometryError
        A matrix whose nearest rotation is not unique (rank below 2, e.g. zero).

    Examples
    --------
    A rotation scaled by 3 has that rotation as its nearest:

    >>> import numpy as np
    >>> from gnssatt.rotation import nearest_rotation
    >>> quarter_z = np.array([[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]])
    >>> bool(np.allclose(nearest_rotation(3.0 * quarter_z), quarter_z, atol=1e-12))
    True
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
    WorkLimitError
        More than :data:`gnssatt._arrays.MAX_BATCH_VALUES` angles, refused before they are copied.

    Examples
    --------
    >>> import numpy as np
    >>> from gnssatt.rotation import wrap_rad
    >>> np.round(wrap_rad([np.pi, 1.5 * np.pi, -0.5]), 4)
    array([-3.1416, -1.5708, -0.5   ])
    """
    batch_limit(MAX_BATCH_VALUES, "MAX_BATCH_VALUES", "angles", x=(x, 0))
    arr = checked_array("x", x, ndim=tuple(range(33)), shape="(...)")
    return (arr + np.pi) % (2.0 * np.pi) - np.pi


#: Rows of ``R_normal`` reordered (N, U, E) -> (E, N, U): the GOST normal frame of Bunyaeva et al. into ENU.
ENU_FROM_NORMAL = np.array([[0.0, 0.0, 1.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]])


def rotation_from_euler(euler_gost_deg: ArrayLike) -> Rotation:
    """Body -> ENU rotation of eq. (5) angles ``(psi, theta, phi)`` in degrees, (3,) or (n, 3): the GOST
    ``YZX`` sequence in the normal frame (``docs/conventions.md``, ``euler_gost_deg``).

    Parameters
    ----------
    euler_gost_deg
        (3,) or (n, 3) ``(psi, theta, phi)``, degrees: psi about the normal frame's Y (up), theta about the
        new Z, phi about the new X (body X nose, Y up, Z right wing).

    Returns
    -------
    scipy.spatial.transform.Rotation
        The body -> ENU rotation, one or a stack of n.

    Raises
    ------
    InvalidInputError
        Wrong shape or non-finite angles (:class:`~gnssatt.errors.InvalidTypeError` for values that are not
        real numbers).
    WorkLimitError
        More than :data:`gnssatt._arrays.MAX_BATCH_ROWS` rows, refused before they are copied.

    Examples
    --------
    ``psi = 90`` deg turns the nose from North (the normal frame's X) to West (compass heading ``-psi``); the
    body's up axis stays up:

    >>> import numpy as np
    >>> from gnssatt.rotation import rotation_from_euler
    >>> r = rotation_from_euler([90.0, 0.0, 0.0])
    >>> np.round(r.apply([[1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]), 12) + 0.0
    array([[-1.,  0.,  0.],
           [ 0.,  0.,  1.]])
    """
    batch_limit(MAX_BATCH_ROWS, "MAX_BATCH_ROWS", "attitudes", euler_gost_deg=(euler_gost_deg, 1))
    angles = shaped("euler_gost_deg", euler_gost_deg, "(3,) or (n, 3)", (3,), (None, 3))
    r_normal = Rotation.from_euler("YZX", angles, degrees=True).as_matrix()
    return Rotation.from_matrix(ENU_FROM_NORMAL @ r_normal)


def euler_from_rotation(rotation: Rotation) -> NDArray[np.float64]:
    """Eq. (5) angles ``(psi, theta, phi)`` in degrees of a body -> ENU rotation (single or a stack): the
    inverse of :func:`rotation_from_euler`.

    Parameters
    ----------
    rotation
        A body -> ENU rotation, single or a stack.

    Returns
    -------
    numpy.ndarray
        (3,) or (n, 3) ``(psi, theta, phi)``, degrees (scipy's ``YZX`` ranges: theta in [-90, 90]).

    Raises
    ------
    InvalidTypeError
        ``rotation`` is not a scipy :class:`~scipy.spatial.transform.Rotation`.

    Examples
    --------
    >>> import numpy as np
    >>> from gnssatt.rotation import euler_from_rotation, rotation_from_euler
    >>> np.round(euler_from_rotation(rotation_from_euler([[10.0, 20.0, 30.0], [-45.0, 5.0, 0.0]])), 9)
    array([[ 10.,  20.,  30.],
           [-45.,   5.,   0.]])
    """
    r = instance("rotation", rotation, Rotation, "a scipy Rotation")
    r_normal = ENU_FROM_NORMAL.T @ r.as_matrix()
    return np.asarray(Rotation.from_matrix(r_normal).as_euler("YZX", degrees=True))
