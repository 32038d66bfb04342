"""Orbit models of Dzhepe Ali: GLONASS ICD propagator against the ICD's worked example and closed forms,
its use by the engine's GLONASS ephemeris, the circular orbit, and TLE input (TEME -> Earth-fixed)."""

from __future__ import annotations

import numpy as np
import pytest

from gnssatt import _core, orbit, sim
from gnssatt.errors import InvalidInputError

# GLONASS CDMA ICD, general description (2016), appendix J: state at t_b = 11700 s (07.09.2012), km -> m.
# Quoted from the ICD in fenrir-naru/ninja-scan-light tool/test/test_GLONASS.cpp (ICD_CDMA_2016_Appendix_J);
# the same numbers are in gnsstk's GLOCNavEph_T.cpp and spanikp/GNSS-toolbox getSatPosGLOtest.m.
ICD_R0 = np.array([7003.008789, -12206.626953, 21280.765625]) * 1e3
ICD_V0 = np.array([0.7835417, 2.8042530, 1.3525150]) * 1e3
ICD_ACC_KM_S2 = np.array([0.0, 1.7e-9, -5.41e-9])
# Output of the simplified algorithm (J.2) at t_i = 12300 s.
ICD_R1 = np.array([7523.174853, -10506.962176, 21999.239866]) * 1e3
ICD_V1 = np.array([0.95012609, 2.85568710, 1.04068137]) * 1e3


def test_icd_appendix_j_example() -> None:
    # The published J.2 output is reproduced only without the luni-solar accelerations: with them
    # (1.7e-6 and -5.41e-6 m/s^2) the state moves by 0.5 a t^2 = 0.31 m and -0.97 m in y and z (checked
    # below), which the example's output does not contain (spanikp/GNSS-toolbox notes the same). The
    # numbers are printed to 1 mm and 1e-5 m/s; the ICD does not state its step or which Earth rate it
    # used (7.292115e-5 moves x by 2 mm here): 2 cm and 1e-4 m/s, 1e-9 of the orbit, allow for that.
    out = orbit.glonass_propagate(ICD_R0, ICD_V0, 600.0, step_s=10.0)
    np.testing.assert_allclose(out.position_m, ICD_R1, rtol=0, atol=0.02)
    np.testing.assert_allclose(out.velocity_m_s, ICD_V1, rtol=0, atol=1e-4)


def test_constant_acceleration_displaces_by_half_a_t_squared() -> None:
    acc = ICD_ACC_KM_S2 * 1e3
    plain = orbit.glonass_propagate(ICD_R0, ICD_V0, 600.0)
    pushed = orbit.glonass_propagate(ICD_R0, ICD_V0, 600.0, lunisolar_m_s2=acc)
    # Closed form for a constant push, to first order: 0.5 a t^2; the gravity gradient and Coriolis
    # coupling change it by O(omega t) ~ 5 % over 600 s.
    expected = 0.5 * acc * 600.0**2
    np.testing.assert_allclose(
        pushed.position_m - plain.position_m, expected, atol=0.05 * np.linalg.norm(expected)
    )


def _numpy_rk4(state: np.ndarray, dt: float, n: int, m: orbit.GlonassModel) -> np.ndarray:
    """Slow reference of the ICD equations (written out as in ICD ed. 5.1 A.3.1.2)."""

    def deriv(y: np.ndarray) -> np.ndarray:
        r, v = y[:3], y[3:]
        rn = np.linalg.norm(r)
        a = -m.gm_m3_s2 / rn**3
        b = 1.5 * m.j2 * m.gm_m3_s2 * m.equatorial_radius_m**2 / rn**5
        z2 = 5.0 * r[2] ** 2 / rn**2
        w = m.omega_rad_s
        acc = np.array(
            [
                (a - b * (1 - z2) + w * w) * r[0] + 2 * w * v[1],
                (a - b * (1 - z2) + w * w) * r[1] - 2 * w * v[0],
                (a - b * (3 - z2)) * r[2],
            ]
        ) + np.asarray(m.lunisolar_m_s2)
        return np.concatenate([v, acc])

    y = state.copy()
    h = dt / n
    for _ in range(n):
        k1 = deriv(y)
        k2 = deriv(y + 0.5 * h * k1)
        k3 = deriv(y + 0.5 * h * k2)
        k4 = deriv(y + h * k3)
        y = y + h / 6 * (k1 + 2 * k2 + 2 * k3 + k4)
    return y


