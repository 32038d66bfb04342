"""Yaw from a magnetometer once an Earth sensor has given pitch and roll, along a near-polar orbit (Ryzhkov
and Holembiovskyi).

A spacecraft on a circular 700 km orbit inclined 87 deg holds yaw, pitch, roll = 5, 3, 4 deg in the orbital
frame (x along-track, y orbit normal, z radial). Its Earth sensor gives pitch and roll exactly; its
magnetometer reads the axial dipole field of eq. (2) with 50 nT of white noise per axis.
:func:`gnssatt.yaw_from_magnetometer` (eq. (3)) returns the yaw. Only the field's component in the
horizontal plane of the orbital frame fixes yaw, and near u = 90 and 270 deg (over the poles) it shrinks to a
few per cent of its largest value: there the same noise gives a yaw error dozens of times larger.
"""

from __future__ import annotations

import numpy as np
from scipy.spatial.transform import Rotation

import gnssatt
from gnssatt import magnetic

SEED = 2026
YAW_PITCH_ROLL_DEG = (5.0, 3.0, 4.0)  # Rotation.from_euler("ZYX", ...): body -> orbital
INCLINATION_DEG = 87.0
RADIUS_M = 6_378_137.0 + 700e3
NOISE_T = 50e-9  # magnetometer white noise per axis, tesla
DRAWS = 400  # noise draws at each orbit position
U_DEG = np.arange(2.5, 360.0, 5.0)  # argument of latitude, deg (72 positions, none exactly over a pole)


def predicted_sigma_rad(b_orbital: np.ndarray) -> np.ndarray:
    """First-order yaw sigma (rad) of eq. (3) for white noise ``NOISE_T`` per body axis.

    With ``c = Rz(-yaw) b_orbital`` the field rotated by yaw only, eq. (3) reads ``c_x`` from the body
    x channel divided by ``cos(pitch)`` and ``c_y`` from a roll-rotated pair of channels, so their noises
    are ``NOISE_T / cos(pitch)`` and ``NOISE_T``, independent. The yaw moves ``c`` along the circle of
    radius ``B_h = |(c_x, c_y)|``: ``d(yaw) = (c_y dc_x - c_x dc_y) / B_h^2``.
    """
    yaw, pitch, _ = np.radians(YAW_PITCH_ROLL_DEG)
    c = Rotation.from_euler("z", -yaw).apply(b_orbital)
    horizontal2 = c[:, 0] ** 2 + c[:, 1] ** 2
    variance = NOISE_T**2 * (c[:, 1] ** 2 / np.cos(pitch) ** 2 + c[:, 0] ** 2) / horizontal2**2
    return np.sqrt(variance)


def main() -> dict[str, object]:
    rng = np.random.default_rng(SEED)
    truth = Rotation.from_euler("ZYX", YAW_PITCH_ROLL_DEG, degrees=True)
    b_orbital = magnetic.dipole_orbital(np.radians(U_DEG), np.radians(INCLINATION_DEG), RADIUS_M)  # (72, 3) T
    # DRAWS noisy readings at every position, as one batch: (DRAWS * 72, 3) body-frame fields.
    model = np.tile(b_orbital, (DRAWS, 1))
    measured = truth.inv().apply(model) + rng.normal(0.0, NOISE_T, model.shape)
    n = len(model)
    result = gnssatt.yaw_from_magnetometer(
        measured, model, np.full(n, YAW_PITCH_ROLL_DEG[1]), np.full(n, YAW_PITCH_ROLL_DEG[2]), degrees=True
    )
    # With pitch and roll exact, estimate = Rz(yaw error) truth: the error is the z rotation vector.
    yaw_error = (result.rotation * truth.inv()).as_rotvec()[:, 2].reshape(DRAWS, len(U_DEG))
    noise_free = gnssatt.yaw_from_magnetometer(
        truth.inv().apply(b_orbital), b_orbital, YAW_PITCH_ROLL_DEG[1], YAW_PITCH_ROLL_DEG[2], degrees=True
    )
    exact = np.degrees(np.abs((noise_free.rotation * truth.inv()).magnitude())).max()
    sigma = np.std(yaw_error, axis=0)
    predicted = predicted_sigma_rad(b_orbital)
    horizontal = np.hypot(b_orbital[:, 0], b_orbital[:, 1])

    print(f"noise-free yaw error below 1e-9 deg: {exact < 1e-9}")
    print(f"horizontal field {horizontal.min() * 1e9:.0f} to {horizontal.max() * 1e9:.0f} nT")
    for name, k in (("least", int(np.argmin(horizontal))), ("most", int(np.argmax(horizontal)))):
        print(
            f"u = {U_DEG[k]:5.1f} deg ({name} horizontal field): yaw sigma {np.degrees(sigma[k]):.3f} deg, "
            f"predicted {np.degrees(predicted[k]):.3f} deg"
        )
    ratio = sigma / predicted
    print(f"sigma / predicted over the orbit: {ratio.min():.2f} to {ratio.max():.2f}")
    return {"yaw_error": yaw_error, "sigma": sigma, "predicted": predicted, "exact_deg": exact}


def figure(found: dict[str, object]):
    import matplotlib.pyplot as plt
    from matplotlib.ticker import NullFormatter, ScalarFormatter

    fig, (top, bottom) = plt.subplots(2, 1, figsize=(9, 6.5), sharex=True)
    predicted = np.degrees(found["predicted"])
    top.plot(U_DEG, np.degrees(found["yaw_error"][0]), ".-", lw=0.8, ms=4, label="one noisy pass")
    top.fill_between(
        U_DEG, -3 * predicted, 3 * predicted, color="C0", alpha=0.15, label="predicted +-3 sigma"
    )
    top.set_ylim(-8.0, 8.0)  # room for the legend above the polar peaks
    top.set_ylabel("yaw error, deg")
    top.set_title("yaw error of eq. (3) along the orbit")
    top.legend(loc="upper center", ncols=2)
    bottom.semilogy(U_DEG, np.degrees(found["sigma"]), "o", ms=4, label=f"sigma of {DRAWS} draws")
    bottom.semilogy(U_DEG, predicted, "-", color="C3", label="first-order prediction")
    bottom.set_xlabel("argument of latitude u (0 = ascending node), deg")
    bottom.set_ylabel("yaw sigma, deg (log scale)")
    bottom.set_title("yaw standard deviation: grows as the horizontal field shrinks over the poles")
    bottom.legend(loc="upper center", ncols=2)
    bottom.set_xticks(np.arange(0, 361, 45))
    bottom.set_ylim(0.1, 8.0)  # room for the legend above the polar peaks
    bottom.set_yticks([0.1, 0.2, 0.5, 1.0, 2.0, 5.0])
    bottom.yaxis.set_major_formatter(ScalarFormatter())
    bottom.yaxis.set_minor_formatter(NullFormatter())
    fig.suptitle(
        f"Magnetometer yaw on a 700 km orbit inclined {INCLINATION_DEG:g} deg, dipole field\n"
        f"{NOISE_T * 1e9:g} nT noise per axis, yaw / pitch / roll = 5 / 3 / 4 deg, pitch and roll exact"
    )
    fig.tight_layout()
    return fig


if __name__ == "__main__":
    import matplotlib.pyplot as plt

    figure(main())
    plt.show()
