"""Attitude and baseline-direction time series from recorded RINEX data of antennas on one platform, by the
Rust observation engine (``gnssatt._core.gnss_run``; ``docs/observation_engine.md``).

Two antennas and no baselines: baseline-direction mode, the azimuth (clockwise from North) and elevation
of the vector from the first antenna to the second. Three or more antennas with body-frame baselines:
attitude mode, heading / pitch / roll (eq. (5) of Bunyaeva et al., compass heading ``= -psi``).

Python only reads the files (:func:`~gnssatt.gnss.session_input.session_input`,
:func:`~gnssatt.rinex.nav.nav_input`), checks the arguments and shapes the results; the engine
does the rest in one GIL-released call: single-point positioning of every receiver (Klobuchar,
Saastamoinen), double differences of every system and frequency slot chosen, float solution, LAMBDA fixing
with a success-rate gate and partial fixing (or the ambiguity-function grid, ``method="ml"``).

Methods (the ``method`` column says which produced each row): ``"lambda"`` (double differences, LAMBDA;
geometry-constrained in attitude mode, then Wahba's problem), ``"ml"`` (the grid on the wrapped single
differences), ``"auto"`` (``"lambda"`` for baselines beyond 100 m, else ``"ml"``).
"""

from __future__ import annotations

import warnings
from collections.abc import Sequence
from os import PathLike
from typing import Any, Literal

from numpy.typing import ArrayLike

from gnssatt._arrays import choice, flag
from gnssatt.gnss._attitude_checks import (
    KNOWN_LENGTH_PROBE_EPOCHS,
    KNOWN_LENGTH_TOLERANCE_M,
    KNOWN_LENGTH_TOLERANCE_RELATIVE,
    MIN_DIRECTION_BASELINE_M,
    EngineWarning,
    ZeroBaselineWarning,
    check_grid_options,
    check_known_lengths,
    check_method,
    probe_known_lengths,
    undirected,
)
from gnssatt.gnss._attitude_inputs import (
    antenna_options,
    check_nav_covers,
    frequency_slots,
    numeric_options,
    obs_list,
    system_letters,
)
from gnssatt.gnss._attitude_series import SYSTEMS, AttitudeSeries, CombinedBaseline, series_from_session
from gnssatt.rinex.nav import RinexNav, navigation
from gnssatt.rinex.obs import RinexObs, read_obs

__all__ = [
    "KNOWN_LENGTH_TOLERANCE_M",
    "KNOWN_LENGTH_TOLERANCE_RELATIVE",
    "MIN_DIRECTION_BASELINE_M",
    "SYSTEMS",
    "AttitudeSeries",
    "CombinedBaseline",
    "EngineWarning",
    "ZeroBaselineWarning",
    "attitude_from_rinex",
]

MethodName = Literal["auto", "ml", "lambda"]
MotionName = Literal["static", "moving"]
FilterName = Literal["static", "kinematic", "velocity"]


