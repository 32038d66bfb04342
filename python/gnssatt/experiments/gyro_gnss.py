"""The experiment of Dzhepe Ali: gyros plus a multi-antenna GNSS receiver, loosely vs tightly coupled, and the
sensitivity of a reduced filter to baseline errors and gyro misalignment.

The thesis (only its table of contents and chapter summaries are available) gives no scenario and no
results beyond a phase precision of about 0.002 cycle, so this experiment fixes its own, stated here:
a 700 km, 51.6 deg circular orbit holding the orbital frame with oscillations of 2, 1, 3 deg (periods 200,
250, 300 s); GPS + GLONASS L1; three antennas on a 1 m equilateral triangle with boresight zenith (80 deg
cone, Earth occlusion with a 100 km grazing layer); 10 Hz gyros with ARW 1e-5 rad/s/sqrt(Hz) and constant
drifts (10, -5, 3) deg/h; phase first differences at 1 Hz with 0.002 cycle noise; initial errors drawn from
0.5 deg (attitude) and 20 deg/h (drift) per axis; a GNSS-phase outage from 2000 to 2300 s after which every
satellite is re-acquired with new ambiguities. The loosely coupled filter uses the receiver's own attitude
solution at every epoch with at least three satellites (covariance from the geometry of the first
differences with resolved integers, :func:`gnssatt.sim.attitude_scenario.attitude_fixes`), or with
``run(..., loose_fixes="matrix")`` the per-epoch :func:`gnssatt.matrix_attitude` solutions of the phases with
their true integers (:func:`gnssatt.phase_attitude_fixes`).
"""

from __future__ import annotations

import functools
import math
from concurrent.futures import Executor
from pathlib import Path
from typing import Any, Literal

import numpy as np
from scipy.spatial.transform import Rotation

from gnssatt import montecarlo, sim
from gnssatt.attitude.gyro_gnss import GyroGnssResult, gyro_gnss_filter
from gnssatt.attitude.phase_attitude import phase_attitude_fixes
from gnssatt.errors import InvalidInputError
from gnssatt.experiments import Experiment
from gnssatt.experiments.report import format_table, write_report
from gnssatt.sim import attitude_scenario as sc

NAME = "gyro-gnss"
RX = sim.OrbitalReceiver(altitude_m=700e3, inclination_deg=51.6)
OSC_AMP_DEG = (2.0, 1.0, 3.0)
OSC_PERIOD_S = (200.0, 250.0, 300.0)
GYRO_DT_S = 0.1
GNSS_EVERY = 10  # gyro samples per GNSS epoch (1 Hz)
ARW = 1e-5  # rad/s/sqrt(Hz)
DRIFT_DEG_H = (10.0, -5.0, 3.0)
PHASE_SIGMA_CYCLES = 0.002
SIGMA_ATT_DEG = 0.5
SIGMA_DRIFT_DEG_H = 20.0
OUTAGE_S = (2000.0, 2300.0)
BASELINE_ERRORS_MM = (0.0, 0.5, 1.0, 2.0, 5.0, 10.0)
MISALIGNMENTS_DEG = (0.0, 0.1, 0.3, 1.0, 3.0)
SENSITIVITY_S = 1000.0
SENS_MC_POINT = (0.3, 2.0)  # misalignment deg, baseline error mm
MISALIGNMENT_ESTIMATE_DEG = 1.0
LINEARITY_SIGMAS_DEG = (0.1, 0.5, 1.0, 2.0)
LINEARITY_S = 300.0
DEG_H = math.radians(1.0) / 3600.0
LooseFixes = Literal["simulated", "matrix"]


@functools.cache
def _gnss() -> sim.Constellation:
    return sim.gps_nominal() + sim.glonass_nominal()


def _baselines() -> np.ndarray:
    return sim.equilateral_triangle(1.0)[1:]


def _p0(sigma_att_deg: float = SIGMA_ATT_DEG) -> np.ndarray:
    return np.diag([math.radians(sigma_att_deg) ** 2] * 3 + [(SIGMA_DRIFT_DEG_H * DEG_H) ** 2] * 3)


def _motion(duration_s: float) -> tuple[np.ndarray, Rotation]:
    t = np.arange(0.0, duration_s + 1e-9, GYRO_DT_S)
    att, _ = sc.orbital_hold_motion(RX, t, np.radians(OSC_AMP_DEG), OSC_PERIOD_S, (0.0, 1.0, 2.0))
    return t, att


