"""Maximum-likelihood attitude from raw carrier phases over a grid of Euler angles (Bunyaeva et al.).

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

from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import dataclass, field
from typing import Literal, get_args

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.spatial.transform import Rotation

from gnssatt import _core
from gnssatt._arrays import batch_limit, choice, float_array, plain_array, scalar, shaped
from gnssatt.errors import InvalidInputError, InvalidTypeError, WorkLimitError
from gnssatt.geometry import MAX_BASELINE_M, MAX_BASELINES, MAX_SIGNALS, MIN_BASELINE_M, checked_baselines

# The GOST Euler sequence lives in gnssatt.rotation (the base layer, which the simulator may import); these
# names stay here too, the paths users and older code know.
from gnssatt.rotation import rotation_from_euler

__all__ = [
    "AttitudePrior",
    "AttitudeSeries",
    "BaselineDirection",
    "BaselineSeries",
    "LikelihoodAttitude",
    "LikelihoodGrid",
    "likelihood_grid",
    "ml_attitude",
    "ml_attitude_series",
    "ml_baseline",
    "ml_baseline_series",
    "prior_from_velocity",
]

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
        (psi, theta, phi) of eq. (5), degrees, each in [-360, 360]. Formerly ``euler_deg``.
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
        (psi, theta, phi) of eq. (5) in degrees (refined when asked); psi, phi in (-180, 180]. Formerly
        ``euler_deg``.
    grid_euler_gost_deg
        Angles of the grid maximum, degrees, the same sequence. Formerly ``grid_euler_deg``.
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


def _intake(
    phase_diffs: ArrayLike,
    los: ArrayLike,
    baselines: ArrayLike,
    wavelength: ArrayLike,
    *,
    n_baselines: int | None,
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
    # from the shapes, before anything is copied: the kernel's work is cells x epochs x baselines x signals
    batch_limit(MAX_SIGNALS, "MAX_SIGNALS", "lines of sight (all epochs)", los=(los, 1))
    batch_limit(
        MAX_BASELINES * MAX_SIGNALS,
        "MAX_BASELINES x MAX_SIGNALS",
        "phase differences",
        phase_diffs=(phase_diffs, 0),
    )
    p = float_array("phase_diffs", phase_diffs, ndim=(2, 3), shape="(m, M) or (epochs, m, M)")
    if p.ndim == 2:
        p = p[None]
    ne, nb, m = p.shape
    if np.any(np.abs(p) > MAX_PHASE_RAD):
        k = tuple(int(i) for i in np.argwhere(np.abs(p) > MAX_PHASE_RAD)[0])
        raise InvalidInputError(
            f"expected phase_diffs at most {MAX_PHASE_RAD:g} rad in magnitude (remove whole cycles), got "
            f"{p[k]:.6g} at (epoch, baseline, satellite) {k}"
        )
    s = float_array("los", los, ndim=(2, 3), shape="(M, 3) or (epochs, M, 3)")
    if s.ndim == 2:
        s = np.broadcast_to(s, (ne, *s.shape))
    if s.shape != (ne, m, 3):
        raise InvalidInputError(
            f"expected los of shape ({m}, 3) or ({ne}, {m}, 3) to match phase_diffs {p.shape} "
            f"(epochs, m, M), got {s.shape}"
        )
    b = checked_baselines("baselines", baselines)
    if b.shape[0] != nb:
        raise InvalidInputError(f"expected baselines of shape ({nb}, 3) to match phase_diffs, got {b.shape}")
    if n_baselines is not None and nb < n_baselines:
        raise InvalidInputError(f"expected at least {n_baselines} baselines (m, 3), got {b.shape}")
    w = float_array("wavelength", wavelength, ndim=(0, 1, 2), shape="scalar, (M,) or (epochs, M)")
    try:
        w = np.broadcast_to(w, (ne, m))
    except ValueError as exc:
        raise InvalidInputError(f"expected wavelength as a scalar or of shape ({m},), got {w.shape}") from exc
    if np.any((w < MIN_WAVELENGTH_M) | (w > MAX_WAVELENGTH_M)):
        k = tuple(int(i) for i in np.argwhere((w < MIN_WAVELENGTH_M) | (w > MAX_WAVELENGTH_M))[0])
        raise InvalidInputError(
            f"expected wavelength in [{MIN_WAVELENGTH_M:g}, {MAX_WAVELENGTH_M:g}] m, got {w[k]:.6g} m at "
            f"(epoch, satellite) {k}"
        )
    return p, np.ascontiguousarray(s), np.ascontiguousarray(w), b


def _rows(name: str, w: NDArray[np.float64], axes: tuple[str, ...]) -> None:
    """Window rows ``[lo, hi]`` in order and within +-WINDOW_LIMIT_DEG."""
    for (lo, hi), axis in zip(w, axes, strict=True):
        if not (-WINDOW_LIMIT_DEG <= lo <= hi <= WINDOW_LIMIT_DEG):
            raise InvalidInputError(
                f"expected {name} rows [lo, hi] with -{WINDOW_LIMIT_DEG:g} <= lo <= hi <= "
                f"{WINDOW_LIMIT_DEG:g} deg, got [{lo}, {hi}] for {axis}"
            )


def _window(window_deg: ArrayLike | AttitudePrior | None) -> list[list[float]] | None:
    if window_deg is None:
        return None
    if isinstance(window_deg, AttitudePrior):
        window_deg = window_deg.window_deg
    w = shaped("window_deg", window_deg, "(3, 2) ([lo, hi] of psi, theta, phi)", (3, 2))
    _rows("window_deg", w, ("psi", "theta", "phi"))
    return [[float(v) for v in row] for row in np.radians(w)]


@contextmanager
def _lobe(b: NDArray[np.float64], length_name: str = "baselines") -> Iterator[None]:
    """Name ``baselines`` (``length_name``) and ``wavelength`` next to ``step_deg`` when the core finds the
    step coarser than the main lobe: the lobe's width lambda / (2 L) is set by the longest baseline and the
    wavelength, so any of the three can be the one to change."""
    try:
        yield
    except InvalidInputError as exc:
        if "main lobe" not in str(exc):
            raise
        longest = float(np.max(np.linalg.norm(b, axis=1)))
        what = "the longest of the baselines" if length_name == "baselines" else length_name
        raise InvalidInputError(
            f"{exc} (L = {longest:.6g} m, {what}; lambda from wavelength): choose a finer step_deg, a "
            f"shorter {length_name} or a longer wavelength"
        ) from exc


def _step(step_deg: float | None) -> float | None:
    if step_deg is None:
        return None
    step = scalar("step_deg", step_deg, minimum=0.0, strict=True, unit="deg")
    if step > MAX_STEP_DEG:
        raise InvalidInputError(f"expected step_deg <= {MAX_STEP_DEG:g} deg, got {step} deg")
    return float(np.radians(step))


def _refine(refine: RefineName) -> str:
    if isinstance(refine, bool | np.bool_):
        return "newton" if refine else "none"
    if not isinstance(refine, str):
        raise InvalidTypeError(
            f"expected refine True, False, 'parabolic' or 'newton', got {type(refine).__name__}"
        )
    if refine not in ("parabolic", "newton"):
        raise InvalidInputError(f"expected refine True, False, 'parabolic' or 'newton', got {refine!r}")
    return refine


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
    """Maximum-likelihood attitude over a grid of Euler angles (Bunyaeva et al.).

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
        would exceed one box per 128 cells (``docs/likelihood_search.md``).
    refine
        ``True`` or ``"newton"`` (default): the parabolic interpolation (16), then Newton's method on the
        statistic (float64, full Hessian, trust region of one grid step), i.e. the continuous maximum of
        ``Z``. ``"parabolic"``: eq. (16) alone, one parabola per axis with wrap-around in heading and roll;
        because the axes of eq. (5) are coupled it leaves errors of a fraction of a step even without
        noise. ``False``: the grid node.

    Returns
    -------
    LikelihoodAttitude
        The body -> ENU rotation, its eq. (5) angles (deg), the grid node found, ``z_max``, the number of
        cells evaluated and the step used (deg).

    Raises
    ------
    InvalidInputError
        Non-finite values, mismatched shapes, fewer than 3 satellites, lines of sight that are not unit
        vectors, baselines shorter than :data:`~gnssatt.geometry.MIN_BASELINE_M` or longer than
        :data:`~gnssatt.geometry.MAX_BASELINE_M`, phase differences beyond :data:`MAX_PHASE_RAD`, wavelengths
        outside [:data:`MIN_WAVELENGTH_M`, :data:`MAX_WAVELENGTH_M`], a step that is not in
        (0, :data:`MAX_STEP_DEG`] or is coarser than the main lobe, a window with ``lo > hi``, beyond
        +-:data:`WINDOW_LIMIT_DEG` or holding no node, a step giving over 2^20 nodes per turn, a grid the
        search cannot afford (the core's documented limits on the work done: 2^31 cells for the
        exhaustive pass, 2^28 direction boxes plus rows for the branch-and-bound where the grid holds
        more cells; checked before any cell is evaluated where they can be: coarsen the step or narrow
        the window), an unknown ``statistic``, ``search`` or ``refine``
        (:class:`~gnssatt.errors.InvalidTypeError` for values of the wrong kind).
    DegenerateGeometryError
        Collinear baselines.
    WorkLimitError
        More than :data:`~gnssatt.geometry.MAX_SIGNALS` lines of sight over all epochs, more than
        :data:`~gnssatt.geometry.MAX_BASELINES` baselines, or more phase differences than the two together,
        refused from the shapes before anything is copied.

    Examples
    --------
    Noise-free phases of a 1 m triangle and six satellites (wavelength 0.19 m) give back the attitude they
    were made with:

    >>> import numpy as np
    >>> from gnssatt.rotation import rotation_from_euler
    >>> from gnssatt.sim import equilateral_triangle, random_los
    >>> los = random_los(1, 6, min_elevation_deg=15.0)  # (6, 3) unit vectors, ENU
    >>> baselines = equilateral_triangle(1.0, plane="xz")[1:]  # (2, 3) m, body
    >>> true = rotation_from_euler([30.0, 10.0, -5.0])  # psi, theta, phi in deg
    >>> phase_diffs = -2 * np.pi / 0.19 * (true.apply(baselines) @ los.T)  # (2, 6) rad, RINEX sign
    >>> from gnssatt import ml_attitude
    >>> result = ml_attitude(phase_diffs, los, baselines, 0.19)
    >>> np.round(result.euler_gost_deg, 6) + 0.0
    array([30., 10., -5.])
    """
    p, s, w, b = _intake(phase_diffs, los, baselines, wavelength, n_baselines=2)
    statistic = choice("statistic", statistic, get_args(StatisticName))
    search = choice("search", search, get_args(SearchName))
    with _lobe(b):
        est = _core.ml_search(
            p,
            s,
            w,
            b,
            statistic=statistic,
            step_rad=_step(step_deg),
            window_rad=_window(window_deg),
            search=search,
            refine=_refine(refine),
            two_dimensional=False,
        )
    angles, grid_angles, z = est.angles_rad, est.grid_angles_rad, est.z_max
    cells, step = est.cells_evaluated, est.step_rad
    euler = np.degrees(angles)
    return LikelihoodAttitude(
        rotation=rotation_from_euler(euler),
        euler_gost_deg=euler,
        grid_euler_gost_deg=np.degrees(grid_angles),
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
    """The statistic on the whole grid (float32), for plots and inspection; inputs as :func:`ml_attitude`.

    Parameters
    ----------
    phase_diffs, los, wavelength
        As :func:`ml_attitude`: (m, M) or (epochs, m, M) phase differences, rad; (M, 3) or (epochs, M, 3)
        unit lines of sight, East-North-Up; wavelengths, m.
    baselines
        (m, 3) antenna positions relative to antenna 0, body frame, metres; m >= 1 (a single baseline
        suffices here; the rotation about it is then not observable).
    statistic, step_deg, window_deg
        As :func:`ml_attitude`.

    Returns
    -------
    LikelihoodGrid
        The statistic ``z`` of shape (n_psi, n_theta, n_phi), its axes in degrees and the step used.

    Raises
    ------
    InvalidInputError, DegenerateGeometryError, WorkLimitError
        As :func:`ml_attitude` (one baseline suffices here).

    Examples
    --------
    On a 5 deg grid the largest statistic lies at the node of the true attitude:

    >>> import numpy as np
    >>> from gnssatt.rotation import rotation_from_euler
    >>> from gnssatt.sim import equilateral_triangle, random_los
    >>> los = random_los(1, 6, min_elevation_deg=15.0)  # (6, 3) unit vectors, ENU
    >>> baselines = equilateral_triangle(1.0, plane="xz")[1:]  # (2, 3) m, body
    >>> true = rotation_from_euler([30.0, 10.0, -5.0])  # psi, theta, phi in deg
    >>> phase_diffs = -2 * np.pi / 0.19 * (true.apply(baselines) @ los.T)  # (2, 6) rad, RINEX sign
    >>> from gnssatt import likelihood_grid
    >>> grid = likelihood_grid(phase_diffs, los, baselines, 0.19, step_deg=5.0)
    >>> grid.z.shape
    (72, 37, 72)
    >>> i, j, k = np.unravel_index(np.argmax(grid.z), grid.z.shape)
    >>> [round(float(a), 6) for a in (grid.psi_deg[i], grid.theta_deg[j], grid.phi_deg[k])]
    [30.0, 10.0, -5.0]
    """
    p, s, w, b = _intake(phase_diffs, los, baselines, wavelength, n_baselines=1)
    statistic = choice("statistic", statistic, get_args(StatisticName))
    step = _step(step_deg)
    with _lobe(b):
        g = _core.likelihood_grid(
            p,
            s,
            w,
            b,
            statistic=statistic,
            step_rad=step,
            window_rad=_window(window_deg),
            two_dimensional=b.shape[0] == 1,
        )
    z, psi, theta, phi = g.z, g.psi_rad, g.theta_rad, g.phi_rad
    spaced = [a for a in (psi, theta, phi) if len(a) > 1]
    if spaced:
        actual = float(spaced[0][1] - spaced[0][0])
    else:  # a window holding a single node: the lattice step of the core, eq. (15) by default
        requested = (
            step if step is not None else float(np.min(w)) / (10.0 * float(np.max(np.linalg.norm(b, axis=1))))
        )
        actual = np.pi / np.ceil(np.pi / requested)
    return LikelihoodGrid(
        z=np.transpose(z, (2, 0, 1)),
        psi_deg=np.degrees(psi),
        theta_deg=np.degrees(theta),
        phi_deg=np.degrees(phi),
        step_deg=float(np.degrees(actual)),
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
        Distance between the antennas, metres, in [:data:`~gnssatt.geometry.MIN_BASELINE_M`,
        :data:`~gnssatt.geometry.MAX_BASELINE_M`].
    window_deg
        ``None`` or (2, 2) ``[lo, hi]`` of the eq. (5) heading ``psi`` (= -compass heading) and elevation.

    Returns
    -------
    BaselineDirection
        Compass heading and elevation (deg) of the baseline, its unit direction in ENU, ``z_max``, the cells
        evaluated and the step used (deg).

    Raises
    ------
    InvalidInputError, DegenerateGeometryError, WorkLimitError
        As :func:`ml_attitude`.

    Examples
    --------
    The first baseline of the :func:`ml_attitude` example points along body X, i.e. at heading
    ``-psi = 330`` deg and elevation ``theta = 10`` deg:

    >>> import numpy as np
    >>> from gnssatt.rotation import rotation_from_euler
    >>> from gnssatt.sim import equilateral_triangle, random_los
    >>> los = random_los(1, 6, min_elevation_deg=15.0)  # (6, 3) unit vectors, ENU
    >>> baselines = equilateral_triangle(1.0, plane="xz")[1:]  # (2, 3) m, body
    >>> true = rotation_from_euler([30.0, 10.0, -5.0])  # psi, theta, phi in deg
    >>> phase_diffs = -2 * np.pi / 0.19 * (true.apply(baselines) @ los.T)  # (2, 6) rad, RINEX sign
    >>> from gnssatt import ml_baseline
    >>> result = ml_baseline(phase_diffs[0], los, 1.0, 0.19)
    >>> round(result.heading_deg, 6), round(result.elevation_deg, 6)
    (330.0, 10.0)
    """
    batch_limit(MAX_SIGNALS, "MAX_SIGNALS", "phase differences (all epochs)", phase_diffs=(phase_diffs, 0))
    p = float_array("phase_diffs", phase_diffs, ndim=(1, 2), shape="(M,) or (epochs, M)")
    p = p[:, None, :] if p.ndim == 2 else p[None, None, :]
    length = scalar(
        "baseline_length_m", baseline_length_m, minimum=MIN_BASELINE_M, maximum=MAX_BASELINE_M, unit="m"
    )
    p, s, w, b = _intake(p, los, [[length, 0.0, 0.0]], wavelength, n_baselines=1)
    statistic = choice("statistic", statistic, get_args(StatisticName))
    win = None
    if window_deg is not None:
        w2 = shaped("window_deg", window_deg, "(2, 2) ([lo, hi] of psi, elevation)", (2, 2))
        _rows("window_deg", w2, ("psi", "elevation"))
        win = [[float(v) for v in row] for row in np.radians(np.vstack([w2, [[-1.0, 1.0]]]))]
    with _lobe(b, "baseline_length_m"):
        est = _core.ml_search(
            p,
            s,
            w,
            b,
            statistic=statistic,
            step_rad=_step(step_deg),
            window_rad=win,
            search="exhaustive",
            refine=_refine(refine),
            two_dimensional=True,
        )
    angles, z, cells, step = est.angles_rad, est.z_max, est.cells_evaluated, est.step_rad
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
        Window half-widths in psi, theta, phi, degrees, each in (0, 360].
    gravity
        m/s^2, > 0.

    Returns
    -------
    AttitudePrior
        The eq. (5) angles ``(psi, theta, phi)`` of the coarse attitude and the window half-widths, deg.

    Raises
    ------
    InvalidInputError
        Wrong shapes, non-finite values, a velocity with a horizontal speed below 1e-9 m/s, half-widths
        out of range, ``gravity <= 0`` (:class:`~gnssatt.errors.InvalidTypeError` for values that are not
        real numbers).

    Examples
    --------
    Flying north at 100 m/s while accelerating at 1 g to the west, a coordinated left turn: heading 0 and a
    45 deg bank to the left (negative roll):

    >>> import numpy as np
    >>> from gnssatt import prior_from_velocity
    >>> prior = prior_from_velocity([0.0, 100.0, 0.0], [-9.80665, 0.0, 0.0])
    >>> np.round(prior.euler_gost_deg, 6) + 0.0
    array([  0.,   0., -45.])
    """
    v = shaped("velocity_enu", velocity_enu, "(3,)", (3,))
    a = None if acceleration_enu is None else shaped("acceleration_enu", acceleration_enu, "(3,)", (3,))
    hw = shaped("half_width_deg", half_width_deg, "(3,)", (3,))
    g = scalar("gravity", gravity, minimum=0.0, strict=True, unit="m/s^2")
    horizontal = float(np.hypot(v[0], v[1]))  # hypot: no overflow for speeds near 1e308
    if horizontal < 1e-9:
        raise InvalidInputError(
            f"expected velocity_enu with a horizontal speed of at least 1e-9 m/s (heading is undefined "
            f"without one), got {horizontal:.3g} m/s"
        )
    compass = np.arctan2(v[0], v[1])
    pitch = np.arctan2(v[2], horizontal)
    roll = 0.0
    if a is not None:
        right = np.array([np.cos(compass), -np.sin(compass), 0.0])
        with np.errstate(over="ignore"):  # an infinite lateral acceleration still has a bank angle of 90 deg
            roll = float(np.arctan2(a @ right, g))
    return AttitudePrior(euler_gost_deg=np.degrees([-compass, pitch, roll]), half_width_deg=hw)


@dataclass(frozen=True)
class AttitudeSeries:
    """Per-epoch attitudes from :func:`ml_attitude_series`.

    Attributes
    ----------
    rotation
        (n_ep,) body -> East-North-Up rotations (the convention of :class:`LikelihoodAttitude`); the identity
        where ``solved`` is False.
    euler_gost_deg
        (n_ep, 3) (psi, theta, phi) of eq. (5), degrees, refined as :func:`ml_attitude` with its defaults;
        NaN where ``solved`` is False. Formerly ``euler_deg``.
    z_max
        (n_ep,) the ambiguity function at each epoch's grid maximum; NaN where ``solved`` is False.
    solved
        (n_ep,) False where the epoch has fewer than 3 signals present at every rover antenna.
    """

    rotation: Rotation
    euler_gost_deg: NDArray[np.float64]
    z_max: NDArray[np.float64]
    solved: NDArray[np.bool_]


@dataclass(frozen=True)
class BaselineSeries:
    """Per-epoch baseline directions from :func:`ml_baseline_series`.

    Attributes
    ----------
    heading_deg
        (n_ep,) compass heading of the baseline (clockwise from North towards East), degrees in [0, 360).
    elevation_deg
        (n_ep,) elevation above the horizontal plane, degrees.
    direction_enu
        (n_ep, 3) unit vectors along the baseline, East-North-Up.
    z_max, solved
        As in :class:`AttitudeSeries`; every angle and vector is NaN where ``solved`` is False.
    """

    heading_deg: NDArray[np.float64]
    elevation_deg: NDArray[np.float64]
    direction_enu: NDArray[np.float64]
    z_max: NDArray[np.float64]
    solved: NDArray[np.bool_]


def _gaps(
    name: str, value: ArrayLike, *, ndim: int | tuple[int, ...], shape: str
) -> tuple[NDArray[np.float64], NDArray[np.bool_]]:
    """:func:`float_array` where NaN marks an absent value: (the values with NaN replaced by 0, the gaps)."""
    raw = value
    gaps: NDArray[np.bool_] | bool = False
    if isinstance(value, np.ndarray | list | tuple | float):
        # masked values are gaps too; the size is checked before np.isnan scans (or copies) the array
        raw = plain_array(name, value, nan_for_masked=True)
        if raw.dtype.kind == "f":
            gaps = np.isnan(raw)
            raw = np.where(gaps, 0.0, raw)
    arr = float_array(name, raw, ndim=ndim, shape=shape)
    return arr, np.broadcast_to(gaps, arr.shape)


#: Most work one :func:`ml_attitude_series` or :func:`ml_baseline_series` call accepts, in kernel terms
#: (epochs x grid cells searched x signals x rovers; ``docs/limits.md``), read from the core.
MAX_SERIES_WORK: float = _core.LIKELIHOOD_MAX_SERIES_WORK


def _check_series_work(
    sd_phase: ArrayLike,
    wavelength: ArrayLike,
    step: float | None,
    window_deg: float | None,
    longest: float,
    *,
    two_dimensional: bool,
) -> None:
    """Refuses a series call whose shapes alone ask for more than :data:`MAX_SERIES_WORK`, before the
    measurements are copied or scanned: every epoch counted solved with all its signals at the longest
    valid wavelength given (the coarsest default step, so no more than the core's own per-epoch count)."""
    shape = np.shape(plain_array("sd_phase", sd_phase, nan_for_masked=True))
    if len(shape) != (2 if two_dimensional else 3):
        return  # the intake names the shape
    n_ep, n_rover, n_sig = (shape[0], 1, shape[1]) if two_dimensional else shape
    w = plain_array("wavelength", wavelength, nan_for_masked=True)
    if w.dtype.kind not in "fiu" or w.size == 0:
        return
    # a reduction, not a mask: nothing of the wavelengths' size is allocated; a longer wavelength than
    # any epoch's smallest only lowers the count
    longest_wavelength = min(float(np.fmax.reduce(w, axis=None)), MAX_WAVELENGTH_M)
    if not longest_wavelength >= MIN_WAVELENGTH_M:
        return  # the intake names the wavelengths
    window = None
    if window_deg is not None:
        window = float(np.radians(scalar("window_deg", window_deg, minimum=0.0, maximum=360.0, strict=True)))
    work = _core.ml_series_work(
        n_ep,
        n_rover,
        n_sig,
        step_rad=step,
        wavelength_m=longest_wavelength,
        longest_baseline_m=longest,
        window_rad=window,
        two_dimensional=two_dimensional,
    )
    if work > MAX_SERIES_WORK:
        raise WorkLimitError(
            f"sd_phase asks for {work:.4g} kernel terms ({n_ep} epochs x grid cells searched x {n_sig} "
            f"signals x {n_rover} rovers), more than the limit of {MAX_SERIES_WORK:.4g} (MAX_SERIES_WORK): "
            "split the epochs into batches, search in a window (window_deg) or with a coarser step_deg"
        )


def _series_intake(
    sd_phase: ArrayLike, los: ArrayLike, wavelength: ArrayLike, mask: ArrayLike | None, n_rover: int
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
    """Checked (n_ep, n_rover, n_sig) phases with NaN where absent, (n_ep, n_sig, 3) lines of sight and
    (n_ep, n_sig) wavelengths, finite wherever a signal is present at every rover."""
    p, absent = _gaps("sd_phase", sd_phase, ndim=3, shape="(n_ep, n_rover, n_sig)")
    ne, nr, m = p.shape
    if ne == 0:
        raise InvalidInputError(f"expected sd_phase with at least one epoch, got shape {p.shape}")
    if nr != n_rover:
        raise InvalidInputError(
            f"expected sd_phase of shape (n_ep, {n_rover}, n_sig) to match the baselines, got {p.shape}"
        )
    if mask is not None:
        mk = np.asarray(mask)
        if mk.dtype != np.bool_ or mk.shape != p.shape:
            raise InvalidInputError(
                f"expected mask as a boolean array of shape {p.shape} (True where a signal is present), got "
                f"{mk.dtype} of shape {mk.shape}"
            )
        absent = absent | ~mk
    used = ~np.any(absent, axis=1)  # (n_ep, n_sig): a signal some rover lacks is left out of its epoch
    big = (np.abs(p) > MAX_PHASE_RAD) & ~absent
    if np.any(big):
        k = tuple(int(i) for i in np.argwhere(big)[0])
        raise InvalidInputError(
            f"expected sd_phase at most {MAX_PHASE_RAD:g} rad in magnitude (remove whole cycles), got "
            f"{p[k]:.6g} at (epoch, rover, signal) {k}"
        )
    s, s_gaps = _gaps("los", los, ndim=(2, 3), shape="(n_sig, 3) or (n_ep, n_sig, 3)")
    if s.shape not in ((m, 3), (ne, m, 3)):
        raise InvalidInputError(
            f"expected los of shape ({m}, 3) or ({ne}, {m}, 3) to match sd_phase {p.shape}, got {s.shape}"
        )
    s, s_gaps = np.broadcast_to(s, (ne, m, 3)), np.broadcast_to(s_gaps, (ne, m, 3))
    w, w_gaps = _gaps("wavelength", wavelength, ndim=(0, 1, 2), shape="scalar, (n_sig,) or (n_ep, n_sig)")
    try:
        w, w_gaps = np.broadcast_to(w, (ne, m)), np.broadcast_to(w_gaps, (ne, m))
    except ValueError as exc:
        raise InvalidInputError(
            f"expected wavelength as a scalar or of shape ({m},) or ({ne}, {m}), got {w.shape}"
        ) from exc
    for name, bad in (("los", np.any(s_gaps, axis=2) & used), ("wavelength", w_gaps & used)):
        if np.any(bad):
            k = tuple(int(i) for i in np.argwhere(bad)[0])
            raise InvalidInputError(
                f"{name} is NaN at (epoch, signal) {k}, where the signal is present at every rover (NaN "
                "is accepted only for absent signals)"
            )
    out = (w < MIN_WAVELENGTH_M) | (w > MAX_WAVELENGTH_M)
    if np.any(out & used):
        k = tuple(int(i) for i in np.argwhere(out & used)[0])
        raise InvalidInputError(
            f"expected wavelength in [{MIN_WAVELENGTH_M:g}, {MAX_WAVELENGTH_M:g}] m, got {w[k]:.6g} m at "
            f"(epoch, signal) {k}"
        )
    # Signals left out carry placeholders the core never reads as measurements.
    p = np.where(absent, np.nan, p)
    s = np.where(used[..., None], s, np.array([0.0, 0.0, 1.0]))
    w = np.where(used, w, 1.0)
    return p, np.ascontiguousarray(s), np.ascontiguousarray(w)


def _series_window(
    window_deg: float | None,
    step_deg: float | None,
    w: NDArray[np.float64],
    used: NDArray[np.bool_],
    longest: float,
) -> float | None:
    """The window half-width in radians, refused when finer than the step of some epoch (it could hold no
    grid node): ``step_deg``, or eq. (15)'s ``lambda_min / (10 L_max)`` of the epoch's signals."""
    if window_deg is None:
        return None
    half = scalar("window_deg", window_deg, minimum=0.0, maximum=360.0, strict=True, unit="deg")
    if step_deg is not None:
        step = float(step_deg)
    else:
        lam = np.min(np.where(used, w, np.inf), axis=1)
        lam = lam[np.isfinite(lam)]
        step = float(np.degrees(np.max(lam) / (10.0 * longest))) if lam.size else 0.0
    if half < step:
        raise InvalidInputError(
            f"expected window_deg of at least the grid step ({step:.6g} deg), got {half} deg: a narrower "
            "window can hold no grid node"
        )
    return float(np.radians(half))


def ml_attitude_series(
    sd_phase: ArrayLike,
    los: ArrayLike,
    baselines: ArrayLike,
    wavelength: ArrayLike,
    *,
    mask: ArrayLike | None = None,
    step_deg: float | None = None,
    window_deg: float | None = None,
) -> AttitudeSeries:
    """Maximum-likelihood attitude of every epoch of a batch, in one call (GIL released; Ctrl-C stops it).

    Each epoch gives what :func:`ml_attitude` gives for that epoch alone with the default statistic, search
    and refinement (its own oscillator phases; the exact branch-and-bound where it is faster than the
    exhaustive pass), bit for bit. Without a window the epochs run in parallel; with one each epoch searches
    ``+- window_deg`` on every angle around the previous epoch's solution (the whole domain at the first
    epoch and after an unsolved one). The work is one grid search per epoch, each within the limits of
    :func:`ml_attitude`.

    Parameters
    ----------
    sd_phase
        (n_ep, n_rover, n_sig) radians: phase at rover antenna ``i`` minus the reference antenna for signal
        ``k`` (sign, wrapping and oscillator phases as in :func:`ml_attitude`); NaN where a rover lacks the
        signal. A signal some rover lacks is left out of its epoch.
    los
        (n_sig, 3) or (n_ep, n_sig, 3) unit lines of sight in East-North-Up; NaN allowed where the signal is
        left out.
    baselines
        (n_rover, 3) rover antenna positions relative to the reference antenna, body frame, metres;
        n_rover >= 2, not collinear.
    wavelength
        Metres: a scalar, (n_sig,) per signal (GLONASS FDMA) or (n_ep, n_sig); NaN allowed where the signal
        is left out.
    mask
        ``None`` or a boolean (n_ep, n_rover, n_sig) array, True where the signal is present (combined with
        the NaNs of ``sd_phase``).
    step_deg
        As in :func:`ml_attitude` (``None``: eq. (15) per epoch, from the wavelengths of its signals).
    window_deg
        ``None`` (every epoch searches the whole domain) or the half-width in degrees, in (0, 360] and at
        least the grid step, of the window around the previous epoch's solution.

    Returns
    -------
    AttitudeSeries
        Per epoch: the body -> ENU rotation, the eq. (5) angles (deg, NaN where unsolved), ``z_max`` and
        whether the epoch was solved.

    Raises
    ------
    InvalidInputError
        As :func:`ml_attitude`; a ``mask`` of the wrong kind or shape, NaN lines of sight or wavelengths of
        a signal used, no epoch, a window finer than the step.
    WorkLimitError
        More than :data:`MAX_SERIES_WORK` kernel terms (epochs x grid cells searched x signals x rovers,
        ``docs/limits.md``), counted before the measurements are copied.
    DegenerateGeometryError
        Collinear baselines.

    Examples
    --------
    Two epochs of the :func:`ml_attitude` example, the second turned by 2 deg in psi:

    >>> import numpy as np
    >>> from gnssatt.rotation import rotation_from_euler
    >>> from gnssatt.sim import equilateral_triangle, random_los
    >>> los = random_los(1, 6, min_elevation_deg=15.0)  # (6, 3) unit vectors, ENU
    >>> baselines = equilateral_triangle(1.0, plane="xz")[1:]  # (2, 3) m, body
    >>> true = rotation_from_euler([30.0, 10.0, -5.0])  # psi, theta, phi in deg
    >>> phase_diffs = -2 * np.pi / 0.19 * (true.apply(baselines) @ los.T)  # (2, 6) rad, RINEX sign
    >>> from gnssatt import ml_attitude_series
    >>> second = rotation_from_euler([32.0, 10.0, -5.0])
    >>> sd_phase = np.stack([phase_diffs, -2 * np.pi / 0.19 * (second.apply(baselines) @ los.T)])
    >>> series = ml_attitude_series(sd_phase, los, baselines, 0.19)
    >>> np.round(series.euler_gost_deg, 6) + 0.0
    array([[30., 10., -5.],
           [32., 10., -5.]])
    """
    b = checked_baselines("baselines", baselines)
    if b.shape[0] < 2:
        raise InvalidInputError(f"expected at least 2 baselines (n_rover, 3), got {b.shape}")
    step = _step(step_deg)
    longest = float(np.max(np.linalg.norm(b, axis=1)))
    _check_series_work(sd_phase, wavelength, step, window_deg, longest, two_dimensional=False)
    p, s, w = _series_intake(sd_phase, los, wavelength, mask, b.shape[0])
    used = ~np.any(np.isnan(p), axis=1)
    window = _series_window(window_deg, step_deg, w, used, longest)
    with _lobe(b):
        series = _core.ml_attitude_series(p, s, w, b, step_rad=step, window_rad=window)
    euler, z, solved = series.euler_gost_rad, series.z_max, series.solved
    euler_deg = np.degrees(euler)
    matrices = rotation_from_euler(np.where(solved[:, None], euler_deg, 0.0)).as_matrix()
    return AttitudeSeries(
        rotation=Rotation.from_matrix(np.where(solved[:, None, None], matrices, np.eye(3))),
        euler_gost_deg=euler_deg,
        z_max=z,
        solved=solved,
    )


def ml_baseline_series(
    sd_phase: ArrayLike,
    los: ArrayLike,
    baseline_length_m: float,
    wavelength: ArrayLike,
    *,
    mask: ArrayLike | None = None,
    step_deg: float | None = None,
    window_deg: float | None = None,
) -> BaselineSeries:
    """Heading and elevation of one baseline at every epoch of a batch, in one call (as
    :func:`ml_baseline` epoch by epoch, with its defaults; windows and parallelism as in
    :func:`ml_attitude_series`, the window on heading and elevation).

    Parameters
    ----------
    sd_phase
        (n_ep, n_sig) radians, phase at antenna 1 minus antenna 0; NaN where absent.
    los, wavelength, step_deg, window_deg
        As in :func:`ml_attitude_series`.
    baseline_length_m
        As in :func:`ml_baseline`.
    mask
        ``None`` or a boolean (n_ep, n_sig) array, True where the signal is present.

    Returns
    -------
    BaselineSeries
        Per epoch: compass heading and elevation (deg, NaN where unsolved), the unit direction in ENU,
        ``z_max`` and whether the epoch was solved.

    Raises
    ------
    InvalidInputError
        As :func:`ml_attitude_series`.
    WorkLimitError
        As :func:`ml_attitude_series`.

    Examples
    --------
    The first baseline of the :func:`ml_attitude_series` example: heading ``-psi``, elevation ``theta``:

    >>> import numpy as np
    >>> from gnssatt.rotation import rotation_from_euler
    >>> from gnssatt.sim import equilateral_triangle, random_los
    >>> los = random_los(1, 6, min_elevation_deg=15.0)  # (6, 3) unit vectors, ENU
    >>> baselines = equilateral_triangle(1.0, plane="xz")[1:]  # (2, 3) m, body
    >>> true = rotation_from_euler([30.0, 10.0, -5.0])  # psi, theta, phi in deg
    >>> phase_diffs = -2 * np.pi / 0.19 * (true.apply(baselines) @ los.T)  # (2, 6) rad, RINEX sign
    >>> from gnssatt import ml_baseline_series
    >>> second = rotation_from_euler([32.0, 10.0, -5.0])
    >>> sd_phase = np.stack([phase_diffs[0], -2 * np.pi / 0.19 * (second.apply(baselines[0]) @ los.T)])
    >>> series = ml_baseline_series(sd_phase, los, 1.0, 0.19)
    >>> np.round(series.heading_deg, 6), np.round(series.elevation_deg, 6)
    (array([330., 328.]), array([10., 10.]))
    """
    length = scalar(
        "baseline_length_m", baseline_length_m, minimum=MIN_BASELINE_M, maximum=MAX_BASELINE_M, unit="m"
    )
    step = _step(step_deg)
    _check_series_work(sd_phase, wavelength, step, window_deg, length, two_dimensional=True)
    p, gaps = _gaps("sd_phase", sd_phase, ndim=2, shape="(n_ep, n_sig)")
    p = np.where(gaps, np.nan, p)[:, None, :]
    if mask is not None:
        mk = np.asarray(mask)
        mask = mk[:, None, :] if mk.ndim == 2 else mk  # a wrong shape is named by the intake
    p, s, w = _series_intake(p, los, wavelength, mask, 1)
    used = ~np.isnan(p[:, 0, :])
    window = _series_window(window_deg, step_deg, w, used, length)
    with _lobe(np.array([[length, 0.0, 0.0]]), "baseline_length_m"):
        series = _core.ml_baseline_series(p, s, w, length, step_rad=step, window_rad=window)
    direction, z, solved = series.direction_rad, series.z_max, series.solved
    heading, elevation = direction[:, 0], direction[:, 1]
    enu = np.stack(
        [np.sin(heading) * np.cos(elevation), np.cos(heading) * np.cos(elevation), np.sin(elevation)], axis=1
    )
    return BaselineSeries(
        heading_deg=np.degrees(heading) % 360.0,  # an angle just under 2 pi can round to 360 deg
        elevation_deg=np.degrees(elevation),
        direction_enu=enu,
        z_max=z,
        solved=solved,
    )
