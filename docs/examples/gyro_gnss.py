"""Gyro + GNSS attitude filter: gyros carry the attitude between GNSS attitude fixes and learn their drift
(Dzhepe Ali, loosely coupled).

A spacecraft turns at a constant 0.5 deg/s. Its gyros, sampled at 10 Hz, have an angle random walk of
0.3 deg/sqrt(h) and an unknown constant drift of a few deg/h; a multi-antenna GNSS receiver gives an attitude
once a second with 0.05 deg of noise per axis. :func:`gnssatt.gyro_gnss_filter` integrates the gyros,
corrects with each fix and estimates the drift. Once the drift is learnt, the attitude uncertainty settles
to the steady state of a scalar Kalman filter per axis (a random walk observed with white noise), whose
closed form the run is compared with.
"""

from __future__ import annotations

import numpy as np
from scipy.spatial.transform import Rotation

import gnssatt
from gnssatt.sim.attitude_scenario import AttitudeFixes

SEED = 2026
DURATION_S = 600.0
GYRO_HZ = 10.0
FIX_INTERVAL_S = 1.0
ARW = np.radians(0.3) / 60.0  # angle random walk, rad/s/sqrt(Hz) (0.3 deg/sqrt(h))
FIX_SIGMA_RAD = np.radians(0.05)  # GNSS attitude noise per body axis
RATE_RAD_S = np.radians([0.3, -0.2, 0.35])  # |rate| = 0.5 deg/s, body axes
DRIFT_RAD_S = np.radians([3.0, -2.0, 1.0]) / 3600.0  # true gyro drift (3, -2, 1 deg/h)
DRIFT_SIGMA0_RAD_S = np.radians(10.0) / 3600.0  # the filter's initial drift sigma (10 deg/h)
STEADY_FROM_S = 300.0  # statistics over the second half of the run


def steady_state_variance() -> tuple[float, float]:
    """Closed-form steady state of one axis, rad^2: before and after a fix.

    Between fixes the attitude error random-walks by ``q = ARW^2 T``; a fix of variance ``r`` then gives
    ``P+ = P- r / (P- + r)``. The fixed point of ``P- = P+ + q`` is ``P- = (q + sqrt(q^2 + 4 q r)) / 2``.
    """
    q, r = ARW**2 * FIX_INTERVAL_S, FIX_SIGMA_RAD**2
    before = (q + np.sqrt(q * q + 4.0 * q * r)) / 2.0
    return before, before * r / (before + r)


