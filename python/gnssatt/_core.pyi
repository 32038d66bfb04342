"""Type stubs of the compiled extension ``gnssatt._core`` (rust/py/src); tests/test_stubs.py checks that
every native function is declared here.

Angles in radians, lengths in metres.
"""

from typing import Any, TypedDict

import numpy as np
from numpy.typing import NDArray

__version__: str

# rotation.rs
def euler_to_dcm(seq: str, angles_rad: tuple[float, float, float] | list[float]) -> NDArray[np.float64]: ...
def dcm_to_euler(seq: str, dcm: NDArray[np.float64]) -> tuple[float, float, float]: ...
def quat_to_dcm(quat: tuple[float, float, float, float] | list[float]) -> NDArray[np.float64]: ...
def dcm_to_quat(dcm: NDArray[np.float64]) -> tuple[float, float, float, float]: ...
def nearest_rotation(matrix: NDArray[np.float64]) -> NDArray[np.float64]: ...

# matrix_method.rs
def matrix_attitude(
    baselines: NDArray[np.float64],
    los: NDArray[np.float64],
    range_diffs: NDArray[np.float64],
    method: str = "svd",
) -> tuple[NDArray[np.float64], NDArray[np.float64], float]: ...

# likelihood.rs: phase_diffs (E, m, M), los (E, M, 3) ENU, wavelengths (E, M), baselines (m, 3) body.
def ml_search(
    phase_diffs: NDArray[np.float64],
    los: NDArray[np.float64],
    wavelengths: NDArray[np.float64],
    baselines: NDArray[np.float64],
    statistic: str,
    step_rad: float | None,
    window_rad: list[list[float]] | None,
    search: str,
    refine: str,
    two_dimensional: bool,
) -> tuple[
    tuple[float, float, float], tuple[float, float, float], float, int, float, tuple[int, int, int]
]: ...
def bnb_stats(
    phase_diffs: NDArray[np.float64],
    los: NDArray[np.float64],
    wavelengths: NDArray[np.float64],
    baselines: NDArray[np.float64],
    statistic: str,
    step_rad: float | None,
    window_rad: list[list[float]] | None,
) -> tuple[int, int, int]: ...
def likelihood_grid(
    phase_diffs: NDArray[np.float64],
    los: NDArray[np.float64],
    wavelengths: NDArray[np.float64],
    baselines: NDArray[np.float64],
    statistic: str,
    step_rad: float | None,
    window_rad: list[list[float]] | None,
    two_dimensional: bool,
) -> tuple[NDArray[np.float32], NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]: ...

# likelihood.rs, per-epoch batches: sd_phase (E, n_rover, n_sig) with NaN for absent signals, los
# (E, n_sig, 3) ENU, wavelengths (E, n_sig). Returns euler_rad (E, 3), direction_rad (E, 2) (compass
# azimuth, elevation of the first baseline), z_max (E,), solved (E,).
def ml_attitude_series(
    sd_phase: NDArray[np.float64],
    los: NDArray[np.float64],
    wavelengths: NDArray[np.float64],
    baselines: NDArray[np.float64],
    step_rad: float | None,
    window_rad: float | None,
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64], NDArray[np.bool_]]: ...
def ml_baseline_series(
    sd_phase: NDArray[np.float64],
    los: NDArray[np.float64],
    wavelengths: NDArray[np.float64],
    baseline_length_m: float,
    step_rad: float | None,
    window_rad: float | None,
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64], NDArray[np.bool_]]: ...

