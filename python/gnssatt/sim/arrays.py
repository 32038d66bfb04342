"""Antenna-array layouts and random attitudes / lines of sight for Monte Carlo scenarios.

Conventions of :mod:`gnssatt.sim`: SI units and radians inside (arguments in degrees end in ``_deg``);
antenna positions in the body frame relative to the vehicle's reference point, metres; attitudes are scipy
``Rotation`` objects mapping body -> reference frame.
"""

from __future__ import annotations

from typing import Literal

import numpy as np
from numpy.typing import NDArray
from scipy.spatial.transform import Rotation

from gnssatt._arrays import finite_result, generator, integer, scalar, text
from gnssatt.errors import InvalidInputError

__all__ = ["equilateral_triangle", "random_attitude", "random_los"]

_AXES = {"x": 0, "y": 1, "z": 2}

#: Most attitudes or lines of sight drawn in one call (each is a few floats; 1e7 is about 0.3 GB).
MAX_DRAWS = 10_000_000


def equilateral_triangle(side_m: float, *, plane: Literal["xy", "xz", "yz"] = "xy") -> NDArray[np.float64]:
    """Three antennas on an equilateral triangle, antenna 0 at the body origin (the reference point).

    Parameters
    ----------
    side_m
        Side length, m (Ryzhkov and Oliinyk: 1 m; Bunyaeva et al.: 0.71 m).
    plane
        Body plane ``"<a><b>"`` holding the triangle: antenna 1 at ``side * e_a`` (with the default
        ``"xy"``, on the body X axis, forward), antenna 2 at ``side * (e_a / 2 + sqrt(3) / 2 e_b)``.
        For the Bunyaeva et al. axes (X forward, Y up, Z right wing) a horizontal array is ``plane="xz"``,
        with antenna 2 to the right of the nose line.

    Returns
    -------
    (3, 3) antenna positions, body frame, m; row i is antenna i.

    Raises
    ------
    InvalidInputError
        ``side_m`` not positive and finite, ``plane`` not ``"xy"``, ``"xz"`` or ``"yz"``
        (:class:`~gnssatt.errors.InvalidTypeError` for a ``side_m`` that is not a real number or a ``plane``
        that is not text).
    ConvergenceError
        ``side_m`` so large (above about 1e308 / 1.8 m) that a coordinate overflows float64.

    Examples
    --------
    Every pair of antennas is one side apart:

    >>> import numpy as np
    >>> from gnssatt.sim.arrays import equilateral_triangle
    >>> antennas = equilateral_triangle(1.0)  # (3, 3) m, body
    >>> np.round(antennas, 6) + 0.0
    array([[0.      , 0.      , 0.      ],
           [1.      , 0.      , 0.      ],
           [0.5     , 0.866025, 0.      ]])
    >>> i, j = np.triu_indices(3, 1)
    >>> np.round(np.linalg.norm(antennas[i] - antennas[j], axis=1), 12)
    array([1., 1., 1.])
    """
    s = scalar("side_m", side_m, minimum=0.0, strict=True)
    text("plane", plane)
    if plane not in ("xy", "xz", "yz"):
        raise InvalidInputError(f"expected plane 'xy', 'xz' or 'yz', got {plane!r}")
    a, b = _AXES[plane[0]], _AXES[plane[1]]
    out = np.zeros((3, 3))
    out[1, a] = s
    out[2, a] = s / 2.0
    with np.errstate(over="ignore"):  # an overflow is reported below, as an error
        out[2, b] = s * np.sqrt(3.0) / 2.0
    # s * sqrt(3) overflows for sides within a factor 1.7 of the float limit
    return finite_result("equilateral_triangle", out, f"side_m = {s:g} m is too large for float64")


