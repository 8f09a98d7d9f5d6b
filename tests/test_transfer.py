"""Validation of ``rodstab.transfer`` (shooting / monodromy second method).

Oracles: sympy's Euler-Lagrange operator (``sympy.calculus.euler.euler_equations``) applied to
the second variation P2 of eq (2.12) -- for the clamped arc in (u, w) with x = s/L and for the
ring in (omega, beta) with R = 1 -- compared with the first-order systems the module builds;
the paper's printed (3.1), (3.4) and general solution (3.5); closed-form ring eigenvalues (3.3);
and a 40-digit mpmath evaluation of the shooting determinant.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.linalg import expm

from rodstab.analytic.arc import clamped_arc_stability
from rodstab.numerics import matrix_roots
from rodstab.sections import circle, rectangle
from rodstab.transfer import (
    RING_RIGID_NULLITY,
    arc_system_matrix,
    clamped_arc_matrix,
    clamped_arc_mode,
    ring_periodicity_measure,
    ring_system_matrix,
)

sp = pytest.importorskip("sympy")
from sympy.calculus.euler import euler_equations  # noqa: E402

RNG = np.random.default_rng(20240611)

x_, th_ = sp.symbols("x theta", real=True)
b1_, b2_, Lb_, m_, M_ = sp.symbols("b1 b2 Lbar m M", real=True)
u_, w_ = sp.Function("u")(x_), sp.Function("w")(x_)
om_, be_ = sp.Function("omega")(th_), sp.Function("beta")(th_)


def _arc_el():
    """EL equations of I[u, w] = int {b1 (u'' - Lb w)^2 + b2 (w' + Lb u')^2
    - m (Lb u'^2 + Lb w^2 + 2 u' w')} dx (P2 of (2.12) with beta = u3', m = M Lbar)."""
    up, upp = u_.diff(x_), u_.diff(x_, 2)
    wp = w_.diff(x_)
    lag = (b1_ * (upp - Lb_ * w_) ** 2 + b2_ * (wp + Lb_ * up) ** 2
           - m_ * (Lb_ * up**2 + Lb_ * w_**2 + 2 * up * wp))
    eq_u, eq_w = euler_equations(lag, [u_, w_], x_)
    return eq_u.lhs, eq_w.lhs


def _arc_solved():
    """(u'''', w'') from the EL equations, as functions of (u'', w, params)."""
    eq_u, eq_w = _arc_el()
    u4, w2 = sp.symbols("u4 w2")
    sub = {u_.diff(x_, 4): u4, w_.diff(x_, 2): w2}
    sol = sp.solve([eq_u.subs(sub), eq_w.subs(sub)], [u4, w2], dict=True)[0]
    u2, ww = sp.symbols("u2 ww")
    back = {u_.diff(x_, 2): u2, w_: ww}
    args = (u2, ww, b1_, b2_, Lb_, m_)
    return (sp.lambdify(args, sol[u4].xreplace(back)),
            sp.lambdify(args, sol[w2].xreplace(back)))


# ------------------------------------------------------------------ the arc: P2 -> eq (3.4)


def test_eq_3_4_arc_system_matrix_is_the_euler_lagrange_system_of_p2():
    """sympy EL equations of I[u, w], solved for u'''' and w'', equal rows 3 and 5 of
    ``arc_system_matrix`` (state y = (u, u', u'', u''', w, w')) at random parameters; all other
    rows are the trivial chain y_k' = y_{k+1}."""
    f_u4, f_w2 = _arc_solved()
    for _ in range(8):
        b1, b2 = RNG.uniform(0.2, 5.0, 2)
        Lb, L_kappa = RNG.uniform(0.0, 7.0), RNG.uniform(-20.0, 20.0)
        m = Lb - L_kappa
        S = arc_system_matrix(L_kappa, Lb, b1, b2)
        y = RNG.normal(size=6)
        dy = S @ y
        np.testing.assert_allclose(dy[[0, 1, 2, 4]], y[[1, 2, 3, 5]], rtol=0, atol=0)
        np.testing.assert_allclose(dy[3], f_u4(y[2], y[4], b1, b2, Lb, m), rtol=1e-12,
                                   atol=1e-12 * np.abs(S).max())
        np.testing.assert_allclose(dy[5], f_w2(y[2], y[4], b1, b2, Lb, m), rtol=1e-12,
                                   atol=1e-12 * np.abs(S).max())


def test_eq_3_4_printed_first_line_is_el_with_w_double_prime():
    """The EL equations are (3.4) with w''' -> w'' in line 1 and w''', u''' -> w'', u'' in
    line 2 (M Lbar = m): the corrected (3.4) minus the sympy EL equations is identically 0."""
    eq_u, eq_w = _arc_el()
    u, w = u_, w_
    d = sp.Derivative
    line1 = (b1_ * (d(u, (x_, 4)) - Lb_ * d(w, (x_, 2))) - b2_ * Lb_ * (d(w, (x_, 2))
             + Lb_ * d(u, (x_, 2))) + m_ * (Lb_ * d(u, (x_, 2)) + d(w, (x_, 2))))
    line2 = (b1_ * Lb_ * (d(u, (x_, 2)) - Lb_ * w) + b2_ * (d(w, (x_, 2)) + Lb_ * d(u, (x_, 2)))
             + m_ * (Lb_ * w - d(u, (x_, 2))))
    # euler_equations returns dL/dq - (dL/dq')' + (dL/dq'')'' = 0: fixed factors 2 and -2.
    assert sp.simplify(eq_u.doit() - 2 * line1.doit()) == 0
    assert sp.simplify(eq_w.doit() + 2 * line2.doit()) == 0


def _printed_3_4(d, b1, b2, Lb, M):
    """Residuals of (3.4) exactly as printed, with derivatives d[('u', k)], d[('w', k)]."""
    r1 = (b1 * (d["u", 4] - Lb * d["w", 3]) - b2 * Lb * (d["w", 2] + Lb * d["u", 2])
          + M * Lb * (Lb * d["u", 2] + d["w", 2]))
    r2 = (b1 * Lb * (d["u", 2] - Lb * d["w", 0]) + b2 * (d["w", 3] + Lb * d["u", 3])
          + M * Lb * (Lb * d["w", 0] - d["u", 2]))
    return r1, r2


def test_eq_3_4_as_printed_is_not_satisfied_by_solutions_of_the_el_system():
    """Typo finding: take a solution y(x) = expm(S x) y0 of the EL system (derivatives read off
    y, S y and S^2 y); it zeroes the corrected (3.4) to round-off but not (3.4) as printed (with
    w''' in line 1 and w''', u''' in line 2)."""
    b1, b2, Lb, L_kappa = 1.0, 0.75, 2.0, 7.0
    M = 1 - L_kappa / Lb
    S = arc_system_matrix(L_kappa, Lb, b1, b2)
    y0 = np.array([0.0, 0.0, 1.0, -0.4, 0.0, 0.3])
    worst_correct, worst_printed = 0.0, 0.0
    for x in np.linspace(0.1, 1.0, 7):
        y = expm(S * x) @ y0
        dy, ddy = S @ y, S @ (S @ y)
        d = {("u", 0): y[0], ("u", 2): y[2], ("u", 3): y[3], ("u", 4): dy[3],
             ("w", 0): y[4], ("w", 2): dy[5], ("w", 3): ddy[5]}
        c1 = (b1 * (d["u", 4] - Lb * d["w", 2]) - b2 * Lb * (d["w", 2] + Lb * d["u", 2])
              + M * Lb * (Lb * d["u", 2] + d["w", 2]))
        c2 = (b1 * Lb * (d["u", 2] - Lb * d["w", 0]) + b2 * (d["w", 2] + Lb * d["u", 2])
              + M * Lb * (Lb * d["w", 0] - d["u", 2]))
        worst_correct = max(worst_correct, abs(c1), abs(c2))
        worst_printed = max(worst_printed, *map(abs, _printed_3_4(d, b1, b2, Lb, M)))
    assert worst_correct < 1e-10
    assert worst_printed > 1e-2


def test_eq_3_5_general_solution_solves_el_system_not_printed_3_4():
    """The paper's general solution (3.5) (lambda, q of (3.6)) satisfies the EL equations
    (corrected (3.4)) identically, and does not satisfy (3.4) as printed: further evidence that
    the printed third derivatives are typos."""
    M, c = sp.symbols("M c", real=True)
    lam = sp.sqrt((b1_ - M) * (b2_ - M) / (b1_ * b2_))
    q = (b2_ - M) / b2_
    eq_u, eq_w = _arc_el()
    vals = {b1_: sp.Rational(9, 4), b2_: sp.Rational(7, 8), Lb_: sp.Rational(3, 2),
            M: sp.Rational(-5, 3)}
    for u_sol, w_sol in [
        (c * sp.cos(lam * Lb_ * x_), -Lb_ * c * q * sp.cos(lam * Lb_ * x_)),
        (c * sp.sin(lam * Lb_ * x_), -Lb_ * c * q * sp.sin(lam * Lb_ * x_)),
        (c * sp.cos(Lb_ * x_), -Lb_ * c * sp.cos(Lb_ * x_)),
        (c + 0 * x_, sp.Integer(0) + 0 * x_),
        (c * x_, sp.Integer(0) + 0 * x_),
    ]:
        sub = {u_: u_sol, w_: w_sol, m_: M * Lb_}
        for eq in (eq_u, eq_w):
            res = eq.subs(sub).doit().subs(vals)
            assert sp.simplify(res) == 0
    # The lambda-family violates the printed line 2 (w''' and u''' are odd in x, the rest even).
    u_sol = c * sp.cos(lam * Lb_ * x_)
    w_sol = -Lb_ * c * q * sp.cos(lam * Lb_ * x_)
    d = {("u", k): u_sol.diff(x_, k) for k in range(5)} | {
        ("w", k): w_sol.diff(x_, k) for k in range(4)}
    _, r2 = _printed_3_4(d, b1_, b2_, Lb_, M)
    assert sp.N(r2.subs(vals).subs({c: 1, x_: sp.Rational(1, 5)})) != 0


# --------------------------------------------------------------- the ring: P2 -> eq (3.1)


def test_eq_3_1_ring_system_matrix_is_the_euler_lagrange_system_of_p2():
    """EL equations of the P2 integrand of (2.12) with R = 1,
    b1 (beta' - omega)^2 + b2 (omega' + beta)^2 - M (beta^2 + omega^2 + 2 beta omega'),
    are the paper's (3.1) (printed correctly), and rows 1, 3 of ``ring_system_matrix`` give
    omega'' and beta'' from them."""
    lag = (b1_ * (be_.diff(th_) - om_) ** 2 + b2_ * (om_.diff(th_) + be_) ** 2
           - M_ * (be_**2 + om_**2 + 2 * be_ * om_.diff(th_)))
    eq_om, eq_be = (e.lhs for e in euler_equations(lag, [om_, be_], th_))
    p1 = b2_ * om_.diff(th_, 2) + (M_ - b1_) * om_ + (-M_ + b1_ + b2_) * be_.diff(th_)
    p2 = b1_ * be_.diff(th_, 2) + (M_ - b2_) * be_ - (-M_ + b1_ + b2_) * om_.diff(th_)
    assert sp.simplify(eq_om + 2 * p1) == 0
    assert sp.simplify(eq_be + 2 * p2) == 0
    o2, b2s = sp.symbols("o2 bb2")
    sol = sp.solve([p1.subs({om_.diff(th_, 2): o2}), p2.subs({be_.diff(th_, 2): b2s})],
                   [o2, b2s], dict=True)[0]
    names = sp.symbols("o o1 bb bb1")
    back = {om_.diff(th_): names[1], be_.diff(th_): names[3], om_: names[0], be_: names[2]}
    f_o2 = sp.lambdify((*names, b1_, b2_, M_), sol[o2].xreplace(back))
    f_b2 = sp.lambdify((*names, b1_, b2_, M_), sol[b2s].xreplace(back))
    for _ in range(8):
        b1, b2 = RNG.uniform(0.2, 5.0, 2)
        M = RNG.uniform(-3.0, 3.0)
        y = RNG.normal(size=4)
        dy = ring_system_matrix(M, b1, b2) @ y
        assert dy[0] == y[1] and dy[2] == y[3]
        assert dy[1] == pytest.approx(f_o2(*y, b1, b2, M), rel=1e-12, abs=1e-12)
        assert dy[3] == pytest.approx(f_b2(*y, b1, b2, M), rel=1e-12, abs=1e-12)


@pytest.mark.parametrize("b1, b2, N, j", [(1.0, 0.75, 1, 2), (1.0, 0.75, 3, 4), (1.0, 0.75, 3, 2),
                                          (2.25, 0.88, 2, 3)])
def test_eq_3_3_monodromy_has_extra_periodic_solutions_at_closed_form_eigenvalues(b1, b2, N, j):
    """At M = M^-(j/N) of (3.3) (closed form) the monodromy T - I over 2 pi N has, besides the
    two rigid rotations (frequency 1), the cos/sin pair of mode j (frequency j/N): all four
    singular values vanish (T = I); at a generic M only the two rigid ones do."""
    k = j / N
    M = (b1 + b2) / 2 - math.sqrt((b1 - b2) ** 2 / 4 + b1 * b2 * k * k)
    s = ring_periodicity_measure(M, N, b1, b2)
    assert s.shape == (4,) and s[0] < 1e-9  # 4x4 system: T = I, every solution is periodic
    s = ring_periodicity_measure(M + 0.05, N, b1, b2)
    assert s[-RING_RIGID_NULLITY] < 1e-9 and s[-RING_RIGID_NULLITY - 1] > 1e-3


# ------------------------------------------------------------------ shooting matrix properties


@pytest.mark.parametrize("aspect", [0.75, 1.0, 3.0])
@pytest.mark.parametrize("Lb", [0.0, 1.0, 4.0])
def test_sec_2_2_stress_free_state_is_not_critical(aspect, Lb):
    """Paper Sec. 2.2: at M = 0 (L kappa_n = L/R) P2 > 0 for every admissible variation that is
    not a rigid motion, and clamping removes the rigid motions: the shooting matrix is regular."""
    s = rectangle(aspect=aspect)
    sv = np.linalg.svd(clamped_arc_matrix(Lb, Lb, s.b1, s.b2), compute_uv=False)
    assert sv[-1] / sv[0] > 1e-3


@pytest.mark.parametrize("Lb", [0.5, 3.0])
def test_clamped_arc_mode_satisfies_clamped_end_conditions(Lb):
    """At a critical load (upper end from ``clamped_arc_stability``) the propagated mode satisfies
    u = u' = omega = 0 at both ends (x = 0 and x = 1), and is normalised to max |u| = 1."""
    s = circle()
    p_crit = clamped_arc_stability(s.b1, s.b2, Lb).L_kappa_interval[1]
    x, u, w = clamped_arc_mode(p_crit, Lb, s.b1, s.b2, n_points=401)
    h = x[1] - x[0]
    assert np.max(np.abs(u)) == pytest.approx(1.0, rel=1e-14)
    # second-order one-sided differences for u'(0), u'(1): error O(h^2) ~ 1e-5
    du0 = (-3 * u[0] + 4 * u[1] - u[2]) / (2 * h)
    du1 = (3 * u[-1] - 4 * u[-2] + u[-3]) / (2 * h)
    for end in (0, -1):
        assert abs(u[end]) < 1e-8 and abs(w[end]) < 1e-8 * np.max(np.abs(w))
    assert abs(du0) < 1e-3 and abs(du1) < 1e-3


def test_shooting_matrix_has_no_root_where_high_precision_determinant_is_large():
    """Rectangle h/t = 10, L/R = 4, L kappa_n in [-180, -175]: neither (3.7) nor (3.8) has a root
    there, and the shooting determinant evaluated with 40-digit mpmath keeps one sign and varies
    by less than 10 % across the window (no zero, touching or not): no critical load lies here."""
    mp = pytest.importorskip("mpmath")
    from rodstab.analytic.arc import antisymmetric_function, symmetric_function
    from rodstab.numerics import find_roots

    s = rectangle(aspect=10.0)
    Lb = 4.0
    mp.mp.dps = 40
    dets = []
    for p in np.linspace(-180.0, -175.0, 6):
        T = mp.expm(mp.matrix(arc_system_matrix(float(p), Lb, s.b1, s.b2).tolist()))
        dets.append(mp.det(mp.matrix([[T[a, b] for b in (2, 3, 5)] for a in (0, 1, 4)])))
    assert all(d > 0 for d in dets) and max(dets) < 1.1 * min(dets)
    for fun in (symmetric_function, antisymmetric_function):
        assert find_roots(lambda p, fun=fun: fun(1 - p / Lb, Lb, s.b1, s.b2), -180.0,
                          -175.0).roots == ()
    found = matrix_roots(lambda p: clamped_arc_matrix(p, Lb, s.b1, s.b2), -180.0, -175.0,
                         n_scan=50)
    assert found.roots == ()


def test_straight_limit_system_is_the_clamped_column():
    """At L/R = 0 the system reduces to w'' = -(L kappa_n / b2) u'' and
    u'''' = -(L kappa_n)^2 / (b1 b2) u'' (the column equation with lambda = L kappa_n /
    sqrt(b1 b2)); read off directly from the EL equations with Lbar = 0, m = -L kappa_n."""
    b1, b2, p = 2.0, 0.7, 3.3
    S = arc_system_matrix(p, 0.0, b1, b2)
    assert S[5, 2] == pytest.approx(-p / b2, rel=1e-15)
    assert S[3, 2] == pytest.approx(-p * p / (b1 * b2), rel=1e-15)
    assert S[5, 4] == 0 and S[3, 4] == 0
    assert math.isclose(np.abs(S[[3, 5]][:, [0, 1, 3, 5]]).max(), 0.0)
