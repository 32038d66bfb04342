"""Type stubs of the compiled extension ``gnssatt._core`` (rust/py/src), held true to the runtime by
``python -m mypy.stubtest gnssatt._core`` (run by .ci/run after the build): names, parameter names, kinds
and defaults.

Angles in radians, lengths in metres. Result types are frozen: their attributes are read-only.
"""

from collections.abc import Mapping, Sequence
from typing import Literal, TypedDict, final

import numpy as np
from numpy.typing import ArrayLike, NDArray

# Every name the module adds (stubtest compares this list with the runtime one).
__all__ = [
    "DYNAMICS_MAX_RK4_STEPS",
    "DYNAMICS_MAX_ROTATION_PER_STEP_RAD",
    "GNSS_DEFAULT_ELEVATION_MASK_DEG",
    "GNSS_DEFAULT_MAX_FAILURE_RATE",
    "GNSS_DEFAULT_MIN_SUCCESS_RATE",
    "GNSS_DEFAULT_RATIO_THRESHOLD",
    "GNSS_FILTERS",
    "GNSS_MAX_FREQUENCIES",
    "GNSS_METHODS",
    "GNSS_MOTIONS",
    "LAMBDA_BATCH_MAX_SEARCH_WORK",
    "LAMBDA_BATCH_MAX_WORK",
    "LAMBDA_MAX_ABS_AMBIGUITY",
    "LAMBDA_MAX_CANDIDATES",
    "LAMBDA_MAX_DIMENSION",
    "LAMBDA_MAX_NODES",
    "LAMBDA_MAX_SAMPLES",
    "LAMBDA_NODES_PER_AMBIGUITY",
    "LIKELIHOOD_MAX_SERIES_WORK",
    "ORBIT_MAX_RK4_STEPS",
    "ORBIT_MIN_RADIUS_FRACTION",
    "BnbStats",
    "Decorrelation",
    "GnssEngine",
    "GnssOptions",
    "GnssSession",
    "GyroGnssFix",
    "GyroGnssOptions",
    "GyroGnssRun",
    "IlsBatch",
    "IlsSolution",
    "LikelihoodGrid",
    "MatrixAttitude",
    "MlEstimate",
    "MlSeries",
    "NavRecords",
    "Navigation",
    "ObsBody",
    "ObservationArrays",
    "OrbitFilterRun",
    "OrbitStates",
    "PartialFix",
    "RatioTest",
    "SatelliteStates",
    "SinglePoints",
    "StateWithStm",
    "TransmitStates",
    "TriadBatch",
    "WahbaBatch",
    "YawBatch",
    "__version__",
    "_panic_for_tests",
    "bnb_stats",
    "circular_orbit_ecef",
    "dcm_to_euler",
    "dcm_to_quat",
    "euler_to_dcm",
    "glonass_propagate",
    "gnss_klobuchar_delay",
    "gnss_run",
    "gnss_satellite_states",
    "gnss_single_point",
    "gnss_transmit_states",
    "gyro_gnss_filter",
    "gyro_propagate",
    "lambda_bootstrap_success_rate",
    "lambda_decorrelate",
    "lambda_ffrt_threshold",
    "lambda_ils",
    "lambda_ils_batch",
    "lambda_partial_fix",
    "lambda_ratio_test",
    "likelihood_grid",
    "matrix_attitude",
    "ml_attitude_series",
    "ml_baseline_series",
    "ml_search",
    "ml_series_work",
    "nearest_rotation",
    "orbit_filter_loose",
    "orbit_filter_tight",
    "quat_to_dcm",
    "rinex_nav_records",
    "rinex_obs_body",
    "triad_batch",
    "tumble_axes",
    "tumble_cost",
    "tumble_states",
    "wahba_batch",
    "yaw_batch",
]

__version__: str

def _panic_for_tests(message: str, *, in_worker: bool = False) -> None:
    """The panic boundary's test hook: panics with ``message`` (on a worker thread with ``in_worker``)."""

# rotation.rs
def euler_to_dcm(seq: str, angles_rad: tuple[float, float, float] | list[float]) -> NDArray[np.float64]: ...
def dcm_to_euler(seq: str, dcm: NDArray[np.float64]) -> tuple[float, float, float]: ...
def quat_to_dcm(quat: tuple[float, float, float, float] | list[float]) -> NDArray[np.float64]: ...
def dcm_to_quat(dcm: NDArray[np.float64]) -> tuple[float, float, float, float]: ...
def nearest_rotation(matrix: NDArray[np.float64]) -> NDArray[np.float64]: ...

