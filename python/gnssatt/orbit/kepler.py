"""Two-body Keplerian orbits propagated to any time, positions and velocities in ECI.

Conventions of :mod:`gnssatt.sim`: SI units and radians inside; ``t`` in seconds from the scenario epoch;
ECI is J2000-like without precession or nutation (see :mod:`gnssatt.frames`). No perturbations: the
node and perigee stay fixed in ECI. The state at ``t`` follows from the mean anomaly
``M(t) = M0 + n t`` (``n = sqrt(GM / a^3)``), Kepler's equation ``M = E - e sin E`` solved by Newton's
method, and the perifocal -> ECI rotation ``Rz(RAAN) Rx(i) Rz(omega)`` (Vallado, *Fundamentals of
Astrodynamics*, algorithm 10 "COE2RV").
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from gnssatt._arrays import MAX_BATCH_ROWS, batch_limit, checked_array, integer, readonly, scalar, time_array
from gnssatt.constants import GM_M3_S2
from gnssatt.errors import ConvergenceError, InvalidInputError, InvalidTypeError
from gnssatt.frames import matvec, rot_x, rot_z

__all__ = ["KeplerOrbits", "solve_kepler"]

#: Most Newton iterations :func:`solve_kepler` accepts (it converges in under 10 for e < 0.99).
MAX_KEPLER_ITERATIONS = 10_000
#: Largest semi-major axis accepted by :class:`KeplerOrbits`, m (about 6700 astronomical units).
MAX_SEMI_MAJOR_AXIS_M = 1e15


def check_orbital_motion(name: str, a: NDArray[np.float64], gm: float) -> None:
    """Refuses radii ``a`` whose mean motion ``sqrt(gm / a^3)`` or orbital speed ``sqrt(gm / a)`` is not a
    positive finite number (``a = 1e-300`` makes ``a^3`` zero and the mean motion infinite; a tiny ``gm``
    makes it zero), naming ``name``: the error would otherwise surface later under another name."""
    with np.errstate(over="ignore", divide="ignore", under="ignore"):
        n = np.sqrt(gm / a**3)
        v = np.sqrt(gm / a)
    bad = ~(np.isfinite(n) & (n > 0.0) & np.isfinite(v))
    if np.any(bad):
        k = int(np.argmax(bad))
        raise InvalidInputError(
            f"expected {name} whose mean motion sqrt(gm_m3_s2 / a^3) and speed sqrt(gm_m3_s2 / a) are "
            f"positive and finite, got {name} = {a.flat[k]:.6g} m with gm_m3_s2 = {gm:.6g} m^3/s^2 (mean "
            f"motion {n.flat[k]:.6g} rad/s) at index {k}"
        )


def solve_kepler(
    mean_anomaly_rad: ArrayLike, eccentricity: ArrayLike, *, tol: float = 1e-14, max_iter: int = 50
) -> NDArray[np.float64]:
    """Eccentric anomaly ``E`` solving Kepler's equation ``M = E - e sin E`` (elliptic, 0 <= e < 1).

    Parameters
    ----------
    mean_anomaly_rad
        Mean anomaly ``M`` in radians, any shape.
    eccentricity
        Eccentricity, broadcastable against ``M``, each in [0, 1).
    tol
        Convergence threshold on the Newton step, rad.
    max_iter
        Newton iterations allowed, 1 to ``MAX_KEPLER_ITERATIONS`` (10,000).

    Returns
    -------
    ``E`` in radians, broadcast shape; ``E`` lies within pi of ``M`` (same revolution).

    Raises
    ------
    InvalidInputError
        Eccentricity outside [0, 1), non-finite input, shapes that do not broadcast, ``tol`` <= 0.
    WorkLimitError
        ``max_iter`` above ``MAX_KEPLER_ITERATIONS``.
    ConvergenceError
        Newton's method did not reach ``tol`` within ``max_iter`` iterations.

    Examples
    --------
    Mean anomalies made from chosen eccentric anomalies, ``M = E - e sin E``, give them back; at apoapsis
    ``M = E = pi`` whatever the eccentricity:

    >>> import numpy as np
    >>> from gnssatt.orbit.kepler import solve_kepler
    >>> e_true, ecc = np.array([0.5, 2.0, 3.0]), np.array([0.1, 0.9, 0.5])
    >>> np.round(solve_kepler(e_true - ecc * np.sin(e_true), ecc), 12)
    array([0.5, 2. , 3. ])
    >>> round(float(solve_kepler(np.pi, 0.7)), 12)
    3.14159265359
    """
    batch_limit(
        MAX_BATCH_ROWS,
        "MAX_BATCH_ROWS",
        "anomalies",
        mean_anomaly_rad=(mean_anomaly_rad, 0),
        eccentricity=(eccentricity, 0),
    )
    m = checked_array("mean_anomaly_rad", mean_anomaly_rad, ndim=(0, 1, 2, 3), shape="(...)")
    e = checked_array("eccentricity", eccentricity, ndim=(0, 1, 2, 3), shape="(...)")
    if np.any((e < 0) | (e >= 1)):
        raise InvalidInputError(f"expected eccentricity in [0, 1), got values in [{e.min()}, {e.max()}]")
    tol = scalar("tol", tol, minimum=0.0, strict=True)
    max_iter = integer("max_iter", max_iter, minimum=1, maximum=MAX_KEPLER_ITERATIONS)
    try:
        np.broadcast_shapes(m.shape, e.shape)
    except ValueError as exc:
        raise InvalidInputError(
            f"expected eccentricity broadcastable against mean_anomaly_rad {m.shape}, got {e.shape}"
        ) from exc
    m_red = np.remainder(m + np.pi, 2 * np.pi) - np.pi  # in [-pi, pi)
    big = np.broadcast_to(e, np.broadcast(m_red, e).shape) > 0.8
    ecc = np.broadcast_to(e, big.shape)
    ea = np.where(big, np.pi * np.sign(m_red + (m_red == 0)), m_red + ecc * np.sin(m_red))
    for _ in range(max_iter):
        step = (ea - ecc * np.sin(ea) - m_red) / (1.0 - ecc * np.cos(ea))
        ea = ea - step
        if np.all(np.abs(step) <= tol * np.maximum(1.0, np.abs(ea))):
            return ea + (m - m_red)
    raise ConvergenceError(f"Kepler's equation: Newton did not converge in {max_iter} iterations")


@dataclass(frozen=True)
class KeplerOrbits:
    """Osculating Keplerian elements of n satellites at ``t = 0`` (two-body propagation).

    Attributes
    ----------
    semi_major_axis_m
        (n,) semi-major axes, m, in (0, ``MAX_SEMI_MAJOR_AXIS_M``].
    eccentricity
        (n,) eccentricities in [0, 1).
    inclination_rad, raan_rad, arg_perigee_rad, mean_anomaly_rad
        (n,) inclination, right ascension of the ascending node (ECI), argument of perigee and mean
        anomaly at ``t = 0``, radians. For a circular orbit the argument of latitude at ``t = 0`` is
        ``arg_perigee + mean_anomaly``.
    gm_m3_s2
        Gravitational parameter, m^3/s^2.
    """

    semi_major_axis_m: NDArray[np.float64]
    eccentricity: NDArray[np.float64]
    inclination_rad: NDArray[np.float64]
    raan_rad: NDArray[np.float64]
    arg_perigee_rad: NDArray[np.float64]
    mean_anomaly_rad: NDArray[np.float64]
    gm_m3_s2: float = GM_M3_S2

    def __post_init__(self) -> None:
        names = ("semi_major_axis_m", "eccentricity", "inclination_rad", "raan_rad", "arg_perigee_rad")
        arrays = [checked_array(k, getattr(self, k), ndim=(0, 1), shape="(n,)") for k in names]
        arrays.append(checked_array("mean_anomaly_rad", self.mean_anomaly_rad, ndim=(0, 1), shape="(n,)"))
        try:
            arrays = [np.array(a) for a in np.broadcast_arrays(*[np.atleast_1d(a) for a in arrays])]
        except ValueError as exc:
            shapes = [np.shape(getattr(self, k)) for k in (*names, "mean_anomaly_rad")]
            raise InvalidInputError(
                f"expected orbital elements of one common shape (n,), got {shapes}"
            ) from exc
        if np.any(arrays[0] <= 0):
            raise InvalidInputError(f"expected semi_major_axis_m > 0, got minimum {arrays[0].min()}")
        if np.any(arrays[0] > MAX_SEMI_MAJOR_AXIS_M):
            # beyond it a^3 overflows the mean motion and the period
            raise InvalidInputError(
                f"expected semi_major_axis_m <= {MAX_SEMI_MAJOR_AXIS_M} m, got maximum {arrays[0].max()}"
            )
        if np.any((arrays[1] < 0) | (arrays[1] >= 1)):
            raise InvalidInputError(f"expected eccentricity in [0, 1), got maximum {arrays[1].max()}")
        gm = scalar("gm_m3_s2", self.gm_m3_s2, minimum=0.0, strict=True)
        object.__setattr__(self, "gm_m3_s2", gm)
        check_orbital_motion("semi_major_axis_m", arrays[0], gm)
        for name, arr in zip((*names, "mean_anomaly_rad"), arrays, strict=True):
            readonly(arr)
            object.__setattr__(self, name, arr)

    @classmethod
    def circular(
        cls,
        semi_major_axis_m: ArrayLike,
        inclination_rad: ArrayLike,
        raan_rad: ArrayLike,
        arg_latitude_rad: ArrayLike,
    ) -> KeplerOrbits:
        """Circular orbits (e = 0, argument of perigee 0) from the argument of latitude at ``t = 0``."""
        u = np.atleast_1d(checked_array("arg_latitude_rad", arg_latitude_rad, ndim=(0, 1), shape="(n,)"))
        a, i, raan = (
            checked_array(k, v, ndim=(0, 1), shape="(n,)")
            for k, v in (
                ("semi_major_axis_m", semi_major_axis_m),
                ("inclination_rad", inclination_rad),
                ("raan_rad", raan_rad),
            )
        )
        return cls(a, np.zeros_like(u), i, raan, np.zeros_like(u), u)

    def __len__(self) -> int:
        return int(self.semi_major_axis_m.shape[0])

    @property
    def mean_motion_rad_s(self) -> NDArray[np.float64]:
        """(n,) mean motion ``sqrt(GM / a^3)``, rad/s."""
        return np.sqrt(self.gm_m3_s2 / self.semi_major_axis_m**3)

    @property
    def period_s(self) -> NDArray[np.float64]:
        """(n,) orbital period ``2 pi sqrt(a^3 / GM)``, s."""
        return 2.0 * np.pi / self.mean_motion_rad_s

    def subset(self, index: ArrayLike) -> KeplerOrbits:
        """The orbits selected by an integer index array or a boolean mask of shape (n,)."""
        idx = np.asarray(index)
        n = len(self)
        if idx.dtype == bool:
            if idx.shape != (n,):
                raise InvalidInputError(f"expected index as a boolean mask of shape ({n},), got {idx.shape}")
        elif idx.dtype.kind in "iu" or idx.size == 0:
            idx = idx.astype(np.int64).reshape(-1)
            if idx.size and (idx.min() < -n or idx.max() >= n):
                raise InvalidInputError(f"expected index in [-{n}, {n}), got [{idx.min()}, {idx.max()}]")
        else:
            raise InvalidTypeError(
                f"expected index as integer indices or a boolean mask, got dtype {idx.dtype}"
            )
        return KeplerOrbits(
            self.semi_major_axis_m[idx],
            self.eccentricity[idx],
            self.inclination_rad[idx],
            self.raan_rad[idx],
            self.arg_perigee_rad[idx],
            self.mean_anomaly_rad[idx],
            self.gm_m3_s2,
        )

    def dcm_eci_from_perifocal(self) -> NDArray[np.float64]:
        """(n, 3, 3) rotation perifocal (x to perigee, z along the angular momentum) -> ECI."""
        return rot_z(self.raan_rad) @ rot_x(self.inclination_rad) @ rot_z(self.arg_perigee_rad)

    def state_eci(self, t: ArrayLike) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """Position (m) and velocity (m/s) in ECI at ``t``.

        Parameters
        ----------
        t
            Seconds from the epoch, shape () or (n_t,).

        Returns
        -------
        position, velocity
            (n, 3) for a scalar ``t``, (n_t, n, 3) for an array.
        """
        tt = time_array(t)
        e = self.eccentricity
        m = self.mean_anomaly_rad + self.mean_motion_rad_s * tt[..., None]  # (..., n)
        ea = solve_kepler(m, e)
        a = self.semi_major_axis_m
        cos_e, sin_e = np.cos(ea), np.sin(ea)
        sq = np.sqrt(1.0 - e**2)
        r_pf = np.stack([a * (cos_e - e), a * sq * sin_e, np.zeros_like(ea)], axis=-1)
        edot = self.mean_motion_rad_s / (1.0 - e * cos_e)
        v_pf = np.stack([-a * sin_e * edot, a * sq * cos_e * edot, np.zeros_like(ea)], axis=-1)
        q = self.dcm_eci_from_perifocal()
        return matvec(q, r_pf), matvec(q, v_pf)
