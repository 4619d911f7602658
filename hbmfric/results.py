"""Results: a periodic solution and an FRF branch, with their work counters,
amplitude measures, plots (matplotlib imported lazily) and ``.npz``
persistence without pickle."""

from __future__ import annotations

import json
import zipfile
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ._validate import dof_index
from .signals import half_peak_to_peak, harmonic_amplitude, synthesis_matrix


def _resolve_dof(dof, names: dict, n_dof: int) -> int:
    """Index of ``dof``: an index, a name of ``names`` (such as ``"tip"``,
    ``"force"``) or None for the contact DOF (0 when unnamed)."""
    if dof is None:
        dof = names.get("contact", 0)
    elif isinstance(dof, str):
        if dof not in names:
            raise ValueError(
                f"dof name must be one of {sorted(names)} for this system, got {dof!r}"
            )
        dof = names[dof]
    return dof_index(dof, n_dof)


@dataclass
class PeriodicSolution:
    """One periodic HBM solution.

    Attributes
    ----------
    omega : float
        Forcing pulsation Ω, rad/s.
    force : float
        Forcing amplitude, N.
    harmonic_numbers : ndarray of int, shape (n_harmonics,)
    coefficients : ndarray, shape (n_dof, n_coef)
        Fourier coefficients per DOF, m.
    converged : bool
    newton_iterations : int
    residual_norm : float
        ``max |R|`` at the solution, N.
    elapsed : float
        Wall time, s.
    contact_state : str
    dof_names : dict
        Named DOFs of the system (e.g. ``"tip"``, ``"force"``) → index.
    method : str
        How :func:`~hbmfric.periodic_solution` obtained it: ``"newton"``,
        ``"load ramp"``, ``"continuation from below"``, ``"continuation
        from above"``, ``"zero force"`` or ``"failed"`` (not converged);
        ``"branch point"`` for :meth:`Branch.point`.
    """

    omega: float
    force: float
    harmonic_numbers: np.ndarray
    coefficients: np.ndarray
    converged: bool
    newton_iterations: int
    residual_norm: float
    elapsed: float = 0.0
    contact_state: str = ""
    dof_names: dict = field(default_factory=dict)
    method: str = ""

    def amplitude(self, harmonic: int | None = None, dof=None) -> float:
        """Amplitude of ``x_dof``: of one harmonic (``sqrt(Xc² + Xs²)``), or
        with ``harmonic=None`` half the peak-to-peak of ``x(t)``, m.

        ``dof``: index, name from ``dof_names`` or None (the contact DOF)."""
        X = self.coefficients[
            _resolve_dof(dof, self.dof_names, self.coefficients.shape[0])
        ]
        if harmonic is None:
            return float(half_peak_to_peak(self.harmonic_numbers, X))
        return float(harmonic_amplitude(self.harmonic_numbers, X, harmonic))

    def time_response(self, n: int = 256, dof=None) -> tuple[np.ndarray, np.ndarray]:
        """``(t, x)`` over one period at ``n`` equidistant instants (s, m)."""
        if isinstance(n, bool) or not isinstance(n, int | np.integer) or n < 2:
            raise ValueError(f"n must be an integer >= 2, got {n!r}")
        X = self.coefficients[
            _resolve_dof(dof, self.dof_names, self.coefficients.shape[0])
        ]
        theta = 2.0 * np.pi * np.arange(n) / n
        return theta / self.omega, synthesis_matrix(self.harmonic_numbers, theta) @ X


