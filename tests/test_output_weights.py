"""The watched output of the truncation estimate (``output_weights`` of the
system protocol): a linear combination of DOF displacements and velocities,
the belt tension on the tensioner rig."""

import math
from dataclasses import dataclass

import numpy as np
import pytest
from scipy.optimize import brentq

import hbmfric as hf
from hbmfric.api import _problem
from hbmfric.continuation.adaptive import _Level, probe_level
from hbmfric.continuation.palc import Continuation
from hbmfric.signals import synthesis_matrix
from hbmfric.systems.protocol import check_system, output_weights
from hbmfric.systems.tensioner import tension_coefficients

RIG = hf.BeltTensioner()
#: above both resonances, where the tension's relative error exceeds the
#: pulley's (issue 14: H = 3 at 92 Hz, 20 N)
BAND = (2.0 * math.pi * 88.0, 2.0 * math.pi * 96.0)


def _points(system, harmonics=5):
    """Points of a fixed-``H`` branch of ``system`` at 20 N, 88-96 Hz, and
    its problem."""
    p = _problem(system, 20.0, harmonics, None, None, "auto", None)
    state, _ = Continuation(p, BAND).run()
    return p, np.array(state.points)


def _probe(problem):
    return _Level(problem.with_harmonics(probe_level(problem.harmonics)), None)


@dataclass(frozen=True)
class RelativeRig:
    """The rig in the coordinates ``q = (u1 − u2, u2)`` (``u = T q``): the
    belt stretch is DOF 0, the tensioner still acts on DOF 1. The equations
    are the rig's premultiplied by ``Tᵀ``."""

    rig: hf.BeltTensioner
    n_dof = 2
    contact_dof = 1
    symmetric = False
    load_phase = 0.5 * math.pi
    #: the watched output: the stretch (DOF 0), alone
    output_weights = (np.array([1.0, 0.0]), np.zeros(2))

    @property
    def contact(self):
        return self.rig.contact

    @staticmethod
    def _t():
        return np.array([[1.0, 1.0], [0.0, 1.0]])

    def matrices(self):
        t = self._t()
        return tuple(t.T @ a @ t for a in self.rig.matrices())

    def load_vector(self, force):
        return self._t().T @ self.rig.load_vector(force)

    def static_load(self):
        return self._t().T @ self.rig.static_load()

    def static_solution(self):
        return np.linalg.solve(self._t(), self.rig.static_solution())


