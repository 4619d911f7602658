"""Matrix files an FE user writes from Python (stop 35, hunt37).

``scipy.sparse.save_npz`` is how a sparse K leaves a Python FE script; it
was refused as "holds 5 arrays (data, format, indices, indptr, shape); say
which with name=", and ``name="data"`` returned the nonzeros as a vector.
A Matrix Market file written with 0-based indices was refused by scipy's
"Line 3: Row index out of bounds", naming neither the file nor the rule.
Reference: the matrix written.
"""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse as sp

import hbmfric as hf
from hbmfric.systems.matrix_files import read_matrices

K = 1e3 * np.array([[2.0, -1.0, 0.0], [-1.0, 2.0, -1.0], [0.0, -1.0, 1.0]])


@pytest.mark.parametrize("fmt", ["csr", "csc", "coo", "bsr", "dia"])
def test_save_npz_file_is_read_as_its_matrix(tmp_path, fmt):
    path = tmp_path / "K.npz"
    sp.save_npz(path, sp.csr_matrix(K).asformat(fmt))
    np.testing.assert_array_equal(hf.read_matrix(path), K)


def test_structure_from_a_save_npz_stiffness(tmp_path):
    sp.save_npz(tmp_path / "K.npz", sp.csr_matrix(K))
    np.save(tmp_path / "M.npy", 0.1 * np.eye(3))
    s = hf.LinearStructure.from_files(tmp_path / "M.npy", tmp_path / "K.npz")
    w2 = np.linalg.eigvalsh(K / 0.1)
    np.testing.assert_allclose(
        s.natural_frequencies(), np.sqrt(w2) / (2 * np.pi), rtol=1e-12
    )
    with pytest.raises(ValueError, match="one sparse matrix"):
        read_matrices(tmp_path / "K.npz")


def test_zero_based_matrix_market_names_the_file(tmp_path):
    path = tmp_path / "zero.mtx"
    path.write_text(
        "%%MatrixMarket matrix coordinate real general\n2 2 2\n0 0 1.0\n1 1 1.0\n"
    )
    with pytest.raises(ValueError, match=r"zero\.mtx.*count from 1"):
        hf.read_matrix(path)


@pytest.mark.parametrize("triangle", [np.triu, np.tril])
def test_one_triangle_in_a_mat_file_is_named(tmp_path, triangle):
    import scipy.io

    path = tmp_path / "model.mat"
    scipy.io.savemat(path, {"M": 0.1 * np.eye(3), "K": sp.csc_matrix(triangle(K))})
    with pytest.raises(ValueError, match="holds only its (upper|lower) triangle"):
        hf.LinearStructure.from_file(path)
    # expanded as the message says: the symmetric matrix
    half = hf.read_matrix(path, "K")
    full = half + half.T - np.diag(np.diag(half))
    np.testing.assert_array_equal(full, K)