# lambda.rs: integer least squares (LAMBDA / MLAMBDA), validation, partial fixing.
def lambda_ils(
    float_ambiguities: NDArray[np.float64], covariance: NDArray[np.float64], candidates: int = 2
) -> tuple[NDArray[np.int64], NDArray[np.float64], int]: ...
def lambda_decorrelate(
    covariance: NDArray[np.float64],
) -> tuple[NDArray[np.int64], NDArray[np.float64], NDArray[np.float64]]: ...
def lambda_bootstrap_success_rate(covariance: NDArray[np.float64]) -> float: ...
def lambda_ffrt_threshold(
    covariance: NDArray[np.float64], failure_rate: float, samples: int, seed: int
) -> float: ...
def lambda_ratio_test(
    float_ambiguities: NDArray[np.float64],
    covariance: NDArray[np.float64],
    threshold: float | None,
    failure_rate: float | None,
    samples: int,
    seed: int,
) -> tuple[bool, float, float, NDArray[np.int64], NDArray[np.float64]]: ...
def lambda_partial_fix(
    float_ambiguities: NDArray[np.float64],
    covariance: NDArray[np.float64],
    threshold: float | None,
    failure_rate: float | None,
    samples: int,
    seed: int,
    min_success_rate: float,
) -> tuple[
    int,
    NDArray[np.int64],
    NDArray[np.int64],
    float,
    float,
    float,
    NDArray[np.float64],
    NDArray[np.float64],
]: ...

# dynamics.rs: params (n, 6) = (psi, alpha, phi) rad (intrinsic YZY, paper orbital axes) and absolute body
# rates rad/s; axes in the library orbital frame (x along-track, y normal, z radial).
class TumbleModelArgs(TypedDict):
    """Seed-004 model parameters, SI units (``gnssatt.tumble.TumbleModel._kwargs()``)."""

    inertia_kg_m2: tuple[float, float, float]
    orbital_rate_rad_s: float
    gravity_gradient: bool
    density_kg_m3: float
    drag_coefficient: float
    area_m2: float
    cp_offset_m: tuple[float, float, float]
    speed_m_s: float

def tumble_axes(
    params: NDArray[np.float64],
    times_s: NDArray[np.float64],
    model: TumbleModelArgs,
    *,
    step_s: float,
) -> NDArray[np.float64]: ...
def tumble_cost(
    params: NDArray[np.float64],
    times_s: NDArray[np.float64],
    measured: NDArray[np.float64],
    model: TumbleModelArgs,
    *,
    step_s: float,
) -> NDArray[np.float64]: ...
def tumble_states(
    param: NDArray[np.float64],
    times_s: NDArray[np.float64],
    model: TumbleModelArgs,
    *,
    step_s: float,
) -> NDArray[np.float64]: ...

# wahba.rs (epochs flattened by gnssatt.vector_attitude / gnssatt.magnetometer)
def wahba_batch(
    body: NDArray[np.float64],
    reference: NDArray[np.float64],
    weights: NDArray[np.float64],
    pairs: int,
    method: str = "svd",
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]: ...
def triad_batch(
    b1: NDArray[np.float64], b2: NDArray[np.float64], r1: NDArray[np.float64], r2: NDArray[np.float64]
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]: ...
def yaw_batch(
    b_body: NDArray[np.float64],
    b_orbital: NDArray[np.float64],
    pitch_rad: NDArray[np.float64],
    roll_rad: NDArray[np.float64],
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]: ...

# orbit.rs: states (x, y, z, vx, vy, vz) Earth-fixed, m and m/s; model = gnssatt.orbit.GlonassModel._kwargs().
def glonass_propagate(
    state: NDArray[np.float64], duration_s: float, model: dict[str, object], *, step_s: float
) -> tuple[NDArray[np.float64], NDArray[np.float64]]: ...
def circular_orbit_ecef(
    elements: list[float], times_s: NDArray[np.float64], *, theta0_rad: float, omega_rad_s: float
) -> tuple[NDArray[np.float64], NDArray[np.float64]]: ...

