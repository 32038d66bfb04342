"""The typed Rust-Python boundary (issue 19): every binding returns a frozen result object instead of a tuple
or dict, and the gyro-GNSS filter takes a frozen keyword-only options object. Checked here: results and
options are read-only, their reprs list every field on one line, keyword-only options refuse positionals and
unknown names with a TypeError, hostile settings reach Python as ``InvalidInputError`` (never a panic), and
the fields hold the right numbers on fixed cases against closed forms, brute force and scipy."""

from __future__ import annotations

import itertools
import types
from collections.abc import Callable

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from gnssatt import _core
from gnssatt.errors import InvalidInputError
from gnssatt.orbit import GlonassModel

RNG_SEED = 19
ICD_STATE = np.array([7003.008789e3, -12206.626953e3, 21280.765625e3, 0.7835417e3, 2.8042530e3, 1.3525150e3])
A3 = np.array([0.31, -1.72, 2.45])
Q3 = np.array([[0.09, 0.05, 0.02], [0.05, 0.08, 0.03], [0.02, 0.03, 0.07]])
L1 = 0.19029367


def _gyro_options(**changes: object) -> _core.GyroGnssOptions:
    settings: dict[str, object] = {
        "arw": 1e-5,
        "rrw": 0.0,
        "baselines": np.array([[1.0, 0.0, 0.0]]),
        "phase_sigma": 0.01,
        "fix_enabled": False,
        "ratio_threshold": 3.0,
        "min_success_rate": 0.999,
        "slip_threshold": 30.0,
        "known_ambiguities": False,
        "output_every": 1,
    }
    return _core.GyroGnssOptions(**{**settings, **changes})


def _gyro_run(t: np.ndarray, rates: np.ndarray, options: _core.GyroGnssOptions) -> _core.GyroGnssRun:
    """The filter without measurements (it propagates the gyro only), starting at the identity."""
    return _core.gyro_gnss_filter(
        t,
        rates,
        q0=np.array([0.0, 0.0, 0.0, 1.0]),
        drift0=np.zeros(3),
        p0=np.eye(6) * 1e-4,
        options=options,
        fix_t=np.zeros(0),
        fix_q=np.zeros((0, 4)),
        fix_cov=np.zeros((0, 3, 3)),
        epoch_t=np.zeros(0),
        phase_epoch=np.zeros(0, np.int64),
        phase_track=np.zeros(0, np.int64),
        phase_los=np.zeros((0, 3)),
        phase_wavelength=np.zeros(0),
        phase=np.zeros((0, 1)),
    )


def _ml_inputs() -> tuple[np.ndarray, ...]:
    """Noise-free phases of two baselines from 6 satellites at a known attitude, shapes of the binding."""
    rng = np.random.default_rng(RNG_SEED)
    los = rng.normal(size=(6, 3))
    los[:, 2] = np.abs(los[:, 2]) + 0.3
    los /= np.linalg.norm(los, axis=1, keepdims=True)
    b = np.array([[1.0, 0.0, 0.0], [0.0, 0.8, 0.0]])
    phase = 2 * np.pi * ((b @ los.T / L1) % 1.0)
    return phase[None], los[None], np.full((1, 6), L1), b


def _series_inputs() -> tuple[np.ndarray, ...]:
    p, s, w, b = _ml_inputs()
    return np.repeat(p, 2, axis=0), np.repeat(s, 2, axis=0), np.repeat(w, 2, axis=0), b


# One circular GPS record (e = 0, no harmonic terms, no clock drift): the orbit is a circle of radius
# sqrt_a^2 whatever the time, the clock af0 (no relativistic term at e = 0), valid for fit_interval_h / 2
# either side of toe; at toe the argument of latitude m0 + omega is 0, so the satellite is over the equator
# (where geodetic and geocentric vertical agree).
TOE_NS = 1_293_494_400 * 10**9  # 2021-01-01T00:00:00 GPST, ns since the GPS epoch
SQRT_A = 5153.7
AF0 = 1e-4
FIT_H = 4.0