def main() -> dict[str, object]:
    rng = np.random.default_rng(SEED)
    start = Rotation.from_euler("ZYX", [30.0, 10.0, -5.0], degrees=True)  # body -> ECI at t = 0
    t = np.arange(0.0, DURATION_S + 0.5 / GYRO_HZ, 1.0 / GYRO_HZ)
    truth = start * Rotation.from_rotvec(np.outer(t, RATE_RAD_S))
    # Gyro model omega_meas = omega - drift - w, with w white of ARW^2 / dt per sample.
    rates = RATE_RAD_S - DRIFT_RAD_S + rng.normal(0.0, ARW * np.sqrt(GYRO_HZ), (len(t), 3))

    every = round(FIX_INTERVAL_S * GYRO_HZ)
    fix_t = t[every::every]
    noise = Rotation.from_rotvec(rng.normal(0.0, FIX_SIGMA_RAD, (len(fix_t), 3)))
    fixes = AttitudeFixes(
        t=fix_t,
        rotation=truth[every::every] * noise,
        covariance=np.tile(FIX_SIGMA_RAD**2 * np.eye(3), (len(fix_t), 1, 1)),
    )
    initial_covariance = np.diag([FIX_SIGMA_RAD**2] * 3 + [DRIFT_SIGMA0_RAD_S**2] * 3)
    result = gnssatt.gyro_gnss_filter(
        t,
        rates,
        initial_rotation=truth[0] * Rotation.from_rotvec(rng.normal(0.0, FIX_SIGMA_RAD, 3)),
        initial_covariance=initial_covariance,
        arw=ARW,
        attitude_fixes=fixes,
        output_every=every,
    )
    kept = np.isin(t, result.t)
    errors = result.errors(truth[kept], DRIFT_RAD_S)  # (n, 6): attitude (rad), drift (rad/s)
    steady = result.t >= STEADY_FROM_S
    final = np.diag(result.covariance[-1])[:3]  # after the last fix's update, rad^2
    before, after = steady_state_variance()

    print(f"{len(t)} gyro samples, {len(fix_t)} attitude fixes")
    print(
        f"attitude sigma after the last fix: reported {np.degrees(np.sqrt(final.mean())):.4f} deg, "
        f"closed form with the drift known {np.degrees(np.sqrt(after)):.4f} deg"
    )
    rms = np.degrees(np.sqrt(np.mean(errors[steady, :3] ** 2, axis=0)))
    print(f"attitude error RMS per axis, t >= {STEADY_FROM_S:.0f} s: {np.round(rms, 4)} deg")
    drift_error = np.degrees(errors[-1, 3:]) * 3600.0
    drift_sigma = np.degrees(np.sqrt(np.diag(result.covariance[-1])[3:])) * 3600.0
    print(f"drift error at {DURATION_S:.0f} s: {np.round(drift_error, 3)} deg/h (sigma {drift_sigma[0]:.3f})")
    return {
        "t": result.t,
        "errors": errors,
        "covariance": result.covariance,
        "drift": result.drift,
        "steady": steady,
        "closed_form": (before, after),
    }


def figure(found: dict[str, object]):
    import matplotlib.pyplot as plt

    t, errors, cov = found["t"], found["errors"], found["covariance"]
    _, after = found["closed_form"]
    fig, (top, bottom) = plt.subplots(2, 1, figsize=(9, 6.5), sharex=True)
    for axis, name in enumerate("xyz"):
        top.plot(t, np.degrees(errors[:, axis]), lw=0.7, label=f"error about body {name}")
    sigma = np.degrees(np.sqrt(cov[:, 0, 0]))
    top.plot(t, 3 * sigma, "k--", lw=0.8, label="filter's 3 sigma (x)")
    top.plot(t, -3 * sigma, "k--", lw=0.8)
    top.axhline(3 * np.degrees(np.sqrt(after)), color="C3", lw=1.0, ls=":", label="closed-form 3 sigma")
    top.axhline(-3 * np.degrees(np.sqrt(after)), color="C3", lw=1.0, ls=":")
    top.set_ylim(-7 * np.degrees(np.sqrt(after)), 7 * np.degrees(np.sqrt(after)))
    top.set_ylabel("attitude error, deg")
    top.set_title("attitude error after each fix, and 3 sigma (clipped in the first seconds)")
    top.legend(loc="upper right", ncols=3, fontsize=8)
    for axis, name in enumerate("xyz"):
        estimate = np.degrees(found["drift"][:, axis]) * 3600.0
        (line,) = bottom.plot(t, estimate, lw=1.0, label=f"estimate {name}")
        bottom.axhline(np.degrees(DRIFT_RAD_S[axis]) * 3600.0, color=line.get_color(), ls=":", lw=1.0)
    bottom.set_xlabel("time, s")
    bottom.set_ylabel("gyro drift, deg/h")
    bottom.set_title("drift estimates (dotted: the truth)")
    bottom.legend(loc="lower right", ncols=3, fontsize=8)
    fig.suptitle(
        "Gyro + GNSS filter: 0.5 deg/s turn, 10 Hz gyros with 0.3 deg/sqrt(h) ARW,\n"
        "GNSS attitude fixes of 0.05 deg at 1 Hz"
    )
    fig.tight_layout()
    return fig


if __name__ == "__main__":
    import matplotlib.pyplot as plt

    figure(main())
    plt.show()
