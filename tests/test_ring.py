"""Validation of ``rodstab.analytic.ring`` against paper Section 3.1 (eqs 3.1-3.3).

Oracles: two independent sympy derivations of the 2x2 mode problem (determinant of the code's
pencil, and the quadratic form obtained by integrating the P2 integrand of (2.12) over the ring
with the modes (3.2)); the closed-form roots of the printed quadratic; the numbers printed in
the paper; the monodromy (transfer-matrix) method of ``rodstab.transfer`` as a second method.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from rodstab.analytic.ring import (
    ring_mode_eigenvalues,
    ring_mode_pencil,
    ring_overlap,
    ring_stability,
)
from rodstab.errors import RodstabInputError
from rodstab.sections import circle, rectangle
from rodstab.transfer import ring_interval_transfer

sp = pytest.importorskip("sympy")

#: The paper prints three significant decimals, truncated rather than rounded (-0.8616 is printed
#: -0.861), so a printed value v means the exact one lies within 1e-3 of v.
PRINTED_3_DECIMALS = 1e-3
#: Agreement required between the Fourier-mode solution and the monodromy method.
TRANSFER_RTOL = 1e-9

CIRCLE = circle(nu=1 / 3)  # b1 = 1, b2 = 3/4 (paper: b2 = 1/(1 + nu))
B1, B2 = CIRCLE.b1, CIRCLE.b2

b1s, b2s, Ms, ks = sp.symbols("b1 b2 M k", positive=True)


def _closed_form_roots(k, b1, b2):
    """Roots of the printed quadratic M^2 - M (b1 + b2) + b1 b2 (1 - k^2) = 0 (by formula)."""
    disc = (b1 + b2) ** 2 / 4 - b1 * b2 * (1 - k * k)
    return (b1 + b2) / 2 - math.sqrt(disc), (b1 + b2) / 2 + math.sqrt(disc)


# ------------------------------------------------------------- the 2x2 problem before eq (3.3)


def test_eq_3_3_determinant_of_ring_mode_pencil_is_the_printed_factorisation():
    """det(A - M C) of ``ring_mode_pencil`` (sympy, symbolic k, b1, b2, M) equals the paper's
    (M^2 - M (b1 + b2) + b1 b2 (1 - k^2)) (1 - k^2)."""
    A, C = ring_mode_pencil(ks, b1s, b2s)
    K = sp.Matrix(A) - Ms * sp.Matrix(C)
    printed = (Ms**2 - Ms * (b1s + b2s) + b1s * b2s * (1 - ks**2)) * (1 - ks**2)
    assert sp.expand(K.det() - printed) == 0


@pytest.mark.parametrize("j, N", [(0, 1), (2, 1), (3, 1), (1, 3), (2, 3), (4, 3), (5, 2)])
def test_eq_2_12_with_modes_3_2_gives_ring_mode_pencil(j, N):
    """Independent derivation: put omega = A cos(k theta), beta = B sin(k theta), k = j/N, into
    the integrand of P2 (2.12) with R = 1,
    b1 (beta' - omega)^2 + b2 (omega' + beta)^2 - M (beta^2 + omega^2 + 2 beta omega'),
    integrate symbolically over 0 .. 2 pi N and read off the quadratic form in (A, B): it is
    pi N x^T (A_k - M C_k) x with the code's pencil (for j = 0 beta drops out and the form is
    2 pi N (b1 - M) A^2: the 1x1 pencil [b1] - M [1])."""
    th, a, b = sp.symbols("theta A B", real=True)
    k = sp.Rational(j, N)
    omega = a * sp.cos(k * th)
    beta = b * sp.sin(k * th)
    integrand = (b1s * (sp.diff(beta, th) - omega) ** 2 + b2s * (sp.diff(omega, th) + beta) ** 2
                 - Ms * (beta**2 + omega**2 + 2 * beta * sp.diff(omega, th)))
    form = sp.integrate(sp.expand(integrand), (th, 0, 2 * sp.pi * N))
    A, C = ring_mode_pencil(k, b1s, b2s)
    K = sp.Matrix(A) - Ms * sp.Matrix(C)
    x = sp.Matrix([a] if j == 0 else [a, b])
    # cos^2 and sin^2 average 1/2 over the ring, except for j = 0 where cos^2 = 1.
    weight = 2 * sp.pi * N if j == 0 else sp.pi * N
    assert sp.simplify(sp.nsimplify(form - weight * (x.T * K * x)[0, 0])) == 0


@pytest.mark.parametrize("b1, b2", [(1.0, 0.75), (2.25, 0.88), (0.5625, 0.457), (4.0, 1.03)])
@pytest.mark.parametrize("j, N", [(2, 1), (3, 1), (1, 3), (2, 3), (4, 3), (7, 5)])
def test_eq_3_3_corrected_roots_are_the_roots_of_the_determinant(b1, b2, j, N):
    """ring_mode_eigenvalues (default, corrected) = the two roots of the quadratic of (3.3),
    from the quadratic formula; det(A - M C) vanishes there."""
    k = j / N
    lo, hi = ring_mode_eigenvalues(j, N, b1, b2)
    assert (lo, hi) == pytest.approx(_closed_form_roots(k, b1, b2), rel=1e-13, abs=1e-13)
    A, C = ring_mode_pencil(k, b1, b2)
    for M in (lo, hi):
        assert abs(np.linalg.det(A - M * C)) < 1e-12 * max(1.0, np.linalg.norm(A) ** 2)


@pytest.mark.parametrize("b1, b2", [(2.25, 0.88), (0.5625, 0.457), (4.0, 1.03)])
@pytest.mark.parametrize("j, N", [(2, 1), (2, 3), (4, 3)])
def test_eq_3_3_as_printed_is_not_a_root_when_b1_differs_from_1(b1, b2, j, N):
    """Typo finding: (3.3) prints b2 (j/N)^2 under the root; the roots of its own quadratic have
    b1 b2 (j/N)^2. For b1 != 1 the printed values do not zero the quadratic."""
    k = j / N
    for M in ring_mode_eigenvalues(j, N, b1, b2, printed=True):
        quad = M * M - M * (b1 + b2) + b1 * b2 * (1 - k * k)
        assert abs(quad) > 1e-3


@pytest.mark.parametrize("b2", [0.75, 0.6, 2.0 / 3.0])
@pytest.mark.parametrize("j, N", [(0, 1), (2, 1), (2, 3), (4, 3)])
def test_eq_3_3_printed_and_corrected_coincide_for_b1_equal_1(b2, j, N):
    """For b1 = 1 (every case the paper evaluates) b2 k^2 = b1 b2 k^2: both forms agree."""
    assert ring_mode_eigenvalues(j, N, 1.0, b2, printed=True) == pytest.approx(
        ring_mode_eigenvalues(j, N, 1.0, b2), rel=1e-15)


# ------------------------------------------------------------- paper numbers for circular rings


def test_sec_3_1_one_loop_circle_nu_one_third():
    """Paper: N = 1, nu = 1/3: M_C^- = -0.861 (j = 2), M_C^+ = 1 (uniform twist j = 0),
    0 < (L/2pi) kappa_n < 1.86. Closed form: M_C^- = 7/8 - sqrt(1/64 + 3)."""
    r = ring_stability(B1, B2, 1)
    lo, hi = r.M_interval
    assert lo == pytest.approx(7 / 8 - math.sqrt(1 / 64 + 3), rel=1e-14)
    assert lo == pytest.approx(-0.861, abs=PRINTED_3_DECIMALS)
    assert hi == pytest.approx(1.0, rel=1e-14)
    assert r.bounding_modes == (2, 0)
    klo, khi = r.kappa_L_over_2pi_interval
    assert klo == pytest.approx(0.0, abs=1e-14)
    assert khi == pytest.approx(1.86, abs=0.005)  # printed to 2 decimals
    assert r.converged


def test_sec_3_1_three_loop_circle_nu_one_third():
    """Paper: N = 3: M^- = 0.284 (j = 2) sets the top, M_C^- = -0.286 (j = 4) the bottom;
    2.15 < (L/2pi) kappa_n < 3.86. Closed form: M^-(k) = 7/8 - sqrt(1/64 + 3 k^2 / 4)."""
    r = ring_stability(B1, B2, 3)
    lo, hi = r.M_interval
    assert hi == pytest.approx(7 / 8 - math.sqrt(1 / 64 + 0.75 * 4 / 9), rel=1e-14)
    assert lo == pytest.approx(7 / 8 - math.sqrt(1 / 64 + 0.75 * 16 / 9), rel=1e-14)
    assert hi == pytest.approx(0.284, abs=PRINTED_3_DECIMALS)
    assert lo == pytest.approx(-0.286, abs=PRINTED_3_DECIMALS)
    assert r.bounding_modes == (4, 2)
    klo, khi = r.kappa_L_over_2pi_interval
    assert klo == pytest.approx(2.15, abs=0.005)
    assert khi == pytest.approx(3.86, abs=0.005)
    assert (klo, khi) == pytest.approx((3 * (1 - hi), 3 * (1 - lo)), rel=1e-15)


def test_sec_3_1_one_and_three_loop_ranges_do_not_overlap_for_circles():
    """Paper: 'The stability ranges of the 1- and 3-loop rings do not overlap for circular
    cross-sections' ((0, 1.86) vs (2.15, 3.86))."""
    ov = ring_overlap(B1, B2, 1, 3)
    assert ov.overlap is None
    assert ov.intervals[0][1] < ov.intervals[1][0]


