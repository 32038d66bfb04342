"""Matrix least-squares attitude from antenna range differences (Ryzhkov and Oliinyk)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.spatial.transform import Rotation

from gnssatt import _core
from gnssatt._arrays import batch_limit, finite_outputs, plain_array, shaped
from gnssatt.errors import DegenerateGeometryError, InvalidInputError
from gnssatt.geometry import MAX_BASELINE_M, MAX_SIGNALS, checked_baselines

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
    heading_pitch_roll_deg
        (3,) heading, pitch, roll in degrees: the intrinsic ``ZYX`` angles of ``rotation`` (body ->
        reference), ``rotation.as_euler("ZYX", degrees=True)``.
    """

    rotation: Rotation
    residual_rms_m: float
    raw_matrix: NDArray[np.float64]
    method: Method

    @property
    def heading_pitch_roll_deg(self) -> NDArray[np.float64]:
        """Heading, pitch, roll in degrees: intrinsic Z-Y'-X'' of body -> reference (docs/conventions.md)."""
        angles: NDArray[np.float64] = self.rotation.as_euler("ZYX", degrees=True)  # scipy is untyped
        return angles


def matrix_attitude(
    baselines: ArrayLike, los: ArrayLike, range_diffs: ArrayLike, *, method: Method = "svd"
) -> MatrixAttitudeResult:
    """Attitude from range differences between antennas, by the matrix method of Ryzhkov and Oliinyk.

    Parameters
    ----------
    baselines
        (m, 3) antenna positions relative to the reference antenna, body frame, metres; m >= 2, each
        between :data:`~gnssatt.geometry.MIN_BASELINE_M` (1e-6) and :data:`~gnssatt.geometry.MAX_BASELINE_M`
        (1.3e7) m long.
    los
        (n, 3) unit lines of sight from the vehicle to the satellites, reference frame; n >= 2.
    range_diffs
        (m, n) range differences in metres: ``b_i . (A s_j)`` plus noise, with ``A`` the
        reference -> body rotation, i.e. how much closer antenna i is to satellite j than the reference
        antenna; at most :data:`~gnssatt.geometry.MAX_BASELINE_M` in magnitude (a range difference never
        exceeds the baseline).
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

    Returns
    -------
    MatrixAttitudeResult
        The body -> reference ``rotation``, the RMS residual (m), the method's raw reference -> body matrix,
        the method, and ``heading_pitch_roll_deg``.

    Raises
    ------
    InvalidInputError
        Wrong shapes, non-finite values, lines of sight that are not unit vectors, baselines or range
        differences outside the limits above, an unknown ``method``
        (:class:`~gnssatt.errors.InvalidTypeError` for values that are not real numbers or text).
    DegenerateGeometryError
        The geometry does not fix the attitude (``range_diffs`` all zero to 1e-12 of the longest baseline
        included), or the chosen formula's matrix is singular; the message names the matrix and its
        condition number.
    ConvergenceError
        ``"ml"`` did not converge, or the result is not finite (not seen in testing; it would point at a
        defect).

    Examples
    --------
    Noise-free range differences of a 1 m triangle (two baselines, coplanar) to four satellites give back the
    attitude they were made with, with zero residual:

    >>> import numpy as np
    >>> from scipy.spatial.transform import Rotation
    >>> from gnssatt.attitude.matrix_method import matrix_attitude
    >>> from gnssatt.sim import equilateral_triangle, random_los
    >>> baselines = equilateral_triangle(1.0)[1:]  # (2, 3) m, body
    >>> los = random_los(1, 4, min_elevation_deg=15.0)  # (4, 3) unit vectors, reference frame
    >>> true = Rotation.from_euler("ZYX", [30.0, 5.0, -2.0], degrees=True)  # body -> reference
    >>> range_diffs = baselines @ true.inv().apply(los).T  # (2, 4) m: b_i . (A s_j)
    >>> result = matrix_attitude(baselines, los, range_diffs)
    >>> np.round(result.heading_pitch_roll_deg, 6) + 0.0
    array([30.,  5., -2.])
    >>> round(result.residual_rms_m, 9) + 0.0
    0.0
    """
    b, s = _checked_geometry(baselines, los)
    r = _checked_range_diffs(range_diffs, b, s)
    dcm, raw, rms = _solved(b, s, r, method)
    finite_outputs(f"matrix_attitude ({method!r})", rotation=dcm, raw_matrix=raw, residual_rms_m=rms)
    return MatrixAttitudeResult(Rotation.from_matrix(dcm), rms, raw, method)