def _start(rng: np.random.Generator, att0: Rotation, p0: np.ndarray) -> dict[str, Any]:
    e0 = rng.multivariate_normal(np.zeros(6), p0)
    return {
        "initial_rotation": att0 * Rotation.from_rotvec(-e0[:3]),
        "initial_covariance": p0,
        "initial_drift": np.array(DRIFT_DEG_H) * DEG_H - e0[3:],
        "arw": ARW,
        "phase_sigma_cycles": PHASE_SIGMA_CYCLES,
        "output_every": GNSS_EVERY,
    }


def _loose_fixes(
    kind: LooseFixes, ph: sc.PhaseObservations, att: Rotation, rng: np.random.Generator
) -> sc.AttitudeFixes:
    """The loosely coupled input: simulated solutions (truth times a draw from their covariance), or the
    matrix-method solutions of the phases with their true integers."""
    if kind == "matrix":
        return phase_attitude_fixes(ph, _baselines(), ph.ambiguity, phase_sigma_cycles=PHASE_SIGMA_CYCLES)
    return sc.attitude_fixes(ph, att, _baselines(), rng, phase_sigma_cycles=PHASE_SIGMA_CYCLES)


def _summary(r: Any, e: np.ndarray) -> dict[str, np.ndarray]:
    sig = np.sqrt(np.diagonal(r.covariance, axis1=1, axis2=2))
    return {"err": e.astype(np.float32), "sig": sig.astype(np.float32), "nees": r.nees(e).astype(np.float32)}


def orbit_trial(
    rng: np.random.Generator, *, duration_s: float, loose_fixes: LooseFixes = "simulated"
) -> dict[str, Any]:
    """Loosely and tightly coupled filters over one scenario with the phase outage."""
    t, att = _motion(duration_s)
    g = sc.gyro_output(t, att, rng, drift_rad_s=np.array(DRIFT_DEG_H) * DEG_H, arw=ARW)
    k = np.arange(0, len(t), GNSS_EVERY)
    k = k[(t[k] < OUTAGE_S[0]) | (t[k] >= OUTAGE_S[1])]
    ph = sc.phase_observations(
        RX,
        _gnss(),
        t[k],
        att[k],
        _baselines(),
        rng,
        phase_sigma_cycles=PHASE_SIGMA_CYCLES,
        new_arcs_after=(OUTAGE_S[1],),
    )
    fixes = _loose_fixes(loose_fixes, ph, att[k], rng)
    start = _start(rng, att[0], _p0())
    out_k = np.arange(0, len(t), GNSS_EVERY)
    truth = (att[out_k], g.drift[out_k])
    tight = gyro_gnss_filter(t, g.rates, **start, baselines_m=_baselines(), phases=ph)
    loose = gyro_gnss_filter(t, g.rates, **start, attitude_fixes=fixes)
    truth_n = {int(tr): a for tr, a in zip(ph.track, ph.ambiguity, strict=True)}
    accepted = [f for f in tight.fixes if f.accepted]
    wrong = sum(any(truth_n[tr][b] != v for tr, b, v in f.values) for f in accepted)
    refix = [f.t for f in accepted if f.t >= OUTAGE_S[1]]
    return {
        "t": tight.t,
        "tight": _summary(tight, tight.errors(*truth)),
        "loose": _summary(loose, loose.errors(*truth)),
        "n_float": tight.n_float,
        "n_fixed": tight.n_fixed,
        "fixes_accepted": len(accepted),
        "fixes_wrong": wrong,
        "first_fix_s": accepted[0].t if accepted else math.nan,
        "refix_after_outage_s": (refix[0] - OUTAGE_S[1]) if refix else math.nan,
        "slips": len(tight.slips),
        "n_visible_mean": float(ph.n_visible()[ph.n_visible() > 0].mean()),
    }


