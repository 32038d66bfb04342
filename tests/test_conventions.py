"""The rules of docs/conventions.md, "One convention each", held for every result type and stochastic entry.

Truths are built with scipy's ``Rotation.from_euler`` in the documented sequence (not with the library's
own converters), and the measurements from the documented measurement models; a result passes when its
``.rotation`` maps body vectors onto the reference-frame vectors those truths give.
"""

from __future__ import annotations

import importlib
import inspect
import pkgutil
from collections.abc import Callable
from typing import Any

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

import gnssatt
from gnssatt import sim
from gnssatt._arrays import generator
from gnssatt.attitude import dynamics as tumble
from gnssatt.attitude import gyro_gnss
from gnssatt.errors import InvalidInputError, InvalidTypeError
from gnssatt.gnss.attitude import AttitudeSeries as RinexAttitudeSeries
from gnssatt.orbit import determination
from gnssatt.sim import attitude_scenario as scen
from gnssatt.sim import rinex_scenario

# (N, U, E) -> (E, N, U): the rows of the GOST normal frame reordered into ENU (docs/conventions.md, Bunyaeva
# et al.)
ENU_FROM_NUE = np.array([[0.0, 0.0, 1.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]])
# Library orbital (x, y, z) = the paper's (Y0, Z0, X0) (docs/conventions.md, Belokonov et al.)
ORBITAL_FROM_ORB0 = np.array([[0.0, 1.0, 0.0], [0.0, 0.0, 1.0], [1.0, 0.0, 0.0]])
LAMBDA_L1 = 299_792_458.0 / 1575.42e6


def _angle_deg(a: Rotation, b: Rotation) -> float:
    return float(np.degrees(np.max(np.atleast_1d((a * b.inv()).magnitude()))))


def _los(n: int, seed: int) -> np.ndarray:
    """n unit lines of sight above 15 deg elevation (z up), spread in azimuth."""
    rng = np.random.default_rng(seed)
    az = np.sort(rng.uniform(0.0, 2 * np.pi, n))
    el = rng.uniform(np.radians(15.0), np.radians(80.0), n)
    return np.column_stack([np.cos(el) * np.sin(az), np.cos(el) * np.cos(az), np.sin(el)])


# --- .rotation of every attitude result, against scipy's from_euler in the documented sequence ---------


def test_matrix_attitude_rotation_and_heading_pitch_roll_are_scipy_zyx() -> None:
    hpr = np.array([30.0, 10.0, -5.0])
    truth = Rotation.from_euler("ZYX", hpr, degrees=True)  # body -> reference
    baselines = np.array([[1.0, 0.0, 0.0], [0.0, 0.8, 0.0], [0.0, 0.0, 0.6]])
    los = _los(6, 1)
    range_diffs = truth.apply(baselines) @ los.T  # dr_ij = b_i . (A s_j), A = R^T
    res = gnssatt.matrix_attitude(baselines, los, range_diffs)
    assert _angle_deg(res.rotation, truth) < 1e-9
    np.testing.assert_allclose(res.rotation.apply(baselines), truth.apply(baselines), atol=1e-9)
    np.testing.assert_allclose(res.heading_pitch_roll_deg, hpr, atol=1e-9)


def _gost_phases(euler_gost_deg: np.ndarray, baselines: np.ndarray, los: np.ndarray) -> np.ndarray:
    """Wrapped phase differences (RINEX sign) of the Bunyaeva et al. truth, built from scipy's YZX in NUE."""
    r_enu = ENU_FROM_NUE @ Rotation.from_euler("YZX", euler_gost_deg, degrees=True).as_matrix()
    d_enu = baselines @ r_enu.T
    return np.angle(np.exp(-2j * np.pi * (d_enu @ los.T) / LAMBDA_L1))


BASELINES_3 = np.array([[1.0, 0.0, 0.0], [0.0, 0.0, 0.8]])  # nose, right wing (body X nose, Y up, Z right)


def test_ml_attitude_rotation_is_gost_yzx_in_the_normal_frame() -> None:
    euler = np.array([-90.0, 4.0, 6.0])  # psi = -90 deg: compass heading 90 deg, the nose towards East
    los = _los(8, 2)
    res = gnssatt.ml_attitude(
        _gost_phases(euler, BASELINES_3, los),
        los,
        BASELINES_3,
        LAMBDA_L1,
        step_deg=2.0,
        window_deg=np.column_stack([euler - 5.0, euler + 5.0]),
    )
    truth = Rotation.from_matrix(ENU_FROM_NUE @ Rotation.from_euler("YZX", euler, degrees=True).as_matrix())
    assert _angle_deg(res.rotation, truth) < 1e-4
    np.testing.assert_allclose(res.euler_gost_deg, euler, atol=1e-4)
    # the documented reading, with no matrix at all: heading 90 deg, pitch 4 deg puts the nose East and up
    nose = res.rotation.apply([1.0, 0.0, 0.0])
    np.testing.assert_allclose(nose, [np.cos(np.radians(4.0)), 0.0, np.sin(np.radians(4.0))], atol=1e-6)


