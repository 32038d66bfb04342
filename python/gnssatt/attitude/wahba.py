"""Attitude from pairs of vectors measured in the body frame and known in a reference frame: TRIAD and
Wahba's problem (SVD, Davenport's q-method, QUEST), batched over a leading epoch axis in the Rust core.

Parallelism: batches run on rayon's global thread pool; set ``RAYON_NUM_THREADS`` before the first call
to choose the thread count. References: Black, AIAA J. 2 (1964) 1350 (TRIAD); Wahba, SIAM Rev. 7 (1965)
409; Markley, J. Astronaut. Sci. 36 (1988) 245 (SVD); Shuster & Oh, J. Guid. Control 4 (1981) 70 (QUEST);
Shuster, J. Astronaut. Sci. 37 (1989) 79 (covariance).
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass
from typing import Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.spatial.transform import Rotation

from gnssatt import _core
from gnssatt._arrays import MAX_BATCH_ROWS, batch_limit, finite_outputs, float_array, shaped
from gnssatt.errors import DegenerateGeometryError, InvalidInputError, NearDegenerateWarning

__all__ = ["MAX_VECTOR_PAIRS", "QUEST_MAX_WEIGHT_SPAN", "TriadResult", "WahbaResult", "triad", "wahba"]

Method = Literal["svd", "davenport", "quest"]

#: TRIAD warns when the sine of the angle between its two vectors (either frame) is below this.
TRIAD_WARN_SIN = 1e-2
#: Wahba warns when the information matrix's smallest/largest eigenvalue ratio is below this (for two
#: vectors about the square of half the angle between them: 1e-4 is about 1.1 deg).
WAHBA_WARN_RATIO = 1e-4
#: Widest span of an epoch's positive weights (largest / smallest) that ``wahba(method="quest")`` takes:
#: beyond about 1e6 QUEST's characteristic quartic returns wrong rotations (``tests/test_vector_attitude.py``
#: measures it against scipy's ``Rotation.align_vectors``).
QUEST_MAX_WEIGHT_SPAN = 1e5
#: Most vector pairs of one :func:`wahba` call (epochs x pairs), counted from the shapes before they are
#: copied: 16 us an epoch of 2-3 pairs plus 2 us a pair of intake (``docs/limits.md``) make about 8 s at
#: two pairs an epoch. TRIAD takes :data:`gnssatt._arrays.MAX_BATCH_ROWS` epochs.
MAX_VECTOR_PAIRS = 2**20


def warn_small(values: NDArray[np.float64], limit: float, what: str) -> None:
    """A :class:`~gnssatt.errors.NearDegenerateWarning` where ``values`` (per epoch) fall below ``limit``,
    naming ``what``, how many epochs and the smallest; shared with :mod:`gnssatt.attitude.magnetometer`
    (a helper of the estimators, not user API, so not in ``__all__``)."""
    small = values < limit
    if np.any(small):
        k = int(np.argmin(values))
        warnings.warn(
            f"{what} is below {limit:g} at {int(small.sum())} epoch(s) (smallest {values[k]:.3e} at epoch "
            f"{k}): errors are amplified by about its reciprocal",
            NearDegenerateWarning,
            stacklevel=3,
        )


def checked_vectors(name: str, value: ArrayLike) -> NDArray[np.float64]:
    """``value`` as (3,) or (epochs, 3) finite reals, checked under ``name``; shared with
    :mod:`gnssatt.attitude.magnetometer` (not in ``__all__``)."""
    return shaped(name, value, "(3,) or (epochs, 3)", (3,), (None, 3))


def rescaled(v: NDArray[np.float64], *, axes: int | tuple[int, ...] = -1) -> NDArray[np.float64]:
    """``v`` divided by its largest magnitude over ``axes`` (kept where that is zero), so that the norms the
    core forms neither overflow (vectors near 1e160) nor underflow (near 1e-160): directions, and ratios of
    weights, are what the estimators use."""
    scale = np.max(np.abs(v), axis=axes, keepdims=True)
    return v / np.where(scale > 0.0, scale, 1.0)


@dataclass(frozen=True)
class TriadResult:
    """Attitude from :func:`triad`.

    Attributes
    ----------
    rotation
        Body -> reference rotation (a batch Rotation for batch input); maps ``b1`` exactly onto ``r1``.
    sin_angle_body, sin_angle_ref
        Sine of the angle between the two vectors in each frame (float, or (epochs,)); the error about
        the axis normal to ``b1`` grows like its reciprocal.
    """

    rotation: Rotation
    sin_angle_body: float | NDArray[np.float64]
    sin_angle_ref: float | NDArray[np.float64]


def triad(b1: ArrayLike, b2: ArrayLike, r1: ArrayLike, r2: ArrayLike) -> TriadResult:
    """TRIAD attitude from two vector pairs; the first pair is matched exactly.

    Parameters
    ----------
    b1, b2
        (3,) or (epochs, 3) body-frame vectors, any length (normalised); ``b1`` should be the more
        accurate one (it is matched exactly, ``b2`` only fixes the rotation about it).
    r1, r2
        The same directions in the reference frame, same shape.

    Returns
    -------
    TriadResult
        ``.rotation`` maps body to reference: ``rotation.apply(b1 / |b1|) == r1 / |r1|``.

    Raises
    ------
    InvalidInputError
        Wrong shapes or non-finite values.
    DegenerateGeometryError
        A zero vector, or ``b1 || b2`` or ``r1 || r2`` (sine of the angle at most 1e-10); names the epoch.
    WorkLimitError
        More than :data:`gnssatt._arrays.MAX_BATCH_ROWS` epochs, refused before they are copied.

    Warns
    -----
    NearDegenerateWarning
        The sine of the angle between the two vectors is below :data:`TRIAD_WARN_SIN`.

    Examples
    --------
    Body X and Y measured along reference Y and -X: a 90 deg turn about Z. ``b1`` need not be a unit vector,
    and ``b2`` need not be normal to it (only its component normal to ``b1`` is used):

    >>> import numpy as np
    >>> from gnssatt.attitude.wahba import triad
    >>> result = triad([2.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0], [-1.0, 0.0, 0.0])
    >>> np.round(result.rotation.as_matrix(), 6) + 0.0
    array([[ 0., -1.,  0.],
           [ 1.,  0.,  0.],
           [ 0.,  0.,  1.]])
    >>> round(result.sin_angle_body, 6)  # 45 deg between b1 and b2
    0.707107
    """
    batch_limit(MAX_BATCH_ROWS, "MAX_BATCH_ROWS", "epochs", b1=(b1, 1), b2=(b2, 1), r1=(r1, 1), r2=(r2, 1))
    arrs = [rescaled(checked_vectors(n, v)) for n, v in (("b1", b1), ("b2", b2), ("r1", r1), ("r2", r2))]
    single = all(a.ndim == 1 for a in arrs)
    try:
        arrs = [np.ascontiguousarray(a) for a in np.broadcast_arrays(*(np.atleast_2d(a) for a in arrs))]
    except ValueError:
        raise InvalidInputError(
            f"expected b1, b2, r1, r2 of one shape (epochs, 3), got {[a.shape for a in arrs]}"
        ) from None
    if arrs[0].shape[0] == 0:
        # numpy broadcasts a single pair against an empty batch to nothing; that is a mismatch here
        raise InvalidInputError(
            f"expected b1, b2, r1, r2 with at least one epoch, got shapes "
            f"{[np.shape(v) for v in (b1, b2, r1, r2)]}"
        )
    out = _core.triad_batch(*arrs)
    quat, sb, sr = out.quat_ref_from_body, out.sin_angle_body, out.sin_angle_ref
    finite_outputs("triad", quaternion=quat, sine=np.concatenate([sb, sr]))
    warn_small(np.minimum(sb, sr), TRIAD_WARN_SIN, "the sine of the angle between the TRIAD vectors")
    if single:
        return TriadResult(Rotation.from_quat(quat[0]), float(sb[0]), float(sr[0]))
    return TriadResult(Rotation.from_quat(quat), sb, sr)


@dataclass(frozen=True)
class WahbaResult:
    """Attitude from :func:`wahba`.

    Attributes
    ----------
    rotation
        Body -> reference rotation (a batch Rotation for batch input).
    covariance
        (3, 3) or (epochs, 3, 3) covariance in rad^2 of the small rotation vector ``delta`` with
        ``rotation = Rotation.from_rotvec(delta) * truth``, ``delta`` in the *reference* frame:
        ``P = [sum_i w_i (I - r_i r_i^T)]^-1`` (Shuster 1989). It is the Cramer-Rao bound for body unit
        vectors with isotropic errors of standard deviation ``sigma_i`` (rad) when ``weights = 1/sigma_i^2``;
        with other weights multiply it by ``sigma^2 * w``. Body frame: ``R^T P R``.
    information_ratio
        Smallest over largest eigenvalue of ``sum_i w_i (I - r_i r_i^T)`` (1 / condition number).
    loss
        Wahba's loss ``(1/2) sum_i w_i |r_i - R b_i|^2`` at the estimate (unit vectors).
    method
        The solver used.
    """

    rotation: Rotation
    covariance: NDArray[np.float64]
    information_ratio: float | NDArray[np.float64]
    loss: float | NDArray[np.float64]
    method: Method


def wahba(
    body: ArrayLike, ref: ArrayLike, weights: ArrayLike | None = None, *, method: Method = "svd"
) -> WahbaResult:
    """Solve Wahba's problem: the rotation minimising ``sum_i w_i |r_i - R b_i|^2`` over unit vectors.

    Parameters
    ----------
    body
        (n, 3) body-frame vectors, or (epochs, n, 3) for a batch; any length (normalised); n >= 2.
    ref
        The same directions in the reference frame, same shape.
    weights
        (n,) or (epochs, n) non-negative weights, not all zero; ``1 / sigma_i^2`` (rad^-2) makes
        ``covariance`` the Cramer-Rao bound. Default: all ones. Only their ratios enter the rotation (the
        core sees them divided by the largest of each epoch, so any finite scale works); ``covariance``
        and ``loss`` scale with them.
    method
        ``"svd"`` (Markley 1988, determinant fixed so the result is never a reflection),
        ``"davenport"`` (q-method, 4x4 symmetric eigenproblem) or ``"quest"`` (Shuster & Oh 1981, with
        sequential rotations near 180 deg). All three give the same optimum to rounding; QUEST's
        characteristic quartic loses it when the weights span more than about 1e6 (measured against
        ``scipy.spatial.transform.Rotation.align_vectors``: 4 wrong rotations in 1000 at 1e6, none off by
        1e-8 rad at 1e5), so ``"quest"`` refuses weights spanning more than
        :data:`QUEST_MAX_WEIGHT_SPAN` (use ``"svd"`` or ``"davenport"`` there).

    Returns
    -------
    WahbaResult

    Raises
    ------
    InvalidInputError
        Weights spanning more than :data:`QUEST_MAX_WEIGHT_SPAN` with ``method="quest"``; wrong shapes,
        non-finite values, negative weights, weights all zero, an unknown ``method``
        (:class:`~gnssatt.errors.InvalidTypeError` for values that are not real numbers or text).
    WorkLimitError
        More than :data:`MAX_VECTOR_PAIRS` vector pairs, refused before they are copied.
    DegenerateGeometryError
        A zero vector, or reference vectors all parallel (among the pairs with non-negligible weights);
        the message names ``body``, ``ref`` and ``weights`` and the epoch.
    ConvergenceError
        Weights so small that the covariance overflows (below about 1e-300), or another non-finite result.

    Warns
    -----
    NearDegenerateWarning
        ``information_ratio`` below :data:`WAHBA_WARN_RATIO`.

    Examples
    --------
    Noise-free vector pairs give back the attitude they were made with, at zero loss:

    >>> import numpy as np
    >>> from scipy.spatial.transform import Rotation
    >>> from gnssatt.attitude.wahba import wahba
    >>> true = Rotation.from_euler("zyx", [40.0, -10.0, 5.0], degrees=True)  # body -> reference
    >>> body = np.eye(3)  # (3, 3) unit vectors, body frame
    >>> result = wahba(body, true.apply(body))
    >>> np.round(result.rotation.as_euler("zyx", degrees=True), 6) + 0.0
    array([ 40., -10.,   5.])
    >>> round(result.loss, 9) + 0.0
    0.0

    Two orthogonal reference vectors X and Y with unit weights: ``P = [diag(0, 1, 1) + diag(1, 0, 1)]^-1``,
    the rotation about Z (fixed by both) half as uncertain in variance:

    >>> np.round(wahba(body[:2], body[:2]).covariance, 6) + 0.0
    array([[1. , 0. , 0. ],
           [0. , 1. , 0. ],
           [0. , 0. , 0.5]])
    """
    b3, r, single = _checked_pairs(body, ref, weights)
    w = _checked_weights(weights, *b3.shape[:2])
    _check_weight_span(w, method)
    quat, cov, ratio, loss = _solved_batch(b3, r, w, method)
    finite_outputs("wahba", quaternion=quat, covariance=cov, information_ratio=ratio, loss=loss)
    warn_small(ratio, WAHBA_WARN_RATIO, "the information ratio of the vector pairs")  # here: its stacklevel
    if single:
        return WahbaResult(Rotation.from_quat(quat[0]), cov[0], float(ratio[0]), float(loss[0]), method)
    return WahbaResult(Rotation.from_quat(quat), cov, ratio, loss, method)


def _checked_pairs(
    body: ArrayLike, ref: ArrayLike, weights: ArrayLike | None
) -> tuple[NDArray[np.float64], NDArray[np.float64], bool]:
    """The vector pairs of :func:`wahba` (sizes and ``weights``' against the limit first): body vectors
    (epochs, n, 3), reference vectors of their shape as given, and whether a single epoch was given."""
    batch_limit(
        MAX_VECTOR_PAIRS,
        "MAX_VECTOR_PAIRS",
        "vector pairs",
        body=(body, 1),
        ref=(ref, 1),
        weights=(weights, 0),
    )
    b = rescaled(shaped("body", body, "(n, 3) or (epochs, n, 3)", (None, 3), (None, None, 3)))
    r = rescaled(shaped("ref", ref, "(n, 3) or (epochs, n, 3)", (None, 3), (None, None, 3)))
    if b.shape != r.shape:
        raise InvalidInputError(
            f"expected body and ref of one shape (..., n, 3), got {b.shape} and {r.shape}"
        )
    single = b.ndim == 2
    b3 = b[None] if single else b
    if b3.shape[1] < 2:
        raise InvalidInputError(f"expected at least 2 vector pairs per epoch, got {b3.shape[1]}")
    return b3, r, single


def _checked_weights(weights: ArrayLike | None, epochs: int, n: int) -> NDArray[np.float64]:
    """The (epochs, n) weights of :func:`wahba` (ones by default): non-negative, not all zero in an epoch."""
    if weights is None:
        return np.ones((epochs, n))
    w = float_array("weights", weights, ndim=(1, 2), shape="(n,) or (epochs, n)")
    try:
        w = np.ascontiguousarray(np.broadcast_to(w, (epochs, n)))
    except ValueError:
        raise InvalidInputError(
            f"expected weights of shape ({n},) or ({epochs}, {n}), got {w.shape}"
        ) from None
    if np.any(w < 0.0):
        k = tuple(int(i) for i in np.argwhere(w < 0.0)[0])
        raise InvalidInputError(f"expected non-negative weights, got {w[k]} at (epoch, pair) {k}")
    zero = np.all(w == 0.0, axis=1)
    if np.any(zero):
        raise InvalidInputError(
            f"expected weights not all zero, got all zero at epoch {int(np.argmax(zero))}"
        )
    return w


def _check_weight_span(w: NDArray[np.float64], method: Method) -> None:
    """QUEST's limit on the weights' span (largest / smallest positive) in each epoch."""
    if method != "quest":
        return
    with np.errstate(divide="ignore"):
        span = np.max(w, axis=1) / np.min(np.where(w > 0.0, w, np.inf), axis=1)
    if np.any(span > QUEST_MAX_WEIGHT_SPAN):
        e = int(np.argmax(span))
        raise InvalidInputError(
            f"expected weights spanning at most {QUEST_MAX_WEIGHT_SPAN:g} (largest / smallest positive) "
            f"for method 'quest', got {span[e]:.3g} at epoch {e}: QUEST's characteristic quartic loses "
            "the optimum there; use method 'svd' or 'davenport'"
        )


def _solved_batch(
    b3: NDArray[np.float64], r: NDArray[np.float64], w: NDArray[np.float64], method: Method
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
    """The core's quaternions, covariances, information ratios and losses of every epoch."""
    # the core sees weights relative to the largest of each epoch; covariance and loss scale back
    scale = np.max(w, axis=1)
    try:
        out = _core.wahba_batch(
            b3.reshape(-1, 3),
            np.ascontiguousarray(r.reshape(-1, 3)),
            (w / scale[:, None]).reshape(-1),
            b3.shape[1],
            method,
        )
        quat, cov, ratio, loss = out.quat_ref_from_body, out.covariance_ref, out.information_ratio, out.loss
    except DegenerateGeometryError as exc:
        # the degeneracy is a property of the pairs together: name the arguments that form them
        raise DegenerateGeometryError(
            f"body, ref and weights do not fix the attitude together: {exc}"
        ) from exc
    with np.errstate(over="ignore"):
        cov, loss = cov / scale[:, None, None], loss * scale
    return quat, cov, ratio, loss
