"""Parameter studies: one FRF per parameter set, run in parallel.

:func:`study` takes a function that builds a system from a parameter set
and a list of parameter sets (a grid from :func:`grid`, or any sample), and
traces one branch per set with :func:`hbmfric.frf`:

* locally by default, in worker processes (``executor="processes"``, one
  per core), or in this process (``executor="serial"``);
* on a Dask cluster when given its client (``client=``;
  ``pip install "hbmfric[cluster]"``), e.g. a ``dask.distributed.LocalCluster``
  or a cluster on a scheduler;

with a progress line, every result gathered into one
:class:`StudyResult` (branches, a long-format table with the columns
:func:`hbmfric.criterion.read_frfs` reads, so a study feeds
:func:`hbmfric.criterion.choose_contact_model` directly), and every failed
parameter set kept with its reason, never losing the rest. Warnings raised
while tracing (coverage, accuracy, convergence) are recorded per set and
summarised once in the calling process.
"""

from __future__ import annotations

import csv
import itertools
import math
import os
import pickle
import sys
import threading
import time
import traceback
import warnings
from collections.abc import Callable, Iterable, Mapping
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from .errors import AccuracyWarning, StudyWarning

#: executors that need no set-up
LOCAL_EXECUTORS = ("processes", "serial")
#: the error of a set that a dead worker process left untraced
BROKEN_POOL = (
    "BrokenProcessPool: a worker process ended abruptly (a crash in native "
    "code, os._exit, the out-of-memory killer) while this set was traced or "
    "queued; not traced (run it with executor='serial' to see the cause)"
)
#: one parameter set at a time per process: ``warnings.catch_warnings`` is
#: process-wide, so two sets traced at once in threads (a Dask worker with
#: ``threads_per_worker > 1``) recorded each other's warnings, or lost
#: them when the other set's exit restored the filters (stop 29: a set at
#: 0.5 N listed clean, a stuck set at 1e-4 N listed with its warning)
_RUN_LOCK = threading.RLock()


def grid(**axes: Iterable) -> list[dict]:
    """Every combination of the given parameter values (Cartesian product).

    Parameters
    ----------
    **axes : iterable
        Parameter name → values, e.g. ``force=[0.1, 0.5], normal_load=[1, 2]``.

    Returns
    -------
    list of dict
        One parameter set per combination, the last axis varying fastest.

    Raises
    ------
    ValueError
        If no axis is given or an axis is empty.
    """
    if not axes:
        raise ValueError("grid needs at least one parameter axis")
    names = list(axes)
    values = []
    for name in names:
        v = list(axes[name]) if not isinstance(axes[name], str) else [axes[name]]
        if not v:
            raise ValueError(f"grid axis {name!r} is empty")
        values.append(v)
    return [
        dict(zip(names, combo, strict=True)) for combo in itertools.product(*values)
    ]


@dataclass
class StudyRun:
    """The outcome of one parameter set.

    Attributes
    ----------
    index : int
        Position in the parameter list.
    parameters : dict
    branch : Branch or None
        None if the run failed.
    error : str or None
        ``"<ExceptionType>: <message>"`` of a failed run.
    warnings : list of str
        Warnings raised while tracing (``"<Category>: <message>"``).
    elapsed : float
        Wall time of the run in its worker, s.
    unread : tuple of str
        Parameters ``build`` never looked at (the force aside, which the
        study reads); :func:`study` warns when one (other than the normal
        load, a tag for the criterion) is unread in every set.
    """

    index: int
    parameters: dict
    branch: object | None = None
    error: str | None = None
    warnings: list = field(default_factory=list)
    elapsed: float = 0.0
    unread: tuple = ()

    @property
    def ok(self) -> bool:
        return self.error is None


def _run_one(build: Callable, force_key: str, frf_options: dict, task) -> StudyRun:
    """Build the system of one parameter set and trace its branch (in a
    worker). Every exception is caught and returned as the run's error.
    One set at a time per process (``_RUN_LOCK``)."""
    index, parameters = task
    with _RUN_LOCK:
        return _run_locked(build, force_key, frf_options, index, parameters)


