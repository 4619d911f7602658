"""Located DLFT with the linear tail of the response (``hf.Coulomb(linear_tail=True)``).

Why a tail
----------
In :func:`hbmfric.kernels.dlft.coulomb.dlft_located` the contact reverses (or
sticks) where the *truncated* relative velocity ``v_H`` changes sign. The
exact velocity has a kink there (the force jumps, so the acceleration does):
its Fourier coefficients decay as ``1/k²`` and ``v_H`` is ``O(1/H)`` off
near its zeros, which moves every switching instant, hence every force
harmonic, by ``O(1/H)``: first-order convergence in ``H``.

The structure is linear apart from the contact, so the harmonics that the
balance does not carry are slaved to the contact force:
``x̂_k = -G(kΩ) F̂_k`` for every ``k`` outside the retained set ``S``
(``G`` the receptance at the contact DOF; the load has no such harmonics).
A force jump ``J`` at ``θ_j`` has ``F̂_k = -i J e^{-ikθ_j} / (π k)``, so the
missing part of the velocity ``dx/dθ`` is, summed over the jumps,

    v_tail(θ) = Σ_j J_j T(θ - θ_j),
    T(φ) = -(1/π) Σ_{k ∉ S, k ≥ 1} Re(G(kΩ) e^{ikφ}).

The sum is done exactly up to ``K`` (``G`` from the structure) and in closed
form beyond with the high-frequency limit ``G ≈ -μ/(kΩ)²``
(``μ = (M⁻¹)_cc``): ``Σ_{k≥1} cos kφ / k² = π²/6 - πφ/2 + φ²/4`` on
``[0, 2π]``. ``T`` has a kink at ``φ = 0``, the kink of the exact velocity.

Switching conditions
--------------------
The velocity events (reversal, or start of a stick phase) sit at the zeros
of ``v_H + v_tail``. With the events' own jumps in the tail this is a small
coupled system, smooth in the positions because each event sees its own
jump through ``T(0)``:

    G_j(θ, y) = v_H(θ_j) + Σ_i J_i T(θ_j - θ_i) = 0,

with ``J_i = -2 s_i f_s`` for a reversal and ``J_i = h(θ_i) - s_i f_s`` for
the start of a stick phase (``h`` the holding force of
:func:`~hbmfric.kernels.dlft.coulomb.dlft_located`, ``s_i`` the slip direction
before the event). It is solved by Newton in ``θ``; the Jacobian of the
contact force follows from the implicit function theorem,
``dθ/dy = -(∂G/∂θ)⁻¹ ∂G/∂y``. Which events occur and of which kind (the
topology) comes from the march of ``dlft_located`` run on the corrected
velocity samples, repeated until it no longer changes and places every
event at its solved position (and that solve converged). Where that fails
(no root of the switching conditions where the samples see the events, met
at coarse ``H`` far from a solution), and for more than
:func:`event_limit` events (a far Newton iterate whose velocity rings
about zero), the located scheme without tail is used for that evaluation.

Two rules keep the topology from flipping near stick phases, where the
true velocity leaves zero only quadratically and the series rings about
it: a velocity zero where the holding force pushes on in the slip
direction (``s h > f_s``) is no event (the velocity only touches zero;
continuous with a stick event at ``h = s f_s``, whose jump vanishes), and
a stick phase ends where the holding force ``|h|`` reaches ``f_s`` (the
penalised force ``h + ε (u - w) + η u̇`` carries the ringing of ``u``),
located on the interpolant of ``h`` between samples with the DFT corrected
for the jump's position (:func:`~hbmfric.kernels.dlft.coulomb.stick_end`), so that
the residual stays continuous when the end crosses a sample. Newton
keeps each event on a downward zero of ``s G_j``: after a short slip
that follows a stick end the corrected velocity can dip below zero and
come back, Newton from the interpolated position reached either zero of
the dip, and the stick phase after it changed length
(:func:`_solve_switching`).

The first march (no events known yet) starts from a guess, the velocity
reversal next to the largest sample of ``u`` after a forward slip; where
that point lies inside a stick phase the guess is wrong, so it marches two
laps and the next pass starts at the first forward-slip event of the
second lap.

In pure slip the force is piecewise constant and its Fourier coefficients
are integrated exactly, so that the retained harmonics of the exact
periodic solution are a fixed point up to the ``O(1/K²)`` remainder of the
tail. With stick phases the force is sampled and its DFT corrected for the
position of each jump, as in ``dlft_located``. In stick phases only the force jumps
enter the tail (the smooth part of the holding force adds ``O(1/k³)``
coefficients); the end of a stick phase is found on the samples.
"""

