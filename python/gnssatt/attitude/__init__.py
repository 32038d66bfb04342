"""Attitude estimators, one module per Rust area they wrap (``rust/core/src/<area>``).

- :mod:`~gnssatt.attitude.matrix_method`: closed-form attitude from baseline and line-of-sight matrices.
- :mod:`~gnssatt.attitude.likelihood`: maximum-likelihood attitude on a grid of carrier-phase differences.
- :mod:`~gnssatt.attitude.wahba`: TRIAD and Wahba's problem from vector pairs.
- :mod:`~gnssatt.attitude.magnetometer`: yaw from a magnetometer and a known field.
- :mod:`~gnssatt.attitude.gyro_gnss`: the gyro + GNSS Kalman filter.
- :mod:`~gnssatt.attitude.phase_attitude`: attitude fixes from fixed carrier phases.
- :mod:`~gnssatt.attitude.visibility`: spin axis from which satellites are visible.
- :mod:`~gnssatt.attitude.dynamics`: torque-free tumbling model and its fit to visibility data.

Nothing is imported here, so that one estimator costs only what it needs; the public names are re-exported
lazily from :mod:`gnssatt`. Layers: ``docs/architecture.md``.
"""
