"""Attitude by maximum likelihood from raw, wrapped carrier phases over the whole attitude grid (Bunyaeva et
al.).

Three antennas on a 0.71 m equilateral triangle in the horizontal plane of the body (the paper's array) see
the 8 highest nominal GPS satellites from Kharkiv. Each antenna's carrier phase is wrapped, carries an
unknown integer and an unknown oscillator phase, and 0.05 rad of noise. :func:`gnssatt.ml_attitude` searches
the whole attitude domain on a 1.5 deg grid (the ambiguity-function statistic, which needs neither the
integers nor the oscillator phases) and refines the best cell. Over 200 noise draws the attitude errors
follow the covariance that small-noise theory predicts for this statistic, a little above the Cramer-Rao
bound.
"""

from __future__ import annotations

import numpy as np
from scipy.spatial.transform import Rotation

import gnssatt
from gnssatt import sim

SEED = 2026
SIDE_M = 0.71
N_SATELLITES = 8
MASK_DEG = 10.0
STEP_DEG = 1.5
PHASE_SIGMA_RAD = 0.05  # per antenna; a phase difference has sqrt(2) times this
TRIALS = 200
# Heading, pitch, roll of eq. (5) of Bunyaeva et al. (GOST: the compass heading is -psi), degrees.
TRUTH_PSI_THETA_PHI_DEG = (-60.0, 5.0, -3.0)
# Rows of the normal frame (North, Up, East) reordered to East-North-Up (docs/conventions.md, Bunyaeva et al.
# row).
ENU_FROM_NORMAL = np.array([[0.0, 0.0, 1.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]])


def sky(t_s: float = 1800.0):
    """Lines of sight (8, 3, ENU) and wavelengths (8,) of the 8 highest GPS satellites above the mask."""
    gps = sim.gps_nominal()
    geometry = sim.line_of_sight(sim.GroundReceiver(lat_deg=50.0, lon_deg=36.2, height_m=150.0), gps, t_s)
    elevation, _ = geometry.elevation_azimuth()
    highest = np.argsort(elevation)[::-1][:N_SATELLITES]
    assert np.degrees(elevation[highest]).min() > MASK_DEG
    geometry = geometry.select(np.isin(np.arange(elevation.size), highest))
    return geometry, gps.select(list(geometry.ids)).wavelengths_m()


def predicted_covariance(truth: Rotation, antennas: np.ndarray, los: np.ndarray, lam: np.ndarray):
    """Small-noise covariances (rad^2) of the ENU rotation-vector error: the ambiguity function's and the
    Cramer-Rao bound.

    At small noise the ambiguity function is least squares on the phase differences with one unknown
    oscillator offset per baseline, ignoring that the differences share antenna 0's noise; its covariance
    is the sandwich ``(H^T H)^-1 H^T S H (H^T H)^-1`` with ``S`` the true noise covariance, the bound
    ``(H^T S^-1 H)^-1``. Rows of ``H``: ``d(phase_ik)/d(delta) = 2 pi / lambda_k (R b_i x s_k)`` for the
    rotation ``exp([delta x]) R``, plus a 1 for offset ``i``.
    """
    b = truth.apply(antennas[1:] - antennas[0])  # (m, 3) baselines in ENU
    m, n = len(b), len(los)
    h = np.zeros((m * n, 3 + m))
    s = np.zeros((m * n, m * n))
    for i in range(m):
        rows = slice(i * n, (i + 1) * n)
        h[rows, :3] = 2 * np.pi / lam[:, None] * np.cross(b[i], los)
        h[rows, 3 + i] = 1.0
        for j in range(m):
            # phi_i - phi_0 and phi_j - phi_0 of one satellite share antenna 0's noise
            s[rows, j * n : (j + 1) * n] = PHASE_SIGMA_RAD**2 * (1.0 + (i == j)) * np.eye(n)
    hth = np.linalg.inv(h.T @ h)
    sandwich = (hth @ h.T @ s @ h @ hth)[:3, :3]
    bound = np.linalg.inv(h.T @ np.linalg.solve(s, h))[:3, :3]
    return sandwich, bound


