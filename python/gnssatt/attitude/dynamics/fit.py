"""The fit of the tumble model's initial state to axis directions (eq. (1)): differential evolution on long
RK4 steps, polished at the requested step, restarted while the objective exceeds what the axis noise
explains (:func:`noise_cost_threshold`)."""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any, Literal, TypedDict

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.optimize import differential_evolution, minimize
from scipy.spatial.transform import Rotation
from scipy.stats import chi2

from gnssatt import _core
from gnssatt._arrays import (
    finite_result,
    integer,
    scalar,
    text,
    vector_array,
)
from gnssatt.attitude.dynamics._intake import (
    checked_times,
    checked_work,
    default_model,
    grid_steps,
)
from gnssatt.attitude.dynamics.model import (
    DCM_ORBITAL_FROM_ORB0,
    MAX_RATE_RAD_S,
    TumbleModel,
)
from gnssatt.attitude.dynamics.propagation import propagate_axes
from gnssatt.errors import InvalidInputError, InvalidTypeError, WorkLimitError

# Fewest epochs accepted by the fit: six unknowns, two independent components per axis direction.
MIN_EPOCHS = 3
#: Rotation per RK4 step of the fit's global search at the search box's fastest rate, rad (see
#: ``search_step_s`` of :func:`fit_rotation`): RK4's local error ``(omega h)^5 / 120`` is 1.5e-4 rad.
SEARCH_TURN_RAD = 0.45
#: Most differential-evolution generations per run, population multiplier and restarts of
#: :func:`fit_rotation`.
MAX_GENERATIONS = 100_000
MAX_POPSIZE = 1_000
MAX_RESTARTS = 100
#: Most RK4 steps of one :func:`fit_rotation` at its generation cap, all runs together (about 20 minutes
#: of one core; the default settings on 1500 one-second epochs need 5.4e8).
MAX_FIT_RK4_STEPS = 10_000_000_000


def noise_cost_threshold(n_epochs: int, axis_sigma_deg: float, false_restart: float = 1e-3) -> float:
    """Objective (1) that the true state exceeds with probability at most ``false_restart``.

    For measured axes tilted from the true ones by independent Gaussian tangent-plane errors of
    ``sigma = axis_sigma_deg`` per component (the paper's "3 sigma = 15 deg" is ``sigma = 5 deg``), the
    measured axis is ``(a + d1 e1 + d2 e2) / sqrt(1 + r^2)`` with ``r^2 = d1^2 + d2^2 ~ sigma^2 chi2(2)``,
    so each term of (1) is ``|a - m|^2 = 2 - 2 / sqrt(1 + r^2) <= r^2``. The objective at the truth is
    therefore at most ``sigma^2 chi2(2 n)``, and the global minimum lies at or below it: a fit whose
    objective is above ``sigma^2 * chi2.ppf(1 - false_restart, 2 n)`` is (but for probability
    ``false_restart``) not the global minimum. The bound is conservative by the neglected ``3 r^4 / 4``
    term, about 2 % of the objective at 5 deg, i.e. half a standard deviation for 1501 epochs.

    Parameters
    ----------
    n_epochs
        Number of measured axes, 1 to 1e12.
    axis_sigma_deg
        Per-component standard deviation of the axis error, degrees, in (0, 180].
    false_restart
        Probability that the truth itself lies above the threshold, in (0, 1).

    Returns
    -------
    float
        The threshold on objective (1), dimensionless (rad^2 of tangent-plane error).

    Raises
    ------
    InvalidInputError
        ``n_epochs`` not in [1, 1e12], ``axis_sigma_deg`` not in (0, 180], ``false_restart`` not in (0, 1)
        (:class:`~gnssatt.errors.InvalidTypeError` for values that are not numbers of the right kind).

    Examples
    --------
    For one epoch ``chi2(2)`` is exponential with mean 2, so its upper quantile is ``-2 ln(false_restart)``:

    >>> import math
    >>> from gnssatt.attitude.dynamics import noise_cost_threshold
    >>> round(noise_cost_threshold(1, 1.0, 1e-3), 9)
    0.004208445
    >>> round(math.radians(1.0) ** 2 * -2.0 * math.log(1e-3), 9)
    0.004208445
    """
    n_epochs = integer("n_epochs", n_epochs, minimum=1)
    if n_epochs > 10**12:  # beyond scipy's chi-square quantile (and any measurement campaign)
        raise InvalidInputError(f"expected n_epochs <= 1e12, got {n_epochs}")
    sigma = scalar("axis_sigma_deg", axis_sigma_deg, minimum=0.0, strict=True)
    sigma = scalar("axis_sigma_deg", sigma, maximum=180.0, unit="deg")
    p = scalar("false_restart", false_restart)
    if not 0.0 < p < 1.0:
        raise InvalidInputError(f"expected false_restart in (0, 1), got {false_restart!r}")
    return math.radians(sigma) ** 2 * float(chi2.isf(p, 2 * int(n_epochs)))


