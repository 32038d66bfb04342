"""Attitude of a three-antenna array from carrier-phase range differences, by the matrix method (Ryzhkov and
Oliinyk).

Three antennas on a 1 m equilateral triangle (body frame) see six satellites. Each range difference is how
much closer antenna i is to satellite j than the reference antenna, ``b_i . (A s_j)`` with ``A`` the
reference -> body rotation; :func:`gnssatt.matrix_attitude` solves all of them for the attitude at once.
Without noise it returns the true attitude; with the millimetre noise of carrier phase the error is a
fraction of a degree, and the maximum-likelihood variant (``method="ml"``) lowers it.
"""

from __future__ import annotations

import numpy as np

import gnssatt
from gnssatt import sim

SEED = 2026
PHASE_NOISE_M = 0.002  # 1 sigma per range difference, metres (about 1 % of the L1 wavelength)
TRIALS = 200


def range_differences(truth, baselines: np.ndarray, los: np.ndarray) -> np.ndarray:
    """(m, n) noise-free ``b_i . (A s_j)``: ``truth`` maps body to reference, so ``A = truth.inv()``."""
    return truth.apply(baselines) @ los.T


def angle_deg(estimate, truth) -> float:
    """Angle of the rotation between estimate and truth, degrees."""
    return float(np.degrees((estimate * truth.inv()).magnitude()))


def main() -> dict[str, object]:
    rng = np.random.default_rng(SEED)
    baselines = sim.equilateral_triangle(1.0)[1:]  # antennas 1 and 2 relative to antenna 0, body frame, m
    los = sim.random_los(rng, 6, min_elevation_deg=10.0)  # unit vectors, reference frame
    exact_truth = truth = sim.random_attitude(rng)

    exact = gnssatt.matrix_attitude(baselines, los, range_differences(truth, baselines, los))
    # The exact error is rounding (1e-14 deg); print only whether it is that small, so the page's output
    # does not depend on the machine's floating-point libraries.
    print(f"noise-free error below 1e-9 deg: {angle_deg(exact.rotation, truth) < 1e-9}")

    errors = {"svd": [], "ml": []}
    for _ in range(TRIALS):
        truth = sim.random_attitude(rng)
        noisy = range_differences(truth, baselines, los) + rng.normal(0.0, PHASE_NOISE_M, (2, 6))
        for method, found in errors.items():
            result = gnssatt.matrix_attitude(baselines, los, noisy, method=method)
            found.append(angle_deg(result.rotation, truth))
    for method, found in errors.items():
        print(f"{PHASE_NOISE_M * 1e3:.0f} mm noise, {method:<3}  median error {np.median(found):.3f} deg")
    return {"exact": exact, "exact_truth": exact_truth, "errors": errors}


def figure(found: dict[str, object]):
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(8, 4.2))
    bins = np.linspace(0.0, max(max(e) for e in found["errors"].values()) * 1.02, 40)
    for (method, errors), color in zip(found["errors"].items(), ("C0", "C3"), strict=True):
        ax.hist(errors, bins=bins, histtype="step", lw=1.5, color=color, label=f"method={method!r}")
        ax.axvline(np.median(errors), color=color, ls=":", label=f"median {np.median(errors):.3f} deg")
    ax.set_xlabel("attitude error (angle of the error rotation), deg")
    ax.set_ylabel(f"trials per bin (of {TRIALS}), count")
    ax.set_title(f"{TRIALS} random attitudes, {PHASE_NOISE_M * 1e3:.0f} mm noise per range difference")
    ax.legend(loc="upper right")
    fig.suptitle("Matrix method: 1 m three-antenna triangle, 6 satellites above 10 deg")
    fig.tight_layout()
    return fig


if __name__ == "__main__":
    import matplotlib.pyplot as plt

    figure(main())
    plt.show()
