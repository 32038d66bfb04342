"""The public API of gnssatt, discovered from the modules' ``__all__``, and for each function a valid call.

Each :class:`Entry` takes its valid call from ``valid_calls.VALID_CALLS`` (the table the intake tests
share) and builds the keyword arguments of one call that must succeed (``test_inventory`` checks
that it does: the harness's own test). The hostile harness then replaces one argument at a time. An entry
also says which arguments are work counts (``counts``), which values are absurd amounts of work that must be
refused quickly (``work``), and where non-finite values are part of the documented input (``nonfinite_ok``)
or output (``nan_output``).

Excluded modules (``EXCLUDED``): ``gnssatt.cli`` (driven through subprocesses by the CLI cases),
``gnssatt.plots`` (draws files from results of the functions here) and ``gnssatt.experiments`` (the papers'
reproductions, reached through ``gnssatt reproduce``).
"""

from __future__ import annotations

import importlib
import inspect
import pkgutil
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from typing import Any

from valid_calls import VALID_CALLS

import gnssatt

# Searched first, so that a function re-exported in several places is known by its most public name.
PREFERRED = (
    "gnssatt",
    "gnssatt.magnetic",
    "gnssatt.sim",
    "gnssatt.orbit",
    "gnssatt.orbit.determination",
    "gnssatt.attitude.dynamics",
    "gnssatt.rinex",
    "gnssatt.montecarlo",
    "gnssatt.attitude.visibility",
    "gnssatt.rotation",
    "gnssatt.geometry",
)
EXCLUDED = ("gnssatt.cli", "gnssatt.plots", "gnssatt.experiments")

WORK_TINY_STEP = (1e-300, 1e-9)  # integration steps: 1e300 and 1e9+ steps per second of span


@dataclass(frozen=True)
class Entry:
    """A valid call of one public function and what its arguments mean to the harness.

    Attributes
    ----------
    build
        Returns fresh valid keyword arguments (``valid_calls.VALID_CALLS[name]``); only these are mutated
        (others keep their defaults).
    counts
        Integer arguments that size work or memory: get the overflow-size counts.
    work
        Per argument, absurd values (tiny steps, huge spans) that must be refused before the work starts.
    nonfinite_ok
        Arguments where NaN/inf is documented input (e.g. missing observations).
    nan_output
        Why the result may hold NaN (documented "not available" fields), or None: all outputs must be finite.
    nan_fields
        Result attributes documented as possibly non-finite (the rest is checked).
    free_text
        Text arguments where any (short, printable) text is valid, such as a marker name: no invalid-name
        or empty-text mutants.
    complex_ok
        Arguments where complex values are documented input (e.g. correlator outputs).
    """

    build: Callable[[], dict[str, Any]]
    counts: frozenset[str] = frozenset()
    work: Mapping[str, tuple[Any, ...]] = field(default_factory=dict)
    nonfinite_ok: frozenset[str] = frozenset()
    nan_output: str | None = None
    nan_fields: frozenset[str] = frozenset()
    free_text: frozenset[str] = frozenset()
    complex_ok: frozenset[str] = frozenset()


def _e(**kw: Any) -> dict[str, Any]:
    for key in ("counts", "nonfinite_ok", "nan_fields", "free_text", "complex_ok"):
        if key in kw:
            kw[key] = frozenset(kw[key])
    return kw


