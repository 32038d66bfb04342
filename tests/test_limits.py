"""Work limits, divergence and Ctrl-C of the Rust propagators and filters (issue 15, part B).

Each long computation called with an absurd size must be refused before it starts, with a
``WorkLimitError`` naming the parameter; a propagation that would produce NaN must raise instead; a long
call must stop on SIGINT. The limits are enforced in Rust, so some calls go to ``gnssatt._core`` directly:
they must hold whatever the Python layer passes. Nothing here asserts speed: a refusal is shown to come
before the work by the memory the call allocates.
"""

from __future__ import annotations

import signal
import subprocess
import sys
import textwrap
import time

import numpy as np
import pytest
from allocation import traced_peak

from gnssatt import _core, orbit
from gnssatt.attitude import dynamics as tumble
from gnssatt.attitude.gyro_gnss import gyro_propagate
from gnssatt.errors import (
    ConvergenceError,
    DegenerateGeometryError,
    InvalidInputError,
    WorkLimitError,
)
from gnssatt.orbit import GlonassModel

# The GLONASS ICD appendix J state, m and m/s.
ICD_R0 = np.array([7003.008789e3, -12206.626953e3, 21280.765625e3])
ICD_V0 = np.array([0.7835417e3, 2.8042530e3, 1.3525150e3])
TUMBLING = np.array([0.7, 1.1, -2.0, 0.01, -0.01, 0.01])
ACCEL_PSD_M2_S3 = 1e-8


def _gyro_filter(gyro_t: np.ndarray, *, p0: np.ndarray | None = None, phases: int = 0) -> _core.GyroGnssRun:
    """The binding of ``gyro_gnss_filter`` with one baseline, no attitude fix and, when ``phases`` > 0,
    one phase epoch at ``gyro_t[0] + 0.5`` with that many satellites."""
    n = len(gyro_t)
    options = _core.GyroGnssOptions(
        arw=1e-5,
        rrw=0.0,
        baselines=np.array([[1.0, 0.0, 0.0]]),
        phase_sigma=0.01,
        fix_enabled=False,
        ratio_threshold=3.0,
        min_success_rate=0.999,
        slip_threshold=30.0,
        known_ambiguities=False,
        output_every=1,
    )
    return _core.gyro_gnss_filter(
        gyro_t,
        np.zeros((n, 3)),
        q0=np.array([0.0, 0.0, 0.0, 1.0]),
        drift0=np.zeros(3),
        p0=np.eye(6) * 1e-4 if p0 is None else p0,
        options=options,
        fix_t=np.zeros(0),
        fix_q=np.zeros((0, 4)),
        fix_cov=np.zeros((0, 3, 3)),
        epoch_t=np.array([gyro_t[0] + 0.5]) if phases else np.zeros(0),
        phase_epoch=np.zeros(phases, np.int64),
        phase_track=np.arange(phases, dtype=np.int64),
        phase_los=np.tile([0.0, 0.0, 1.0], (phases, 1)),
        phase_wavelength=np.full(phases, 0.19),
        phase=np.zeros((phases, 1)),
    )


def _loose_filter(times_s: np.ndarray, step_s: float) -> _core.OrbitFilterRun:
    n = len(times_s)
    x0 = np.concatenate([ICD_R0, ICD_V0])
    valid = np.zeros(n, bool)
    valid[0] = True
    return _core.orbit_filter_loose(
        times_s,
        x0,
        np.eye(6) * 100.0,
        np.tile(ICD_R0, (n, 1)),
        np.tile(ICD_V0, (n, 1)),
        np.tile(np.eye(6), (n, 1, 1)),
        valid,
        model=GlonassModel()._kwargs(),
        accel_psd_m2_s3=ACCEL_PSD_M2_S3,
        step_s=step_s,
    )


