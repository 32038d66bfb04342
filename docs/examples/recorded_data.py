"""A baseline from two recorded RINEX files, epoch by epoch, through the observation engine.

The GEONET pair shipped with the package (stations 0759 and 3040, 3.3 km apart, RINEX 2.10, GPS L1 + L2,
30 s, 120 epochs) is solved one epoch at a time (``motion="moving"``: every epoch fixed on its own, as a
moving receiver would need) with LAMBDA on the double differences of both frequencies, the reference antenna
at its surveyed (header) position. The fixed baselines are compared with RTKLIB 2.4.3's static L1 + L2
solution of the same pair (``docs/rtklib_comparison.md``), an answer nobody here computed.
"""

from __future__ import annotations

import numpy as np

from gnssatt.data import geonet_dir
from gnssatt.gnss.attitude import attitude_from_rinex

#: APPROX POSITION XYZ of 0759's header, ECEF m (the station's surveyed position).
BASE_ECEF_M = (-3976219.5082, 3382372.5671, 3652512.9849)
#: RTKLIB 2.4.3 static-continuous L1 + L2 of the same pair, ENU at the base, m.
RTKLIB_STATIC_ENU_M = np.array([953.6732, -3196.1396, 4.6497])


def main() -> dict[str, np.ndarray]:
    d = geonet_dir()
    series = attitude_from_rinex(
        [d / "07590920.05o", d / "30400920.05o"],
        [d / "07590920.05n", d / "30400920.05n"],
        motion="moving",
        method="lambda",
        systems="G",
        frequencies=2,
        base_position_m=BASE_ECEF_M,
    )
    fixed = series.fixed.astype(bool)
    error_mm = 1e3 * np.linalg.norm(series.baselines_enu_m[:, 0] - RTKLIB_STATIC_ENU_M, axis=1)
    print(series.summary().splitlines()[1])  # the fix rate
    print(f"epochs fixed {fixed.sum()} of {fixed.size}")
    print(
        f"distance to RTKLIB's static solution, fixed epochs: median {np.median(error_mm[fixed]):.1f} mm, "
        f"largest {error_mm[fixed].max():.1f} mm"
    )
    length_m = np.linalg.norm(series.baselines_enu_m[0, 0])
    print(f"azimuth of the first epoch {series.angles_deg[0, 0]:.4f} deg, length {length_m:.3f} m")
    minutes = (series.time - series.time[0]) / np.timedelta64(1, "s") / 60.0
    difference_mm = 1e3 * (series.baselines_enu_m[:, 0] - RTKLIB_STATIC_ENU_M)
    return {"fixed": fixed, "error_mm": error_mm, "minutes": minutes, "difference_mm": difference_mm}


def figure(found: dict[str, np.ndarray]):
    import matplotlib.pyplot as plt

    fixed, minutes, difference = found["fixed"], found["minutes"], found["difference_mm"]
    fig, ax = plt.subplots(figsize=(9, 4.2))
    for axis, name in enumerate(("East", "North", "Up")):
        ax.plot(minutes[fixed], difference[fixed, axis], ".-", lw=0.6, ms=4, label=f"{name}, fixed epochs")
    ax.set_ylim(-60.0, 60.0)
    for t in minutes[~fixed]:
        ax.axvline(t, color="0.6", lw=4, alpha=0.4, zorder=0)
    ax.plot([], [], color="0.6", lw=4, alpha=0.4, label=f"not fixed ({(~fixed).sum()} epochs, float)")
    ax.set_xlabel("time from the first epoch (2005-04-02 00:00 GPST), min")
    ax.set_ylabel("baseline minus RTKLIB static, mm")
    ax.set_title("each epoch fixed on its own (LAMBDA, L1 + L2, surveyed reference position)")
    ax.legend(loc="lower left", ncols=4, fontsize=8)
    fig.suptitle(
        "GEONET 0759 -> 3040 (3.3 km, 30 s): single-epoch baselines against RTKLIB 2.4.3's static solution"
    )
    fig.tight_layout()
    return fig


if __name__ == "__main__":
    import matplotlib.pyplot as plt

    figure(main())
    plt.show()
