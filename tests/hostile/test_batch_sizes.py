"""The batch-size dimension (issue 31): a zero-stride view with a leading axis of 10^7 rows costs nothing to
pass, so every batch entry point must answer it within the hang limit, with a result or a refusal such as
``WorkLimitError``. The sweep (``benches/python/hostile_inputs.py``) broadcasts every numeric array argument
of every entry to 10^6 and 10^7 rows; here, to keep the suite fast, the entry points whose work grows with
the batch and that the issue or the third sweep found running for minutes, at 10^7 rows."""

from __future__ import annotations

import pytest

from . import harness
from .conftest import report
from .worker import Pool

# (entry, argument): the reproducers, and the gyro samples checked before they are copied
BATCHES = [
    ("gnssatt.ml_attitude_series", "sd_phase"),
    ("gnssatt.ml_baseline_series", "sd_phase"),
    ("gnssatt.magnetic.igrf_field_ecef", "position_ecef_m"),
    ("gnssatt.sim.line_of_sight", "t"),
    ("gnssatt.sim.simulate_array", "antennas_body_m"),
    ("gnssatt.gyro_propagate", "t"),
    # the row limits of gnssatt._arrays.batch_limit: one of each kind of batch
    ("gnssatt.wahba", "body"),
    ("gnssatt.matrix_attitude", "baselines"),
    ("gnssatt.sim.elevation_azimuth", "los_enu"),
    ("gnssatt.attitude.dynamics.propagate", "t"),
]


@pytest.mark.parametrize(("name", "param"), BATCHES)
def test_a_batch_of_ten_million_rows_is_answered_or_refused(pool: Pool, name: str, param: str) -> None:
    assert param in harness.batch_params(name)
    records = harness.run_batch(pool, [name], rows=(10**7,), only=param)
    assert records and all(r.outcome == "refused-ok" for r in records), report([r.line() for r in records])
    bad = [r.line() for r in harness.failures(records)]
    assert not bad, report(bad)