@dataclass
class Branch:
    """A branch of periodic solutions traced by continuation (an FRF).

    Attributes
    ----------
    omega : ndarray, shape (n_points,)
        Ω in path order, rad/s (non-monotone across folds).
    coefficients : ndarray, shape (n_points, n_dof, n_coef)
        Fourier coefficients of every DOF at every point, m.
    harmonic_numbers : ndarray of int, shape (n_harmonics,)
    force : float
        Forcing amplitude, N.
    folds : ndarray of int
        Index ``i`` of each fold: the turning point lies between points
        ``i - 1`` and ``i``.
    stop_reason : str
    n_steps, n_rejected, newton_iterations : int
        Work counters.
    elapsed : float
        Wall time of the continuation, s.
    info : dict
        Description of the run (system, law, options), JSON-serialisable.
    point_harmonics : ndarray of int, shape (n_points,), optional
        Highest harmonic used at each point (``harmonics="auto"``); None
        when the whole branch used ``harmonic_numbers``.
    dof_names : dict
        Named DOFs of the system (e.g. ``"tip"``, ``"force"``) → index.
    truncation_error : ndarray, shape (n_points,), optional
        Estimated relative truncation error of each point: of the
        first-harmonic amplitude and of half the peak-to-peak value at the
        contact DOF (:mod:`hbmfric.continuation.accuracy`); 0 at a linear
        (stuck) point. None for branches saved before it existed.
    """

    omega: np.ndarray
    coefficients: np.ndarray
    harmonic_numbers: np.ndarray
    force: float
    folds: np.ndarray
    stop_reason: str
    n_steps: int
    n_rejected: int
    newton_iterations: int
    elapsed: float
    info: dict = field(default_factory=dict)
    point_harmonics: np.ndarray | None = None
    dof_names: dict = field(default_factory=dict)
    truncation_error: np.ndarray | None = None

    def __len__(self) -> int:
        return self.omega.size

    @property
    def n_points(self) -> int:
        return self.omega.size

    def amplitude(self, harmonic: int | None = None, dof=None) -> np.ndarray:
        """Amplitude at every point, shape (n_points,), m.

        ``harmonic=k``: ``sqrt(Xc_k² + Xs_k²)`` (``|X0|`` for k = 0);
        ``harmonic=None``: half the peak-to-peak of ``x(t)`` over the period.
        ``dof``: index, name from ``dof_names`` (``"tip"``, ``"force"`` for
        the beam) or None (the contact DOF).
        """
        X = self.coefficients[
            :, _resolve_dof(dof, self.dof_names, self.coefficients.shape[1])
        ]
        if harmonic is None:
            return half_peak_to_peak(self.harmonic_numbers, X)
        return harmonic_amplitude(self.harmonic_numbers, X, harmonic)

    def harmonics_at(self, index: int) -> int:
        """Highest harmonic used at point ``index``."""
        if self.point_harmonics is not None:
            return int(self.point_harmonics[index])
        return int(self.harmonic_numbers[-1])

    def point(self, index: int) -> PeriodicSolution:
        """The periodic solution at one point of the branch."""
        return PeriodicSolution(
            omega=float(self.omega[index]),
            force=self.force,
            harmonic_numbers=self.harmonic_numbers,
            coefficients=self.coefficients[index].copy(),
            converged=True,
            newton_iterations=0,
            residual_norm=float("nan"),
            dof_names=dict(self.dof_names),
            method="branch point",
        )

    def plot(self, ax=None, harmonic: int | None = None, dof=None, **kwargs):
        """Draw amplitude against Ω (folds marked); returns the axes."""
        import matplotlib.pyplot as plt

        if ax is None:
            _, ax = plt.subplots()
        amp = self.amplitude(harmonic=harmonic, dof=dof)
        (line,) = ax.plot(self.omega, amp, **kwargs)
        if self.folds.size:
            ax.plot(
                self.omega[self.folds], amp[self.folds], "x", color=line.get_color()
            )
        ax.set_xlabel("Ω (rad/s)")
        label = "amplitude" if harmonic is None else f"harmonic {harmonic} amplitude"
        ax.set_ylabel(f"{label} (m)")
        return ax

    # ------------------------------------------------------------------
    def save(self, path: str | Path) -> Path:
        """Write the branch to ``path`` (``.npz``, no pickle)."""
        path = Path(path)
        meta = {
            "force": self.force,
            "stop_reason": self.stop_reason,
            "n_steps": self.n_steps,
            "n_rejected": self.n_rejected,
            "newton_iterations": self.newton_iterations,
            "elapsed": self.elapsed,
            "info": self.info,
            "dof_names": self.dof_names,
            "format": "hbmfric.Branch/1",
        }
        arrays = {
            "omega": self.omega,
            "coefficients": self.coefficients,
            "harmonic_numbers": self.harmonic_numbers,
            "folds": self.folds,
            "meta": np.array(json.dumps(meta)),
        }
        if self.point_harmonics is not None:
            arrays["point_harmonics"] = self.point_harmonics
        if self.truncation_error is not None:
            arrays["truncation_error"] = self.truncation_error
        np.savez(path, **arrays)
        return path if path.suffix == ".npz" else path.with_suffix(path.suffix + ".npz")

    @classmethod
    def load(cls, path: str | Path) -> Branch:
        """Read a branch written by :meth:`save` (no pickle).

        Raises
        ------
        ValueError
            If ``path`` is not a readable hbmfric branch file.
        """
        _check_npz_sizes(path)
        try:
            with np.load(Path(path), allow_pickle=False) as data:
                meta = json.loads(str(data["meta"]))
                if (
                    not isinstance(meta, dict)
                    or meta.get("format") != "hbmfric.Branch/1"
                ):
                    raise ValueError("wrong format tag")
                branch = cls(
                    omega=np.asarray(data["omega"], dtype=np.float64).copy(),
                    coefficients=np.asarray(
                        data["coefficients"], dtype=np.float64
                    ).copy(),
                    harmonic_numbers=np.asarray(
                        data["harmonic_numbers"], dtype=np.int64
                    ).copy(),
                    force=float(meta["force"]),
                    folds=np.asarray(data["folds"], dtype=np.int64).copy(),
                    stop_reason=str(meta["stop_reason"]),
                    n_steps=int(meta["n_steps"]),
                    n_rejected=int(meta["n_rejected"]),
                    newton_iterations=int(meta["newton_iterations"]),
                    elapsed=float(meta["elapsed"]),
                    info=dict(meta["info"]),
                    dof_names={
                        str(k): int(v) for k, v in meta.get("dof_names", {}).items()
                    },
                    point_harmonics=(
                        np.asarray(data["point_harmonics"], dtype=np.int64).copy()
                        if "point_harmonics" in data.files
                        else None
                    ),
                    truncation_error=(
                        np.asarray(data["truncation_error"], dtype=np.float64).copy()
                        if "truncation_error" in data.files
                        else None
                    ),
                )
        except (
            AttributeError,
            OSError,
            EOFError,
            KeyError,
            TypeError,
            ValueError,
            zipfile.BadZipFile,
        ) as exc:
            raise ValueError(
                f"path {str(path)!r} is not an hbmfric branch file, or is damaged "
                f"({exc})"
            ) from None
        _check_branch_arrays(path, branch)
        return branch


