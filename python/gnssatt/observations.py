"""Measurement types the estimators take and the simulator makes, on the base layer so that neither imports
the other (``docs/architecture.md``): carrier-phase first differences and attitude fixes (inputs of
:func:`gnssatt.gyro_gnss_filter`, :func:`gnssatt.phase_attitude_fixes`), and spaceborne pseudorange and
Doppler measurements (inputs of :mod:`gnssatt.orbit.determination`). Each checks its fields on construction.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray
from scipy.spatial.transform import Rotation

from gnssatt._arrays import float_array, instance, real_array, scalar, text, vector_array
from gnssatt._arrays import rows as _rows
from gnssatt.errors import InvalidInputError

__all__ = ["SYSTEM_INDEX", "AttitudeFixes", "PhaseObservations", "SpaceborneMeasurements"]


#: System index of each satellite id prefix (the filters difference within a system only).
SYSTEM_INDEX = {"G": 0, "R": 1}


@dataclass(frozen=True)
class PhaseObservations:
    """Carrier-phase first differences, one row per (epoch, tracked satellite).

    Attributes
    ----------
    epoch_t
        (n_e,) epoch times, s.
    epoch
        (n_rows,) index into ``epoch_t``, non-decreasing.
    track
        (n_rows,) arc id: a new id means new ambiguities (satellite rose, or lock was lost).
    los
        (n_rows, 3) unit lines of sight receiver -> satellite, ECI.
    wavelength
        (n_rows,) m.
    phase
        (n_rows, m) first differences slave ``i`` minus master, cycles.
    ambiguity
        (n_rows, m) true integers ``N_ik`` of each row (for checking fixes).
    satellite
        (n_rows,) index of the satellite in the constellation.
    """

    epoch_t: NDArray[np.float64]
    epoch: NDArray[np.int64]
    track: NDArray[np.int64]
    los: NDArray[np.float64]
    wavelength: NDArray[np.float64]
    phase: NDArray[np.float64]
    ambiguity: NDArray[np.int64]
    satellite: NDArray[np.int64]

    def __post_init__(self) -> None:
        # Also the intake of the phase-based solvers (gnssatt.phase_attitude_fixes, attitude_fixes).
        n_e = _rows("epoch_t", self.epoch_t, ())
        n = _rows("epoch", self.epoch, (), integers=True)
        if n and (np.min(self.epoch) < 0 or np.max(self.epoch) >= n_e):
            raise InvalidInputError(
                f"expected epoch as indices into epoch_t, in [0, {n_e}), got {self.epoch}"[:300]
            )
        _rows("track", self.track, (n,), integers=True)
        _rows("satellite", self.satellite, (n,), integers=True)
        _rows("los", self.los, (n, 3))
        _rows("wavelength", self.wavelength, (n,))
        if n and np.min(self.wavelength) <= 0:
            raise InvalidInputError(f"expected wavelength > 0, got minimum {np.min(self.wavelength)}")
        phase = float_array("phase", self.phase, ndim=2, shape="(n_rows, m)")
        _rows("phase", phase, (n, phase.shape[1]))
        _rows("ambiguity", self.ambiguity, phase.shape, integers=True)

    def without_ambiguities(self) -> PhaseObservations:
        """The same rows with the true integers removed (for a filter told ``known_ambiguities``)."""
        return PhaseObservations(
            self.epoch_t,
            self.epoch,
            self.track,
            self.los,
            self.wavelength,
            self.phase - self.ambiguity,
            np.zeros_like(self.ambiguity),
            self.satellite,
        )

    def n_visible(self) -> NDArray[np.int64]:
        """(n_e,) satellites per epoch."""
        return np.bincount(self.epoch, minlength=len(self.epoch_t))


@dataclass(frozen=True)
class AttitudeFixes:
    """Attitude solutions of the receiver: ``rotation`` body -> ECI at ``t`` with the covariance (n, 3, 3) of
    its body-frame rotation-vector error, rad^2."""

    t: NDArray[np.float64]
    rotation: Rotation
    covariance: NDArray[np.float64]

    def __post_init__(self) -> None:
        # Also an input of gnssatt.gyro_gnss_filter.
        n = _rows("t", self.t, ())
        instance("rotation", self.rotation, Rotation, "a scipy Rotation")
        if self.rotation.single or len(self.rotation) != n:
            got = "a single rotation" if self.rotation.single else f"{len(self.rotation)} rotations"
            raise InvalidInputError(f"expected rotation as {n} rotations (one per t), got {got}")
        _rows("covariance", self.covariance, (n, 3, 3))


@dataclass(frozen=True)
class SpaceborneMeasurements:
    """Measurements of a spaceborne receiver and the truth behind them.

    Attributes
    ----------
    times_s
        (n_t,) epochs, s.
    ids
        (n_sat,) satellite ids (``G..`` GPS, ``R..`` GLONASS).
    system
        (n_sat,) uint32 system index (0 GPS, 1 GLONASS).
    wavelength_m
        (n_sat,) L1 carrier wavelengths, m.
    sat_position_m, sat_velocity_m_s
        (n_t, n_sat, 3) satellite states, ECEF.
    pseudorange_m, doppler_hz
        (n_t, n_sat) measurements (NaN where not visible).
    visible
        (n_t, n_sat) tracked.
    code_sigma_m, doppler_sigma_hz
        Noise standard deviations used.
    clock_bias_s, clock_drift
        (n_t,) truth: receiver clock bias (s) and drift (s/s).
    isb_m
        Truth: GLONASS minus GPS inter-system bias, m.
    """

    times_s: NDArray[np.float64]
    ids: tuple[str, ...]
    system: NDArray[np.uint32]
    wavelength_m: NDArray[np.float64]
    sat_position_m: NDArray[np.float64]
    sat_velocity_m_s: NDArray[np.float64]
    pseudorange_m: NDArray[np.float64]
    doppler_hz: NDArray[np.float64]
    visible: NDArray[np.bool_]
    code_sigma_m: float
    doppler_sigma_hz: float
    clock_bias_s: NDArray[np.float64]
    clock_drift: NDArray[np.float64]
    isb_m: float

    def __post_init__(self) -> None:
        # Also the intake of real receivers' data in this layout (gnssatt.orbit.determination): every field
        # is checked for shape and type, the truth and the satellite states for finiteness, the measurements
        # where tracked (NaN elsewhere).
        t = float_array("times_s", self.times_s, ndim=1, shape="(n_t,)")
        if t.size == 0 or np.any(np.diff(t) <= 0):
            raise InvalidInputError("expected at least one epoch and strictly increasing times_s")
        ids = instance("ids", self.ids, tuple, "a tuple of str")
        if not all(isinstance(i, str) and i[:1] in SYSTEM_INDEX for i in ids):
            raise InvalidInputError(
                f"expected ids as str starting with one of {list(SYSTEM_INDEX)}, got {ids!r}"[:300]
            )
        n_t, n_sat = t.size, len(ids)
        system = np.asarray(self.system)
        if system.dtype.kind not in "iu" or system.shape != (n_sat,):
            raise InvalidInputError(
                f"expected system as ({n_sat},) integers, got {system.dtype} {system.shape}"
            )
        if np.any((system < 0) | (system >= len(SYSTEM_INDEX))):
            raise InvalidInputError(
                f"expected system indices in [0, {len(SYSTEM_INDEX)}), got {np.unique(system).tolist()}"
            )
        lam = float_array("wavelength_m", self.wavelength_m, ndim=1, shape=f"({n_sat},)")
        if lam.shape != (n_sat,) or np.any(lam <= 0):
            raise InvalidInputError(f"expected wavelength_m of shape ({n_sat},), each > 0")
        visible = np.asarray(self.visible)
        if visible.dtype != bool or visible.shape != (n_t, n_sat):
            raise InvalidInputError(
                f"expected visible as booleans of shape ({n_t}, {n_sat}), got {visible.dtype} {visible.shape}"
            )
        for name in ("sat_position_m", "sat_velocity_m_s"):
            arr = vector_array(name, getattr(self, name), ndim=3, shape=f"({n_t}, {n_sat}, 3)")
            if arr.shape != (n_t, n_sat, 3):
                raise InvalidInputError(f"expected {name} of shape ({n_t}, {n_sat}, 3), got {arr.shape}")
        for name in ("pseudorange_m", "doppler_hz"):
            arr = real_array(name, getattr(self, name))
            if arr.shape != (n_t, n_sat):
                raise InvalidInputError(f"expected {name} of shape ({n_t}, {n_sat}), got {arr.shape}")
            if not np.all(np.isfinite(arr[visible])):
                raise InvalidInputError(f"{name} contains a non-finite value where visible")
        for name in ("clock_bias_s", "clock_drift"):
            arr = float_array(name, getattr(self, name), ndim=1, shape=f"({n_t},)")
            if arr.shape != (n_t,):
                raise InvalidInputError(f"expected {name} of shape ({n_t},), got {arr.shape}")
        scalar("code_sigma_m", self.code_sigma_m, minimum=0.0, strict=True)
        scalar("doppler_sigma_hz", self.doppler_sigma_hz, minimum=0.0, strict=True)
        scalar("isb_m", self.isb_m)

    def select_systems(self, prefixes: str) -> SpaceborneMeasurements:
        """Only the satellites whose id starts with one of ``prefixes`` (e.g. ``"G"`` or ``"GR"``)."""
        text("prefixes", prefixes)
        keep = np.array([i[0] in prefixes for i in self.ids], dtype=bool)
        if not keep.any():
            raise InvalidInputError(
                f"expected prefixes naming systems among {sorted({i[0] for i in self.ids})}, got {prefixes!r}"
            )
        return SpaceborneMeasurements(
            self.times_s,
            tuple(i for i, k in zip(self.ids, keep, strict=True) if k),
            self.system[keep],
            self.wavelength_m[keep],
            self.sat_position_m[:, keep],
            self.sat_velocity_m_s[:, keep],
            self.pseudorange_m[:, keep],
            self.doppler_hz[:, keep],
            self.visible[:, keep],
            self.code_sigma_m,
            self.doppler_sigma_hz,
            self.clock_bias_s,
            self.clock_drift,
            self.isb_m,
        )
