"""What the observation engine takes from RINEX files: the session's observations on common epochs
(:func:`session_input`) and the navigation records as arrays (:func:`~gnssatt.rinex.nav.nav_input`, which
lives with the navigation reader so that the simulator can use it too; importable from here as before).

Both return plain numpy arrays in C order, laid out as the Rust core's ``Observations`` and ``NavData``
(``rust/core/src/gnss/observations.rs``, ``navdata.rs``); :meth:`SessionInput.observations` and
:meth:`~gnssatt.rinex.nav.NavInput.navigation` convert them once into the frozen objects the engine's
bindings take (``_core.ObservationArrays``, ``_core.Navigation``).
"""

from __future__ import annotations

import warnings
from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from gnssatt import _core
from gnssatt._arrays import instance, integer
from gnssatt.errors import GnssattWarning, InvalidInputError, InvalidTypeError, RinexError
from gnssatt.rinex.nav import GPS_EPOCH, RinexNav, leap_seconds
from gnssatt.rinex.obs import RinexObs
from gnssatt.rinex.signals import SignalChoice, choose_signals, phase_codes, slot_frequency_hz

__all__ = [
    "MATCH_TOLERANCE_NS",
    "MAX_RECEIVERS",
    "NO_CHANNEL",
    "SYSTEMS",
    "EpochsDroppedWarning",
    "MixedTrackingWarning",
    "SessionInput",
    "SystemDroppedWarning",
    "epochs_gpst_ns",
    "session_input",
]

#: The systems, in the order of the engine's ``System::ALL``.
SYSTEMS = "GRECJ"
#: Slots per system (``MAX_FREQUENCIES`` of the core).
SLOTS = 3
#: Epoch labels of two files closer than this are the same epoch, ns: RTKLIB's ``DTTOL`` (25 ms), or less
#: than half the shortest epoch spacing of the files where that is shorter (high-rate data). Receivers
#: that do not steer their clock label epochs off the whole second (the GEONET pair: up to 9 ms apart, so a
#: 1 us rule keeps 12 of its 120 epochs). Matched labels need not be equal: each file's code and phase are
#: moved onto the first file's labels by :func:`_to_common_labels`.
MATCH_TOLERANCE_NS = 25_000_000
#: Most receivers of a session (``MAX_RECEIVERS`` of the core).
MAX_RECEIVERS = 16
#: ``glonass_channel`` of a satellite that is not GLONASS or whose channel is unknown.
NO_CHANNEL = 99
_NS = 1_000_000_000
#: Speed of light, m/s.
_C = 299_792_458.0
#: Offsets of RINEX time systems to GPST at the same instant, s (GLONASS: UTC(SU) + 3 h, plus leap seconds).
_TIME_OFFSET_S = {"GPS": 0, "GAL": 0, "QZS": 0, "IRN": 0, "BDT": 14}


class SystemDroppedWarning(GnssattWarning):
    """A system asked for is missing from one of the observation files and is left out of the session."""


class EpochsDroppedWarning(GnssattWarning):
    """Epochs of an observation file that the other files lack are left out of the session."""


class MixedTrackingWarning(GnssattWarning):
    """The files carry a slot's carrier phase in different tracking modes (RINEX 3 attributes) and not every
    file declares them aligned to the band's reference signal (``SYS / PHASE SHIFT``)."""


