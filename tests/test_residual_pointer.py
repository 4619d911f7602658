"""The residual called through its address (issue 17, the cold first run).

The continuation kernels call the residual through the address of its
compiled code (:mod:`hbmfric.kernels.residuals.pointer`) so that they do not
link and compile it again. The references: the residual kernels called
directly (``hbm_residual``, ``condensed_residual``), which must give the
same state code, residual and Jacobian bit for bit; and the compiled code
of the chain kernels, which must not contain the residual's functions.
"""

import numpy as np
import pytest
from numba import njit
from numba.core.errors import TypingError

import hbmfric as hf
from hbmfric.condensation import CondensedHBMProblem
from hbmfric.hbm import HBMProblem
from hbmfric.kernels.residuals.condensed import condensed_residual
from hbmfric.kernels.residuals.hbm import hbm_residual
from hbmfric.kernels.residuals.pointer import (
    call_residual,
    chain_problem,
    residual_address,
)
from hbmfric.kernels.steps import arclength, newton, truncation


@njit
def _through(address, y, problem, R, J):
    return call_residual(address, y, problem, R, J)


@njit
def _strided(address, y, problem, R, J):
    return call_residual(address, y[::1][::2], problem, R, J)


def _osc(law):
    return hf.Oscillator(1.0, 0.02, 1.0, law)


def _y(problem, amplitude, omega):
    y = np.zeros(problem.n_unknowns + 1)
    y[1] = amplitude  # first-harmonic cosine of DOF 0
    y[-1] = omega
    return y


CASES = {
    "jenkins": lambda: HBMProblem(
        _osc(hf.Jenkins(stiffness=3.0, slip_force=1.0)), 0.5, 7
    ),
    "menq": lambda: HBMProblem(
        _osc(hf.Menq.from_stiffness(stiffness=3.0, slip_force=1.0)), 0.5, 7
    ),
    "cubic (plain tuple)": lambda: HBMProblem(_osc(hf.Cubic(0.2)), 0.5, 7),
    "condensed jenkins": lambda: CondensedHBMProblem(
        _osc(hf.Jenkins(stiffness=3.0, slip_force=1.0)), 0.5, 7
    ),
}

#: more problem types for the continuation's one type per residual
#: (:func:`chain_problem`): rigid Coulomb (DLFT) and Dahl, full and condensed
CHAIN_CASES = {
    **CASES,
    "coulomb": lambda: HBMProblem(_osc(hf.Coulomb(slip_force=1.0)), 0.5, 7),
    "dahl": lambda: HBMProblem(
        _osc(hf.ModifiedDahl(beta=20.0, upper=(0.0, 1.0), lower=(0.0, -1.0))),
        0.5,
        7,
    ),
    "condensed coulomb": lambda: CondensedHBMProblem(
        _osc(hf.Coulomb(slip_force=1.0)), 0.5, 7
    ),
    "condensed menq": lambda: CondensedHBMProblem(
        _osc(hf.Menq.from_stiffness(stiffness=3.0, slip_force=1.0)), 0.5, 7
    ),
}


@pytest.mark.parametrize("case", sorted(CASES))
@pytest.mark.parametrize("amplitude", [0.1, 2.0])  # stuck, slipping
def test_pointer_gives_the_residual_bit_for_bit(case, amplitude):
    problem = CASES[case]()
    kp = problem.kernel_problem
    direct = (
        condensed_residual if isinstance(problem, CondensedHBMProblem) else hbm_residual
    )
    y = _y(problem, amplitude, 1.1)
    n = problem.n_unknowns
    R, J = np.full(n, np.nan), np.full((n, n + 1), np.nan)
    R2, J2 = np.full(n, np.nan), np.full((n, n + 1), np.nan)
    s = _through(residual_address(kp), y, kp, R, J)
    s2 = direct(y, kp, R2, J2)
    assert s == s2 >= 0
    assert np.array_equal(R, R2) and np.array_equal(J, J2)
    assert np.all(np.isfinite(J))