@dataclass(frozen=True)
class RotationFit:
    """Result of :func:`fit_rotation`.

    Attributes
    ----------
    params
        (6,) fitted ``(psi, alpha, phi, wx, wy, wz)`` at ``t = 0`` (rad, rad/s).
    cost
        Objective (1) at ``params`` (sum of squared unit-vector differences, dimensionless).
    nfev
        Objective evaluations (one per propagated initial state), all runs together.
    nit
        Differential-evolution generations, all runs together.
    stopped_by
        How the best run (its first window for a "horizon" restart) stopped: ``"paper"`` (population-mean
        objective changed by less than ``tol_abs``), ``"settled"`` (population within ``settle``),
        ``"maxiter"`` or ``"scipy"`` (scipy's own test).
    residual_rms_deg
        RMS angle between fitted and measured axes, degrees.
    attempt_params, attempt_costs
        (k, 6) best state and (k,) objective of each differential-evolution run, the first run first;
        ``k - 1`` restarts were made (see ``max_restarts`` of :func:`fit_rotation`).
    cost_threshold
        The objective above which a run was restarted (:func:`noise_cost_threshold`); ``inf`` when no
        ``axis_sigma_deg`` was given.
    euler_yzy_deg
        (3,) ``params[:3]`` in degrees: precession psi, attack alpha, spin phi of the intrinsic ``YZY``
        sequence from the paper's orbital frame ``X0 Y0 Z0`` (``docs/conventions.md``, Belokonov et al.), not
        of
        ``rotation``'s frame.
    omega_deg_s
        (3,) ``params[3:]``, body rates in deg/s.
    """

    params: NDArray[np.float64]
    cost: float
    nfev: int
    nit: int
    stopped_by: str
    residual_rms_deg: float
    attempt_params: NDArray[np.float64]
    attempt_costs: NDArray[np.float64]
    cost_threshold: float
    euler_yzy_deg: NDArray[np.float64] = field(init=False)
    omega_deg_s: NDArray[np.float64] = field(init=False)

    def __post_init__(self) -> None:
        object.__setattr__(self, "euler_yzy_deg", np.degrees(self.params[:3]))
        object.__setattr__(self, "omega_deg_s", np.degrees(self.params[3:]))

    @property
    def rotation(self) -> Rotation:
        """Body -> library orbital frame at ``t = 0``."""
        return Rotation.from_matrix(DCM_ORBITAL_FROM_ORB0) * Rotation.from_euler("YZY", self.params[:3])