def _run_locked(build, force_key, frf_options, index, parameters) -> StudyRun:
    """:func:`_run_one` of one set, holding ``_RUN_LOCK``."""
    from .api import frf

    start = time.perf_counter()
    run = StudyRun(index, dict(parameters))
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        try:
            seen = _ReadTracker(parameters)
            system = build(seen)
            run.unread = tuple(
                k for k in parameters if k not in seen.read and k != force_key
            )
            force = parameters[force_key]
            run.branch = frf(system, force, **frf_options)
        except Exception as exc:  # noqa: BLE001 - reported, never lost
            last = traceback.extract_tb(exc.__traceback__)[-1:]
            where = f" ({last[0].filename}:{last[0].lineno})" if last else ""
            run.error = f"{type(exc).__name__}: {exc}{where}"
    run.warnings = [f"{w.category.__name__}: {w.message}" for w in caught]
    run.elapsed = time.perf_counter() - start
    return run


class _ReadTracker(dict):
    """The parameter set handed to ``build``, noting which keys it reads:
    a key read one by one (``p["x"]``, ``p.get``, ``in``) or all at once
    (iteration, ``keys``/``items``/``values``, ``dict(p)``, ``{**p}``,
    ``copy``). A grid axis with a misspelt name is otherwise never read and
    every set differing only in it traces the same system, quietly."""

    def __init__(self, parameters) -> None:
        super().__init__(parameters)
        self.read: set = set()

    def _all(self) -> None:
        self.read.update(dict.keys(self))

    def __getitem__(self, key):
        self.read.add(key)
        return super().__getitem__(key)

    def get(self, key, default=None):
        self.read.add(key)
        return super().get(key, default)

    def __contains__(self, key) -> bool:
        self.read.add(key)
        return super().__contains__(key)

    def pop(self, key, *default):
        self.read.add(key)
        return super().pop(key, *default)

    def setdefault(self, key, default=None):
        self.read.add(key)
        return super().setdefault(key, default)

    def __iter__(self):
        self._all()
        return super().__iter__()

    def keys(self):
        self._all()
        return super().keys()

    def items(self):
        self._all()
        return super().items()

    def values(self):
        self._all()
        return super().values()

    def copy(self) -> dict:
        self._all()
        return dict(dict.items(self))

    def __or__(self, other):
        self._all()
        return dict(dict.items(self)) | other

    def __reduce__(self):  # pickled as a plain dict (a build that sends it on)
        self._all()
        return (dict, (dict(dict.items(self)),))


class _Progress:
    """One status line on standard error, rewritten in place on a terminal,
    every 10 % otherwise."""

    def __init__(self, total: int, enabled: bool | None, label: str) -> None:
        stream = sys.stderr
        self.tty = bool(getattr(stream, "isatty", lambda: False)())
        self.enabled = self.tty if enabled is None else bool(enabled)
        self.total, self.label = total, label
        self.done = self.failed = 0
        self.start = time.perf_counter()
        self._next = 0.1

    def update(self, run: StudyRun) -> None:
        self.done += 1
        self.failed += not run.ok
        if not self.enabled:
            return
        frac = self.done / max(self.total, 1)
        if not self.tty and frac < self._next and self.done < self.total:
            return
        self._next = math.floor(frac * 10 + 1) / 10
        line = (
            f"study ({self.label}): {self.done}/{self.total} done, "
            f"{self.failed} failed, {time.perf_counter() - self.start:.1f} s"
        )
        end = "\n" if (not self.tty or self.done == self.total) else ""
        print(("\r" if self.tty else "") + line, end=end, file=sys.stderr, flush=True)


