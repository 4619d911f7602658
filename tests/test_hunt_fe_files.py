"""Trust hunt, stop 28: matrix files as FE codes and MATLAB write them.

The reference is the matrix written: every file must read back to it
exactly, or be refused with a message that says why."""

import numpy as np
import pytest
import scipy.io as sio
import scipy.sparse as sp

from hbmfric.systems.matrix_files import read_matrices, read_matrix

N = 6
K = 1000.0 * (2.0 * np.eye(N) - np.eye(N, k=1) - np.eye(N, k=-1))
K[-1, -1] = 1000.0
M = np.diag(np.arange(1.0, N + 1.0))


def _write_triangle(path, upper: bool) -> None:
    """A 'symmetric' coordinate file storing one triangle, 1-based."""
    rows, cols = np.nonzero(np.triu(K) if upper else np.tril(K))
    lines = ["%%MatrixMarket matrix coordinate real symmetric", f"{N} {N} {rows.size}"]
    lines += [
        f"{i + 1} {j + 1} {K[i, j]:.17g}" for i, j in zip(rows, cols, strict=True)
    ]
    path.write_text("\n".join(lines) + "\n")


@pytest.mark.parametrize("upper", [False, True])
def test_symmetric_coordinate_file_either_triangle(tmp_path, upper):
    path = tmp_path / "K.mtx"
    _write_triangle(path, upper)
    np.testing.assert_array_equal(read_matrix(path), K)


def test_symmetric_integer_and_array_files(tmp_path):
    sio.mmwrite(tmp_path / "Ki.mtx", sp.coo_matrix(K.astype(int)), symmetry="symmetric")
    np.testing.assert_array_equal(read_matrix(tmp_path / "Ki.mtx"), K)
    sio.mmwrite(tmp_path / "Ka.mtx", K, symmetry="symmetric")
    np.testing.assert_array_equal(read_matrix(tmp_path / "Ka.mtx"), K)


def test_complex_files_are_refused(tmp_path):
    """A structural-damping K(1 + iη), or a complex field with zero
    imaginary parts: refused (the cast would drop the imaginary part)."""
    sio.mmwrite(tmp_path / "Kc.mtx", sp.coo_matrix(K * (1 + 0.01j)))
    with pytest.raises(ValueError, match="real numbers"):
        read_matrix(tmp_path / "Kc.mtx")
    sio.savemat(tmp_path / "mc.mat", {"K": K * (1 + 0.02j), "M": M})
    with pytest.raises(ValueError, match="real numbers"):
        read_matrices(tmp_path / "mc.mat")


def test_sparse_and_integer_mat_file(tmp_path):
    sio.savemat(tmp_path / "m.mat", {"K": sp.csc_matrix(K), "M": M.astype(np.int32)})
    found = read_matrices(tmp_path / "m.mat")
    np.testing.assert_array_equal(found["stiffness"], K)
    np.testing.assert_array_equal(found["mass"], M)


def test_abaqus_matrix_output_is_named_in_the_refusal(tmp_path):
    """Abaqus's *MATRIX OUTPUT file is also called .mtx but has no Matrix
    Market banner; the refusal says what it is (scipy's own message was
    'Line 1: Not a Matrix Market file. Missing banner.')."""
    path = tmp_path / "Job-1_STIF1.mtx"
    path.write_text("1,1,1,1,  2.0e+04\n1,1,2,1, -1.0e+04\n2,1,2,1,  1.0e+04\n")
    with pytest.raises(ValueError, match="Abaqus"):
        read_matrix(path)