# gnss_nav.rs (test-facing): nav dicts = gnssatt.rinex.session_input.NavInput.kepler / .glonass arrays.
def gnss_satellite_states(
    kepler: dict[str, NDArray[Any]],
    glonass: dict[str, NDArray[Any]],
    klobuchar: NDArray[np.float64] | None,
    leap_seconds: int | None,
    sats: list[str],
    t_gpst_ns: NDArray[np.int64],
    *,
    offset_s: NDArray[np.float64] | None = None,
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.bool_]]: ...
def gnss_transmit_states(
    kepler: dict[str, NDArray[Any]],
    glonass: dict[str, NDArray[Any]],
    klobuchar: NDArray[np.float64] | None,
    leap_seconds: int | None,
    sats: list[str],
    t_rx_gpst_ns: NDArray[np.int64],
    receiver_m: NDArray[np.float64],
    receiver_clock_s: NDArray[np.float64],
) -> tuple[
    NDArray[np.float64], NDArray[np.float64], NDArray[np.float64], NDArray[np.float64], NDArray[np.bool_]
]: ...
def gnss_klobuchar_delay(
    coefficients: NDArray[np.float64],
    t_gpst_ns: NDArray[np.int64],
    lat_rad: float,
    lon_rad: float,
    azimuth_rad: NDArray[np.float64],
    elevation_rad: NDArray[np.float64],
    frequency_hz: NDArray[np.float64],
) -> NDArray[np.float64]: ...
def gnss_single_point(
    kepler: dict[str, NDArray[Any]],
    glonass: dict[str, NDArray[Any]],
    klobuchar: NDArray[np.float64] | None,
    leap_seconds: int | None,
    time_gpst_ns: NDArray[np.int64],
    sats: list[str],
    glonass_channel: NDArray[np.int64],
    code_m: NDArray[np.float64],
    *,
    approx_position_m: NDArray[np.float64] | None = None,
    systems: str = "GRECJ",
    frequencies: int = 1,
    elevation_mask_deg: float = 10.0,
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.int64], NDArray[np.float64]]: ...
def orbit_filter_loose(
    times_s: NDArray[np.float64],
    x0: NDArray[np.float64],
    p0: NDArray[np.float64],
    fix_position_m: NDArray[np.float64],
    fix_velocity_m_s: NDArray[np.float64],
    fix_covariance: NDArray[np.float64],
    fix_valid: NDArray[np.bool_],
    model: dict[str, object],
    settings: dict[str, float],
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64], NDArray[np.uint64]]: ...
def orbit_filter_tight(
    times_s: NDArray[np.float64],
    x0: NDArray[np.float64],
    p0: NDArray[np.float64],
    sat_position_m: NDArray[np.float64],
    sat_velocity_m_s: NDArray[np.float64],
    pseudorange_m: NDArray[np.float64],
    doppler_hz: NDArray[np.float64],
    visible: NDArray[np.bool_],
    wavelength_m: NDArray[np.float64],
    system: NDArray[np.uint32],
    code_sigma_m: float,
    doppler_sigma_hz: float,
    model: dict[str, object],
    settings: dict[str, float],
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64], NDArray[np.uint64]]: ...

# gyro_gnss.rs (arguments built by gnssatt.gyro_gnss)
def gyro_propagate(
    q0: NDArray[np.float64], t: NDArray[np.float64], rates: NDArray[np.float64]
) -> NDArray[np.float64]: ...
def gyro_gnss_filter(
    gyro_t: NDArray[np.float64],
    gyro_rates: NDArray[np.float64],
    q0: NDArray[np.float64],
    drift0: NDArray[np.float64],
    p0: NDArray[np.float64],
    arw: float,
    rrw: float,
    baselines: NDArray[np.float64],
    phase_sigma: float,
    fix_enabled: bool,
    ratio_threshold: float,
    min_success_rate: float,
    slip_threshold: float,
    known_ambiguities: bool,
    sensitivity: tuple[float, float] | None,
    misalignment_sigma: float | None,
    output_every: int,
    fix_t: NDArray[np.float64],
    fix_q: NDArray[np.float64],
    fix_cov: NDArray[np.float64],
    epoch_t: NDArray[np.float64],
    phase_epoch: NDArray[np.int64],
    phase_track: NDArray[np.int64],
    phase_los: NDArray[np.float64],
    phase_wavelength: NDArray[np.float64],
    phase: NDArray[np.float64],
) -> dict[str, object]: ...

# Work limits of the core, read by the Python layer (tumble, orbit).
DYNAMICS_MAX_RK4_STEPS: float
DYNAMICS_MAX_ROTATION_PER_STEP_RAD: float
ORBIT_MAX_RK4_STEPS: float
LAMBDA_MAX_CANDIDATES: int
LAMBDA_MAX_SAMPLES: int
LAMBDA_MAX_DIMENSION: int
LAMBDA_MAX_NODES: int
LAMBDA_MAX_ABS_AMBIGUITY: float