def two_satellite_trial(
    rng: np.random.Generator, *, duration_s: float, loose_fixes: LooseFixes = "simulated"
) -> dict[str, float]:
    """Final attitude 3-sigma (deg) of both filters when only two satellites are tracked."""
    t, att = _motion(duration_s)
    g = sc.gyro_output(t, att, rng, drift_rad_s=np.array(DRIFT_DEG_H) * DEG_H, arw=ARW)
    k = np.arange(0, len(t), GNSS_EVERY)
    ph = sc.phase_observations(
        RX, _gnss(), t[k], att[k], _baselines(), rng, phase_sigma_cycles=PHASE_SIGMA_CYCLES, max_satellites=2
    )
    fixes = _loose_fixes(loose_fixes, ph, att[k], rng)
    start = _start(rng, att[0], _p0())
    tight = gyro_gnss_filter(t, g.rates, **start, baselines_m=_baselines(), phases=ph)
    loose = gyro_gnss_filter(t, g.rates, **start, attitude_fixes=fixes)
    e = tight.errors(att[k], g.drift[k])

    def s3(r: GyroGnssResult) -> float:
        return 3 * math.degrees(math.sqrt(np.linalg.eigvalsh(r.covariance[-1][:3, :3]).max()))

    return {
        "tight_3sigma_deg": s3(tight),
        "loose_3sigma_deg": s3(loose),
        "loose_updates": len(loose.nis),
        "tight_error_deg": math.degrees(float(np.linalg.norm(e[-1, :3]))),
        "tight_nees": float(tight.nees(e)[-1]),
    }


def sensitivity_trial(
    rng: np.random.Generator, *, misalignment_deg: float, baseline_mm: float, draw: bool
) -> dict[str, np.ndarray]:
    """Reduced filter (known integers, no baseline or misalignment states) against the full truth model; the
    truth's misalignment and baseline errors are drawn from their priors when ``draw``, else zero."""
    t, att = _motion(SENSITIVITY_S)
    mis, base = math.radians(misalignment_deg), baseline_mm * 1e-3
    mu = rng.normal(0.0, mis, 3) if draw else np.zeros(3)
    db = rng.normal(0.0, base, (2, 3)) if draw else np.zeros((2, 3))
    g = sc.gyro_output(t, att, rng, drift_rad_s=np.array(DRIFT_DEG_H) * DEG_H, arw=ARW, misalignment_rad=mu)
    k = np.arange(0, len(t), GNSS_EVERY)
    ph = sc.phase_observations(
        RX,
        _gnss(),
        t[k],
        att[k],
        _baselines(),
        rng,
        phase_sigma_cycles=PHASE_SIGMA_CYCLES,
        baseline_errors_m=db,
    ).without_ambiguities()
    start = _start(rng, att[0], _p0()) | {"output_every": len(t) - 1}
    r = gyro_gnss_filter(
        t,
        g.rates,
        **start,
        baselines_m=_baselines(),
        phases=ph,
        known_ambiguities=True,
        sensitivity=(mis, base),
    )
    assert r.true_covariance is not None
    return {
        "err": r.errors(att[[0, -1]], g.drift[[0, -1]])[-1],
        "reported": r.covariance[-1],
        "true": r.true_covariance[-1],
    }


def misalignment_trial(rng: np.random.Generator, *, sigma_deg: float) -> dict[str, np.ndarray]:
    """Final errors and sigmas of the reduced filter and of the one with misalignment states (prior
    ``sigma_deg``), the truth's misalignment drawn from that prior."""
    t, att = _motion(SENSITIVITY_S)
    mu = rng.normal(0.0, math.radians(sigma_deg), 3)
    g = sc.gyro_output(t, att, rng, drift_rad_s=np.array(DRIFT_DEG_H) * DEG_H, arw=ARW, misalignment_rad=mu)
    k = np.arange(0, len(t), GNSS_EVERY)
    ph = sc.phase_observations(
        RX, _gnss(), t[k], att[k], _baselines(), rng, phase_sigma_cycles=PHASE_SIGMA_CYCLES
    )
    start = _start(rng, att[0], _p0()) | {
        "output_every": len(t) - 1,
        "baselines_m": _baselines(),
        "phases": ph,
    }
    reduced = gyro_gnss_filter(t, g.rates, **start)
    full = gyro_gnss_filter(t, g.rates, **start, misalignment_sigma_rad=math.radians(sigma_deg))
    truth = (att[[0, -1]], g.drift[[0, -1]])
    return {
        "reduced_err": reduced.errors(*truth)[-1, :3],
        "reduced_sig": np.sqrt(np.diag(reduced.covariance[-1])[:3]),
        "full_err": full.errors(*truth)[-1, :3],
        "full_sig": np.sqrt(np.diag(full.covariance[-1])[:3]),
        "mu_err": mu - full.misalignment[-1],
        "mu_sig": np.sqrt(np.diag(full.misalignment_covariance[-1])),
    }


