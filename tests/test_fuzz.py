"""Property-based tests of the public edge (hypothesis): any input to a
constructor or entry point gives a valid result or a ValueError/TypeError
that names the offending parameter -- never a crash from deep inside, a
hang, a NaN result or a Numba typing error."""

import math

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import hbmfric as hf

FUZZ = settings(
    max_examples=30,
    deadline=20000,  # ms: a hang fails the example
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.function_scoped_fixture],
    derandomize=True,
)

#: anything a user might pass where a number is expected
anything = st.one_of(
    st.floats(allow_nan=True, allow_infinity=True),
    st.floats(min_value=-1e6, max_value=1e6),
    st.integers(min_value=-(10**6), max_value=10**6),
    st.booleans(),
    st.none(),
    st.text(max_size=4),
    st.lists(st.floats(min_value=-10, max_value=10), max_size=3),
    st.just(np.array([1.0, 2.0])),
    st.just(np.float32(2.5)),
    st.just(np.int64(3)),
    st.just(1 + 2j),
    st.just(object()),
)


def _call(fn, names, *args, **kwargs):
    """Result of ``fn`` or None if it raised a ValueError/TypeError naming
    one of ``names``; anything else fails the test."""
    try:
        return fn(*args, **kwargs)
    except (ValueError, TypeError) as exc:
        msg = str(exc)
        assert "numba" not in msg.lower(), msg
        assert any(n in msg for n in names), (names, msg)
        return None


def _finite(*arrays):
    for a in arrays:
        assert np.all(np.isfinite(np.asarray(a, dtype=float)))


@FUZZ
@given(stiffness=anything, slip_force=anything)
def test_jenkins(stiffness, slip_force):
    law = _call(
        hf.Jenkins,
        ("stiffness", "slip_force"),
        stiffness=stiffness,
        slip_force=slip_force,
    )
    if law is not None:
        assert law.stiffness > 0 and law.slip_force >= 0
        _finite(law.params)


@FUZZ
@given(stiffness=anything, mu=anything, fn=anything)
def test_jenkins_by_normal_load(stiffness, mu, fn):
    law = _call(
        hf.Jenkins,
        ("stiffness", "friction_coefficient", "normal_load", "slip_force"),
        stiffness=stiffness,
        friction_coefficient=mu,
        normal_load=fn,
    )
    if law is not None:
        _finite(law.params)
        assert math.isclose(law.slip_force, law.friction_coefficient * law.normal_load)


@FUZZ
@given(coefficient=anything)
def test_cubic(coefficient):
    law = _call(hf.Cubic, ("coefficient",), coefficient)
    if law is not None:
        _finite(law.params)


@FUZZ
@given(
    mass=anything,
    damping=anything,
    stiffness=anything,
    contact=st.one_of(anything, st.just(hf.Cubic(1.0))),
)
def test_oscillator(mass, damping, stiffness, contact):
    osc = _call(
        hf.Oscillator,
        ("mass", "damping", "stiffness", "contact"),
        mass,
        damping,
        stiffness,
        contact,
    )
    if osc is not None:
        for m in osc.matrices():
            _finite(m)


LAW = hf.Jenkins(stiffness=3.0, slip_force=1.0)
OSC = hf.Oscillator(1.0, 0.05, 1.0, LAW)

small_int = st.one_of(st.integers(min_value=-3, max_value=9), anything)
omega_pair = st.one_of(
    st.tuples(
        st.floats(min_value=0.05, max_value=4.0),
        st.floats(min_value=0.05, max_value=4.0),
    ),
    st.tuples(anything, anything),
    anything,
)