def _gps_record() -> dict[str, np.ndarray]:
    rec = {
        "sat": np.array(["G07"]),
        "toc_gpst_ns": np.array([TOE_NS], dtype=np.int64),
        "toe_gpst_ns": np.array([TOE_NS], dtype=np.int64),
        "af": np.array([[AF0, 0.0, 0.0]]),
        "tgd_s": np.array([[0.0, np.nan]]),
    }
    scalars = {
        "crs": 0.0, "delta_n": 0.0, "m0": 0.3, "cuc": 0.0, "e": 0.0, "cus": 0.0, "sqrt_a": SQRT_A,
        "cic": 0.0, "omega0": 1.1, "cis": 0.0, "i0": 0.96, "crc": 0.0, "omega": -0.3, "omega_dot": 0.0,
        "idot": 0.0, "health": 0.0, "iode": 1.0, "accuracy_m": 2.0, "fit_interval_h": FIT_H,
        "data_source": np.nan,
    }  # fmt: skip
    rec.update({k: np.array([v]) for k, v in scalars.items()})
    return rec


def _satellite_states() -> _core.SatelliteStates:
    """G07 at toe (valid) and 1 s past the end of its fit interval (not valid)."""
    late = TOE_NS + int(FIT_H / 2 * 3600 + 1) * 10**9
    t = np.array([TOE_NS, late])
    return _core.gnss_satellite_states(_core.Navigation(kepler=_gps_record()), ["G07", "G07"], t)


def _transmit_states() -> _core.TransmitStates:
    """G07 received at toe by a receiver on the equator right under it, and a satellite the navigation
    data do not have (G08)."""
    at_toe = _satellite_states().position_m[0]
    receiver = 6.371e6 * at_toe / np.linalg.norm(at_toe)
    return _core.gnss_transmit_states(
        _core.Navigation(kepler=_gps_record()), ["G07", "G08"], np.array([TOE_NS, TOE_NS]),
        np.tile(receiver, (2, 1)), np.zeros(2),
    )  # fmt: skip


def _single_points() -> _core.SinglePoints:
    """Two epochs without any code: no solution, so NaN rows and no satellite used."""
    return _core.gnss_single_point(
        _core.Navigation(kepler=_gps_record()), np.array([TOE_NS, TOE_NS + 10**9]), ["G07"], np.array([99]),
        np.full((2, 1, 3), np.nan),
    )  # fmt: skip


