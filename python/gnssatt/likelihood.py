"""Maximum-likelihood attitude from raw carrier phases over a grid of Euler angles (seed 001).

Bunyaeva, Piskorzh, Cheranovsky (KhAI): sufficient statistics (8)-(14), (17)-(18), grid step (15),
refinement (16). The grid runs in the Rust core (float32, polynomial sine/cosine with absolute error below
1e-6, SIMD across heading nodes, rayon across rows, GIL released); set the thread count with the
``RAYON_NUM_THREADS`` environment variable before the first call.

Conventions
-----------
Body axes: X forward (nose), Y up, Z right wing. The Euler angles ``(psi, theta, phi)`` are those of eq. (5),
the GOST 20058-80 heading, pitch and roll written in the normal frame (North, Up, East):
``R_normal_from_body = Ry(psi) Rz(theta) Rx(phi)`` (scipy ``Rotation.from_euler("YZX", [psi, theta, phi])``).
At zero angles the nose points North and the right wing East; positive ``psi`` turns the nose West (the
compass heading is ``-psi``), positive ``theta`` raises the nose, positive ``phi`` lowers the right wing.
``.rotation`` maps body vectors to East-North-Up: ``R_enu_from_body = P R_normal_from_body`` with ``P`` the
permutation (N, U, E) -> (E, N, U).

Measurements: ``phase_diffs[i, k]`` is the carrier phase (radians) at antenna ``i + 1`` minus antenna 0 for
satellite ``k``, RINEX sign (an antenna displaced by ``d`` towards the satellite has its phase lowered by
``2 pi (d . los_k) / lambda_k``), any multiple of 2 pi added, plus an unknown oscillator phase per baseline.

Statistics
----------
``"ambiguity_function"`` (default): ``Z = sum_i |sum_k exp(j[phase_diff_ik + 2 pi / lambda_k los_k . R
r_i])|``, the oscillator phases maximised out per baseline; works on wrapped phases. With several epochs of
a static platform the oscillator phases are taken as constant over the batch (one nuisance phase per
baseline), so the epochs are summed inside the modulus; if the receivers' oscillators drift between epochs,
pass the epochs one at a time. ``"mean"``: eqs. (10)-(14) as written; the satellite-mean of *wrapped* phases
leaves a per-antenna offset ``2 pi (sum of integers) / M`` and the peak moves (tens of degrees): it works
only on phases whose integer cycles are already consistent. ``"double_difference"``: eqs. (17)-(18) against
the highest-elevation satellite of each epoch; immune to wrapping, about 1.8 times the variance of the
ambiguity function for M = 8.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.spatial.transform import Rotation

from gnssatt import _core
from gnssatt._arrays import float_array
from gnssatt.errors import InvalidInputError

__all__ = [
    "AttitudePrior",
    "BaselineDirection",
    "LikelihoodAttitude",
    "LikelihoodGrid",
    "likelihood_grid",
    "ml_attitude",
    "ml_baseline",
    "prior_from_velocity",
]

StatisticName = Literal["ambiguity_function", "mean", "double_difference"]
SearchName = Literal["auto", "exhaustive", "branch_and_bound"]
RefineName = bool | Literal["parabolic", "newton"]

#: Rows of ``R_normal`` reordered (N, U, E) -> (E, N, U).
ENU_FROM_NORMAL = np.array([[0.0, 0.0, 1.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]])


def rotation_from_euler(euler_deg: ArrayLike) -> Rotation:
    """Body -> ENU rotation of eq. (5) angles ``(psi, theta, phi)`` in degrees."""
    r_normal = Rotation.from_euler("YZX", np.asarray(euler_deg, dtype=float), degrees=True).as_matrix()
    return Rotation.from_matrix(ENU_FROM_NORMAL @ r_normal)


def euler_from_rotation(rotation: Rotation) -> NDArray[np.float64]:
    """Eq. (5) angles ``(psi, theta, phi)`` in degrees of a body -> ENU rotation."""
    r_normal = ENU_FROM_NORMAL.T @ rotation.as_matrix()
    return np.asarray(Rotation.from_matrix(r_normal).as_euler("YZX", degrees=True))


@dataclass(frozen=True)
class AttitudePrior:
    """A coarse attitude and the search window around it.

    Attributes
    ----------
    euler_deg
        (psi, theta, phi) of eq. (5), degrees.
    half_width_deg
        Half-widths of the window in psi, theta, phi, degrees.
    """

    euler_deg: NDArray[np.float64]
    half_width_deg: NDArray[np.float64]

    @property
    def window_deg(self) -> NDArray[np.float64]:
        """(3, 2) ``[lo, hi]`` ranges in degrees of psi, theta, phi."""
        return np.stack([self.euler_deg - self.half_width_deg, self.euler_deg + self.half_width_deg], axis=1)


@dataclass(frozen=True)
class LikelihoodAttitude:
    """Attitude from :func:`ml_attitude`.

    Attributes
    ----------
    rotation
        Body -> East-North-Up rotation.
    euler_deg
        (psi, theta, phi) of eq. (5) in degrees (refined when asked); psi, phi in (-180, 180].
    grid_euler_deg
        Angles of the grid maximum, degrees.
    z_max
        The statistic at the grid maximum.
    cells_evaluated
        Grid cells whose statistic was evaluated (branch-and-bound: kernel cells plus one per direction box
        and row block tested; refinement adds up to 6).
    step_deg
        The grid step actually used, degrees (``360 / n`` with ``n`` even).
    """

    rotation: Rotation
    euler_deg: NDArray[np.float64]
    grid_euler_deg: NDArray[np.float64]
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


def _intake(
    phase_diffs: ArrayLike,
    los: ArrayLike,
    baselines: ArrayLike,
    wavelength: ArrayLike,
    *,
    n_baselines: int | None,
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
    p = float_array("phase_diffs", phase_diffs, ndim=(2, 3), shape="(m, M) or (epochs, m, M)")
    if p.ndim == 2:
        p = p[None]
    ne, nb, m = p.shape
    s = float_array("los", los, ndim=(2, 3), shape="(M, 3) or (epochs, M, 3)")
    if s.ndim == 2:
        s = np.broadcast_to(s, (ne, *s.shape))
    if s.shape != (ne, m, 3):
        raise InvalidInputError(f"expected los of shape ({m}, 3) or ({ne}, {m}, 3), got {s.shape}")
    b = float_array("baselines", baselines, ndim=2, shape="(m, 3)")
    if b.shape[1] != 3 or b.shape[0] != nb:
        raise InvalidInputError(f"expected baselines of shape ({nb}, 3) to match phase_diffs, got {b.shape}")
    if n_baselines is not None and nb < n_baselines:
        raise InvalidInputError(f"expected at least {n_baselines} baselines (m, 3), got {b.shape}")
    w = float_array("wavelength", wavelength, ndim=(0, 1, 2), shape="scalar, (M,) or (epochs, M)")
    try:
        w = np.broadcast_to(w, (ne, m))
    except ValueError as exc:
        raise InvalidInputError(f"expected wavelength as a scalar or of shape ({m},), got {w.shape}") from exc
    return p, np.ascontiguousarray(s), np.ascontiguousarray(w), b


def _window(window_deg: ArrayLike | AttitudePrior | None) -> list[list[float]] | None:
    if window_deg is None:
        return None
    if isinstance(window_deg, AttitudePrior):
        window_deg = window_deg.window_deg
    w = float_array("window_deg", window_deg, ndim=2, shape="(3, 2)")
    if w.shape != (3, 2):
        raise InvalidInputError(
            f"expected window_deg of shape (3, 2) ([lo, hi] of psi, theta, phi), got {w.shape}"
        )
    return [[float(v) for v in row] for row in np.radians(w)]


def _step(step_deg: float | None) -> float | None:
    if step_deg is None:
        return None
    step = float(step_deg)
    if not np.isfinite(step) or step <= 0:
        raise InvalidInputError(f"expected a positive step_deg, got {step_deg}")
    return float(np.radians(step))


def _refine(refine: RefineName) -> str:
    if refine is True:
        return "newton"
    if refine is False:
        return "none"
    if refine in ("parabolic", "newton"):
        return refine
    raise InvalidInputError(f"expected refine True, False, 'parabolic' or 'newton', got {refine!r}")


def ml_attitude(
    phase_diffs: ArrayLike,
    los: ArrayLike,
    baselines: ArrayLike,
    wavelength: ArrayLike,
    *,
    statistic: StatisticName = "ambiguity_function",
    step_deg: float | None = None,
    window_deg: ArrayLike | AttitudePrior | None = None,
    search: SearchName = "auto",
    refine: RefineName = True,
) -> LikelihoodAttitude:
    """Maximum-likelihood attitude over a grid of Euler angles (seed 001).

    Parameters
    ----------
    phase_diffs
        (m, M) radians, or (epochs, m, M) for a static platform: phase at antenna ``i + 1`` minus antenna 0
        for satellite ``k`` (module docs: sign, wrapping, oscillator phases).
    los
        (M, 3) unit lines of sight in East-North-Up, or (epochs, M, 3).
    baselines
        (m, 3) antenna positions relative to antenna 0, body frame, metres; m >= 2, not collinear.
    wavelength
        Metres: a scalar, or (M,) per satellite (GLONASS FDMA), or (epochs, M).
    statistic
        ``"ambiguity_function"`` (default), ``"mean"`` or ``"double_difference"`` (module docs).
    step_deg
        Grid step in degrees; ``None`` uses eq. (15) with factor 10, ``lambda_min / (10 L_max)``. The step
        actually used is ``360 / n`` with ``n = 2 ceil(180 / step_deg)``. Steps coarser than
        ``lambda_min / (2 L_max)`` are refused.
    window_deg
        ``None`` (the whole attitude domain), a (3, 2) array of ``[lo, hi]`` degrees for psi, theta, phi,
        or an :class:`AttitudePrior` (:func:`prior_from_velocity`).
    search
        ``"auto"`` (default): branch-and-bound for the ambiguity function on grids of at least 2**22 cells
        with a step of at most ``lambda_min / (8 L_max)``, the exhaustive pass otherwise.
        ``"exhaustive"``: every cell, in parallel. ``"branch_and_bound"``: exact (the same grid cell and
        ``z_max`` as the exhaustive pass, bit for bit), parallel, through per-baseline direction sets; it
        falls back to the exhaustive pass for the per-satellite statistics and where its bounding work
        would exceed one box per 256 cells (``docs/likelihood_search.md``).
    refine
        ``True`` or ``"newton"`` (default): the parabolic interpolation (16), then Newton's method on the
        statistic (float64, full Hessian, trust region of one grid step), i.e. the continuous maximum of
        ``Z``. ``"parabolic"``: eq. (16) alone, one parabola per axis with wrap-around in heading and roll;
        because the axes of eq. (5) are coupled it leaves errors of a fraction of a step even without
        noise. ``False``: the grid node.

    Raises
    ------
    InvalidInputError
        Non-finite values, mismatched shapes, fewer than 3 satellites, zero baselines, non-positive
        wavelengths, a step coarser than the main lobe, an empty window.
    DegenerateGeometryError
        Collinear baselines.
    """
    p, s, w, b = _intake(phase_diffs, los, baselines, wavelength, n_baselines=2)
    angles, grid_angles, z, cells, step, _ = _core.ml_search(
        p, s, w, b, statistic, _step(step_deg), _window(window_deg), search, _refine(refine), False
    )
    euler = np.degrees(angles)
    return LikelihoodAttitude(
        rotation=rotation_from_euler(euler),
        euler_deg=euler,
        grid_euler_deg=np.degrees(grid_angles),
        z_max=float(z),
        cells_evaluated=int(cells),
        step_deg=float(np.degrees(step)),
    )


def likelihood_grid(
    phase_diffs: ArrayLike,
    los: ArrayLike,
    baselines: ArrayLike,
    wavelength: ArrayLike,
    *,
    statistic: StatisticName = "ambiguity_function",
    step_deg: float | None = None,
    window_deg: ArrayLike | AttitudePrior | None = None,
) -> LikelihoodGrid:
    """The statistic on the whole grid (float32), for plots and inspection; inputs as :func:`ml_attitude`."""
    p, s, w, b = _intake(phase_diffs, los, baselines, wavelength, n_baselines=1)
    z, psi, theta, phi = _core.likelihood_grid(
        p, s, w, b, statistic, _step(step_deg), _window(window_deg), b.shape[0] == 1
    )
    return LikelihoodGrid(
        z=np.transpose(z, (2, 0, 1)),
        psi_deg=np.degrees(psi),
        theta_deg=np.degrees(theta),
        phi_deg=np.degrees(phi),
        step_deg=float(np.degrees(psi[1] - psi[0])) if len(psi) > 1 else float("nan"),
    )


def ml_baseline(
    phase_diffs: ArrayLike,
    los: ArrayLike,
    baseline_length_m: float,
    wavelength: ArrayLike,
    *,
    statistic: StatisticName = "ambiguity_function",
    step_deg: float | None = None,
    window_deg: ArrayLike | None = None,
    refine: RefineName = True,
) -> BaselineDirection:
    """Heading and elevation of one baseline (two antennas) over a 2-D grid.

    Parameters
    ----------
    phase_diffs
        (M,) or (epochs, M) radians: phase at antenna 1 minus antenna 0 (sign and wrapping as in
        :func:`ml_attitude`).
    los, wavelength, statistic, step_deg, refine
        As in :func:`ml_attitude`.
    baseline_length_m
        Distance between the antennas, metres.
    window_deg
        ``None`` or (2, 2) ``[lo, hi]`` of the eq. (5) heading ``psi`` (= -compass heading) and elevation.
    """
    p = float_array("phase_diffs", phase_diffs, ndim=(1, 2), shape="(M,) or (epochs, M)")
    p = p[:, None, :] if p.ndim == 2 else p[None, None, :]
    length = float(baseline_length_m)
    if not np.isfinite(length) or length <= 0:
        raise InvalidInputError(f"expected a positive baseline_length_m, got {baseline_length_m}")
    p, s, w, b = _intake(p, los, [[length, 0.0, 0.0]], wavelength, n_baselines=1)
    win = None
    if window_deg is not None:
        w2 = float_array("window_deg", window_deg, ndim=2, shape="(2, 2)")
        if w2.shape != (2, 2):
            raise InvalidInputError(f"expected window_deg of shape (2, 2), got {w2.shape}")
        win = [[float(v) for v in row] for row in np.radians(np.vstack([w2, [[-1.0, 1.0]]]))]
    angles, _, z, cells, step, _ = _core.ml_search(
        p, s, w, b, statistic, _step(step_deg), win, "exhaustive", _refine(refine), True
    )
    psi, theta = angles[0], angles[1]
    direction = np.array([-np.sin(psi) * np.cos(theta), np.cos(psi) * np.cos(theta), np.sin(theta)])
    return BaselineDirection(
        heading_deg=float(np.degrees(-psi) % 360.0),
        elevation_deg=float(np.degrees(theta)),
        direction_enu=direction,
        z_max=float(z),
        cells_evaluated=int(cells),
        step_deg=float(np.degrees(step)),
    )


def prior_from_velocity(
    velocity_enu: ArrayLike,
    acceleration_enu: ArrayLike | None = None,
    *,
    half_width_deg: ArrayLike = (7.0, 7.0, 7.0),
    gravity: float = 9.80665,
) -> AttitudePrior:
    """A coarse attitude from the velocity vector, as the paper suggests for shrinking the search window.

    Heading and pitch are those of the velocity (no sideslip, no angle of attack); roll is the bank of a
    coordinated turn, ``atan2(a_lateral, g)`` with ``a_lateral`` the acceleration towards the right wing
    (positive roll lowers the right wing, eq. (5)). The paper quotes 5-7 degrees for such a prior.

    Parameters
    ----------
    velocity_enu
        (3,) velocity, East-North-Up, m/s; not zero horizontally.
    acceleration_enu
        (3,) acceleration, East-North-Up, m/s^2; ``None`` gives zero roll.
    half_width_deg
        Window half-widths in psi, theta, phi, degrees.
    gravity
        m/s^2.
    """
    v = float_array("velocity_enu", velocity_enu, ndim=1, shape="(3,)")
    if v.shape != (3,):
        raise InvalidInputError(f"expected velocity_enu of shape (3,), got {v.shape}")
    horizontal = float(np.hypot(v[0], v[1]))
    if horizontal < 1e-9:
        raise InvalidInputError("velocity_enu has no horizontal component: heading is undefined")
    compass = np.arctan2(v[0], v[1])
    pitch = np.arctan2(v[2], horizontal)
    roll = 0.0
    if acceleration_enu is not None:
        a = float_array("acceleration_enu", acceleration_enu, ndim=1, shape="(3,)")
        if a.shape != (3,):
            raise InvalidInputError(f"expected acceleration_enu of shape (3,), got {a.shape}")
        right = np.array([np.cos(compass), -np.sin(compass), 0.0])
        roll = float(np.arctan2(a @ right, gravity))
    hw = float_array("half_width_deg", half_width_deg, ndim=1, shape="(3,)")
    if hw.shape != (3,) or np.any(hw <= 0):
        raise InvalidInputError(f"expected three positive half_width_deg, got {hw}")
    return AttitudePrior(euler_deg=np.degrees([-compass, pitch, roll]), half_width_deg=hw)
