"""Geometry shared by the estimators: the intake of antenna baselines (:func:`checked_baselines`, with the
length limits every estimator applies) and how well an array and a set of lines of sight fix an attitude
(Cramer-Rao bound of range-difference attitude)."""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.spatial.transform import Rotation

from gnssatt._arrays import batch_limit, instance, shaped, unit_rows
from gnssatt.errors import DegenerateGeometryError, InvalidInputError

__all__ = [
    "MAX_BASELINES",
    "MAX_BASELINE_M",
    "MAX_SIGNALS",
    "MIN_BASELINE_M",
    "attitude_dop",
    "range_difference_fisher",
]

#: Shortest baseline any estimator accepts, m: below a micrometre a baseline is a zero (and the squares and
#: inverses the estimators form underflow or overflow near 1e-150 m).
MIN_BASELINE_M = 1e-6
#: Longest baseline any estimator accepts, m (the Earth's diameter): range differences, informations (fourth
#: power of the length) and grid steps then stay far from overflow.
MAX_BASELINE_M = 1.3e7
#: Most baselines (antennas but the reference) one estimator call takes, counted from the shape before the
#: baselines are copied: arrays have 2-16 antennas, and the per-epoch estimators' work grows with baselines x
#: lines of sight (``docs/limits.md``).
MAX_BASELINES = 1024
#: Most lines of sight (signals) of one epoch that a per-epoch estimator takes, counted from the shape before
#: they are copied: all constellations on all frequencies are under 600; 1024 x 4096 pairs of the Fisher
#: information take about 8 s on the loaded 2-core build machine (1.8 us a pair, ``docs/limits.md``).
MAX_SIGNALS = 4096


def checked_baselines(name: str, value: ArrayLike) -> NDArray[np.float64]:
    """``value`` as (m, 3) antenna baselines, metres, each between :data:`MIN_BASELINE_M` and
    :data:`MAX_BASELINE_M` long: the one intake of baselines for every estimator.

    Raises
    ------
    InvalidInputError
        Wrong shape, non-finite values, a baseline shorter or longer than the limits (the message names the
        row and its length); :class:`~gnssatt.errors.InvalidTypeError` for values that are not real numbers.
    WorkLimitError
        More than :data:`MAX_BASELINES` rows, refused before they are copied.
    """
    batch_limit(MAX_BASELINES, "MAX_BASELINES", "baselines", **{name: (value, 1)})
    b = shaped(name, value, "(m, 3)", (None, 3))
    # the largest component first, so that the squares neither overflow (1e200 m) nor underflow (1e-200 m)
    big = np.max(np.abs(b), axis=1, initial=0.0)
    length = big * np.linalg.norm(b / np.where(big > 0.0, big, 1.0)[:, None], axis=1)
    bad = np.flatnonzero((length < MIN_BASELINE_M) | (length > MAX_BASELINE_M))
    if bad.size:
        k = int(bad[0])
        raise InvalidInputError(
            f"expected {name} between {MIN_BASELINE_M:g} and {MAX_BASELINE_M:g} m long, baseline {k} has "
            f"length {length[k]:.6g} m"
        )
    return b