# A fixed case of every binding with a typed result: (class, call).
CASES: dict[str, Callable[[], object]] = {
    "IlsSolution": lambda: _core.lambda_ils(A3, Q3, 3),
    "Decorrelation": lambda: _core.lambda_decorrelate(Q3),
    "RatioTest": lambda: _core.lambda_ratio_test(
        A3, Q3, threshold=None, failure_rate=None, samples=1000, seed=0
    ),
    "PartialFix": lambda: _core.lambda_partial_fix(
        A3, Q3, threshold=None, failure_rate=None, samples=1000, seed=0, min_success_rate=0.9
    ),
    "MatrixAttitude": lambda: _core.matrix_attitude(np.eye(3), np.eye(3), np.eye(3), "svd"),
    # 0.09 rad: just finer than half the main lobe of the 1 m baseline (0.095 rad), 1.7e5 grid cells
    "MlEstimate": lambda: _core.ml_search(
        *_ml_inputs(),
        statistic="mean",
        step_rad=0.09,
        window_rad=None,
        search="auto",
        refine="newton",
        two_dimensional=False,
    ),
    "BnbStats": lambda: _core.bnb_stats(*_ml_inputs(), statistic="mean", step_rad=0.09, window_rad=None),
    "LikelihoodGrid": lambda: _core.likelihood_grid(
        *_ml_inputs(),
        statistic="mean",
        step_rad=0.05,
        window_rad=[[0.0, 0.3], [0.0, 0.2], [0.0, 0.1]],
        two_dimensional=False,
    ),
    "MlSeries": lambda: _core.ml_attitude_series(*_series_inputs(), step_rad=None, window_rad=None),
    "WahbaBatch": lambda: _core.wahba_batch(np.eye(3), np.eye(3), np.ones(3), 3, "svd"),
    "TriadBatch": lambda: _core.triad_batch(*(np.eye(3)[None, k] for k in (0, 1, 0, 1))),
    "YawBatch": lambda: _core.yaw_batch(np.eye(3)[:1], np.eye(3)[:1], np.zeros(1), np.zeros(1)),
    "StateWithStm": lambda: _core.glonass_propagate(ICD_STATE, 60.0, GlonassModel()._kwargs(), step_s=10.0),
    "OrbitStates": lambda: _core.circular_orbit_ecef(
        [7e6, 1.0, 0.3, 0.2, 3.986004418e14], np.array([0.0, 60.0]), theta0_rad=0.0, omega_rad_s=7.2921e-5
    ),
    "OrbitFilterRun": lambda: _core.orbit_filter_loose(
        np.array([0.0, 30.0]),
        ICD_STATE,
        np.eye(6) * 100.0,
        np.tile(ICD_STATE[:3], (2, 1)),
        np.tile(ICD_STATE[3:], (2, 1)),
        np.tile(np.eye(6), (2, 1, 1)),
        np.array([True, False]),
        model=GlonassModel()._kwargs(),
        accel_psd_m2_s3=1e-8,
        step_s=10.0,
    ),
    "GyroGnssRun": lambda: _gyro_run(np.array([0.0, 0.1, 0.2]), np.zeros((3, 3)), _gyro_options()),
    "SatelliteStates": _satellite_states,
    "TransmitStates": _transmit_states,
    "SinglePoints": _single_points,
}


def _fields(obj: object) -> list[str]:
    """The attributes a result type exposes: getters, and members (pyo3 makes a ``Py`` field a member)."""
    kinds = (types.GetSetDescriptorType, types.MemberDescriptorType)
    return [n for n, v in vars(type(obj)).items() if isinstance(v, kinds) and not n.startswith("__")]


@pytest.mark.parametrize("name", sorted(CASES))
def test_results_are_typed_and_frozen(name: str) -> None:
    out = CASES[name]()
    assert type(out).__name__ == name and type(out).__module__ == "gnssatt._core"
    fields = _fields(out)
    assert fields, f"{name} exposes no field"
    for field in fields:
        with pytest.raises(AttributeError):
            setattr(out, field, getattr(out, field))
    with pytest.raises(AttributeError):
        out.extra = 1  # type: ignore[attr-defined]
    with pytest.raises(TypeError):
        type(out)()  # results are made by the bindings only


@pytest.mark.parametrize("name", sorted(CASES))
def test_result_repr_lists_every_field_on_one_line(name: str) -> None:
    out = CASES[name]()
    shown = repr(out)
    assert shown.startswith(f"{name}(") and shown.endswith(")") and "\n" not in shown
    for field in _fields(out):
        value = getattr(out, field)
        if isinstance(value, np.ndarray):
            dims = ", ".join(str(d) for d in value.shape) + ("," if value.ndim == 1 else "")
            assert f"{field}=array(shape=({dims}), dtype={value.dtype})" in shown
        else:
            assert f"{field}={value!r}" in shown


