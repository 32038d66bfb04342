"""The three platform presets, a car, a ship and an aircraft: each a
:class:`~gnssatt.sim.platforms.Trajectory`, an antenna array, a :class:`~gnssatt.sim.platforms.Blockage`
and a base handed to :func:`~gnssatt.sim.platforms.simulate_platform` (frames and truth as described
there)."""

from __future__ import annotations

import inspect
from collections.abc import Callable
from os import PathLike
from typing import Any, TypeVar

import numpy as np
from numpy.typing import ArrayLike, NDArray

from gnssatt._arrays import integer, scalar, shaped
from gnssatt.errors import InvalidInputError
from gnssatt.rinex.writer import MAX_SPAN_S
from gnssatt.sim.platforms import (
    MAX_LEGS,
    MAX_LEVER_ARM_M,
    MAX_SPEED_M_S,
    Blockage,
    Leg,
    NoiseProfile,
    SimulatedPlatform,
    Trajectory,
    simulate_platform,
)

__all__ = ["aircraft", "car", "ship"]


def _array(n_antennas: int, along_m: float, across_m: float, mast_m: float = 0.0) -> NDArray[np.float64]:
    """Lever arms of a preset array: antenna 1 ``along_m`` towards the nose, antenna 2 ``across_m``
    towards the right wing, all ``mast_m`` above the reference point."""
    n = integer("n_antennas", n_antennas, minimum=2, maximum=3)
    arms = np.array([[0.0, mast_m, 0.0], [along_m, mast_m, 0.0], [0.0, mast_m, across_m]])
    return arms[:n]


def _base(value: ArrayLike) -> NDArray[np.float64]:
    """A preset's base offset: always a (3,) array (a preset always writes its base)."""
    return shaped("base_offset_enu_m", value, "(3,)", (3,))


def _separations(baseline_m: object) -> tuple[float, float]:
    """``baseline_m`` as the (along, across) separations of a preset array, each in (0, MAX_LEVER_ARM_M] m."""
    ab = shaped("baseline_m", baseline_m, "(2,)", (2,))
    if not np.all((ab > 0.0) & (ab <= MAX_LEVER_ARM_M)):
        raise InvalidInputError(f"expected baseline_m in (0, {MAX_LEVER_ARM_M}] m, got {ab.tolist()}")
    return float(ab[0]), float(ab[1])


def _checked(name: str, value: float, lo: float, hi: float, unit: str) -> float:
    return scalar(name, value, minimum=lo, maximum=hi, unit=unit)


_F = TypeVar("_F", bound=Callable[..., Any])

# What the presets' docstrings share, written once: ``_preset_doc`` puts each block where the docstring names
# it (``{session}``, ``{baseline}``, ``{tail}``), so that the presets document one contract in one wording.
_PRESET_DOC_BLOCKS = {
    "{session}": """duration_s, interval_s
    Session length and epoch spacing, s.
noise
    Noise profile or its name (:data:`NOISE_PROFILES`).""",
    "{baseline}": """baseline_m
    Along and across separations of the array, m (0.3 to 5 m in the presets' use; up to
    ``MAX_LEVER_ARM_M``).""",
    "{tail}": """start_s
    First epoch after ``2024-03-01T10:00:00`` GPST, s (the default: eight GPS satellites above 10
    degrees, of the 24 nominal ones).
rng
    Seed or generator (:func:`simulate_platform`).

Returns
-------
SimulatedPlatform

Raises
------
InvalidTypeError, InvalidInputError, WorkLimitError
    As :func:`simulate_platform`""",
}


def _preset_doc(fn: _F) -> _F:
    """``fn`` with the shared blocks of ``_PRESET_DOC_BLOCKS`` written into its docstring."""
    doc = inspect.cleandoc(fn.__doc__ or "")
    for marker, block in _PRESET_DOC_BLOCKS.items():
        if marker not in doc:
            raise AssertionError(f"{fn.__name__}'s docstring lacks {marker}")
        doc = doc.replace(marker, block)
    fn.__doc__ = doc
    return fn