def test_sec_3_1_large_out_of_plane_stiffness_gives_overlap():
    """Paper: 'Rods with cross-section having sufficiently large out-of-plane bending stiffness
    compared to in-plane stiffness have overlapping stability ranges for 1- and 3-loop rings.'
    A rectangle with h/t = 3 (b1 = 9)."""
    s = rectangle(aspect=3.0)
    ov = ring_overlap(s.b1, s.b2, 1, 3)
    assert ov.overlap is not None and ov.overlap[0] < ov.overlap[1]


def test_sec_3_1_modes_below_N_bound_only_from_above():
    """Paper: for 0 < j/N < 1 the stability range is M < M^- (M^+ plays no role); for j/N > 1
    it is M^- < M < M^+. Checked mode by mode against the closed-form roots (N = 3)."""
    r = ring_stability(B1, B2, 3)
    for m in r.modes:
        k = m.j / 3
        if m.j == 0:
            assert (m.lower, m.upper) == (-math.inf, pytest.approx(B1))
            continue
        mm, mp = _closed_form_roots(k, B1, B2)
        if k < 1:
            assert m.lower == -math.inf and m.upper == pytest.approx(mm, rel=1e-13)
        else:
            assert (m.lower, m.upper) == pytest.approx((mm, mp), rel=1e-13)
    assert all(m.j != 3 for m in r.modes)  # j = N: rigid rotations, excluded