class _Objective:
    """Vectorised objective for scipy: x (6, S) -> (S,), counting evaluations and tracking the population.

    With ``updating="deferred"`` scipy calls it once with the initial population and then once per
    generation with the trial vectors, trial ``i`` competing with member ``i``; the population's energies
    are therefore ``min(previous, trial)`` elementwise, from which the paper's rule is evaluated.
    """

    def __init__(
        self, t: NDArray[np.float64], measured: NDArray[np.float64], model: TumbleModel, step_s: float
    ):
        self.t, self.measured, self.model, self.step_s = t, measured, model, step_s
        self.kwargs = model._kwargs()
        self.nfev = 0
        self.population: NDArray[np.float64] | None = None
        self.means: list[float] = []

    def __call__(self, x: NDArray[np.float64]) -> NDArray[np.float64]:
        batch = np.ascontiguousarray(np.atleast_2d(x.T) if x.ndim == 2 else x[None, :])
        cost = _core.tumble_cost(batch, self.t, self.measured, self.kwargs, step_s=self.step_s)
        # A trial whose integration diverged (Nelder-Mead may leave the search box's rates) is infinitely
        # bad, never a NaN that the optimisers would compare wrongly.
        cost = np.where(np.isfinite(cost), cost, np.inf)
        self.nfev += len(batch)
        if x.ndim == 2 and batch.shape[0] > 1:
            if self.population is None or self.population.shape != cost.shape:
                self.population = cost.copy()
            else:
                self.population = np.minimum(self.population, cost)
            self.means.append(float(np.mean(self.population)))
        return cost if x.ndim == 2 else cost[0]

    def value_and_gradient(
        self, x: NDArray[np.float64], lower: NDArray[np.float64], upper: NDArray[np.float64]
    ) -> tuple[float, NDArray[np.float64]]:
        """Objective at ``x`` (6,) and its forward-difference gradient, the seven states in one core call
        (two packs of four lanes instead of seven one-state calls).

        The steps are those of scipy's L-BFGS-B without a ``jac`` (``approx_derivative``, ``2-point``,
        absolute step ``eps = 1e-8``; ``sqrt(eps_f64) * sign(x) * max(1, |x|)`` where ``x + 1e-8 == x``),
        reversed where they would leave ``[lower, upper]``, the difference divided by the step as
        represented: L-BFGS-B takes the same path as with its own finite differences.
        """
        rel = math.sqrt(np.finfo(np.float64).eps) * np.where(x >= 0, 1.0, -1.0) * np.maximum(1.0, np.abs(x))
        h = np.where((x + LBFGSB_EPS) - x == 0, rel, LBFGSB_EPS)
        ahead = x + h
        flip = ((ahead < lower) | (ahead > upper)) & (np.abs(h) <= np.maximum(x - lower, upper - x))
        h = np.where(flip, -h, h)
        steps = np.diag(h)
        points = np.vstack([x, x + steps])
        batch = np.ascontiguousarray(points)
        cost = _core.tumble_cost(batch, self.t, self.measured, self.kwargs, step_s=self.step_s)
        cost = np.where(np.isfinite(cost), cost, np.inf)
        self.nfev += len(batch)
        dx = np.diagonal(points[1:]) - x
        return float(cost[0]), (cost[1:] - cost[0]) / dx


# scipy's default absolute finite-difference step of L-BFGS-B (its ``eps`` option).
LBFGSB_EPS = 1e-8
# Restart k of the "horizon" kind fits the first HORIZON_FRACTIONS[(k - 1) % 3] of the span by differential
# evolution, then refines over windows doubling up to the whole span.
HORIZON_FRACTIONS = (0.1, 0.2, 0.05)
# Fewest epochs in the first window of a "horizon" restart.
MIN_HORIZON_EPOCHS = 20


def _canonical(params: NDArray[np.float64]) -> NDArray[np.float64]:
    """The same state with ``psi, phi in [0, 2 pi)``, ``alpha in [0, pi]`` (``YZY`` angles are 2-to-1)."""
    angles = Rotation.from_euler("YZY", params[:3]).as_euler("YZY") % (2 * math.pi)
    angles[1] = min(angles[1], 2 * math.pi - angles[1])  # as_euler gives [0, pi]; guard a rounded 2 pi
    state: NDArray[np.float64] = np.r_[angles, params[3:]]  # scipy is untyped, so angles are Any
    return state


class _DeOptions(TypedDict):
    """The differential-evolution settings of :func:`fit_rotation`, checked."""

    popsize: int
    mutation: float | tuple[float, float]
    recombination: float
    strategy: str
    tol_abs: float
    patience: int
    settle: float
    maxiter: int
    polish: bool