@pytest.mark.parametrize("case", sorted(CHAIN_CASES))
@pytest.mark.parametrize("amplitude", [0.1, 2.0])  # stuck, slipping
def test_chain_problem_gives_the_residual_bit_for_bit(case, amplitude):
    """The continuation kernels receive every problem in one type per
    residual (:func:`chain_problem`) and call the residual compiled for the
    problem's own type through its address: the same state code, ``R`` and
    ``J`` bit for bit as the residual kernel called directly on the
    problem itself."""
    problem = CHAIN_CASES[case]()
    kp = problem.kernel_problem
    direct = (
        condensed_residual if isinstance(problem, CondensedHBMProblem) else hbm_residual
    )
    y = _y(problem, amplitude, 1.1)
    n = problem.n_unknowns
    R, J = np.full(n, np.nan), np.full((n, n + 1), np.nan)
    R2, J2 = np.full(n, np.nan), np.full((n, n + 1), np.nan)
    chain = chain_problem(kp)
    assert type(chain) is not type(kp) and tuple(chain) == tuple(kp)
    s = _through(residual_address(kp), y, chain, R, J)
    s2 = direct(y, kp, R2, J2)
    assert s == s2 >= 0
    assert np.array_equal(R, R2) and np.array_equal(J, J2)
    assert np.all(np.isfinite(J))


def test_one_chain_type_per_residual():
    """Every full problem type (AFT families, plain tuple, rigid Coulomb)
    reaches the continuation kernels as one Numba type, every condensed one
    of one contact to ground of an AFT family as another, the other
    condensed ones (rigid Coulomb, the general type) as a third; the
    residual itself is resolved for the problem's own type only (a chain
    problem does not name the law family)."""

    def chain_types(cases):
        return [_type_of(chain_problem(CHAIN_CASES[c]().kernel_problem)) for c in cases]

    full = chain_types(("jenkins", "menq", "dahl", "cubic (plain tuple)", "coulomb"))
    assert len(set(full)) == 1
    single = chain_types(("condensed jenkins", "condensed menq"))
    assert len(set(single)) == 1 and single[0] != full[0]
    condensed = chain_types(("condensed coulomb",))
    general = CondensedHBMProblem(_osc(hf.Cubic(0.2)), 0.5, 7).kernel_problem
    condensed.append(_type_of(chain_problem(general)))
    assert len(set(condensed)) == 1
    assert condensed[0] not in (full[0], single[0])
    kp = CASES["jenkins"]().kernel_problem
    assert chain_problem(chain_problem(kp)) == chain_problem(kp)
    with pytest.raises(TypeError, match="not its chain_problem"):
        residual_address(chain_problem(kp))


def test_one_address_per_problem_type():
    """Problems of one type share the residual (one signature, one
    address); another type gets its own."""
    a = HBMProblem(
        _osc(hf.Jenkins(stiffness=3.0, slip_force=1.0)), 0.5, 7
    ).kernel_problem
    b = HBMProblem(
        _osc(hf.Jenkins(stiffness=5.0, slip_force=0.3)), 2.0, 15
    ).kernel_problem
    c = HBMProblem(_osc(hf.Cubic(0.2)), 0.5, 7).kernel_problem
    assert residual_address(a) == residual_address(b) > 0
    assert residual_address(c) != residual_address(a)
    jenkins_sigs = [s for s in hbm_residual.signatures if s[1] == _type_of(a)]
    assert len(jenkins_sigs) == 1


def _type_of(value):
    from numba import typeof

    return typeof(value)


def test_call_residual_refuses_other_layouts():
    """Arrays of another layout than the residual was compiled for are a
    typing error at compile time, never a call with the wrong layout."""
    problem = HBMProblem(_osc(hf.Jenkins(stiffness=3.0, slip_force=1.0)), 0.5, 7)
    kp = problem.kernel_problem
    n = problem.n_unknowns
    y = np.zeros(2 * (n + 1))
    with pytest.raises(TypingError, match="call_residual: y"):
        _strided(residual_address(kp), y, kp, np.empty(n), np.empty((n, n + 1)))