import numpy as np

from ..._jit import jit
from ..aft.schemes import GROSS_SLIP, STUCK
from ..linalg.lu import solve_inplace
from .coulomb import (
    _jump_correction,
    add_samples,
    contact_samples,
    dlft_located,
    stick_end,
    stick_sample,
    stuck_at_reference,
)

#: status when a dynamic stiffness of the tail is singular (as in
#: :mod:`hbmfric.kernels.residuals.condensed`)
SINGULAR_RECEPTANCE = -100
#: event kinds
REVERSAL = 0
STICK = 1
#: at most this many passes of march + event solve (topology changes)
MAX_PASSES = 8
#: Newton iterations on the switching conditions
MAX_NEWTON = 30


@jit
def event_limit(h_max):
    """Most velocity events per period solved with the tail; beyond, the
    located scheme is used (a far iterate of Newton, its velocity ringing
    around zero: the switching system would cost ``O(n_e² K)`` per Newton
    step for events the truncated series cannot tell apart)."""
    return max(8, h_max // 2)


@jit
def tail_length(h_max):
    """``K``: harmonics summed exactly in the tail (beyond: closed form)."""
    return max(64, 4 * h_max)


@jit
def contact_receptance(mass, damping, stiffness, contact_dof, omega,
                       harmonic_numbers, mu, q, dq):  # fmt: skip
    """Tail coefficients ``q_k`` of the receptance at the contact DOF.

    ``q_k = G(kΩ) [k ∉ S] - a₂ / k²`` for ``k = 1 … K``; when ``S`` holds
    odd harmonics only (antiperiodic motion) the tail is odd too: ``q_k = 0``
    for even ``k`` and ``q[0] = 1`` flags it (else ``q[0] = 0``),
    ``a₂ = -μ/Ω²`` the coefficient of the closed-form high-frequency part,
    and their Ω-derivatives.

    Parameters
    ----------
    mass, damping, stiffness : ndarray, shape (n_dof, n_dof)
        Symmetric structural matrices.
    contact_dof : int
    omega : float
        Ω, rad/s.
    harmonic_numbers : ndarray of int64
        The retained set ``S``.
    mu : float
        ``(M⁻¹)_cc``, 1/kg.
    q, dq : ndarray of complex128, shape (K + 1,)
        Output: ``q_k`` and ``dq_k/dΩ`` (m/N, m/(N rad/s)).

    Returns
    -------
    tuple of (float, float, bool)
        ``a₂``, ``da₂/dΩ`` and False if a dynamic stiffness was singular.
    """
    n_k = q.size
    kept = np.zeros(n_k, dtype=np.bool_)
    odd = True
    for k in harmonic_numbers:
        if k % 2 == 0:
            odd = False
    # flag in the unused q[0]: odd harmonics only (antiperiodic motion)
    q[0] = 1.0 if odd else 0.0
    dq[0] = 0.0
    for k in harmonic_numbers:
        if k < n_k:
            kept[k] = True
    a2 = -mu / (omega * omega)
    da2 = 2.0 * mu / (omega * omega * omega)
    n = mass.shape[0]
    c = contact_dof
    A = np.empty((2 * n, 2 * n))
    b = np.empty(2 * n)
    z = np.empty(n, dtype=np.complex128)
    for k in range(1, n_k):
        w = k * omega
        g = 0.0j
        dg = 0.0j
        if odd and k % 2 == 0:
            q[k] = 0.0
            dq[k] = 0.0
            continue
        if not kept[k]:
            if n == 1:
                kd = stiffness[0, 0] - mass[0, 0] * w * w
                wc = damping[0, 0] * w
                if kd == 0.0 and wc == 0.0:
                    return a2, da2, False
                g = 1.0 / (kd + 1j * wc)
                dg = -g * g * k * (-2.0 * mass[0, 0] * w + 1j * damping[0, 0])
            else:
                for i in range(n):
                    for j in range(n):
                        kd = stiffness[i, j] - w * w * mass[i, j]
                        wc = w * damping[i, j]
                        A[i, j] = kd
                        A[i, n + j] = -wc
                        A[n + i, j] = wc
                        A[n + i, n + j] = kd
                    b[i] = 0.0
                    b[n + i] = 0.0
                b[c] = 1.0
                if not solve_inplace(A, b):
                    return a2, da2, False
                for i in range(n):
                    z[i] = b[i] + 1j * b[n + i]
                g = z[c]
                for i in range(n):
                    for j in range(n):
                        dz = k * (-2.0 * w * mass[i, j] + 1j * damping[i, j])
                        dg -= z[i] * dz * z[j]
        if odd and k % 2 == 0:
            q[k] = 0.0
            dq[k] = 0.0
        else:
            q[k] = g - a2 / (k * k)
            dq[k] = dg - da2 / (k * k)
    return a2, da2, True


@jit
def _closed_form(phi, odd):
    """``Σ cos kφ / k²`` over ``k >= 1`` (odd ``k`` only if ``odd``) and
    its φ-derivative: ``π²/6 - πx/2 + x²/4`` on ``x = φ mod 2π``, minus a
    quarter of the same at ``2φ`` for the odd terms."""
    x = phi % (2.0 * np.pi)
    c2 = np.pi * np.pi / 6.0 - 0.5 * np.pi * x + 0.25 * x * x
    d2 = -0.5 * np.pi + 0.5 * x
    if odd:
        x = (2.0 * phi) % (2.0 * np.pi)
        c2 -= 0.25 * (np.pi * np.pi / 6.0 - 0.5 * np.pi * x + 0.25 * x * x)
        d2 -= 0.5 * (-0.5 * np.pi + 0.5 * x)
    return c2, d2


@jit
def _kernel(q, dq, a2, da2, phi):
    """``T(φ)``, ``dT/dφ`` and ``∂T/∂Ω`` of the tail (see module doc)."""
    c1 = np.cos(phi)
    s1 = np.sin(phi)
    ck = 1.0
    sk = 0.0
    val = 0.0
    der = 0.0
    dom = 0.0
    for k in range(1, q.size):
        ck, sk = ck * c1 - sk * s1, sk * c1 + ck * s1
        qr = q[k].real
        qi = q[k].imag
        val += qr * ck - qi * sk
        der -= k * (qr * sk + qi * ck)
        dom += dq[k].real * ck - dq[k].imag * sk
    c2, d2 = _closed_form(phi, q[0].real != 0.0)
    return (
        -(val + a2 * c2) / np.pi,
        -(der + a2 * d2) / np.pi,
        -(dom + da2 * c2) / np.pi,
    )


@jit
def _basis(harmonic_numbers, theta, b0, b1, b2):
    """Fourier basis at ``θ`` (coefficient layout) and its θ-derivatives."""
    col = 0
    for k in harmonic_numbers:
        if k == 0:
            b0[col] = 1.0
            b1[col] = 0.0
            b2[col] = 0.0
            col += 1
        else:
            c = np.cos(k * theta)
            s = np.sin(k * theta)
            b0[col] = c
            b0[col + 1] = s
            b1[col] = -k * s
            b1[col + 1] = k * c
            b2[col] = -k * k * c
            b2[col + 1] = -k * k * s
            col += 2


@jit
def _wrap(x):
    """``x`` brought into ``[-π, π)``."""
    return (x + np.pi) % (2.0 * np.pi) - np.pi


@jit
def _tail_samples(n_e, theta, jumps, q, a2, out):
    """``out[i] = Σ_e J_e T(θ_i - θ_e)`` at the samples ``θ_i = 2πi/N``."""
    n_time = out.size
    h = 2.0 * np.pi / n_time
    n_k = q.size
    odd = q[0].real != 0.0
    coef = np.zeros(n_k, dtype=np.complex128)
    for e in range(n_e):
        for k in range(1, n_k):
            coef[k] += jumps[e] * np.exp(-1j * k * theta[e])
    for k in range(1, n_k):
        coef[k] *= q[k]
    table = np.exp(1j * h * np.arange(n_time))
    for i in range(n_time):
        acc = 0.0
        for k in range(1, n_k):
            acc += (coef[k] * table[(k * i) % n_time]).real
        for e in range(n_e):
            x = (i * h - theta[e]) % (2.0 * np.pi)
            acc += a2 * jumps[e] * _closed_form(x, odd)[0]
        out[i] = -acc / np.pi


@jit
def _event_values(harmonic_numbers, theta, U, Hc, b0, b1, b2):
    """``u, u', u''`` and ``h, h'`` at ``θ`` (``u' = v_H``)."""
    _basis(harmonic_numbers, theta, b0, b1, b2)
    u = 0.0
    v = 0.0
    a = 0.0
    hv = 0.0
    hd = 0.0
    for r in range(U.size):
        u += b0[r] * U[r]
        v += b1[r] * U[r]
        a += b2[r] * U[r]
        hv += b0[r] * Hc[r]
        hd += b1[r] * Hc[r]
    return u, v, a, hv, hd


@jit
def _switching_system(n_e, kinds, signs, theta, slip_force, harmonic_numbers,
                      U, Hc, q, dq, a2, da2, G, A, jumps, djumps, work):  # fmt: skip
    """Switching conditions ``G_j`` and ``∂G/∂θ`` at ``θ``; the jumps and
    their θ-derivatives are stored for later use."""
    b0, b1, b2 = work
    vel = np.empty(n_e)
    acc = np.empty(n_e)
    for j in range(n_e):
        _, v, a, hv, hd = _event_values(harmonic_numbers, theta[j], U, Hc, b0, b1, b2)
        vel[j] = v
        acc[j] = a
        if kinds[j] == STICK:
            jumps[j] = hv - signs[j] * slip_force
            djumps[j] = hd
        else:
            jumps[j] = -2.0 * signs[j] * slip_force
            djumps[j] = 0.0
    t0, _, _ = _kernel(q, dq, a2, da2, 0.0)
    for j in range(n_e):
        G[j] = vel[j] + jumps[j] * t0
        A[j, j] = acc[j] + djumps[j] * t0
        for i in range(n_e):
            if i != j:
                t, dt, _ = _kernel(q, dq, a2, da2, theta[j] - theta[i])
                G[j] += jumps[i] * t
                A[j, j] += jumps[i] * dt
                A[j, i] = djumps[i] * t - jumps[i] * dt


@jit
def _newton_switching(n_e, kinds, signs, theta, slip_force, step_limit,
                      harmonic_numbers, U, Hc, q, dq, a2, da2, jumps, djumps,
                      work, G, A):  # fmt: skip
    """Newton iterations on the switching conditions from ``theta``; on
    convergence ``G`` and ``A`` hold the conditions and ``∂G/∂θ`` at the
    root. False if it does not converge."""
    for _ in range(MAX_NEWTON):
        _switching_system(n_e, kinds, signs, theta, slip_force, harmonic_numbers,
                          U, Hc, q, dq, a2, da2, G, A, jumps, djumps, work)  # fmt: skip
        if not solve_inplace(A, G):
            return False
        big = 0.0
        for j in range(n_e):
            step = G[j]
            if step > step_limit:
                step = step_limit
            elif step < -step_limit:
                step = -step_limit
            theta[j] -= step
            if abs(step) > big:
                big = abs(step)
        if big < 1e-12:
            _switching_system(n_e, kinds, signs, theta, slip_force,
                              harmonic_numbers, U, Hc, q, dq, a2, da2, G, A,
                              jumps, djumps, work)  # fmt: skip
            return True
    return False


@jit
def _solve_switching(n_e, kinds, signs, theta, slip_force, step_limit,
                     harmonic_numbers, U, Hc, q, dq, a2, da2, jumps, djumps,
                     work):  # fmt: skip
    """Newton on the switching conditions; False if it does not converge.

    A velocity event ends slip in direction ``s``: its condition crosses
    zero downwards in ``s G`` (``s ∂G_j/∂θ_j < 0``). Newton from the
    interpolated position may land on the upward zero that closes a dip of
    the velocity below zero (the series ringing after a stick end); which
    of the two it reaches flips with the unknowns, and with it the length
    of the stick phase that follows, so the residual jumps. Such an event
    is moved back, in quarter samples over at most the window of
    :func:`_march`, to where ``s G_j > 0`` (still slipping), and Newton is
    run again from there: the root is the first zero of the dip, which
    moves continuously with the unknowns.
    """
    G = np.empty(n_e)
    A = np.empty((n_e, n_e))
    if not _newton_switching(n_e, kinds, signs, theta, slip_force, step_limit,
                             harmonic_numbers, U, Hc, q, dq, a2, da2, jumps,
                             djumps, work, G, A):  # fmt: skip
        return False
    for _ in range(2):
        moved = False
        for j in range(n_e):
            if signs[j] * A[j, j] <= 0.0:
                continue
            # upward zero: back to where the slip still goes on
            start = theta[j]
            for m in range(1, 13):
                theta[j] = start - 0.25 * m * step_limit
                _switching_system(n_e, kinds, signs, theta, slip_force,
                                  harmonic_numbers, U, Hc, q, dq, a2, da2, G,
                                  A, jumps, djumps, work)  # fmt: skip
                if signs[j] * G[j] > 0.0:
                    moved = True
                    break
            if not moved:
                theta[j] = start
            break
        if not moved:
            return True
        if not _newton_switching(n_e, kinds, signs, theta, slip_force,
                                 step_limit, harmonic_numbers, U, Hc, q, dq,
                                 a2, da2, jumps, djumps, work, G, A):  # fmt: skip
            return False
    return True


@jit
def _march(with_grad, slip_force, eps, eta, omega, harmonic_numbers, base,
           U, Hc, dH, u, d, dc, hh, dhh, inverse, derivative, n_given, given,
           kinds, signs, theta, dtheta, force, grad, F, dF, work):  # fmt: skip
    """The march of :func:`~hbmfric.kernels.dlft.coulomb.dlft_located` on the
    corrected velocity samples ``dc``.

    In slip, a given event ``given[e]`` within three samples (or a quarter
    period of the highest harmonic) of the current sample is taken in the
    sample interval that holds it; otherwise an event is where ``dc``
    changes sign, at the zero of its linear interpolant. Records the events' kinds, slip
    directions before them and positions. With ``with_grad`` also
    accumulates the sampled force and its gradient (``force``, ``grad``) and
    the jump corrections (``F``, ``dF``), with ``dtheta`` the derivatives
    of the (given) positions.

    Returns
    -------
    tuple of (int, bool)
        Number of events, whether no sample slips, and whether the march
        ends in a stick phase (then the forced start event lies inside it).
    """
    b0, b1, b2 = work
    n_time = u.size
    n_coef = U.size
    n1 = dH.shape[1]
    h = 2.0 * np.pi / n_time
    # a given position belongs to the event found within this distance
    window = max(3.0 * h, 0.5 * np.pi / harmonic_numbers[-1])
    corr = np.zeros(n_coef)
    dcorr = np.zeros(n_coef)
    dw = np.zeros(n1)
    dhr = np.zeros(n1)
    # start at the forward-to-backward sign change of dc nearest to the
    # largest sample of u (the tail may move it by several samples)
    i_max = np.argmax(u)
    i0 = i_max if dc[i_max] > 0.0 else (i_max - 1) % n_time
    for off in range(n_time // 2):
        a = (i_max + off) % n_time
        b = (i_max - 1 - off) % n_time
        if dc[a] > 0.0 and dc[(a + 1) % n_time] <= 0.0:
            i0 = a
            break
        if dc[b] > 0.0 and dc[(b + 1) % n_time] <= 0.0:
            i0 = b
            break
    if n_given > 0:
        # the interval that holds the first given event
        i0 = int(np.floor((given[0] % (2.0 * np.pi)) / h)) % n_time
    i1 = (i0 + 1) % n_time
    stuck_all = True
    stick = False
    sign = 1.0
    w = 0.0
    armed = True
    first = True
    n_e = 0
    # without given events the start is a guess: march two laps, keep the
    # events of the second (the first settles the state at the start)
    laps = 2 if n_given == 0 else 1
    for j in range(laps * n_time):
        if j == n_time:
            n_e = 0
            stuck_all = True
        i = (i1 + j) % n_time
        p = (i - 1) % n_time
        theta_i = (i0 + 1 + j) * h
        event = first
        ended = False
        if not first:
            if stick:
                lam = hh[i]
                if lam > slip_force or lam < -slip_force:
                    stick = False
                    ended = True
                    sign = 1.0 if lam > 0.0 else -1.0
                    armed = sign * dc[i] > 0.0
            else:
                # a given event close by is taken in its own interval
                near = False
                if n_e < n_given:
                    delta = _wrap(given[n_e] - theta_i)
                    if -window < delta < window:
                        near = True
                        event = delta <= 0.0
                if near:
                    pass
                elif n_given > 0 and theta_i > theta[0] + 2.0 * np.pi - window:
                    # the start event again, one period on: not a new one
                    pass
                elif sign * dc[i] > 0.0:
                    armed = True
                elif armed:
                    event = True
        if event and n_e < kinds.size:
            mid = theta_i - 0.5 * h
            if n_e < n_given and abs(_wrap(given[n_e] - mid)) < window + h:
                theta_e = mid + _wrap(given[n_e] - mid)
            else:
                den = dc[p] - dc[i]
                alpha = dc[p] / den if den != 0.0 else 0.0
                alpha = min(max(alpha, 0.0), 1.0)
                theta_e = theta_i - h + alpha * h
            u_e, v_e, _, h_e, hd_e = _event_values(
                harmonic_numbers, theta_e, U, Hc, b0, b1, b2
            )
            if not first and sign * h_e > slip_force:
                # pushed on in the slip direction where the velocity is
                # zero: it only touches zero (a truncation artefact), no event
                event = False
                armed = False
        if event and n_e < kinds.size:
            before = sign * slip_force
            kinds[n_e] = STICK if -slip_force <= h_e <= slip_force else REVERSAL
            signs[n_e] = sign
            theta[n_e] = theta_e
            if kinds[n_e] == STICK:
                stick = True
                w = u_e
                jump = h_e - before
            else:
                stick = False
                sign = -sign
                armed = sign * dc[i] > 0.0
                jump = -2.0 * before
            if with_grad:
                if kinds[n_e] == STICK:
                    for c in range(n1):
                        dw[c] = v_e * dtheta[n_e, c]
                        acc = hd_e * dtheta[n_e, c]
                        for r in range(n_coef):
                            acc += b0[r] * dH[r, c]
                        dhr[c] = acc
                    for r in range(n_coef):
                        dw[base + r] += b0[r]
                else:
                    for c in range(n1):
                        dhr[c] = 0.0
                for r in range(n_coef):
                    corr[r] = 0.0
                    dcorr[r] = 0.0
                _jump_correction(
                    harmonic_numbers, theta_e, theta_i, h, 1.0, corr, dcorr
                )
                for r in range(n_coef):
                    F[r] += jump * corr[r]
                    for c in range(n1):
                        dF[r, c] += corr[r] * dhr[c] + jump * dcorr[r] * dtheta[n_e, c]
            n_e += 1
            first = False
        if stick:
            if with_grad:
                stick_sample(i, eps, eta, omega, base, w, dw, u, d, hh, dhh,
                             inverse, derivative, force, grad)  # fmt: skip
        else:
            stuck_all = False
            if with_grad and ended and n_e > 0:
                # stick ends inside (θ_p, θ_i]: located, jump corrected
                stick_end(harmonic_numbers, i, p, theta_i, h, sign * slip_force,
                          hh, dhh, eps, eta, omega, base, w, dw, u, d, inverse,
                          derivative, force, grad, F, dF, corr, dcorr)  # fmt: skip
            elif with_grad:
                force[i] = sign * slip_force
    return n_e, stuck_all, stick


@jit
def _slip_coefficients(harmonic_numbers, n_e, theta, signs, slip_force,
                       dtheta, F, dF):  # fmt: skip
    """Exact Fourier coefficients of a pure-slip force (``F``, overwritten)
    and their Jacobian ``Σ_e ∂F/∂θ_e dθ_e/dy`` (``dF``, overwritten).

    Reversal ``e`` at ``θ_e`` ends slip in direction ``s_e`` (jump
    ``J_e = -2 s_e f_s``): ``a_k = -Σ J_e sin kθ_e / (πk)``,
    ``b_k = Σ J_e cos kθ_e / (πk)``, the mean from the interval lengths.
    """
    n1 = dF.shape[1]
    F[:] = 0.0
    dF[:, :] = 0.0
    col = 0
    for k in harmonic_numbers:
        if k == 0:
            acc = 0.0
            for e in range(n_e):
                nxt = theta[(e + 1) % n_e]
                length = (nxt - theta[e]) % (2.0 * np.pi)
                if n_e == 1:
                    length = 2.0 * np.pi
                acc += -signs[e] * slip_force * length
                jump = -2.0 * signs[e] * slip_force
                for c in range(n1):
                    dF[col, c] -= jump / (2.0 * np.pi) * dtheta[e, c]
            F[col] = acc / (2.0 * np.pi)
            col += 1
        else:
            for e in range(n_e):
                jump = -2.0 * signs[e] * slip_force
                ck = np.cos(k * theta[e])
                sk = np.sin(k * theta[e])
                F[col] -= jump * sk / (np.pi * k)
                F[col + 1] += jump * ck / (np.pi * k)
                for c in range(n1):
                    dF[col, c] -= jump * ck / np.pi * dtheta[e, c]
                    dF[col + 1, c] -= jump * sk / np.pi * dtheta[e, c]
            col += 2


@jit
def dlft_tail(params, harmonic_numbers, base, m_cc, q, dq, a2, da2, y,
              inverse, forward, derivative, R, J):  # fmt: skip
    """Rigid Coulomb contact by located DLFT with the linear tail.

    As :func:`hbmfric.kernels.dlft.coulomb.dlft_located`, with the velocity events
    located on ``v_H + v_tail`` (module doc).

    Parameters
    ----------
    params : ndarray, shape (>= 3,)
        ``[slip_force, penalty ε, penalty damping η, ...]`` (N, N/m, N s/m).
    harmonic_numbers : ndarray of int64
    base : int
        Index of the contact DOF's first coefficient in ``y``.
    m_cc : float
        Mass of the contact DOF, kg.
    q, dq : ndarray of complex128, shape (K + 1,)
        Tail coefficients of the receptance and their Ω-derivatives
        (:func:`contact_receptance`).
    a2, da2 : float
        Closed-form high-frequency coefficient ``-μ/Ω²`` and its Ω-derivative.
    y, inverse, forward, derivative, R, J
        As in :func:`~hbmfric.kernels.dlft.coulomb.dlft_located`.

    Returns
    -------
    int
        ``STUCK`` or ``GROSS_SLIP``.
    """
    slip_force = params[0]
    eps = params[1]
    eta = params[2]
    n_time, n_coef = inverse.shape
    n1 = J.shape[1]
    n = n1 - 1
    omega = y[n]
    h = 2.0 * np.pi / n_time
    U, Hc, dH, u, d, hh, dhh = contact_samples(
        harmonic_numbers, base, m_cc, y, R, J, inverse, derivative
    )
    force = np.zeros(n_time)
    grad = np.zeros((n_time, n1))
    # a contact that holds with w = 0 all period is stuck at the reference
    if stuck_at_reference(slip_force, eps, eta, omega, base, u, d, hh, dhh,
                          inverse, forward, derivative, force, grad, R, J):  # fmt: skip
        return STUCK
    work = (np.empty(n_coef), np.empty(n_coef), np.empty(n_coef))
    b0, b1, b2 = work
    max_events = n_time
    kinds = np.zeros(max_events, dtype=np.int64)
    signs = np.zeros(max_events)
    theta = np.zeros(max_events)
    given = np.zeros(max_events)
    given_kinds = np.zeros(max_events, dtype=np.int64)
    given_signs = np.zeros(max_events)
    jumps = np.zeros(max_events)
    djumps = np.zeros(max_events)
    dtheta = np.zeros((max_events, n1))
    F = np.zeros(n_coef)
    dF = np.zeros((n_coef, n1))
    dc = d.copy()
    n_given = 0
    n_e = 0
    settled = False
    solved = False
    for it in range(MAX_PASSES):
        n_e, _, end_stick = _march(False, slip_force, eps, eta, omega, harmonic_numbers,
                        base, U, Hc, dH, u, d, dc, hh, dhh, inverse,
                        derivative, n_given, given, kinds, signs, theta,
                        dtheta, force, grad, F, dF, work)  # fmt: skip
        if n_e > event_limit(harmonic_numbers[-1]):
            break
        if n_given == 0 and n_e > 0:
            # restart at the first event of the settled lap after a forward
            # slip (the state the march assumes at its start)
            e0 = 0
            while e0 < n_e and signs[e0] < 0.0:
                e0 += 1
            if e0 < n_e:
                for e in range(n_e):
                    k = (e0 + e) % n_e
                    given[e] = theta[k] % (2.0 * np.pi)
                    given_kinds[e] = -1
                n_given = n_e
                continue
        if end_stick and n_e >= 2 and kinds[n_e - 1] == STICK:
            # the start event lies inside the stick phase that the last
            # event begins: start there instead, drop the start event
            given[0] = theta[n_e - 1]
            for e in range(1, n_e - 1):
                given[e] = theta[e]
            n_given = n_e - 1
            for e in range(n_given):
                given_kinds[e] = -1
            continue
        same = it > 0 and n_e == n_given
        if same:
            for e in range(n_e):
                if (
                    kinds[e] != given_kinds[e]
                    or signs[e] != given_signs[e]
                    or abs(_wrap(theta[e] - given[e])) > 1e-12
                ):
                    same = False
                    break
        settled = same and solved
        if same:
            # the topology is settled: the positions are those just solved
            for e in range(n_e):
                theta[e] = given[e]
            break
        solved = _solve_switching(n_e, kinds, signs, theta, slip_force, h,
                                  harmonic_numbers, U, Hc, q, dq, a2, da2,
                                  jumps, djumps, work)  # fmt: skip
        if not solved:
            # keep the interpolated positions; the Jacobian stays consistent
            _, _, end_stick = _march(False, slip_force, eps, eta, omega,
                                     harmonic_numbers, base, U, Hc, dH, u, d,
                                     dc, hh, dhh, inverse, derivative, 0,
                                     given, kinds, signs, theta, dtheta,
                                     force, grad, F, dF, work)  # fmt: skip
            _switching_system(n_e, kinds, signs, theta, slip_force,
                              harmonic_numbers, U, Hc, q, dq, a2, da2,
                              np.empty(n_e), np.empty((n_e, n_e)), jumps,
                              djumps, work)  # fmt: skip
        for e in range(n_e):
            given[e] = theta[e]
            given_kinds[e] = kinds[e]
            given_signs[e] = signs[e]
        n_given = n_e
        _tail_samples(n_e, theta, jumps, q, a2, dc)
        for i in range(n_time):
            dc[i] += d[i]
    if not settled:
        # the switching conditions have no root where the samples place the
        # events: fall back to the located scheme without the tail
        return dlft_located(params, harmonic_numbers, base, m_cc, y, inverse,
                            forward, derivative, R, J)  # fmt: skip
    # implicit function theorem: dθ/dy = -(∂G/∂θ)⁻¹ ∂G/∂y
    Gv = np.empty(n_e)
    A = np.empty((n_e, n_e))
    _switching_system(n_e, kinds, signs, theta, slip_force, harmonic_numbers,
                      U, Hc, q, dq, a2, da2, Gv, A, jumps, djumps, work)  # fmt: skip
    B = np.zeros((n_e, n1))
    dj = np.zeros((n_e, n1))
    for e in range(n_e):
        _basis(harmonic_numbers, theta[e], b0, b1, b2)
        for r in range(n_coef):
            B[e, base + r] += b1[r]
        if kinds[e] == STICK:
            for c in range(n1):
                acc = 0.0
                for r in range(n_coef):
                    acc += b0[r] * dH[r, c]
                dj[e, c] = acc
    for j in range(n_e):
        for i in range(n_e):
            t, _, t_om = _kernel(q, dq, a2, da2, theta[j] - theta[i])
            if i == j:
                t, _, t_om = _kernel(q, dq, a2, da2, 0.0)
            B[j, n] += jumps[i] * t_om
            if kinds[i] == STICK:
                for c in range(n1):
                    B[j, c] += dj[i, c] * t
    Ainv = np.empty((n_e, n_e))
    Awork = np.empty((n_e, n_e))
    rhs = np.empty(n_e)
    for col_e in range(n_e):
        Awork[:, :] = A
        rhs[:] = 0.0
        rhs[col_e] = 1.0
        solve_inplace(Awork, rhs)
        Ainv[:, col_e] = rhs
    for e in range(n_e):
        for c in range(n1):
            acc = 0.0
            for i in range(n_e):
                acc -= Ainv[e, i] * B[i, c]
            dtheta[e, c] = acc
    for e in range(n_e):
        given[e] = theta[e]
    n_final, stuck_all, _ = _march(True, slip_force, eps, eta, omega,
                                harmonic_numbers, base, U, Hc, dH, u, d, dc,
                                hh, dhh, inverse, derivative, n_e, given,
                                kinds, signs, theta, dtheta, force, grad, F,
                                dF, work)  # fmt: skip
    consistent = n_final == n_e
    for e in range(n_e):
        if abs(_wrap(theta[e] - given[e])) > 1e-12:
            consistent = False
    if not consistent:
        return dlft_located(params, harmonic_numbers, base, m_cc, y, inverse,
                            forward, derivative, R, J)  # fmt: skip
    pure_slip = n_e > 0
    for e in range(n_e):
        if kinds[e] != REVERSAL:
            pure_slip = False
    if pure_slip:
        # piecewise constant ±f_s: exact Fourier integrals
        _slip_coefficients(harmonic_numbers, n_e, theta, signs, slip_force,
                           dtheta, F, dF)  # fmt: skip
    else:
        add_samples(forward, force, grad, F, dF)
    for r in range(n_coef):
        R[base + r] += F[r]
        for c in range(n1):
            J[base + r, c] += dF[r, c]
    return STUCK if stuck_all else GROSS_SLIP
