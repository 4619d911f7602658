"""Reading ``.npz`` result files safely: sizes checked from the array
headers before anything is allocated, errors that name the file and the
field."""

from __future__ import annotations

import zipfile
from collections.abc import Callable
from pathlib import Path

import numpy as np


def check_npz_sizes(path, kind: str) -> None:
    """Check, from the array headers alone, that every array of the ``.npz``
    file ``path`` fits in the bytes stored for it (a damaged or forged
    header must not make a loader allocate terabytes) and holds no Python
    objects; ``kind`` names the file type in the messages (``"branch"``).

    Raises
    ------
    ValueError
        Naming the file and the field.
    """
    try:
        with zipfile.ZipFile(Path(path)) as zf:
            for info in zf.infolist():
                if not info.filename.endswith(".npy"):
                    continue
                field_name = info.filename[:-4]
                with zf.open(info) as fh:
                    version = np.lib.format.read_magic(fh)
                    if version == (1, 0):
                        header = np.lib.format.read_array_header_1_0(fh)
                    else:
                        header = np.lib.format.read_array_header_2_0(fh)
                    offset = fh.tell()
                shape, _, dtype = header
                if dtype.hasobject:
                    raise ValueError(
                        f"path {str(path)!r}: field {field_name!r} holds Python "
                        f"objects; a {kind} file holds numbers only"
                    )
                size = dtype.itemsize
                for dim in shape:
                    size *= int(dim)
                stored = info.file_size - offset
                if size > stored:
                    raise ValueError(
                        f"path {str(path)!r}: field {field_name!r} claims shape "
                        f"{tuple(shape)} ({size} bytes) but the file stores "
                        f"{stored} bytes for it; the file is damaged"
                    )
    except (OSError, EOFError, zipfile.BadZipFile) as exc:
        raise ValueError(
            f"path {str(path)!r} is not an hbmfric {kind} file, or is damaged ({exc})"
        ) from None


#: what reading a damaged or foreign ``.npz`` file may raise (a missing
#: field, a wrong dtype or shape, a broken archive); loaders turn each into
#: one ``ValueError`` naming the file
READ_ERRORS = (
    AttributeError,
    OSError,
    EOFError,
    KeyError,
    TypeError,
    ValueError,
    zipfile.BadZipFile,
)


def stored_array(data, name: str, dtype) -> np.ndarray:
    """A copy of the array ``name`` of the open ``.npz`` file ``data`` as
    ``dtype`` (``KeyError`` if it is missing)."""
    return np.asarray(data[name], dtype=dtype).copy()


def optional_array(data, name: str, dtype, default=None):
    """:func:`stored_array`, or ``default`` when the file has no array ``name``
    (a field added by a later version)."""
    return stored_array(data, name, dtype) if name in data.files else default


def field_error(path) -> Callable[[str, str], ValueError]:
    """``bad(field, what)``: the ``ValueError`` for one field of ``path``."""

    def bad(field_name: str, what: str) -> ValueError:
        return ValueError(f"path {str(path)!r}: field {field_name!r} {what}")

    return bad


def check_harmonics(bad, harmonic_numbers: np.ndarray) -> int:
    """Check increasing non-negative harmonic numbers; returns the number of
    real coefficients per DOF they take."""
    k = harmonic_numbers
    if k.ndim != 1 or k.size == 0 or np.any(k < 0) or np.any(np.diff(k) <= 0):
        raise bad("harmonic_numbers", f"must be increasing integers >= 0, got {k}")
    return int(np.sum(np.where(k == 0, 1, 2)))