# matrix_method.rs
@final
class MatrixAttitude:
    @property
    def dcm_ref_from_body(self) -> NDArray[np.float64]: ...  # (3, 3)
    @property
    def raw_body_from_ref(self) -> NDArray[np.float64]: ...  # (3, 3)
    @property
    def residual_rms_m(self) -> float: ...

def matrix_attitude(
    baselines: NDArray[np.float64],
    los: NDArray[np.float64],
    range_diffs: NDArray[np.float64],
    method: str,
) -> MatrixAttitude: ...

# likelihood.rs: phase_diffs (E, m, M), los (E, M, 3) ENU, wavelengths (E, M), baselines (m, 3) body.
@final
class MlEstimate:
    @property
    def angles_rad(self) -> NDArray[np.float64]: ...  # (3,) psi, theta, phi (GOST)
    @property
    def grid_angles_rad(self) -> NDArray[np.float64]: ...  # (3,)
    @property
    def z_max(self) -> float: ...
    @property
    def cells_evaluated(self) -> int: ...
    @property
    def step_rad(self) -> float: ...
    @property
    def grid_index(self) -> NDArray[np.uint64]: ...  # (3,)

@final
class BnbStats:
    @property
    def boxes_bounded(self) -> int: ...
    @property
    def leaf_cells(self) -> int: ...
    @property
    def grid_cells(self) -> int: ...
    @property
    def rounds(self) -> int: ...

@final
class LikelihoodGrid:
    @property
    def z(self) -> NDArray[np.float32]: ...  # (n_theta, n_phi, n_psi)
    @property
    def psi_rad(self) -> NDArray[np.float64]: ...
    @property
    def theta_rad(self) -> NDArray[np.float64]: ...
    @property
    def phi_rad(self) -> NDArray[np.float64]: ...

def ml_search(
    phase_diffs: NDArray[np.float64],
    los: NDArray[np.float64],
    wavelengths: NDArray[np.float64],
    baselines: NDArray[np.float64],
    *,
    statistic: str,
    step_rad: float | None,
    window_rad: list[list[float]] | None,
    search: str,
    refine: bool | str,
    two_dimensional: bool,
) -> MlEstimate: ...
def bnb_stats(
    phase_diffs: NDArray[np.float64],
    los: NDArray[np.float64],
    wavelengths: NDArray[np.float64],
    baselines: NDArray[np.float64],
    *,
    statistic: str,
    step_rad: float | None,
    window_rad: list[list[float]] | None,
) -> BnbStats: ...
def likelihood_grid(
    phase_diffs: NDArray[np.float64],
    los: NDArray[np.float64],
    wavelengths: NDArray[np.float64],
    baselines: NDArray[np.float64],
    *,
    statistic: str,
    step_rad: float | None,
    window_rad: list[list[float]] | None,
    two_dimensional: bool,
) -> LikelihoodGrid: ...

# likelihood.rs, per-epoch batches: sd_phase (E, n_rover, n_sig) with NaN for absent signals, los
# (E, n_sig, 3) ENU, wavelengths (E, n_sig).
@final
class MlSeries:
    @property
    def euler_gost_rad(self) -> NDArray[np.float64]: ...  # (E, 3)
    @property
    def direction_rad(self) -> NDArray[np.float64]: ...  # (E, 2) compass azimuth, elevation
    @property
    def z_max(self) -> NDArray[np.float64]: ...  # (E,)
    @property
    def solved(self) -> NDArray[np.bool_]: ...  # (E,)

def ml_attitude_series(
    sd_phase: NDArray[np.float64],
    los: NDArray[np.float64],
    wavelengths: NDArray[np.float64],
    baselines: NDArray[np.float64],
    *,
    step_rad: float | None,
    window_rad: float | None,
) -> MlSeries: ...
def ml_baseline_series(
    sd_phase: NDArray[np.float64],
    los: NDArray[np.float64],
    wavelengths: NDArray[np.float64],
    baseline_length_m: float,
    *,
    step_rad: float | None,
    window_rad: float | None,
) -> MlSeries: ...