def _tight_filter(n_sat: int) -> _core.OrbitFilterRun:
    return _core.orbit_filter_tight(
        np.array([0.0]),
        np.concatenate([ICD_R0, ICD_V0]),
        np.eye(6) * 100.0,
        np.zeros((1, n_sat, 3)),
        np.zeros((1, n_sat, 3)),
        np.zeros((1, n_sat)),
        np.zeros((1, n_sat)),
        np.zeros((1, n_sat), bool),
        np.full(n_sat, 0.19),
        np.zeros(n_sat, np.uint32),
        code_sigma_m=1.0,
        doppler_sigma_hz=0.0,
        model=GlonassModel()._kwargs(),
        accel_psd_m2_s3=ACCEL_PSD_M2_S3,
        step_s=10.0,
    )


ABSURD = {
    # 1 s in steps of 1e-300 s: 1e300 RK4 steps (ran forever before).
    "tumble step_s": (lambda: tumble.propagate_axes(TUMBLING, [1.0], step_s=1e-300), "step_s"),
    # 1e4 initial states over 1e5 s: 1e9 steps over the batch.
    "tumble batch": (
        lambda: tumble.axis_cost(np.tile(TUMBLING, (10_000, 1)), [1e5], [[1.0, 0.0, 0.0]]),
        "step_s",
    ),
    # 1e5 states x 1e3 times x 3 axes: 3e8 output values.
    "tumble outputs": (lambda: tumble.propagate_axes(np.tile(TUMBLING, (100_000, 1)), np.zeros(1000)), "t"),
    # 1e9 steps of 1 us.
    "glonass step_s": (lambda: orbit.glonass_propagate(ICD_R0, ICD_V0, 1000.0, step_s=1e-6), "step_s"),
    # Two epochs 1e4 s apart predicted in 1 ms steps: 1e7 prediction steps.
    "orbit filter step_s": (lambda: _loose_filter(np.array([0.0, 1e4]), 1e-3), "step_s"),
    # 2e7 + 1 gyro samples as zero-stride views (the check comes before the samples are copied: 640 MB).
    "gyro samples": (
        lambda: gyro_propagate(
            [0.0, 0.0, 0.0, 1.0], np.broadcast_to(0.0, (20_000_001,)), np.broadcast_to(0.0, (20_000_001, 3))
        ),
        "t",
    ),
    # 5e5 + 1 samples through the filter.
    "gyro filter samples": (lambda: _gyro_filter(np.zeros(500_001)), "gyro_t"),
    # 1025 satellites: an update cubic in them.
    "orbit filter satellites": (lambda: _tight_filter(1025), "data"),
    # 600 satellites on one baseline: 606 error states.
    "gyro filter states": (lambda: _gyro_filter(np.array([0.0, 1.0]), phases=600), "phases"),
}


@pytest.mark.slow
@pytest.mark.parametrize("name", list(ABSURD))
def test_absurd_work_is_refused_before_it_starts(name: str) -> None:
    call, parameter = ABSURD[name]
    # A refusal is a check, not work: counted by the memory the call allocates (tracemalloc sees numpy's
    # buffers), never timed. Every call here would allocate hundreds of MB doing the work (the outputs,
    # or a copy of its inputs); the inputs themselves are small or zero-stride views.
    with traced_peak() as peak, pytest.raises(WorkLimitError, match=parameter) as info:
        call()
    assert isinstance(info.value, InvalidInputError)
    assert "limit" in str(info.value)
    assert peak.bytes < 64_000_000, peak


def test_a_rate_too_fast_for_the_tumble_step_is_refused_not_nan() -> None:
    fast = np.array([0.7, 1.1, -2.0, 6.0, -8.0, 0.0])  # 10 rad/s with 1 s steps: NaN before
    with pytest.raises(InvalidInputError, match=r"step_s.*use step_s <= "):
        tumble.propagate_axes(fast, np.arange(11.0), step_s=1.0)
    # The step it suggests works and gives unit axes.
    axes = tumble.propagate_axes(fast, np.arange(11.0), step_s=0.09)
    assert np.allclose(np.linalg.norm(axes, axis=1), 1.0)