def main() -> dict[str, object]:
    rng = np.random.default_rng(SEED)
    geometry, lam = sky()
    antennas = sim.equilateral_triangle(SIDE_M, plane="xz")  # body: X forward, Y up, Z right wing
    truth = Rotation.from_matrix(ENU_FROM_NORMAL) * Rotation.from_euler(
        "YZX", TRUTH_PSI_THETA_PHI_DEG, degrees=True
    )
    errors = np.empty((TRIALS, 3))
    for k in range(TRIALS):
        measured = sim.simulate_array(geometry, truth, antennas, lam, rng, phase_sigma_rad=PHASE_SIGMA_RAD)
        found = gnssatt.ml_attitude(
            measured.phase_diffs(), geometry.los, antennas[1:], lam, step_deg=STEP_DEG
        )
        errors[k] = (found.rotation * truth.inv()).as_rotvec()  # rad, East-North-Up axes
    grid = gnssatt.likelihood_grid(measured.phase_diffs(), geometry.los, antennas[1:], lam, step_deg=STEP_DEG)
    sandwich, bound = predicted_covariance(truth, antennas, geometry.los, lam)

    rms = np.degrees(np.sqrt(np.mean(errors**2, axis=0)))
    print(
        f"satellites {len(lam)}, elevations {np.degrees(geometry.elevation_azimuth()[0]).min():.0f}-"
        f"{np.degrees(geometry.elevation_azimuth()[0]).max():.0f} deg, grid {grid.z.size} cells"
    )
    print(f"largest error of {TRIALS} trials {np.degrees(np.linalg.norm(errors, axis=1)).max():.2f} deg")
    for axis, name in enumerate(("East", "North", "Up")):
        print(
            f"error about {name:<5}  RMS {rms[axis]:.3f} deg   predicted "
            f"{np.degrees(np.sqrt(sandwich[axis, axis])):.3f}   Cramer-Rao "
            f"{np.degrees(np.sqrt(bound[axis, axis])):.3f}"
        )
    return {
        "errors": errors,
        "sandwich": sandwich,
        "bound": bound,
        "grid": grid,
        "truth_psi_theta_phi_deg": np.array(TRUTH_PSI_THETA_PHI_DEG),
    }


def _ellipse(ax, cov_deg2: np.ndarray, label: str, style: str) -> None:
    """The 95 % ellipse of a 2-D Gaussian of covariance ``cov_deg2`` (deg^2)."""
    values, vectors = np.linalg.eigh(cov_deg2)
    angle = np.linspace(0.0, 2 * np.pi, 200)
    radius = np.sqrt(5.991)  # chi-square, 2 degrees of freedom, 95 %
    points = vectors @ (radius * np.sqrt(values)[:, None] * np.array([np.cos(angle), np.sin(angle)]))
    ax.plot(points[0], points[1], style, label=label)


def figure(found: dict[str, object]):
    import matplotlib.pyplot as plt

    grid, truth = found["grid"], found["truth_psi_theta_phi_deg"]
    fig, (left, right) = plt.subplots(1, 2, figsize=(11, 4.4))
    it = int(np.argmin(np.abs(grid.theta_deg - truth[1])))
    ip = int(np.argmin(np.abs(grid.phi_deg - truth[2])))
    left.plot(grid.psi_deg, grid.z[:, it, ip], lw=1.0)
    left.axvline(truth[0] % 360.0, color="k", ls=":", label=f"true psi {truth[0] % 360.0:.0f} deg")
    left.set_xlabel("psi of eq. (5) (compass heading = -psi), deg")
    left.set_ylabel("ambiguity function Z, dimensionless (at most 16)")
    left.set_title(f"Z along psi at theta = {grid.theta_deg[it]:.1f}, phi = {grid.phi_deg[ip]:.1f} deg")
    left.legend(loc="upper left")

    errors = np.degrees(found["errors"])
    right.plot(errors[:, 0], errors[:, 2], ".", ms=3, color="0.4", label=f"{len(errors)} noise draws")
    east_up = np.ix_([0, 2], [0, 2])
    deg2 = np.degrees(np.degrees(1.0))  # rad^2 -> deg^2
    _ellipse(right, deg2 * found["sandwich"][east_up], "predicted 95 %", "C0-")
    _ellipse(right, deg2 * found["bound"][east_up], "Cramer-Rao 95 %", "C3--")
    right.set_xlabel("error about East (pitch-like), deg")
    right.set_ylabel("error about Up (heading), deg")
    right.set_title("attitude errors of ml_attitude")
    right.set_aspect("equal", adjustable="datalim")
    right.legend(loc="upper left", fontsize=8)
    fig.suptitle(
        f"ML attitude, 0.71 m triangle, 8 GPS satellites over Kharkiv, {PHASE_SIGMA_RAD} rad phase noise"
    )
    fig.tight_layout()
    return fig


if __name__ == "__main__":
    import matplotlib.pyplot as plt

    figure(main())
    plt.show()
