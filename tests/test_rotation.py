"""The rotation conventions of docs/conventions.md, pinned against scipy.spatial.transform.Rotation."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

import gnssatt
from gnssatt import rotation

SEQUENCES = ["XYZ", "XZY", "YXZ", "YZX", "ZXY", "ZYX", "XYX", "XZX", "YXY", "YZY", "ZXZ", "ZYZ"]


@pytest.mark.parametrize("seq", SEQUENCES)
def test_euler_matches_scipy_intrinsic(seq: str, rng: np.random.Generator) -> None:
    for _ in range(20):
        r = Rotation.random(random_state=rng)
        angles = r.as_euler(seq)
        np.testing.assert_allclose(rotation.euler_to_dcm(seq, angles), r.as_matrix(), atol=1e-12)
        back = rotation.dcm_to_euler(seq, r.as_matrix())
        np.testing.assert_allclose(Rotation.from_euler(seq, back).as_matrix(), r.as_matrix(), atol=1e-12)
        np.testing.assert_allclose(back, angles, atol=1e-9)


def test_degrees_flag() -> None:
    np.testing.assert_allclose(
        rotation.euler_to_dcm("ZYX", [90, 0, 0], degrees=True),
        Rotation.from_euler("z", 90, degrees=True).as_matrix(),
        atol=1e-15,
    )


def test_quaternions_are_scalar_last_like_scipy(rng: np.random.Generator) -> None:
    for r in Rotation.random(20, random_state=rng):
        q = r.as_quat(canonical=True)
        np.testing.assert_allclose(rotation.dcm_to_quat(r.as_matrix()), q, atol=1e-12)
        np.testing.assert_allclose(rotation.quat_to_dcm(q * 3.0), r.as_matrix(), atol=1e-12)


def test_nearest_rotation_fixes_reflections(rng: np.random.Generator) -> None:
    r = Rotation.random(random_state=rng).as_matrix()
    noisy = r + 1e-3 * rng.standard_normal((3, 3))
    np.testing.assert_allclose(
        rotation.nearest_rotation(noisy), Rotation.from_matrix(noisy).as_matrix(), atol=1e-9
    )
    reflected = r @ np.diag([1.0, 1.0, -1.0])
    out = rotation.nearest_rotation(reflected)
    assert np.linalg.det(out) == pytest.approx(1.0)


def test_gost_sequence_reading() -> None:
    # At zero angles body X (nose) -> North, Y -> Up, Z (right wing) -> East in the (N, U, E) normal frame;
    # positive heading about Up turns the nose West (towards -East).
    turn = rotation.euler_to_dcm("YZX", [10, 0, 0], degrees=True)
    nose = turn @ [1.0, 0.0, 0.0]
    assert nose[2] < 0.0 and nose[0] > 0.98
    raised = rotation.euler_to_dcm("YZX", [0, 10, 0], degrees=True) @ [1.0, 0.0, 0.0]
    assert raised[1] > 0.0  # positive pitch raises the nose
    rolled = rotation.euler_to_dcm("YZX", [0, 0, 10], degrees=True) @ [0.0, 0.0, 1.0]
    assert rolled[1] < 0.0  # positive roll lowers the right wing


@pytest.mark.parametrize(
    ("call", "match"),
    [
        (lambda: rotation.euler_to_dcm("ZZX", [0, 0, 0]), "seq"),
        (lambda: rotation.euler_to_dcm("ZYX", [0, 0]), r"shape \(3,\)"),
        (lambda: rotation.dcm_to_euler("ZYX", np.eye(3) * 2), "orthogonal"),
        (lambda: rotation.dcm_to_euler("ZYX", np.diag([1.0, 1.0, -1.0])), "det"),
        (lambda: rotation.quat_to_dcm([0, 0, 0, 0]), "non-zero"),
        (lambda: rotation.nearest_rotation(np.full((3, 3), np.nan)), "non-finite"),
        (lambda: rotation.nearest_rotation(np.eye(2)), r"\(3, 3\)"),
    ],
)
def test_bad_input(call, match: str) -> None:  # type: ignore[no-untyped-def]
    with pytest.raises(gnssatt.InvalidInputError, match=match):
        call()
