"""Measurements of an antenna array at a given attitude: code, carrier phase, Doppler, correlator outputs.

Conventions of :mod:`gnssatt.sim`
---------------------------------
- SI units and radians inside; phases also in cycles where the name says ``_cycles``.
- Attitude ``R`` is a scipy ``Rotation`` body -> reference frame (the frame of the lines of sight).
- ``antennas_body_m`` (n_ant, 3): antenna phase centres in the body frame relative to the vehicle's
  reference point, whose position is the receiver position of the geometry. With
  :func:`~gnssatt.sim.arrays.equilateral_triangle` antenna 0 sits at that point.
- Far field: the range from antenna i to satellite k is ``rho_ik = rho_k - gamma_k . (R r_i)``.
- Carrier phase (RINEX sign, grows with range), cycles:
  ``phi_ik = rho_ik / lambda_k + N_ik + osc_i / (2 pi) + alpha_k / (2 pi) + e_ik``, with integer
  ambiguities ``N_ik``, per-receiver oscillator phases ``osc_i`` (rad), per-satellite signal phases
  ``alpha_k`` (rad) and white noise ``e_ik``. The receiver clock enters the phases only through ``osc_i``.
- Pseudorange ``P_ik = rho_ik + c dt_i + eps_ik`` (m), ``dt_i`` the clock bias of antenna i's receiver.
- Doppler (RINEX sign, positive while approaching), Hz: ``D_ik = -(d rho_k / dt) / lambda_k + noise``; the
  reference point's range rate is used for every antenna (the attitude-rate term ``d(gamma . R r_i)/dt``,
  below 1 cm/s for metre baselines, is left out).
- Complex correlator output (prompt, one coherent integration of ``T`` seconds):
  ``u_ik = A_k exp(j 2 pi phi_ik^0) + n_ik`` with ``phi^0`` the noise-free phase above,
  ``n = n_I + j n_Q``, ``n_I, n_Q ~ N(0, 1)`` independent, and ``A_k = sqrt(2 (C/N0)_k T)`` with ``C/N0``
  converted from dB-Hz. Hence the post-correlation SNR ``A^2 / (2 sigma^2) = (C/N0) T`` and, at high SNR,
  the phase of ``u`` has standard deviation ``sigma = 1 / A = 1 / sqrt(2 (C/N0) T)`` rad.
- Randomness comes only from the ``rng`` argument, drawn in this order: ambiguities (if not given),
  oscillator phases (if not given), satellite phases (if not given), code noise, phase noise, Doppler
  noise, correlator noise (if ``cn0_dbhz`` is given).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.spatial.transform import Rotation

from gnssatt._arrays import (
    MAX_BATCH_VALUES,
    batch_limit,
    checked_array,
    finite_result,
    float_array,
    generator,
    instance,
    integer,
    plain_array,
    readonly,
    scalar,
    text,
)
from gnssatt.constants import SPEED_OF_LIGHT_M_S
from gnssatt.errors import InvalidInputError, InvalidTypeError, WorkLimitError
from gnssatt.orbit.line_of_sight import Geometry, attitude_matrices
from gnssatt.rotation import wrap_rad

__all__ = [
    "MAX_SIMULATED_VALUES",
    "ArrayMeasurements",
    "correlator_amplitude",
    "phase_diffs",
    "simulate_array",
    "wrap_rad",
]

#: Range of C/N0 accepted, dB-Hz: far beyond any receiver (20-60 dB-Hz), inside what ``10^(C/10)`` holds.
CN0_RANGE_DBHZ = (-100.0, 200.0)
#: Largest ``ambiguity_max`` of :func:`simulate_array`: integers of 2^31 cycles are 400,000 km of L1.
MAX_AMBIGUITY = 2**31
#: Most (epoch, antenna, satellite) measurements one :func:`simulate_array` call makes: 2^22, about 420 MB
#: (99 bytes each, measured with tracemalloc) and, measured on the loaded 2-core build machine, 1-2 us each.
MAX_SIMULATED_VALUES = 2**22


@dataclass(frozen=True)
class ArrayMeasurements:
    """Measurements of an antenna array and the truth behind them.

    Shapes: ``(n_ant, n_sat)`` for one epoch, ``(n_t, n_ant, n_sat)`` for several.

    Attributes
    ----------
    pseudorange_m
        Code pseudoranges, m.
    carrier_phase_cycles
        Carrier phases with ambiguities, oscillator and satellite phases and noise, not wrapped, cycles.
    doppler_hz
        Doppler shifts, Hz (positive while the satellite approaches).
    correlator
        Complex correlator outputs (module docstring), or None when no ``cn0_dbhz`` was given.
    range_m
        Truth: noise-free far-field range from each antenna, ``rho_k - gamma_k . (R r_i)``, m.
    los
        Truth: (n_sat, 3) or (n_t, n_sat, 3) unit lines of sight in the reference frame.
    wavelengths_m
        (n_sat,) carrier wavelengths, m.
    ambiguities
        (n_ant, n_sat) integer ambiguities ``N_ik``, cycles (int64).
    oscillator_phases_rad
        (n_ant,) receiver oscillator phases ``osc_i``, rad.
    satellite_phases_rad
        (n_sat,) satellite signal phases ``alpha_k``, rad.
    clock_bias_s
        (n_ant,) receiver clock biases, s.
    antennas_body_m
        (n_ant, 3) antenna positions, body frame, m.
    attitude
        The body -> reference rotation used (one, or one per epoch).
    ids
        Satellite ids.
    """

    pseudorange_m: NDArray[np.float64]
    carrier_phase_cycles: NDArray[np.float64]
    doppler_hz: NDArray[np.float64]
    correlator: NDArray[np.complex128] | None
    range_m: NDArray[np.float64]
    los: NDArray[np.float64]
    wavelengths_m: NDArray[np.float64]
    ambiguities: NDArray[np.int64]
    oscillator_phases_rad: NDArray[np.float64]
    satellite_phases_rad: NDArray[np.float64]
    clock_bias_s: NDArray[np.float64]
    antennas_body_m: NDArray[np.float64]
    attitude: Rotation
    ids: tuple[str, ...]

    def carrier_phase_rad(self, *, wrapped: bool = True) -> NDArray[np.float64]:
        """Carrier phases in radians, wrapped to [-pi, pi) (as a receiver without cycle count gives them)
        or not."""
        if not isinstance(wrapped, bool | np.bool_):
            raise InvalidTypeError(f"expected wrapped as a bool, got {type(wrapped).__name__}")
        phase = 2.0 * np.pi * self.carrier_phase_cycles
        return wrap_rad(phase) if wrapped else phase

    def phase_diffs(self, *, source: str = "phase") -> NDArray[np.float64]:
        """First differences antenna i - antenna 0, wrapped, rad, shape (..., n_ant - 1, n_sat).

        ``source="phase"`` uses :attr:`carrier_phase_cycles`; ``source="correlator"`` the phases of the
        correlator outputs.
        """
        text("source", source)
        if source == "phase":
            return phase_diffs(self.carrier_phase_rad(wrapped=True))
        if source == "correlator":
            if self.correlator is None:
                raise InvalidInputError(
                    "expected measurements simulated with cn0_dbhz, got no correlator outputs"
                )
            return phase_diffs(self.correlator)
        raise InvalidInputError(f"expected source 'phase' or 'correlator', got {source!r}")


def phase_diffs(phases: ArrayLike) -> NDArray[np.float64]:
    """Phase differences between antennas i = 1..n_ant-1 and antenna 0, wrapped to [-pi, pi).

    This is the input the Bunyaeva et al. maximum-likelihood estimator takes (``ddtheta``, eq. (8)-(9)).

    Parameters
    ----------
    phases
        (..., n_ant, M) phases in radians (wrapped or not), or complex correlator outputs, whose
        differences are ``angle(u_i conj(u_0))``. n_ant >= 2.

    Returns
    -------
    (..., n_ant - 1, M) radians.

    Raises
    ------
    InvalidInputError
        Wrong shapes (fewer than 2 antennas), non-finite values (:class:`~gnssatt.errors.InvalidTypeError` for
        values that are not numbers, ragged sequences).
    WorkLimitError
        More than :data:`gnssatt._arrays.MAX_BATCH_VALUES` phases, refused before they are copied.

    Examples
    --------
    Antenna 1 minus antenna 0 for two signals; ``3.0 - (-3.0) = 6`` rad wraps to ``6 - 2 pi``. Correlator
    outputs ``exp(j phase)`` give the same differences:

    >>> import numpy as np
    >>> from gnssatt.sim.measurements import phase_diffs
    >>> phases = np.array([[0.1, -3.0], [0.4, 3.0]])  # (n_ant = 2, M = 2) rad
    >>> np.round(phase_diffs(phases), 6), round(6.0 - 2.0 * np.pi, 6)
    (array([[ 0.3     , -0.283185]]), -0.283185)
    >>> np.round(phase_diffs(np.exp(1j * phases)), 6)
    array([[ 0.3     , -0.283185]])
    """
    batch_limit(MAX_BATCH_VALUES, "MAX_BATCH_VALUES", "phases", phases=(phases, 0))
    arr = plain_array("phases", phases)
    if arr.dtype.kind == "c":
        if arr.ndim < 2 or arr.shape[-2] < 2 or not np.all(np.isfinite(arr)):
            raise InvalidInputError(f"expected finite phases of shape (..., n_ant >= 2, M), got {arr.shape}")
        return wrap_rad(np.angle(arr[..., 1:, :] * np.conj(arr[..., :1, :])))
    p = float_array("phases", phases, ndim=(2, 3), shape="(..., n_ant, M)")
    if p.shape[-2] < 2:
        raise InvalidInputError(f"expected phases of shape (..., n_ant >= 2, M), got {p.shape}")
    return wrap_rad(p[..., 1:, :] - p[..., :1, :])


def correlator_amplitude(cn0_dbhz: ArrayLike, integration_time_s: float) -> NDArray[np.float64]:
    """Signal amplitude ``A = sqrt(2 (C/N0) T)`` of the correlator model (unit noise variance per I and Q).

    Parameters
    ----------
    cn0_dbhz
        Carrier-to-noise density ratio, dB-Hz, () or (n_sat,), each in ``CN0_RANGE_DBHZ`` ([-100, 200]).
    integration_time_s
        Coherent integration time ``T``, s, in (0, 1e6].

    Returns
    -------
    numpy.ndarray
        ``A``, the shape of ``cn0_dbhz``, in units of the noise standard deviation per I and Q.

    Raises
    ------
    InvalidInputError
        Non-finite values, ``cn0_dbhz`` outside ``CN0_RANGE_DBHZ``, ``integration_time_s`` outside (0, 1e6]
        (:class:`~gnssatt.errors.InvalidTypeError` for values that are not real numbers).
    WorkLimitError
        More than :data:`gnssatt._arrays.MAX_BATCH_VALUES` values of ``cn0_dbhz``, refused before they are
        copied.

    Examples
    --------
    50 dB-Hz over 1 ms: ``A = sqrt(2 * 1e5 * 1e-3) = sqrt(200)``, a phase noise of ``1 / A = 0.0707`` rad;
    10 dB less divides ``A`` by ``sqrt(10)``:

    >>> import numpy as np
    >>> from gnssatt.sim.measurements import correlator_amplitude
    >>> np.round(correlator_amplitude([50.0, 40.0], 1e-3), 6), round(float(np.sqrt(200.0)), 6)
    (array([14.142136,  4.472136]), 14.142136)
    """
    batch_limit(MAX_BATCH_VALUES, "MAX_BATCH_VALUES", "values", cn0_dbhz=(cn0_dbhz, 0))
    c = checked_array("cn0_dbhz", cn0_dbhz, ndim=(0, 1), shape="() or (n_sat,)")
    lo, hi = CN0_RANGE_DBHZ
    if c.size and (c.min() < lo or c.max() > hi):
        raise InvalidInputError(f"expected cn0_dbhz in [{lo}, {hi}] dB-Hz, got [{c.min()}, {c.max()}]")
    t = scalar("integration_time_s", integration_time_s, minimum=0.0, strict=True)
    scalar("integration_time_s", t, maximum=1e6, unit="s")
    return np.sqrt(2.0 * 10.0 ** (c / 10.0) * t)


def _vector(name: str, value: Any, n: int, what: str) -> NDArray[np.float64]:
    arr = checked_array(name, value, ndim=(0, 1), shape=f"() or ({what},)")
    if arr.ndim == 1 and arr.shape != (n,):
        raise InvalidInputError(f"expected {name} of shape () or ({n},) ({what}), got {arr.shape}")
    full: NDArray[np.float64] = np.broadcast_to(arr, (n,)).copy()  # numpy types broadcast_to as Any
    return full


def _wavelengths(wavelengths_m: ArrayLike, n_sat: int) -> NDArray[np.float64]:
    lam: NDArray[np.float64] = float_array("wavelengths_m", wavelengths_m, ndim=1, shape="(n_sat,)").copy()
    if lam.shape != (n_sat,):
        raise InvalidInputError(f"expected wavelengths_m of shape ({n_sat},) (n_sat), got {lam.shape}")
    if np.any(lam <= 0):
        raise InvalidInputError(f"expected wavelengths_m > 0, got minimum {lam.min()}")
    return lam


def _ambiguities(
    rng: np.random.Generator, ambiguities: ArrayLike | None, ambiguity_max: int, n_ant: int, n_sat: int
) -> NDArray[np.int64]:
    """(n_ant, n_sat) integer ambiguities: as given, or drawn uniform in +-``ambiguity_max``."""
    if ambiguities is None:
        amax = integer("ambiguity_max", ambiguity_max, minimum=0, maximum=MAX_AMBIGUITY)
        return rng.integers(-amax, amax + 1, size=(n_ant, n_sat), dtype=np.int64)
    amb_in = np.asarray(ambiguities)
    if amb_in.dtype.kind not in "iu":
        raise InvalidTypeError(f"expected integer ambiguities, got dtype {amb_in.dtype}")
    if amb_in.shape != (n_ant, n_sat):
        raise InvalidInputError(f"expected ambiguities of shape ({n_ant}, {n_sat}), got {amb_in.shape}")
    if amb_in.size and np.max(np.abs(amb_in.astype(np.float64))) > MAX_AMBIGUITY:
        raise InvalidInputError(
            f"expected ambiguities within +-{MAX_AMBIGUITY}, got {amb_in.min()}..{amb_in.max()}"
        )
    return amb_in.astype(np.int64)


def _antenna_ranges(
    geometry: Geometry, m: NDArray[np.float64], ant: NDArray[np.float64]
) -> NDArray[np.float64]:
    """Far-field ranges per antenna ``rho_k - gamma_k . (R r_i)``: (..., n_ant, n_sat), m, for one
    attitude matrix ``m`` (3, 3) or one per epoch (n_t, 3, 3)."""
    los = geometry.los
    if m.ndim == 3:
        r_ref = np.einsum("tij,aj->tai", m, ant)
        proj = np.einsum("tai,tki->tak", r_ref, los)
    else:
        r_ref = ant @ m.T
        proj = np.einsum("ai,...ki->...ak", r_ref, los)
    rho: NDArray[np.float64] = geometry.range_m[..., None, :] - proj
    return rho


def _checked_antennas(antennas_body_m: ArrayLike, n_epochs: int, n_sat: int) -> NDArray[np.float64]:
    """A copy of the (n_ant, 3) body-frame antenna positions, m; the work refused first, from the shape."""
    n_ant = np.shape(plain_array("antennas_body_m", antennas_body_m))[:1] or (1,)
    if n_epochs * n_ant[0] * n_sat > MAX_SIMULATED_VALUES:
        raise WorkLimitError(
            f"antennas_body_m asks for {n_epochs} epochs x {n_ant[0]} antennas x {n_sat} satellites = "
            f"{n_epochs * n_ant[0] * n_sat} measurements, more than the limit of {MAX_SIMULATED_VALUES} "
            "(MAX_SIMULATED_VALUES): simulate fewer epochs or antennas per call"
        )
    ant = float_array("antennas_body_m", antennas_body_m, ndim=2, shape="(n_ant, 3)")
    if ant.shape[1] != 3 or ant.shape[0] < 1:
        raise InvalidInputError(f"expected antennas_body_m of shape (n_ant, 3), got {ant.shape}")
    copy: NDArray[np.float64] = ant.copy()  # the result holds read-only copies, never the caller's arrays
    return copy


def _checked_sigmas(
    code_sigma_m: float, phase_sigma_rad: float, phase_sigma_m: float, doppler_sigma_hz: float
) -> tuple[float, float, float, float]:
    """The noise sigmas of :func:`simulate_array`: code (m), phase (rad or m, one of the two) and
    Doppler (Hz)."""
    sig_code = scalar("code_sigma_m", code_sigma_m, minimum=0.0)
    sig_rad = scalar("phase_sigma_rad", phase_sigma_rad, minimum=0.0)
    sig_m = scalar("phase_sigma_m", phase_sigma_m, minimum=0.0)
    if sig_rad > 0 and sig_m > 0:
        raise InvalidInputError(f"expected one of phase_sigma_rad, phase_sigma_m, got {sig_rad} and {sig_m}")
    sig_dop = scalar("doppler_sigma_hz", doppler_sigma_hz, minimum=0.0)
    return sig_code, sig_rad, sig_m, sig_dop


def _phases(
    rng: np.random.Generator, name: str, value: ArrayLike | None, n: int, n_name: str
) -> NDArray[np.float64]:
    """Initial phases (rad): ``value`` checked as (n,), or drawn uniform in [-pi, pi) when None."""
    if value is None:
        return rng.uniform(-np.pi, np.pi, size=n)
    return _vector(name, value, n, n_name)


def _correlator(
    rng: np.random.Generator, cn0_dbhz: ArrayLike, integration_time_s: float, frac: NDArray[np.float64],
    n_sat: int,
) -> NDArray[np.complex128]:  # fmt: skip
    """Prompt correlator outputs at the fractional phases ``frac`` (cycles), unit complex noise added."""
    amp = correlator_amplitude(cn0_dbhz, integration_time_s)
    if amp.ndim == 1 and amp.shape != (n_sat,):
        raise InvalidInputError(f"expected cn0_dbhz of shape () or ({n_sat},), got {amp.shape}")
    noise = rng.standard_normal((*frac.shape, 2))
    corr: NDArray[np.complex128] = amp * np.exp(2j * np.pi * frac) + (noise[..., 0] + 1j * noise[..., 1])
    return corr


def simulate_array(
    geometry: Geometry,
    attitude: Rotation,
    antennas_body_m: ArrayLike,
    wavelengths_m: ArrayLike,
    rng: int | np.random.Generator | None = None,
    *,
    code_sigma_m: float = 0.0,
    phase_sigma_rad: float = 0.0,
    phase_sigma_m: float = 0.0,
    doppler_sigma_hz: float = 0.0,
    clock_bias_s: ArrayLike = 0.0,
    ambiguities: ArrayLike | None = None,
    ambiguity_max: int = 100,
    oscillator_phases_rad: ArrayLike | None = None,
    satellite_phases_rad: ArrayLike | None = None,
    cn0_dbhz: ArrayLike | None = None,
    integration_time_s: float = 0.001,
) -> ArrayMeasurements:
    """Simulate code, carrier phase, Doppler and correlator outputs of an antenna array (module docstring).

    Parameters
    ----------
    geometry
        Lines of sight, ranges and range rates (:func:`~gnssatt.orbit.line_of_sight.line_of_sight` or
        :meth:`Geometry.from_los`), one epoch or n_t epochs.
    attitude
        Body -> reference rotation: one, or n_t (one per epoch).
    antennas_body_m
        (n_ant, 3) antenna positions relative to the reference point, body frame, m.
    wavelengths_m
        (n_sat,) carrier wavelength per satellite (e.g. ``Constellation.wavelengths_m("L1")``), m.
    rng
        The only source of randomness: ``np.random.default_rng(rng)``, an int seed (reproducible), a
        ``numpy.random.Generator`` (used and advanced) or None (fresh entropy).
    code_sigma_m
        Standard deviation of the white pseudorange noise, m.
    phase_sigma_rad, phase_sigma_m
        Standard deviation of the white carrier-phase noise in radians, or in metres (converted per
        satellite with its wavelength); give at most one.
    doppler_sigma_hz
        Standard deviation of the white Doppler noise, Hz.
    clock_bias_s
        Receiver clock bias, scalar or (n_ant,), s (pseudoranges only).
    ambiguities
        (n_ant, n_sat) integers; default uniform integers in ``[-ambiguity_max, ambiguity_max]``.
    ambiguity_max
        Bound of the random ambiguities, 0 to ``MAX_AMBIGUITY`` (2^31).
    oscillator_phases_rad
        (n_ant,) receiver oscillator phases; default uniform in [-pi, pi) for every antenna (pass
        ``[0, ...]`` to pin antenna 0 as in Bunyaeva et al.).
    satellite_phases_rad
        (n_sat,) satellite signal phases; default uniform in [-pi, pi).
    cn0_dbhz
        Carrier-to-noise density ratio, scalar or (n_sat,), dB-Hz; correlator outputs only if given.
    integration_time_s
        Coherent integration time of the correlator, s.

    Returns
    -------
    ArrayMeasurements

    Raises
    ------
    InvalidTypeError
        ``geometry``, ``attitude`` or ``rng`` of the wrong type, non-numeric arrays, non-integer ambiguities
        (also a ``TypeError``).
    InvalidInputError
        Wrong shapes, non-finite values, negative noise levels or non-positive wavelengths.
    WorkLimitError
        More than :data:`MAX_SIMULATED_VALUES` epochs x antennas x satellites, refused before any is made.
    ConvergenceError
        Finite but extreme inputs (noise levels, clock biases, ranges near the float limit) overflowed a
        simulated measurement.

    Examples
    --------
    Noise-free phases with zero ambiguities, oscillator and satellite phases: the difference of an antenna
    5 cm along body X is ``-2 pi (gamma . R r_1) / lambda``, zero for a satellite at the zenith and
    ``-2 pi 0.05 / 0.19 = -1.653470`` rad for one on the X axis; the pseudoranges are the far-field ranges:

    >>> import numpy as np
    >>> from scipy.spatial.transform import Rotation
    >>> from gnssatt.orbit.line_of_sight import Geometry
    >>> from gnssatt.sim.measurements import simulate_array
    >>> geometry = Geometry.from_los([[0.0, 0.0, 1.0], [1.0, 0.0, 0.0]], range_m=2.2e7)  # ENU, m
    >>> antennas = [[0.0, 0.0, 0.0], [0.05, 0.0, 0.0]]  # (2, 3) m, body
    >>> zeros = {"ambiguities": np.zeros((2, 2), int), "oscillator_phases_rad": [0.0, 0.0],
    ...          "satellite_phases_rad": [0.0, 0.0]}
    >>> m = simulate_array(geometry, Rotation.identity(), antennas, [0.19, 0.19], rng=1, **zeros)
    >>> np.round(m.phase_diffs(), 6) + 0.0, round(-2 * np.pi * 0.05 / 0.19, 6)
    (array([[ 0.     , -1.65347]]), -1.65347)
    >>> np.round(m.pseudorange_m, 3)
    array([[22000000.  , 22000000.  ],
           [22000000.  , 21999999.95]])
    """
    instance("geometry", geometry, Geometry, "a gnssatt.sim Geometry")
    rng = generator("rng", rng)
    los = geometry.los
    batched = los.ndim == 3
    n_sat = geometry.n_sat
    n_epochs = los.shape[0] if batched else 1
    ant = _checked_antennas(antennas_body_m, n_epochs, n_sat)
    n_ant = ant.shape[0]
    lam = _wavelengths(wavelengths_m, n_sat)
    m = attitude_matrices(attitude, los.shape[0] if batched else None)
    sig_code, sig_rad, sig_m, sig_dop = _checked_sigmas(
        code_sigma_m, phase_sigma_rad, phase_sigma_m, doppler_sigma_hz
    )
    dt = _vector("clock_bias_s", clock_bias_s, n_ant, "n_ant")

    amb = _ambiguities(rng, ambiguities, ambiguity_max, n_ant, n_sat)
    osc = _phases(rng, "oscillator_phases_rad", oscillator_phases_rad, n_ant, "n_ant")
    alpha = _phases(rng, "satellite_phases_rad", satellite_phases_rad, n_sat, "n_sat")

    rho = _antenna_ranges(geometry, m, ant)
    shape = rho.shape

    code_noise = rng.standard_normal(shape)
    phase_noise = rng.standard_normal(shape)
    dop_noise = rng.standard_normal(shape)

    with np.errstate(over="ignore", invalid="ignore"):  # an overflow is reported below, by name
        pseudorange = rho + SPEED_OF_LIGHT_M_S * dt[:, None] + sig_code * code_noise
        sig_cycles = sig_rad / (2.0 * np.pi) if sig_rad > 0 else sig_m / lam
        frac = np.remainder(rho / lam, 1.0) + (osc[:, None] + alpha[None, :]) / (2.0 * np.pi)
        phase_free = (rho / lam + amb) + (osc[:, None] + alpha[None, :]) / (2.0 * np.pi)
        phase = phase_free + sig_cycles * phase_noise
        rate = np.broadcast_to(geometry.range_rate_mps[..., None, :], shape)
        doppler = -rate / lam + sig_dop * dop_noise

    corr = None if cn0_dbhz is None else _correlator(rng, cn0_dbhz, integration_time_s, frac, n_sat)
    cause = "the inputs (noise levels, clock biases, ranges, wavelengths) are too large for float64"
    for what, value in (
        ("pseudorange_m", pseudorange),
        ("carrier_phase_cycles", phase),
        ("doppler_hz", doppler),
    ):
        finite_result(f"the simulated {what}", value, cause)
    out = ArrayMeasurements(
        pseudorange_m=pseudorange,
        carrier_phase_cycles=phase,
        doppler_hz=np.ascontiguousarray(doppler),
        correlator=corr,
        range_m=rho,
        los=los,
        wavelengths_m=lam,
        ambiguities=amb,
        oscillator_phases_rad=osc,
        satellite_phases_rad=alpha,
        clock_bias_s=dt,
        antennas_body_m=ant,
        attitude=attitude,
        ids=geometry.ids,
    )
    readonly(pseudorange, phase, out.doppler_hz, corr, rho, lam, amb, osc, alpha, dt, ant)
    return out
