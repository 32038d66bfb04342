"""Rotation of a tumbling spacecraft from its antenna-axis directions (Belokonov et al., 2019).

Euler's equations with gravity-gradient and aerodynamic torques and quaternion kinematics relative to the
orbital frame (eqs. (3)-(4)) run in the Rust core (``gnssatt._core.tumble_*``, RK4, rayon over initial
states). The initial state ``b = (psi, alpha, phi, wx, wy, wz)`` is fitted to axis directions collected
over an interval by differential evolution (eq. (1), scipy's ``differential_evolution`` with a vectorised
objective and the paper's stopping rule), which searches on long RK4 steps (about 5 s, axes interpolated)
and is polished on the objective at the requested step. Given the axis noise, a fit whose objective
exceeds what the noise explains (:func:`noise_cost_threshold`) is a local minimum and is restarted
(:func:`fit_rotation`).

Frames and angles (``docs/conventions.md``, Belokonov et al.):

- orbital frame of the library: x along-track, y orbit normal, z radial (zenith). The paper's orbital frame
  ``X0`` (radial), ``Y0`` (along-track), ``Z0`` (normal) is the same triad relabelled:
  ``(x, y, z) = (Y0, Z0, X0)``. Axes and rotations returned here are in the library's orbital frame.
- body frame: the paper's principal axes ``Xc, Yc, Zc``; the antenna (longitudinal) axis is ``Yc``.
- angles: precession ``psi`` about ``Y0``, attack ``alpha`` about ``Z0'``, spin ``phi`` about ``Y0''``,
  intrinsic ``YZY`` in the paper's orbital axes: ``dcm_orb0_from_body = R_y(psi) R_z(alpha) R_y(phi)``,
  so ``cos(alpha)`` is the axis component along the velocity.
- rates: the absolute (inertial) angular velocity in body axes, rad/s, as in eqs. (3).

Every rotation by pi about ``Yc`` maps one solution onto another when the centre of pressure lies on
``Yc`` (the default): ``(psi, alpha, phi + pi, -wx, wy, -wz)`` gives the same axis history; see
:func:`fold_symmetric`.

The package's modules: :mod:`~gnssatt.attitude.dynamics.model` (the model's parameters and frames),
:mod:`~gnssatt.attitude.dynamics.propagation` (the integration) and :mod:`~gnssatt.attitude.dynamics.fit`
(the fit of the initial state).
"""

from gnssatt.attitude.dynamics.fit import (
    MAX_FIT_RK4_STEPS,
    MAX_GENERATIONS,
    MAX_POPSIZE,
    MAX_RESTARTS,
    MIN_EPOCHS,
    SEARCH_TURN_RAD,
    RotationFit,
    fit_rotation,
    noise_cost_threshold,
)
from gnssatt.attitude.dynamics.model import (
    DCM_ORBITAL_FROM_ORB0,
    EARTH_RADIUS_M,
    GM_M3_S2,
    MAX_PROPAGATE_TIMES,
    MAX_RATE_RAD_S,
    MAX_RK4_STEPS,
    MAX_ROTATION_PER_STEP_RAD,
    TumbleModel,
)
from gnssatt.attitude.dynamics.propagation import (
    TumbleTrajectory,
    axis_cost,
    fold_symmetric,
    propagate,
    propagate_axes,
)

__all__ = [
    "DCM_ORBITAL_FROM_ORB0",
    "EARTH_RADIUS_M",
    "GM_M3_S2",
    "MAX_FIT_RK4_STEPS",
    "MAX_GENERATIONS",
    "MAX_POPSIZE",
    "MAX_PROPAGATE_TIMES",
    "MAX_RATE_RAD_S",
    "MAX_RESTARTS",
    "MAX_RK4_STEPS",
    "MAX_ROTATION_PER_STEP_RAD",
    "MIN_EPOCHS",
    "SEARCH_TURN_RAD",
    "RotationFit",
    "TumbleModel",
    "TumbleTrajectory",
    "axis_cost",
    "fit_rotation",
    "fold_symmetric",
    "noise_cost_threshold",
    "propagate",
    "propagate_axes",
]

# The classes' one public home is this package (the submodules are how the code is organised, not paths to
# import from): pickles and the API reference name it, and the reference describes each class once.
for _cls in (RotationFit, TumbleModel, TumbleTrajectory):
    _cls.__module__ = __name__
del _cls