def linearity_trial(rng: np.random.Generator, *, sigma_att_deg: float) -> float:
    """NEES at the end of a float-only tightly coupled run started with the given attitude uncertainty."""
    t, att = _motion(LINEARITY_S)
    g = sc.gyro_output(t, att, rng, drift_rad_s=np.array(DRIFT_DEG_H) * DEG_H, arw=ARW)
    k = np.arange(0, len(t), GNSS_EVERY)
    ph = sc.phase_observations(
        RX, _gnss(), t[k], att[k], _baselines(), rng, phase_sigma_cycles=PHASE_SIGMA_CYCLES
    )
    start = _start(rng, att[0], _p0(sigma_att_deg)) | {"output_every": len(t) - 1}
    r = gyro_gnss_filter(
        t, g.rates, **start, baselines_m=_baselines(), phases=ph, fix_ambiguities=False, slip_false_alarm=None
    )
    return float(r.nees(r.errors(att[[0, -1]], g.drift[[0, -1]]))[-1])


def _rms(x: np.ndarray, axis: Any = None) -> np.ndarray:
    rms: np.ndarray = np.sqrt(np.mean(np.square(x, dtype=np.float64), axis=axis))  # np.mean is typed Any
    return rms


def _orbit_measures(
    t: np.ndarray, rows: list[dict[str, Any]], measured: dict[str, Any]
) -> dict[str, dict[str, np.ndarray]]:
    """Add the orbit trials' numbers to ``measured`` (each filter's attitude and drift errors and sigmas in
    the steady state, at the end and at the outage's end; the tight filter's fixes); each filter's error and
    sigma series, for the plot."""
    steady = (t >= 600.0) & (t < OUTAGE_S[0])
    end_out = int(np.searchsorted(t, OUTAGE_S[1]) - 1)
    series: dict[str, dict[str, np.ndarray]] = {}
    for mode in ("loose", "tight"):
        err = np.array([r[mode]["err"] for r in rows])
        sig = np.array([r[mode]["sig"] for r in rows])
        nees = np.array([r[mode]["nees"] for r in rows])
        series[mode] = {"err": err, "sig": sig}
        measured[f"{mode}_attitude_rms_deg"] = math.degrees(float(_rms(err[:, steady, :3])))
        measured[f"{mode}_attitude_sigma_deg"] = math.degrees(float(_rms(sig[:, steady, :3])))
        measured[f"{mode}_drift_rms_final_deg_h"] = float(_rms(err[:, -1, 3:])) / DEG_H
        measured[f"{mode}_drift_sigma_final_deg_h"] = float(_rms(sig[:, -1, 3:])) / DEG_H
        measured[f"{mode}_nees_mean"] = float(nees.mean())  # 6 for a consistent filter
        measured[f"{mode}_outage_end_attitude_rms_deg"] = math.degrees(float(_rms(err[:, end_out, :3])))
        measured[f"{mode}_outage_end_attitude_sigma_deg"] = math.degrees(float(_rms(sig[:, end_out, :3])))
    phase_epochs = (t < OUTAGE_S[0]) | (t >= OUTAGE_S[1])
    n_float = np.array([r["n_float"] for r in rows])[:, phase_epochs]
    measured["tight_fix_rate"] = float(np.mean(n_float == 0))
    measured["tight_fixes_accepted"] = int(sum(r["fixes_accepted"] for r in rows))
    measured["tight_fixes_wrong"] = int(sum(r["fixes_wrong"] for r in rows))
    measured["tight_first_fix_s_mean"] = float(np.nanmean([r["first_fix_s"] for r in rows]))
    measured["tight_refix_after_outage_s_mean"] = float(np.nanmean([r["refix_after_outage_s"] for r in rows]))
    measured["tight_slips_detected"] = int(sum(r["slips"] for r in rows))
    return series


def _misalignment_measures(mis_rows: list[dict[str, Any]]) -> dict[str, Any]:
    """RMS errors and sigmas (deg) of the misalignment trials, the reduced and the full filter."""
    tag = f"misalignment_{MISALIGNMENT_ESTIMATE_DEG:g}deg"
    return {
        f"{tag}_{name}_deg": math.degrees(float(_rms(np.array([r[key] for r in mis_rows]))))
        for key, name in (
            ("reduced_err", "reduced_attitude_rms"),
            ("full_err", "full_attitude_rms"),
            ("mu_err", "full_misalignment_rms"),
            ("reduced_sig", "reduced_attitude_sigma"),
            ("full_sig", "full_attitude_sigma"),
            ("mu_sig", "full_misalignment_sigma"),
        )
    }


