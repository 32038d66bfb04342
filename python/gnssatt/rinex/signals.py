"""The signal of each system and frequency slot of an observation file: which RINEX observation codes
(code, phase, Doppler, signal strength) fill slot 0, 1, 2 of the engine (``rust/core/src/gnss/signal.rs``).

====  ===========  ===========  ============  ======================================  ===========
slot  GPS          GLONASS      Galileo       BeiDou                                  QZSS
====  ===========  ===========  ============  ======================================  ===========
0     L1 (band 1)  G1 (band 1)  E1 (band 1)   B1I (band 2; band 1 before RINEX 3.03)  L1 (band 1)
1     L2 (band 2)  G2 (band 2)  E5b (band 7)  B2I/B2b (band 7)                        L2 (band 2)
2     L5 (band 5)  G3 (band 3)  E5a (band 5)  B3I (band 6)                            L5 (band 5)
====  ===========  ===========  ============  ======================================  ===========

Why these exclusions: from RINEX 3.03 on, BeiDou band 1 is B1C (1575.42 MHz), another carrier than B1I;
GLONASS bands 4 and 6 (G1a/G2a) are CDMA signals on fixed carriers, not the FDMA carriers of slots 0/1.

Within a slot the attribute (tracking mode, third character of a RINEX 3 code) is chosen by the priority
of RTKLIB 2.4.3 (``codepris`` in ``rtkcmn.c``: the values only), first listed first, attributes it does not
list after those it lists, and only among codes with at least one value in the file for the system. Code
and phase of the same attribute are preferred when both exist (a pair tracked together); Doppler and
signal strength follow the phase's attribute where they can. RINEX 2 codes carry no attribute: ``C1``
counts as attribute C, ``P1`` as P, the phase ``L1`` goes with either (GPS band 1 prefers C1, band 2 P2).
In a session (:func:`~gnssatt.gnss.session_input.session_input`) the phase codes every file has come first
(``preferred_phases``), so that a double difference pairs phases of one tracking mode: receivers need not
align the phases of different modes, which can differ by a quarter cycle (RINEX 3 ``SYS / PHASE SHIFT``).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from gnssatt._arrays import instance, integer, scalar
from gnssatt.errors import InvalidInputError
from gnssatt.rinex.obs import RinexObs

__all__ = ["SLOT_BANDS", "SignalChoice", "choose_signals", "slot_bands", "slot_frequency_hz"]

#: RINEX band digits of each system's slots (RINEX 3.03 on; see :func:`slot_bands` for older BeiDou).
SLOT_BANDS: dict[str, tuple[str, str, str]] = {
    "G": ("1", "2", "5"),
    "R": ("1", "2", "3"),
    "E": ("1", "7", "5"),
    "C": ("2", "7", "6"),
    "J": ("1", "2", "5"),
}

_MHZ = 1e6
#: Carrier of each slot, Hz (module table of ``signal.rs``); GLONASS G1/G2 as (base, step per channel).
_CARRIER_HZ: dict[str, tuple[float | tuple[float, float], ...]] = {
    "G": (1575.42 * _MHZ, 1227.60 * _MHZ, 1176.45 * _MHZ),
    "J": (1575.42 * _MHZ, 1227.60 * _MHZ, 1176.45 * _MHZ),
    "E": (1575.42 * _MHZ, 1207.14 * _MHZ, 1176.45 * _MHZ),
    "C": (1561.098 * _MHZ, 1207.14 * _MHZ, 1268.52 * _MHZ),
    "R": ((1602.0 * _MHZ, 0.5625 * _MHZ), (1246.0 * _MHZ, 0.4375 * _MHZ), 1202.025 * _MHZ),
}

#: Attribute priority per system and slot, highest first (RTKLIB 2.4.3 ``codepris``; BeiDou slot 2 is
#: B3I, RTKLIB's frequency index 3).
_PRIORITY: dict[str, tuple[str, str, str]] = {
    "G": ("CPYWMNSL", "PYWCMNDLSX", "IQX"),
    "R": ("CPABX", "PCABX", "IQX"),
    "E": ("CABXZ", "IQX", "IQX"),
    "C": ("IQXDPAN", "IQXDPZ", "IQXA"),
    "J": ("CLSXZ", "LSX", "IQXDPZ"),
}
#: RINEX 2 code types: the attribute they stand for.
_RINEX2_ATTRIBUTE = {"C": "C", "P": "P"}


@dataclass(frozen=True)
class SignalChoice:
    """The observation codes of one system and slot in one file (``None`` where the file has none).

    Attributes
    ----------
    code, phase, doppler, strength
        RINEX codes as the file writes them (``"C1C"``, ``"L1C"``; RINEX 2 ``"C1"``, ``"L1"``).
    """

    code: str | None
    phase: str | None
    doppler: str | None
    strength: str | None

    @property
    def label(self) -> str:
        """``"C1C/L1C"`` (code / phase; an absent one left empty), ``""`` when the slot has neither."""
        if self.code is None and self.phase is None:
            return ""
        return f"{self.code or ''}/{self.phase or ''}"


def _system(value: object) -> str:
    """``value`` as one system letter of ``"GRECJ"``."""
    letter = instance("system", value, str, "a system letter of 'GRECJ'")
    if letter not in _CARRIER_HZ or len(letter) != 1:
        raise InvalidInputError(f"expected system as one letter of 'GRECJ', got {value!r}")
    return letter


def slot_frequency_hz(system: str, slot: int, glonass_channel: int | None = None) -> float | None:
    """Carrier frequency of ``slot`` (0..2) of ``system``, Hz; None for a GLONASS FDMA slot without a
    channel in -7..6 (as ``carrier_frequency_hz`` of the core).

    Raises
    ------
    InvalidTypeError
        ``system`` not text, ``slot`` or ``glonass_channel`` not an integer.
    InvalidInputError
        ``system`` not a letter of ``"GRECJ"``, ``slot`` outside 0..2.
    """
    system = _system(system)
    slot = integer("slot", slot, minimum=0, maximum=2)
    if glonass_channel is not None:
        glonass_channel = integer("glonass_channel", glonass_channel)
    f = _CARRIER_HZ[system][slot]
    if isinstance(f, tuple):
        if glonass_channel is None or not -7 <= glonass_channel <= 6:
            return None
        return f[0] + f[1] * glonass_channel
    return f


def slot_bands(system: str, version: float) -> tuple[tuple[str, ...], tuple[str, ...], tuple[str, ...]]:
    """RINEX band digits that may fill each slot of ``system`` in a file of ``version``.

    BeiDou B1I is band 2 from RINEX 3.03 on and band 1 before (RINEX 2 and 3.02 files label it ``C1I``).

    Raises
    ------
    InvalidTypeError
        ``system`` not text, ``version`` not a real number.
    InvalidInputError
        ``system`` not a letter of ``"GRECJ"``, ``version`` outside [2, 5).
    """
    system = _system(system)
    version = scalar("version", version, minimum=2.0, maximum=5.0)
    if version >= 5.0:
        raise InvalidInputError(f"expected a RINEX version below 5, got {version}")
    bands = SLOT_BANDS[system]
    if system == "C" and version < 3.03:
        return (("2", "1"), (bands[1],), (bands[2],))
    return ((bands[0],), (bands[1],), (bands[2],))


def _attribute(code: str, version: float) -> str:
    """Attribute of a code: the third character (RINEX 3), C or P for RINEX 2 codes, '' for others."""
    if version >= 3:
        return code[2]
    return _RINEX2_ATTRIBUTE.get(code[0], "")


def _rank(priority: str, attribute: str) -> tuple[int, str]:
    """Sort key: listed attributes by their place, unlisted ones after (alphabetically); '' (a RINEX 2
    phase, which goes with any code) first."""
    if attribute == "":
        return (-1, "")
    k = priority.find(attribute)
    return (k if k >= 0 else len(priority), attribute)


def _usable(obs: RinexObs, system: str) -> list[list[str]]:
    """Per slot, the code, phase, Doppler and strength types of ``system`` with at least one value."""
    types = obs.obs_types.get(system, ())
    rows = np.array([s[0] == system for s in obs.sats], dtype=bool)
    present = set()
    if rows.any():
        # np.any rather than the method: numpy types the method over axes as a scalar or an array
        filled: NDArray[np.bool_] = np.any(np.isfinite(obs.data[:, rows, :]), axis=(0, 1))
        present = {c for c, f in zip(obs.codes, filled, strict=True) if f}
    return [
        [c for c in types if c in present and c[1] in bands and c[0] in "CPLDS"]
        for bands in slot_bands(system, obs.version)
    ]


def phase_codes(obs: RinexObs, system: str) -> tuple[frozenset[str], ...]:
    """Per slot (3), the carrier-phase codes of ``system`` that ``obs`` has values of."""
    return tuple(frozenset(c for c in u if c[0] == "L") for u in _usable(obs, _system(system)))


def choose_signals(
    obs: RinexObs, system: str, preferred_phases: Sequence[frozenset[str]] | None = None
) -> tuple[SignalChoice, SignalChoice, SignalChoice]:
    """The codes of each slot of ``system`` in ``obs`` (module docstring for the rules).

    Parameters
    ----------
    obs
        An observation file as read by :func:`~gnssatt.rinex.obs.read_obs`.
    system
        A system letter of ``"GRECJ"``.
    preferred_phases
        Per slot, phase codes to choose among when the file has any of them (the codes every file of a
        session has: a double difference of one tracking mode needs no quarter-cycle alignment);
        default: no preference.

    Returns
    -------
    (slot 0, slot 1, slot 2) choices.

    Raises
    ------
    InvalidTypeError
        ``obs`` not a :class:`~gnssatt.rinex.obs.RinexObs`, ``system`` not text.
    InvalidInputError
        ``system`` not a letter of ``"GRECJ"``.
    """
    obs = instance("obs", obs, RinexObs, "a RinexObs (from read_obs)")
    system = _system(system)
    out = []
    for slot, (bands, usable) in enumerate(
        zip(slot_bands(system, obs.version), _usable(obs, system), strict=True)
    ):
        priority = _PRIORITY[system][slot]
        if preferred_phases is not None and _usable_preferred(usable, preferred_phases[slot]):
            usable = [c for c in usable if c[0] != "L" or c in preferred_phases[slot]]
        # within a band list, an earlier band wins (BeiDou: band 2 before band 1)
        by_kind: dict[str, list[str]] = {"code": [], "L": [], "D": [], "S": []}
        for c in usable:
            by_kind["code" if c[0] in "CP" else c[0]].append(c)
        for v in by_kind.values():
            v.sort(key=lambda c: (bands.index(c[1]), _rank(priority, _attribute(c, obs.version))))
        codes, phases = by_kind["code"], by_kind["L"]
        code = codes[0] if codes else None
        phase = phases[0] if phases else None
        if obs.version >= 3 and codes and phases:
            # the best attribute carried by both code and phase, if any
            pairs = [(c, p) for c in codes for p in phases if c[1:] == p[1:]]
            if pairs:
                code, phase = min(
                    pairs,
                    key=lambda cp: (bands.index(cp[0][1]), _rank(priority, cp[0][2])),
                )
        out.append(
            SignalChoice(
                code=code,
                phase=phase,
                doppler=_follow(by_kind["D"], phase, obs.version),
                strength=_follow(by_kind["S"], phase, obs.version),
            )
        )
    return out[0], out[1], out[2]


def _usable_preferred(usable: list[str], preferred: frozenset[str]) -> bool:
    """Whether some usable phase code is preferred."""
    return any(c in preferred for c in usable if c[0] == "L")


def _follow(candidates: list[str], phase: str | None, version: float) -> str | None:
    """The candidate of the phase's band and attribute if there is one, else the best candidate."""
    if not candidates:
        return None
    if phase is not None:
        same = [c for c in candidates if c[1:] == phase[1:]] if version >= 3 else []
        same = same or [c for c in candidates if c[1] == phase[1]]
        if same:
            return same[0]
    return candidates[0]