def test_ml_attitude_series_rotation_is_batched_with_the_identity_where_unsolved() -> None:
    euler = np.array([[20.0, 3.0, -2.0], [25.0, 2.0, 1.0]])
    los = _los(7, 3)
    sd = np.stack([_gost_phases(e, BASELINES_3, los) for e in euler] + [np.full((2, 7), np.nan)])
    res = gnssatt.ml_attitude_series(sd, los, BASELINES_3, LAMBDA_L1, step_deg=2.0)
    assert len(res.rotation) == 3 and res.solved.tolist() == [True, True, False]
    for k in range(2):
        truth = Rotation.from_matrix(
            ENU_FROM_NUE @ Rotation.from_euler("YZX", euler[k], degrees=True).as_matrix()
        )
        assert _angle_deg(res.rotation[k], truth) < 1e-4
    np.testing.assert_array_equal(res.rotation[2].as_matrix(), np.eye(3))


def _rinex_series(matrices: np.ndarray, angles_deg: np.ndarray) -> RinexAttitudeSeries:
    n = len(angles_deg)
    zeros = np.zeros(n)
    return RinexAttitudeSeries(
        time=np.arange(n).astype("datetime64[s]").astype("datetime64[ns]"),
        mode="attitude",
        angles_deg=angles_deg,
        method=np.array(["lambda"] * n),
        fixed=np.ones(n, dtype=np.int64),
        fix_state=np.array(["fixed"] * n),
        satellites=np.full(n, 8),
        angle_sigmas_deg=np.zeros((n, 3)),
        baselines_enu_m=np.zeros((n, 2, 3)),
        ratio=zeros,
        success_rate=zeros,
        satellites_per_system=np.zeros((n, 5), dtype=np.int64),
        frequency_slots_used=np.ones(n, dtype=np.uint8),
        double_differences=np.zeros((5, 3), dtype=np.uint64),
        rotation_matrices=matrices,
        signal_codes={},
        warnings=(),
    )


def test_rinex_attitude_series_rotation_has_one_rotation_per_epoch() -> None:
    # compass heading h = -psi, pitch, roll of the engine's attitude mode, as scipy's GOST YZX in NUE
    hpr = np.array([[40.0, 5.0, 3.0], [np.nan, np.nan, np.nan], [300.0, -2.0, 1.0]])
    psi_theta_phi = np.column_stack([-hpr[:, 0], hpr[:, 1], hpr[:, 2]])
    mats = ENU_FROM_NUE @ Rotation.from_euler("YZX", np.nan_to_num(psi_theta_phi), degrees=True).as_matrix()
    mats[1] = np.nan  # the engine's unsolved epoch
    rot = _rinex_series(mats, hpr).rotation
    assert len(rot) == 3
    np.testing.assert_array_equal(rot[1].as_matrix(), np.eye(3))
    for k in (0, 2):
        nose = rot[k].apply([1.0, 0.0, 0.0])  # ENU
        heading = np.degrees(np.arctan2(nose[0], nose[1])) % 360.0
        assert heading == pytest.approx(hpr[k, 0], abs=1e-9)
        assert np.degrees(np.arcsin(nose[2])) == pytest.approx(hpr[k, 1], abs=1e-9)


def test_yaw_from_magnetometer_rotation_is_scipy_zyx_body_to_orbital() -> None:
    psi, theta, phi = 0.7, 0.05, -0.08
    truth = Rotation.from_euler("ZYX", [psi, theta, phi])  # body -> orbital
    b_orbital = np.array([1.0e-5, 2.0e-5, -3.0e-5])
    res = gnssatt.yaw_from_magnetometer(truth.inv().apply(b_orbital), b_orbital, theta, phi)
    assert _angle_deg(res.rotation, truth) < 1e-9
    assert res.yaw_rad == pytest.approx(psi, abs=1e-12)
    assert res.yaw_deg == pytest.approx(np.degrees(psi), abs=1e-10)