def run(
    *,
    runs: int,
    seed: int,
    out: Path,
    executor: Executor | None = None,
    progress: bool = True,
    duration_s: float | None = None,
    loose_fixes: LooseFixes = "simulated",
) -> dict[str, Any]:
    if loose_fixes not in ("simulated", "matrix"):
        raise InvalidInputError(f"expected loose_fixes 'simulated' or 'matrix', got {loose_fixes!r}")
    out.mkdir(parents=True, exist_ok=True)
    duration = float(math.floor(RX.period_s if duration_s is None else duration_s))  # whole GNSS epochs
    mc = functools.partial(montecarlo.run, seed=seed, executor=executor, progress=progress)
    rows = mc(functools.partial(orbit_trial, duration_s=duration, loose_fixes=loose_fixes), runs)
    t = rows[0]["t"]
    measured: dict[str, Any] = {
        "duration_s": float(duration),
        "runs": runs,
        "loose_fixes": loose_fixes,
        "visible_satellites_mean": float(np.mean([r["n_visible_mean"] for r in rows])),
    }
    series = _orbit_measures(t, rows, measured)

    two = mc(functools.partial(two_satellite_trial, duration_s=600.0, loose_fixes=loose_fixes), runs)
    for key in ("tight_3sigma_deg", "loose_3sigma_deg", "tight_error_deg", "tight_nees"):
        measured[f"two_satellites_{key}_mean"] = float(np.mean([r[key] for r in two]))
    measured["two_satellites_loose_updates"] = int(sum(r["loose_updates"] for r in two))

    sens = _sensitivity(mc, runs)
    measured |= sens["measured"]
    mis_rows = mc(functools.partial(misalignment_trial, sigma_deg=MISALIGNMENT_ESTIMATE_DEG), runs)
    measured |= _misalignment_measures(mis_rows)
    lin = {s: mc(functools.partial(linearity_trial, sigma_att_deg=s), runs) for s in LINEARITY_SIGMAS_DEG}
    for s, v in lin.items():
        measured[f"float_only_nees_{LINEARITY_S:g}s_init_{s:g}deg"] = float(np.mean(v))

    paper: dict[str, Any] = {k: None for k in measured}
    paper["phase_precision_cycles"] = 0.002
    measured["phase_precision_cycles"] = PHASE_SIGMA_CYCLES
    _plot_errors(t, series, out / f"{NAME}-errors.png")
    _plot_fixes(
        t,
        np.array([r["n_fixed"] for r in rows])[0],
        np.array([r["n_float"] for r in rows])[0],
        out / f"{NAME}-ambiguities.png",
    )
    _plot_sensitivity(sens, out / f"{NAME}-sensitivity.png")
    # The phase precision is the paper's input, simulated as given: the same number exactly.
    doc = write_report(out, NAME, paper, measured, runs, seed, tolerance={"phase_precision_cycles": 1.0})
    print(format_table(doc))
    return doc