LIKELIHOOD_MAX_SERIES_WORK: float

def ml_series_work(
    n_epochs: int,
    n_rover: int,
    n_sig: int,
    *,
    step_rad: float | None,
    wavelength_m: float,
    longest_baseline_m: float,
    window_rad: float | None,
    two_dimensional: bool,
) -> float: ...

# lambda.rs: integer least squares (LAMBDA / MLAMBDA), validation, partial fixing.
@final
class IlsSolution:
    @property
    def fixed(self) -> NDArray[np.int64]: ...  # (m, n), row k the k-th best
    @property
    def squared_norms(self) -> NDArray[np.float64]: ...  # (m,)
    @property
    def nodes_visited(self) -> int: ...

@final
class IlsBatch:
    @property
    def fixed(self) -> NDArray[np.int64]: ...  # (k, m, n)
    @property
    def squared_norms(self) -> NDArray[np.float64]: ...  # (k, m)
    @property
    def nodes_visited(self) -> NDArray[np.uint64]: ...  # (k,)

@final
class Decorrelation:
    @property
    def z(self) -> NDArray[np.int64]: ...  # (n, n)
    @property
    def l(self) -> NDArray[np.float64]: ...  # noqa: E743 (n, n), Z^T Q Z = L^T diag(D) L
    @property
    def d(self) -> NDArray[np.float64]: ...  # (n,)

@final
class RatioTest:
    @property
    def accepted(self) -> bool: ...
    @property
    def ratio(self) -> float: ...
    @property
    def threshold(self) -> float: ...
    @property
    def fixed(self) -> NDArray[np.int64]: ...  # (n,)
    @property
    def squared_norms(self) -> NDArray[np.float64]: ...  # (2,)

@final
class PartialFix:
    @property
    def fixed_count(self) -> int: ...
    @property
    def combinations(self) -> NDArray[np.int64]: ...  # (n, k)
    @property
    def values(self) -> NDArray[np.int64]: ...  # (k,)
    @property
    def ratio(self) -> float: ...
    @property
    def threshold(self) -> float: ...
    @property
    def success_rate(self) -> float: ...
    @property
    def ambiguities(self) -> NDArray[np.float64]: ...  # (n,)
    @property
    def covariance(self) -> NDArray[np.float64]: ...  # (n, n)

def lambda_ils(
    float_ambiguities: NDArray[np.float64], covariance: NDArray[np.float64], candidates: int = 2
) -> IlsSolution: ...
def lambda_ils_batch(
    float_ambiguities: NDArray[np.float64], covariance: NDArray[np.float64], candidates: int = 2
) -> IlsBatch: ...
def lambda_decorrelate(covariance: NDArray[np.float64]) -> Decorrelation: ...
def lambda_bootstrap_success_rate(covariance: NDArray[np.float64]) -> float: ...
def lambda_ffrt_threshold(
    covariance: NDArray[np.float64], failure_rate: float, samples: int, seed: int
) -> float: ...
def lambda_ratio_test(
    float_ambiguities: NDArray[np.float64],
    covariance: NDArray[np.float64],
    *,
    threshold: float | None,
    failure_rate: float | None,
    samples: int,
    seed: int,
) -> RatioTest: ...
def lambda_partial_fix(
    float_ambiguities: NDArray[np.float64],
    covariance: NDArray[np.float64],
    *,
    threshold: float | None,
    failure_rate: float | None,
    samples: int,
    seed: int,
    min_success_rate: float,
) -> PartialFix: ...

# dynamics.rs: params (n, 6) = (psi, alpha, phi) rad (intrinsic YZY, paper orbital axes) and absolute body
# rates rad/s; axes in the library orbital frame (x along-track, y normal, z radial).
class _TumbleModelArgs(TypedDict):
    """Belokonov et al. model parameters, SI units (``gnssatt.attitude.dynamics.TumbleModel._kwargs()``); a
    dict at runtime."""

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
    model: _TumbleModelArgs,
    *,
    step_s: float,
) -> NDArray[np.float64]: ...
def tumble_cost(
    params: NDArray[np.float64],
    times_s: NDArray[np.float64],
    measured: NDArray[np.float64],
    model: _TumbleModelArgs,
    *,
    step_s: float,
) -> NDArray[np.float64]: ...
def tumble_states(
    param: NDArray[np.float64],
    times_s: NDArray[np.float64],
    model: _TumbleModelArgs,
    *,
    step_s: float,
) -> NDArray[np.float64]: ...