def _de_run(
    obj: _Objective, bounds: list[tuple[float, float]], seed: Any, opts: _DeOptions
) -> tuple[NDArray[np.float64], float, int, str]:
    """One differential-evolution run with the paper's stopping rule, or stopped once the population has
    settled (``opts["settle"]``), unpolished: (x, cost, generations, stopped_by)."""
    obj.population, obj.means = None, []
    stopped = {"by": "maxiter"}
    tol_abs, patience, settle = opts["tol_abs"], opts["patience"], opts["settle"]

    def callback(intermediate_result: Any) -> None:
        pop = obj.population
        # Every member within `settle` of the best: the population has gathered in one basin, where the
        # polish finishes faster than further generations (which only shrink the spread).
        if settle > 0 and pop is not None and np.max(pop) - np.min(pop) <= settle * np.min(pop):
            stopped["by"] = "settled"
            raise StopIteration
        recent = np.abs(np.diff(obj.means[-(patience + 1) :]))
        if len(recent) >= patience and np.all(recent < tol_abs):
            stopped["by"] = "paper"
            raise StopIteration

    res = differential_evolution(
        obj,
        bounds,
        popsize=opts["popsize"],
        mutation=opts["mutation"],
        recombination=opts["recombination"],
        strategy=opts["strategy"],
        seed=seed,
        maxiter=opts["maxiter"],
        tol=0.0,
        atol=0.0,
        polish=False,
        vectorized=True,
        updating="deferred",
        callback=callback,
        init="sobol",
    )
    if stopped["by"] == "maxiter" and res.success:
        stopped["by"] = "scipy"
    return np.asarray(res.x, dtype=np.float64), float(res.fun), int(res.nit), stopped["by"]


def _horizon_run(
    obj: _Objective, bounds: list[tuple[float, float]], seed: Any, opts: _DeOptions, fraction: float
) -> tuple[NDArray[np.float64], int, str]:
    """Differential evolution on the first ``fraction`` of the span, then Nelder-Mead over doubling windows.

    Over a short window the axis history depends smoothly on the state and the global basin is wide;
    each doubling starts inside the next window's basin. Returns (x, generations, stopped_by of the
    first window's run); the last window is the whole span.
    """
    t, m = obj.t, obj.measured
    span = t[-1] - t[0]
    end = t[0] + fraction * span
    n = max(int(np.searchsorted(t, end, side="right")), min(MIN_HORIZON_EPOCHS, t.size))
    window = _Objective(t[:n], m[:n], obj.model, obj.step_s)
    x, _, nit, stopped = _de_run(window, bounds, seed, opts)
    obj.nfev += window.nfev
    while n < t.size:
        end = t[0] + 2 * (t[n - 1] - t[0])
        n = max(int(np.searchsorted(t, end, side="right")), min(2 * n, t.size))
        part = _Objective(t[:n], m[:n], obj.model, obj.step_s)
        # A window short of the whole span only has to hand the next one a start in its basin: its
        # simplex stops at 1e-4 in the objective instead of the last window's 1e-7.
        tight = n >= t.size
        options = {"maxfev": 4000, "xatol": 1e-8 if tight else 1e-6, "fatol": 1e-7 if tight else 1e-4}
        res = minimize(part, x, method="Nelder-Mead", options=options)
        obj.nfev += part.nfev
        x = np.asarray(res.x, dtype=np.float64)
    return x, nit, stopped


def _polished(
    obj: _Objective, x: NDArray[np.float64], polish: bool, max_rate: float
) -> tuple[NDArray[np.float64], float]:
    """``x`` refined by L-BFGS-B on ``obj`` (the fit's objective, at its RK4 step) when ``polish``, in the
    canonical angle ranges, with its objective.

    The rates keep to the search box (an unbounded line search can try rates that no step resolves);
    the angles are free, so that a minimum near 0 or 2 pi is not clipped.
    """
    if polish:
        rates = np.clip(x[3:], -max_rate, max_rate)
        bounds = [(None, None)] * 3 + [(-max_rate, max_rate)] * 3
        lower = np.r_[[-np.inf] * 3, [-max_rate] * 3]
        upper = -lower

        def fun(p: NDArray[np.float64]) -> tuple[float, NDArray[np.float64]]:
            return obj.value_and_gradient(np.asarray(p, dtype=np.float64), lower, upper)

        res = minimize(fun, np.r_[x[:3], rates], method="L-BFGS-B", jac=True, bounds=bounds)
        if np.isfinite(res.fun) and res.fun <= float(obj(x)):
            x = np.asarray(res.x, dtype=np.float64)
    x = _canonical(x)
    return x, float(obj(x))


