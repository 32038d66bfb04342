"""Orbit determination of a small satellite from GPS + GLONASS pseudoranges and Doppler (Dzhepe Ali, chapter
1).

A satellite on a 500 km sun-synchronous circular orbit carries a zenith-pointing GNSS receiver (85 deg cone,
Earth and 50 km of atmosphere block the view). Pseudoranges have 1 m of noise, Doppler 0.2 Hz; the receiver
clock wanders and GLONASS is offset from GPS by 20 m. For five minutes (900-1200 s) no satellite is tracked.
The tightly coupled filter (:func:`gnssatt.orbit.determination.orbit_filter`) differences the measurements between
satellites of one system, so clock and inter-system bias cancel, and predicts with the J2 model between
updates. The true orbit follows the same model plus the white acceleration noise the filter assumes, so a
consistent filter's normalised errors are chi-square distributed, which is what the run checks over
20 independent runs.
"""

from __future__ import annotations

import numpy as np
from scipy.stats import chi2

from gnssatt import sim
from gnssatt.orbit import CircularOrbit
from gnssatt.orbit.determination import noisy_orbit, orbit_filter

SEED = 2026
RUNS = 20
ORBIT = CircularOrbit(6_378_137.0 + 500e3, np.radians(97.4), 0.3, 0.0)  # radius m, i, RAAN, u0 rad
TIMES_S = np.arange(0.0, 1800.0 + 5.0, 10.0)
ACCEL_PSD_M2_S3 = 1e-8  # white acceleration noise, truth and filter alike
P0 = np.diag([30.0**2] * 3 + [0.05**2] * 3)  # initial covariance: 30 m, 5 cm/s per axis
OUTAGES = ((900.0, 1200.0, 0),)  # (start s, end s, satellites kept)


def one_run(rng: np.random.Generator) -> dict[str, np.ndarray]:
    r, v = ORBIT.state_ecef(TIMES_S[:1])
    truth = noisy_orbit(np.concatenate([r[0], v[0]]), TIMES_S, rng, accel_psd_m2_s3=ACCEL_PSD_M2_S3)
    constellation = sim.gps_nominal() + sim.glonass_nominal()
    measured = sim.simulate_spaceborne(
        truth[:, :3], truth[:, 3:], TIMES_S, constellation, rng, outages=OUTAGES
    )
    x0 = truth[0] + rng.multivariate_normal(np.zeros(6), P0)
    result = orbit_filter(measured, x0, P0, coupling="tight", accel_psd_m2_s3=ACCEL_PSD_M2_S3)
    updated = result.nis_dof > 0
    return {
        "error": result.states - truth,
        "sigma": result.sigma(),
        "nees": result.nees(truth),
        "nis_sum": float(result.nis[updated].sum()),
        "nis_dof": int(result.nis_dof[updated].sum()),
        "tracked": measured.visible.sum(axis=1),
    }


def main() -> dict[str, object]:
    rng = np.random.default_rng(SEED)
    runs = [one_run(rng) for _ in range(RUNS)]
    nees = np.array([r["nees"] for r in runs])  # (runs, epochs)
    error = np.array([r["error"] for r in runs])  # (runs, epochs, 6)
    final_nees_sum = float(nees[:, -1].sum())
    nis_sum = sum(r["nis_sum"] for r in runs)
    nis_dof = sum(r["nis_dof"] for r in runs)
    position_rms = np.sqrt(np.mean(np.sum(error[:, :, :3] ** 2, axis=2)))

    tracked = runs[0]["tracked"].max()
    print(f"{RUNS} runs of {TIMES_S[-1]:.0f} s at 10 s, tracked satellites {tracked} at most")
    print(f"position error RMS (3-D) {position_rms:.2f} m over all epochs")
    low, high = chi2.ppf([0.0005, 0.9995], 6 * RUNS)
    print(
        f"final NEES summed over runs {final_nees_sum:.1f}; "
        f"chi-square({6 * RUNS}) 99.9 % interval {low:.1f}-{high:.1f}"
    )
    low, high = chi2.ppf([0.0005, 0.9995], nis_dof)
    print(
        f"NIS summed over runs and epochs {nis_sum:.0f}; "
        f"chi-square({nis_dof}) 99.9 % interval {low:.0f}-{high:.0f}"
    )
    return {
        "runs": runs,
        "nees": nees,
        "final_nees_sum": final_nees_sum,
        "nis_sum": nis_sum,
        "nis_dof": nis_dof,
    }


def figure(found: dict[str, object]):
    import matplotlib.pyplot as plt

    run = found["runs"][0]
    fig, (top, bottom) = plt.subplots(2, 1, figsize=(9, 6.5), sharex=True)
    for axis, name in enumerate("xyz"):
        (line,) = top.plot(TIMES_S, run["error"][:, axis], lw=0.9, label=f"{name} error")
        top.plot(TIMES_S, 3 * run["sigma"][:, axis], color=line.get_color(), lw=0.6, ls="--")
        top.plot(TIMES_S, -3 * run["sigma"][:, axis], color=line.get_color(), lw=0.6, ls="--")
    top.set_ylim(-3.0, 3.0)
    top.set_ylabel("position error (ECEF), m")
    top.set_title("run 0: position errors and the filter's +-3 sigma (dashed)")
    top.legend(loc="lower left", ncols=3, fontsize=8)
    mean_nees = found["nees"].mean(axis=0)
    low, high = chi2.ppf([0.025, 0.975], 6 * RUNS) / RUNS
    bottom.plot(TIMES_S, mean_nees, lw=0.9, label=f"NEES averaged over {RUNS} runs")
    bottom.axhspan(low, high, color="C2", alpha=0.2, label="95 % interval of a consistent filter")
    bottom.axhline(6.0, color="C2", lw=0.8, label="expected value, 6 states")
    bottom.set_xlabel("time, s")
    bottom.set_ylabel("NEES, dimensionless")
    bottom.set_title("consistency: normalised estimation error squared")
    bottom.legend(loc="upper left", ncols=3, fontsize=8)
    bottom.set_ylim(0.0, max(14.0, 1.1 * mean_nees.max()))
    for ax in (top, bottom):
        for start, end, _ in OUTAGES:
            ax.axvspan(start, end, color="0.88", zorder=0)
    top.text(1050.0, 2.6, "outage: no satellites", ha="center", fontsize=8)
    fig.suptitle(
        "Tightly coupled orbit filter: 500 km sun-synchronous orbit, GPS + GLONASS, 1 m code, 0.2 Hz Doppler"
    )
    fig.tight_layout()
    return fig


if __name__ == "__main__":
    import matplotlib.pyplot as plt

    figure(main())
    plt.show()
