"""Receiver -> satellite geometry: unit lines of sight, ranges and range rates.

Conventions of :mod:`gnssatt.sim`: SI units and radians inside; ``t`` in seconds from the scenario epoch.
Lines of sight ``gamma_k`` are unit vectors from the receiver (its reference point) to satellite k, given in
the receiver's reference frame (ENU on the ground, the orbital frame in orbit; see
:mod:`gnssatt.orbit.receivers`). Body-frame lines of sight use an attitude ``Rotation`` mapping body ->
reference: ``gamma_body = attitude.inv().apply(gamma_ref)``.

Ranges are instantaneous geometric distances (no light-time, Sagnac, clock or atmosphere terms); range rates
are ``gamma . (v_sat - v_rx)`` with both velocities in ECI, the time derivative of that distance.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.spatial.transform import Rotation

from gnssatt._arrays import (
    MAX_BATCH_ROWS,
    batch_limit,
    checked_array,
    finite_result,
    instance,
    plain_array,
    readonly,
    real_array,
    text,
    vector_array,
)
from gnssatt.errors import InvalidInputError, InvalidTypeError, WorkLimitError
from gnssatt.orbit.constellation import Constellation
from gnssatt.orbit.receivers import GroundReceiver, OrbitalReceiver

__all__ = ["MAX_GEOMETRY_VALUES", "Geometry", "elevation_azimuth", "line_of_sight", "los_body"]

#: Most (time, satellite) pairs one :func:`line_of_sight` call computes: 2^22, about 870 MB of arrays
#: (210 bytes a pair, measured with tracemalloc) and, measured on the loaded 2-core build machine, 5-10 us
#: a pair. A day at 1 s of 32 satellites is 2.8e6.
MAX_GEOMETRY_VALUES = 2**22


@dataclass(frozen=True)
class Geometry:
    """Lines of sight from one receiver to n_sat satellites at one epoch or n_t epochs.

    Attributes
    ----------
    los
        (n_sat, 3) or (n_t, n_sat, 3) unit vectors receiver -> satellite in the reference frame ``frame``.
    range_m
        (n_sat,) or (n_t, n_sat) geometric ranges, m.
    range_rate_mps
        Same shape, time derivative of ``range_m``, m/s (negative while the satellite approaches).
    frame
        ``"enu"``, ``"orbital"`` or another label of the reference frame of ``los``.
    ids
        Satellite ids (length n_sat).
    t
        Epochs, s: shape () or (n_t,).
    receiver_eci_m
        (3,) or (n_t, 3) receiver position in ECI, m (NaN where unknown, e.g. from :meth:`from_los`).
    satellites_eci_m
        (n_sat, 3) or (n_t, n_sat, 3) satellite positions in ECI, m (NaN where unknown).
    """

    los: NDArray[np.float64]
    range_m: NDArray[np.float64]
    range_rate_mps: NDArray[np.float64]
    frame: str
    ids: tuple[str, ...]
    t: NDArray[np.float64]
    receiver_eci_m: NDArray[np.float64]
    satellites_eci_m: NDArray[np.float64]

    def __post_init__(self) -> None:
        los = vector_array("los", self.los, ndim=(2, 3), shape="(n_sat, 3) or (n_t, n_sat, 3)").copy()
        lead = los.shape[:-1]
        text("frame", self.frame)
        ids = tuple(instance("ids", self.ids, tuple | list, "a tuple of str"))
        if len(ids) != lead[-1] or not all(isinstance(i, str) for i in ids):
            raise InvalidInputError(f"expected ids as {lead[-1]} str (one per satellite), got {ids!r}"[:300])
        arrays = {"los": los}
        for name, want, finite in (
            ("range_m", lead, True),
            ("range_rate_mps", lead, True),
            ("t", lead[:-1], True),
            ("receiver_eci_m", (*lead[:-1], 3), False),
            ("satellites_eci_m", (*lead, 3), False),
        ):
            value = getattr(self, name)
            if finite:
                arr = checked_array(name, value, ndim=(0, 1, 2), shape=str(want)).copy()
            else:  # NaN where unknown
                arr = real_array(name, value)
            if arr.shape != want:
                raise InvalidInputError(f"expected {name} of shape {want}, got {arr.shape}")
            arrays[name] = arr
        object.__setattr__(self, "ids", ids)
        for name, arr in arrays.items():
            object.__setattr__(self, name, arr)
        readonly(self.los, self.range_m, self.range_rate_mps, self.t)
        readonly(self.receiver_eci_m, self.satellites_eci_m)

    @classmethod
    def from_los(
        cls,
        los: ArrayLike,
        range_m: ArrayLike = 2.0e7,
        range_rate_mps: ArrayLike = 0.0,
        *,
        frame: str = "enu",
        ids: tuple[str, ...] | None = None,
    ) -> Geometry:
        """Geometry from given lines of sight, without orbits (e.g. the static scenarios of Ryzhkov and
        Oliinyk and of Bunyaeva et al.).

        Parameters
        ----------
        los
            (n_sat, 3) or (n_t, n_sat, 3) lines of sight in the reference frame; normalised here.
        range_m, range_rate_mps
            Ranges (m) and range rates (m/s), broadcast to the leading shape of ``los``.
        frame
            Label of the reference frame.
        ids
            Satellite ids; default ``"S01"``, ``"S02"``, ...
        """
        g = vector_array("los", los, ndim=(2, 3), shape="(n_sat, 3) or (n_t, n_sat, 3)")
        norm = np.linalg.norm(g, axis=-1, keepdims=True)
        if np.any(norm < 1e-12):
            raise InvalidInputError("expected non-zero lines of sight in los, got a zero vector")
        g = g / norm
        text("frame", frame)
        lead = g.shape[:-1]
        n_sat = lead[-1]
        try:
            rho = np.broadcast_to(
                checked_array("range_m", range_m, ndim=(0, 1, 2), shape=str(lead)), lead
            ).copy()
            rr = np.broadcast_to(
                checked_array("range_rate_mps", range_rate_mps, ndim=(0, 1, 2), shape=str(lead)), lead
            ).copy()
        except InvalidInputError:
            raise
        except ValueError as exc:
            raise InvalidInputError(f"expected range_m and range_rate_mps broadcastable to {lead}") from exc
        if np.any(rho <= 0):
            raise InvalidInputError(f"expected range_m > 0, got minimum {rho.min()}")
        if ids is None:
            ids = tuple(f"S{k + 1:02d}" for k in range(n_sat))
        instance("ids", ids, tuple | list, "a tuple of str")
        if len(ids) != n_sat:
            raise InvalidInputError(f"expected {n_sat} ids, got {len(ids)}")
        t = np.zeros(lead[:-1])
        nan_rx = np.full((*lead[:-1], 3), np.nan)
        nan_sat = np.full((*lead, 3), np.nan)
        return cls(g, rho, rr, frame, tuple(ids), t, nan_rx, nan_sat)

    @property
    def n_sat(self) -> int:
        """Number of satellites."""
        return len(self.ids)

    def los_body(self, attitude: Rotation) -> NDArray[np.float64]:
        """Lines of sight in the body frame for a body -> reference ``attitude`` (see :func:`los_body`)."""
        return los_body(self.los, attitude)

    def elevation_azimuth(self) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """Elevation and azimuth of each satellite, rad (see :func:`elevation_azimuth`; ENU frame only)."""
        if self.frame != "enu":
            raise InvalidInputError(f"expected a geometry in the 'enu' frame, got {self.frame!r}")
        return elevation_azimuth(self.los)

    def select(self, mask: ArrayLike) -> Geometry:
        """The satellites where ``mask`` (n_sat,) is true, or given by an integer index array.

        For several epochs the same satellites are kept at every epoch.
        """
        m = np.asarray(mask)
        if m.dtype == bool:
            if m.shape != (self.n_sat,):
                raise InvalidInputError(f"expected a boolean mask of shape ({self.n_sat},), got {m.shape}")
            idx = np.flatnonzero(m)
        elif m.dtype.kind in "iu":
            idx = m.reshape(-1)
            if idx.size and (idx.min() < -self.n_sat or idx.max() >= self.n_sat):
                raise InvalidInputError(
                    f"expected mask indices in [-{self.n_sat}, {self.n_sat}), got [{idx.min()}, {idx.max()}]"
                )
        else:
            raise InvalidTypeError(f"expected mask as a boolean mask or integer indices, got dtype {m.dtype}")
        return replace(
            self,
            los=self.los[..., idx, :],
            range_m=self.range_m[..., idx],
            range_rate_mps=self.range_rate_mps[..., idx],
            ids=tuple(self.ids[i] for i in idx),
            satellites_eci_m=self.satellites_eci_m[..., idx, :],
        )


def attitude_matrices(attitude: Any, n_t: int | None) -> NDArray[np.float64]:
    """Body -> reference matrices of ``attitude``, a scipy Rotation: (3, 3) for a single one, (n_t, 3, 3) for
    one per epoch (``n_t`` None: only a single one is accepted). Shared with the simulator's measurements
    (not in ``__all__``).

    Raises
    ------
    InvalidTypeError
        ``attitude`` is not a scipy Rotation.
    InvalidInputError
        A stack of another length than ``n_t``, or any stack where ``n_t`` is None.
    """
    instance("attitude", attitude, Rotation, "a scipy Rotation")
    m: NDArray[np.float64] = attitude.as_matrix()
    if m.ndim == 3:
        if n_t is None or m.shape[0] != n_t:
            want = "a single Rotation" if n_t is None else f"a single Rotation or {n_t} rotations"
            raise InvalidInputError(
                f"expected attitude as {want} (one per epoch), got {m.shape[0]} rotations"
            )
    return m


def los_body(los: ArrayLike, attitude: Rotation) -> NDArray[np.float64]:
    """Lines of sight in the body frame: ``R^T gamma`` for the body -> reference rotation ``R``.

    Parameters
    ----------
    los
        (n_sat, 3) or (n_t, n_sat, 3) unit vectors in the reference frame.
    attitude
        Body -> reference rotation: a single one, or n_t of them (one per epoch).

    Returns
    -------
    Body-frame unit vectors, shape of ``los``.

    Raises
    ------
    InvalidInputError
        Wrong shapes or non-finite lines of sight, a number of rotations other than one or n_t
        (:class:`~gnssatt.errors.InvalidTypeError` for an ``attitude`` that is not a scipy ``Rotation``).
    ConvergenceError
        Entries of ``los`` so large (near 1e308) that the rotated vectors overflow float64.

    Examples
    --------
    A body turned 90 deg about Up (its X axis to the North): a satellite due North lies along body X:

    >>> import numpy as np
    >>> from scipy.spatial.transform import Rotation
    >>> from gnssatt.orbit.line_of_sight import los_body
    >>> attitude = Rotation.from_euler("z", 90.0, degrees=True)  # body -> ENU
    >>> np.round(los_body([[0.0, 1.0, 0.0]], attitude), 6) + 0.0
    array([[1., 0., 0.]])
    """
    batch_limit(MAX_BATCH_ROWS, "MAX_BATCH_ROWS", "lines of sight", los=(los, 1))
    g = vector_array("los", los, ndim=(2, 3), shape="(n_sat, 3) or (n_t, n_sat, 3)")
    m = attitude_matrices(attitude, g.shape[0] if g.ndim == 3 else None)
    with np.errstate(over="ignore", invalid="ignore"):  # an overflow is reported below, as an error
        if m.ndim == 3:
            body: NDArray[np.float64] = np.einsum("tji,tkj->tki", m, g)  # einsum's result is typed Any
        else:
            body = g @ m
    # los is not required to be unit: entries near 1e308 overflow when rotated
    return finite_result("los_body", body, "los too large to rotate in float64")


def elevation_azimuth(los_enu: ArrayLike) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Elevation above the local horizontal and azimuth (from North towards East, in [0, 2 pi)), rad.

    Parameters
    ----------
    los_enu
        (..., 3) unit lines of sight in ENU.

    Returns
    -------
    elevation, azimuth
        Arrays of the leading shape of ``los_enu``, rad: elevation in [-pi/2, pi/2], azimuth in [0, 2 pi).

    Raises
    ------
    InvalidInputError
        Wrong shapes, non-finite values or a zero vector (:class:`~gnssatt.errors.InvalidTypeError` for values
        that are not real numbers).

    Examples
    --------
    North-east at 45 deg up, and due East on the horizon:

    >>> import numpy as np
    >>> from gnssatt.orbit.line_of_sight import elevation_azimuth
    >>> el, az = elevation_azimuth([[0.5, 0.5, np.sqrt(0.5)], [1.0, 0.0, 0.0]])
    >>> np.round(np.degrees(el), 6) + 0.0, np.round(np.degrees(az), 6) + 0.0
    (array([45.,  0.]), array([45., 90.]))
    """
    batch_limit(MAX_BATCH_ROWS, "MAX_BATCH_ROWS", "lines of sight", los_enu=(los_enu, 1))
    g = vector_array("los_enu", los_enu, ndim=(1, 2, 3), shape="(..., 3)", nonzero=True)
    el = np.arcsin(np.clip(g[..., 2] / np.linalg.norm(g, axis=-1), -1.0, 1.0))
    az = np.arctan2(g[..., 0], g[..., 1]) % (2.0 * np.pi)
    return el, az