@_preset_doc
def car(
    folder: str | PathLike[str],
    *,
    n_antennas: int = 2,
    duration_s: float = 60.0,
    interval_s: float = 0.1,
    noise: str | NoiseProfile = "gps_l1_ublox",
    speed_m_s: float = 12.0,
    turn_radius_m: float = 40.0,
    baseline_m: tuple[float, float] = (1.2, 0.9),
    base_offset_enu_m: ArrayLike = (-150.0, 80.0, -1.5),
    start_s: float = 7200.0,
    rng: int | np.random.Generator | None = None,
) -> SimulatedPlatform:
    """A car at 10 Hz on a block circuit: straights of 10 s and 90-degree turns at ``turn_radius_m``
    (right, right, left, ...), tree-lined from 20 % to 45 % of the session (mask 15 degrees along the road,
    45 across), a 3 s outage (a bridge) at 55 % and a 2 s one at 80 %.

    Parameters
    ----------
    folder
        Existing folder for the files (:func:`simulate_platform`).
    n_antennas
        2 (roof antennas ``baseline_m[0]`` apart along the car) or 3 (a third ``baseline_m[1]`` to the
        right of the first).
    {session}
    speed_m_s, turn_radius_m
        Speed, m/s, and the radius of every turn, m (turn rate ``speed / radius``).
    {baseline}
    base_offset_enu_m
        Static base from the start point, ENU, m.
    {tail}; ``turn_radius_m`` not in [1, 1e4] m.

    Examples
    --------
    A one-second session: its first outage (3 s from 55 % of the session) leaves 6 of the 11 epochs at the
    antennas, all 11 at the base:

    >>> import tempfile
    >>> from gnssatt import sim
    >>> from gnssatt.rinex import read_obs
    >>> with tempfile.TemporaryDirectory() as folder:
    ...     run = sim.car(folder, n_antennas=3, duration_s=1.0, rng=1)
    ...     names = [p.name for p in (*run.obs_paths, run.base_path)]
    ...     n_epochs = [len(read_obs(p).time) for p in (run.obs_paths[0], run.base_path)]
    >>> names, n_epochs, round(float(run.heading_deg[0]), 6)
    (['ant0.rnx', 'ant1.rnx', 'ant2.rnx', 'base.rnx'], [6, 11], 30.0)
    """
    speed = _checked("speed_m_s", speed_m_s, 0.1, MAX_SPEED_M_S, "m/s")
    radius = _checked("turn_radius_m", turn_radius_m, 1.0, 1e4, "m")
    duration = _checked("duration_s", duration_s, 0.0, MAX_SPAN_S, "s")
    rate = np.degrees(speed / radius)
    turn_s = 90.0 / rate
    legs: list[Leg] = []
    signs = (1.0, 1.0, -1.0)
    while sum(x.duration_s for x in legs) <= duration and len(legs) < MAX_LEGS - 1:
        legs += [Leg(10.0, speed), Leg(turn_s, speed, signs[(len(legs) // 2) % 3] * rate)]
    d = duration
    block = Blockage(
        outages_s=((0.55 * d, 0.55 * d + 3.0), (0.8 * d, 0.8 * d + 2.0)), tree_lined_s=((0.2 * d, 0.45 * d),)
    )
    along, across = _separations(baseline_m)
    return simulate_platform(
        folder, Trajectory(tuple(legs), heading0_deg=30.0), _array(n_antennas, along, across),
        duration_s=duration, interval_s=interval_s, noise=noise, blockage=block,
        base_offset_enu_m=_base(base_offset_enu_m), start_s=start_s, rng=rng,
    )  # fmt: skip


@_preset_doc
def ship(
    folder: str | PathLike[str],
    *,
    n_antennas: int = 2,
    duration_s: float = 120.0,
    interval_s: float = 1.0,
    noise: str | NoiseProfile = "gps_l1_ublox",
    roll_amplitude_deg: float = 15.0,
    pitch_amplitude_deg: float = 10.0,
    heave_amplitude_m: float = 1.5,
    baseline_m: tuple[float, float] = (4.0, 3.0),
    base_offset_enu_m: ArrayLike = (-300.0, -200.0, 2.0),
    start_s: float = 7200.0,
    rng: int | np.random.Generator | None = None,
) -> SimulatedPlatform:
    """A ship at 6 m/s in a swell: roll ``roll_amplitude_deg`` with an 8 s period, pitch
    ``pitch_amplitude_deg`` with 6 s, heave ``heave_amplitude_m`` with 7 s, a 60-degree turn at 1 deg/s
    after a third of the session; antennas on a mast 8 m above the roll centre.

    Parameters
    ----------
    folder
        Existing folder for the files (:func:`simulate_platform`).
    n_antennas
        2 (``baseline_m[0]`` apart fore-aft) or 3 (a third ``baseline_m[1]`` to starboard).
    {session}
    roll_amplitude_deg, pitch_amplitude_deg, heave_amplitude_m
        Swell amplitudes (degrees, degrees, m).
    {baseline}
    base_offset_enu_m
        Static base (a quay) from the start point (the origin, at sea level), ENU, m.
    {tail}.

    Examples
    --------
    The roll reaches its amplitude a quarter of its 8 s period in:

    >>> import tempfile
    >>> from gnssatt import sim
    >>> with tempfile.TemporaryDirectory() as folder:
    ...     run = sim.ship(folder, duration_s=2.0, rng=1)
    >>> [round(float(x), 3) for x in run.roll_deg]
    [0.0, 10.607, 15.0]
    """
    d = _checked("duration_s", duration_s, 0.0, MAX_SPAN_S, "s")
    legs = (Leg(d / 3, 6.0), Leg(60.0, 6.0, 1.0), Leg(d, 6.0))
    traj = Trajectory(
        legs, heading0_deg=120.0, roll_amplitude_deg=roll_amplitude_deg, roll_period_s=8.0,
        pitch_amplitude_deg=pitch_amplitude_deg, pitch_period_s=6.0, heave_amplitude_m=heave_amplitude_m,
        heave_period_s=7.0, height_m=0.0,
    )  # fmt: skip
    along, across = _separations(baseline_m)
    return simulate_platform(
        folder, traj, _array(n_antennas, along, across, mast_m=8.0), duration_s=d, interval_s=interval_s,
        noise=noise, base_offset_enu_m=_base(base_offset_enu_m), start_s=start_s, rng=rng,
    )  # fmt: skip


@_preset_doc
def aircraft(
    folder: str | PathLike[str],
    *,
    n_antennas: int = 2,
    duration_s: float = 120.0,
    interval_s: float = 0.5,
    noise: str | NoiseProfile = "gps_l1_ublox",
    speed_m_s: float = 60.0,
    baseline_m: tuple[float, float] = (3.0, 4.5),
    base_offset_enu_m: ArrayLike = (-500.0, -300.0, 0.0),
    start_s: float = 7200.0,
    rng: int | np.random.Generator | None = None,
) -> SimulatedPlatform:
    """A light aircraft 300 m above the airfield at ``speed_m_s``: a climb at 4 m/s (a quarter of the
    session), level flight, a banked right turn at the standard rate (3 deg/s, coordinated: bank
    ``atan(v omega / g)``, 18 degrees at 60 m/s) through 180 degrees, level flight again.

    Parameters
    ----------
    folder
        Existing folder for the files (:func:`simulate_platform`).
    n_antennas
        2 (``baseline_m[0]`` apart along the fuselage) or 3 (a third ``baseline_m[1]`` out on the right wing).
    {session}
    speed_m_s
        Airspeed (ground speed, no wind), m/s.
    {baseline}
    base_offset_enu_m
        Static base on the airfield, ENU from the origin (300 m below the start), m.
    {tail}.

    Examples
    --------
    The climb's flight-path angle ``atan(4 / 60)``:

    >>> import tempfile
    >>> from gnssatt import sim
    >>> with tempfile.TemporaryDirectory() as folder:
    ...     run = sim.aircraft(folder, duration_s=1.0, rng=1)
    >>> round(float(run.pitch_deg[0]), 3), round(float(run.position_enu_m[0, 2]), 1)
    (3.814, 300.0)
    """
    d = _checked("duration_s", duration_s, 0.0, MAX_SPAN_S, "s")
    v = _checked("speed_m_s", speed_m_s, 1.0, MAX_SPEED_M_S, "m/s")
    legs = (Leg(d / 4, v, 0.0, 4.0), Leg(d / 8, v), Leg(60.0, v, 3.0), Leg(d, v))
    traj = Trajectory(legs, heading0_deg=250.0, start_enu_m=(0.0, 0.0, 300.0), banked=True)
    along, across = _separations(baseline_m)
    return simulate_platform(
        folder, traj, _array(n_antennas, along, across), duration_s=d, interval_s=interval_s, noise=noise,
        base_offset_enu_m=_base(base_offset_enu_m), start_s=start_s, rng=rng,
    )  # fmt: skip