# wahba.rs (epochs flattened by gnssatt.attitude.wahba / gnssatt.attitude.magnetometer)
@final
class WahbaBatch:
    @property
    def quat_ref_from_body(self) -> NDArray[np.float64]: ...  # (E, 4) scalar-last
    @property
    def covariance_ref(self) -> NDArray[np.float64]: ...  # (E, 3, 3)
    @property
    def information_ratio(self) -> NDArray[np.float64]: ...  # (E,)
    @property
    def loss(self) -> NDArray[np.float64]: ...  # (E,)

@final
class TriadBatch:
    @property
    def quat_ref_from_body(self) -> NDArray[np.float64]: ...  # (E, 4) scalar-last
    @property
    def sin_angle_body(self) -> NDArray[np.float64]: ...  # (E,)
    @property
    def sin_angle_ref(self) -> NDArray[np.float64]: ...  # (E,)

@final
class YawBatch:
    @property
    def yaw_rad(self) -> NDArray[np.float64]: ...  # (E,)
    @property
    def cos_pitch(self) -> NDArray[np.float64]: ...  # (E,) |cos pitch|
    @property
    def horizontal_fraction(self) -> NDArray[np.float64]: ...  # (E,)

def wahba_batch(
    body: NDArray[np.float64],
    reference: NDArray[np.float64],
    weights: NDArray[np.float64],
    pairs: int,
    method: str,
) -> WahbaBatch: ...
def triad_batch(
    b1: NDArray[np.float64], b2: NDArray[np.float64], r1: NDArray[np.float64], r2: NDArray[np.float64]
) -> TriadBatch: ...
def yaw_batch(
    b_body: NDArray[np.float64],
    b_orbital: NDArray[np.float64],
    pitch_rad: NDArray[np.float64],
    roll_rad: NDArray[np.float64],
) -> YawBatch: ...

# orbit.rs: states (x, y, z, vx, vy, vz) Earth-fixed, m and m/s.
class _GlonassModelArgs(TypedDict):
    """ICD model constants, SI units (``gnssatt.orbit.GlonassModel._kwargs()``); a dict at runtime."""

    gm_m3_s2: float
    j2: float
    equatorial_radius_m: float
    omega_rad_s: float
    lunisolar_m_s2: tuple[float, float, float]

@final
class StateWithStm:
    @property
    def state(self) -> NDArray[np.float64]: ...  # (6,)
    @property
    def stm(self) -> NDArray[np.float64]: ...  # (6, 6)

@final
class OrbitStates:
    @property
    def position_m(self) -> NDArray[np.float64]: ...  # (n, 3)
    @property
    def velocity_m_s(self) -> NDArray[np.float64]: ...  # (n, 3)

@final
class OrbitFilterRun:
    @property
    def states(self) -> NDArray[np.float64]: ...  # (n, 6)
    @property
    def covariances(self) -> NDArray[np.float64]: ...  # (n, 6, 6)
    @property
    def nis(self) -> NDArray[np.float64]: ...  # (n,)
    @property
    def dof(self) -> NDArray[np.uint64]: ...  # (n,), 0: no update

def glonass_propagate(
    state: NDArray[np.float64], duration_s: float, model: _GlonassModelArgs, *, step_s: float
) -> StateWithStm: ...
def circular_orbit_ecef(
    elements: list[float], times_s: NDArray[np.float64], *, theta0_rad: float, omega_rad_s: float
) -> OrbitStates: ...

# gnss_nav_input.rs: the navigation records converted once (from the column arrays of
# gnssatt.rinex.nav.NavInput, see NavInput.navigation), the argument of every GNSS binding.
@final
class Navigation:
    """Broadcast navigation data as the core's NavData (frozen; kepler/glonass missing: no such record)."""

    def __new__(
        cls,
        *,
        kepler: Mapping[str, ArrayLike] | None = None,
        glonass: Mapping[str, ArrayLike] | None = None,
        klobuchar: NDArray[np.float64] | None = None,
        leap_seconds: int | None = None,
    ) -> Navigation: ...
    @property
    def kepler_records(self) -> int: ...
    @property
    def glonass_records(self) -> int: ...
    @property
    def klobuchar(self) -> NDArray[np.float64] | None: ...  # (8,) alpha0..3, beta0..3
    @property
    def leap_seconds(self) -> int | None: ...  # GPS - UTC, s

