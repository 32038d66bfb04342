"""Figures of the experiments. matplotlib is imported lazily and always with the Agg backend, so plotting
works headless and importing gnssatt stays cheap."""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path

import numpy as np
from numpy.typing import ArrayLike

__all__ = ["error_vs_geometry"]


def _pyplot():  # type: ignore[no-untyped-def]
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def error_vs_geometry(
    crb_deg: ArrayLike, errors_deg: Mapping[str, ArrayLike], path: Path, *, title: str
) -> Path:
    """Each trial's total attitude error against its Cramer-Rao bound (log-log), one series per estimator,
    with the binned RMS error and the line error = bound; saved as PNG at ``path``."""
    plt = _pyplot()
    crb = np.asarray(crb_deg, dtype=float)
    edges = np.quantile(crb, np.linspace(0, 1, 11))
    idx = np.clip(np.digitize(crb, edges[1:-1]), 0, 9)
    centres = [np.median(crb[idx == k]) for k in range(10)]
    fig, ax = plt.subplots(figsize=(7, 5), dpi=120)
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
    plt.close(fig)
    return path