def line_of_sight(
    receiver: GroundReceiver | OrbitalReceiver, constellation: Constellation, t: ArrayLike
) -> Geometry:
    """Lines of sight, ranges and range rates from ``receiver`` to every satellite of ``constellation``.

    Parameters
    ----------
    receiver
        A :class:`~gnssatt.orbit.receivers.GroundReceiver` (lines of sight in ENU) or
        :class:`~gnssatt.orbit.receivers.OrbitalReceiver` (orbital frame).
    constellation
        The satellites; no visibility test is applied here (see :mod:`gnssatt.orbit.masks`).
    t
        Seconds from the epoch, () or (n_t,).

    Returns
    -------
    Geometry
        Unbatched for a scalar ``t``, with a leading epoch axis for an array.

    Raises
    ------
    InvalidInputError
        Non-finite or wrongly shaped ``t``, a receiver that coincides with a satellite
        (:class:`~gnssatt.errors.InvalidTypeError` for a ``receiver`` or ``constellation`` of another type).
    WorkLimitError
        More than :data:`MAX_GEOMETRY_VALUES` times x satellites, refused before any is computed.

    Examples
    --------
    A satellite 1000 km straight above an equatorial receiver at ``t = 0``: the line of sight is the orbital
    frame's zenith, the range 1000 km, and the range rate zero (both velocities are normal to it):

    >>> import numpy as np
    >>> from gnssatt.orbit.constellation import walker
    >>> from gnssatt.orbit.line_of_sight import line_of_sight
    >>> from gnssatt.orbit.receivers import OrbitalReceiver
    >>> receiver = OrbitalReceiver(500e3, inclination_deg=0.0)  # m, deg
    >>> above = walker(1, 1, 0, inclination_deg=0.0, semi_major_axis_m=receiver.radius_m + 1000e3)
    >>> geometry = line_of_sight(receiver, above, 0.0)
    >>> geometry.frame, np.round(geometry.los, 6) + 0.0
    ('orbital', array([[0., 0., 1.]]))
    >>> np.round(geometry.range_m, 3), np.round(geometry.range_rate_mps, 6) + 0.0
    (array([1000000.]), array([0.]))
    """
    instance("receiver", receiver, GroundReceiver | OrbitalReceiver, "a GroundReceiver or OrbitalReceiver")
    instance("constellation", constellation, Constellation, "a Constellation")
    n_values = np.size(plain_array("t", t)) * len(constellation)
    if n_values > MAX_GEOMETRY_VALUES:
        raise WorkLimitError(
            f"t asks for {np.size(plain_array('t', t))} times x {len(constellation)} satellites = {n_values} "
            f"lines of sight, more than the limit of {MAX_GEOMETRY_VALUES} (MAX_GEOMETRY_VALUES): split t"
        )
    tt = np.asarray(checked_array("t", t, ndim=(0, 1), shape="() or (n_t,)"))
    r_s, v_s = constellation.state_eci(tt)
    r_r, v_r = receiver.state_eci(tt)
    d = r_s - r_r[..., None, :]
    rho = np.linalg.norm(d, axis=-1)
    if np.any(rho == 0.0):
        raise InvalidInputError("receiver coincides with a satellite: the line of sight is undefined")
    g_eci = d / rho[..., None]
    rate = np.sum(g_eci * (v_s - v_r[..., None, :]), axis=-1)
    m = receiver.dcm_eci_from_reference(tt)  # (..., 3, 3) reference -> ECI
    g_ref = np.einsum("...ji,...kj->...ki", m, g_eci)
    return Geometry(g_ref, rho, rate, receiver.frame, constellation.ids, tt, r_r, r_s)
