"""GNSS constellations: nominal GPS and GLONASS, Walker patterns, satellite states at any time.

Conventions of :mod:`gnssatt.sim`: SI units and radians inside (arguments in degrees end in ``_deg``);
``t`` in seconds from the scenario epoch; ECI/ECEF as in :mod:`gnssatt.frames` (ECEF = ECI rotated by
``theta0 + OMEGA_E t``). Orbits are two-body Keplerian (:class:`~gnssatt.orbit.kepler.KeplerOrbits`), so the
nominal constellations keep their geometry but drift from the real ones over days (no J2 node regression).

Sources of the nominal elements
-------------------------------
GPS (:func:`gps_nominal`): the 24 baseline slots, RAAN and argument of latitude at the defined epoch
(0000Z 1 July 1993, Greenwich hour angle 18h 36m 14.4s, FK5/J2000), from the GPS SPS Performance Standard,
3rd edition (October 2001), Table 3-1 "Reference Orbit Slot Assignments as of the Defined Epoch"; the later
editions (2008, 2020 Table 3.2-1) keep these baseline slots. The 2001 table was read here in a secondary
transcription (also printed as Table 3.1 in Kaplan & Hegarty, *Understanding GPS*, 2nd ed.; the two copies
differ for D3, 35.156 deg versus 35.136 deg; 35.156 deg is used). The 2020 edition itself could not be
consulted, so its expandable-slot variants (B1F/B1A, D2F/D2A, F2F/F2A) are not built in; pass extra
satellites through ``extra_slots_deg``. Inclination 55 deg, semi-major axis 26,559.7 km, eccentricity 0
(nominal values of the same table). To put the Earth where it was at that epoch use
``theta0_rad = GPS_SLOT_EPOCH_GHA_RAD``.

GLONASS (:func:`glonass_nominal`): GLONASS ICD (edition 5.1, 2008), section 3.5: 24 satellites in 3 planes
120 deg apart in RAAN, 8 per plane 45 deg apart in argument of latitude, planes shifted by 15 deg in
argument of latitude, inclination 64.8 deg, semi-major axis 25,510 km (draconic period 11 h 15 min 44 s);
slots 1-8 in plane 1, 9-16 in plane 2, 17-24 in plane 3. Assumed here (the ICD fixes spacings, not the
absolute phase or the numbering direction): RAAN of plane p is ``raan0 + 120 (p - 1)`` deg and slot
``s = 8 (p - 1) + j`` (j = 1..8) has argument of latitude ``u0 + 45 (j - 1) + 15 (p - 1)`` deg at ``t = 0``.
Frequency channels per slot: the long-standing published assignment (e.g. IAC / UNB "GLONASS
Constellation Status" tables; slots 10, 12, 13, 15, 19, 20 with channels -7, -1, -2, 0, 3, 2 checked there)
``1:1 2:-4 3:5 4:6 5:1 6:-4 7:5 8:6 9:-2 10:-7 11:0 12:-1 13:-2 14:-7 15:0 16:-1 17:4 18:-3 19:3 20:2
21:4 22:-3 23:3 24:2``; antipodal satellites (slots j and j + 4 of one plane) share a channel.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from gnssatt._arrays import float_array, instance, integer, readonly, scalar, text
from gnssatt.constants import GPS_L1_HZ, GPS_L2_HZ, SPEED_OF_LIGHT_M_S, glonass_frequency_hz
from gnssatt.errors import InvalidInputError, InvalidTypeError, WorkLimitError
from gnssatt.frames import eci_to_ecef
from gnssatt.orbit.kepler import KeplerOrbits

__all__ = [
    "GLONASS_SLOT_CHANNELS",
    "GPS_BASELINE_SLOTS",
    "GPS_SLOT_EPOCH_GHA_RAD",
    "Constellation",
    "glonass_nominal",
    "gps_nominal",
    "walker",
]

#: GPS baseline 24-slot constellation: slot -> (RAAN deg, argument of latitude deg) at 0000Z 1 July 1993
#: (GPS SPS Performance Standard 2001, Table 3-1).
GPS_BASELINE_SLOTS: dict[str, tuple[float, float]] = {
    "A1": (272.847, 268.126), "A2": (272.847, 161.786), "A3": (272.847, 11.676), "A4": (272.847, 41.806),
    "B1": (332.847, 80.956), "B2": (332.847, 173.336), "B3": (332.847, 309.976), "B4": (332.847, 204.376),
    "C1": (32.847, 111.876), "C2": (32.847, 11.796), "C3": (32.847, 339.666), "C4": (32.847, 241.556),
    "D1": (92.847, 135.226), "D2": (92.847, 265.446), "D3": (92.847, 35.156), "D4": (92.847, 167.356),
    "E1": (152.847, 197.046), "E2": (152.847, 302.596), "E3": (152.847, 66.066), "E4": (152.847, 333.686),
    "F1": (212.847, 238.886), "F2": (212.847, 345.226), "F3": (212.847, 105.206), "F4": (212.847, 135.346),
}  # fmt: skip

#: Greenwich hour angle at the GPS slot epoch (18h 36m 14.4s), rad.
GPS_SLOT_EPOCH_GHA_RAD = float(np.radians((18 + 36 / 60 + 14.4 / 3600) * 15.0))

#: GLONASS orbital slot (1..24) -> FDMA channel number.
GLONASS_SLOT_CHANNELS: dict[int, int] = {
    1: 1, 2: -4, 3: 5, 4: 6, 5: 1, 6: -4, 7: 5, 8: 6,
    9: -2, 10: -7, 11: 0, 12: -1, 13: -2, 14: -7, 15: 0, 16: -1,
    17: 4, 18: -3, 19: 3, 20: 2, 21: 4, 22: -3, 23: 3, 24: 2,
}  # fmt: skip

_GPS_A_M = 26_559_700.0
_GPS_INC_DEG = 55.0
_GLO_A_M = 25_510_000.0
_GLO_INC_DEG = 64.8

#: Most satellites :func:`walker` builds (and :func:`gps_nominal` with ``extra_slots_deg``): well above any
#: navigation constellation, small enough that every per-satellite array stays cheap.
MAX_SATELLITES = 100_000


@dataclass(frozen=True)
class Constellation:
    """Satellites with their orbits and carrier frequencies.

    Attributes
    ----------
    ids
        Satellite identifiers, RINEX style: ``"G01"``.. for GPS, ``"R01"``.. for GLONASS.
    orbits
        Keplerian orbits of the satellites, in the order of ``ids``.
    frequencies_hz
        Carrier frequency per satellite and band, Hz; keys are band names (``"L1"``, ``"L2"``), values
        arrays of shape (n_sat,).
    slots
        Orbital slot names (GPS ``"A1"``, GLONASS ``"1"``..``"24"``) or ``""`` where none.
    glonass_channels
        (n_sat,) FDMA channel numbers; 0 for non-GLONASS satellites (see ``ids``).
    """

    ids: tuple[str, ...]
    orbits: KeplerOrbits
    frequencies_hz: dict[str, NDArray[np.float64]]
    slots: tuple[str, ...]
    glonass_channels: NDArray[np.int64]

    def __post_init__(self) -> None:
        instance("orbits", self.orbits, KeplerOrbits, "a gnssatt.sim.KeplerOrbits")
        instance("ids", self.ids, tuple, "a tuple of str")
        instance("slots", self.slots, tuple, "a tuple of str")
        instance("frequencies_hz", self.frequencies_hz, dict, "a dict of band name -> (n_sat,) array")
        if not all(isinstance(i, str) for i in (*self.ids, *self.slots, *self.frequencies_hz)):
            raise InvalidTypeError("expected ids, slots and the band names of frequencies_hz as str")
        n = len(self.orbits)
        if len(self.ids) != n or len(self.slots) != n or np.shape(self.glonass_channels) != (n,):
            raise InvalidInputError(
                f"expected ids, slots and glonass_channels of length {n} (the number of orbits), got "
                f"{len(self.ids)}, {len(self.slots)}, {np.shape(self.glonass_channels)}"
            )
        if len(set(self.ids)) != n:
            raise InvalidInputError(f"expected unique satellite ids, got {list(self.ids)}")
        freqs = {
            band: float_array(f"frequencies_hz[{band!r}]", f, ndim=(0, 1, 2), shape=f"({n},)").copy()
            for band, f in self.frequencies_hz.items()
        }
        channels = np.array(self.glonass_channels)
        if channels.size and channels.dtype.kind not in "iu":
            raise InvalidTypeError(f"expected glonass_channels as integers, got dtype {channels.dtype}")
        object.__setattr__(self, "frequencies_hz", freqs)
        object.__setattr__(self, "glonass_channels", channels.astype(np.int64))
        for band, f in freqs.items():
            if np.shape(f) != (n,):
                raise InvalidInputError(
                    f"expected frequencies_hz[{band!r}] of shape ({n},), got {np.shape(f)}"
                )
            if np.any(f <= 0):
                raise InvalidInputError(f"expected frequencies_hz[{band!r}] > 0, got minimum {f.min()}")
            readonly(f)
        readonly(self.glonass_channels)

    def __len__(self) -> int:
        return len(self.ids)

    def __add__(self, other: Constellation) -> Constellation:
        """Both constellations in one (e.g. GPS + GLONASS); only bands present in both are kept."""
        if not isinstance(other, Constellation):
            return NotImplemented
        o1, o2 = self.orbits, other.orbits

        def cat(name: str) -> NDArray[np.float64]:
            return np.concatenate([getattr(o1, name), getattr(o2, name)])

        orbits = KeplerOrbits(
            cat("semi_major_axis_m"),
            cat("eccentricity"),
            cat("inclination_rad"),
            cat("raan_rad"),
            cat("arg_perigee_rad"),
            cat("mean_anomaly_rad"),
            gm_m3_s2=o1.gm_m3_s2,
        )
        bands = [b for b in self.frequencies_hz if b in other.frequencies_hz]
        freqs = {b: np.concatenate([self.frequencies_hz[b], other.frequencies_hz[b]]) for b in bands}
        return Constellation(
            self.ids + other.ids,
            orbits,
            freqs,
            self.slots + other.slots,
            np.concatenate([self.glonass_channels, other.glonass_channels]),
        )

    def wavelengths_m(self, band: str = "L1") -> NDArray[np.float64]:
        """(n_sat,) carrier wavelengths in metres for ``band``."""
        text("band", band)
        if band not in self.frequencies_hz:
            raise InvalidInputError(f"expected band in {sorted(self.frequencies_hz)}, got {band!r}")
        return SPEED_OF_LIGHT_M_S / self.frequencies_hz[band]

    def select(self, which: Sequence[str] | ArrayLike) -> Constellation:
        """The satellites named in ``which`` (ids), or selected by an index array / boolean mask (n_sat,)."""
        if isinstance(which, Sequence) and all(isinstance(w, str) for w in which) and len(which) > 0:
            missing = [w for w in which if w not in self.ids]
            if missing:
                raise InvalidInputError(
                    f"expected which as satellite ids from {list(self.ids)}, got unknown {missing}"
                )
            idx = np.array([self.ids.index(w) for w in which], dtype=np.int64)
        else:
            arr = np.asarray(which)
            if arr.dtype == bool:
                if arr.shape != (len(self),):
                    raise InvalidInputError(
                        f"expected a boolean mask of shape ({len(self)},), got {arr.shape}"
                    )
                idx = np.flatnonzero(arr)
            elif arr.dtype.kind in "iu" or arr.size == 0:
                idx = arr.astype(np.int64).reshape(-1)
                n = len(self)
                if idx.size and (idx.min() < -n or idx.max() >= n):
                    raise InvalidInputError(
                        f"expected which as indices in [-{n}, {n}), got [{idx.min()}, {idx.max()}]"
                    )
            else:
                raise InvalidTypeError(
                    f"expected which as satellite ids, indices or a boolean mask, got dtype {arr.dtype}"
                )
        return Constellation(
            tuple(self.ids[i] for i in idx),
            self.orbits.subset(idx),
            {b: f[idx] for b, f in self.frequencies_hz.items()},
            tuple(self.slots[i] for i in idx),
            self.glonass_channels[idx],
        )

    def state_eci(self, t: ArrayLike) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """Positions (m) and velocities (m/s) in ECI: (n_sat, 3) for scalar ``t``, (n_t, n_sat, 3) else."""
        return self.orbits.state_eci(t)

    def state_ecef(
        self, t: ArrayLike, theta0_rad: float = 0.0
    ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """Positions (m) and velocities (m/s, relative to the rotating Earth) in ECEF; shapes as
        :meth:`state_eci`."""
        r, v = self.orbits.state_eci(t)
        return eci_to_ecef(r, v, t, theta0_rad)


def _gps_ids(n: int, start: int = 1) -> tuple[str, ...]:
    return tuple(f"G{i:02d}" for i in range(start, start + n))


def gps_nominal(*, extra_slots_deg: Sequence[tuple[float, float]] = ()) -> Constellation:
    """The nominal 24-slot GPS constellation (plus optional extra satellites), circular orbits.

    Parameters
    ----------
    extra_slots_deg
        Additional satellites as ``(RAAN, argument of latitude at t = 0)`` pairs in degrees, on the same
        inclination and semi-major axis; they get ids ``G25``, ``G26``, ... and empty slot names.

    Returns
    -------
    Constellation
        ``G01``..``G24`` for slots A1..A4, B1..B4, ..., F1..F4 (module docstring for the source), with L1
        and L2 frequencies.

    Raises
    ------
    InvalidInputError
        A pair that is not two finite numbers (:class:`~gnssatt.errors.InvalidTypeError` for non-numbers).
    WorkLimitError
        More than ``MAX_SATELLITES - 24`` extra satellites.

    Examples
    --------
    Every satellite is on the 26 559.7 km circle, with a period of half a sidereal day (11.9658 h) and the L1
    wavelength ``c / 1575.42 MHz``; an extra satellite comes last as ``G25``:

    >>> import numpy as np
    >>> from gnssatt.orbit.constellation import gps_nominal
    >>> gps = gps_nominal(extra_slots_deg=[(272.847, 100.0)])
    >>> len(gps), gps.ids[0], gps.slots[0], gps.ids[-1]
    (25, 'G01', 'A1', 'G25')
    >>> r, v = gps.state_eci(0.0)  # (25, 3) m, m/s
    >>> np.unique(np.round(np.linalg.norm(r, axis=1) / 1e3, 3))  # km
    array([26559.7])
    >>> round(float(gps.orbits.period_s[0]) / 3600.0, 4), round(float(gps.wavelengths_m("L1")[0]), 6)
    (11.9658, 0.190294)
    """
    pairs = list(GPS_BASELINE_SLOTS.values())
    extra = list(instance("extra_slots_deg", extra_slots_deg, (Sequence,), "a sequence of (raan, u) pairs"))
    if len(extra) > MAX_SATELLITES - 24:
        raise WorkLimitError(f"{len(extra)} extra_slots_deg exceed the limit of {MAX_SATELLITES - 24}")
    for k, p in enumerate(extra):
        if not isinstance(p, Sequence | np.ndarray) or len(p) != 2:
            raise InvalidInputError(
                f"expected extra_slots_deg[{k}] as (raan_deg, arg_latitude_deg), got {p!r}"
            )
        name = f"extra_slots_deg[{k}]"
        pairs.append((scalar(f"{name}[0]", p[0]), scalar(f"{name}[1]", p[1])))
    raan, u = np.radians(np.array(pairs, dtype=np.float64)).T
    n = len(pairs)
    orbits = KeplerOrbits.circular(np.full(n, _GPS_A_M), np.full(n, np.radians(_GPS_INC_DEG)), raan, u)
    slots = tuple(GPS_BASELINE_SLOTS) + ("",) * (n - 24)
    freqs = {"L1": np.full(n, GPS_L1_HZ), "L2": np.full(n, GPS_L2_HZ)}
    return Constellation(_gps_ids(n), orbits, freqs, slots, np.zeros(n, dtype=np.int64))


def glonass_nominal(*, raan0_deg: float = 0.0, arg_latitude0_deg: float = 0.0) -> Constellation:
    """The nominal 24-satellite GLONASS constellation, circular orbits, with FDMA channels per slot.

    Parameters
    ----------
    raan0_deg
        RAAN of plane 1 (slots 1-8) in ECI, degrees.
    arg_latitude0_deg
        Argument of latitude of slot 1 at ``t = 0``, degrees.

    Returns
    -------
    Constellation
        ``R01``..``R24`` for slots 1..24 with L1/L2 FDMA frequencies of their channels (module docstring).

    Raises
    ------
    InvalidInputError
        ``raan0_deg`` or ``arg_latitude0_deg`` not finite (:class:`~gnssatt.errors.InvalidTypeError` for
        values that are not real numbers).

    Examples
    --------
    Slot 10 has channel -7, so its L1 carrier is ``1602 - 7 * 0.5625 = 1598.0625`` MHz; slots 1 and 5 are
    antipodal (45 deg x 4 apart in one plane) and share channel 1:

    >>> import numpy as np
    >>> from gnssatt.orbit.constellation import glonass_nominal
    >>> glo = glonass_nominal()
    >>> glo.ids[9], int(glo.glonass_channels[9]), float(glo.frequencies_hz["L1"][9]) / 1e6
    ('R10', -7, 1598.0625)
    >>> r, v = glo.state_eci(0.0)  # (24, 3) m, m/s
    >>> np.round(r[0] + r[4], 6) + 0.0, glo.glonass_channels[[0, 4]].tolist()
    (array([0., 0., 0.]), [1, 1])
    """
    raan0 = scalar("raan0_deg", raan0_deg)
    u0 = scalar("arg_latitude0_deg", arg_latitude0_deg)
    slot = np.arange(1, 25)
    plane = (slot - 1) // 8
    j = (slot - 1) % 8
    raan = np.radians(raan0 + 120.0 * plane)
    u = np.radians(u0 + 45.0 * j + 15.0 * plane)
    orbits = KeplerOrbits.circular(np.full(24, _GLO_A_M), np.full(24, np.radians(_GLO_INC_DEG)), raan, u)
    ch = np.array([GLONASS_SLOT_CHANNELS[int(s)] for s in slot], dtype=np.int64)
    freqs = {"L1": glonass_frequency_hz(ch, "L1"), "L2": glonass_frequency_hz(ch, "L2")}
    return Constellation(tuple(f"R{s:02d}" for s in slot), orbits, freqs, tuple(str(s) for s in slot), ch)


def _walker_pattern(n_sat: int, n_planes: int, phasing: int, prefix: str) -> tuple[int, int, int]:
    """The checked integers ``T/P/F`` of :func:`walker`, and its ``prefix`` checked (in the order the
    checks had inside :func:`walker`: the first bad argument is the one named)."""
    n_sat = integer("n_sat", n_sat, minimum=1, maximum=MAX_SATELLITES)
    n_planes = integer("n_planes", n_planes, minimum=1)
    phasing = integer("phasing", phasing)
    if abs(phasing) > 2**53:  # 360.0 * phasing must be exact, and finite (10**400 overflows float)
        raise InvalidInputError(f"expected phasing within +-2^53, got {phasing}")
    text("prefix", prefix)
    if len(prefix) != 1:
        raise InvalidInputError(f"expected prefix as one letter (the RINEX system), got {prefix!r}")
    if n_planes < 1 or n_sat < 1 or n_sat % n_planes:
        raise InvalidInputError(
            f"expected n_sat a positive multiple of n_planes >= 1, got {n_sat}/{n_planes}"
        )
    return n_sat, n_planes, phasing


def _walker_angles(
    n_sat: int, n_planes: int, phasing: int, raan0_deg: float
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """RAAN and argument of latitude at ``t = 0`` (rad) of each satellite of the pattern ``T/P/F``,
    satellites numbered plane by plane."""
    per = n_sat // n_planes
    k = np.arange(n_sat)
    p, j = k // per, k % per
    raan = np.radians(scalar("raan0_deg", raan0_deg) + 360.0 * p / n_planes)
    u = np.radians(360.0 * j / per + 360.0 * phasing * p / n_sat)
    return raan, u


def walker(
    n_sat: int,
    n_planes: int,
    phasing: int,
    *,
    inclination_deg: float,
    semi_major_axis_m: float,
    prefix: str = "G",
    frequency_hz: float = GPS_L1_HZ,
    raan0_deg: float = 0.0,
) -> Constellation:
    """A Walker delta pattern ``i: n_sat / n_planes / phasing`` of circular orbits (single band ``"L1"``).

    Plane p (0-based) has RAAN ``raan0 + 360 p / n_planes``; satellite j of plane p has argument of latitude
    ``360 j / (n_sat / n_planes) + 360 phasing p / n_sat`` degrees at ``t = 0``.

    Parameters
    ----------
    n_sat
        Number of satellites, 1 to ``MAX_SATELLITES``, a multiple of ``n_planes``.
    n_planes
        Number of equally spaced orbital planes, >= 1.
    phasing
        Walker phasing factor ``f``: plane ``p`` is shifted by ``360 f p / n_sat`` deg in argument of
        latitude.
    inclination_deg
        Inclination in ECI, degrees, in [0, 180].
    semi_major_axis_m
        Orbit radius, m, > 0.
    prefix
        One-letter RINEX system of the ids (``"G"`` gives ``G01``, ``G02``, ...).
    frequency_hz
        Carrier frequency of every satellite, Hz, > 0 (band ``"L1"``).
    raan0_deg
        RAAN of plane 0, degrees.

    Returns
    -------
    Constellation
        ``n_sat`` satellites, plane by plane, with empty slot names and one band ``"L1"``.

    Raises
    ------
    InvalidInputError
        ``n_sat`` not a positive multiple of ``n_planes``, ``inclination_deg`` outside [0, 180],
        ``semi_major_axis_m`` <= 0, ``frequency_hz`` <= 0, ``prefix`` not a one-letter str.
    WorkLimitError
        ``n_sat`` above ``MAX_SATELLITES`` (100,000).

    Examples
    --------
    A polar ``90: 6/3/1`` pattern: two satellites per plane 180 deg apart; satellite 2 (plane 1, first of its
    plane) has RAAN 120 deg and argument of latitude ``360 * 1 * 1 / 6 = 60`` deg, i.e. the unit position
    ``Rz(120) (cos 60, 0, sin 60) = (-0.25, 0.433013, 0.866025)``:

    >>> import numpy as np
    >>> from gnssatt.orbit.constellation import walker
    >>> pattern = walker(6, 3, 1, inclination_deg=90.0, semi_major_axis_m=7e6)
    >>> pattern.ids
    ('G01', 'G02', 'G03', 'G04', 'G05', 'G06')
    >>> r, v = pattern.state_eci(0.0)  # (6, 3) m, m/s
    >>> np.round(r[2] / 7e6, 6) + 0.0
    array([-0.25    ,  0.433013,  0.866025])
    """
    n_sat, n_planes, phasing = _walker_pattern(n_sat, n_planes, phasing, prefix)
    raan, u = _walker_angles(n_sat, n_planes, phasing, raan0_deg)
    inc = np.radians(scalar("inclination_deg", inclination_deg, minimum=0.0, maximum=180.0, unit="deg"))
    a = scalar("semi_major_axis_m", semi_major_axis_m, minimum=0.0, strict=True)
    f = scalar("frequency_hz", frequency_hz, minimum=0.0, strict=True, unit="Hz")
    orbits = KeplerOrbits.circular(np.full(n_sat, a), np.full(n_sat, inc), raan, u)
    return Constellation(
        tuple(f"{prefix}{i + 1:02d}" for i in range(n_sat)),
        orbits,
        {"L1": np.full(n_sat, f)},
        ("",) * n_sat,
        np.zeros(n_sat, dtype=np.int64),
    )