def test_triad_and_wahba_rotations_map_body_vectors_onto_the_reference_vectors() -> None:
    truth = Rotation.from_euler("ZYX", [120.0, -20.0, 35.0], degrees=True)
    ref = _los(4, 4)
    body = truth.inv().apply(ref)
    tri = gnssatt.triad(body[0], body[1], ref[0], ref[1])
    wah = gnssatt.wahba(body, ref)
    for res in (tri, wah):
        assert _angle_deg(res.rotation, truth) < 1e-9
        np.testing.assert_allclose(res.rotation.apply(body), ref, atol=1e-9)


def test_tumble_rotation_is_scipy_yzy_from_the_papers_orbital_frame() -> None:
    params = np.array([0.4, 1.1, 2.0, 0.001, -0.002, 0.0015])  # psi, alpha, phi (rad), rates (rad/s)
    truth = Rotation.from_matrix(ORBITAL_FROM_ORB0 @ Rotation.from_euler("YZY", params[:3]).as_matrix())
    fit = tumble.RotationFit(
        params=params,
        cost=0.0,
        nfev=0,
        nit=0,
        stopped_by="paper",
        residual_rms_deg=0.0,
        attempt_params=params[None],
        attempt_costs=np.zeros(1),
        cost_threshold=np.inf,
    )
    assert _angle_deg(fit.rotation, truth) < 1e-12
    np.testing.assert_allclose(fit.euler_yzy_deg, np.degrees(params[:3]))
    # the paper's reading: alpha is the angle between the antenna axis (body Yc) and the velocity (Y0 = x)
    axis = fit.rotation.apply([0.0, 1.0, 0.0])
    assert np.degrees(np.arccos(axis[0])) == pytest.approx(np.degrees(params[1]), abs=1e-9)
    traj = tumble.propagate(params, [0.0, 10.0])
    assert len(traj.rotation) == 2 and _angle_deg(traj.rotation[0], truth) < 1e-9
    np.testing.assert_allclose(traj.axis, traj.rotation.apply([0.0, 1.0, 0.0]), atol=1e-12)


def test_attitude_fixes_rotation_is_the_body_to_eci_attitude() -> None:
    t = np.array([0.0, 10.0, 20.0])
    truth = Rotation.from_euler(
        "ZYX", [[10.0, 20.0, 30.0], [11.0, 20.0, 30.0], [12.0, 20.0, 30.0]], degrees=True
    )
    leo = sim.OrbitalReceiver(altitude_m=500e3, inclination_deg=97.0)
    b = np.array([[1.0, 0.0, 0.0], [0.0, 1.0, 0.0]])
    ph = scen.phase_observations(
        leo, sim.gps_nominal(), t, truth, b, rng=2, phase_sigma_cycles=1e-4, half_angle_deg=180.0
    )
    fixes = scen.attitude_fixes(ph, truth, b, rng=3, phase_sigma_cycles=1e-4)
    assert len(fixes.rotation) == len(fixes.t) == 3
    assert _angle_deg(fixes.rotation, truth) < 0.05  # 1e-4 cycles on 1 m baselines: ~1e-3 deg


# Every public attitude result type of the package: the structural rule, so that a new result without
# .rotation fails here.
ATTITUDE_RESULTS = [
    gnssatt.MatrixAttitudeResult,
    gnssatt.LikelihoodAttitude,
    gnssatt.LikelihoodAttitudeSeries,
    RinexAttitudeSeries,
    gnssatt.YawResult,
    gnssatt.TriadResult,
    gnssatt.WahbaResult,
    gnssatt.RotationFit,
    tumble.TumbleTrajectory,
    scen.AttitudeFixes,
    gnssatt.GyroGnssResult,
    gyro_gnss.GyroPropagation,
]


@pytest.mark.parametrize("cls", ATTITUDE_RESULTS, ids=lambda c: c.__name__)
def test_every_attitude_result_type_has_rotation(cls: type) -> None:
    fields = getattr(cls, "__dataclass_fields__", {})
    assert "rotation" in fields or isinstance(inspect.getattr_static(cls, "rotation", None), property)


@pytest.mark.parametrize("cls", ATTITUDE_RESULTS, ids=lambda c: c.__name__)
def test_no_attitude_result_has_an_unnamed_euler_field(cls: type) -> None:
    # Euler angles are named by their sequence: heading_pitch_roll_deg or euler_<convention>_deg
    names = set(getattr(cls, "__dataclass_fields__", {})) | {
        n
        for n, v in vars(cls).items()
        if isinstance(v, property) and not (v.__doc__ or "").startswith("Deprecated")
    }
    assert not {"euler_deg", "euler_rad", "euler", "angles_deg", "yaw"} & names or cls is RinexAttitudeSeries