@dataclass(frozen=True)
class SessionInput:
    """Observations of several receivers on their common epochs and satellites.

    Attributes
    ----------
    time_gpst_ns
        (n_ep,) epoch labels of the first file, GPST ns since the GPS epoch, common to all files.
    sats
        (n_sat,) satellite ids (``"G03"``) of the chosen systems seen by every file, in the order G, R, E,
        C, J, then by number.
    glonass_channel
        (n_sat,) GLONASS FDMA channel, :data:`NO_CHANNEL` (99) for other systems or where unknown.
    code_m, phase_cycles, doppler_hz, snr_dbhz
        (n_rx, n_ep, n_sat, 3) pseudorange (m), carrier phase (cycles, RINEX sign), Doppler (Hz), C/N0
        (dB-Hz as written) of each frequency slot; NaN where absent. Code and phase of every file are
        referred to ``time_gpst_ns`` (the first file's labels): a file labelled ``delta`` s later has
        ``c delta`` (m) and ``f delta`` (cycles) taken off, which keeps its true sampling instant.
    lli
        (n_rx, n_ep, n_sat, 3) loss-of-lock indicator of the phase; bit 0 also set where a dropped epoch
        (not common to all files) carried it since the previous kept epoch.
    approx_position_m
        (n_rx, 3) header APPROX POSITION XYZ, ECEF m; NaN rows where the header gives none.
    signal_codes
        Per receiver path: system letter -> the chosen codes of slots 0..2 (``"C1C/L1C"``, ``""`` where
        none), for summaries.
    epochs_dropped
        (n_rx,) epochs of each file not common to all files.
    """

    time_gpst_ns: NDArray[np.int64]
    sats: tuple[str, ...]
    glonass_channel: NDArray[np.int64]
    code_m: NDArray[np.float64]
    phase_cycles: NDArray[np.float64]
    doppler_hz: NDArray[np.float64]
    snr_dbhz: NDArray[np.float64]
    lli: NDArray[np.uint8]
    approx_position_m: NDArray[np.float64]
    signal_codes: dict[str, dict[str, tuple[str, ...]]]
    epochs_dropped: tuple[int, ...]

    def observations(self, epochs: slice = slice(None)) -> _core.ObservationArrays:
        """The observation arrays of ``epochs`` (all by default) converted into the core's observations, the
        argument of ``_core.gnss_run`` and ``GnssEngine.process``: made and checked once.

        Parameters
        ----------
        epochs
            The epochs to take, as a slice of ``time_gpst_ns`` (a block for ``GnssEngine.process``).

        Returns
        -------
        gnssatt._core.ObservationArrays
            Frozen; ``receivers``, ``epochs`` and ``sats`` describe it.

        Raises
        ------
        InvalidInputError
            The arrays are not of the shapes above, a satellite id or GLONASS channel is malformed, times
            are not strictly increasing, or there are fewer than two receivers.
        WorkLimitError
            More than the core's limit of epoch x satellite x receiver cells.
        """
        return _core.ObservationArrays(
            time_gpst_ns=self.time_gpst_ns[epochs],
            sats=list(self.sats),
            glonass_channel=self.glonass_channel,
            code_m=self.code_m[:, epochs],
            phase_cycles=self.phase_cycles[:, epochs],
            doppler_hz=self.doppler_hz[:, epochs],
            snr_dbhz=self.snr_dbhz[:, epochs],
            lli=self.lli[:, epochs],
            approx_position_m=self.approx_position_m,
        )


def _warn_mixed_tracking(
    files: Sequence[RinexObs], choices: Sequence[Mapping[str, Sequence[SignalChoice]]]
) -> None:
    """A warning per system and slot whose RINEX 3 phases differ in attribute between files, unless every
    file declares its phase aligned to the band's reference signal (``SYS / PHASE SHIFT``, RINEX 3.01 on:
    the writer has applied the shift, so phases of different attributes of one band agree)."""
    for s in choices[0]:
        for slot in range(len(choices[0][s])):
            phases = {(o.path, ch[s][slot].phase) for o, ch in zip(files, choices, strict=True)}
            if all(p is not None for _, p in phases) and len({p for _, p in phases}) > 1:
                aligned = all(_aligned(o, s, ch[s][slot].phase) for o, ch in zip(files, choices, strict=True))
                if all(o.version >= 3 for o in files) and not aligned:
                    listed = ", ".join(f"{p} in {path}" for path, p in sorted(phases))
                    warnings.warn(
                        f"system {s} slot {slot + 1}: the files have no phase of one tracking mode in common "
                        f"({listed}); receivers that do not align the phases of different modes (RINEX 3 "
                        "SYS / PHASE SHIFT) leave a quarter cycle between them, which no integer fix absorbs",
                        MixedTrackingWarning,
                        stacklevel=3,
                    )


def _aligned(obs: RinexObs, system: str, phase: str | None) -> bool:
    """Whether the header's ``SYS / PHASE SHIFT`` lists ``phase`` of ``system`` for all satellites: its
    phases are then aligned to the reference signal of the band (the correction already applied)."""
    record = obs.phase_shift_cycles.get(system, {}).get(phase or "")
    return record is not None and not record[1]


