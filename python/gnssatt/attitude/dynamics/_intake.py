"""Checks shared by the propagation and the fit of the tumble model: initial states, times, the RK4 work
and the finiteness of the integrated states (private to :mod:`gnssatt.attitude.dynamics`)."""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from gnssatt._arrays import (
    finite_result,
    float_array,
    instance,
    scalar,
)
from gnssatt.attitude.dynamics.model import (
    MAX_RK4_STEPS,
    MAX_ROTATION_PER_STEP_RAD,
    TumbleModel,
)
from gnssatt.errors import InvalidInputError, WorkLimitError


def default_model(model: TumbleModel | None) -> TumbleModel:
    return instance("model", TumbleModel.circular() if model is None else model, TumbleModel, "a TumbleModel")


def checked_times(t: ArrayLike) -> NDArray[np.float64]:
    tt = float_array("t", t, ndim=1, shape="(n_t,)")
    if tt.size and tt[0] < 0:
        raise InvalidInputError(f"expected t >= 0 s from the initial epoch, got {tt[0]}")
    if np.any(np.diff(tt) < 0):
        i = int(np.flatnonzero(np.diff(tt) < 0)[0]) + 1
        raise InvalidInputError(f"expected non-decreasing t, got {tt[i]} after {tt[i - 1]} at index {i}")
    return tt


def checked_work(
    n_states: int, t: NDArray[np.float64], step_s: Any, max_rate_rad_s: float, name: str = "step_s"
) -> float:
    """``step_s`` (the parameter ``name``) as a float after checking the work and the rotation per step,
    before any propagation.

    The core's grid: ``ceil(t[-1] / step_s)`` equal RK4 steps from 0 to the last time (times between grid
    points are interpolated); ``max_rate_rad_s`` is the fastest rate of the batch (:func:`max_rate`).
    """
    h = scalar(name, step_s, minimum=0.0, strict=True, unit="s")
    per_state = grid_steps(t, h)
    steps = n_states * per_state
    if steps > MAX_RK4_STEPS:
        raise WorkLimitError(
            f"{n_states} initial states over t up to {t[-1]} s in {name} = {h} s need {steps:.3g} RK4 steps, "
            f"beyond the limit of {MAX_RK4_STEPS}; use a longer {name}, fewer times or fewer states"
        )
    h_eff = float(t[-1]) / per_state if per_state else 0.0
    if max_rate_rad_s * h_eff > MAX_ROTATION_PER_STEP_RAD:
        raise InvalidInputError(
            f"{name}: expected |omega| * step <= {MAX_ROTATION_PER_STEP_RAD} rad for a stable RK4 "
            f"integration, got rates up to {max_rate_rad_s} rad/s (params plus twice the orbital rate) in "
            f"steps of {h_eff} s; "
            f"use {name} <= {MAX_ROTATION_PER_STEP_RAD / max_rate_rad_s:.3g} s"
        )
    return h


def grid_steps(t: NDArray[np.float64], step_s: float) -> float:
    """RK4 steps of one trajectory to the last of ``t``, as the core counts them (its 1e-9 slack keeps a
    span that is a whole number of steps up to rounding from gaining a step)."""
    end = float(t[-1]) if t.size else 0.0
    # In floats: a subnormal step makes the count infinite, which the work limit then refuses.
    return max(float(np.ceil(end / step_s - 1e-9)), 1.0) if end > 0 else 0.0


def finite_state(what: str, value: NDArray[np.float64], step_s: float) -> NDArray[np.float64]:
    return finite_result(what, value, f"the integration diverged (step_s = {step_s} s); try a shorter step_s")


def max_rate(p: NDArray[np.float64], model: TumbleModel) -> float:
    """Fastest initial rate (norm) of the batch plus twice the orbital frame's rate: the bound the core
    applies (``|omega| + 2 w0``, the body's rate relative to the rotating orbital frame with margin), checked
    here first so that a fit is refused before its first generation."""
    rates = np.linalg.norm(np.atleast_2d(p)[:, 3:], axis=1)
    return float(np.max(rates, initial=0.0)) + 2.0 * model.orbital_rate_rad_s


def checked_params(p: Any, ndim: int | tuple[int, ...]) -> NDArray[np.float64]:
    arr = float_array("params", p, ndim=ndim, shape="(6,) or (n, 6)" if ndim != 1 else "(6,)")
    if arr.shape[-1:] != (6,):
        raise InvalidInputError(
            f"expected params of shape {'(6,)' if ndim == 1 else '(6,) or (n, 6)'}, got {arr.shape}"
        )
    return arr