def test_gyro_options_are_keyword_only_and_frozen() -> None:
    with pytest.raises(TypeError, match="positional"):
        _core.GyroGnssOptions(1e-5)  # type: ignore[misc]
    with pytest.raises(TypeError, match="ratio_treshold"):
        _gyro_options(ratio_treshold=3.0)
    full = {
        "arw": 1e-5,
        "rrw": 0.0,
        "baselines": np.eye(3)[:1],
        "phase_sigma": 0.01,
        "fix_enabled": False,
        "ratio_threshold": 3.0,
        "min_success_rate": 0.999,
        "slip_threshold": 30.0,
        "known_ambiguities": False,
    }
    with pytest.raises(TypeError, match="output_every"):
        _core.GyroGnssOptions(**full)  # type: ignore[call-arg]
    options = _gyro_options(sensitivity=(1e-3, 2e-3))
    with pytest.raises(AttributeError):
        options.arw = 1.0  # type: ignore[attr-defined]
    shown = repr(options)
    assert shown.startswith("GyroGnssOptions(") and "ratio_threshold: 3.0" in shown
    assert "misalignment_sigma: 0.001" in shown and "baseline_sigma: 0.002" in shown


def test_gyro_filter_takes_its_arrays_by_name() -> None:
    t, rates = np.array([0.0, 0.1]), np.zeros((2, 3))
    with pytest.raises(TypeError, match="positional"):
        _core.gyro_gnss_filter(t, rates, np.array([0.0, 0.0, 0.0, 1.0]))  # type: ignore[misc]


@pytest.mark.parametrize(
    ("change", "named"),
    [
        ({"baselines": np.ones((2, 2))}, "baselines"),
        ({"baselines": np.array([[np.nan, 0.0, 0.0]])}, "baselines"),
        ({"arw": -1.0}, "gyro noise"),
        ({"rrw": np.inf}, "gyro noise"),
        ({"phase_sigma": 0.0}, "phase_sigma"),
        ({"ratio_threshold": 0.5}, "ratio_threshold"),
        ({"min_success_rate": np.nan}, "min_success_rate"),
        ({"slip_threshold": np.nan}, "slip_threshold"),
        ({"output_every": 0}, "output_every"),
        ({"misalignment_sigma": -1.0}, "misalignment_sigma"),
        ({"sensitivity": (np.nan, 0.0)}, "sensitivity"),
    ],
)
def test_hostile_gyro_settings_are_refused_by_name(change: dict[str, object], named: str) -> None:
    # the options are typed at construction and checked by the core when the filter starts: either way an
    # InvalidInputError naming the setting, never a panic (InternalError)
    t, rates = np.array([0.0, 0.1, 0.2]), np.zeros((3, 3))
    with pytest.raises(InvalidInputError, match=named):
        _gyro_run(t, rates, _gyro_options(**change))


def test_gyro_run_propagates_a_constant_rate_exactly() -> None:
    # no measurement: the filter's attitude is the exact rotation exp(omega t), scipy's closed form
    omega = np.array([0.02, -0.01, 0.03])
    t = np.linspace(0.0, 10.0, 101)
    run = _gyro_run(t, np.tile(omega, (len(t), 1)), _gyro_options(output_every=10))
    np.testing.assert_array_equal(run.t, t[::10])
    expected = Rotation.from_rotvec(run.t[:, None] * omega)
    assert np.max((Rotation.from_quat(run.quaternion).inv() * expected).magnitude()) < 1e-12
    assert run.covariance.shape == (11, 6, 6) and run.n_float.shape == (11,)
    assert run.fixes == [] and run.slips.shape == (0, 3) and run.nis.shape == (0, 3)


def test_ils_solution_is_the_brute_force_minimum() -> None:
    out = _core.lambda_ils(A3, Q3, 2)
    qi = np.linalg.inv(Q3)
    grid = np.array(list(itertools.product(*(range(int(np.floor(a)) - 3, int(np.floor(a)) + 5) for a in A3))))
    d = grid - A3
    norms = np.einsum("ki,ij,kj->k", d, qi, d)
    order = np.argsort(norms)[:2]
    np.testing.assert_array_equal(out.fixed, grid[order])
    np.testing.assert_allclose(out.squared_norms, norms[order], rtol=1e-12)
    assert out.nodes_visited > 0