def _systems(value: object) -> str:
    if not isinstance(value, str):
        raise InvalidTypeError(
            f"expected systems as text of letters from {SYSTEMS!r}, got {type(value).__name__}"
        )
    bad = [c for c in value if c not in SYSTEMS]
    if not value or bad or len(set(value)) != len(value):
        raise InvalidInputError(
            f"expected systems as distinct letters from {SYSTEMS!r} (G GPS, R GLONASS, E Galileo, C BeiDou, "
            f"J QZSS), got {value!r}"
        )
    return "".join(c for c in SYSTEMS if c in value)


def epochs_gpst_ns(obs: RinexObs, leaps: int | None = None) -> NDArray[np.int64]:
    """The epoch labels of ``obs`` as GPST ns since the GPS epoch.

    Parameters
    ----------
    obs
        An observation file read by :func:`~gnssatt.rinex.obs.read_obs`, labelled in its ``time_system``.
    leaps
        GPS - UTC leap seconds for a file labelled in GLONASS time or UTC (None: from the date of its first
        epoch, :func:`~gnssatt.rinex.nav.leap_seconds`).

    Returns
    -------
    numpy.ndarray
        (n_epochs,) int64 GPST ns.

    Raises
    ------
    RinexError
        A time system other than GPS, GLO, GAL, BDT, QZS, IRN or UTC.
    InvalidTypeError
        ``obs`` not a :class:`~gnssatt.rinex.obs.RinexObs`, ``leaps`` not an integer.
    InvalidInputError
        ``leaps`` outside [0, 1000].

    Examples
    --------
    A file labelled in GPS time: its first epoch, 2005-04-02 00:00:00, counted from the GPS epoch
    (1980-01-06):

    >>> import numpy as np
    >>> from gnssatt.data import geonet_dir
    >>> from gnssatt.gnss.session_input import epochs_gpst_ns
    >>> from gnssatt.rinex import read_obs
    >>> t = epochs_gpst_ns(read_obs(geonet_dir() / "07590920.05o"))
    >>> int(t[0]) == (9218 * 86_400) * 10**9, len(t)
    (True, 120)
    """
    obs = instance("obs", obs, RinexObs, "an observation file read by read_obs")
    if leaps is not None:
        leaps = integer("leaps", leaps, minimum=0, maximum=1000)
    t = (obs.time - GPS_EPOCH).astype(np.int64)
    ts = obs.time_system
    if ts in _TIME_OFFSET_S:
        return np.asarray(t + _TIME_OFFSET_S[ts] * _NS, dtype=np.int64)
    if ts in ("GLO", "UTC"):
        if not len(obs.time):
            return np.asarray(t, dtype=np.int64)
        utc = obs.time[0] - np.timedelta64(3 if ts == "GLO" else 0, "h")
        n = leaps if leaps is not None else leap_seconds(utc)
        return np.asarray(t + (n - (3 * 3600 if ts == "GLO" else 0)) * _NS, dtype=np.int64)
    raise RinexError(obs.path, None, f"unknown time system {ts!r}: expected GPS, GLO, GAL, BDT, QZS or UTC")