# gnss_nav.rs (test-facing): evaluations of the broadcast records of a Navigation.
@final
class SatelliteStates:
    @property
    def position_m(self) -> NDArray[np.float64]: ...  # (n, 3) ECEF of the instant, NaN where not valid
    @property
    def clock_s(self) -> NDArray[np.float64]: ...  # (n,)
    @property
    def valid(self) -> NDArray[np.bool_]: ...  # (n,)

@final
class TransmitStates:
    @property
    def position_m(self) -> NDArray[np.float64]: ...  # (n, 3) at transmission, ECEF of reception
    @property
    def clock_s(self) -> NDArray[np.float64]: ...  # (n,) at transmission
    @property
    def elevation_rad(self) -> NDArray[np.float64]: ...  # (n,)
    @property
    def azimuth_rad(self) -> NDArray[np.float64]: ...  # (n,) clockwise from North
    @property
    def valid(self) -> NDArray[np.bool_]: ...  # (n,)

@final
class SinglePoints:
    @property
    def position_m(self) -> NDArray[np.float64]: ...  # (n_ep, 3) ECEF
    @property
    def clock_s(self) -> NDArray[np.float64]: ...  # (n_ep, 5) per system G R E C J, NaN where none
    @property
    def satellites(self) -> NDArray[np.int64]: ...  # (n_ep,) used
    @property
    def residual_rms_m(self) -> NDArray[np.float64]: ...  # (n_ep,)
    @property
    def pdop(self) -> NDArray[np.float64]: ...  # (n_ep,), NaN where none
    @property
    def satellites_per_system(self) -> NDArray[np.int64]: ...  # (n_ep, 5) used per system G R E C J

def gnss_satellite_states(
    navigation: Navigation,
    sats: list[str],
    t_gpst_ns: NDArray[np.int64],
    *,
    offset_s: NDArray[np.float64] | None = None,
) -> SatelliteStates: ...
def gnss_transmit_states(
    navigation: Navigation,
    sats: list[str],
    t_rx_gpst_ns: NDArray[np.int64],
    receiver_m: NDArray[np.float64],
    receiver_clock_s: NDArray[np.float64],
) -> TransmitStates: ...
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
    navigation: Navigation,
    time_gpst_ns: NDArray[np.int64],
    sats: list[str],
    glonass_channel: NDArray[np.int64],
    code_m: NDArray[np.float64],
    *,
    approx_position_m: NDArray[np.float64] | None = None,
    systems: str = "GRECJ",
    frequencies: int = 1,
    elevation_mask_deg: float = 10.0,
) -> SinglePoints: ...
def orbit_filter_loose(
    times_s: NDArray[np.float64],
    x0: NDArray[np.float64],
    p0: NDArray[np.float64],
    fix_position_m: NDArray[np.float64],
    fix_velocity_m_s: NDArray[np.float64],
    fix_covariance: NDArray[np.float64],
    fix_valid: NDArray[np.bool_],
    *,
    model: _GlonassModelArgs,
    accel_psd_m2_s3: float,
    step_s: float,
) -> OrbitFilterRun: ...
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
    *,
    code_sigma_m: float,
    doppler_sigma_hz: float,
    model: _GlonassModelArgs,
    accel_psd_m2_s3: float,
    step_s: float,
) -> OrbitFilterRun: ...

# gyro_gnss.rs, gyro_gnss_options.rs (arguments built by gnssatt.attitude.gyro_gnss)
def gyro_propagate(
    q0: NDArray[np.float64], t: NDArray[np.float64], rates: NDArray[np.float64]
) -> NDArray[np.float64]: ...

@final
class GyroGnssOptions:
    """The filter's settings, keyword-only; values checked by the core when the filter starts."""

    def __new__(
        cls,
        *,
        arw: float,
        rrw: float,
        baselines: NDArray[np.float64],
        phase_sigma: float,
        fix_enabled: bool,
        ratio_threshold: float,
        min_success_rate: float,
        slip_threshold: float,
        known_ambiguities: bool,
        output_every: int,
        sensitivity: tuple[float, float] | None = None,
        misalignment_sigma: float | None = None,
        max_failure_rate: float = 0.0,
    ) -> GyroGnssOptions: ...