def test_decorrelation_and_ratio_test_fields() -> None:
    dec = _core.lambda_decorrelate(Q3)
    assert abs(round(np.linalg.det(dec.z))) == 1
    np.testing.assert_allclose(dec.z.T @ Q3 @ dec.z, dec.l.T @ np.diag(dec.d) @ dec.l, rtol=1e-12, atol=1e-15)
    test = _core.lambda_ratio_test(A3, Q3, threshold=2.0, failure_rate=None, samples=10, seed=0)
    best = _core.lambda_ils(A3, Q3, 2)
    np.testing.assert_array_equal(test.fixed, best.fixed[0])
    assert test.ratio == pytest.approx(best.squared_norms[1] / best.squared_norms[0], rel=1e-12)
    assert test.threshold == 2.0 and test.accepted == (test.ratio >= 2.0)


def test_matrix_attitude_fields_on_noise_free_ranges() -> None:
    rot = Rotation.from_euler("ZYX", [40.0, -10.0, 5.0], degrees=True).as_matrix()
    b = np.array([[1.0, 0.0, 0.0], [0.0, 1.2, 0.0], [0.1, 0.2, 0.9]])
    s = np.array([[0.3, 0.2, 1.0], [-0.7, 0.1, 0.5], [0.2, -0.8, 0.4], [0.5, 0.5, 0.7]])
    s /= np.linalg.norm(s, axis=1, keepdims=True)
    out = _core.matrix_attitude(b, s, b @ rot.T @ s.T, "svd")
    np.testing.assert_allclose(out.dcm_ref_from_body, rot, atol=1e-12)
    np.testing.assert_allclose(out.raw_body_from_ref, rot.T, atol=1e-12)
    assert out.residual_rms_m < 1e-12


def test_triad_and_circular_orbit_fields_against_closed_forms() -> None:
    rot = Rotation.from_euler("XYZ", [10.0, 20.0, 30.0], degrees=True)
    b1, b2 = np.array([[1.0, 0.0, 0.0]]), np.array([[0.0, 1.0, 0.0]])
    out = _core.triad_batch(b1, b2, rot.apply(b1), rot.apply(b2))
    assert (Rotation.from_quat(out.quat_ref_from_body[0]).inv() * rot).magnitude() < 1e-12
    np.testing.assert_allclose([out.sin_angle_body[0], out.sin_angle_ref[0]], 1.0, rtol=1e-12)
    orbit = _core.circular_orbit_ecef(
        [7e6, 1.0, 0.3, 0.2, 3.986004418e14], np.linspace(0, 5e3, 6), theta0_rad=0.0, omega_rad_s=0.0
    )
    # no Earth rotation: the Earth-fixed state is the inertial one, radius r and speed sqrt(GM / r)
    np.testing.assert_allclose(np.linalg.norm(orbit.position_m, axis=1), 7e6, rtol=1e-12)
    np.testing.assert_allclose(np.linalg.norm(orbit.velocity_m_s, axis=1), np.sqrt(3.986004418e14 / 7e6))


def test_orbit_filter_run_reports_no_update_without_a_fix() -> None:
    out = CASES["OrbitFilterRun"]()
    assert isinstance(out, _core.OrbitFilterRun)
    assert out.states.shape == (2, 6) and out.covariances.shape == (2, 6, 6)
    assert out.dof[1] == 0 and out.dof[0] > 0


def test_satellite_states_fields_on_a_circular_orbit() -> None:
    out = _satellite_states()
    assert out.position_m.shape == (2, 3) and out.clock_s.shape == (2,) and out.valid.dtype == np.bool_
    assert list(out.valid) == [True, False]
    assert np.linalg.norm(out.position_m[0]) == pytest.approx(SQRT_A**2, rel=1e-12)
    assert abs(out.position_m[0, 2]) < 1e-6  # over the equator
    assert out.clock_s[0] == pytest.approx(AF0, abs=1e-18)
    assert np.isnan(out.position_m[1]).all() and np.isnan(out.clock_s[1])