@dataclass
class StudyResult:
    """All runs of a study, in parameter order.

    Attributes
    ----------
    runs : list of StudyRun
    executor : str
        ``"serial"``, ``"processes"`` or ``"dask"``.
    elapsed : float
        Wall time of the whole study, s.
    force_key, normal_load_key : str
        Parameter names of the excitation force and the normal load.
    """

    runs: list
    executor: str
    elapsed: float
    force_key: str = "force"
    normal_load_key: str | None = "normal_load"

    def __len__(self) -> int:
        return len(self.runs)

    @property
    def branches(self) -> list:
        """Branch of every run (None where it failed)."""
        return [r.branch for r in self.runs]

    @property
    def failures(self) -> list[StudyRun]:
        """The runs that failed, with their parameters and error."""
        return [r for r in self.runs if not r.ok]

    @property
    def warned(self) -> list[StudyRun]:
        """The runs that succeeded with warnings."""
        return [r for r in self.runs if r.ok and r.warnings]

    def table(self, harmonic: int | None = 1, dof=None) -> dict[str, np.ndarray]:
        """Long-format table: one row per branch point of every successful
        run.

        Columns: ``curve`` (run index), every parameter, ``omega`` (rad/s,
        path order), ``amplitude`` (:meth:`Branch.amplitude` with
        ``harmonic`` and ``dof``); ``force`` and ``normal_load`` under those
        names so that :func:`hbmfric.criterion.read_frfs` reads the CSV.
        """
        _check_table_dof(self.runs, dof)
        names = []
        for r in self.runs:
            for k in r.parameters:
                if k not in names:
                    names.append(k)
        cols: dict[str, list] = {"curve": [], **{k: [] for k in names}}
        cols.update(omega=[], amplitude=[])
        for r in self.runs:
            if not r.ok:
                continue
            b = r.branch
            n = len(b)
            cols["curve"] += [r.index] * n
            for k in names:
                cols[k] += [r.parameters.get(k, np.nan)] * n
            cols["omega"] += list(b.omega)
            cols["amplitude"] += list(b.amplitude(harmonic=harmonic, dof=dof))
        out = {k: np.asarray(v) for k, v in cols.items()}
        if self.force_key != "force" and self.force_key in out:
            out["force"] = out[self.force_key]
        nk = self.normal_load_key
        if nk is not None and nk != "normal_load" and nk in out:
            out["normal_load"] = out[nk]
        return out

    def to_csv(self, path: str | Path, harmonic: int | None = 1, dof=None) -> Path:
        """Write :meth:`table` as CSV (readable by
        :func:`hbmfric.criterion.read_frfs` when the parameters include the
        normal load). The CSV holds the traced sets only (a plain table
        that NumPy, pandas and spreadsheets read as is); when some sets
        failed, they are written beside it to ``<stem>.failed.csv``
        (columns ``index``, ``parameters``, ``error``), so that the files
        never drop a set unmarked; the traced sets whose branch does not
        cover the band (:attr:`hbmfric.Branch.gaps`, a
        :class:`~hbmfric.CoverageWarning` when traced) to
        ``<stem>.partial.csv`` (columns ``index``, ``parameters``,
        ``gaps``, rad/s): the table's rows of such a set have no points in
        its gaps, and read back (:func:`~hbmfric.criterion.read_frfs`) the
        curve is joined across them. Returns the path of the table."""
        path = Path(path)
        t = self.table(harmonic, dof)
        names = list(t)
        partial = path.with_name(path.stem + ".partial.csv")
        gapped = [r for r in self.runs if r.ok and len(r.branch) and r.branch.gaps]
        if gapped:
            with open(partial, "w", newline="") as fh:
                w = csv.writer(fh)
                w.writerow(["index", "parameters", "gaps"])
                for r in gapped:
                    spans = " ".join(
                        f"[{lo:.12g}, {hi:.12g}]" for lo, hi in r.branch.gaps
                    )
                    w.writerow([r.index, repr(r.parameters), spans])
        elif partial.exists():
            partial.unlink()  # from an earlier study written to the same path
        failed = path.with_name(path.stem + ".failed.csv")
        if self.failures:
            with open(failed, "w", newline="") as fh:
                w = csv.writer(fh)
                w.writerow(["index", "parameters", "error"])
                for r in self.failures:
                    error = " ".join(str(r.error).split())
                    w.writerow([r.index, repr(r.parameters), error])
        elif failed.exists():
            failed.unlink()  # from an earlier study written to the same path
        with open(path, "w", newline="") as fh:
            w = csv.writer(fh)
            w.writerow(names)
            for row in zip(*(t[k] for k in names), strict=True):
                w.writerow([_cell(v) for v in row])
        self._warn_unwatched(dof)
        return path

    def _warn_unwatched(self, dof) -> None:
        """One :class:`~hbmfric.errors.AccuracyWarning` when the straight
        lines between the points of ``dof`` (a DOF the step control did not
        watch) exceed the ``curve_tolerance`` of their run in some runs
        (:meth:`hbmfric.Branch.curve_errors_of`)."""
        if dof is None:
            return
        over = []
        for r in self.runs:
            excess = r.branch._unwatched_excess(dof) if r.ok else None
            if excess is not None:
                worst, _, _, tol = excess
                over.append((worst, r.index, tol))
        if over:
            worst, index, tol = max(over)
            warnings.warn(
                f"the straight lines between the points of DOF {dof!r} exceed "
                f"curve_tolerance in {len(over)} of {len(self.runs)} runs "
                f"(worst: run {index}, estimated {worst:.2g} against "
                f"{tol:g}): the step control bounds the lines of the watched "
                "contact DOF only; per-interval estimates in "
                "Branch.curve_errors_of",
                AccuracyWarning,
                stacklevel=3,
            )

    def to_npz(self, path: str | Path, harmonic: int | None = 1, dof=None) -> Path:
        """Write :meth:`table` (and the failures) to a NumPy ``.npz`` file."""
        path = Path(path)
        t = self.table(harmonic, dof)
        failed = np.array(
            [f"{r.index}: {r.parameters}: {r.error}" for r in self.failures], dtype=str
        )
        np.savez(path, **{k: np.asarray(v) for k, v in t.items()}, failures=failed)
        return path

    def records(self, harmonic: int | None = 1, dof=None) -> list:
        """The successful runs as :class:`hbmfric.criterion.FRFRecord` for
        :func:`hbmfric.criterion.choose_contact_model` (needs the normal
        load among the parameters)."""
        from .criterion import FRFRecord

        nk = self.normal_load_key
        out = []
        for r in self.runs:
            if not r.ok:
                continue
            if nk is None or nk not in r.parameters:
                raise ValueError(
                    f"records need the normal load: parameter {nk!r} is not in "
                    f"run {r.index}'s parameters {sorted(r.parameters)}"
                )
            out.append(
                FRFRecord.from_branch(
                    r.branch, float(r.parameters[nk]), harmonic=harmonic, dof=dof
                )
            )
        return out


