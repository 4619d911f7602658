"""Quiet failures and misleading behaviour found by trying the library as a
new user would (each test failed before its fix)."""

import numpy as np
import pytest

import hbmfric as hf
import hbmfric.stability as stability_module


def _duffing_branch():
    duffing = hf.Oscillator(1.0, 0.05, 1.0, hf.Cubic(0.1))
    return duffing, hf.frf(duffing, 0.5, (0.5, 2.5), harmonics=3)


def test_special_points_reuse_the_cached_stability(monkeypatch):
    """``special_points()`` recomputed every point's stability on each call
    (minutes on a several-DOF friction branch, by the monodromy)."""
    system, branch = _duffing_branch()
    calls = []
    original = stability_module.stability_of_points

    def counted(*args, **kwargs):
        calls.append(1)
        return original(*args, **kwargs)

    monkeypatch.setattr(stability_module, "stability_of_points", counted)
    branch.stability()
    assert len(calls) == 1
    assert not np.all(branch.stable)  # the middle stretch: a real test case
    kinds = [p.kind for p in branch.special_points()]
    assert "fold" in kinds
    branch.special_points()
    branch.special_points(system)  # the same system object: still cached
    assert len(calls) == 1


@pytest.mark.parametrize("ratios", [2.0, [0.01, 5.0], 1.0])
def test_modal_damping_given_in_percent_is_refused(ratios):
    """``modal_damping=2.0`` (meant as 2 %) gave 200 % damping quietly."""
    with pytest.raises(ValueError, match="critical"):
        hf.LinearStructure(np.eye(2), np.diag([1.0, 4.0]), modal_damping=ratios)
    # a ratio below 1 is accepted and gives 2 ζ ω on the diagonal here
    s = hf.LinearStructure(np.eye(2), np.diag([1.0, 4.0]), modal_damping=0.02)
    np.testing.assert_allclose(np.diag(s.matrices()[1]), [0.04, 0.08], rtol=1e-12)


def test_cli_version_and_defaults_in_help(capsys):
    from hbmfric.cli import main

    with pytest.raises(SystemExit) as exit_info:
        main(["--version"])
    assert exit_info.value.code == 0
    assert capsys.readouterr().out.startswith("hbmfric ")
    with pytest.raises(SystemExit):
        main(["paper", "--help"])
    assert "default: paper-results" in capsys.readouterr().out
    with pytest.raises(SystemExit):
        main(["run", "--help"])
    assert "scenes-and-studies" in capsys.readouterr().out


def test_exact_reference_names_the_contact_it_refuses():
    """ "got 1 contact(s)" for one contact between two DOFs."""
    from hbmfric.validation import exact_periodic_solution

    law = hf.Jenkins(stiffness=3.0, slip_force=1.0)
    system = hf.LinearStructure(
        np.eye(2),
        np.array([[2.0, -1.0], [-1.0, 2.0]]),
        modal_damping=0.01,
        contacts=[hf.Contact(law, 0, other=1)],
    )
    with pytest.raises(ValueError, match="between DOFs 0 and 1.*steady_state"):
        exact_periodic_solution(system, 0.5, 1.0)


def test_monodromy_stability_of_a_chain_starts_on_the_orbit():
    """Stability of a three-DOF chain with a Jenkins contact between two DOFs
    (the time-domain monodromy): at converged branch points near the first
    resonance it warned "the start is not on a periodic orbit ... 1.1e-2"
    (a virgin slider, forgotten at 0.91 per period)."""
    import warnings

    from hbmfric.stability import stability_of_points

    mass = np.eye(3)
    stiffness = np.array(
        [[2000.0, -1000.0, 0.0], [-1000.0, 2000.0, -1000.0], [0.0, -1000.0, 1000.0]]
    )
    law = hf.Jenkins(stiffness=2000.0, slip_force=1.0)
    system = hf.LinearStructure(
        mass,
        stiffness,
        modal_damping=0.01,
        load={0: 1.0},
        contacts=[hf.Contact(law, 1, other=2)],
    )
    branch = hf.frf(system, 5.0, (8.0, 25.0))  # the user's call
    pick = np.array([np.argmin(abs(branch.omega - w)) for w in (12.50, 12.88, 12.91)])
    with warnings.catch_warnings():
        warnings.simplefilter("error", hf.HbmfricWarning)
        stab = stability_of_points(
            system,
            branch.force,
            branch.omega[pick],
            branch.harmonic_numbers,
            branch.coefficients[pick],
            branch.point_harmonics[pick],
            symmetric=bool(branch.info.get("odd_only", False)),
            method="monodromy",
        )
    assert np.all(stab.stable)
    # a stable slipping orbit of a damped structure: all multipliers inside
    # the unit circle but the slider's, which a slipping contact damps too
    assert np.all(np.abs(stab.multipliers) < 1.0)