def test_transmit_states_fields_for_a_receiver_under_the_satellite() -> None:
    out = _transmit_states()
    assert list(out.valid) == [True, False]
    # the circle keeps its radius through light time and the Earth's turn (a rotation about z)
    assert np.linalg.norm(out.position_m[0]) == pytest.approx(SQRT_A**2, rel=1e-12)
    # straight overhead at the equator, up to the satellite's motion in the ~67 ms of light time (3.9 km/s
    # over 20,000 km: ~1.3e-5 rad)
    assert abs(out.elevation_rad[0] - np.pi / 2) < 1e-4
    assert out.clock_s[0] == pytest.approx(AF0, abs=1e-18)
    for field in (out.clock_s, out.elevation_rad, out.azimuth_rad):
        assert np.isnan(field[1])
    assert np.isnan(out.position_m[1]).all()


def test_single_points_without_code_are_empty_rows() -> None:
    out = _single_points()
    assert out.position_m.shape == (2, 3) and out.clock_s.shape == (2, 5)
    assert out.satellites.dtype == np.int64 and list(out.satellites) == [0, 0]
    assert np.isnan(out.position_m).all() and np.isnan(out.clock_s).all()
    assert np.isnan(out.residual_rms_m).all()


def test_navigation_is_keyword_only_frozen_and_counts_its_records() -> None:
    """The navigation records cross once, as a frozen keyword-only object that every GNSS binding takes."""
    with pytest.raises(TypeError, match="positional"):
        _core.Navigation(_gps_record())  # type: ignore[misc]
    with pytest.raises(TypeError, match="keplr"):
        _core.Navigation(keplr=_gps_record())  # type: ignore[call-arg]
    coefficients = np.arange(8.0) * 1e-8
    nav = _core.Navigation(kepler=_gps_record(), klobuchar=coefficients, leap_seconds=18)
    assert type(nav).__module__ == "gnssatt._core"
    assert (nav.kepler_records, nav.glonass_records, nav.leap_seconds) == (1, 0, 18)
    np.testing.assert_array_equal(nav.klobuchar, coefficients)
    for field in ("kepler_records", "glonass_records", "klobuchar", "leap_seconds"):
        with pytest.raises(AttributeError):
            setattr(nav, field, None)
    with pytest.raises(AttributeError):
        nav.extra = 1  # type: ignore[attr-defined]
    assert repr(nav) == (
        "Navigation(kepler_records=1, glonass_records=0, klobuchar=array(shape=(8,), dtype=float64), "
        "leap_seconds=18)"
    )
    empty = _core.Navigation()
    assert repr(empty) == "Navigation(kepler_records=0, glonass_records=0, klobuchar=None, leap_seconds=None)"
    # an empty table and a missing one are the same: no record of that kind
    assert _core.Navigation(kepler={}, glonass={}).kepler_records == 0


def test_navigation_refuses_malformed_columns_by_name() -> None:
    rec = _gps_record()
    with pytest.raises(InvalidInputError, match=r"expected klobuchar of shape \(8,\)"):
        _core.Navigation(kepler=rec, klobuchar=np.zeros(7))
    rec["af"] = np.zeros((1, 2))
    with pytest.raises(InvalidInputError, match=r'kepler\["af"\]'):
        _core.Navigation(kepler=rec)
    one = np.zeros(1)
    glonass = {"sat": np.array(["G07"]), "tb_gpst_ns": np.array([TOE_NS]), "channel": np.array([1])}
    glonass |= {k: one for k in ("clock_bias_s", "gamma_n", "health")}
    glonass |= {k: np.zeros((1, 3)) for k in ("position_m", "velocity_m_s", "acceleration_m_s2")}
    with pytest.raises(InvalidInputError, match=r'expected glonass\["sat"\] of GLONASS, row 0 is G07'):
        _core.Navigation(glonass=glonass)
    glonass["sat"] = np.array(["R07"])
    assert _core.Navigation(glonass=glonass).glonass_records == 1