def _check_table_dof(runs, dof) -> None:
    """Refuse a DOF *index* for a table of branches whose DOF counts differ
    (a parameter changes the model, e.g. a beam's ``n_elements``): the same
    index is a different point of each model, and one column would mix
    them without a word. A name (resolved per branch) or None (each
    branch's contact DOF) is kept."""
    if dof is None or isinstance(dof, str):
        return
    counts = sorted(
        {int(r.branch.coefficients.shape[1]) for r in runs if r.ok and len(r.branch)}
    )
    if len(counts) > 1:
        raise ValueError(
            f"dof={dof!r} is a DOF index, but the study's models have "
            f"{', '.join(map(str, counts))} DOFs (a parameter changes the "
            "model): the index is a different point in each; name the DOF "
            "(its dof_names, such as 'tip') or leave dof unset for each "
            "model's contact DOF"
        )


def _cell(v) -> str:
    if isinstance(v, float | np.floating):
        return f"{float(v):.12g}"
    return str(v)


def _check_picklable(obj, label: str) -> None:
    try:
        pickle.dumps(obj)
    except Exception as exc:  # noqa: BLE001 - any pickling failure
        raise TypeError(
            f"{label} must be picklable to run in worker processes (define it at "
            f"module level, not as a lambda or a local function; {exc}); or use "
            'executor="serial"'
        ) from None


