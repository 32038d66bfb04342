"""ML grid versus LAMBDA on the same recorded-data path.

Simulated part: a rotating three-antenna platform (equilateral triangle of 1 m sides in the body X-Z plane,
heading turning 3 deg per epoch, pitch and roll oscillating by a few degrees, 20 epochs at 1 s) above
50 N 36.2 E, GPS L1, code 0.3 m and phase 2 mm white noise, written to RINEX 3 by
:func:`gnssatt.sim.rinex_scenario.simulate_rinex_array` and read back; each trial draws the start time (so the
satellite geometry) and keeps the 5, 6, 7 or 8 highest satellites. Methods, on the same aligned data:
``ml`` (whole-domain grid each epoch; all through
:func:`gnssatt.gnss.attitude.attitude_from_rinex`, GPS L1), ``ml_window`` (+/- 10 deg around the previous
epoch),
``lambda`` (geometry-constrained single-epoch fix; the held variant of attitude mode, ``--continuity``, is
not run here: the GEONET part below holds them).
Per method and satellite count: fraction of epochs with a wrong solution (an Euler angle off by more than
3 deg, i.e. a wrong peak or wrong integers), fix rate (LAMBDA), RMS error of the right solutions, time per
epoch (file reading excluded; the engine's single-point positioning included).

GEONET part (2 stations 3.3 km apart, baseline mode, the pair shipped in :mod:`gnssatt.data`, GPS L1,
through :func:`gnssatt.gnss.attitude.attitude_from_rinex`): static-session LAMBDA (fixed, and the fraction of
epochs fixed), single-epoch LAMBDA and held LAMBDA; errors against the static solution and the header
positions. The ML grid does not run there: its step ``lambda / (10 L)`` is 3.3e-4 deg for 3.3 km,
so the whole domain needs more than the grid's 2^20 nodes per turn (``docs/limits.md``); a window around a
start would hold few (3.7e5 for 0.2 deg), but no start for the first epoch is built (and the grid's planar
wavefront is off by ``L^2 / (2 rho)`` ~ 0.3 m at that length).
"""

from __future__ import annotations

import functools
import tempfile
import time
from concurrent.futures import Executor
from pathlib import Path
from typing import Any

import numpy as np

from gnssatt import montecarlo
from gnssatt.experiments import Experiment
from gnssatt.experiments.report import format_table, write_report

__all__ = ["EXPERIMENT", "geonet", "run", "trial"]

NAME = "recorded-methods"
N_SATS = (5, 6, 7, 8)
METHODS = ("ml", "ml_window", "lambda")
N_EP = 20
WRONG_DEG = 3.0


def _angles_error(a: np.ndarray, truth: np.ndarray) -> np.ndarray:
    worst: np.ndarray = np.max(np.abs((a - truth + 180.0) % 360.0 - 180.0), axis=1)  # np.max is typed Any
    return worst


def trial(rng: np.random.Generator) -> dict[str, float]:
    """One geometry and initial heading; every satellite count and method on it."""
    from gnssatt import sim
    from gnssatt.gnss.attitude import attitude_from_rinex
    from gnssatt.rinex import read_nav, read_obs
    from gnssatt.sim.rinex_scenario import simulate_rinex_array

    ant = sim.equilateral_triangle(1.0, plane="xz")
    body = ant[1:] - ant[0]
    k = np.arange(N_EP)
    psi0 = rng.uniform(-180.0, 180.0)
    euler = np.stack([psi0 + 3.0 * k, 5.0 * np.sin(k / 3.0), 3.0 * np.cos(k / 4.0)], axis=1)
    truth = np.stack([(-euler[:, 0]) % 360.0, euler[:, 1], euler[:, 2]], axis=1)
    start = float(rng.uniform(0.0, 3.5 * 3600.0))  # within the broadcast records' 4 h validity
    row: dict[str, float] = {}
    for n in N_SATS:
        with tempfile.TemporaryDirectory() as folder:
            s = simulate_rinex_array(
                folder, ant, euler, rng=int(rng.integers(2**31)), n_sats=n, start_s=start
            )
            obs, nav = [read_obs(p) for p in s.obs_paths], read_nav(s.nav_path)
        for name in METHODS:
            method = "ml" if name.startswith("ml") else "lambda"
            t0 = time.perf_counter()
            res = attitude_from_rinex(
                obs,
                nav,
                body,
                method=method,  # type: ignore[arg-type]
                window_deg=10.0 if name == "ml_window" else None,
                systems="G",
                frequencies=1,
                elevation_mask_deg=5.0,
            )
            row[f"{name}_n{n}_time_s"] = (time.perf_counter() - t0) / N_EP
            err = _angles_error(res.angles_deg, truth)
            fixed = res.fixed == 1 if method == "lambda" else np.ones(N_EP, dtype=bool)
            ok = fixed & np.isfinite(err)
            row[f"{name}_n{n}_solutions"] = float(ok.sum())
            row[f"{name}_n{n}_wrong"] = float(np.sum(ok & (err > WRONG_DEG)))
            right = ok & (err <= WRONG_DEG)
            row[f"{name}_n{n}_right"] = float(right.sum())
            row[f"{name}_n{n}_sq_err_sum"] = float(np.sum(err[right] ** 2))
    return row