def _checked_geometry(
    baselines: ArrayLike, los: ArrayLike
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """The (m, 3) baselines and (n, 3) lines of sight of :func:`matrix_attitude`, two of each at least."""
    # from the shapes, before anything is copied: range_diffs is (m, n) with m baselines and n lines of sight
    batch_limit(MAX_SIGNALS, "MAX_SIGNALS", "lines of sight", los=(los, 1))
    b = checked_baselines("baselines", baselines)
    if len(b) < 2:
        raise InvalidInputError(f"expected baselines of shape (m, 3) with m >= 2, got {b.shape}")
    s = shaped("los", los, "(n, 3)", (None, 3))
    if len(s) < 2:
        raise InvalidInputError(f"expected los of shape (n, 3) with n >= 2, got {s.shape}")
    return b, s


def _checked_range_diffs(
    range_diffs: ArrayLike, b: NDArray[np.float64], s: NDArray[np.float64]
) -> NDArray[np.float64]:
    """The (m, n) range differences of :func:`matrix_attitude`, m, bounded by :data:`MAX_BASELINE_M`."""
    raw = plain_array("range_diffs", range_diffs)
    shape = raw.shape
    if raw.dtype.kind in "iuf" and shape != (len(b), len(s)):
        # name the argument whose size differs from range_diffs' (m, n), not range_diffs alone
        raise InvalidInputError(
            f"expected range_diffs of shape (m, n) with m the rows of baselines and n those of los, i.e. "
            f"({len(b)}, {len(s)}) for baselines {b.shape} and los {s.shape}, got range_diffs {shape}"
        )
    r = shaped("range_diffs", range_diffs, f"(m, n) = ({len(b)}, {len(s)})", (len(b), len(s)))
    if np.any(np.abs(r) > MAX_BASELINE_M):
        k = tuple(int(i) for i in np.argwhere(np.abs(r) > MAX_BASELINE_M)[0])
        raise InvalidInputError(
            f"expected range_diffs at most {MAX_BASELINE_M:g} m in magnitude, got {r[k]:.6g} m at index {k}"
        )
    return r


def _solved(
    b: NDArray[np.float64], s: NDArray[np.float64], r: NDArray[np.float64], method: Method
) -> tuple[NDArray[np.float64], NDArray[np.float64], float]:
    """The core's rotation matrix, raw matrix and residual RMS; a degenerate geometry named by the
    arguments it comes from."""
    try:
        out = _core.matrix_attitude(b, s, r, method)
        return out.dcm_ref_from_body, out.raw_body_from_ref, out.residual_rms_m
    except DegenerateGeometryError as exc:
        longest = float(np.max(np.linalg.norm(b, axis=1)))
        if float(np.max(np.abs(r))) > 1e-12 * longest:
            # the core speaks of vector pairs; which arguments they come from is known only here
            raise DegenerateGeometryError(
                f"{exc} (the pairs come from baselines, los and range_diffs: range_diffs far from those of "
                "a rotation of the baselines can be degenerate too)"
            ) from exc
        raise DegenerateGeometryError(
            f"range_diffs do not fix the attitude: they are all zero to 1e-12 of the longest baseline "
            f"({longest:.6g} m), max |range_diffs| = {float(np.max(np.abs(r))):.3g} m"
        ) from exc
