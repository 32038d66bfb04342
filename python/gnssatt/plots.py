"""Figures of the experiments. matplotlib is imported lazily, and only its figure and Agg canvas (never
pyplot, so no backend is resolved and no GUI is ever needed): plotting works headless, importing gnssatt
stays cheap and a plot written by the command line costs less of its start (issue 30)."""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike

if TYPE_CHECKING:
    from matplotlib.figure import Figure

    from gnssatt.attitude.likelihood import LikelihoodGrid
    from gnssatt.gnss.attitude import AttitudeSeries
    from gnssatt.gnss.position import PositionSeries

__all__ = [
    "attitude_series",
    "dipole_vs_igrf",
    "error_histograms",
    "error_vs_geometry",
    "likelihood_sections",
    "position_series",
    "yaw_error_along_orbit",
]


def _figure(**kwargs: Any) -> Figure:
    """A figure drawn by the Agg canvas, without pyplot: no backend to resolve, no GUI, no figure manager
    to close (the figure goes with its last reference). ``kwargs`` go to :class:`matplotlib.figure.Figure`."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    fig = Figure(**kwargs)
    FigureCanvasAgg(fig)
    return fig


def error_vs_geometry(
    crb_deg: ArrayLike, errors_deg: Mapping[str, ArrayLike], path: Path, *, title: str
) -> Path:
    """Each trial's total attitude error against its Cramer-Rao bound (log-log), one series per estimator,
    with the binned RMS error and the line error = bound; saved as PNG at ``path``."""
    crb = np.asarray(crb_deg, dtype=float)
    edges = np.quantile(crb, np.linspace(0, 1, 11))
    idx = np.clip(np.digitize(crb, edges[1:-1]), 0, 9)
    centres = [np.median(crb[idx == k]) for k in range(10)]
    fig = _figure(figsize=(7, 5), dpi=120)
    ax = fig.subplots()
    for n, (label, values) in enumerate(errors_deg.items()):
        err = np.abs(np.asarray(values, dtype=float))
        ax.scatter(crb, err, s=3, alpha=0.25, color=f"C{n}")
        median = [np.median(err[idx == k]) for k in range(10)]
        ax.plot(centres, median, "o-", color=f"C{n}", label=f"{label}: median error per decile of the bound")
    lim = [crb.min(), crb.max()]
    ax.plot(lim, lim, "k--", label="error = Cramer-Rao bound (RMS)")
    ax.set(
        xscale="log",
        yscale="log",
        xlabel="Cramer-Rao bound of the total rotation error (deg)",
        ylabel="total rotation error (deg)",
        title=title,
    )
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path)
    return path


def likelihood_sections(grid: LikelihoodGrid, truth_deg: ArrayLike, path: Path) -> Path:
    """Bunyaeva et al., figures 1-2: Z over (pitch, roll) at the grid heading nearest the truth, and over
    (heading, pitch) at the grid roll nearest the truth; the truth marked; saved as PNG."""
    psi, theta, phi = (float(v) for v in np.asarray(truth_deg, dtype=float))
    i = int(np.argmin(np.abs((grid.psi_deg - psi + 180.0) % 360.0 - 180.0)))
    q = int(np.argmin(np.abs((grid.phi_deg - phi + 180.0) % 360.0 - 180.0)))
    fig = _figure(figsize=(12, 4.8), dpi=110)
    axes = fig.subplots(1, 2)
    panels = (
        (
            grid.z[i, :, :],
            grid.phi_deg,
            grid.theta_deg,
            "roll phi (deg)",
            (phi, theta),
            f"Z at heading psi = {grid.psi_deg[i]:.1f} deg (true {psi:.1f})",
        ),
        (
            grid.z[:, :, q].T,
            grid.psi_deg,
            grid.theta_deg,
            "heading psi (deg)",
            (psi, theta),
            f"Z at roll phi = {grid.phi_deg[q]:.1f} deg (true {phi:.1f})",
        ),
    )
    for ax, (z, x, y, xlabel, mark, title) in zip(axes, panels, strict=True):
        im = ax.pcolormesh(x, y, z, shading="auto", cmap="viridis")
        ax.plot(*mark, "r+", ms=14, mew=2, label="truth")
        ax.set(xlabel=xlabel, ylabel="pitch theta (deg)", title=title)
        ax.legend(loc="lower right")
        fig.colorbar(im, ax=ax, label="Z")
    fig.tight_layout()
    fig.savefig(path)
    return path


def attitude_series(series: AttitudeSeries, path: Path, *, data: str = "") -> Path:
    """Time series of the angles of :func:`gnssatt.gnss.attitude.attitude_from_rinex` (one panel each),
    fixed, held and float epochs marked apart; ``data`` names the files or stations in the title."""
    names = series.angle_names
    minutes = (series.time - series.time[0]).astype("timedelta64[ms]").astype(np.float64) / 60_000.0
    fig = _figure(figsize=(8, 2.2 * len(names)))
    axes = fig.subplots(len(names), 1, sharex=True, squeeze=False)
    styles = {"fixed": ("C0", "."), "held": ("C2", "."), "float": ("C3", "x")}
    for ax, j in zip(axes[:, 0], range(len(names)), strict=True):
        for state, (colour, marker) in styles.items():
            rows = series.fix_state == state
            if rows.any():
                ax.plot(
                    minutes[rows],
                    series.angles_deg[rows, j],
                    marker,
                    ms=3,
                    color=colour,
                    linestyle="none",
                    label=f"{state} ({int(rows.sum())})",
                )
        # the angle itself on the axis (163.3858 deg, not "+1.63385e2" above the axis)
        ax.ticklabel_format(axis="y", useOffset=False, style="plain")
        ax.set_ylabel(f"{names[j].removesuffix('_deg').replace('_', ' ')} (deg)")
        ax.grid(alpha=0.3)
    axes[0, 0].legend(loc="best", fontsize="small", title="epochs")
    axes[-1, 0].set_xlabel(f"minutes from {np.datetime_as_string(series.time[0], unit='s')} GPST")
    what = f"{series.mode} mode, method {', '.join(sorted(set(series.method)))}"
    fig.suptitle(f"{data}: {what}" if data else what)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    return path


def position_series(series: PositionSeries, path: Path) -> Path:
    """The positions of :func:`gnssatt.gnss.position.position_from_rinex`: East against North about the
    median position (equal axes, metres) and the height about the median over time."""
    enu = series.enu_about_median_m()
    ok = series.solved
    minutes = (series.time - series.time[0]).astype("timedelta64[ms]").astype(np.float64) / 60_000.0
    fig = _figure(figsize=(11, 5))
    ax_h, ax_u = fig.subplots(1, 2, gridspec_kw={"width_ratios": [1, 1.4]})
    ax_h.plot(enu[ok, 0], enu[ok, 1], ".", ms=3, alpha=0.6)
    ax_h.plot([0.0], [0.0], "k+", ms=12, label="median position")
    shown = [np.abs(enu[ok, :2]).ravel()]
    if np.isfinite(series.header_position_m).all() and ok.any():
        from gnssatt.frames import dcm_ecef_from_enu, ecef_to_geodetic

        lat, lon, _ = ecef_to_geodetic(series.median_position_m)
        d = (series.header_position_m - series.median_position_m) @ dcm_ecef_from_enu(float(lat), float(lon))
        ax_h.plot([d[0]], [d[1]], "rx", ms=10, label=f"header position ({d[2]:+.2f} m up)")
        shown.append(np.abs(d[:2]))
    # a square panel with one scale on both axes, centred on the median: a metre east is a metre north
    half = 1.15 * float(max(np.max(np.concatenate(shown), initial=0.0), 0.01))
    ax_h.set(
        xlabel="east about the median (m)",
        ylabel="north about the median (m)",
        xlim=(-half, half),
        ylim=(-half, half),
        aspect="equal",
    )
    ax_h.set_box_aspect(1)
    ax_h.legend(loc="best")
    ax_u.plot(minutes[ok], enu[ok, 2], ".", ms=3)
    start = np.datetime_as_string(series.time[0], unit="s") if len(series.time) else "-"
    ax_u.set(xlabel=f"minutes from {start} GPST", ylabel="height about the median (m)")
    for ax in (ax_h, ax_u):
        ax.grid(alpha=0.3)
        ax.ticklabel_format(useOffset=False, style="plain")
    file = Path(series.path).name
    name = f"{series.marker_name} ({file})" if series.marker_name else file
    fig.suptitle(f"{name}: code positions, systems {series.systems}, {int(ok.sum())} of {len(ok)} epochs")
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    return path


# Fewer runs than this give a strip plot instead of a histogram (error_histograms).
MIN_HISTOGRAM_RUNS = 30


def error_histograms(errors: Mapping[str, ArrayLike], path: Path, *, title: str, unit: str) -> Path:
    """One histogram (probability density) per error series, titled with its mean ``M`` and standard
    deviation ``sigma``, like Belokonov et al.'s figures 3 and 4; saved as PNG at ``path``. Under
    ``MIN_HISTOGRAM_RUNS`` values a histogram shows nothing but its bins, so each value is drawn as a point
    (a strip plot) instead."""
    fig = _figure(figsize=(4 * len(errors), 3.6), dpi=120)
    axes = fig.subplots(1, len(errors), squeeze=False)
    for ax, (label, values) in zip(axes[0], errors.items(), strict=True):
        v = np.asarray(values, dtype=float)
        if v.size >= MIN_HISTOGRAM_RUNS:
            # about two bins per sqrt(runs), at most the paper's 30
            ax.hist(v, bins=min(30, int(2 * np.sqrt(v.size))), density=True, color="C0", alpha=0.8)
            ax.set(xlabel=f"error {label} ({unit})", ylabel="probability density")
        else:
            jitter = np.random.default_rng(0).uniform(-0.2, 0.2, v.size)  # drawing only, fixed
            ax.plot(v, jitter, "o", color="C0", alpha=0.8, label=f"{v.size} runs")
            ax.axvline(float(np.mean(v)), color="C3", lw=1, label="mean")
            ax.set(xlabel=f"error {label} ({unit})", ylim=(-1, 1), yticks=[])
            ax.legend(loc="upper right", fontsize=7)
        ax.set_title(f"M = {np.mean(v):.3g}, sigma = {np.std(v):.3g}", fontsize=9)
        ax.grid(True, alpha=0.3)
    fig.suptitle(title, fontsize=10)
    fig.tight_layout()
    fig.savefig(path)
    return path


def yaw_error_along_orbit(
    u_deg: ArrayLike, curves: Mapping[float, Mapping[str, ArrayLike]], path: Path, *, title: str
) -> Path:
    """Yaw error against argument of latitude, one panel per inclination: TRIAD solid, eq. (3) dashed
    (as the paper's figs. 2 and 3); saved as PNG at ``path``."""
    fig = _figure(figsize=(7, 2.8 * len(curves)), dpi=120)
    axes = fig.subplots(len(curves), 1, sharex=True)
    for ax, (inc, err) in zip(np.atleast_1d(axes), curves.items(), strict=True):
        ax.plot(u_deg, err["triad"], "k-", label="TRIAD (local vertical + field)")
        ax.plot(u_deg, err["eq3"], "C3--", label="eq. (3)")
        ax.set(ylabel="yaw error (deg)", title=f"inclination {inc:g} deg")
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=8)
    np.atleast_1d(axes)[-1].set_xlabel("argument of latitude u (deg)")
    fig.suptitle(title, fontsize=9)
    fig.tight_layout()
    fig.savefig(path)
    return path