@final
class GyroGnssFix:
    @property
    def t(self) -> float: ...
    @property
    def accepted(self) -> bool: ...
    @property
    def ratio(self) -> float: ...
    @property
    def success_rate(self) -> float: ...
    @property
    def values(self) -> list[tuple[int, int, int]]: ...  # (track, baseline, integer)

@final
class GyroGnssRun:
    @property
    def t(self) -> NDArray[np.float64]: ...  # (n,)
    @property
    def quaternion(self) -> NDArray[np.float64]: ...  # (n, 4) scalar-last, body -> reference
    @property
    def drift(self) -> NDArray[np.float64]: ...  # (n, 3)
    @property
    def covariance(self) -> NDArray[np.float64]: ...  # (n, 6, 6)
    @property
    def true_covariance(self) -> NDArray[np.float64]: ...  # (n, 6, 6)
    @property
    def misalignment(self) -> NDArray[np.float64]: ...  # (n, 3)
    @property
    def misalignment_covariance(self) -> NDArray[np.float64]: ...  # (n, 3, 3)
    @property
    def n_float(self) -> NDArray[np.uint64]: ...  # (n,)
    @property
    def n_fixed(self) -> NDArray[np.uint64]: ...  # (n,)
    @property
    def fixes(self) -> list[GyroGnssFix]: ...
    @property
    def slips(self) -> NDArray[np.float64]: ...  # (k, 3) rows (t, track, NIS)
    @property
    def nis(self) -> NDArray[np.float64]: ...  # (u, 3) rows (t, NIS, dof)

def gyro_gnss_filter(
    gyro_t: NDArray[np.float64],
    gyro_rates: NDArray[np.float64],
    *,
    q0: NDArray[np.float64],
    drift0: NDArray[np.float64],
    p0: NDArray[np.float64],
    options: GyroGnssOptions,
    fix_t: NDArray[np.float64],
    fix_q: NDArray[np.float64],
    fix_cov: NDArray[np.float64],
    epoch_t: NDArray[np.float64],
    phase_epoch: NDArray[np.int64],
    phase_track: NDArray[np.int64],
    phase_los: NDArray[np.float64],
    phase_wavelength: NDArray[np.float64],
    phase: NDArray[np.float64],
) -> GyroGnssRun: ...

# Work limits of the core, read by the Python layer (tumble, orbit).
DYNAMICS_MAX_RK4_STEPS: float
DYNAMICS_MAX_ROTATION_PER_STEP_RAD: float
ORBIT_MAX_RK4_STEPS: float
ORBIT_MIN_RADIUS_FRACTION: float
LAMBDA_MAX_CANDIDATES: int
LAMBDA_MAX_SAMPLES: int
LAMBDA_MAX_DIMENSION: int
LAMBDA_MAX_NODES: int
LAMBDA_NODES_PER_AMBIGUITY: int
LAMBDA_BATCH_MAX_WORK: int
LAMBDA_BATCH_MAX_SEARCH_WORK: int
LAMBDA_MAX_ABS_AMBIGUITY: float

# gnss.rs: the observation engine. ObservationArrays (of SessionInput.observations(): n_rx receivers,
# n_ep epochs, n_sat satellites, 3 frequency slots) and a Navigation; options None take the
# engine's defaults.
@final
class GnssSession:
    """Per-epoch results (n epochs, m rovers, k = 2 angles in baseline mode, 3 in attitude mode)."""

    mode: str  # "baseline" or "attitude"
    time_gpst_ns: NDArray[np.int64]  # (n,)
    method: list[str]  # (n,) "lambda" or "ml"
    solved: NDArray[np.bool_]  # (n,)
    fixed: NDArray[np.bool_]  # (n,)
    fix_state: list[str]  # (n,) "fixed", "held" or "float"
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

@final
class GnssOptions:
    """The engine's options, checked when made (None: the engine's default)."""

    def __new__(
        cls,
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
        baseline_lengths_m: Sequence[float] | None = None,
        filter: str | None = None,
        rigid: bool | None = None,
    ) -> GnssOptions: ...

