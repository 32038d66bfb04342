"""The single-epoch estimators of :mod:`gnssatt.attitude.likelihood`: the attitude (:func:`ml_attitude`),
the whole grid (:func:`likelihood_grid`), one baseline's direction (:func:`ml_baseline`) and a prior window
from the velocity (:func:`prior_from_velocity`)."""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

from gnssatt import _core
from gnssatt._arrays import batch_limit, float_array, scalar, shaped
from gnssatt.attitude.likelihood._intake import (
    checked_baseline_window,
    checked_inputs,
    checked_length,
    checked_step,
    checked_window,
    direction_enu,
    named_lobe,
)
from gnssatt.attitude.likelihood.model import (
    AttitudePrior,
    BaselineDirection,
    LikelihoodAttitude,
    LikelihoodGrid,
    RefineName,
    SearchName,
    StatisticName,
)
from gnssatt.errors import InvalidInputError
from gnssatt.geometry import MAX_SIGNALS
from gnssatt.rotation import rotation_from_euler


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
    p, s, w, b = checked_inputs(phase_diffs, los, baselines, wavelength, n_baselines=2)
    with named_lobe(b):
        est = _core.ml_search(
            p,
            s,
            w,
            b,
            statistic=statistic,
            step_rad=checked_step(step_deg),
            window_rad=checked_window(window_deg),
            search=search,
            refine=refine,
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
    p, s, w, b = checked_inputs(phase_diffs, los, baselines, wavelength, n_baselines=1)
    step = checked_step(step_deg)
    with named_lobe(b):
        g = _core.likelihood_grid(
            p,
            s,
            w,
            b,
            statistic=statistic,
            step_rad=step,
            window_rad=checked_window(window_deg),
            two_dimensional=b.shape[0] == 1,
        )
    z, psi, theta, phi = g.z, g.psi_rad, g.theta_rad, g.phi_rad
    return LikelihoodGrid(
        z=np.transpose(z, (2, 0, 1)),
        psi_deg=np.degrees(psi),
        theta_deg=np.degrees(theta),
        phi_deg=np.degrees(phi),
        step_deg=float(np.degrees(_grid_step((psi, theta, phi), step, w, b))),
    )


def _grid_step(
    axes: tuple[NDArray[np.float64], ...], step: float | None, w: NDArray[np.float64], b: NDArray[np.float64]
) -> float:
    """The step of the grid the core evaluated, rad: the spacing of its first axis with two nodes or more.

    Parameters
    ----------
    axes
        The grid's psi, theta and phi nodes, rad.
    step
        The step asked for, rad, or None for the core's default.
    w, b
        The checked wavelengths (m) and baselines ((m, 3), metres): the default step's inputs.

    Returns
    -------
    float
        The step, rad.
    """
    spaced = [a for a in axes if len(a) > 1]
    if spaced:
        return float(spaced[0][1] - spaced[0][0])
    # a window holding a single node: the lattice step of the core, eq. (15) by default
    if step is not None:
        requested = step
    else:
        requested = float(np.min(w)) / (10.0 * float(np.max(np.linalg.norm(b, axis=1))))
    return float(np.pi / np.ceil(np.pi / requested))


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
    length = checked_length(baseline_length_m)
    p, s, w, b = checked_inputs(p, los, [[length, 0.0, 0.0]], wavelength, n_baselines=1)
    win = checked_baseline_window(window_deg)
    with named_lobe(b, "baseline_length_m"):
        est = _core.ml_search(
            p,
            s,
            w,
            b,
            statistic=statistic,
            step_rad=checked_step(step_deg),
            window_rad=win,
            search="exhaustive",
            refine=refine,
            two_dimensional=True,
        )
    return _baseline_direction(est.angles_rad, est.z_max, est.cells_evaluated, est.step_rad)


def _baseline_direction(angles: NDArray[np.float64], z: float, cells: int, step: float) -> BaselineDirection:
    """The :class:`BaselineDirection` of the core's search: its psi (the heading's negative) and theta
    (the elevation), rad, statistic, cells evaluated and step, rad."""
    psi, theta = angles[0], angles[1]
    return BaselineDirection(
        heading_deg=float(np.degrees(-psi) % 360.0),
        elevation_deg=float(np.degrees(theta)),
        direction_enu=direction_enu(-psi, theta),
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