def dipole_vs_igrf(
    path: Path, radius_m: float, inclination_deg: float, *, decimal_year: float = 2025.0
) -> dict[str, float]:
    """Angle and magnitude difference between the axial dipole of eq. (2), the tilted IGRF-14 dipole and
    the full IGRF-14 (ppigrf) along one circular orbit (Earth rotating underneath, node at longitude 0);
    PNG at ``path``. Raises ImportError without ppigrf. Returns the maxima in degrees and percent.

    The tilted dipole equals ppigrf's degree-1 field (tests/test_magnetic.py); the differences shown are
    the non-dipole field (largest over the South Atlantic Anomaly and near the dip equator)."""
    from gnssatt import magnetic
    from gnssatt.constants import GM_M3_S2, OMEGA_E_RAD_S

    u = np.radians(np.linspace(0.0, 360.0, 361))
    inc = np.radians(inclination_deg)
    period = 2 * np.pi * np.sqrt(radius_m**3 / GM_M3_S2)
    era = OMEGA_E_RAD_S * period * u / (2 * np.pi)
    r_eci = radius_m * np.stack([np.cos(u), np.sin(u) * np.cos(inc), np.sin(u) * np.sin(inc)], -1)
    c, s = np.cos(era), np.sin(era)
    r_ecef = np.stack(
        [c * r_eci[:, 0] + s * r_eci[:, 1], -s * r_eci[:, 0] + c * r_eci[:, 1], r_eci[:, 2]], -1
    )
    full = magnetic.igrf_field_ecef(r_ecef, decimal_year)
    tilted = magnetic.dipole_field_ecef(r_ecef, decimal_year)
    m = np.array([0.0, 0.0, -magnetic.EARTH_DIPOLE_T_M3])
    rh = r_ecef / radius_m
    axial = (3 * (rh @ m)[:, None] * rh - m) / radius_m**3

    def ang(a: np.ndarray, b: np.ndarray) -> np.ndarray:
        cosang = np.sum(a * b, -1) / np.linalg.norm(a, axis=-1) / np.linalg.norm(b, axis=-1)
        angle: np.ndarray = np.degrees(np.arccos(np.clip(cosang, -1, 1)))  # norm over an axis is typed Any
        return angle

    fig = _figure(figsize=(7, 5.5), dpi=120)
    ax1, ax2 = fig.subplots(2, 1, sharex=True)
    results = {}
    for label, model in (("axial dipole (eq. 2)", axial), ("tilted IGRF-14 dipole", tilted)):
        a = ang(model, full)
        d = 100 * (np.linalg.norm(model, axis=-1) / np.linalg.norm(full, axis=-1) - 1)
        ax1.plot(np.degrees(u), a, label=label)
        ax2.plot(np.degrees(u), d, label=label)
        key = "axial" if label.startswith("axial") else "tilted"
        results[f"{key}_dipole_vs_igrf_max_angle_deg"] = float(np.max(a))
        results[f"{key}_dipole_vs_igrf_max_magnitude_error_pct"] = float(np.max(np.abs(d)))
    ax1.set(
        ylabel="angle to full IGRF-14 (deg)",
        title=f"{radius_m / 1e3 - 6378:.0f} km, i = {inclination_deg:g} deg",
    )
    ax2.set(xlabel="argument of latitude u (deg)", ylabel="|B| error vs IGRF-14 (%)")
    for ax in (ax1, ax2):
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path)
    return results
