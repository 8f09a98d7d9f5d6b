"""Validation of ``rodstab.kinematics`` against Section 2 of the paper (eqs. 2.1-2.12, 4.1).

Oracles: closed-form identities, an independent numerical evaluation of (2.7) in lab Cartesian
coordinates, a displacement field built by integrating the tangent, and sympy Taylor expansions
(sympy is a test-only dependency).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from rodstab import kinematics as kin
from rodstab.errors import RodstabInputError

sp = pytest.importorskip("sympy")

#: Tolerance of an order measurement (findiff convention: observed = expected +- 0.2).
ORDER_TOL = 0.2
#: Step of the 4th-order central differences along s; truncation ~h^4 and round-off ~1e-16/h
#: both stay below 1e-11.
FD_STEP = 1e-3

RNG = np.random.default_rng(20240601)


def _fd4(f, s, h=FD_STEP):
    """Fourth-order central difference of ``f`` (array-valued, leading axis = s) at ``s``."""
    return (f(s - 2 * h) - 8 * f(s - h) + 8 * f(s + h) - f(s + 2 * h)) / (12 * h)


def _large_state(s):
    """O(1) smooth Euler angles (a genuinely nonlinear state) and their exact s-derivatives."""
    a = 0.9 * np.sin(1.3 * s + 0.4) + 0.3
    b = 0.7 * np.cos(0.8 * s) - 0.2 * s
    g = 1.1 * np.sin(0.6 * s - 1.0) + 0.5 * np.cos(2.1 * s)
    da = 0.9 * 1.3 * np.cos(1.3 * s + 0.4)
    db = -0.7 * 0.8 * np.sin(0.8 * s) - 0.2
    dg = 1.1 * 0.6 * np.cos(0.6 * s - 1.0) - 0.5 * 2.1 * np.sin(2.1 * s)
    return a, b, g, da, db, dg


def _lab_frame(s, R):
    """Rows e_i in lab Cartesian components: (2.1) times the reference basis at theta = s/R."""
    a, b, g = _large_state(s)[:3]
    f = kin.frame(a, b, g)
    if math.isinf(R):
        return f  # straight reference: (i_r, i_theta, i_3) fixed, = lab axes
    return f @ kin.reference_basis(s / R)


# --------------------------------------------------------------------------- eq. (2.1) frame


def test_eq_2_1_frame_is_proper_rotation_for_random_angles():
    """(2.1): rows e_i are orthonormal and right-handed (det +1) for arbitrary angles."""
    a, b, g = RNG.uniform(-np.pi, np.pi, (3, 200))
    f = kin.frame(a, b, g)
    assert f.shape == (200, 3, 3)
    np.testing.assert_allclose(f @ np.swapaxes(f, -1, -2), np.broadcast_to(np.eye(3), f.shape),
                               atol=1e-14)
    np.testing.assert_allclose(np.linalg.det(f), 1.0, atol=1e-14)
    np.testing.assert_allclose(np.cross(f[:, 0], f[:, 1]), f[:, 2], atol=1e-14)


def test_eq_2_1_frame_is_identity_at_zero_angles_and_vectorised():
    """(2.1): e_i = (i_r, i_theta, i_3) in the reference state; shapes broadcast."""
    np.testing.assert_array_equal(kin.frame(0.0, 0.0, 0.0), np.eye(3))
    assert kin.frame(np.zeros((4, 5)), 0.1, np.zeros(5)).shape == (4, 5, 3, 3)


def test_eq_2_4_2_5_e2_is_the_tangent():
    """(2.4)-(2.5): e2 of (2.1) equals (-phi_3, 1 + eps_theta, phi_r) in reference components."""
    a, b, g = RNG.uniform(-np.pi, np.pi, (3, 100))
    eps_t, phi_r, phi_3 = kin.axis_strains(b, g)
    np.testing.assert_allclose(kin.frame(a, b, g)[:, 1],
                               np.stack([-phi_3, 1 + eps_t, phi_r], -1), atol=1e-15)
    # (2.3): inextensibility, and (2.6): tan gamma = -phi_3 / phi_r
    np.testing.assert_allclose(eps_t, np.sqrt(1 - phi_r**2 - phi_3**2) * np.sign(np.cos(b)) - 1,
                               atol=1e-14)
    np.testing.assert_allclose(np.tan(g), -phi_3 / phi_r, rtol=1e-9)


def test_eq_2_5_and_2_11_signs_from_an_integrated_displacement_field():
    """(2.4), (2.5) from displacements; shows the sign slip in the middle member of (2.11).

    Method: the deformed centreline r(s) = R i_r(0) + int_0^s e2 ds' (Gauss-Legendre, 40 nodes),
    u = r - R i_r(s/R), components on the rotating reference basis, derivatives by 4th-order
    central differences. Then du_theta/ds + u_r/R = cos(beta) - 1, du_3/ds = sin(beta) cos(gamma)
    and du_r/ds - u_theta/R = +sin(beta) sin(gamma) = -phi_3 as (2.5) defines. For small angles
    this is +beta*gamma; (2.11) prints "phi_3 = (du_r/ds - R^-1 u_theta) = -beta gamma", whose
    middle member lacks the minus sign of (2.5) (phi_3 = -beta gamma itself is right).
    """
    R = 1.7
    x, w = np.polynomial.legendre.leggauss(40)

    def u_ref_components(s):
        s = np.asarray(s)
        nodes = 0.5 * s[..., None] * (x + 1)
        e2_lab = _lab_frame(nodes, R)[..., 1, :]
        r = np.array([R, 0.0, 0.0]) + np.einsum("...n,...nc->...c", 0.5 * s[..., None] * w, e2_lab)
        basis = kin.reference_basis(s / R)
        u = r - R * basis[..., 0, :]
        return np.einsum("...ic,...c->...i", basis, u)  # (u_r, u_theta, u_3)

    s = np.linspace(0.2, 3.0, 15)
    u = u_ref_components(s)
    du = _fd4(u_ref_components, s)
    _, b, g = _large_state(s)[:3]
    np.testing.assert_allclose(du[:, 1] + u[:, 0] / R, np.cos(b) - 1, atol=1e-10)  # (2.4)
    np.testing.assert_allclose(du[:, 2], np.sin(b) * np.cos(g), atol=1e-10)  # (2.5) phi_r
    np.testing.assert_allclose(du[:, 0] - u[:, 1] / R, np.sin(b) * np.sin(g), atol=1e-10)
    _, _, phi_3 = kin.axis_strains(b, g)
    np.testing.assert_allclose(phi_3, -(du[:, 0] - u[:, 1] / R), atol=1e-10)  # (2.5), not (2.11)


# ------------------------------------------------------------------ eq. (2.7) vs (2.8), (4.1)


@pytest.mark.parametrize("R", [1.7, 0.6, math.inf])
def test_eq_2_8_agrees_with_frenet_formula_2_7_by_finite_differences(R):
    """(2.8) = (2.7) kappa_i = 1/2 eps_ijk (de_j/ds).e_k, evaluated numerically.

    Method (independent of (2.8)): the lab-frame rows e_i(s) = frame(2.1) @ reference_basis(s/R)
    (i_r, i_theta rotate with theta = s/R; fixed for R = inf), de_j/ds by 4th-order central
    differences, contracted with the Levi-Civita symbol. O(1) angles, so the check is of the exact
    nonlinear formula.
    """
    s = np.linspace(0.0, 4.0, 41)
    e = _lab_frame(s, R)
    de = _fd4(lambda t: _lab_frame(t, R), s)
    levi = np.zeros((3, 3, 3))
    for i, j, k in [(0, 1, 2), (1, 2, 0), (2, 0, 1)]:
        levi[i, j, k], levi[i, k, j] = 1.0, -1.0
    kappa_27 = 0.5 * np.einsum("ijk,njc,nkc->ni", levi, de, e)
    np.testing.assert_allclose(kin.curvatures(*_large_state(s), R=R), kappa_27, atol=1e-9)


def test_eq_4_1_is_the_straight_limit_of_eq_2_8():
    """(4.1): (2.8) with R = inf is (4.1) exactly, and R -> inf is continuous."""
    a, b, g, da, db, dg = _large_state(np.linspace(0, 3, 31))
    eq41 = np.stack([np.cos(a) * db + np.sin(a) * np.sin(b) * dg,
                     da + np.cos(b) * dg,
                     np.sin(a) * db - np.cos(a) * np.sin(b) * dg], -1)
    np.testing.assert_allclose(kin.curvatures(a, b, g, da, db, dg, R=math.inf), eq41, atol=1e-15)
    np.testing.assert_allclose(kin.curvatures(a, b, g, da, db, dg, R=1e9), eq41, atol=1e-8)


def test_reference_state_curvature_and_energy():
    """Below (2.9): reference curvatures (0, 0, 1/R), SE0 density B3 (1/R - kappa_n)^2 / 2."""
    R, kn, B3 = 1.3, 0.4, 2.0
    kap = kin.curvatures(0, 0, 0, 0, 0, 0, R=R)
    np.testing.assert_allclose(kap, [0, 0, 1 / R])
    M = 1 - R * kn
    se0 = kin.strain_energy_density(kap, kn, 1.0, 1.0, B3)
    assert se0 == pytest.approx(0.5 * B3 * (M / R) ** 2)


# ----------------------------------------------------------------------- sympy expansions

S, EPS, RHO, KN, B1, B2, B3 = sp.symbols("s epsilon rho kappa_n B1 B2 B3", real=True)
ALPHA, BETA, GAMMA = (sp.Function(n)(S) for n in ("alpha", "beta", "gamma"))


def _kappa_28(a, b, g, rho):
    """(2.8) in sympy, with rho = 1/R."""
    da, db, dg = a.diff(S), b.diff(S), g.diff(S)
    p = db - rho * sp.sin(g)
    q = -sp.sin(b) * dg + rho * sp.cos(b) * sp.cos(g)
    return [sp.cos(a) * p - sp.sin(a) * q,
            da + sp.cos(b) * dg + rho * sp.sin(b) * sp.cos(g),
            sp.cos(a) * q + sp.sin(a) * p]


def _kappa_210(a, b, g, rho):
    """(2.10) as printed, in sympy, with omega = alpha + gamma."""
    w = a + g
    return [b.diff(S) - rho * w,
            w.diff(S) + rho * b,
            rho * (1 - w**2 / 2 - b**2 / 2) - b * w.diff(S) + (a * b).diff(S)]


def _taylor(expr, n):
    """Coefficient of eps^n of expr(eps)."""
    return sp.expand(sp.diff(expr, EPS, n).subs(EPS, 0) / sp.factorial(n))


@pytest.fixture(scope="module")
def expansions():
    """Taylor coefficients (orders 0..4) in eps of (2.8) and (2.9), alpha -> eps*alpha etc."""
    kap = _kappa_28(EPS * ALPHA, EPS * BETA, EPS * GAMMA, RHO)
    kap_coeffs = [[_taylor(k, n) for n in range(5)] for k in kap]
    dens = sp.Rational(1, 2) * (B1 * kap[0] ** 2 + B2 * kap[1] ** 2 + B3 * (kap[2] - KN) ** 2)
    energy_coeffs = [_taylor(dens, n) for n in range(5)]
    return kap_coeffs, energy_coeffs


def _lowest_nonzero_order(coeffs, start):
    return next(n for n in range(start, len(coeffs)) if sp.simplify(coeffs[n]) != 0)


def test_eq_2_10_quadratic_expansion_agrees_term_by_term(expansions):
    """(2.10): sympy Taylor expansion of (2.8) to second order equals the printed (2.10).

    Method: alpha, beta, gamma -> eps*alpha(s), ... ; coefficients of eps^0, eps^1, eps^2 of each
    curvature compared with those of the printed (2.10). Also the numpy implementation of (2.10)
    is compared with the lambdified sympy series at random values.
    """
    kap_coeffs, _ = expansions
    printed = _kappa_210(EPS * ALPHA, EPS * BETA, EPS * GAMMA, RHO)
    for i in range(3):
        for n in range(3):
            assert sp.simplify(kap_coeffs[i][n] - _taylor(printed[i], n)) == 0, (i + 1, n)
    # numeric: curvatures_second_order == sum_{n<=2} eps^n coeff_n (eps = 1)
    d = sp.symbols("a b g da db dg")
    subs = {ALPHA.diff(S): d[3], BETA.diff(S): d[4], GAMMA.diff(S): d[5]}
    subs2 = {ALPHA: d[0], BETA: d[1], GAMMA: d[2]}
    series = [sum(kap_coeffs[i][:3]).subs(subs).subs(subs2) for i in range(3)]
    f = sp.lambdify([*d, RHO], series, "numpy")
    vals = RNG.normal(size=(6, 20))
    R = 1.9
    np.testing.assert_allclose(kin.curvatures_second_order(*vals, R=R),
                               np.stack(f(*vals, 1 / R), -1), atol=1e-13)


def test_eq_2_10_truncation_orders_claimed_are_true(expansions):
    """(2.10) claims O3 for kappa1, kappa2 (no quadratic terms) and O4 for kappa3 (no cubic terms).

    sympy: kappa1, kappa2 are odd in (alpha, beta, gamma) and kappa3 even, so the claims hold.
    They are sharp: the cubic terms of kappa1, kappa2 (asserted below) are non-zero, the quartic
    of kappa3 is non-zero. The cubic terms do not enter the second variation.
    """
    kap_coeffs, _ = expansions
    a, b, g = ALPHA, BETA, GAMMA
    w = a + g
    assert kap_coeffs[0][2] == 0 and kap_coeffs[1][2] == 0
    assert kap_coeffs[2][1] == 0 and kap_coeffs[2][3] == 0
    cubic1 = -a**2 * b.diff(S) / 2 + a * b * g.diff(S) + RHO * (w**3 / 6 + a * b**2 / 2)
    cubic2 = -b**2 * g.diff(S) / 2 - RHO * (b**3 / 6 + b * g**2 / 2)
    assert sp.expand(kap_coeffs[0][3] - cubic1) == 0
    assert sp.expand(kap_coeffs[1][3] - cubic2) == 0
    assert kap_coeffs[2][4] != 0


def test_eq_2_12_quadratic_energy_and_corrected_end_term(expansions):
    """(2.12): quadratic part of (2.9) with (2.8) equals P2's integrand plus an exact derivative.

    Method (sympy, rho = 1/R and kappa_n independent, M/R = rho - kappa_n, so the straight
    state rho = 0 is included): c2 = eps^2 coefficient of the density. c2 - (integrand of P2) is a
    null Lagrangian (its Euler-Lagrange expressions vanish) equal to C d/ds(B3 (M/R) alpha beta)
    with C solved for: C = 1. The paper prints "+ 2 B3 M alpha beta / R |_0^L" outside the 1/2,
    i.e. C = 2, which is wrong (harmless for rings and clamped arcs, where alpha beta|_0^L = 0).
    Inextensibility needs no multiplier: it is built into the Euler angles. Also: eps^1 and eps^3
    coefficients vanish (equilibrium; no cubic terms, by parity), the eps^4 one does not.
    """
    _, c = expansions
    a, b, g = ALPHA, BETA, GAMMA
    w = a + g
    m_over_r = RHO - KN  # = M / R
    p2_integrand = sp.Rational(1, 2) * (
        B1 * (b.diff(S) - RHO * w) ** 2 + B2 * (w.diff(S) + RHO * b) ** 2
        - B3 * m_over_r * (RHO * b**2 + RHO * w**2 + 2 * b * w.diff(S)))
    assert sp.simplify(c[0] - B3 * m_over_r**2 / 2) == 0  # SE0 density
    assert c[1] == 0 and c[3] == 0 and c[4] != 0
    rest = sp.expand(c[2] - p2_integrand)
    el = sp.euler_equations(rest, [a, b, g], S)
    assert all(sp.simplify(eq.lhs - eq.rhs) == 0 for eq in el)  # exact derivative
    C = sp.Symbol("C")
    sol = sp.solve(sp.Poly(sp.expand(rest - C * sp.diff(B3 * m_over_r * a * b, S)),
                           a, b, a.diff(S), b.diff(S)).coeffs(), C)
    assert sol == {C: 1}
    # numpy p2_density + d/ds p2_boundary_term == c2 at random values, circular and straight
    d = sp.symbols("a b g da db dg")
    subs = {a.diff(S): d[3], b.diff(S): d[4], g.diff(S): d[5]}
    f = sp.lambdify([*d, RHO, KN, B1, B2, B3],
                    c[2].subs(subs).subs({a: d[0], b: d[1], g: d[2]}), "numpy")
    av, bv, gv, dav, dbv, dgv = RNG.normal(size=(6, 20))
    for R, kn in [(1.4, 0.3), (math.inf, 0.8)]:
        kw = dict(R=R, B1=1.5, B2=0.7, B3=1.2, kappa_n=kn)
        p2 = kin.p2_density(bv, dbv, av + gv, dav + dgv, **kw)
        # d/ds of the end term B3 (M/R) alpha beta, by the product rule
        unit = kin.p2_boundary_term(1.0, 1.0, R=R, B3=1.2, kappa_n=kn)
        np.testing.assert_allclose(p2 + unit * (dav * bv + av * dbv),
                                   f(av, bv, gv, dav, dbv, dgv, 1 / R, kn, 1.5, 0.7, 1.2),
                                   atol=1e-12)


def test_section_2_2_uniform_axisymmetric_twist_integrand():
    """End of Section 2.2: for omega = const, beta = 0 the braces of P2 are (b1 - M) omega^2 B3/R^2.

    p2_density includes the factor 1/2 of (2.12), so it equals half the paper's "integrand".
    """
    B1_, B2_, B3_, R, M = 1.6, 0.7, 2.0, 1.3, 0.45
    omega = np.linspace(-0.3, 0.3, 7)
    p2 = kin.p2_density(0.0, 0.0, omega, 0.0, R=R, B1=B1_, B2=B2_, B3=B3_, M=M)
    np.testing.assert_allclose(2 * p2, (B1_ / B3_ - M) * omega**2 * B3_ / R**2, rtol=1e-14)


def test_p2_density_M_and_kappa_n_forms_agree():
    """(2.12): M = 1 - R kappa_n; giving M or kappa_n is the same density."""
    R, kn = 1.3, 0.25
    args = RNG.normal(size=(4, 5))
    kw = dict(R=R, B1=1.0, B2=0.8, B3=1.1)
    np.testing.assert_allclose(kin.p2_density(*args, **kw, M=1 - R * kn),
                               kin.p2_density(*args, **kw, kappa_n=kn), rtol=1e-14)


# ------------------------------------------------------------------- measured orders


@pytest.mark.parametrize("seed, R", [(0, 1.3), (1, 0.7), (2, math.inf)])
def test_remainder_orders_agree_with_sympy(expansions, seed, R):
    """remainder_orders(): measured log-log slopes of |kappa(2.8) - kappa(2.10)| vs eps agree
    (+-0.2) with the lowest non-vanishing order of the sympy remainder (3, 3, 4)."""
    kap_coeffs, _ = expansions
    expected = {f"kappa{i + 1}": _lowest_nonzero_order(kap_coeffs[i], 3) for i in range(3)}
    assert expected == {"kappa1": 3, "kappa2": 3, "kappa3": 4}
    measured = kin.remainder_orders(seed, R=R)
    for key, order in expected.items():
        assert measured[key] == pytest.approx(order, abs=ORDER_TOL), (key, measured)


@pytest.mark.parametrize("seed, M", [(0, 0.4), (3, -0.8)])
def test_energy_remainder_order_agrees_with_sympy(expansions, seed, M):
    """energy_remainder_order(): |SE - SE0 - P2| = O(eps^4) for a generic non-symmetric state with
    M != 0 and the corrected end term (sympy: lowest non-zero order >= 3 is 4); with the end term
    as printed (factor 2) the error is O(eps^2)."""
    _, c = expansions
    assert _lowest_nonzero_order(c, 3) == 4
    measured = kin.energy_remainder_order(seed, M=M)
    assert measured["energy"] == pytest.approx(4, abs=ORDER_TOL)
    assert measured["energy_printed_end_term"] == pytest.approx(2, abs=ORDER_TOL)


# ------------------------------------------------------------------------ bad input


@pytest.mark.parametrize(
    "call, name",
    [
        (lambda: kin.curvatures(0, 0, 0, 0, 0, 0, R=0.0), "R"),
        (lambda: kin.curvatures(0, 0, 0, 0, 0, 0, R=-1.0), "R"),
        (lambda: kin.curvatures(0, 0, 0, 0, 0, 0, R=-math.inf), "R"),
        (lambda: kin.curvatures_second_order(0, 0, 0, 0, 0, 0, R=math.nan), "R"),
        (lambda: kin.strain_energy_density([0, 0, 1], 0.1, 0.0, 1.0, 1.0), "B1"),
        (lambda: kin.strain_energy_density([0, 0], 0.1, 1.0, 1.0, 1.0), "kappa"),
        (lambda: kin.strain_energy_density([0, 0, 1], math.nan, 1.0, 1.0, 1.0), "kappa_n"),
        (lambda: kin.p2_density(0, 0, 0, 0, R=1.0, B1=1, B2=1, B3=1), "M"),
        (lambda: kin.p2_density(0, 0, 0, 0, R=1.0, B1=1, B2=1, B3=1, M=0.1, kappa_n=0.2), "M"),
        (lambda: kin.p2_density(0, 0, 0, 0, R=math.inf, B1=1, B2=1, B3=1, M=0.1), "M"),
        (lambda: kin.p2_density(0, 0, 0, 0, R=1.0, B1=1, B2=-1, B3=1, M=0.1), "B2"),
        (lambda: kin.p2_boundary_term(0, 0, R=1.0, B3=0, M=0.1), "B3"),
        (lambda: kin.energy_remainder_order(R=math.inf), "R"),
    ],
)
def test_bad_input_raises_naming_the_parameter(call, name):
    with pytest.raises(RodstabInputError, match=name):
        call()