def random_attitude(rng: int | np.random.Generator | None = None, n: int | None = None) -> Rotation:
    """Attitude(s) drawn uniformly over SO(3) from ``rng`` (one ``Rotation``, or ``n`` stacked).

    Parameters
    ----------
    rng
        Source of randomness: ``np.random.default_rng(rng)``, an int seed (reproducible), a
        ``numpy.random.Generator`` (used and advanced) or None (fresh entropy).
    n
        Number of attitudes, 1 to ``MAX_DRAWS`` (1e7), or None for a single one.

    Returns
    -------
    scipy.spatial.transform.Rotation
        Body -> reference rotation: a single one for ``n=None``, else ``n`` stacked.

    Raises
    ------
    InvalidInputError
        ``rng`` not an int, Generator or None, ``n`` not an integer >= 1
        (:class:`~gnssatt.errors.WorkLimitError` above ``MAX_DRAWS``, 1e7).

    Examples
    --------
    The same seed gives the same attitude; under the uniform (Haar) distribution the trace of the rotation
    matrix has mean 0, which 100 000 draws reproduce to about 0.003:

    >>> import numpy as np
    >>> from gnssatt.sim.arrays import random_attitude
    >>> bool(np.allclose(random_attitude(7).as_quat(), random_attitude(7).as_quat()))
    True
    >>> draws = random_attitude(7, 100_000)
    >>> len(draws), bool(abs(np.trace(draws.as_matrix(), axis1=1, axis2=2).mean()) < 0.02)
    (100000, True)
    """
    rng = generator("rng", rng)
    if n is not None:
        n = integer("n", n, minimum=1, maximum=MAX_DRAWS)
    return Rotation.random(n, random_state=rng)


def random_los(
    rng: int | np.random.Generator | None, n_sat: int, *, min_elevation_deg: float = 0.0
) -> NDArray[np.float64]:
    """Unit lines of sight uniform over the spherical cap above ``min_elevation_deg`` (z is up).

    Parameters
    ----------
    rng
        Source of randomness: ``np.random.default_rng(rng)``, an int seed (reproducible), a
        ``numpy.random.Generator`` (used and advanced) or None (fresh entropy).
    n_sat
        Number of directions, 1 to ``MAX_DRAWS`` (1e7).
    min_elevation_deg
        Lowest elevation, degrees, in [-90, 90).

    Returns
    -------
    (n_sat, 3) unit vectors in a local-level frame (ENU or orbital).

    Raises
    ------
    InvalidInputError
        A negative ``rng`` seed, ``n_sat`` below 1, ``min_elevation_deg`` outside [-90, 90)
        (:class:`~gnssatt.errors.InvalidTypeError` for an ``rng`` that is not an int, Generator or None, and
        other values of the wrong type).
    WorkLimitError
        ``n_sat`` above ``MAX_DRAWS`` (1e7).

    Examples
    --------
    Unit vectors, none below the mask; uniform over the cap, their up component is uniform on
    ``[sin 15 deg, 1]``, with mean ``(sin 15 deg + 1) / 2 = 0.63``:

    >>> import numpy as np
    >>> from gnssatt.sim.arrays import random_los
    >>> los = random_los(3, 100_000, min_elevation_deg=15.0)  # (100000, 3), ENU
    >>> low = np.sin(np.radians(15.0))
    >>> bool(np.allclose(np.linalg.norm(los, axis=1), 1.0)), bool(np.all(los[:, 2] >= low))
    (True, True)
    >>> round(float(los[:, 2].mean()), 2), round(float((low + 1.0) / 2.0), 2)
    (0.63, 0.63)
    """
    rng = generator("rng", rng)
    n_sat = integer("n_sat", n_sat, minimum=1, maximum=MAX_DRAWS)
    el = scalar("min_elevation_deg", min_elevation_deg)
    if not -90.0 <= el < 90.0:
        raise InvalidInputError(f"expected min_elevation_deg in [-90, 90), got {el}")
    z = rng.uniform(np.sin(np.radians(el)), 1.0, size=n_sat)
    az = rng.uniform(0.0, 2.0 * np.pi, size=n_sat)
    c = np.sqrt(1.0 - z**2)
    return np.stack([c * np.sin(az), c * np.cos(az), z], axis=-1)