@FUZZ
@given(
    force=st.one_of(st.floats(min_value=-3.0, max_value=3.0), anything),
    omega=omega_pair,
    harmonics=small_int,
    n_time=st.one_of(st.none(), st.integers(min_value=-2, max_value=80), anything),
    aft=st.sampled_from(["auto", "events", "samples", "fft", 3]),
    sweep=st.sampled_from(["up", "down", "sideways", None]),
    symmetry=st.one_of(st.none(), st.booleans(), anything),
)
def test_frf(force, omega, harmonics, n_time, aft, sweep, symmetry):
    b = _call(
        hf.frf,
        ("force", "omega", "harmonics", "n_time", "aft", "sweep", "symmetry"),
        OSC,
        force,
        omega,
        harmonics,
        n_time=n_time,
        aft=aft,
        sweep=sweep,
        symmetry=symmetry,
        max_steps=400,
    )
    if b is not None:
        _finite(b.omega, b.coefficients)
        assert b.stop_reason


@FUZZ
@given(
    force=st.one_of(st.floats(min_value=-3.0, max_value=3.0), anything),
    omega=st.one_of(st.floats(min_value=0.01, max_value=10.0), anything),
    harmonics=small_int,
    n_time=st.one_of(st.none(), st.integers(min_value=-2, max_value=80), anything),
    guess=st.one_of(
        st.none(), anything, st.just(np.zeros(3)), st.just(np.full(5, np.nan))
    ),
)
def test_periodic_solution(force, omega, harmonics, n_time, guess):
    sol = _call(
        hf.periodic_solution,
        ("force", "omega", "harmonics", "n_time", "initial_guess"),
        OSC,
        force,
        omega,
        harmonics,
        n_time=n_time,
        initial_guess=guess,
    )
    if sol is not None:
        _finite(sol.coefficients, [sol.residual_norm])


@FUZZ
@given(
    force=st.one_of(st.floats(min_value=-3.0, max_value=3.0), anything),
    omega=st.one_of(st.floats(min_value=0.2, max_value=5.0), anything),
    harmonics=small_int,
    steps=st.one_of(st.integers(min_value=-5, max_value=200), anything),
    tol=st.one_of(st.floats(min_value=1e-9, max_value=1e-2), anything),
    initial_state=st.one_of(
        st.none(),
        st.just("linear"),
        st.just("sideways"),
        st.tuples(anything, anything),
        anything,
    ),
)
def test_steady_state(force, omega, harmonics, steps, tol, initial_state):
    ref = _call(
        hf.validation.steady_state,
        ("force", "omega", "harmonics", "steps_per_period", "tol", "initial_state"),
        OSC,
        force,
        omega,
        harmonics=harmonics,
        steps_per_period=steps,
        tol=tol,
        max_periods=200,
        initial_state=initial_state,
    )
    if ref is not None:
        _finite(ref.coefficients, ref.samples)


@FUZZ
@given(content=st.one_of(st.binary(max_size=200), st.just(b"PK\x03\x04garbage")))
def test_branch_load_garbage(tmp_path, content):
    path = tmp_path / "x.npz"
    path.write_bytes(content)
    _call(hf.Branch.load, ("path",), path)


@FUZZ
@given(
    drop=st.sampled_from(
        ["omega", "coefficients", "meta", "folds", "harmonic_numbers", None]
    ),
    meta=st.sampled_from(
        ['{"format": "hbmfric.Branch/1"}', "not json", '{"format": 3}', None]
    ),
)
def test_branch_load_tampered(tmp_path, drop, meta):
    b = hf.frf(OSC, 0.5, (0.5, 1.0), 3)
    path = b.save(tmp_path / "b.npz")
    with np.load(path, allow_pickle=False) as data:
        arrays = {k: data[k] for k in data.files if k != drop}
    if meta is not None and "meta" in arrays:
        arrays["meta"] = np.array(meta)
    np.savez(path, **arrays)
    back = _call(hf.Branch.load, ("path",), path)
    if back is not None:
        _finite(back.omega, back.coefficients)


def test_branch_load_refuses_pickle(tmp_path):
    path = tmp_path / "p.npz"
    np.savez(path, omega=np.array([object()], dtype=object))
    with pytest.raises(ValueError, match="path"):
        hf.Branch.load(path)
