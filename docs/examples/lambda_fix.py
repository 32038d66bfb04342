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


def figure(found: dict[str, object]):
    import matplotlib.pyplot as plt

    fig, (left, right) = plt.subplots(1, 2, figsize=(10, 4.2))
    k = np.arange(3)
    left.bar(k - 0.2, np.diag(COVARIANCE), width=0.4, label="float ambiguities")
    left.bar(k + 0.2, np.sort(found["d"])[::-1], width=0.4, label="after decorrelation (conditional)")
    left.set_xticks(k, ["1st", "2nd", "3rd"])
    left.set_xlabel("ambiguity (after decorrelation: sorted by variance)")
    left.set_ylabel("variance, cycles^2")
    left.set_title("what LAMBDA searches")
    left.set_ylim(0.0, 1.35 * np.max(np.diag(COVARIANCE)))  # room for the legend above the bars
    left.legend(loc="upper right", fontsize=8)
    names = ["rounded float", "ILS best", "ILS second"]
    values = [squared_norm(found["rounded"]), *found["norms"]]
    right.bar(names, values, color=["0.6", "C2", "C1"])
    for x, v in enumerate(values):
        right.text(x, v, f"{v:.3f}", ha="center", va="bottom")
    right.set_ylim(0.0, 1.15 * max(values))
    test = found["ratio"]
    right.set_xlabel("integer candidate")
    right.set_ylabel("squared norm (a - z) Q^-1 (a - z), dimensionless")
    right.set_title(f"ratio {test.ratio:.2f} < threshold {test.threshold:.0f}: keep the float solution")
    fig.suptitle("LAMBDA on three correlated float ambiguities (variances 6.3 cycles^2)")
    fig.tight_layout()
    return fig


if __name__ == "__main__":
    import matplotlib.pyplot as plt

    figure(main())
    plt.show()
