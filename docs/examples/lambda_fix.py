"""Fix integer ambiguities with LAMBDA, and see why rounding the float solution is not enough.

A float solution of three carrier-phase ambiguities (cycles) whose covariance is strongly correlated, as
single-epoch double differences are: the integer least-squares (ILS) solution that LAMBDA finds differs from
the float vector rounded component by component. The ratio test then says whether to trust the fix, and the
bootstrapped success rate bounds the probability that the ILS fix is right.
"""

from __future__ import annotations

import numpy as np

import gnssatt

# Float ambiguities a (cycles) and their covariance Q (cycles^2): variances of 6.3 cycles^2, correlations up
# to 0.95 between the first two.
FLOAT = np.array([5.45, 3.10, 2.97])
COVARIANCE = np.array(
    [
        [6.290, 5.978, 0.544],
        [5.978, 6.292, 2.340],
        [0.544, 2.340, 6.288],
    ]
)


def squared_norm(z: np.ndarray) -> float:
    """``(a - z) @ inv(Q) @ (a - z)``, the ILS objective, for one integer vector ``z``."""
    r = FLOAT - z
    return float(r @ np.linalg.solve(COVARIANCE, r))


def main() -> dict[str, object]:
    fixed, norms = gnssatt.lambda_ils(FLOAT, COVARIANCE, candidates=2)
    rounded = np.rint(FLOAT).astype(np.int64)
    test = gnssatt.ratio_test(FLOAT, COVARIANCE, threshold=3.0)
    z, _, d = gnssatt.lambda_decorrelate(COVARIANCE)
    success = gnssatt.bootstrap_success_rate(COVARIANCE)

    print(f"rounded float     {rounded}  squared norm {squared_norm(rounded):.3f}")
    print(f"ILS best          {fixed[0]}  squared norm {norms[0]:.3f}")
    print(f"ILS second        {fixed[1]}  squared norm {norms[1]:.3f}")
    print(f"ratio test        ratio {test.ratio:.2f} against {test.threshold:.0f}: accepted {test.accepted}")
    print(f"conditional variances after decorrelation (cycles^2) {np.round(d, 3)}")
    print(f"variances before (cycles^2)                          {np.round(np.diag(COVARIANCE), 3)}")
    print(f"bootstrapped success rate {success:.3f}")
    return {"fixed": fixed, "norms": norms, "rounded": rounded, "ratio": test, "z": z, "d": d}


if __name__ == "__main__":
    main()