# Per function with arguments of a special meaning to the harness (a key of ``valid_calls.VALID_CALLS``).
META: dict[str, dict[str, Any]] = {
    # --- gnssatt (estimators, ambiguities) ---
    "gnssatt.lambda_ils": _e(counts={"candidates"}),
    "gnssatt.lambda_ils_batch": _e(counts={"candidates"}),
    "gnssatt.ratio_test": _e(
        counts={"samples"},
        nan_fields={"ratio"},  # inf when the best squared norm is 0 (integer float vector), documented
    ),
    "gnssatt.partial_fix": _e(
        counts={"samples"},
        nan_fields={"ratio", "threshold"},  # NaN when nothing is fixed, ratio inf on integers: documented
    ),
    "gnssatt.ratio_threshold_fixed_failure_rate": _e(counts={"samples"}),
    "gnssatt.ml_attitude_series": _e(
        nonfinite_ok={"sd_phase", "los", "wavelength"},  # NaN marks absent signals, documented
        nan_fields={"euler_gost_deg", "z_max"},  # NaN at unsolved epochs, flagged by solved
    ),
    "gnssatt.ml_baseline_series": _e(
        nonfinite_ok={"sd_phase", "los", "wavelength"},  # NaN marks absent signals, documented
        nan_fields={"heading_deg", "elevation_deg", "direction_enu", "z_max"},  # unsolved epochs
    ),
    "gnssatt.gyro_gnss_filter": _e(counts={"output_every"}),
    "gnssatt.fit_rotation": _e(
        counts={"max_restarts", "popsize", "maxiter", "patience"},
        work={"step_s": WORK_TINY_STEP},
        nan_fields={"cost_threshold"},  # inf when axis_sigma_deg is None (no restart test), documented
    ),
    # --- gnssatt.magnetic ---
    "gnssatt.magnetic.igrf_field_ecef": _e(counts={"max_degree"}),
    # --- gnssatt.sim ---
    "gnssatt.sim.phase_diffs": _e(
        complex_ok={"phases"},  # complex correlator outputs are documented input
    ),
    "gnssatt.sim.random_attitude": _e(counts={"n"}),
    "gnssatt.sim.random_los": _e(counts={"n_sat"}),
    "gnssatt.sim.simulate_array": _e(counts={"ambiguity_max"}),
    **{f"gnssatt.sim.{name}": _e(counts={"n_antennas"}) for name in ("car", "ship", "aircraft")},
    "gnssatt.sim.simulate_spaceborne": _e(
        nan_output="measurements of satellites out of view are NaN, flagged by visible"
    ),
    "gnssatt.sim.solve_kepler": _e(counts={"max_iter"}),
    "gnssatt.sim.walker": _e(counts={"n_sat", "n_planes"}),
    # --- gnssatt.orbit ---
    "gnssatt.orbit.glonass_propagate": _e(work={"step_s": WORK_TINY_STEP, "duration_s": (1e12, 1e300)}),
    # --- gnssatt.orbit.determination ---
    "gnssatt.orbit.determination.noisy_orbit": _e(work={"step_s": WORK_TINY_STEP}),
    "gnssatt.orbit.determination.orbit_filter": _e(work={"step_s": WORK_TINY_STEP}),
    "gnssatt.orbit.determination.receiver_fix": _e(
        nan_output="invalid epochs' fixes are NaN, flagged by valid"
    ),
    # --- gnssatt.attitude.dynamics ---
    "gnssatt.attitude.dynamics.axis_cost": _e(work={"step_s": WORK_TINY_STEP}),
    "gnssatt.attitude.dynamics.noise_cost_threshold": _e(counts={"n_epochs"}),
    "gnssatt.attitude.dynamics.propagate": _e(work={"step_s": WORK_TINY_STEP}),
    "gnssatt.attitude.dynamics.propagate_axes": _e(work={"step_s": WORK_TINY_STEP}),
    # --- gnssatt.rinex ---
    "gnssatt.rinex.read_obs": _e(nan_output="missing observations are NaN"),
    "gnssatt.rinex.read_nav": _e(nan_output="absent header Klobuchar coefficients are NaN"),
    "gnssatt.gnss.attitude.attitude_from_rinex": _e(
        nan_output="epochs without a solution are NaN, flagged in the series"
    ),
    "gnssatt.position_from_rinex": _e(nan_output="epochs without a solution are NaN, flagged in the series"),
    "gnssatt.rinex.write_obs": _e(
        nonfinite_ok={"observations"},
        free_text={"marker_name"},
    ),
    "gnssatt.sim.rinex_scenario.simulate_rinex_array": _e(counts={"n_sats"}),
    "gnssatt.sim.rinex_scenario.simulate_gnss_rinex": _e(counts={"n_epochs", "n_sats"}),
    "gnssatt.rinex.nav.nav_input": _e(
        nan_output="group delays, fit interval and data source are NaN where a system has none"
    ),
    "gnssatt.gnss.session_input.session_input": _e(
        nan_output="absent observations (slots, satellites, epochs) are NaN"
    ),
    # --- gnssatt.montecarlo ---
    "gnssatt.montecarlo.run": _e(counts={"n_trials", "chunksize"}),
    "gnssatt.montecarlo.trial_generators": _e(counts={"n_trials"}),
    # --- gnssatt.attitude.visibility ---
    # --- gnssatt.rotation, gnssatt.geometry ---
}
ENTRIES: dict[str, Entry] = {name: Entry(build, **META.get(name, {})) for name, build in VALID_CALLS.items()}


def public_modules() -> list[str]:
    """Every importable gnssatt module without an underscore in its path, outside ``EXCLUDED``,
    ``PREFERRED`` first."""
    found = [m.name for m in pkgutil.walk_packages(gnssatt.__path__, "gnssatt.")]
    rest = sorted(
        m
        for m in found
        if not any(part.startswith("_") for part in m.split("."))
        and not any(m == x or m.startswith(x + ".") for x in EXCLUDED)
        and m not in PREFERRED
    )
    return [*PREFERRED, *rest]


def public_functions() -> dict[str, Callable[..., Any]]:
    """Qualified name -> function, for every function in a public module's ``__all__`` (or, without one,
    every public name it defines); a function exported in several places is named once, where first
    found in :func:`public_modules` order."""
    seen: dict[int, str] = {}
    out: dict[str, Callable[..., Any]] = {}
    for name in public_modules():
        mod = importlib.import_module(name)
        names = getattr(mod, "__all__", None)
        if names is None:
            names = [
                n
                for n, v in vars(mod).items()
                if not n.startswith("_") and getattr(v, "__module__", "") == name
            ]
        for attr in names:
            obj = getattr(mod, attr)
            if inspect.isroutine(obj) and id(obj) not in seen:
                seen[id(obj)] = f"{name}.{attr}"
                out[f"{name}.{attr}"] = obj
    return out