def test_weighted_output_equals_the_dof_of_changed_coordinates():
    """Without belt damping the tension is ``K (u1 − u2)``: its estimate
    on the rig equals that of DOF 0 of the same rig in the coordinates
    ``(u1 − u2, u2)`` (the change is covariant), and differs from the
    pulley's (the former estimate)."""
    rig = hf.BeltTensioner(belt_damping=0.0)
    p, points = _points(rig)
    probe = _probe(p)
    # the same points in the coordinates (u1 - u2, u2)
    n_coef = p.n_coef
    moved = points.copy()
    moved[:, :n_coef] = points[:, :n_coef] - points[:, n_coef : 2 * n_coef]
    q = _problem(RelativeRig(rig), 20.0, p.harmonics, None, None, "auto", None)
    probe_q = _probe(q)
    rows = range(0, len(points), max(1, len(points) // 12))
    tension = np.array([probe.change(points[i]) for i in rows])
    stretch = np.array([probe_q.change(moved[i]) for i in rows])
    assert tension.max() > 1e-6
    np.testing.assert_allclose(tension, stretch, rtol=1e-7)
    # the pulley's change (unit weight on u2) is another number
    pulley = _Level(probe.problem, None)
    pulley.output = np.array([[0.0, 1.0], [0.0, 0.0]])
    pulley_change = np.array([pulley.change(points[i]) for i in rows])
    assert np.max(np.abs(pulley_change / tension - 1.0)) > 0.1


def test_tension_change_matches_numpy():
    """The change the kernel measures on the rig is that of the belt
    tension (displacement and velocity terms), formed here in plain NumPy
    by :func:`tension_coefficients` from the kernel's first-order step,
    half the peak-to-peak change read at the extremes' instants
    (``scipy.optimize.brentq``)."""
    p, points = _points(RIG)
    probe = _probe(p)
    _, _, synthesis, _, _, y, _, _, _, dX = probe.work()
    hn = probe.problem.harmonic_numbers
    n_coef = probe.n_coef
    checked = 0
    for i in range(0, len(points), max(1, len(points) // 10)):
        got = probe.change(points[i])
        omega = y[-1]
        z = tension_coefficients(RIG, hn, y[:-1].reshape(2, n_coef), omega)
        dz = tension_coefficients(RIG, hn, dX.reshape(2, n_coef), omega)
        z[0] -= RIG.pretension
        dz[0] -= RIG.pretension
        a1 = np.hypot(z[1], z[2])
        a1_change = abs(np.hypot(z[1] + dz[1], z[2] + dz[2]) - a1) / a1
        # the extremes of the tension at their instants (brentq on its
        # derivative around the best samples), the change read there
        t = synthesis @ z
        step = 2.0 * np.pi / synthesis.shape[0]

        def at(c, a):
            return float((synthesis_matrix(hn, np.atleast_1d(a)) @ c)[0])

        def slope(a, z=z):
            return (at(z, a + 1e-7) - at(z, a - 1e-7)) / 2e-7

        ends = []
        for j in (int(np.argmax(t)), int(np.argmin(t))):
            a0 = math.atan2(synthesis[j, 2], synthesis[j, 1])
            ends.append(brentq(slope, a0 - step, a0 + step, xtol=1e-13))
        hpp_change = abs(at(dz, ends[0]) - at(dz, ends[1])) / (
            at(z, ends[0]) - at(z, ends[1])
        )
        expected = max(a1_change, hpp_change)
        assert got == pytest.approx(expected, rel=1e-6)
        checked += expected > 1e-7
    assert checked >= 5


def test_condensed_problem_watches_the_contact():
    """A problem condensed onto the contact DOF watches it (its only DOF)."""
    beam = hf.CantileverBeam(contact=hf.Jenkins(stiffness=1e5, slip_force=1.0))
    p = _problem(beam, 1.0, 3, None, None, "auto", None)
    assert p.n_unknowns == p.n_coef  # condensed
    level = _Level(p, None)
    np.testing.assert_array_equal(level.output, [[1.0], [0.0]])


def test_default_output_is_the_contact_dof():
    osc = hf.Oscillator(1.0, 0.1, 1.0)
    w = output_weights(osc, 1, 0)
    np.testing.assert_array_equal(w, [[1.0], [0.0]])
    w = output_weights(RIG, 2, 1)
    k, c = RIG.belt_stiffness, RIG.belt_damping
    np.testing.assert_array_equal(w, [[k, -k], [c, -c]])


@dataclass(frozen=True)
class _Weighted:
    weights: object
    n_dof = 2
    contact_dof = 1
    contact = None

    @property
    def output_weights(self):
        return self.weights

    def matrices(self):
        return np.eye(2), np.zeros((2, 2)), np.eye(2)

    def load_vector(self, force):
        return np.array([force, 0.0])


@pytest.mark.parametrize(
    "weights, match",
    [
        (np.ones(3), "pair"),
        ((np.ones(3), np.zeros(2)), r"output_weights\[0\].*shape \(2,\)"),
        ((np.ones(2), [0.0, np.nan]), r"output_weights\[1\].*finite"),
        ((np.zeros(2), np.zeros(2)), "all zero"),
    ],
)
def test_invalid_output_weights_are_named(weights, match):
    with pytest.raises(ValueError, match=match):
        check_system(_Weighted(weights))


def test_free_measure_is_the_tensions():
    """The free measure ``H max(|Z_H|, (K'/H)^4 |Z_K'|) / |Z_1|`` the
    estimate carries between calibrations is that of the tension, formed
    in NumPy by :func:`tension_coefficients` (its ratio to the change then
    stays put where the tension's first harmonic nearly vanishes)."""
    p, points = _points(RIG)
    level = _Level(p, None)
    hn = p.harmonic_numbers
    assert hn[-1] == 5 and hn[-2] == 4
    for y in points[:: max(1, len(points) // 8)]:
        z = tension_coefficients(RIG, hn, y[:-1].reshape(2, p.n_coef), y[-1])
        amp = np.hypot(z[1::2], z[2::2])  # harmonics 1..5
        expected = 5 * max(amp[4], (4 / 5) ** 4 * amp[3]) / amp[0]
        assert level.measure(y) == pytest.approx(expected, rel=1e-12)