def study(
    build: Callable[[dict], object],
    parameters: Iterable[Mapping],
    omega: tuple[float, float],
    *,
    executor: str = "processes",
    client=None,
    workers: int | None = None,
    progress: bool | None = None,
    force_key: str = "force",
    normal_load_key: str | None = "normal_load",
    **frf_options,
) -> StudyResult:
    """Trace one FRF branch per parameter set, in parallel.

    Parameters
    ----------
    build : callable
        ``build(parameters) -> system``: the system (any system
        :func:`hbmfric.frf` takes) of one parameter set (a dict). Must be
        picklable (defined at module level) for worker processes.
    parameters : iterable of mapping
        The parameter sets, e.g. :func:`grid` or a random sample (a list of
        dicts). Each must hold ``force_key``: the forcing amplitude, N.
    omega : (float, float)
        Frequency range of every branch, rad/s.
    executor : {"processes", "serial"}
        Local execution: worker processes (default) or this process.
        Ignored when ``client`` is given.
    client : dask.distributed.Client, optional
        Run on this Dask cluster instead (its workers need hbmfric). A
        worker process traces one set at a time (the warnings of a set are
        recorded process-wide): give each worker one thread
        (``threads_per_worker=1``) and start as many workers as sets should
        run at once.
    workers : int, optional
        Worker processes (``"processes"``); default: the CPU count.
    progress : bool, optional
        Progress line on standard error (default: when it is a terminal).
    force_key : str
        Parameter holding the forcing amplitude.
    normal_load_key : str or None
        Parameter holding the normal load (CSV column ``normal_load`` and
        :meth:`StudyResult.records`).
    **frf_options
        Passed to :func:`hbmfric.frf` (``harmonics``, ``sweep``, ...).

    Returns
    -------
    StudyResult

    Warns
    -----
    StudyWarning
        Once, if some parameter sets failed (each with its reason in
        :attr:`StudyResult.failures`) or warned.

    Raises
    ------
    ValueError
        No parameter sets, a set without ``force_key``, an unknown
        executor, or ``workers < 1``.
    TypeError
        ``build`` not callable, or not picklable for worker processes.
    """
    if not callable(build):
        raise TypeError(f"build must be callable, got {type(build).__name__}")
    tasks = []
    for i, p in enumerate(parameters):
        if not isinstance(p, Mapping):
            raise ValueError(
                f"parameter set {i} must be a mapping (dict), got {type(p).__name__}"
            )
        if force_key not in p:
            raise ValueError(
                f"parameter set {i} has no {force_key!r} (the forcing amplitude): "
                f"{dict(p)}"
            )
        tasks.append((i, dict(p)))
    if not tasks:
        raise ValueError("study needs at least one parameter set")
    lo_hi = tuple(omega)
    options = dict(frf_options, omega=lo_hi)
    if client is None and executor not in LOCAL_EXECUTORS:
        raise ValueError(
            f"executor must be one of {LOCAL_EXECUTORS} (or pass a Dask client=), "
            f"got {executor!r}"
        )
    if workers is not None and (
        isinstance(workers, bool) or not isinstance(workers, int) or workers < 1
    ):
        raise ValueError(f"workers must be an integer >= 1, got {workers!r}")
    kind = "dask" if client is not None else executor
    bar = _Progress(len(tasks), progress, kind)
    start = time.perf_counter()
    runs: list[StudyRun] = []
    if kind == "serial":
        for task in tasks:
            run = _run_one(build, force_key, options, task)
            runs.append(run)
            bar.update(run)
    elif kind == "processes":
        _check_picklable(build, "build")
        from concurrent.futures import ProcessPoolExecutor, as_completed
        from concurrent.futures.process import BrokenProcessPool

        n = workers or os.cpu_count() or 1
        pool = ProcessPoolExecutor(max_workers=min(n, len(tasks)))
        try:
            futures = {
                pool.submit(_run_one, build, force_key, options, t): t for t in tasks
            }
            for fut in as_completed(futures):
                try:
                    run = fut.result()
                except BrokenProcessPool:
                    # a worker died (a crash in native code, os._exit, the
                    # out-of-memory killer): the pool fails every set not
                    # finished; the finished ones are kept (stop 29: the
                    # whole study raised and returned nothing)
                    run = StudyRun(futures[fut][0], dict(futures[fut][1]))
                    run.error = BROKEN_POOL
                runs.append(run)
                bar.update(run)
        except BaseException:
            # Ctrl-C (or a broken pool): stop now. Leaving the pool by its
            # context manager would wait for every queued set to be traced.
            _stop_pool(pool)
            raise
        pool.shutdown(wait=True)
    else:
        from dask.distributed import as_completed as dask_completed

        futures = client.map(
            _run_one,
            [build] * len(tasks),
            [force_key] * len(tasks),
            [options] * len(tasks),
            tasks,
            pure=False,
        )
        task_of = {fut.key: t for fut, t in zip(futures, tasks, strict=True)}
        try:
            for fut in dask_completed(futures):
                try:
                    run = fut.result()
                except Exception as exc:  # noqa: BLE001 - reported per set
                    # _run_one catches the set's own errors: this is the
                    # cluster's (KilledWorker after a worker died on the
                    # set, a lost connection); the other sets are kept
                    index, parameters = task_of[fut.key]
                    run = StudyRun(index, dict(parameters))
                    run.error = f"{type(exc).__name__} (cluster): {exc}"
                runs.append(run)
                bar.update(run)
        except BaseException:
            client.cancel(futures)
            raise
    runs.sort(key=lambda r: r.index)
    result = StudyResult(
        runs, kind, time.perf_counter() - start, force_key, normal_load_key
    )
    _summarise(result)
    _warn_unread(result)
    return result