def test_rust_propagator_matches_numpy_reference() -> None:
    m = orbit.GlonassModel(lunisolar_m_s2=(1e-6, -2e-6, 3e-6))
    out = orbit.glonass_propagate(ICD_R0, ICD_V0, 900.0, step_s=60.0, model=m)
    ref = _numpy_rk4(np.concatenate([ICD_R0, ICD_V0]), 900.0, 15, m)
    # Same arithmetic in another order: round-off only (1e-15 relative of 2.5e7 m over 15 steps).
    np.testing.assert_allclose(out.state, ref, rtol=1e-12, atol=1e-6)


def test_circular_period_and_jacobi_integral_without_j2() -> None:
    m = orbit.GlonassModel(j2=0.0)
    a = 7.0e6
    # A circular orbit in inertial axes, expressed in the rotating axes: v_rot = v_in - omega x r.
    v_in = np.sqrt(m.gm_m3_s2 / a) * np.array([0.0, 0.6, 0.8])
    r0 = np.array([a, 0.0, 0.0])
    v0 = v_in - np.cross([0, 0, m.omega_rad_s], r0)
    period = 2 * np.pi * np.sqrt(a**3 / m.gm_m3_s2)
    out = orbit.glonass_propagate(r0, v0, period, step_s=2.0, model=m)
    # After one period the satellite is back in inertial space; the Earth-fixed axes turned by omega T.
    ang = m.omega_rad_s * period
    back = np.array([np.cos(ang) * a, -np.sin(ang) * a, 0.0])
    # RK4 phase error per revolution 2 pi (n h)^4 / 120 ~ 1e-11 rad -> below 1 mm.
    np.testing.assert_allclose(out.position_m, back, atol=1e-3)

    def jacobi(r: np.ndarray, v: np.ndarray) -> float:
        return 0.5 * v @ v - 0.5 * m.omega_rad_s**2 * (r[0] ** 2 + r[1] ** 2) - m.gm_m3_s2 / np.linalg.norm(r)

    e0 = jacobi(ICD_R0, ICD_V0)
    later = orbit.glonass_propagate(ICD_R0, ICD_V0, 4 * 3600.0, step_s=30.0, model=m)
    assert abs(jacobi(later.position_m, later.velocity_m_s) / e0 - 1) < 1e-9


def test_stm_predicts_a_small_perturbation() -> None:
    base = orbit.glonass_propagate(ICD_R0, ICD_V0, 300.0)
    d = np.array([5.0, -3.0, 2.0, 0.01, 0.02, -0.005])
    moved = orbit.glonass_propagate(ICD_R0 + d[:3], ICD_V0 + d[3:], 300.0)
    # Linearisation error is second order: |d|^2 GM / r^3 t^2 ~ 1e-6 m here.
    np.testing.assert_allclose(moved.state - base.state, base.stm @ d, atol=1e-4)


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"duration_s": -10.0}, "duration_s"),
        ({"duration_s": 10.0, "step_s": 20.0}, "no longer than the duration"),
        ({"duration_s": 10.0, "step_s": 0.0}, "step > 0"),
        ({"duration_s": float("nan")}, "finite duration_s"),
    ],
)
def test_propagate_bad_input(kwargs: dict[str, float], match: str) -> None:
    with pytest.raises(InvalidInputError, match=match):
        orbit.glonass_propagate(ICD_R0, ICD_V0, **kwargs)


def test_propagate_bad_state() -> None:
    with pytest.raises(InvalidInputError, match="non-finite"):
        orbit.glonass_propagate([np.nan, 0, 0], ICD_V0, 10.0)
    with pytest.raises(InvalidInputError, match=r"shape \(3,\)"):
        orbit.glonass_propagate(ICD_R0[:2], ICD_V0, 10.0)
    with pytest.raises(InvalidInputError, match="away from the Earth's centre"):
        orbit.glonass_propagate([0, 0, 0], ICD_V0, 10.0)


def _glonass_record(state: np.ndarray, acc: np.ndarray, tb_ns: int) -> dict[str, np.ndarray]:
    """One healthy GLONASS record as the engine's NavInput arrays."""
    return {
        "sat": np.array(["R01"]),
        "tb_gpst_ns": np.array([tb_ns], dtype=np.int64),
        "clock_bias_s": np.zeros(1),
        "gamma_n": np.zeros(1),
        "position_m": state[None, :3].copy(),
        "velocity_m_s": state[None, 3:].copy(),
        "acceleration_m_s2": acc[None, :].copy(),
        "channel": np.zeros(1, dtype=np.int64),
        "health": np.zeros(1),
    }


