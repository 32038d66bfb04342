# Type stubs of the native module gnssatt._core (rust/py). Keep in step with rust/py/src/*.rs:
# tests/test_stubs.py checks that every native function is declared here.
import numpy as np
from numpy.typing import NDArray

__version__: str

# rotation.rs
def euler_to_dcm(seq: str, angles_rad: tuple[float, float, float]) -> NDArray[np.float64]: ...
def dcm_to_euler(seq: str, dcm: NDArray[np.float64]) -> tuple[float, float, float]: ...
def quat_to_dcm(quat: tuple[float, float, float, float]) -> NDArray[np.float64]: ...
def dcm_to_quat(dcm: NDArray[np.float64]) -> tuple[float, float, float, float]: ...
def nearest_rotation(matrix: NDArray[np.float64]) -> NDArray[np.float64]: ...

# matrix_method.rs
def matrix_attitude(
    baselines: NDArray[np.float64],
    los: NDArray[np.float64],
    range_diffs: NDArray[np.float64],
    method: str = "svd",
) -> tuple[NDArray[np.float64], NDArray[np.float64], float]: ...

# wahba.rs (epochs flattened by gnssatt.vector_attitude / gnssatt.magnetometer)
def wahba_batch(
    body: NDArray[np.float64],
    reference: NDArray[np.float64],
    weights: NDArray[np.float64],
    pairs: int,
    method: str = "svd",
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]: ...
def triad_batch(
    b1: NDArray[np.float64], b2: NDArray[np.float64], r1: NDArray[np.float64], r2: NDArray[np.float64]
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]: ...
def yaw_batch(
    b_body: NDArray[np.float64],
    b_orbital: NDArray[np.float64],
    pitch_rad: NDArray[np.float64],
    roll_rad: NDArray[np.float64],
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]: ...