def range_difference_fisher(baselines: ArrayLike, los: ArrayLike, rotation: Rotation) -> NDArray[np.float64]:
    """Fisher information (3, 3) of a small rotation vector for unit-variance range differences.

    The measurement is ``dr_ij = (M b_i) . s_j`` with ``M`` the body -> reference rotation; perturbing
    ``M -> exp([delta]x) M`` with ``delta`` in the reference frame gives the gradient ``(M b_i) x s_j``, so
    the information is ``sum_ij g_ij g_ij^T`` (rad^-2 per m^-2 of range-difference variance).

    Parameters
    ----------
    baselines
        (m, 3) antenna positions relative to the reference antenna, body frame, metres; each between
        :data:`MIN_BASELINE_M` and :data:`MAX_BASELINE_M` long.
    los
        (n, 3) unit lines of sight, reference frame.
    rotation
        A single body -> reference :class:`~scipy.spatial.transform.Rotation`.

    Returns
    -------
    numpy.ndarray
        (3, 3) symmetric information matrix, reference frame, rad^-2 per m^-2 of range-difference variance.

    Raises
    ------
    InvalidInputError
        Wrong shapes, non-finite values, lines of sight that are not unit vectors, baselines outside the
        length limits; :class:`~gnssatt.errors.InvalidTypeError` for a ``rotation`` that is not a single
        Rotation.
    WorkLimitError
        More than :data:`MAX_BASELINES` baselines or :data:`MAX_SIGNALS` lines of sight, refused before
        they are copied.

    Examples
    --------
    Unit baselines and lines of sight along the three axes: each cross product ``e_i x e_j`` (``i != j``)
    is a unit axis, every axis twice, so ``J = 2 I``:

    >>> import numpy as np
    >>> from scipy.spatial.transform import Rotation
    >>> from gnssatt.geometry import range_difference_fisher
    >>> bool(np.allclose(range_difference_fisher(np.eye(3), np.eye(3), Rotation.identity()), 2 * np.eye(3)))
    True
    """
    batch_limit(MAX_SIGNALS, "MAX_SIGNALS", "lines of sight", los=(los, 1))
    b = checked_baselines("baselines", baselines)
    s = unit_rows("los", los, "(n, 3)", (None, 3))
    r = instance("rotation", rotation, Rotation, "a single scipy Rotation")
    if not r.single:
        raise InvalidInputError(f"expected rotation as a single Rotation, got a stack of {len(r)}")
    g: NDArray[np.float64] = np.cross(r.apply(b)[:, None, :], s[None, :, :]).reshape(-1, 3)
    fisher: NDArray[np.float64] = g.T @ g  # numpy types this matmul as Any
    return fisher


def attitude_dop(baselines: ArrayLike, los: ArrayLike, rotation: Rotation) -> float:
    """Attitude dilution of precision: ``sqrt(trace(J^-1))`` with ``J`` from :func:`range_difference_fisher`.

    Multiplied by the range-difference noise sigma (m) it gives the Cramer-Rao bound on the RMS total
    rotation error (rad) of any unbiased estimator.

    Parameters
    ----------
    baselines
        (m, 3) antenna positions relative to the reference antenna, body frame, metres (m >= 1), as
        :func:`range_difference_fisher` takes them.
    los
        (n, 3) unit lines of sight, reference frame (n >= 1).
    rotation
        A single body -> reference :class:`~scipy.spatial.transform.Rotation`.

    Returns
    -------
    float
        The attitude DOP, rad per metre of range-difference sigma.

    Raises
    ------
    InvalidInputError
        As :func:`range_difference_fisher`; also no baselines or no lines of sight (shape (0, 3)).
    DegenerateGeometryError
        The geometry does not fix the attitude (all baselines or all lines of sight parallel).

    Examples
    --------
    The geometry of :func:`range_difference_fisher`'s example, ``J = 2 I``: ``sqrt(3 / 2)``:

    >>> import numpy as np
    >>> from scipy.spatial.transform import Rotation
    >>> from gnssatt.geometry import attitude_dop
    >>> abs(attitude_dop(np.eye(3), np.eye(3), Rotation.identity()) - 1.5**0.5) < 1e-12
    True
    """
    batch_limit(MAX_SIGNALS, "MAX_SIGNALS", "lines of sight", los=(los, 1))
    b = checked_baselines("baselines", baselines)
    s = unit_rows("los", los, "(n, 3)", (None, 3))
    for name, arr, dim in (("baselines", b, "m"), ("los", s, "n")):
        if len(arr) == 0:
            raise InvalidInputError(f"expected {name} of shape ({dim}, 3) with {dim} >= 1, got {arr.shape}")
    info = range_difference_fisher(b, s, rotation)
    eig = np.linalg.eigvalsh(info)
    # eig[0] > 0 does not make 1 / eig finite: a subnormal information (baselines near 1e-160 m) overflows
    with np.errstate(over="ignore", divide="ignore"):
        dop = float(np.sqrt(np.sum(1.0 / eig))) if eig[0] > 1e-12 * eig[-1] else float("inf")
    if not np.isfinite(dop):
        raise DegenerateGeometryError(
            f"baselines {b.shape} and los {s.shape} do not fix the attitude: the Fisher information has "
            f"eigenvalues {eig[0]:.3e} to {eig[-1]:.3e} rad^-2 m^-2 (condition number above 1e12, or too "
            "small to invert); expected baselines not all parallel and los not all parallel"
        )
    return dop
