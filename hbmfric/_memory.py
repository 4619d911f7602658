"""How much memory a harmonic-balance solve needs, against what the machine
has.

A problem solved in full (not condensed onto its contacts) keeps dense
matrices of order ``n = n_dof × n_coef`` (the unknowns of one harmonic
level): the Jacobian and the bordered matrix of the corrector, and, where
the level calibrates a lower one's truncation estimate, two more. On an
81-DOF beam with a 2D contact element (every harmonic) ``harmonics="auto"``
climbed to ``H = 31`` and held about 5 GB; a 500-DOF model would need tens
of GB at the same levels, and Linux then kills the process without a word
(the allocation itself succeeds and fails only when the pages are touched).
So the public calls check first, with :func:`fits`, and either stop the
harmonic ladder below what does not fit or raise a ``MemoryError`` that
says what to do, before any work is lost.
"""

from __future__ import annotations

import os

#: share of the available memory a solve may plan to use (the rest is the
#: interpreter, the compiled kernels, the points and the user's own data)
MEMORY_SHARE = 0.75
#: dense matrices of order ``n`` a traced level keeps (Jacobian and
#: bordered matrix of the corrector, and the calibration's pair when the
#: level also calibrates a lower one)
TRACED_MATRICES = 4
#: ... and a level that only calibrates (the probe of a truncation estimate)
PROBE_MATRICES = 2


def available_memory() -> int | None:
    """Bytes of memory available to a new allocation, or None where the
    system does not say (``MemAvailable`` of ``/proc/meminfo`` on Linux,
    else the free physical pages)."""
    try:
        # one raw read (a text file object and its line loop cost several
        # times the kernel's own work, on every frf call)
        fd = os.open("/proc/meminfo", os.O_RDONLY)
        try:
            available = mem_available(os.read(fd, 1 << 16))
        finally:
            os.close(fd)
        if available is not None:
            return available
    except OSError:
        pass
    try:
        return int(os.sysconf("SC_AVPHYS_PAGES")) * int(os.sysconf("SC_PAGE_SIZE"))
    except (AttributeError, ValueError, OSError):
        return None


def mem_available(meminfo: bytes) -> int | None:
    """Bytes of the ``MemAvailable:`` line (kB) of the text of
    ``/proc/meminfo``, None when it has no such line or it does not read."""
    text = b"\n" + meminfo
    at = text.find(b"\nMemAvailable:")
    if at < 0:
        return None
    end = text.find(b"\n", at + 1)
    try:
        return int(text[at + 14 : None if end < 0 else end].split()[0]) * 1024
    except (ValueError, IndexError):
        return None


def budget() -> float:
    """Bytes a solve may plan to use: ``MEMORY_SHARE`` of
    :func:`available_memory` (inf where unknown)."""
    available = available_memory()
    return float("inf") if available is None else MEMORY_SHARE * available


def unknowns(n_dof: int, harmonics: int, odd: bool) -> int:
    """Unknowns of a harmonic level: ``n_dof`` times the Fourier
    coefficients of harmonics ``0 … H`` (``1, 3, … H`` when ``odd``)."""
    h = int(harmonics)
    if h < 1:
        from .hbm import select_harmonics

        select_harmonics(h, bool(odd))  # raises its ValueError
    # harmonics 1, 3, … <= H: a cosine and a sine each; 0 … H: the constant
    # and a pair per harmonic (the layout of select_harmonics)
    n_coef = 2 * ((h + 1) // 2) if odd else 2 * h + 1
    return int(n_dof) * n_coef


def dense_bytes(n: int, matrices: int) -> float:
    """Bytes of ``matrices`` dense float64 matrices of order ``n + 1``."""
    return 8.0 * matrices * (n + 1.0) ** 2


def gigabytes(n_bytes: float) -> str:
    """``n_bytes`` as GB with two significant digits."""
    return f"{n_bytes / 1e9:.2g} GB"


def level_plan_bytes(n_dof: int, odd: bool, traced, probes) -> float:
    """Bytes of the dense matrices of the ``traced`` and ``probes`` levels
    (iterables of ``H``; a level in both counts once, as traced)."""
    traced = set(int(h) for h in traced)
    probes = set(int(h) for h in probes) - traced
    total = sum(dense_bytes(unknowns(n_dof, h, odd), TRACED_MATRICES) for h in traced)
    total += sum(dense_bytes(unknowns(n_dof, h, odd), PROBE_MATRICES) for h in probes)
    return float(total)


def too_large(what: str, needed: float, available: float) -> MemoryError:
    """The error of a solve that does not fit, with what to do."""
    return MemoryError(
        f"{what} needs about {gigabytes(needed)} for its dense matrices, more "
        f"than the {gigabytes(available)} this machine can give it "
        f"({MEMORY_SHARE:.0%} of the memory available now). Solve fewer "
        "unknowns: condense onto the contacts (1D contacts, condense=None or "
        "'modal'), reduce the model (hf.craig_bampton, keeping the contact and "
        "loaded DOFs), or use fewer harmonics (symmetry=True where the system "
        "is odd halves them)"
    )


def _per_coefficient(problem) -> int:
    """Unknowns per Fourier coefficient of ``problem`` (its DOFs, or its
    contact coordinates when condensed)."""
    return int(problem.n_unknowns // problem.n_coef)


def check_fixed(problem, what: str) -> None:
    """Raise :func:`too_large` when ``problem`` at its own ``H``, with the
    level that calibrates its truncation estimate, does not fit in
    :func:`budget`."""
    from .continuation.adaptive import LADDER, probe_level

    h = int(problem.harmonic_numbers[-1])
    need = level_plan_bytes(
        _per_coefficient(problem), problem.odd, [h], [probe_level(h, LADDER)]
    )
    room = budget()
    if need > room:
        raise too_large(
            f"{what} ({problem.n_unknowns} unknowns at H = {h})",
            need,
            room / MEMORY_SHARE,
        )


def fitting_ladder(problem, ladder, first: int) -> tuple[tuple, float | None]:
    """The rungs of ``ladder`` whose levels and calibrating levels fit in
    :func:`budget`, for an adaptive run of ``problem``'s kind starting at
    rung index ``first``.

    Returns
    -------
    rungs : tuple of int
        ``ladder`` itself when all of it fits, else its leading rungs.
    needed : float or None
        Bytes the next rung would have needed (None when all fits).

    Raises
    ------
    MemoryError
        When not even the rungs up to the first level fit.
    """
    from .continuation.adaptive import probe_level

    ladder = tuple(int(h) for h in ladder)
    per, odd = _per_coefficient(problem), problem.odd
    room = budget()

    def need(k: int) -> float:
        rungs = ladder[:k]
        return level_plan_bytes(per, odd, rungs, [probe_level(h, rungs) for h in rungs])

    if need(len(ladder)) <= room:
        return ladder, None
    for k in range(len(ladder) - 1, first, -1):
        if need(k) <= room:
            return ladder[:k], need(k + 1)
    raise too_large(
        f"harmonics='auto' on {per} unknowns per coefficient (its first level "
        f"H = {ladder[first]})",
        need(first + 1),
        room / MEMORY_SHARE,
    )