def test_gyro_propagate_result_has_rotation() -> None:
    # a constant rate about body z: the closed form is the truth, R(t) = Rz(w t)
    w = 0.3
    out = gnssatt.gyro_propagate([0.0, 0.0, 0.0, 1.0], [0.0, 1.0, 2.0], np.tile([0.0, 0.0, w], (3, 1)))
    assert isinstance(out.rotation, Rotation) and len(out.rotation) == 3
    assert _angle_deg(out.rotation, Rotation.from_rotvec(np.outer([0.0, 1.0, 2.0], [0.0, 0.0, w]))) < 1e-10


def test_gyro_propagate_quaternions_are_its_rotation() -> None:
    out = gnssatt.gyro_propagate([0.0, 0.0, 0.0, 1.0], [0.0, 1.0], np.tile([0.0, 0.0, 0.3], (2, 1)))
    np.testing.assert_allclose(Rotation.from_quat(out.quaternions).as_matrix(), out.rotation.as_matrix())
    with pytest.raises(TypeError):
        out[1]  # type: ignore[index]  # a result, not the array it used to be (CHANGELOG.md)


# --- rng= on every stochastic entry -------------------------------------------------------------------

GPS = sim.gps_nominal()
GEOM = sim.line_of_sight(sim.GroundReceiver(lat_deg=50.0, lon_deg=36.2, height_m=150.0), GPS, t=0.0)
LEO = sim.OrbitalReceiver(altitude_m=500e3, inclination_deg=97.0)
T3 = np.array([0.0, 10.0, 20.0])
ATT3 = Rotation.from_rotvec(np.zeros((3, 3)))
B2 = np.array([[1.0, 0.0, 0.0], [0.0, 1.0, 0.0]])
PHASES = scen.phase_observations(LEO, GPS, T3, ATT3, B2, rng=2, phase_sigma_cycles=0.01, half_angle_deg=180.0)
_R, _V = LEO.state_ecef(T3)


def _fit_axes() -> np.ndarray:
    return tumble.propagate_axes(np.array([0.4, 1.1, 2.0, 0.001, -0.002, 0.0015]), np.arange(0.0, 60.0, 10.0))


# name -> a call taking rng=, and a function of its result that holds every draw (compared with ==)
STOCHASTIC: dict[str, tuple[Callable[..., Any], Callable[[Any], Any]]] = {
    "random_attitude": (lambda rng: sim.random_attitude(rng=rng, n=3), lambda r: r.as_quat()),
    "random_los": (lambda rng: sim.random_los(rng=rng, n_sat=4), lambda r: r),
    "simulate_array": (
        lambda rng: sim.simulate_array(
            GEOM,
            Rotation.identity(),
            sim.equilateral_triangle(1.0),
            GPS.wavelengths_m(),
            rng=rng,
            code_sigma_m=0.5,
            phase_sigma_m=0.002,
            doppler_sigma_hz=0.1,
        ),
        lambda m: np.concatenate(
            [m.pseudorange_m.ravel(), m.carrier_phase_cycles.ravel(), m.doppler_hz.ravel()]
        ),
    ),
    "simulate_spaceborne": (
        lambda rng: sim.simulate_spaceborne(_R, _V, T3, GPS, rng=rng),
        lambda m: np.nan_to_num(np.concatenate([m.pseudorange_m.ravel(), m.doppler_hz.ravel()])),
    ),
    "gyro_output": (
        lambda rng: scen.gyro_output(T3, ATT3, rng=rng, drift_rad_s=np.zeros(3), arw=1e-5, rrw=1e-7),
        lambda g: g.rates,
    ),
    "phase_observations": (
        lambda rng: scen.phase_observations(
            LEO, GPS, T3, ATT3, B2, rng=rng, phase_sigma_cycles=0.01, half_angle_deg=180.0
        ),
        lambda p: p.phase,
    ),
    "attitude_fixes": (
        lambda rng: scen.attitude_fixes(PHASES, ATT3, B2, rng=rng, phase_sigma_cycles=0.01),
        lambda f: f.rotation.as_quat(),
    ),
    "noisy_orbit": (
        lambda rng: determination.noisy_orbit(
            np.concatenate([_R[0], _V[0]]), T3, rng=rng, accel_psd_m2_s3=1e-6, step_s=10.0
        ),
        lambda x: x,
    ),
    "fit_rotation": (
        lambda rng: tumble.fit_rotation(
            np.arange(0.0, 60.0, 10.0), _fit_axes(), rng=rng, maxiter=2, popsize=2, polish=False
        ),
        lambda f: f.params,
    ),
}