def _check_npz_sizes(path) -> None:
    """Check, from the array headers alone, that every array of the ``.npz``
    file ``path`` fits in the bytes stored for it (a damaged or forged
    header must not make :meth:`Branch.load` allocate terabytes)."""
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
                        "objects; a branch file holds numbers only"
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
            f"path {str(path)!r} is not an hbmfric branch file, or is damaged ({exc})"
        ) from None


def _check_branch_arrays(path, branch: Branch) -> None:
    """Check that the arrays of a loaded branch agree with each other;
    ``ValueError`` naming the file and the field otherwise."""

    def bad(field_name: str, what: str) -> ValueError:
        return ValueError(f"path {str(path)!r}: field {field_name!r} {what}")

    n = branch.omega.size
    if branch.omega.ndim != 1:
        raise bad("omega", f"must be 1-d, has shape {branch.omega.shape}")
    if not np.all(np.isfinite(branch.omega)):
        raise bad("omega", "has non-finite values")
    k = branch.harmonic_numbers
    if k.ndim != 1 or k.size == 0 or np.any(k < 0) or np.any(np.diff(k) <= 0):
        raise bad("harmonic_numbers", f"must be increasing integers >= 0, got {k}")
    n_coef = int(np.sum(np.where(k == 0, 1, 2)))
    c = branch.coefficients
    if c.ndim != 3 or c.shape[0] != n or c.shape[2] != n_coef:
        raise bad(
            "coefficients",
            f"has shape {c.shape}; omega ({n} points) and harmonic_numbers "
            f"({n_coef} coefficients) ask for ({n}, n_dof, {n_coef})",
        )
    if not np.all(np.isfinite(c)):
        raise bad("coefficients", "has non-finite values")
    folds = branch.folds
    if folds.ndim != 1 or np.any(folds < 0) or np.any(folds > n):
        raise bad("folds", f"must be point indices in [0, {n}], got {folds}")
    ph = branch.point_harmonics
    if ph is not None and ph.shape != (n,):
        raise bad("point_harmonics", f"must have shape ({n},), got {ph.shape}")
    te = branch.truncation_error
    if te is not None and te.shape != (n,):
        raise bad("truncation_error", f"must have shape ({n},), got {te.shape}")
    n_dof = c.shape[1]
    for name, index in branch.dof_names.items():
        if not 0 <= index < n_dof:
            raise bad("dof_names", f"maps {name!r} to {index}, not in [0, {n_dof - 1}]")