def _warn_unread(result: StudyResult) -> None:
    """One :class:`StudyWarning` naming the parameters ``build`` read in
    no set that it built (the force and normal-load keys are the study's
    own): most often a misspelt grid axis, whose sets then trace the same
    system."""
    built = [r for r in result.runs if r.ok or r.unread]
    if not built:
        return
    own = {result.force_key, result.normal_load_key}
    unread = [
        k
        for k in built[0].parameters
        if k not in own and all(k in r.unread for r in built)
    ]
    if unread:
        names = ", ".join(repr(k) for k in unread)
        warnings.warn(
            f"build never read the parameter(s) {names} in any set: a misspelt "
            "name? Sets that differ only in them trace the same system "
            "(StudyRun.unread lists them per set)",
            StudyWarning,
            stacklevel=3,
        )


#: seconds to wait for a terminated worker process to exit
STOP_TIMEOUT = 5.0


def _stop_pool(pool) -> None:
    """Cancel the queued sets of a process pool and end its workers (the
    sets being traced are abandoned)."""
    processes = list((getattr(pool, "_processes", None) or {}).values())
    pool.shutdown(wait=False, cancel_futures=True)
    for process in processes:
        if process.is_alive():
            process.terminate()
    for process in processes:
        process.join(STOP_TIMEOUT)


def _summarise(result: StudyResult) -> None:
    failed, warned = result.failures, result.warned
    if not failed and not warned:
        return
    parts = []
    if failed:
        first = failed[0]
        parts.append(
            f"{len(failed)} of {len(result)} parameter sets failed (first: set "
            f"{first.index} {first.parameters}: {first.error})"
        )
    if warned:
        first = warned[0]
        parts.append(
            f"{len(warned)} succeeded with warnings (first: set {first.index} "
            f"{first.parameters}: {first.warnings[0]})"
        )
    warnings.warn(
        "; ".join(parts) + "; see StudyResult.failures and .warned",
        StudyWarning,
        stacklevel=3,
    )