def test_a_torque_that_spins_the_body_up_raises_instead_of_nan() -> None:
    model = tumble.TumbleModel(
        orbital_rate_rad_s=0.0,
        speed_m_s=1e4,
        gravity_gradient=False,
        density_kg_m3=1e3,
        drag_coefficient=2.0,
        area_m2=1.0,
        cp_offset_m=(1.0, 0.0, 1.0),
    )
    with pytest.raises(ConvergenceError, match="diverged"):
        tumble.propagate_axes([0.1, 0.2, 0.3, 0.0, 0.0, 0.0], np.arange(100.0), model)


def test_huge_gyro_rates_are_refused_not_nan() -> None:
    rates = np.zeros((3, 3))
    rates[1] = [1e200, 1e200, 0.0]
    with pytest.raises(InvalidInputError, match=r"rates\[1\]"):
        gyro_propagate([0.0, 0.0, 0.0, 1.0], [0.0, 1.0, 2.0], rates)


def test_glonass_states_that_are_not_orbits_are_refused() -> None:
    with pytest.raises(InvalidInputError, match=r"velocity_m_s.*escape"):
        orbit.glonass_propagate(ICD_R0, [1e7, 0.0, 0.0], 10.0, step_s=1.0)
    with pytest.raises(InvalidInputError, match="position_m"):
        orbit.glonass_propagate([1e6, 0.0, 0.0], [0.0, 1e3, 0.0], 10.0, step_s=1.0)


def test_a_glonass_trajectory_that_meets_the_earth_raises_instead_of_nan() -> None:
    # 300 km up, falling at 7 km/s: below the surface after about 40 s.
    with pytest.raises(ConvergenceError, match="below the Earth's surface"):
        orbit.glonass_propagate([6_678_137.0, 0.0, 0.0], [-7000.0, 0.0, 0.0], 600.0, step_s=1.0)


def test_a_gyro_filter_covariance_that_overflows_raises_instead_of_inf() -> None:
    # Drift variance 1e300 grows the attitude variance as 1e300 t^2: infinite after 1e4 s.
    with pytest.raises((ConvergenceError, DegenerateGeometryError)):
        _gyro_filter(np.array([0.0, 1e3, 1e5]), p0=np.eye(6) * 1e300)


def test_wahba_weights_that_overflow_raise_instead_of_nan() -> None:
    v = np.eye(3)[:2]
    with pytest.raises((ConvergenceError, DegenerateGeometryError)):
        _core.wahba_batch(v, v, np.full(2, np.finfo(float).max), 2, "svd")


CHILD = textwrap.dedent(
    """
    import signal
    import time
    import numpy as np
    from gnssatt.attitude import dynamics as tumble

    # A child of a background job inherits SIGINT ignored, and Python then installs no KeyboardInterrupt
    # handler: install it, so the test measures the library and not how the test runner was started.
    signal.signal(signal.SIGINT, signal.default_int_handler)
    print("ready", flush=True)
    try:
        # 2.8e7 RK4 steps, under the 3e7 limit: several seconds uninterrupted.
        tumble.propagate_axes([0.7, 1.1, -2.0, 0.01, -0.01, 0.01], [1.4e6], step_s=0.05)
        print("finished", flush=True)
    except KeyboardInterrupt:
        print("interrupted", flush=True)
    """
)


@pytest.mark.slow
def test_sigint_stops_a_long_rust_call() -> None:
    child = subprocess.Popen(
        [sys.executable, "-c", CHILD], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True
    )
    try:
        assert child.stdout is not None
        assert child.stdout.readline().strip() == "ready"
        time.sleep(0.3)
        child.send_signal(signal.SIGINT)
        out, err = child.communicate(timeout=60)
    finally:
        child.kill()
    # The latency (the worker polls every 1024 steps, the caller checks signals every 50 ms) is measured
    # by benches/python/sigint_latency.py, not asserted here: a loaded machine made such bounds fail.
    assert out.split()[:1] == ["interrupted"], (out, err)


def test_non_finite_euler_angles_are_refused_not_nan() -> None:
    with pytest.raises(InvalidInputError, match="angles_rad"):
        _core.euler_to_dcm("ZYX", [np.nan, 0.0, 0.0])