def _draws(name: str, rng: Any) -> np.ndarray:
    call, held = STOCHASTIC[name]
    return np.asarray(held(call(rng)))


@pytest.mark.parametrize("name", list(STOCHASTIC))
def test_rng_int_is_reproducible_and_a_generator_is_read_as_default_rng(name: str) -> None:
    a, b = _draws(name, 7), _draws(name, 7)
    np.testing.assert_array_equal(a, b)
    assert not np.array_equal(a, _draws(name, 8))  # the draws do depend on the seed
    if name != "fit_rotation":  # scipy's documented reading of an int seed is default_rng(int)
        np.testing.assert_array_equal(a, _draws(name, np.random.default_rng(7)))
    gen = np.random.default_rng(7)
    first = _draws(name, gen)
    assert not np.array_equal(first, _draws(name, gen))  # a Generator is advanced, not copied
    assert _draws(name, None).shape == a.shape


@pytest.mark.parametrize("name", list(STOCHASTIC))
@pytest.mark.parametrize(
    "bad", [2.5, True, "7", np.random.RandomState(1)], ids=["float", "bool", "text", "RandomState"]
)
def test_rng_of_another_kind_is_refused_by_name(name: str, bad: Any) -> None:
    with pytest.raises(InvalidTypeError, match="rng"):
        _draws(name, bad)


# The documented exceptions keeping ``seed`` (docs/conventions.md, "Randomness").
SEED_KEPT = {
    "gnssatt.montecarlo.run",
    "gnssatt.montecarlo.trial_generators",
    "gnssatt.ambiguity.ratio_threshold_fixed_failure_rate",
    "gnssatt.ambiguity.ratio_test",
    "gnssatt.ambiguity.partial_fix",
}
# rng= tested elsewhere: each call writes RINEX files (tests/test_rinex_simulate_gnss.py,
# tests/test_sim_platforms.py, and below)
RNG_ELSEWHERE = {
    "gnssatt.sim.rinex_scenario.simulate_gnss_rinex",
    "gnssatt.sim.rinex_scenario.simulate_rinex_array",
    "gnssatt.sim.platforms.simulate_platform",
    "gnssatt.sim.platform_presets.car",
    "gnssatt.sim.platform_presets.ship",
    "gnssatt.sim.platform_presets.aircraft",
}


def _public_functions() -> dict[str, Any]:
    out = {}
    for info in pkgutil.walk_packages(gnssatt.__path__, "gnssatt."):
        if info.name.startswith("gnssatt.experiments") or info.name.rsplit(".", 1)[-1].startswith("_"):
            continue  # private modules; the experiments' trials take the Generator montecarlo.run hands them
        mod = importlib.import_module(info.name)
        for name, obj in vars(mod).items():
            if inspect.isfunction(obj) and obj.__module__ == mod.__name__ and not name.startswith("_"):
                out[f"{mod.__name__}.{name}"] = obj
    return out


def test_every_public_entry_taking_randomness_calls_it_rng() -> None:
    functions = _public_functions()
    takes = {
        n: set(inspect.signature(f).parameters) & {"rng", "seed", "random_state"}
        for n, f in functions.items()
    }
    assert {n for n, p in takes.items() if p - {"rng"}} == SEED_KEPT
    tested = {n for n, f in functions.items() if f.__name__ in STOCHASTIC}
    assert {n for n, p in takes.items() if "rng" in p} == tested | RNG_ELSEWHERE


def test_generator_intake() -> None:
    gen = np.random.default_rng(1)
    assert generator("rng", gen) is gen
    assert generator("rng", np.int64(3)).integers(1000) == np.random.default_rng(3).integers(1000)
    with pytest.raises(InvalidInputError, match="rng as a non-negative integer seed, got -1"):
        generator("rng", -1)


def test_simulate_rinex_array_reads_rng_as_default_rng(tmp_path: Any) -> None:
    def run(sub: str, **kw: Any) -> tuple[bytes, ...]:
        folder = tmp_path / sub
        folder.mkdir()
        ant = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0]]
        s = rinex_scenario.simulate_rinex_array(folder, ant, interval_s=1.0, n_sats=5, **kw)
        return tuple(p.read_bytes() for p in s.obs_paths)

    euler = np.array([[-40.0, 5.0, 3.0], [-41.0, 5.0, 3.0]])
    new = run("new", euler_gost_deg=euler, rng=3)
    assert run("generator", euler_gost_deg=euler, rng=np.random.default_rng(3)) == new
    assert run("other", euler_gost_deg=euler, rng=4) != new  # the draws do depend on the seed