def geonet() -> dict[str, float]:
    """The GEONET pair in baseline mode (module docstring), GPS L1 as the simulated part."""
    from gnssatt.data import geonet_dir
    from gnssatt.frames import dcm_ecef_from_enu, ecef_to_geodetic
    from gnssatt.gnss.attitude import attitude_from_rinex
    from gnssatt.rinex import read_nav, read_obs

    data = geonet_dir()
    a, b = read_obs(data / "07590920.05o"), read_obs(data / "30400920.05o")
    nav = read_nav(data / "07590920.05n")
    lat, lon, _ = ecef_to_geodetic(a.approx_position_m)
    header = (b.approx_position_m - a.approx_position_m) @ dcm_ecef_from_enu(float(lat), float(lon))

    def solve(motion: str, continuity: bool = False) -> tuple[Any, float]:
        t0 = time.perf_counter()
        s = attitude_from_rinex(
            [a, b], nav, method="lambda", motion=motion, continuity=continuity,  # type: ignore[arg-type]
            systems="G", frequencies=1,
        )  # fmt: skip
        return s, (time.perf_counter() - t0) / len(s.time)

    out: dict[str, float] = {}
    st, out["geonet_static_time_s"] = solve("static")
    fixed = st.fixed == 1
    # the session's fixed baseline: the median of the fixed epochs (one solution, repeated)
    ref = np.median(st.baselines_enu_m[fixed, 0], axis=0) if fixed.any() else np.full(3, np.nan)
    out["geonet_static_fixed"] = float(fixed.any())  # the session's ambiguities were fixed
    out["geonet_static_fix_rate"] = float(fixed.mean())  # epochs with every ambiguity fixed
    out["geonet_static_vs_header_m"] = float(np.linalg.norm(ref - header))
    for name, motion, cont in (("single_epoch", "moving", False), ("hold", "moving", True)):
        sol, out[f"geonet_{name}_time_s"] = solve(motion, cont)
        err = np.linalg.norm(sol.baselines_enu_m[:, 0] - ref, axis=1)
        floats = sol.fixed == 0
        out[f"geonet_{name}_fix_rate"] = float(np.mean(sol.fixed == 1))
        out[f"geonet_{name}_success_rate_median"] = float(np.nanmedian(sol.success_rate))
        out[f"geonet_{name}_float_error_median_m"] = float(np.median(err[floats])) if floats.any() else 0.0
    return out


def run(
    *, runs: int, seed: int, out: Path, executor: Executor | None = None, progress: bool = True
) -> dict[str, Any]:
    rows = montecarlo.run(functools.partial(trial), runs, seed=seed, executor=executor, progress=progress)
    measured: dict[str, Any] = {}
    for n in N_SATS:
        for name in METHODS:
            keys = ("solutions", "wrong", "right", "sq_err_sum", "time_s")
            col = {q: np.array([r[f"{name}_n{n}_{q}"] for r in rows]) for q in keys}
            epochs = runs * N_EP
            measured[f"{name}_n{n}_wrong_fraction"] = float(col["wrong"].sum() / epochs)
            if name.startswith("lambda"):
                measured[f"{name}_n{n}_fix_rate"] = float(col["solutions"].sum() / epochs)
            right = col["right"].sum()
            measured[f"{name}_n{n}_rms_error_deg"] = (
                float(np.sqrt(col["sq_err_sum"].sum() / right)) if right else None
            )
            measured[f"{name}_n{n}_time_per_epoch_ms"] = float(1e3 * np.median(col["time_s"]))
    measured |= geonet()
    # no paper gives these numbers: the report has no paper column
    doc = write_report(out, NAME, {}, measured, runs, seed)
    print(format_table(doc))
    return doc


EXPERIMENT = Experiment(
    name=NAME,
    summary="Recorded-data path: ML grid vs LAMBDA on simulated RINEX (5-8 satellites) and the GEONET pair",
    run=run,
    default_runs=25,
    quick_runs=2,
)