def _tolerance(times: list[NDArray[np.int64]]) -> int:
    """The matching tolerance, ns: :data:`MATCH_TOLERANCE_NS`, or less than half the shortest epoch spacing
    of any file (then no two epochs of one file can match the same label)."""
    spacing = [int(np.min(np.diff(t))) for t in times if len(t) > 1]
    return min([MATCH_TOLERANCE_NS, *((d - 1) // 2 for d in spacing)])


def _common(times: list[NDArray[np.int64]], tol: int) -> list[NDArray[np.int64]]:
    """Per file, the index of each common epoch (epochs of the first file matched in every other file
    within ``tol`` ns)."""
    ref = times[0]
    keep = np.ones(len(ref), dtype=bool)
    matches = []
    for t in times[1:]:
        # the nearer of the neighbours around each reference label
        hi = np.clip(np.searchsorted(t, ref), 0, len(t) - 1)
        lo = np.clip(hi - 1, 0, len(t) - 1)
        j = np.where(np.abs(t[lo] - ref) <= np.abs(t[hi] - ref), lo, hi)
        keep &= np.abs(t[j] - ref) <= tol
        matches.append(j)
    return [np.flatnonzero(keep)] + [m[keep] for m in matches]


def _carried_lli(lli: NDArray[np.uint8], kept: NDArray[np.int64]) -> NDArray[np.uint8]:
    """LLI at the kept epochs with bit 0 of the dropped epochs since the previous kept one ORed in (a slip
    flagged at an epoch the session does not see still happened)."""
    out: NDArray[np.uint8] = lli[kept].copy()  # numpy types fancy indexing as Any
    lost = (lli & 1).astype(bool)
    # epoch e's slip belongs to the first kept epoch at or after it
    owner = np.searchsorted(kept, np.arange(len(lli)))
    # not np.setdiff1d: its np.unique loads numpy.ma (30-50 ms of a command-line start)
    is_dropped = np.ones(len(lli), dtype=bool)
    is_dropped[kept] = False
    dropped = np.flatnonzero(is_dropped)
    for e in dropped:
        if owner[e] < len(kept):
            out[owner[e]] |= lost[e].astype(np.uint8)
    return out


def _checked_files(observations: Sequence[RinexObs]) -> list[RinexObs]:
    """The observation files, 2 to ``MAX_RECEIVERS`` of them, each with epochs."""
    if isinstance(observations, RinexObs) or not isinstance(observations, Sequence):
        raise InvalidTypeError(
            f"expected observations as a sequence of RinexObs, got {type(observations).__name__}"
        )
    files = [
        instance(f"observations[{k}]", o, RinexObs, "a RinexObs (from read_obs)")
        for k, o in enumerate(observations)
    ]
    if not 2 <= len(files) <= MAX_RECEIVERS:
        raise InvalidInputError(
            f"expected observations of 2 to {MAX_RECEIVERS} receivers (the engine's limit), got {len(files)}"
        )
    for o in files:
        if len(o.time) == 0:
            raise RinexError(
                o.path, None, "the observation file holds no epochs (a header only): nothing to solve from it"
            )
    return files


def _signal_choices(
    files: list[RinexObs], asked: str, n_freq: int
) -> list[dict[str, tuple[SignalChoice, ...]]]:
    """Per file and system, the signals of slots 1..n_freq; every file has some carrier phase."""
    # Per system and slot, the phase codes every file has: chosen first, so that a double difference
    # pairs one tracking mode (receivers need not align the phases of different modes, which can differ
    # by a quarter cycle: RINEX 3 SYS / PHASE SHIFT).
    common = {
        s: tuple(
            frozenset.intersection(*slot) for slot in zip(*(phase_codes(o, s) for o in files), strict=True)
        )
        for s in asked
    }
    choices = [{s: choose_signals(o, s, common[s])[:n_freq] for s in asked} for o in files]
    _warn_mixed_tracking(files, choices)
    for o, ch in zip(files, choices, strict=True):
        if not any(c.phase for cs in ch.values() for c in cs):
            raise RinexError(
                o.path,
                None,
                f"expected carrier-phase observations (L codes) of systems {asked!r} in slots 1..{n_freq}, "
                f"the file has codes {list(o.codes)}",
            )
    return choices


def _systems_used(
    files: list[RinexObs], choices: list[dict[str, tuple[SignalChoice, ...]]], asked: str, systems: str
) -> str:
    """The systems of ``asked`` with carrier phase in every file; the others dropped with a warning (at the
    caller of :func:`session_input`)."""
    used = ""
    for s in asked:
        lacking = [o.path for o, ch in zip(files, choices, strict=True) if not any(c.phase for c in ch[s])]
        if not lacking:
            used += s
        elif len(lacking) < len(files) or systems != SYSTEMS:
            warnings.warn(
                f"system {s} dropped: no carrier phase of it in {', '.join(lacking)}",
                SystemDroppedWarning,
                stacklevel=3,
            )
    if not used:
        raise RinexError(
            ", ".join(o.path for o in files),
            None,
            f"expected a system of {asked!r} with carrier phase in every file, found none common",
        )
    return used


def _common_epochs(
    files: list[RinexObs], times: list[NDArray[np.int64]]
) -> tuple[list[NDArray[np.int64]], tuple[int, ...]]:
    """Per file, the indices of the epochs common to all files (labels within the tolerance), and how
    many epochs of each were left out (with a warning at the caller of :func:`session_input`)."""
    tol = _tolerance(times)
    index = _common(times, tol)
    if len(index[0]) == 0:
        spans = "; ".join(f"{o.path}: {o.time[0]} to {o.time[-1]} ({o.time_system})" for o in files)
        raise RinexError(
            ", ".join(o.path for o in files),
            None,
            f"no epoch common to all files (labels within {tol} ns): {spans}",
        )
    dropped = tuple(len(o.time) - len(k) for o, k in zip(files, index, strict=True))
    if any(dropped):
        warnings.warn(
            "epochs not common to all files left out: "
            + ", ".join(f"{o.path}: {d} of {len(o.time)}" for o, d in zip(files, dropped, strict=True) if d),
            EpochsDroppedWarning,
            stacklevel=3,
        )
    return index, dropped


def _observation_arrays(
    files: list[RinexObs],
    choices: list[dict[str, tuple[SignalChoice, ...]]],
    index: list[NDArray[np.int64]],
    sats: tuple[str, ...],
) -> tuple[
    NDArray[np.float64], NDArray[np.float64], NDArray[np.float64], NDArray[np.float64], NDArray[np.uint8]
]:
    """Code, phase, Doppler, SNR (n_rx, n_ep, n_sat, SLOTS; NaN where absent) and LLI of the chosen
    signals at the common epochs."""
    n_rx, n_ep, n_sat = len(files), len(index[0]), len(sats)
    shape = (n_rx, n_ep, n_sat, SLOTS)
    code = np.full(shape, np.nan)
    phase = np.full(shape, np.nan)
    doppler = np.full(shape, np.nan)
    snr = np.full(shape, np.nan)
    lli = np.zeros(shape, dtype=np.uint8)
    for r, (o, ch, kept) in enumerate(zip(files, choices, index, strict=True)):
        cols = o.sat_index(sats)
        for k, s in enumerate(sats):
            for slot, c in enumerate(ch[s[0]]):
                _fill(o, c, kept, cols[k], (r, slice(None), k, slot), code, phase, doppler, snr, lli)
    return code, phase, doppler, snr, lli


def session_input(
    observations: Sequence[RinexObs],
    *,
    systems: str = SYSTEMS,
    frequencies: int = 3,
    nav: RinexNav | None = None,
) -> SessionInput:
    """The engine's observations of several receivers: common epochs, common satellites, one signal per
    system and frequency slot (:mod:`gnssatt.rinex.signals`).

    Parameters
    ----------
    observations
        Two or more files from :func:`~gnssatt.rinex.obs.read_obs`, the reference antenna ("base") first.
    systems
        Letters of the systems to use, from ``"GRECJ"``. A system named but missing (no phase of it) from
        a file is dropped with a :class:`SystemDroppedWarning` naming the file; with the default (every
        system), systems that no file has are dropped silently.
    frequencies
        Slots to fill, 1 to 3 (1: L1/G1/E1/B1I; 2: also L2/G2/E5b/B2I; 3: also L5/G3/E5a/B3I).
    nav
        Navigation records, for GLONASS channels the observation headers do not give
        (``GLONASS SLOT / FRQ #``), and for leap seconds where a file is labelled in GLONASS time.

    Returns
    -------
    SessionInput

    Warns
    -----
    SystemDroppedWarning
        A system named is missing from a file (above).
    EpochsDroppedWarning
        Epochs of a file that another file lacks are left out (counted in ``epochs_dropped``).

    Raises
    ------
    InvalidTypeError
        ``observations`` not a sequence of ``RinexObs``, ``systems`` not text, ``frequencies`` not an
        integer, ``nav`` not a ``RinexNav``.
    InvalidInputError
        Fewer than two or more than :data:`MAX_RECEIVERS` files; ``systems`` not distinct letters of
        ``"GRECJ"``; ``frequencies`` outside 1..3.
    RinexError
        A file of no epochs (a header only), a file without carrier-phase observations of the chosen
        systems and slots, no system left that every file has, no epoch common to all files, no satellite
        seen by every file (each message names the files).

    Examples
    --------
    The GEONET pair shipped with gnssatt (stations 0759 and 3040, GPS L1, 120 epochs) on common epochs:

    >>> from gnssatt.data import geonet_dir
    >>> from gnssatt.gnss.session_input import session_input
    >>> from gnssatt.rinex import read_obs
    >>> files = [read_obs(geonet_dir() / name) for name in ("07590920.05o", "30400920.05o")]
    >>> si = session_input(files, systems="G", frequencies=1)
    >>> si.code_m.shape, si.sats[:3], si.epochs_dropped
    ((2, 120, 11, 3), ('G01', 'G03', 'G04'), (0, 0))
    """
    files, asked, n_freq, nav = _checked_arguments(observations, systems, frequencies, nav)
    # called from here: their warnings name the caller of session_input (stacklevel=3)
    choices = _signal_choices(files, asked, n_freq)
    used = _systems_used(files, choices, asked, systems)
    leaps = _leap_seconds(files, nav)
    times = [epochs_gpst_ns(o, leaps) for o in files]
    index, dropped = _common_epochs(files, times)
    sats = _common_sats(files, choices, index, used)
    return _assembled(files, choices, used, n_freq, times, index, dropped, sats, nav)


def _checked_arguments(
    observations: Sequence[RinexObs], systems: str, frequencies: int, nav: RinexNav | None
) -> tuple[list[RinexObs], str, int, RinexNav | None]:
    """The files, the systems asked for, the number of frequency slots and the navigation data of
    :func:`session_input`, checked."""
    files = _checked_files(observations)
    asked = _systems(systems)
    n_freq = integer("frequencies", frequencies, minimum=1, maximum=SLOTS)
    if nav is not None:
        nav = instance("nav", nav, RinexNav, "a RinexNav (from read_nav)")
    return files, asked, n_freq, nav


def _leap_seconds(files: list[RinexObs], nav: RinexNav | None) -> int | None:
    """GPS - UTC, s: the first observation header that gives it, else the navigation file's."""
    leaps = next((o.leap_seconds for o in files if o.leap_seconds is not None), None)
    if leaps is None and nav is not None:
        leaps = nav.leap_seconds
    return leaps


def _assembled(
    files: list[RinexObs], choices: list[dict[str, tuple[SignalChoice, ...]]], used: str, n_freq: int,
    times: list[NDArray[np.int64]], index: list[NDArray[np.int64]], dropped: tuple[int, ...],
    sats: tuple[str, ...], nav: RinexNav | None,
) -> SessionInput:  # fmt: skip
    """The :class:`SessionInput` of the chosen signals of ``sats`` at the common epochs ``index`` (labels
    of the first file, phases moved to them)."""
    code, phase, doppler, snr, lli = _observation_arrays(files, choices, index, sats)
    channels = _channels(sats, files, nav)
    _to_common_labels([t[k] for t, k in zip(times, index, strict=True)], sats, channels, code, phase)
    pos = np.array([o.approx_position_m for o in files], dtype=np.float64)
    pos[~np.any(pos != 0.0, axis=1)] = np.nan
    return SessionInput(
        time_gpst_ns=np.ascontiguousarray(times[0][index[0]]),
        sats=sats,
        glonass_channel=channels,
        code_m=code,
        phase_cycles=phase,
        doppler_hz=doppler,
        snr_dbhz=snr,
        lli=lli,
        approx_position_m=pos,
        signal_codes={
            o.path: {s: tuple(c.label for c in ch[s]) + ("",) * (SLOTS - n_freq) for s in used}
            for o, ch in zip(files, choices, strict=True)
        },
        epochs_dropped=dropped,
    )


def _to_common_labels(
    labels: list[NDArray[np.int64]],
    sats: tuple[str, ...],
    channels: NDArray[np.int64],
    code: NDArray[np.float64],
    phase: NDArray[np.float64],
) -> None:
    """Move every receiver's code (m) and phase (cycles) in place from its own epoch labels onto the first
    file's, exactly.

    A receiver's code and phase are ``c (label - t_transmit)`` and ``f (label - t_transmit)`` plus terms
    that do not depend on the label, where ``label`` is its clock's reading at the true reception instant.
    The same instant read as ``label - delta`` (``delta`` = own label minus the first file's, s) gives
    ``code - c delta`` and ``phase - f delta``: the engine then finds that receiver's clock offset smaller
    by ``delta`` and the true reception instant unchanged. Left alone, the clock estimated from the code
    absorbs ``c delta`` but the satellite geometry is computed ``delta`` away from the instant sampled, an
    error of the range rate times ``delta`` that differs per satellite (GEONET 0759/3040: labels up to
    9 ms apart, double-difference phase drifting by 35 L1 cycles over the hour). A phase whose carrier
    frequency is unknown (GLONASS without a channel) cannot be moved and becomes NaN where ``delta != 0``.
    """
    freq = np.array(
        [
            [
                np.nan if (f := slot_frequency_hz(s[0], slot, _channel(int(ch)))) is None else f
                for slot in range(SLOTS)
            ]
            for s, ch in zip(sats, channels, strict=True)
        ]
    )  # (n_sat, SLOTS), Hz
    for r in range(1, len(labels)):
        delta_s = (labels[r] - labels[0]).astype(np.float64) * 1e-9  # exact: |difference| < 1 s in ns
        moved = delta_s != 0.0
        code[r, moved] -= _C * delta_s[moved, None, None]
        phase[r, moved] -= freq[None] * delta_s[moved, None, None]


def _channel(value: int) -> int | None:
    """A GLONASS channel, or None for :data:`NO_CHANNEL`."""
    return None if value == NO_CHANNEL else value


def _fill(
    o: RinexObs,
    c: SignalChoice,
    kept: NDArray[np.int64],
    col: int,
    at: tuple[int, slice, int, int],
    code: NDArray[np.float64],
    phase: NDArray[np.float64],
    doppler: NDArray[np.float64],
    snr: NDArray[np.float64],
    lli: NDArray[np.uint8],
) -> None:
    """Copy one satellite's signal of one slot of one file into the session arrays."""
    for name, out in ((c.code, code), (c.phase, phase), (c.doppler, doppler), (c.strength, snr)):
        if name is not None:
            out[at] = o.data[kept, col, o.codes.index(name)]
    if c.phase is not None:
        lli[at] = _carried_lli(o.lli[:, col, o.codes.index(c.phase)], kept)


def _common_sats(
    files: list[RinexObs],
    choices: list[dict[str, tuple[SignalChoice, ...]]],
    index: list[NDArray[np.int64]],
    used: str,
) -> tuple[str, ...]:
    """Satellites of the systems ``used`` with a phase of some slot in every file at a common epoch
    (refused when there is none)."""
    common: set[str] | None = None
    for o, ch, kept in zip(files, choices, index, strict=True):
        seen = set()
        for k, s in enumerate(o.sats):
            if s[0] not in used:
                continue
            cols = [o.codes.index(c.phase) for c in ch[s[0]] if c.phase is not None]
            if cols and np.isfinite(o.data[np.ix_(kept, np.array([k]), np.array(cols))]).any():
                seen.add(s)
        common = seen if common is None else common & seen
    if not common:
        raise RinexError(
            ", ".join(o.path for o in files),
            None,
            f"no satellite of systems {used!r} with carrier phase in every file at the common epochs",
        )
    return tuple(sorted(common, key=lambda s: (SYSTEMS.index(s[0]), int(s[1:]))))


def _channels(sats: tuple[str, ...], files: list[RinexObs], nav: RinexNav | None) -> NDArray[np.int64]:
    """GLONASS channel of each satellite: the observation headers first, then the navigation records."""
    known: dict[str, int] = {}
    if nav is not None:
        g = nav.glonass
        for s, k in zip(g.sats.tolist(), g.channel.tolist(), strict=True):
            known.setdefault(s, int(k))
    for o in reversed(files):  # the first file's header wins
        known.update(o.glonass_channels)
    out = np.full(len(sats), NO_CHANNEL, dtype=np.int64)
    for k, s in enumerate(sats):
        if s[0] == "R" and s in known and -7 <= known[s] <= 6:
            out[k] = known[s]
    return out
