"""Matrix least-squares attitude from antenna range differences (Ryzhkov & Oliinyk, seed 000)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.spatial.transform import Rotation

from gnssatt import _core
from gnssatt._arrays import float_array

__all__ = ["MatrixAttitudeResult", "matrix_attitude"]

Method = Literal["svd", "ml", "closed_form", "paper"]


@dataclass(frozen=True)
class MatrixAttitudeResult:
    """Attitude from :func:`matrix_attitude`.

    Attributes
    ----------
    rotation
        Body -> reference rotation: ``rotation.apply(v_body)`` gives reference-frame coordinates.
    residual_rms_m
        RMS of the range-difference residuals ``R - B^T A S`` over all m x n entries, metres.
    raw_matrix
        The method's own reference -> body matrix ``A`` before orthogonalisation (eq. (3) is not
        orthogonal with noisy data; for the other methods it equals ``rotation.inv().as_matrix()``).
    method
        The method used.
    """

    rotation: Rotation
    residual_rms_m: float
    raw_matrix: NDArray[np.float64]
    method: Method

    @property
    def euler_deg(self) -> NDArray[np.float64]:
        """Heading, pitch, roll in degrees: intrinsic Z-Y'-X'' of body -> reference (docs/conventions.md)."""
        return self.rotation.as_euler("ZYX", degrees=True)


def matrix_attitude(
    baselines: ArrayLike, los: ArrayLike, range_diffs: ArrayLike, *, method: Method = "svd"
) -> MatrixAttitudeResult:
    """Attitude from range differences between antennas, by the matrix method of seed 000.

    Parameters
    ----------
    baselines
        (m, 3) antenna positions relative to the reference antenna, body frame, metres; m >= 2.
    los
        (n, 3) unit lines of sight from the vehicle to the satellites, reference frame; n >= 2.
    range_diffs
        (m, n) range differences in metres: ``b_i . (A s_j)`` plus noise, with ``A`` the
        reference -> body rotation, i.e. how much closer antenna i is to satellite j than the reference
        antenna.
    method
        ``"svd"`` (default): the proper rotation solving the least-squares problem (5) by SVD; handles
        coplanar arrays (three antennas) given 3 non-coplanar lines of sight, and equals eq. (16) whenever
        that is a rotation. ``"ml"``: minimises the paper's least-squares loss (4) itself by Gauss-Newton
        on SO(3), started from ``"svd"``: the maximum-likelihood attitude for independent Gaussian errors,
        which reaches the Cramer-Rao bound where ``"svd"`` does not (about half the median error with
        three antennas and three satellites). ``"closed_form"``: eq. (3), exact without noise (its
        ``rotation`` is the
        nearest rotation to the non-orthogonal raw matrix). ``"paper"``: eq. (16). The last two need
        3 non-coplanar baselines and 3 non-coplanar lines of sight.

    Raises
    ------
    InvalidInputError
        Wrong shapes, non-finite values, lines of sight that are not unit vectors, zero baselines.
    DegenerateGeometryError
        The geometry does not fix the attitude, or the chosen formula's matrix is singular; the message
        names the matrix and its condition number.
    ConvergenceError
        ``"ml"`` did not converge (not seen in testing; it would point at a defect).
    """
    b = float_array("baselines", baselines, ndim=2, shape="(m, 3)")
    s = float_array("los", los, ndim=2, shape="(n, 3)")
    r = float_array("range_diffs", range_diffs, ndim=2, shape="(m, n)")
    dcm, raw, rms = _core.matrix_attitude(b, s, r, method)
    return MatrixAttitudeResult(Rotation.from_matrix(dcm), rms, raw, method)