@pytest.mark.parametrize("offset_s", [600.0, -600.0, 37.5])
def test_engine_glonass_ephemeris_matches_the_numpy_reference(offset_s: float) -> None:
    acc = np.array([1e-6, 2e-6, -3e-6])
    tb = 1_000_000_000_000_000
    record = _glonass_record(np.concatenate([ICD_R0, ICD_V0]), acc, tb)
    states = _core.gnss_satellite_states(
        _core.Navigation(glonass=record), ["R01"], np.array([tb]), offset_s=np.array([offset_s])
    )
    pos, valid = states.position_m, states.valid
    assert valid.all()
    m = orbit.GlonassModel(
        gm_m3_s2=398600.4418e9, j2=1.0826257e-3, equatorial_radius_m=6378136.0, omega_rad_s=7.292115e-5,
        lunisolar_m_s2=tuple(acc),
    )  # fmt: skip
    n = int(np.ceil(abs(offset_s) / 60.0))
    ref = _numpy_rk4(np.concatenate([ICD_R0, ICD_V0]), offset_s, n, m)
    np.testing.assert_allclose(pos[0], ref[:3], rtol=0, atol=1e-6)


def test_circular_orbit_matches_the_simulator() -> None:
    o = orbit.CircularOrbit(6_978_137.0, np.radians(97.8), 0.4, 1.2)
    t = np.linspace(0.0, o.period_s, 7)
    r, v = o.state_ecef(t, theta0_rad=0.3)
    kep = sim.KeplerOrbits.circular([o.radius_m], [o.inclination_rad], [o.raan_rad], [o.arg_latitude0_rad])
    r_eci, v_eci = kep.state_eci(t)
    r_ref, v_ref = sim.eci_to_ecef(r_eci[:, 0], v_eci[:, 0], t, 0.3)
    np.testing.assert_allclose(r, r_ref, atol=1e-6)
    np.testing.assert_allclose(v, v_ref, atol=1e-9)
    np.testing.assert_allclose(r[-1], sim.eci_to_ecef(r_eci[0, 0], v_eci[0, 0], t[-1], 0.3)[0], atol=1e-5)


def test_teme_to_ecef_vallado_example() -> None:
    # Vallado, Fundamentals of Astrodynamics, example 3-15 / AAS 06-675: TEME state at 2004-04-06
    # 07:51:28.386009 UTC, UT1 - UTC = -0.4399619 s; PEF (Earth-fixed without polar motion) result, km.
    # Quoted as published in several test suites (e.g. the SatelliteToolbox.jl TEME tests).
    r_teme = np.array([5094.18016210, 6127.64465950, 6380.34453270]) * 1e3
    v_teme = np.array([-4.7461314870, 0.7858180410, 5.5319312880]) * 1e3
    r_pef = np.array([-1033.47503130, 7901.30558560, 6380.34453270]) * 1e3
    v_pef = np.array([-3.2256327470, -2.8724425110, 5.5319312880]) * 1e3
    day = (7 * 3600 + 51 * 60 + 28.386009 - 0.4399619) / 86400.0
    jd_ut1 = 2453101.5 + day
    r, v = orbit.teme_to_ecef(r_teme, v_teme, jd_ut1)
    # Published to 0.1 mm; the Julian date in one float carries 40 us (2 cm at 465 m/s): 5 cm, 1e-4 m/s
    # (the book's Earth rate includes the length-of-day change, 1e-5 m/s here).
    np.testing.assert_allclose(r, r_pef, atol=0.05)
    np.testing.assert_allclose(v, v_pef, atol=1e-4)


def test_tle_states_vanguard() -> None:
    pytest.importorskip("sgp4")
    # Satellite 00005 of the SGP4 verification set (Vallado et al. 2006, tcppver.out): TEME at 360 min.
    line1 = "1 00005U 58002B   00179.78495062  .00000023  00000-0  28098-4 0  4753"
    line2 = "2 00005  34.2682 348.7242 1859667 331.7664  19.3264 10.82419157413667"
    r_teme = np.array([-7154.03120202, -3783.17682504, -3536.19412294]) * 1e3
    v_teme = np.array([4.741887409, -4.151817765, -2.093935425]) * 1e3
    epoch = np.datetime64("2000-06-27T18:50:19.733568")  # day 179.78495062 of 2000
    t = epoch + np.timedelta64(360 * 60, "s")
    r, v = orbit.tle_states(line1, line2, np.array([t]))
    jd = 2451722.5 + (18 * 3600 + 50 * 60 + 19.733568 + 360 * 60) / 86400.0
    r_ref, v_ref = orbit.teme_to_ecef(r_teme, v_teme, jd)
    # Published TEME to 0.01 mm; the TLE epoch written in days to 1e-8 d carries 0.4 ms (3 m at 7 km/s).
    np.testing.assert_allclose(r[0], r_ref, atol=5.0)
    np.testing.assert_allclose(v[0], v_ref, atol=5e-3)


def test_tle_bad_input() -> None:
    pytest.importorskip("sgp4")
    with pytest.raises(TypeError, match="datetime64"):
        orbit.tle_states("1 x", "2 y", np.array([0.0]))
