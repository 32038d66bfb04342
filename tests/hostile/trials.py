"""A Monte Carlo trial for ``gnssatt.montecarlo.run``'s valid call, in a module that imports only numpy:
with ``executor=None`` each spawned worker imports the trial's module, and importing the inventory (gnssatt,
scipy, the scenario) there took most of the 10 s hang limit on a loaded machine."""

from __future__ import annotations

import numpy as np


def monte_trial(rng: np.random.Generator) -> float:
    return float(rng.normal())