def attitude_from_rinex(
    observations: Sequence[RinexObs | str | PathLike[str]],
    nav: RinexNav | str | PathLike[str] | Sequence[str | PathLike[str]],
    baselines: ArrayLike | None = None,
    *,
    method: MethodName = "auto",
    motion: MotionName | None = None,
    continuity: bool = False,
    filter: FilterName | None = None,
    rigid: bool = False,
    systems: str = SYSTEMS,
    frequencies: int | Literal["all"] = "all",
    elevation_mask_deg: float | None = None,
    min_success_rate: float | None = None,
    ratio_threshold: float | None = None,
    max_failure_rate: float | None = None,
    base_position_m: ArrayLike | None = None,
    step_deg: float | None = None,
    window_deg: float | None = None,
    baseline_length_m: ArrayLike | None = None,
) -> AttitudeSeries:
    """Attitude (with ``baselines``) or baseline direction (two antennas, none) at every common epoch.

    Parameters
    ----------
    observations
        Observation files (or read :class:`RinexObs`), one per antenna, the reference antenna first.
    nav
        Navigation file(s) or a read :class:`RinexNav`.
    baselines
        (n_ant - 1, 3) antenna positions relative to the first, body frame of Bunyaeva et al. (X nose, Y up,
        Z right wing), m; required with three or more antennas.
    method
        ``"auto"``, ``"ml"`` or ``"lambda"`` (module docstring).
    motion
        ``"static"``: the ambiguities of the whole session fixed once (a static pair); ``"moving"``: every
        epoch fixed on its own (or held along arcs with ``continuity``). Default: static for two antennas
        (moving with ``continuity``), moving in attitude mode, where ``"static"`` is refused.
    continuity
        Moving mode: hold fixed integers along slip-free arcs while each epoch's data agree with them
        (chi-square), instead of fixing every epoch afresh; in attitude mode the integers of the whole
        array, new arcs fixed on them, a fresh fix replacing them only when the data prefer it
        (``fix_state`` says ``held``; ``docs/observation_engine.md``). Refused with ``motion="static"``
        (one set for the session already).
    filter
        A multi-epoch Kalman filter of each baseline (implies ``motion="moving"``) with the
        process model ``"static"`` (the baseline does not change), ``"kinematic"`` (a random walk of
        30 m/sqrt(s): each epoch's baseline from its own data and the ambiguities carried along their arcs)
        or ``"velocity"`` (constant velocity, white acceleration 1 (m/s^2)^2/Hz); integers fixed on the
        filter's covariance every epoch and held while they agree with it (``fix_state``;
        ``docs/observation_engine.md``). With ``baseline_length_m`` the filter's fix is the
        length-constrained integer search on its covariance, and every fix's length is checked against the
        known one. With ``baselines`` (attitude mode) each rover's baseline has its filter, which knows
        the body baseline's length and holds its own integers; the filtered floats are fixed together
        under the body baselines (the constrained search and its simulated success rate on the
        filters' covariances), and an epoch the filters leave float is fixed on its own as without a
        filter. Refused with ``motion="static"``, ``continuity`` and ``method="ml"``.
    rigid
        With ``filter``: both antennas are on one rigid body (a moving base on the rover's vehicle), so the
        baseline's length is constant. The filter learns it from its first fixes and refuses a fix whose
        length disagrees beyond 4 sigma (``docs/observation_engine.md``). Wrong for a rover moving against a
        static base (its length changes); refused without ``filter`` and with ``baseline_length_m`` or
        ``baselines`` (a known length or body baselines are checked already).
    systems
        Satellite systems, letters among ``"GRECJ"`` (default all).
    frequencies
        Frequency slots used per system, 1..3 or ``"all"`` (3): slot 1 L1/G1/E1/B1I, 2 L2/G2/E5b/B2I,
        3 L5/G3/E5a/B3I (``docs/observation_engine.md``).
    elevation_mask_deg
        Elevation mask at the reference antenna, degrees (default: the engine's, 10).
    min_success_rate
        Smallest bootstrapped success rate of the ambiguity set fixed; the largest subset that reaches it
        is fixed when the full set does not (default ``gnssatt._core.GNSS_DEFAULT_MIN_SUCCESS_RATE``).
    ratio_threshold
        Ratio-test acceptance threshold, >= 1 (default ``gnssatt._core.GNSS_DEFAULT_RATIO_THRESHOLD``).
    max_failure_rate
        In [0, 0.1]: a full set below ``min_success_rate`` whose ratio passes ``ratio_threshold`` is still
        fixed when the ratio also passes the fixed-failure-rate threshold for this probability of accepting
        a wrong fix, simulated for the epoch's own float covariance (0: off; default
        ``gnssatt._core.GNSS_DEFAULT_MAX_FAILURE_RATE``, ``docs/observation_engine.md``).
    base_position_m
        (3,) surveyed ECEF position of the reference antenna, m; default its code solution at each epoch.
    step_deg, window_deg
        ML grid step (default eq. (15) of Bunyaeva et al.) and search window around the previous epoch's
        solution (default the whole domain), degrees.
    baseline_length_m
        Baseline mode: the known distance of each rover antenna from the reference antenna (a number for
        two antennas, else (n_ant - 1,)), m, in [0.01, 1e4]: the integers are fixed with the length
        constraint, gated by its own simulated success rate (``docs/observation_engine.md``).

    Returns
    -------
    AttitudeSeries
        One row per epoch common to all files.

    Warns
    -----
    EngineWarning
        What the engine says a user should know (also in :attr:`AttitudeSeries.warnings`).
    ZeroBaselineWarning
        Baseline mode: the baseline is shorter than :data:`MIN_DIRECTION_BASELINE_M` (one antenna seen
        twice); azimuth and elevation are NaN at those epochs, the baselines are kept.

    Raises
    ------
    RinexError
        Unreadable files, no common epochs, a file without phase or a system another file lacks; a
        navigation file with no record of the satellites observed within 6 h of their epochs (of another
        day), named with both time spans.
    InvalidTypeError
        ``observations`` not a list of files or :class:`RinexObs`, ``nav`` not a :class:`RinexNav`, file
        or list of files, another argument of the wrong kind.
    InvalidInputError
        Fewer than two observations, baselines of the wrong shape or not finite, an unknown method, motion
        or system letter, an option out of its range; ``method="ml"`` where the likelihood grid failed
        or solved no epoch; ``step_deg`` or ``window_deg`` where the grid never runs (``method="lambda"``,
        a ``filter``) or solved no epoch (``method="auto"`` with every epoch fixed), since they would change
        nothing; a ``baseline_length_m`` that the fixed epochs contradict (beyond
        :data:`KNOWN_LENGTH_TOLERANCE_M` plus :data:`KNOWN_LENGTH_TOLERANCE_RELATIVE` of it), the
        message giving the measured length: checked first on the first :data:`KNOWN_LENGTH_PROBE_EPOCHS`
        epochs of a longer session, before the session runs, then on the session.

    Examples
    --------
    Three epochs of a 1 m triangle simulated at heading 330, pitch 10, roll -5 deg (eq. (5) angles
    ``psi = 30``, ``theta = 10``, ``phi = -5``; GPS + Galileo, two frequencies, phase noise 0.01 mm, code
    1 cm, no atmosphere), written as RINEX and read back: every epoch fixed, the attitude given back:

    >>> import tempfile
    >>> import numpy as np
    >>> from gnssatt.gnss.attitude import attitude_from_rinex
    >>> from gnssatt.sim import equilateral_triangle
    >>> from gnssatt.sim.rinex_scenario import simulate_gnss_rinex
    >>> antennas = equilateral_triangle(1.0, plane="xz")  # (3, 3) m, body (X nose, Y up, Z right wing)
    >>> quiet = {"phase_sigma_m": 1e-5, "code_sigma_m": 0.01, "atmosphere": False}
    >>> with tempfile.TemporaryDirectory() as folder:
    ...     sim = simulate_gnss_rinex(folder, antennas, [30.0, 10.0, -5.0], systems="GE", frequencies=2,
    ...                               n_epochs=3, rng=1, **quiet)
    ...     series = attitude_from_rinex(list(sim.obs_paths), sim.nav_path, antennas[1:])
    >>> series.mode, series.angle_names, series.fixed.tolist()
    ('attitude', ('heading_deg', 'pitch_deg', 'roll_deg'), [1, 1, 1])
    >>> np.round(series.angles_deg, 1) + 0.0
    array([[330.,  10.,  -5.],
           [330.,  10.,  -5.],
           [330.,  10.,  -5.]])
    """
    from gnssatt import _core
    from gnssatt.gnss.session_input import session_input
    from gnssatt.rinex.nav import nav_input

    method = choice("method", method, _core.GNSS_METHODS)
    if motion is not None:
        motion = choice("motion", motion, _core.GNSS_MOTIONS)
    continuity = flag("continuity", continuity)
    rigid = flag("rigid", rigid)
    if filter is not None:
        filter = choice("filter", filter, _core.GNSS_FILTERS)
    systems = system_letters(systems)
    n_freq = frequency_slots(frequencies)
    opts, grid_options = numeric_options(
        method,
        filter,
        elevation_mask_deg=elevation_mask_deg,
        min_success_rate=min_success_rate,
        ratio_threshold=ratio_threshold,
        max_failure_rate=max_failure_rate,
        base_position_m=base_position_m,
        step_deg=step_deg,
        window_deg=window_deg,
    )
    observations = obs_list("observations", observations)
    opts.update(antenna_options(len(observations) - 1, baselines, baseline_length_m))
    if motion is None:
        motion = "moving" if baselines is not None or continuity or filter is not None else "static"
    obs = [o if isinstance(o, RinexObs) else read_obs(o) for o in observations]
    nv = navigation(nav, "nav")
    si = session_input(obs, systems=systems, frequencies=n_freq, nav=nv)
    check_nav_covers(si.time_gpst_ns, si.sats, nv)
    ni = nav_input(nv)
    modes: dict[str, Any] = {
        "systems": systems,
        "frequencies": n_freq,
        "motion": motion,
        "continuity": continuity,
    }
    options = _core.GnssOptions(  # checks every option
        **modes, method=method, filter=filter, rigid=rigid, **opts
    )
    if baseline_length_m is not None and len(si.time_gpst_ns) > KNOWN_LENGTH_PROBE_EPOCHS:
        probe_known_lengths(opts["baseline_lengths_m"], si, ni.navigation(), modes, opts)
    s = _core.gnss_run(si.observations(), ni.navigation(), options)
    series = series_from_session(s, si.signal_codes)
    check_method(method, series)
    check_grid_options(grid_options, series)
    if baseline_length_m is not None:
        check_known_lengths(opts["baseline_lengths_m"], series, "the session")
    for message in s.warnings:
        warnings.warn(message, EngineWarning, stacklevel=2)
    return undirected(series, [str(o.path) for o in obs])