def _defined_functions(dispatcher):
    """Names of the functions the compiled code of each signature of
    ``dispatcher`` defines (not the ones it calls through a declaration):
    the module Numba keeps for linking, which a kernel loaded from the cache
    has too (Numba's private ``_shared_module``; a fresh compilation's final
    module otherwise)."""
    names = set()
    for cres in dispatcher.overloads.values():
        names.update(_defined(cres))
    return names


def _defined(cres):
    """Names of the functions one compiled signature defines (see
    :func:`_defined_functions`)."""
    module = getattr(cres.library, "_shared_module", None)
    if module is None:
        module = cres.library._final_module
    return {f.name for f in module.functions if not f.is_declaration}


def test_chain_kernels_do_not_link_the_residual():
    """The continuation kernels call the residual through its address: their
    compiled code holds neither the residual's body nor its contact law's
    AFT (before, each of them compiled the whole residual again)."""
    b = hf.frf(_osc(hf.Jenkins(stiffness=3.0, slip_force=1.0)), 0.5, (0.5, 3.0), 15)
    assert b.stop_reason.startswith("end")
    # the kernels Python calls (truncation_change, called from compiled code
    # only, holds no signature of its own when its callers come from the
    # cache)
    for kernel in (newton.correct, arclength.trace, truncation.branch_truncation):
        defined = _defined_functions(kernel)
        assert defined, kernel
        linked = [
            name
            for name in defined
            if "hbm_residual" in name or "aft_jenkins_events" in name
        ]
        assert not linked, (kernel, linked[:3])


#: functions of the several-contact path (coordinates, their receptances
#: and drawn output) and of the iterative solvers of the condensed chain
SEVERAL_CONTACT_PATH = (
    "_coordinates_residual",
    "_coordinates_linear",
    "_coordinates_drawn",
    "state_matrix",
    "block_solve",
    "reuse_solve",
    "gmres_blocks",
    "gmres_pattern",
    "equilibrate_pattern",
    "pattern_term_sum",
    "pattern_nonzeros",
    "scatter_pattern",
)


def _overload_for(dispatcher, numba_type):
    """The compiled code of ``dispatcher`` whose signature takes an
    argument of ``numba_type``."""
    found = [
        cres
        for args, cres in dispatcher.overloads.items()
        if any(a == numba_type for a in args)
    ]
    assert len(found) == 1, (dispatcher, numba_type, list(dispatcher.overloads))
    return found[0]


def test_one_contact_to_ground_compiles_no_several_contact_path():
    """A problem condensed onto one contact to ground (the paper beam's
    kind) never runs the several-contact path (empty ``law_codes``) nor the
    iterative solvers (solver arrays of order 0): its residual and the
    continuation kernels of its chain type do not compile them (they did,
    about 40 s of the paper's first run, bench/README.md "Issue 17, stop
    29"); the several-contact chain type still does. Reference: the
    functions each compiled kernel defines."""
    jenkins = hf.Jenkins(stiffness=3.0, slip_force=1.0)
    b = hf.frf(_osc(jenkins), 0.5, (0.5, 3.0), "auto", condense=True)
    assert b.stop_reason.startswith("end")
    kp = CondensedHBMProblem(_osc(jenkins), 0.5, 7).kernel_problem
    kernels = [(condensed_residual, _type_of(kp))]
    chain = _type_of(chain_problem(kp))
    for kernel in (newton.correct, arclength.trace, truncation.branch_truncation):
        kernels.append((kernel, chain))
    for kernel, numba_type in kernels:
        defined = _defined(_overload_for(kernel, numba_type))
        compiled = [name for name in defined for f in SEVERAL_CONTACT_PATH if f in name]
        assert not compiled, (kernel, compiled[:3])
