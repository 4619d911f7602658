"""Reading structural matrices from the files finite-element codes export.

Formats, chosen by the file suffix:

``.mtx`` (Matrix Market)
    One matrix per file (ANSYS ``*EXPORT`` with ``MMF``, Nastran via DMAP,
    FreeFEM, MATLAB's ``mmwrite`` and most sparse tools write it), read by
    :func:`scipy.io.mmread`. Abaqus's ``*MATRIX OUTPUT`` files, also
    named ``.mtx``, are another format (no ``%%MatrixMarket`` banner; rows
    of node and DOF labels): they are refused with a message saying so. A
    "symmetric" file stores one triangle; it is expanded (a symmetric file
    that stores an entry in both triangles is refused, as is a "pattern"
    file, which has no values).
``.mat`` (MATLAB, version 5 to 7.2)
    Several named variables per file, read by :func:`scipy.io.loadmat`.
``.npz`` / ``.npy`` (NumPy)
    Several named arrays per file, or one; or one sparse matrix written by
    :func:`scipy.sparse.save_npz`.

Sparse matrices are returned dense: the harmonic balance works on dense
(reduced) matrices of up to a few thousand DOFs; reduce larger models first
(:func:`hbmfric.craig_bampton` on a model of that size, or in the FE code).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

#: names tried, in order, for each matrix in ``.mat`` and ``.npz`` files
#: (case-insensitive)
DEFAULT_NAMES = {
    "mass": ("M", "mass", "Mass", "MGG", "Mff"),
    "stiffness": ("K", "stiffness", "Stiffness", "KGG", "Kff"),
    "damping": ("C", "D", "damping", "Damping", "BGG", "Cff"),
}


_V73 = (
    "{path}: MATLAB v7.3 (HDF5) files are not read; save with "
    "save(..., '-v7') or export the matrices as Matrix Market"
)


def _dense(value, label: str) -> np.ndarray:
    if hasattr(value, "toarray"):
        value = value.toarray()
    a = np.asarray(value)
    if a.dtype.kind not in "iuf":
        raise ValueError(f"{label} must hold real numbers, got dtype {a.dtype}")
    return np.array(a, dtype=np.float64)


def _read_matrix_market(path: Path) -> np.ndarray:
    """A Matrix Market file as a dense float64 matrix. A "pattern" file
    (positions without values) and a file with a symmetric header that
    stores an entry twice (both triangles, which :func:`scipy.io.mmread`
    would add up) are refused."""
    from scipy.io import mminfo, mmread

    with path.open("rb") as fh:
        first = fh.readline(200).decode("latin-1").strip()
    if not first.lower().startswith("%%matrixmarket"):
        raise ValueError(
            f"{path} is not a Matrix Market file: its first line {first[:60]!r} "
            "is not the '%%MatrixMarket matrix ...' banner. Abaqus's *MATRIX "
            "OUTPUT files, also named .mtx, are another format (node and DOF "
            "labels per entry) and are not read: convert them to a matrix "
            "(Matrix Market, .mat or .npz) with your own DOF numbering"
        )
    _, n_cols, _, layout, field, symmetry = mminfo(str(path))
    if field == "pattern":
        raise ValueError(
            f"{path} is a 'pattern' Matrix Market file: it stores the positions "
            "of the entries but no values"
        )
    try:
        value = mmread(str(path))
    except ValueError as exc:
        # scipy's parser names neither the file nor the convention
        # ("Line 3: Row index out of bounds" for a 0-based export)
        raise ValueError(
            f"{path}: not a valid Matrix Market file ({exc}); indices count "
            "from 1 and the size line gives rows, columns and the number of "
            "entries that follow"
        ) from None
    if layout == "coordinate" and symmetry != "general":
        # mmread mirrors every off-diagonal entry of a symmetric file; a
        # file that already stores both triangles would be summed twice
        coo = value.tocoo()
        keys = np.asarray(coo.row, dtype=np.int64) * n_cols + coo.col
        unique, counts = np.unique(keys, return_counts=True)
        if np.any(counts > 1):
            first = int(unique[np.argmax(counts > 1)])
            i, j = divmod(first, n_cols)
            raise ValueError(
                f"{path} has the {symmetry!r} header, which stores one triangle, "
                f"but entry ({i + 1}, {j + 1}) appears twice (both triangles "
                "stored, or a repeated entry); reading it would double the "
                "off-diagonal terms. Write the file with the 'general' header, "
                "or with one triangle only"
            )
    return _dense(value, str(path))


#: the arrays of a file written by :func:`scipy.sparse.save_npz`
_SPARSE_NPZ = {"format", "shape", "data"}


def _sparse_npz(path: Path) -> bool:
    """True for a file written by :func:`scipy.sparse.save_npz` (one sparse
    matrix, stored as its ``data``, ``indices``, ``indptr`` or ``row`` /
    ``col``, ``shape`` and ``format`` arrays)."""
    with np.load(path, allow_pickle=False) as data:
        return _SPARSE_NPZ <= set(data.files)


def _read_sparse_npz(path: Path, name: str | None) -> np.ndarray:
    """The one matrix of a :func:`scipy.sparse.save_npz` file, dense (it was
    refused as "holds 5 arrays (data, format, indices, indptr, shape)",
    and ``name="data"`` gave its nonzeros as a vector)."""
    from scipy.sparse import load_npz

    if name is not None:
        raise ValueError(
            f"{path} holds one sparse matrix (written by scipy.sparse.save_npz), "
            f"not named arrays: read it without a name (got {name!r}); save "
            "several matrices in one file with numpy.savez(path, M=..., K=...) "
            "of dense arrays, or one save_npz file per matrix"
        )
    try:
        value = load_npz(path)
    except (ValueError, KeyError, OSError) as exc:
        raise ValueError(f"{path}: not a readable scipy.sparse file ({exc})") from None
    return _dense(value, str(path))


def read_matrix(path: str | Path, name: str | None = None) -> np.ndarray:
    """Read one matrix from a ``.mtx``, ``.mat``, ``.npz`` or ``.npy`` file.

    Parameters
    ----------
    path : str or Path
        The file; its suffix selects the format.
    name : str, optional
        Variable name inside a ``.mat`` or ``.npz`` file. Required when
        the file holds several arrays; ignored for ``.mtx`` and ``.npy``.

    Returns
    -------
    ndarray, shape (n, m), float64
        Dense.

    Raises
    ------
    FileNotFoundError
        If the file does not exist.
    ValueError
        Unknown suffix, unknown or ambiguous variable name (the message
        lists the names in the file), or non-real entries.
    """
    path = Path(path)
    if not path.is_file():
        raise FileNotFoundError(f"no such matrix file: {path}")
    suffix = path.suffix.lower()
    if suffix == ".mtx":
        return _read_matrix_market(path)
    if suffix == ".npy":
        return _dense(np.load(path, allow_pickle=False), str(path))
    if suffix == ".mat":
        from scipy.io import loadmat

        try:
            data = loadmat(str(path))
        except NotImplementedError:
            raise ValueError(_V73.format(path=path)) from None
        arrays = {k: v for k, v in data.items() if not k.startswith("__")}
    elif suffix == ".npz":
        if _sparse_npz(path):
            return _read_sparse_npz(path, name)
        with np.load(path, allow_pickle=False) as data:
            arrays = {k: data[k] for k in data.files}
    else:
        raise ValueError(
            f"{path}: unknown matrix file type {suffix!r} (use .mtx, .mat, .npz "
            "or .npy)"
        )
    if name is None:
        if len(arrays) != 1:
            raise ValueError(
                f"{path} holds {len(arrays)} arrays ({', '.join(sorted(arrays))}); "
                "say which with name="
            )
        name = next(iter(arrays))
    if name not in arrays:
        raise ValueError(
            f"{path} has no array {name!r} (it has {', '.join(sorted(arrays))})"
        )
    return _dense(arrays[name], f"{path}[{name}]")


def read_matrices(
    path: str | Path, names: dict[str, str] | None = None
) -> dict[str, np.ndarray]:
    """Read the mass, stiffness and (if present) damping matrices from one
    ``.mat`` or ``.npz`` file.

    Parameters
    ----------
    path : str or Path
    names : dict, optional
        ``{"mass": ..., "stiffness": ..., "damping": ...}``: the variable
        names in the file. Default: the one array whose name is among
        :data:`DEFAULT_NAMES` of the role, ignoring case (several such
        arrays are refused: say which).

    Returns
    -------
    dict
        ``"mass"`` and ``"stiffness"`` (and ``"damping"`` if found), dense
        float64 arrays.

    Raises
    ------
    ValueError
        If the mass or stiffness matrix is not found (the message lists the
        names in the file), or several arrays may be one of the three.
    """
    path = Path(path)
    if path.suffix.lower() not in (".mat", ".npz"):
        raise ValueError(
            f"{path}: read_matrices reads .mat or .npz files; for Matrix Market "
            "files (one matrix each) use read_matrix on each"
        )
    if path.suffix.lower() == ".mat":
        from scipy.io import whosmat

        if not path.is_file():
            raise FileNotFoundError(f"no such matrix file: {path}")
        try:
            present = [entry[0] for entry in whosmat(str(path))]
        except NotImplementedError:
            raise ValueError(_V73.format(path=path)) from None
    else:
        if not path.is_file():
            raise FileNotFoundError(f"no such matrix file: {path}")
        if _sparse_npz(path):
            raise ValueError(
                f"{path} holds one sparse matrix (written by "
                "scipy.sparse.save_npz), not named mass and stiffness arrays: "
                "read each matrix from its own file (LinearStructure.from_files, "
                "or read_matrix)"
            )
        with np.load(path, allow_pickle=False) as data:
            present = list(data.files)
    out = {}
    for role in ("mass", "stiffness", "damping"):
        given = (names or {}).get(role)
        if given is not None:
            out[role] = read_matrix(path, given)
            continue
        # every array whose name is one of the role's, ignoring case: two of
        # them ("M" and "m", "MGG" and "Mff": the unconstrained and the
        # constrained set of a Nastran export) leave the choice to the user
        wanted = {c.lower() for c in DEFAULT_NAMES[role]}
        found = [p for p in present if p.lower() in wanted]
        if len(found) > 1:
            raise ValueError(
                f"{path} holds several arrays that may be the {role} matrix "
                f"({', '.join(found)}); say which with names={{'{role}': ...}}"
            )
        if found:
            out[role] = read_matrix(path, found[0])
        elif role != "damping":
            raise ValueError(
                f"{path}: no {role} matrix found (looked for "
                f"{', '.join(DEFAULT_NAMES[role])}; the file has "
                f"{', '.join(sorted(present)) or 'nothing readable'}); pass "
                f"names={{'{role}': ...}}"
            )
    return out