def _checked_axes(tt: NDArray[np.float64], measured_axes: ArrayLike) -> NDArray[np.float64]:
    """The (n_t, 3) measured axes as unit rows; any scale of a row is the same direction."""
    m = vector_array("measured_axes", measured_axes, ndim=2, shape="(n_t, 3)")
    if m.shape != (tt.size, 3):
        raise InvalidInputError(f"expected measured_axes of shape ({tt.size}, 3), got {m.shape}")
    if tt.size < MIN_EPOCHS:
        raise InvalidInputError(f"expected at least {MIN_EPOCHS} epochs to fit 6 parameters, got {tt.size}")
    with np.errstate(over="ignore"):  # an infinite norm is rescaled below
        norm = np.linalg.norm(m, axis=1)
    if np.any(norm < 1e-9):
        raise InvalidInputError(f"measured_axes row {int(np.argmin(norm))} is zero")
    scale = np.max(np.abs(m), axis=1, keepdims=True)  # directions only: rescaled first so no norm overflows
    m = m / scale
    norm = np.linalg.norm(m, axis=1)
    return np.ascontiguousarray(m / norm[:, None])


def _checked_rng(
    rng: int | np.random.Generator | np.random.SeedSequence | None,
) -> int | np.random.Generator | np.random.SeedSequence | None:
    if rng is not None and not isinstance(rng, np.random.Generator | np.random.SeedSequence):
        rng = integer("rng", rng, minimum=0)
        if rng > 2**32 - 1:  # scipy's integer seeds; a SeedSequence takes any entropy
            raise InvalidInputError(
                f"expected rng in [0, 2**32 - 1], a numpy Generator or SeedSequence, or None, got {rng}"
            )
    return rng


def _checked_mutation(mutation: float | tuple[float, float]) -> float | tuple[float, float]:
    """scipy's weight F, or a (low, high) pair that dithers it."""
    if isinstance(mutation, tuple | list):
        if len(mutation) != 2:
            raise InvalidInputError(f"expected mutation as F or a (low, high) pair, got {mutation!r}")
        lo, hi = (scalar(f"mutation[{k}]", f, minimum=0.0) for k, f in enumerate(mutation))
        if not lo < hi < 2.0:
            raise InvalidInputError(
                f"expected mutation (low, high) with 0 <= low < high < 2, got {mutation!r}"
            )
        return (lo, hi)
    f = scalar("mutation", mutation, minimum=0.0)
    if f >= 2.0:
        raise InvalidInputError(f"expected mutation in [0, 2), got {f}")
    return f


def _check_fit_work(tt: NDArray[np.float64], step_s: float, opts: _DeOptions, max_restarts: int) -> None:
    """Refuses a fit whose runs at their generation cap (every run, every generation, the whole
    population, at the shorter of the two steps) would take more than ``MAX_FIT_RK4_STEPS``."""
    per_state = grid_steps(tt, step_s)
    total = (opts["maxiter"] + 1) * opts["popsize"] * 6 * (max_restarts + 1) * per_state
    if total > MAX_FIT_RK4_STEPS:
        raise WorkLimitError(
            f"fit_rotation may need {total:.3g} RK4 steps ((maxiter + 1) * popsize * 6 * (max_restarts + 1) "
            f"propagations of {per_state:.3g} steps), beyond the limit of {MAX_FIT_RK4_STEPS:.3g}; lower "
            "maxiter, popsize or max_restarts, or use a longer step_s"
        )


def _run_generators(
    rng: int | np.random.Generator | np.random.SeedSequence | None, n_spawn: int
) -> tuple[np.random.Generator | int | None, list[np.random.Generator]]:
    """The first run's randomness and the restarts' generators. An integer seeds scipy's first run
    directly and roots the restarts' SeedSequence, as the former ``seed=`` did, so that fits (and the
    visibility-rotation figures) keep their numbers."""
    if isinstance(rng, np.random.Generator):
        return rng, rng.spawn(n_spawn)
    root = rng if isinstance(rng, np.random.SeedSequence) else np.random.SeedSequence(rng)
    first = np.random.default_rng(root) if isinstance(rng, np.random.SeedSequence) else rng
    return first, [np.random.default_rng(c) for c in root.spawn(n_spawn)]


