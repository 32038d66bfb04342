"""The statistics, input limits and result types of the maximum-likelihood grid (Bunyaeva et al.); the
conventions are those of :mod:`gnssatt.attitude.likelihood`."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Literal

import numpy as np
from numpy.typing import NDArray
from scipy.spatial.transform import Rotation

from gnssatt._arrays import shaped
from gnssatt.errors import InvalidInputError

StatisticName = Literal["ambiguity_function", "mean", "double_difference"]
SearchName = Literal["auto", "exhaustive", "branch_and_bound"]
RefineName = bool | Literal["parabolic", "newton"]

#: Largest magnitude of a phase difference, radians: any multiple of 2 pi may be added, but above this the
#: float64 spacing (1.2e-4 rad) no longer carries the fraction of a cycle the statistic needs.
MAX_PHASE_RAD = 1e12
#: Carrier wavelengths are accepted in [MIN_WAVELENGTH_M, MAX_WAVELENGTH_M] (GNSS: 0.19 to 0.26 m); outside,
#: wave numbers ``2 pi / lambda`` and grid steps leave the float range long before anything physical.
MIN_WAVELENGTH_M, MAX_WAVELENGTH_M = 1e-6, 1e6
#: Window limits (degrees) are accepted within +-WINDOW_LIMIT_DEG: ten turns, room for any window written
#: around a heading, far from the integer range of the grid's node indices.
WINDOW_LIMIT_DEG = 3600.0
#: Largest grid step, degrees (coarser than a half turn is no grid).
MAX_STEP_DEG = 180.0


@dataclass(frozen=True)
class AttitudePrior:
    """A coarse attitude and the search window around it.

    Attributes
    ----------
    euler_gost_deg
        (psi, theta, phi) of eq. (5), degrees, each in [-360, 360].
    half_width_deg
        Half-widths of the window in psi, theta, phi, degrees, each in (0, 360].

    Raises
    ------
    InvalidInputError
        Wrong shapes, non-finite values or values out of the ranges above
        (:class:`~gnssatt.errors.InvalidTypeError` for values that are not real numbers).
    """

    euler_gost_deg: NDArray[np.float64]
    half_width_deg: NDArray[np.float64]

    def __post_init__(self) -> None:
        euler = shaped("euler_gost_deg", self.euler_gost_deg, "(3,)", (3,))
        half = shaped("half_width_deg", self.half_width_deg, "(3,)", (3,))
        if np.any(np.abs(euler) > 360.0):
            raise InvalidInputError(f"expected euler_gost_deg in [-360, 360] deg, got {euler}")
        if np.any(half <= 0.0) or np.any(half > 360.0):
            raise InvalidInputError(f"expected half_width_deg in (0, 360] deg, got {half}")
        object.__setattr__(self, "euler_gost_deg", euler)  # frozen: store the checked float64 copies
        object.__setattr__(self, "half_width_deg", half)

    @property
    def window_deg(self) -> NDArray[np.float64]:
        """(3, 2) ``[lo, hi]`` ranges in degrees of psi, theta, phi."""
        e, h = self.euler_gost_deg, self.half_width_deg
        return np.stack([e - h, e + h], axis=1)


@dataclass(frozen=True)
class LikelihoodAttitude:
    """Attitude from :func:`ml_attitude`.

    Attributes
    ----------
    rotation
        Body -> East-North-Up rotation.
    euler_gost_deg
        (psi, theta, phi) of eq. (5) in degrees (refined when asked); psi, phi in (-180, 180].
    grid_euler_gost_deg
        Angles of the grid maximum, degrees, the same sequence.
    z_max
        The statistic at the grid maximum.
    cells_evaluated
        Grid cells whose statistic was evaluated (branch-and-bound: kernel cells plus one per direction box
        and row block tested; refinement adds up to 6).
    step_deg
        The grid step actually used, degrees (``360 / n`` with ``n`` even).
    """

    rotation: Rotation
    euler_gost_deg: NDArray[np.float64]
    grid_euler_gost_deg: NDArray[np.float64]
    z_max: float
    cells_evaluated: int
    step_deg: float


@dataclass(frozen=True)
class BaselineDirection:
    """Direction of a single baseline from :func:`ml_baseline`.

    Attributes
    ----------
    heading_deg
        Compass heading of the baseline (clockwise from North towards East), degrees in [0, 360).
    elevation_deg
        Elevation above the horizontal plane, degrees.
    direction_enu
        Unit vector along the baseline, East-North-Up.
    z_max, cells_evaluated, step_deg
        As in :class:`LikelihoodAttitude`.
    """

    heading_deg: float
    elevation_deg: float
    direction_enu: NDArray[np.float64]
    z_max: float
    cells_evaluated: int
    step_deg: float


@dataclass(frozen=True)
class LikelihoodGrid:
    """The whole statistic from :func:`likelihood_grid`.

    Attributes
    ----------
    z
        (n_psi, n_theta, n_phi) float32 (a transposed view of the (theta, phi, psi) array the core fills).
    psi_deg, theta_deg, phi_deg
        The axes, degrees (psi and phi may run past 360 / 180 in a window that wraps).
    step_deg
        The grid step actually used, degrees (``360 / n`` with ``n`` even), also for a window holding a
        single node.
    """

    z: NDArray[np.float32]
    psi_deg: NDArray[np.float64]
    theta_deg: NDArray[np.float64]
    phi_deg: NDArray[np.float64]
    step_deg: float = field(default=0.0)

    def argmax_deg(self) -> NDArray[np.float64]:
        """(psi, theta, phi) of the grid maximum, degrees."""
        p, t, f = np.unravel_index(int(np.argmax(self.z)), self.z.shape)
        return np.array([self.psi_deg[p], self.theta_deg[t], self.phi_deg[f]])
