"""The experiment of Dzhepe Ali's thesis, chapter 1: GNSS orbit determination of a small satellite, loosely vs
tightly coupled, GPS vs GPS + GLONASS, with outages.

The thesis summary gives no numbers; the scenario here: a 500 km sun-synchronous circular orbit (i = 97.4
deg), one revolution (5670 s) at 10 s epochs; truth = the ICD model (J2) plus white acceleration noise of
PSD 1e-8 m^2/s^3, the same the filter assumes; a zenith antenna with an 85 deg half-angle cone and Earth
occlusion (50 km atmosphere); pseudorange noise 1 m, Doppler 0.2 Hz, a random-walk receiver clock and a 20 m
GPS-GLONASS inter-system bias; two outages: 1800-2400 s with only the 2 satellites nearest the zenith
(no fix: the loosely coupled filter only predicts; the tightly coupled one still differences them when they
belong to one system) and 3600-3900 s with none. Initial error drawn from P0 = diag(30 m, 5 cm/s)^2.
Consistency: per epoch, the NEES averaged over runs times the number of runs is chi-square with 6 runs
degrees of freedom; the fraction of epochs inside the two-sided 95 % bounds should be near 0.95.
"""

from __future__ import annotations

import functools
from concurrent.futures import Executor
from pathlib import Path
from typing import Any

import numpy as np
from scipy.stats import chi2

from gnssatt import montecarlo, sim
from gnssatt.experiments import Experiment
from gnssatt.experiments.report import format_table, write_report
from gnssatt.orbit import CircularOrbit
from gnssatt.orbit.determination import noisy_orbit, orbit_filter

NAME = "orbit-filter"
ORBIT = CircularOrbit(6_378_137.0 + 500e3, np.radians(97.4), 0.3, 0.0)
TIMES_S = np.arange(0.0, 5670.0, 10.0)
Q_M2_S3 = 1e-8
P0 = np.diag([30.0**2] * 3 + [0.05**2] * 3)
OUTAGES = ((1800.0, 2400.0, 2), (3600.0, 3900.0, 0))
CONFIGS = (("loose", "G"), ("loose", "GR"), ("tight", "G"), ("tight", "GR"))


def _label(coupling: str, systems: str) -> str:
    return f"{coupling}_{'gps' if systems == 'G' else 'gps_glonass'}"


def trial(rng: np.random.Generator) -> dict[str, Any]:
    """One run: truth, measurements, and the four filters' errors, sigmas, NEES and NIS."""
    r, v = ORBIT.state_ecef(TIMES_S[:1])
    truth = noisy_orbit(np.concatenate([r[0], v[0]]), TIMES_S, rng=rng, accel_psd_m2_s3=Q_M2_S3)
    cons = sim.gps_nominal() + sim.glonass_nominal()
    meas = sim.simulate_spaceborne(truth[:, :3], truth[:, 3:], TIMES_S, cons, rng, outages=OUTAGES)
    x0 = truth[0] + rng.multivariate_normal(np.zeros(6), P0)
    out: dict[str, Any] = {}
    for coupling, systems in CONFIGS:
        m = meas.select_systems(systems)
        res = orbit_filter(m, x0, P0, coupling=coupling, accel_psd_m2_s3=Q_M2_S3)
        ok = res.nis_dof > 0
        out[_label(coupling, systems)] = {
            "error": res.states - truth,
            "sigma": res.sigma(),
            "nees": res.nees(truth),
            "nis_sum": float(res.nis[ok].sum()),
            "nis_dof": int(res.nis_dof[ok].sum()),
            "visible": m.visible.sum(axis=1),
        }
    return out