def _de_options(
    popsize: int, mutation: float | tuple[float, float], recombination: float, strategy: str, tol_abs: float,
    patience: int, settle: float, maxiter: int, polish: bool,
) -> _DeOptions:  # fmt: skip
    """The differential evolution's settings of :func:`fit_rotation`, checked (``strategy`` and ``polish``
    are checked by the caller)."""
    return {
        "popsize": integer("popsize", popsize, minimum=1, maximum=MAX_POPSIZE),
        "mutation": _checked_mutation(mutation),
        "recombination": scalar("recombination", recombination, minimum=0.0, maximum=1.0),
        "strategy": strategy,
        "tol_abs": scalar("tol_abs", tol_abs, minimum=0.0),
        "patience": integer("patience", patience, minimum=1, maximum=MAX_GENERATIONS),
        "settle": scalar("settle", settle, minimum=0.0),
        "maxiter": integer("maxiter", maxiter, minimum=1, maximum=MAX_GENERATIONS),
        "polish": polish,
    }


def _runs(
    obj: _Objective, search: _Objective, w: float,
    rng: int | np.random.Generator | np.random.SeedSequence | None, n_restarts: int, min_restarts: int,
    threshold: float, restart: str, opts: _DeOptions,
) -> list[tuple[NDArray[np.float64], float, int, str]]:  # fmt: skip
    """The first search and its restarts (at most ``n_restarts``; past ``min_restarts`` they stop once a
    run's cost is at most ``threshold``): each run's polished state, cost, generations and why it stopped.

    The search runs at the search objective's step; each run's result is polished and compared with
    ``obj`` (rates bounded by ``w`` rad/s on each axis).
    """
    bounds = [(0.0, 2 * math.pi), (0.0, math.pi), (0.0, 2 * math.pi), (-w, w), (-w, w), (-w, w)]
    first, restarts = _run_generators(rng, n_restarts)
    runs: list[tuple[NDArray[np.float64], float, int, str]] = []
    for k, run_rng in enumerate([first, *restarts]):
        if k > min_restarts and min(r[1] for r in runs) <= threshold:
            break
        if k == 0 or restart == "fresh":
            x, _, nit, stopped = _de_run(search, bounds, run_rng, opts)
        else:
            fraction = HORIZON_FRACTIONS[(k - 1) % len(HORIZON_FRACTIONS)]
            x, nit, stopped = _horizon_run(search, bounds, run_rng, opts, fraction)
        runs.append((*_polished(obj, x, opts["polish"], w), nit, stopped))
    return runs