@final
class ObservationArrays:
    """Observations of every receiver on common epochs, checked and converted once (frozen)."""

    def __new__(
        cls,
        *,
        time_gpst_ns: NDArray[np.int64],
        sats: list[str],
        glonass_channel: NDArray[np.int64],
        code_m: NDArray[np.float64],
        phase_cycles: NDArray[np.float64],
        doppler_hz: NDArray[np.float64],
        snr_dbhz: NDArray[np.float64],
        lli: NDArray[np.uint8],
        approx_position_m: NDArray[np.float64],
    ) -> ObservationArrays: ...
    @property
    def receivers(self) -> int: ...
    @property
    def epochs(self) -> int: ...
    @property
    def sats(self) -> list[str]: ...

def gnss_run(
    observations: ObservationArrays,
    navigation: Navigation,
    options: GnssOptions | None = None,
) -> GnssSession: ...

@final
class GnssEngine:
    """The engine fed a block of epochs at a time (state carried between calls)."""

    def __new__(
        cls,
        sats: list[str],
        glonass_channel: NDArray[np.int64],
        n_receivers: int,
        navigation: Navigation,
        options: GnssOptions | None = None,
    ) -> GnssEngine: ...
    def process(self, observations: ObservationArrays) -> GnssSession: ...

# The engine's defaults (rust/core/src/gnss/options.rs), read by gnssatt.gnss.attitude and the CLI.
GNSS_DEFAULT_MIN_SUCCESS_RATE: float
GNSS_DEFAULT_RATIO_THRESHOLD: float
GNSS_DEFAULT_MAX_FAILURE_RATE: float
GNSS_DEFAULT_ELEVATION_MASK_DEG: float
GNSS_MAX_FREQUENCIES: int
# The names GnssOptions accepts for motion, method, filter (rust/py/src/gnss_options.rs): the CLI's choices
# and gnssatt.gnss.attitude's checks (tests/test_gnss_option_names.py holds these Literals to the tables).
GNSS_MOTIONS: tuple[Literal["static", "moving"], ...]
GNSS_METHODS: tuple[Literal["auto", "ml", "lambda"], ...]
GNSS_FILTERS: tuple[Literal["static", "kinematic", "velocity"], ...]

# RINEX observation bodies (rust/py/src/rinex.rs)
@final
class ObsBody:
    @property
    def time_ns(self) -> NDArray[np.int64]: ...  # (n_epochs,) ns since 1970, as written
    @property
    def epoch_flag(self) -> NDArray[np.uint8]: ...
    @property
    def clock_offset_s(self) -> NDArray[np.float64]: ...
    @property
    def sats(self) -> list[str]: ...
    @property
    def data(self) -> NDArray[np.float64]: ...  # (n_epochs, n_sats, n_codes)
    @property
    def lli(self) -> NDArray[np.uint8]: ...
    @property
    def ssi(self) -> NDArray[np.uint8]: ...
    @property
    def cut(self) -> str | None: ...

def rinex_obs_body(
    path: str,
    text: bytes,
    first_line: int,
    v3: bool,
    default_system: str,
    layouts: list[tuple[str, int, list[int], list[int], list[float]]],
    n_codes: int,
    header_labels: list[str],
    max_cells: int,
) -> ObsBody: ...

# RINEX navigation files (rust/py/src/rinex_nav.rs)
@final
class NavRecords:
    @property
    def kepler_values(self) -> NDArray[np.float64]: ...  # (n, 29): af0-af2, the 26 orbit fields
    @property
    def kepler_sats(self) -> list[str]: ...
    @property
    def kepler_toc_ns(self) -> NDArray[np.int64]: ...  # (n,) ns since 1970 of the label
    @property
    def glonass_values(self) -> NDArray[np.float64]: ...  # (m, 15)
    @property
    def glonass_sats(self) -> list[str]: ...
    @property
    def glonass_tb_ns(self) -> NDArray[np.int64]: ...  # (m,) ns since 1970 of the UTC label
    @property
    def iono_alpha(self) -> NDArray[np.float64]: ...
    @property
    def iono_beta(self) -> NDArray[np.float64]: ...
    @property
    def leap_seconds(self) -> int | None: ...
    @property
    def unused(self) -> list[tuple[str, int]]: ...
    @property
    def skips(self) -> list[tuple[str, str]]: ...  # ("not an orbit" | "cut", description)
    @property
    def lines(self) -> int: ...

def rinex_nav_records(path: str, text: bytes, header_labels: list[str]) -> NavRecords: ...
