"""Hill's stability checks its memory before any eigenvalue work (stop 35).

Before stop 35 ``stability_of_points`` (``Branch.stability``,
``PeriodicSolution.stability``) checked nothing: Hill's problem of a full
model holds about 12-15 dense matrices of the Jacobian's order (measured
with ``tracemalloc``: 15.1 at order 930, 12.0 at order 1860), more than the
12 of the ``frf`` plan the branch was traced under, so a branch that just
fitted could be killed by the operating system in its stability call. The
plan (:func:`hbmfric.stability.hill_bytes`) is checked here against the
measured peak, and the refusal against a budget just below it.
"""

import tracemalloc
import warnings

import numpy as np
import pytest

import hbmfric as hf
from hbmfric import _memory
from hbmfric import stability as _stability
from hbmfric.stability import hill_bytes, stability_of_points


def _chain(n: int):
    k = 2.0 * np.eye(n) - np.eye(n, k=1) - np.eye(n, k=-1)
    return hf.LinearStructure(
        mass=np.eye(n),
        stiffness=k,
        damping=0.01 * k + 0.01 * np.eye(n),
        contacts=[hf.Contact(hf.Jenkins(stiffness=2.0, slip_force=0.3), n - 1)],
        load={n - 1: 1.0},
    )


def _points(system, omegas, harmonics):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        sols = [
            hf.periodic_solution(system, 1.0, w, harmonics=harmonics) for w in omegas
        ]
    coefficients = np.stack([p.coefficients for p in sols])
    return sols[0].harmonic_numbers, coefficients


def _case(n_dof: int, harmonics: int, omegas=(0.1, 0.12)):
    """The chain of ``n_dof`` DOFs and its solutions at ``omegas``."""
    system = _chain(n_dof)
    omegas = np.array(omegas)
    return (system, omegas, *_points(system, omegas, harmonics))


def _plan(n_dof: int, harmonics: int, n_points: int, split: bool) -> float:
    n = n_dof * (2 * harmonics + 1)  # Hill's basis 0 … H of every DOF
    orders = [n] if not split else [n_dof * (harmonics + 1), n_dof * harmonics]
    kept, working = hill_bytes(n, orders, n_points)
    return kept + working


def test_plan_covers_the_measured_peak():
    # 24 DOFs at H = 9: Jacobians of order 456, the whole pencil (no split)
    n_dof, h = 24, 9
    system, omegas, hn, coef = _case(n_dof, h, (0.1, 0.11, 0.12))
    # compiled (or loaded from the cache) before the measure: Numba's own
    # allocations are not the problem's
    stability_of_points(
        system, 1.0, omegas[:1], hn, coef[:1], np.full(1, h), method="hill"
    )
    tracemalloc.start()
    try:
        stability_of_points(
            system, 1.0, omegas, hn, coef, np.full(3, h), method="hill", exponents="all"
        )
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    plan = _plan(n_dof, h, 3, split=False)
    # never under the measured peak (43.6 MB against a plan of 56.6 MB when
    # written), and not a gross over-count
    assert peak <= plan
    assert plan <= 2.0 * peak


def test_too_large_raises_before_any_jacobian(monkeypatch):
    n_dof, h = 6, 7
    system, omegas, hn, coef = _case(n_dof, h)
    whole = _plan(n_dof, h, 2, split=False)
    monkeypatch.setattr(_memory, "budget", lambda: 0.9 * whole)

    def no_jacobians(*args, **kwargs):
        raise AssertionError("a Jacobian was evaluated before the memory check")

    with monkeypatch.context() as m:
        m.setattr(_stability._Level, "_evaluate", no_jacobians)
        with pytest.raises(MemoryError, match=r"Hill's stability at H = 7 .*monodromy"):
            stability_of_points(
                system, 1.0, omegas, hn, coef, np.full(2, h), method="hill"
            )
    # with the budget just above the plan it is computed (and stable: the
    # solutions are those of a damped chain forced far below resonance)
    monkeypatch.setattr(_memory, "budget", lambda: 1.01 * whole)
    st = stability_of_points(
        system, 1.0, omegas, hn, coef, np.full(2, h), method="hill"
    )
    assert st.stable.all()


def test_split_blocks_fit_where_the_whole_would_not(monkeypatch):
    # an odd system with odd solutions: Hill's odd and even blocks apart
    # need about a third of the whole pencil; a budget between the two plans
    # refuses only the whole
    n_dof, h = 6, 7
    system, omegas, hn, coef = _case(n_dof, h)
    split = _plan(n_dof, h, 2, split=True)
    whole = _plan(n_dof, h, 2, split=False)
    assert split < 0.6 * whole
    monkeypatch.setattr(_memory, "budget", lambda: 0.5 * (split + whole))
    st = stability_of_points(
        system, 1.0, omegas, hn, coef, np.full(2, h), method="hill", symmetric=True
    )
    assert st.stable.all()
    with pytest.raises(MemoryError, match="Hill's stability"):
        stability_of_points(
            system, 1.0, omegas, hn, coef, np.full(2, h), method="hill", symmetric=False
        )


def test_branch_stability_refuses_and_the_monodromy_still_answers(monkeypatch):
    # the public path: a branch of the chain, its Hill stability refused
    # under a small budget, the monodromy (what the message advises) not
    n_dof, h = 3, 15
    system = _chain(n_dof)
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # the branch is right: no warning
        branch = hf.frf(system, force=1.0, omega=(1.2, 1.3), harmonics=h)
    monkeypatch.setattr(_memory, "budget", lambda: 1e3)
    with pytest.raises(MemoryError, match="Hill's stability"):
        branch.stability(method="hill")
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        st = branch.stability(method="monodromy")
    assert st.stable.all()


def test_a_long_hill_call_warns_before_its_eigenvalues(monkeypatch):
    # the 8-DOF chain of stop 34's hunt (Jenkins + relative Menq, H up to
    # 63, 505 points) ran Branch.stability() for 20-40 minutes without a
    # word; the estimate is checked here on a small chain with the
    # threshold lowered, before any eigenvalue solve
    n_dof, h = 6, 15
    system, omegas, hn, coef = _case(n_dof, h)
    seconds = _stability.hill_seconds([(2, [n_dof * (2 * h + 1)])])
    monkeypatch.setattr(_stability, "COST_WARNING_SECONDS", 0.5 * seconds)

    def no_eigenvalues(*args, **kwargs):
        raise AssertionError("eigenvalues computed before the warning")

    with monkeypatch.context() as m:
        m.setattr(_stability, "_companion_eigenvalues", no_eigenvalues)
        with warnings.catch_warnings():
            warnings.simplefilter("error", hf.CostWarning)
            with pytest.raises(hf.CostWarning, match="Hill's stability at 2 points"):
                stability_of_points(
                    system, 1.0, omegas, hn, coef, np.full(2, h), method="hill"
                )
    # the hint: a smaller perturbation basis, below the top H and cheaper
    with pytest.warns(hf.CostWarning, match=r"perturbation_harmonics=7 \(about"):
        stability_of_points(system, 1.0, omegas, hn, coef, np.full(2, h), method="hill")
    # under the threshold: no word
    monkeypatch.setattr(_stability, "COST_WARNING_SECONDS", 2.0 * seconds)
    with warnings.catch_warnings():
        warnings.simplefilter("error", hf.CostWarning)
        st = stability_of_points(
            system, 1.0, omegas, hn, coef, np.full(2, h), method="hill"
        )
    assert st.stable.all()