def fit_rotation(
    t: ArrayLike,
    measured_axes: ArrayLike,
    model: TumbleModel | None = None,
    *,
    rng: int | np.random.Generator | np.random.SeedSequence | None = None,
    axis_sigma_deg: float | None = None,
    max_restarts: int = 3,
    min_restarts: int = 0,
    false_restart: float = 1e-3,
    restart: Literal["horizon", "fresh"] = "horizon",
    popsize: int = 15,
    mutation: float | tuple[float, float] = (0.5, 1.0),
    recombination: float = 0.9,
    strategy: str = "best1bin",
    tol_abs: float = 1e-3,
    patience: int = 20,
    settle: float = 0.003,
    maxiter: int = 1000,
    max_rate_rad_s: float = MAX_RATE_RAD_S,
    polish: bool = True,
    step_s: float = 1.0,
    search_step_s: float | None = None,
) -> RotationFit:
    """Fit the initial state to measured antenna axes by differential evolution (Belokonov et al., eq. (1)).

    Parameters
    ----------
    t
        (n_t,) measurement times, s from the initial epoch (non-decreasing, >= 0), ``n_t >= 3``.
    measured_axes
        (n_t, 3) measured antenna axes in the library orbital frame (normalised here).
    model
        :class:`TumbleModel`; default ``TumbleModel.circular()``.
    rng
        Randomness of the optimiser: an integer in [0, 2**32 - 1] (the same integer, the same fit), a
        ``numpy.random.Generator`` (used and advanced), a ``numpy.random.SeedSequence`` or None (fresh
        entropy). The first run uses an integer as scipy's ``seed`` (a Generator or a SeedSequence's
        Generator as given); restart ``k`` draws from the ``k``-th child of ``SeedSequence(rng)`` (of a
        Generator: its ``k``-th spawned child).
    axis_sigma_deg
        Per-component standard deviation of the measured axes' tangent-plane error, degrees (5 for the
        paper's "3 sigma = 15 deg"). When given, a run whose objective lies above
        :func:`noise_cost_threshold` ``(n_t, axis_sigma_deg, false_restart)`` -- more than the measurement
        noise can explain, so a local minimum -- is followed by a fresh run, up to ``max_restarts``
        times; the best run is returned. ``None``: one run.
    max_restarts
        Most restarts, >= 0.
    min_restarts
        Restarts run whatever the first run's objective, ``0 <= min_restarts <= max_restarts`` (also
        without ``axis_sigma_deg``): a local minimum whose objective lies within the noise spread of the
        global one passes the threshold (how often, in ``docs/results/visibility_rotation.md``, "The
        settings of fit_rotation"). The best objective is returned.
    restart
        ``"horizon"`` (default): each restart runs differential evolution (same settings, next seed) on
        the first 10, 20 or 5 % of the span only, where the global basin is wide, then refines by
        Nelder-Mead over windows doubling up to the whole span. ``"fresh"``: each restart repeats the
        first run with the next seed (it tends to fall into the same wrong minimum). The Nelder-Mead
        simplex of a window short of the whole span stops at 1e-4 in the objective (the last window's at
        1e-7): it only has to start the next window in its basin.
    false_restart
        Probability that a fit at the global minimum is restarted all the same (the threshold's tail).
    popsize, mutation, recombination
        scipy's population multiplier (``popsize * 6`` members, the paper's N), weight F (dithered
        when a tuple) and crossover probability P.
    strategy
        scipy's mutation strategy. ``"rand1bin"`` is the paper's ``b_m = b1 + F (b2 - b3)`` with random
        ``b1``; scipy's ``"best1bin"`` is the default (why, in the results page above).
    tol_abs
        The paper's stopping rule: stop when the population-mean objective changes by less than
        ``tol_abs`` between consecutive generations (0.001 in the paper), here required over ``patience``
        consecutive generations: read literally (``patience=1``) the rule fires on the first generation
        in which no trial vector wins, long before the population has converged.
    patience
        Consecutive generations over which the ``tol_abs`` rule must hold, 1 <= patience <=
        ``MAX_GENERATIONS``.
    settle
        Relative spread, >= 0, at which a run also stops: once every member's objective lies within
        ``settle`` times the best one's (``max - min <= settle * min``) the population has gathered in
        one basin, and the polish (``polish=True``) finishes the minimum faster than further
        generations. ``0`` leaves the paper's rule alone (what the default saves, in
        ``docs/results/visibility-rotation-timing.md``).
    maxiter
        Generation cap per run.
    max_rate_rad_s
        Search box for each rate component, rad/s (3 deg/s: the paper's bound); angles span
        ``psi, phi in [0, 2 pi]``, ``alpha in [0, pi]``.
    polish
        Finish each run with an L-BFGS-B refinement of its best state on the objective at ``step_s``
        (forward-difference gradient, its seven states in one core call).
    step_s
        RK4 step of the objective that is minimised and reported (``cost``, the threshold test), s.
    search_step_s
        RK4 step of the global search (the differential evolution and a restart's windows), s. ``None``:
        the step that turns the fastest state of the search box by ``SEARCH_TURN_RAD`` (0.45 rad), but
        no shorter than ``step_s``: 4.8 s for the 3 deg/s box. The search only has to reach the global
        basin, and the polish on the objective at ``step_s`` removes the longer step's error from the
        result (measured in ``docs/results/visibility-rotation-timing.md``, "Search step").

    Returns
    -------
    RotationFit
        The best run's initial state, its objective and residual, and every run's state and objective.

    Raises
    ------
    InvalidInputError
        Fewer than 3 epochs, shapes that disagree, non-finite or zero axes, non-increasing times, a
        non-positive ``axis_sigma_deg``, a negative ``max_restarts``, ``min_restarts`` outside
        ``[0, max_restarts]``, optimiser settings out of range (``recombination`` in [0, 1], ``mutation``
        in [0, 2), ``tol_abs`` >= 0, ``settle`` >= 0, ``max_rate_rad_s`` > 0), a rate bound and ``step_s`` or
        ``search_step_s`` that turn the body by more than ``MAX_ROTATION_PER_STEP_RAD`` per step.
    WorkLimitError
        ``popsize`` above ``MAX_POPSIZE`` (1000), ``maxiter`` or ``patience`` above ``MAX_GENERATIONS``
        (1e5), ``max_restarts`` above ``MAX_RESTARTS`` (100), one generation needing more than
        ``MAX_RK4_STEPS`` RK4 steps at ``search_step_s``, or the whole fit at its generation cap more
        than ``MAX_FIT_RK4_STEPS`` (1e10).

    Notes
    -----
    The objective runs the Rust batch propagator over the whole population in parallel (rayon; set
    ``RAYON_NUM_THREADS`` for the thread count); results do not depend on the thread count.

    Examples
    --------
    Noise-free axes of a known state over 400 s give it back, up to the mirror state that has the same
    axes (:func:`fold_symmetric`) and to turns of 2 pi; a tighter ``tol_abs`` than the paper's lets the search
    settle in the exact minimum:

    >>> import numpy as np
    >>> from gnssatt.attitude.dynamics import fit_rotation, fold_symmetric, propagate_axes
    >>> state = np.array([0.3, 1.0, 0.5, 0.01, 0.02, -0.015])  # rad, rad/s
    >>> t = np.arange(0.0, 401.0, 20.0)  # s
    >>> fit = fit_rotation(t, propagate_axes(state, t), rng=1, popsize=10, tol_abs=1e-6)
    >>> found = fold_symmetric(fit.params, state)
    >>> np.round(found[:3] % (2 * np.pi), 2) + 0.0, np.round(found[3:], 3) + 0.0
    (array([0.3, 1. , 0.5]), array([ 0.01 ,  0.02 , -0.015]))
    >>> bool(fit.residual_rms_deg < 0.01)
    True
    """
    tt = checked_times(t)
    m = _checked_axes(tt, measured_axes)
    max_restarts = integer("max_restarts", max_restarts, minimum=0, maximum=MAX_RESTARTS)
    min_restarts = integer("min_restarts", min_restarts, minimum=0)
    if min_restarts > max_restarts:
        raise InvalidInputError(
            f"expected min_restarts as an integer in [0, max_restarts = {max_restarts}], got {min_restarts!r}"
        )
    threshold = math.inf
    if axis_sigma_deg is not None:
        threshold = noise_cost_threshold(tt.size, axis_sigma_deg, false_restart)
    text("restart", restart, ("horizon", "fresh"))
    text("strategy", strategy)
    if not isinstance(polish, bool | np.bool_):
        raise InvalidTypeError(f"expected polish as a bool, got {type(polish).__name__}")
    rng = _checked_rng(rng)
    opts = _de_options(popsize, mutation, recombination, strategy, tol_abs, patience, settle, maxiter, polish)
    w = scalar("max_rate_rad_s", max_rate_rad_s, minimum=0.0, strict=True)
    mdl = default_model(model)
    # Every population member lies in the search box: its rates are at most sqrt(3) w.
    box_rate = math.sqrt(3.0) * w + 2.0 * mdl.orbital_rate_rad_s
    step_s = checked_work(1, tt, step_s, box_rate)
    if search_step_s is None:
        search_step_s = max(step_s, SEARCH_TURN_RAD / box_rate)
    search_step_s = checked_work(opts["popsize"] * 6, tt, search_step_s, box_rate, "search_step_s")
    _check_fit_work(tt, min(step_s, search_step_s), opts, max_restarts)
    obj = _Objective(tt, m, mdl, step_s)
    search = _Objective(tt, m, mdl, search_step_s)

    n_restarts = max_restarts if threshold < math.inf else min_restarts
    runs = _runs(obj, search, w, rng, n_restarts, min_restarts, threshold, restart, opts)
    best, cost, _, stopped_by = min(runs, key=lambda r: r[1])
    finite_result("the fitted objective", cost, f"every run diverged; step_s = {step_s} s")
    fitted = propagate_axes(best, tt, mdl, step_s=step_s)
    ang = np.arccos(np.clip(np.sum(fitted * m, axis=1), -1.0, 1.0))
    return RotationFit(
        params=best,
        cost=cost,
        nfev=obj.nfev + search.nfev,
        nit=sum(r[2] for r in runs),
        stopped_by=stopped_by,
        residual_rms_deg=float(np.degrees(np.sqrt(np.mean(ang**2)))),
        attempt_params=np.array([r[0] for r in runs]),
        attempt_costs=np.array([r[1] for r in runs]),
        cost_threshold=threshold,
    )