def _plots(rows: list[dict[str, Any]], out: Path, runs: int) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    labels = [_label(c, s) for c, s in CONFIGS]
    fig, axes = plt.subplots(len(labels), 2, figsize=(12, 11), sharex=True)
    for i, lab in enumerate(labels):
        r0 = rows[0][lab]
        for j, (sl, unit) in enumerate(((slice(0, 3), "m"), (slice(3, 6), "m/s"))):
            ax = axes[i, j]
            for a, name in zip(range(sl.start, sl.stop), "xyz", strict=True):
                (line,) = ax.plot(TIMES_S, r0["error"][:, a], lw=0.8, label=f"{name} error")
                ax.plot(TIMES_S, 3 * r0["sigma"][:, a], color=line.get_color(), lw=0.6, ls="--")
                ax.plot(TIMES_S, -3 * r0["sigma"][:, a], color=line.get_color(), lw=0.6, ls="--")
            for t0, t1, n in OUTAGES:
                ax.axvspan(t0, t1, color="0.85", zorder=0)
                ax.text(t0, 0.9, f"{n} sats", transform=ax.get_xaxis_transform(), fontsize=7)
            ax.set_ylabel(unit)
            lim = 3 * np.percentile(np.abs(r0["sigma"][:, sl]), 90)
            ax.set_ylim(-lim, lim)
            ax.set_title(
                f"{lab}: {'position' if j == 0 else 'velocity'} error, +-3 sigma (dashed)", fontsize=9
            )
    axes[0, 0].legend(fontsize=7, loc="lower right")
    for ax in axes[-1]:
        ax.set_xlabel("time, s")
    fig.suptitle("Dzhepe Ali: orbit-determination errors of run 0 (ECEF axes); grey = outages")
    fig.tight_layout()
    fig.savefig(out / f"{NAME}-errors.png", dpi=110)
    plt.close(fig)

    fig, ax = plt.subplots(figsize=(10, 4))
    lo, hi = chi2.ppf([0.025, 0.975], 6 * runs) / runs
    for lab in labels:
        ax.plot(TIMES_S, np.mean([r[lab]["nees"] for r in rows], axis=0), lw=0.8, label=lab)
    ax.axhline(lo, color="k", ls="--", lw=0.8)
    ax.axhline(hi, color="k", ls="--", lw=0.8, label="95 % chi-square bounds")
    ax.set_yscale("log")
    ax.set_xlabel("time, s")
    ax.set_ylabel(f"NEES averaged over {runs} runs")
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(out / f"{NAME}-nees.png", dpi=110)
    plt.close(fig)


def run(
    *, runs: int, seed: int, out: Path, executor: Executor | None = None, progress: bool = True
) -> dict[str, Any]:
    rows = montecarlo.run(functools.partial(trial), runs, seed=seed, executor=executor, progress=progress)
    measured: dict[str, Any] = {}
    window = (TIMES_S >= OUTAGES[0][0]) & (TIMES_S <= OUTAGES[0][1])
    lo, hi = chi2.ppf([0.025, 0.975], 6 * runs) / runs
    for coupling, systems in CONFIGS:
        lab = _label(coupling, systems)
        err = np.stack([r[lab]["error"] for r in rows])  # (runs, n_t, 6)
        pos2 = np.sum(err[..., :3] ** 2, axis=-1)
        measured[f"{lab}_position_rms_m"] = float(np.sqrt(pos2.mean()))
        measured[f"{lab}_velocity_rms_m_s"] = float(np.sqrt(np.sum(err[..., 3:] ** 2, axis=-1).mean()))
        measured[f"{lab}_position_rms_two_sat_outage_m"] = float(np.sqrt(pos2[:, window].mean()))
        nees = np.mean([r[lab]["nees"] for r in rows], axis=0)
        measured[f"{lab}_nees_mean"] = float(nees.mean())
        measured[f"{lab}_nees_in_95pct_bounds_fraction"] = float(np.mean((nees > lo) & (nees < hi)))
        nis_sum = sum(r[lab]["nis_sum"] for r in rows)
        nis_dof = sum(r[lab]["nis_dof"] for r in rows)
        measured[f"{lab}_nis_per_dof"] = float(nis_sum / nis_dof)
    measured["visible_sats_gps_glonass_median"] = float(np.median(rows[0][_label("tight", "GR")]["visible"]))
    doc = write_report(out, NAME, {k: None for k in measured}, measured, runs, seed)
    _plots(rows, out, runs)
    print(format_table(doc))
    return doc


EXPERIMENT = Experiment(
    name=NAME,
    summary="Dzhepe Ali: GNSS orbit determination, loosely vs tightly coupled, GPS vs GPS+GLONASS, outages",
    run=run,
    default_runs=50,
    quick_runs=4,
)