def _sensitivity(mc: Any, runs: int) -> dict[str, Any]:
    """Reported vs true attitude sigma (deg, worst axis) at the end of the run over the two sweeps, and a
    Monte Carlo check of the true-error covariance at one point."""

    def sigmas(mis: float, base: float) -> tuple[float, float]:
        r = sensitivity_trial(np.random.default_rng(0), misalignment_deg=mis, baseline_mm=base, draw=False)

        def worst(p: np.ndarray) -> float:
            return math.degrees(math.sqrt(float(np.max(np.diag(p)[:3]))))

        return worst(r["reported"]), worst(r["true"])

    base_sweep = [sigmas(0.0, b) for b in BASELINE_ERRORS_MM]
    mis_sweep = [sigmas(m, 0.0) for m in MISALIGNMENTS_DEG]
    measured: dict[str, Any] = {}
    for b, (rep, tru) in zip(BASELINE_ERRORS_MM, base_sweep, strict=True):
        measured[f"sens_baseline_{b:g}mm_reported_sigma_deg"] = rep
        measured[f"sens_baseline_{b:g}mm_true_sigma_deg"] = tru
    for m, (rep, tru) in zip(MISALIGNMENTS_DEG, mis_sweep, strict=True):
        measured[f"sens_misalignment_{m:g}deg_reported_sigma_deg"] = rep
        measured[f"sens_misalignment_{m:g}deg_true_sigma_deg"] = tru
    mis, base = SENS_MC_POINT
    rows = mc(
        functools.partial(sensitivity_trial, misalignment_deg=mis, baseline_mm=base, draw=True), max(runs, 10)
    )
    err = np.array([r["err"] for r in rows])
    true_var = np.mean([np.diag(r["true"]) for r in rows], axis=0)
    rep_var = np.mean([np.diag(r["reported"]) for r in rows], axis=0)
    tag = f"sens_mc_{mis:g}deg_{base:g}mm"
    measured[f"{tag}_runs"] = len(rows)
    measured[f"{tag}_attitude_rms_deg"] = [math.degrees(float(v)) for v in _rms(err[:, :3], axis=0)]
    measured[f"{tag}_true_sigma_deg"] = [math.degrees(math.sqrt(v)) for v in true_var[:3]]
    measured[f"{tag}_reported_sigma_deg"] = [math.degrees(math.sqrt(v)) for v in rep_var[:3]]
    return {"measured": measured, "baseline": base_sweep, "misalignment": mis_sweep}


def _plot_errors(t: np.ndarray, series: dict[str, dict[str, np.ndarray]], path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(2, 2, figsize=(12, 7), sharex=True)
    for col, mode in enumerate(("loose", "tight")):
        err, sig = series[mode]["err"], series[mode]["sig"]
        for row, (sl, unit, scale) in enumerate(
            ((slice(0, 3), "deg", math.degrees(1.0)), (slice(3, 6), "deg/h", 1.0 / DEG_H))
        ):
            ax = axes[row, col]
            for i, c in enumerate("xyz"):
                # |error| on a log axis beside the 3-sigma envelope: a signed error on a symlog axis drew
                # the three traces as one solid band around zero
                ax.plot(
                    t, np.abs(err[0, :, sl][:, i]) * scale, lw=0.5, alpha=0.8, label=f"|{c} error| (run 0)"
                )
                ax.plot(
                    t,
                    3 * _rms(sig[:, :, sl][:, :, i], axis=0) * scale,
                    "--",
                    lw=1.0,
                    color=f"C{i}",
                    label=f"{c} 3 sigma",
                )
            ax.axvspan(*OUTAGE_S, color="0.85", label="phase outage")
            ax.set_ylabel(f"|{'attitude' if row == 0 else 'drift'} error|, {unit}")
            ax.set_yscale("log")
            ax.set_title(f"{mode}ly coupled")
        axes[1, col].set_xlabel("t, s")
    axes[0, 0].legend(fontsize=7, ncol=2)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def _plot_fixes(t: np.ndarray, n_fixed: np.ndarray, n_float: np.ndarray, path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(10, 3.5))
    ax.step(t, n_fixed, where="post", label="fixed ambiguities")
    ax.step(t, n_float, where="post", label="float ambiguities")
    ax.axvspan(*OUTAGE_S, color="0.85", label="phase outage")
    ax.set_xlabel("t, s")
    ax.set_ylabel("count (run 0)")
    ax.legend()
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def _plot_sensitivity(sens: dict[str, Any], path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 2, figsize=(11, 4))
    for ax, key, grid, label in (
        (axes[0], "baseline", BASELINE_ERRORS_MM, "baseline error sigma, mm"),
        (axes[1], "misalignment", MISALIGNMENTS_DEG, "misalignment sigma, deg"),
    ):
        rep, tru = np.array(sens[key]).T
        ax.plot(grid, tru, "o-", label="true error sigma (covariance analysis)")
        ax.plot(grid, rep, "s--", label="reduced filter's own sigma")
        ax.set_xlabel(label)
        ax.set_ylabel(f"attitude sigma at {SENSITIVITY_S:g} s, deg (worst axis)")
        ax.set_yscale("log")
        ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


EXPERIMENT = Experiment(
    name=NAME,
    summary="Dzhepe Ali: gyro + multi-antenna GNSS, loosely vs tightly coupled, LAMBDA, outage, sensitivity",
    run=run,
    default_runs=20,
    quick_runs=2,
)
