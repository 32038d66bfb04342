"""Geometry diagnostics shared by the estimators: how well an array and a set of lines of sight fix an
attitude (Cramer-Rao bound of range-difference attitude)."""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.spatial.transform import Rotation

from gnssatt._arrays import float_array
from gnssatt.errors import DegenerateGeometryError

__all__ = ["attitude_dop", "range_difference_fisher"]


def range_difference_fisher(baselines: ArrayLike, los: ArrayLike, rotation: Rotation) -> NDArray[np.float64]:
    """Fisher information (3, 3) of a small rotation vector for unit-variance range differences.

    The measurement is ``dr_ij = (M b_i) . s_j`` with ``M`` the body -> reference rotation; perturbing
    ``M -> exp([delta]x) M`` with ``delta`` in the reference frame gives the gradient ``(M b_i) x s_j``, so
    the information is ``sum_ij g_ij g_ij^T`` (rad^-2 per m^-2 of range-difference variance).
    """
    b = float_array("baselines", baselines, ndim=2, shape="(m, 3)")
    s = float_array("los", los, ndim=2, shape="(n, 3)")
    g = np.cross(rotation.apply(b)[:, None, :], s[None, :, :]).reshape(-1, 3)
    return g.T @ g


def attitude_dop(baselines: ArrayLike, los: ArrayLike, rotation: Rotation) -> float:
    """Attitude dilution of precision: ``sqrt(trace(J^-1))`` with ``J`` from :func:`range_difference_fisher`.

    Multiplied by the range-difference noise sigma (m) it gives the Cramer-Rao bound on the RMS total
    rotation error (rad) of any unbiased estimator.
    """
    info = range_difference_fisher(baselines, los, rotation)
    eig = np.linalg.eigvalsh(info)
    if eig[0] <= 1e-12 * eig[-1]:
        raise DegenerateGeometryError(
            f"the geometry does not fix the attitude: the Fisher information has condition number "
            f"{eig[-1] / max(eig[0], 1e-300):.3e}"
        )
    return float(np.sqrt(np.sum(1.0 / eig)))
