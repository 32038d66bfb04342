"""Maximum-likelihood attitude from raw carrier phases over a grid of Euler angles (Bunyaeva et al.).

Bunyaeva, Piskorzh, Cheranovsky (KhAI): sufficient statistics (8)-(14), (17)-(18), grid step (15),
refinement (16). The grid runs in the Rust core (float32, polynomial sine/cosine with absolute error below
1e-6, SIMD across heading nodes, rayon across rows, GIL released); set the thread count with the
``RAYON_NUM_THREADS`` environment variable before the first call.

Conventions
-----------
Body axes: X forward (nose), Y up, Z right wing. The Euler angles ``(psi, theta, phi)`` are those of eq. (5),
the GOST 20058-80 heading, pitch and roll written in the normal frame (North, Up, East):
``R_normal_from_body = Ry(psi) Rz(theta) Rx(phi)`` (scipy ``Rotation.from_euler("YZX", [psi, theta, phi])``).
At zero angles the nose points North and the right wing East; positive ``psi`` turns the nose West (the
compass heading is ``-psi``), positive ``theta`` raises the nose, positive ``phi`` lowers the right wing.
``.rotation`` maps body vectors to East-North-Up: ``R_enu_from_body = P R_normal_from_body`` with ``P`` the
permutation (N, U, E) -> (E, N, U).

Measurements: ``phase_diffs[i, k]`` is the carrier phase (radians) at antenna ``i + 1`` minus antenna 0 for
satellite ``k``, RINEX sign (an antenna displaced by ``d`` towards the satellite has its phase lowered by
``2 pi (d . los_k) / lambda_k``), any multiple of 2 pi added, plus an unknown oscillator phase per baseline.

Statistics
----------
``"ambiguity_function"`` (default): ``Z = sum_i |sum_k exp(j[phase_diff_ik + 2 pi / lambda_k los_k . R
r_i])|``, the oscillator phases maximised out per baseline; works on wrapped phases. With several epochs of
a static platform the oscillator phases are taken as constant over the batch (one nuisance phase per
baseline), so the epochs are summed inside the modulus; if the receivers' oscillators drift between epochs,
pass the epochs one at a time. ``"mean"``: eqs. (10)-(14) as written; the satellite-mean of *wrapped* phases
leaves a per-antenna offset ``2 pi (sum of integers) / M`` and the peak moves (tens of degrees): it works
only on phases whose integer cycles are already consistent. ``"double_difference"``: eqs. (17)-(18) against
the highest-elevation satellite of each epoch; immune to wrapping, about 1.8 times the variance of the
ambiguity function for M = 8.
"""

from gnssatt.attitude.likelihood.epoch import likelihood_grid, ml_attitude, ml_baseline, prior_from_velocity
from gnssatt.attitude.likelihood.model import (
    AttitudePrior,
    BaselineDirection,
    LikelihoodAttitude,
    LikelihoodGrid,
)
from gnssatt.attitude.likelihood.model import StatisticName as StatisticName
from gnssatt.attitude.likelihood.series import MAX_SERIES_WORK as MAX_SERIES_WORK
from gnssatt.attitude.likelihood.series import (
    BaselineSeries,
    LikelihoodAttitudeSeries,
    ml_attitude_series,
    ml_baseline_series,
)

__all__ = [
    "AttitudePrior",
    "BaselineDirection",
    "BaselineSeries",
    "LikelihoodAttitude",
    "LikelihoodAttitudeSeries",
    "LikelihoodGrid",
    "likelihood_grid",
    "ml_attitude",
    "ml_attitude_series",
    "ml_baseline",
    "ml_baseline_series",
    "prior_from_velocity",
]