# gnss.rs: the observation engine. Arrays of gnssatt.rinex.session_input.SessionInput (n_rx receivers,
# n_ep epochs, n_sat satellites, 3 frequency slots) and NavInput; options None take the engine's defaults.
class GnssSession:
    """Per-epoch results (n epochs, m rovers, k = 2 angles in baseline mode, 3 in attitude mode)."""

    mode: str  # "baseline" or "attitude"
    time_gpst_ns: NDArray[np.int64]  # (n,)
    method: list[str]  # (n,) "lambda" or "ml"
    solved: NDArray[np.bool_]  # (n,)
    fixed: NDArray[np.bool_]  # (n,)
    fixed_ambiguities: NDArray[np.int64]  # (n,)
    ambiguities: NDArray[np.int64]  # (n,)
    ratio: NDArray[np.float64]  # (n,)
    success_rate: NDArray[np.float64]  # (n,)
    angles_deg: NDArray[np.float64]  # (n, k)
    angle_sigmas_deg: NDArray[np.float64]  # (n, k)
    baselines_enu_m: NDArray[np.float64]  # (n, m, 3)
    baseline_covariance_enu_m2: NDArray[np.float64]  # (n, m, 3, 3)
    rotation_enu_from_body: NDArray[np.float64] | None  # (n, 3, 3), attitude mode
    satellites_per_system: NDArray[np.int64]  # (n, 5), G R E C J
    frequency_slots_used: NDArray[np.uint8]  # (n,) bit s: slot s used
    base_position_m: NDArray[np.float64]  # (n, 3) ECEF
    double_differences: NDArray[np.uint64] | None  # (5, 3); None from GnssEngine.process
    warnings: list[str]
    code_sigma_scale: list[float]

class GnssOptions:
    """The engine's options, checked when made (None: the engine's default)."""

    def __init__(
        self,
        *,
        systems: str | None = None,
        frequencies: int | None = None,
        elevation_mask_deg: float | None = None,
        base_position_m: NDArray[np.float64] | None = None,
        motion: str | None = None,
        method: str | None = None,
        continuity: bool | None = None,
        min_success_rate: float | None = None,
        ratio_threshold: float | None = None,
        max_failure_rate: float | None = None,
        body_baselines_m: NDArray[np.float64] | None = None,
        step_deg: float | None = None,
        window_deg: float | None = None,
    ) -> None: ...

def gnss_run(
    time_gpst_ns: NDArray[np.int64],
    sats: list[str],
    glonass_channel: NDArray[np.int64],
    code_m: NDArray[np.float64],
    phase_cycles: NDArray[np.float64],
    doppler_hz: NDArray[np.float64],
    snr_dbhz: NDArray[np.float64],
    lli: NDArray[np.uint8],
    approx_position_m: NDArray[np.float64],
    kepler: dict[str, NDArray[Any]],
    glonass: dict[str, NDArray[Any]],
    klobuchar: NDArray[np.float64] | None,
    leap_seconds: int | None,
    options: GnssOptions | None = None,
) -> GnssSession: ...

class GnssEngine:
    """The engine fed a block of epochs at a time (state carried between calls)."""

    def __init__(
        self,
        sats: list[str],
        glonass_channel: NDArray[np.int64],
        n_receivers: int,
        kepler: dict[str, NDArray[Any]],
        glonass: dict[str, NDArray[Any]],
        klobuchar: NDArray[np.float64] | None,
        leap_seconds: int | None,
        options: GnssOptions | None = None,
    ) -> None: ...
    def process(
        self,
        time_gpst_ns: NDArray[np.int64],
        code_m: NDArray[np.float64],
        phase_cycles: NDArray[np.float64],
        doppler_hz: NDArray[np.float64],
        snr_dbhz: NDArray[np.float64],
        lli: NDArray[np.uint8],
        approx_position_m: NDArray[np.float64],
    ) -> GnssSession: ...

# The engine's defaults (rust/core/src/gnss/options.rs), read by gnssatt.rinex.attitude and the CLI.
GNSS_DEFAULT_MIN_SUCCESS_RATE: float
GNSS_DEFAULT_RATIO_THRESHOLD: float
GNSS_DEFAULT_MAX_FAILURE_RATE: float
GNSS_DEFAULT_ELEVATION_MASK_DEG: float
GNSS_MAX_FREQUENCIES: int