# ------------------------------------------------------------- second method: monodromy


@pytest.mark.parametrize("b1, b2", [(1.0, 0.75), (1.0, 0.6), (2.25, 0.88), (0.5625, 0.457),
                                    (4.0, 1.03), (1.7, 2.3)])
@pytest.mark.parametrize("N", [1, 2, 3, 5])
def test_eq_3_1_ring_stability_agrees_with_monodromy_method(b1, b2, N):
    """Second method (no Fourier ansatz): periodic solutions of (3.1) from the monodromy matrix
    over 2 pi N, with the closure condition int beta = 0 (rodstab.transfer)."""
    r = ring_stability(b1, b2, N)
    lo, hi, _ = ring_interval_transfer(b1, b2, N)
    assert lo == pytest.approx(r.M_interval[0], rel=TRANSFER_RTOL)
    assert hi == pytest.approx(r.M_interval[1], rel=TRANSFER_RTOL)


def test_sec_3_1_spurious_root_M_equals_b2_is_excluded_by_closure():
    """Paper: M = b2 (beta = const) is periodic but excluded by int beta = 0. The monodromy
    method sees it (periodic solution) and must drop it: M = b2 is not an admissible root."""
    _, _, admissible = ring_interval_transfer(B1, B2, 1)
    assert all(abs(m - B2) > 1e-6 for m in admissible)


@pytest.mark.parametrize("kwargs, name", [
    (dict(b1=0.0, b2=1.0, loops=1), "b1"),
    (dict(b1=1.0, b2=-1.0, loops=1), "b2"),
    (dict(b1=math.nan, b2=1.0, loops=1), "b1"),
    (dict(b1=1.0, b2=math.inf, loops=1), "b2"),
    (dict(b1=1.0, b2=1.0, loops=0), "loops"),
    (dict(b1=1.0, b2=1.0, loops=1.5), "loops"),
    (dict(b1=1.0, b2=1.0, loops=True), "loops"),
])
def test_ring_stability_rejects_bad_input_naming_it(kwargs, name):
    """Bad input raises RodstabInputError (a ValueError) whose message names the parameter."""
    with pytest.raises(RodstabInputError, match=name):
        ring_stability(**kwargs)


def test_a_ring_of_a_billion_loops_is_refused_before_any_work():
    """2N + 4 mode eigenproblems past limits.max_steps: refused naming loops and the limit
    option (issue 10: it ran unbounded); a lower limit refuses a small ring too."""
    from rodstab.errors import RodstabInputError
    from rodstab.limits import Limits

    with pytest.raises(RodstabInputError, match=r"loops 1000000000.*--max-steps"):
        ring_stability(1.0, 0.75, 10**9)
    with pytest.raises(RodstabInputError, match=r"loops 5: 14 Fourier modes"):
        ring_stability(1.0, 0.75, 5, limits=Limits(max_steps=13))
    assert ring_stability(1.0, 0.75, 5, limits=Limits(max_steps=14)).loops == 5


@pytest.mark.parametrize("b1, b2", [(1.0, 0.75), (16.0, 1.45), (0.25, 0.05), (3.0, 3.0)])
@pytest.mark.parametrize("loops", [1, 2, 3, 5])
def test_closed_form_mode_bounds_equal_the_pencil_eigen_solve(b1, b2, loops):
    """ring_mode_bound (the roots of (3.3), corrected) gives the interval about M = 0 that the
    generalized eigen solve of the mode's pencil gives, for every mode j != N up to 2N + 4."""
    from rodstab.analytic.ring import ring_mode_bound
    from rodstab.numerics import pencil_interval

    for j in range(2 * loops + 5):
        if j == loops:
            continue
        got = ring_mode_bound(j, loops, b1, b2)
        ref = pencil_interval(*ring_mode_pencil(j / loops, b1, b2))
        for a, b in ((got.lower, ref.lo), (got.upper, ref.hi)):
            assert a == b or a == pytest.approx(b, rel=1e-12), (j, a, b)
