"""Structural matrices that used to enter quietly wrong (issue 14): a
complex matrix lost its imaginary part, a Matrix Market file with a
symmetric header and both triangles stored had its off-diagonal terms
doubled, a "pattern" file became a matrix of ones."""

import numpy as np
import pytest

import hbmfric as hf

K = np.array([[2.0, -1.0, 0.0], [-1.0, 2.0, -1.0], [0.0, -1.0, 1.0]])


def _write(path, text):
    path.write_text(text)
    return path


def test_one_triangle_of_a_symmetric_file_is_expanded(tmp_path):
    lower = _write(
        tmp_path / "lower.mtx",
        "%%MatrixMarket matrix coordinate real symmetric\n% comment\n%\n"
        "3 3 5\n1 1 2\n2 1 -1\n2 2 2\n3 2 -1\n3 3 1\n",
    )
    upper = _write(
        tmp_path / "upper.mtx",
        "%%MatrixMarket matrix coordinate real symmetric\n"
        "3 3 5\n1 1 2\n1 2 -1\n2 2 2\n2 3 -1\n3 3 1\n",
    )
    np.testing.assert_array_equal(hf.read_matrix(lower), K)
    np.testing.assert_array_equal(hf.read_matrix(upper), K)


def test_a_symmetric_file_with_both_triangles_is_refused(tmp_path):
    both = _write(
        tmp_path / "both.mtx",
        "%%MatrixMarket matrix coordinate real symmetric\n"
        "3 3 7\n1 1 2\n2 1 -1\n1 2 -1\n2 2 2\n3 2 -1\n2 3 -1\n3 3 1\n",
    )
    with pytest.raises(
        ValueError, match=r"entry \(1, 2\) appears twice \(both triangles"
    ):
        hf.read_matrix(both)
    with pytest.raises(ValueError, match="appears twice"):
        hf.LinearStructure.from_files(both, both)


def test_a_general_file_with_both_triangles_is_read_as_written(tmp_path):
    general = _write(
        tmp_path / "general.mtx",
        "%%MatrixMarket matrix coordinate real general\n"
        "3 3 7\n1 1 2\n2 1 -1\n1 2 -1\n2 2 2\n3 2 -1\n2 3 -1\n3 3 1\n",
    )
    np.testing.assert_array_equal(hf.read_matrix(general), K)


def test_a_pattern_file_is_refused(tmp_path):
    pattern = _write(
        tmp_path / "pattern.mtx",
        "%%MatrixMarket matrix coordinate pattern general\n2 2 2\n1 1\n2 2\n",
    )
    with pytest.raises(ValueError, match="pattern"):
        hf.read_matrix(pattern)


@pytest.mark.parametrize("role", ["mass", "stiffness", "damping"])
def test_a_complex_matrix_is_refused_not_truncated(role):
    matrices = {"mass": np.eye(3), "stiffness": K, "damping": 0.01 * K}
    matrices[role] = matrices[role] * (1.0 + 0.02j)  # structural damping K(1 + iη)
    with pytest.raises(ValueError, match=f"{role} must be a real.*complex"):
        hf.LinearStructure(matrices["mass"], matrices["stiffness"], matrices["damping"])


def test_strings_are_no_matrix():
    with pytest.raises(ValueError, match="mass must be a real"):
        hf.LinearStructure([["1", "0"], ["0", "1"]], np.eye(2))


def test_a_matlab_v73_file_is_named_as_such(tmp_path):
    """read_matrices said "no mass matrix found ... the file has nothing
    readable" for a v7.3 (HDF5) file."""
    import scipy.io

    path = tmp_path / "model.mat"
    scipy.io.savemat(path, {"M": np.eye(2), "K": np.eye(2)})
    data = bytearray(path.read_bytes())
    data[124:126] = b"\x00\x02"  # the header's version field: 7.3
    path.write_bytes(bytes(data))
    for call in (
        lambda: hf.read_matrix(path, "K"),
        lambda: hf.read_matrices(path),
        lambda: hf.LinearStructure.from_file(path),
    ):
        with pytest.raises(ValueError, match="v7.3"):
            call()
