"""Quiet failures found on the newer public paths (issue 14, last loose
ends): each used to give a wrong number without a word, or a traceback
where a clear error belongs."""

import numpy as np
import pytest
import scipy.io

import hbmfric as hf

M = 0.05 * np.eye(3)
K = np.array([[2.0, -1.0, 0.0], [-1.0, 2.0, -1.0], [0.0, -1.0, 1.0]]) * 1e4


@pytest.mark.parametrize("suffix", [".npz", ".mat"])
def test_two_arrays_that_may_be_one_matrix_are_refused(tmp_path, suffix):
    """A file holding "M" and "m" read the last of them (names were looked
    up ignoring case, the later one won): twice the mass, no word. A
    Nastran export with the unconstrained and the constrained set (MGG and
    Mff) took the first found."""
    path = tmp_path / f"model{suffix}"
    arrays = {"M": M, "K": K, "m": 2 * M}
    if suffix == ".npz":
        np.savez(path, **arrays)
    else:
        # MATLAB names are case-sensitive too
        scipy.io.savemat(path, arrays)
    with pytest.raises(ValueError, match=r"several arrays .* mass .*\bM\b.*\bm\b"):
        hf.read_matrices(path)
    with pytest.raises(ValueError, match="names="):
        hf.LinearStructure.from_file(path, modal_damping=0.01, load={0: 1.0})
    out = hf.read_matrices(path, {"mass": "M"})
    np.testing.assert_array_equal(out["mass"], M)
    np.testing.assert_array_equal(out["stiffness"], K)
    nastran = tmp_path / "nastran.mat"
    scipy.io.savemat(nastran, {"MGG": np.eye(4), "KGG": np.eye(4), "Mff": M, "Kff": K})
    with pytest.raises(ValueError, match=r"MGG, Mff"):
        hf.read_matrices(nastran)
