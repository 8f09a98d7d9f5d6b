"""Tests of ``rodstab.numerics`` (the one root finder and the one eigen solver).

Oracles: a catalogue of functions and matrix families whose roots and multiplicities are known in
closed form (scipy's ``_zeros`` test-catalogue habit), closed-form generalized eigenvalues of 2x2
and 3x3 pencils, and, for random pencils, a direct check with ``numpy.linalg.eigvalsh`` that
``A - p C`` is positive definite inside the reported interval and singular at its ends.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from rodstab.numerics import (
    SUBSCAN,
    XTOL,
    find_roots,
    golden_min,
    matrix_roots,
    pencil_interval,
    pencil_interval_sparse,
    sigma_min_2x2,
)

#: Accuracy asked of a refined simple root (Brent to XTOL * span, with margin for round-off).
ROOT_ATOL = 1e-12
#: A root of multiplicity m is only determined to about eps**(1/m); (x-a)^2 etc. are exact at a.
MULTI_ROOT_ATOL = 1e-6

PROPERTY = settings(derandomize=True, max_examples=60, deadline=None, database=None)


def _assert_roots(search, expected):
    """``expected`` = [(x, multiplicity), ...]; assert same count, places and multiplicities."""
    got = [(r.x, r.multiplicity) for r in search.roots]
    assert len(got) == len(expected), f"got {got}, expected {expected}"
    for (x, m), (x0, m0) in zip(got, expected, strict=True):
        tol = ROOT_ATOL if m0 == 1 else MULTI_ROOT_ATOL
        assert abs(x - x0) <= tol * max(1.0, abs(x0)), (got, expected)
        assert m == m0, (got, expected)


# ----------------------------------------------------------------------- find_roots catalogue
# Intervals are chosen so that no root falls on a scan grid point (those are tested separately).

CATALOGUE = [
    # id, f, lo, hi, n_scan, [(root, multiplicity)]
    ("sin", math.sin, 0.5, 10.0, 400,
     [(math.pi, 1), (2 * math.pi, 1), (3 * math.pi, 1)]),
    ("tan_roots_not_poles", math.tan, 0.5, 10.0, 400,
     [(math.pi, 1), (2 * math.pi, 1), (3 * math.pi, 1)]),
    ("double_touching", lambda x: (x - 1.0) ** 2, 0.0, 3.0, 400, [(1.0, 2)]),
    ("quadruple_touching", lambda x: (x - 2.0) ** 4, 0.0, 3.0, 400, [(2.0, 4)]),
    ("triple_sign_change", lambda x: (x - 2.0) ** 3, -1.0, 5.3, 400, [(2.0, 3)]),
    ("quintuple_sign_change", lambda x: (x - 2.0) ** 5, 0.1, 3.1, 400, [(2.0, 5)]),
    ("double_and_simple", lambda x: (x - 2.0) ** 2 * math.sin(x), 0.5, 10.3, 400,
     [(2.0, 2), (math.pi, 1), (2 * math.pi, 1), (3 * math.pi, 1)]),
    # spacing h = 0.1, separation 0.01: closer than h but more than h/SUBSCAN = 0.00625
    ("close_pair_inside_one_interval", lambda x: (x - 1.03) * (x - 1.04), 0.0, 10.0, 100,
     [(1.03, 1), (1.04, 1)]),
    ("close_pair_straddling_grid", lambda x: (x - 0.995) * (x - 1.005), 0.0, 10.0, 100,
     [(0.995, 1), (1.005, 1)]),
    ("pole_is_not_a_root", lambda x: 1.0 / (x - 3.0), 0.0, 5.3, 400, []),
    ("root_and_pole", lambda x: (x - 1.0) / (x - 3.0), 0.0, 5.3, 400, [(1.0, 1)]),
    ("no_root", lambda x: 2.0 + math.cos(x), 0.0, 10.0, 400, []),
]


@pytest.mark.parametrize("f, lo, hi, n_scan, expected",
                         [c[1:] for c in CATALOGUE], ids=[c[0] for c in CATALOGUE])
def test_find_roots_catalogue_known_roots_and_multiplicities(f, lo, hi, n_scan, expected):
    """Catalogue of closed-form roots: sin/tan (k pi, tan poles excluded), (x-a)^m (order m),
    pairs closer than one scan spacing, poles (1/(x-3)) that change sign but are not roots."""
    _assert_roots(find_roots(f, lo, hi, n_scan=n_scan), expected)


def test_find_roots_kinds_and_residuals():
    """A sign change is refined by Brent (kind 'sign-change', |f| ~ eps); an even-order root is
    found as a minimum of |f| (kind 'touching'); the residual stored is |f(x)| at the root."""
    res = find_roots(lambda x: (x - 2.0) ** 2 * math.sin(x), 0.5, 10.3)
    kinds = [r.kind for r in res.roots]
    assert kinds == ["touching", "sign-change", "sign-change", "sign-change"]
    for r in res.roots:
        f = (r.x - 2.0) ** 2 * math.sin(r.x)
        assert r.residual == pytest.approx(abs(f), abs=1e-300)
        assert r.residual < 1e-11
        assert r.bracket[0] <= r.x <= r.bracket[1]
    assert res.converged and res.n_scan == 400 and res.interval == (0.5, 10.3)


@PROPERTY
@given(
    k=st.integers(min_value=2, max_value=95),
    frac=st.floats(min_value=0.0, max_value=0.999),
    sep_over_h=st.floats(min_value=1.02 / SUBSCAN, max_value=2.0),
)
def test_find_roots_never_misses_a_pair_separated_by_more_than_h_over_subscan(k, frac, sep_over_h):
    """Module guarantee: two simple roots separated by more than h/SUBSCAN are both found
    (h = scan spacing). Roots c and c + s of (x - c)(x - c - s), both off the scan grid."""
    h = 0.1
    c = (k + frac) * h
    d = c + sep_over_h * h
    # Roots exactly on a scan point or on a point of the local re-scan (spacing h/SUBSCAN from
    # the grid) are a separate case: see the grid-point tests below.
    for r in (c, d):
        assume(abs(r * SUBSCAN / h - round(r * SUBSCAN / h)) > 1e-6)
    res = find_roots(lambda x: (x - c) * (x - d), 0.0, 10.0, n_scan=100)
    assert [m.multiplicity for m in res.roots] == [1, 1]
    np.testing.assert_allclose(res.values, [c, d], rtol=0, atol=ROOT_ATOL)


def test_find_roots_simple_roots_on_grid_points():
    """x (x-1)(x-2)(x-3) on [0, 3] with n_scan = 6: every root is a grid point where f is exactly
    0 in floating point; each is reported once, as a simple root."""
    res = find_roots(lambda x: x * (x - 1) * (x - 2) * (x - 3), 0.0, 3.0, n_scan=6)
    _assert_roots(res, [(0.0, 1), (1.0, 1), (2.0, 1), (3.0, 1)])
    assert {r.kind for r in res.roots} == {"grid-point"}


@pytest.mark.parametrize("f, lo, hi, root, m", [
    (lambda x: (x - 1.0) ** 2, 0.0, 2.0, 1.0, 2),   # 1.0 = linspace(0, 2, 401)[200]
    (lambda x: (x - 2.0) ** 3, 0.0, 4.0, 2.0, 3),   # 2.0 = linspace(0, 4, 401)[200]
], ids=["double", "triple"])
def test_find_roots_multiple_root_on_a_grid_point_has_its_multiplicity(f, lo, hi, root, m):
    """(x - a)^m with a on the scan grid: the root's multiplicity is m (closed form)."""
    _assert_roots(find_roots(f, lo, hi), [(root, m)])


@pytest.mark.parametrize("a, b", [(9.5, 9.51), (9.49, 9.5), (1.0, 1.05), (0.25, 0.275)],
                         ids=["grid_then_close", "close_then_grid", "grid_half_h", "subgrid"])
def test_find_roots_close_pair_with_one_root_on_a_grid_point(a, b):
    """(x - a)(x - b), h = 0.1, |a - b| > h/SUBSCAN, one root exactly on a scan point (or, for
    0.25, on a point of the local re-scan 0.2 + k h/16): both roots are found (module docstring:
    'a pair of simple roots closer than that is still found when it is separated by more than
    h / SUBSCAN')."""
    _assert_roots(find_roots(lambda x: (x - a) * (x - b), 0.0, 10.0, n_scan=100),
                  [(a, 1), (b, 1)])


@pytest.mark.parametrize("f, lo, hi, expected", [
    (lambda x: (x - 2.0) ** 3, 0.0, 3.0, [(2.0, 3)]),
    (lambda x: math.sin(x) ** 3, 0.5, 10.0, [(math.pi, 3), (2 * math.pi, 3), (3 * math.pi, 3)]),
], ids=["cube", "sin_cubed"])
def test_find_roots_triple_root_does_not_crash(f, lo, hi, expected):
    """(x-2)^3 and sin^3: roots of order 3 at 2 and k pi (closed form)."""
    _assert_roots(find_roots(f, lo, hi), expected)


@pytest.mark.parametrize("lo, hi", [(1.0, 1.0), (2.0, 1.0), (0.0, math.inf), (math.nan, 1.0)])
def test_find_roots_rejects_bad_interval(lo, hi):
    """Bad intervals raise ValueError naming lo and hi."""
    with pytest.raises(ValueError, match="lo"):
        find_roots(math.sin, lo, hi)
    with pytest.raises(ValueError, match="lo"):
        matrix_roots(lambda x: np.eye(2) * math.sin(x), lo, hi)


def test_golden_min_finds_v_shaped_minimum():
    """|x - 0.3| on [0, 1] (a kink, where parabolic steps stall) and a smooth parabola."""
    x, g = golden_min(lambda t: abs(t - 0.3), 0.0, 1.0, 1e-12)
    assert x == pytest.approx(0.3, abs=1e-11) and g < 1e-11
    x, g = golden_min(lambda t: (t - 0.7) ** 2 + 1.0, 0.0, 1.0, 1e-12)
    assert x == pytest.approx(0.7, abs=1e-6) and g == pytest.approx(1.0, abs=1e-12)


# ---------------------------------------------------------------------- matrix_roots catalogue

MATRIX_CATALOGUE = [
    # id, A(x), lo, hi, n_scan, [(root, nullity)]
    ("diag_simple_roots", lambda x: np.diag([x - 1.0, x - 3.0]), 0.03, 5.3, 400,
     [(1.0, 1), (3.0, 1)]),
    ("coupled_2x2", lambda x: np.array([[x - 2.0, 1.0], [1.0, x - 2.0]]), 0.03, 5.3, 400,
     [(1.0, 1), (3.0, 1)]),  # eigenvalues 2 -+ 1
    ("double_root_nullity_2", lambda x: np.diag([x - 1.0, x - 1.0, 1.0]), 0.0, 3.0, 400,
     [(1.0, 2)]),  # det (x-1)^2 touches zero, two zero singular values
    ("touching_det_nullity_1", lambda x: np.diag([(x - 1.0) ** 2, 1.0]), 0.0, 3.0, 400,
     [(1.0, 1)]),
    ("jordan_block_nullity_1", lambda x: np.array([[x - 1.0, 1e-3], [0.0, x - 1.0]]), 0.0, 3.0,
     400, [(1.0, 1)]),  # det (x-1)^2 but the null space is one-dimensional
    ("close_pair", lambda x: np.diag([x - 1.03, x - 1.04]), 0.0, 10.0, 100,
     [(1.03, 1), (1.04, 1)]),
    ("simple_roots_on_grid", lambda x: np.diag([x - 1.0, x - 3.0]), 0.0, 5.0, 400,
     [(1.0, 1), (3.0, 1)]),  # 1 and 3 are grid points of linspace(0, 5, 401)
]


@pytest.mark.parametrize("A, lo, hi, n_scan, expected", [c[1:] for c in MATRIX_CATALOGUE],
                         ids=[c[0] for c in MATRIX_CATALOGUE])
def test_matrix_roots_catalogue_known_roots_and_nullities(A, lo, hi, n_scan, expected):
    """Singular points of matrix families known in closed form, with the dimension of the null
    space as multiplicity (repeated roots where det only touches zero included)."""
    got = matrix_roots(A, lo, hi, n_scan=n_scan)
    _assert_roots(got, expected)
    for r in got.roots:
        assert r.residual <= 1e-8


@pytest.mark.parametrize("lo, hi", [(0.0, 3.0), (0.0, 2.0)], ids=["off_grid", "on_grid"])
def test_matrix_roots_diag_x_minus_1_twice(lo, hi):
    """diag(x - 1, x - 1) is singular at x = 1 with a two-dimensional null space (closed form)."""
    _assert_roots(matrix_roots(lambda x: np.diag([x - 1.0, x - 1.0]), lo, hi), [(1.0, 2)])


def test_matrix_roots_simple_root_on_grid_point_is_not_labelled_touching():
    """det diag(x-1, x-3) changes sign through x = 1 and x = 3 (simple roots)."""
    got = matrix_roots(lambda x: np.diag([x - 1.0, x - 3.0]), 0.0, 5.0)
    assert [r.kind for r in got.roots if r.kind == "touching"] == []


def test_matrix_roots_pole_is_not_a_singular_point():
    """diag(1/(x-3), 1) is nonsingular wherever it is defined (det = 1/(x-3) != 0)."""
    assert matrix_roots(lambda x: np.diag([1.0 / (x - 3.0), 1.0]), 0.0, 5.3).roots == ()


def test_matrix_roots_known_nullity_ignores_permanent_null_space():
    """With ``known_nullity=1`` the permanent zero singular value of diag(0, x-2, 1) is skipped and
    only x = 2 is reported, with multiplicity 1 (beyond the known one)."""
    got = matrix_roots(lambda x: np.diag([0.0, x - 2.0, 1.0]), 0.03, 5.3, known_nullity=1)
    _assert_roots(got, [(2.0, 1)])


def test_matrix_roots_complex_matrix_with_fixed_determinant_phase_polishes_by_sign():
    """diag(e^(i a) (x - 1), e^(i b) (x - 2.5)) (closed form: roots 1 and 2.5) has the
    determinant ``e^(i(a+b)) (x-1)(x-2.5)``, of one phase: both roots are sign changes along
    it, refined to full precision (no golden search)."""
    a, b = 0.7, -2.1
    got = matrix_roots(lambda x: np.diag([np.exp(1j * a) * (x - 1.0),
                                          np.exp(1j * b) * (x - 2.5)]), 0.03, 5.3)
    _assert_roots(got, [(1.0, 1), (2.5, 1)])
    assert [r.kind for r in got.roots] == ["sign-change", "sign-change"]
    assert max(abs(r.x - x) for r, x in zip(got.roots, (1.0, 2.5), strict=True)) <= 1e-13


def test_matrix_roots_complex_matrix_whose_phase_turns_is_still_searched_by_minima():
    """diag(e^(i x) (x - 1), 1): the determinant's phase turns with x, so it gives no sign;
    the root x = 1 is still found, as a minimum of sigma_min (the fallback)."""
    got = matrix_roots(lambda x: np.diag([np.exp(1j * x) * (x - 1.0), 1.0 + 0j]), 0.03, 5.3)
    _assert_roots(got, [(1.0, 1)])
    assert got.roots[0].kind == "touching"


def test_bloch_determinant_times_rho_to_minus_three_is_real():
    """The property the Bloch method's sign relies on (:mod:`rodstab.transfer.cyclic`): for a
    complex harmonic, ``rho^-3 det(rho G - J G T)`` is real (a palindromic characteristic
    polynomial: the one-arc map is similar to a symplectic one), for cusps, smooth welds and
    an arbitrary weld turn, at loads on both sides of the stress-free one."""
    from rodstab.transfer.cyclic import _bloch, _cyclic_parts

    for weld, n, h in (("cusp", 6, 1), ("smooth", 5, 2), (0.83, 7, 3)):
        rho = np.exp(2j * math.pi * h / n)
        for mu in (-4.0, -0.3, 1.0, 3.7):
            det = np.linalg.det(_bloch(*_cyclic_parts(mu, 2.2, 1.7, 0.6, weld), h, n))
            assert abs((det * rho ** -3).imag) <= 1e-12 * abs(det)


# ------------------------------------------------------------------------------ pencil_interval


def test_pencil_interval_2x2_closed_form():
    """A = [[2,1],[1,2]], C = diag(1,-1): det(C - theta A) = 3 theta^2 - 1, so the stable
    interval is (-sqrt 3, sqrt 3); at p = sqrt 3 the mode is (1, sqrt 3 - 2), at -sqrt 3 it is
    (1, -sqrt 3 - 2)^T up to scale (null vectors of A - p C)."""
    A = np.array([[2.0, 1.0], [1.0, 2.0]])
    C = np.diag([1.0, -1.0])
    res = pencil_interval(A, C)
    assert res.lo == pytest.approx(-math.sqrt(3), rel=1e-14)
    assert res.hi == pytest.approx(math.sqrt(3), rel=1e-14)
    assert (res.multiplicity_lo, res.multiplicity_hi) == (1, 1)
    for v, expected in ((res.mode_hi[:, 0], [1.0, math.sqrt(3) - 2]),
                        (res.mode_lo[:, 0], [1.0, -math.sqrt(3) - 2])):
        cos = abs(v @ expected) / np.linalg.norm(v) / np.linalg.norm(expected)
        assert cos == pytest.approx(1.0, abs=1e-14)
    assert res.residual < 1e-14 and res.converged and res.n_dof == 2


def test_pencil_interval_repeated_eigenvalue_multiplicity_2():
    """A = I, C = diag(1, 1, -1): theta = 1 twice and -1 once; interval (-1, 1), multiplicity 2
    at the top with a two-column mode basis spanning e1, e2."""
    res = pencil_interval(np.eye(3), np.diag([1.0, 1.0, -1.0]))
    assert (res.lo, res.hi) == (pytest.approx(-1.0), pytest.approx(1.0))
    assert (res.multiplicity_lo, res.multiplicity_hi) == (1, 2)
    assert res.mode_hi.shape == (3, 2)
    np.testing.assert_allclose(res.mode_hi[2], 0.0, atol=1e-15)


@pytest.mark.parametrize("C, lo, hi", [
    (np.diag([-1.0, 0.0]), -1.0, math.inf),      # C negative semidefinite: no upper bound
    (np.diag([2.0, 0.0]), -math.inf, 0.5),       # C positive semidefinite: no lower bound
    (np.zeros((2, 2)), -math.inf, math.inf),     # no load term at all
])
def test_pencil_interval_unbounded_sides(C, lo, hi):
    """With A = I, K(p) = I - p C is positive definite for all p on a side where C has no
    eigenvalue of the matching sign: that side is infinite, multiplicity 0, mode None."""
    res = pencil_interval(np.eye(2), C)
    assert (res.lo, res.hi) == (lo, hi)
    if math.isinf(hi):
        assert res.multiplicity_hi == 0 and res.mode_hi is None
    if math.isinf(lo):
        assert res.multiplicity_lo == 0 and res.mode_lo is None


@pytest.mark.parametrize("A", [
    np.array([[1.0, 2.0], [2.0, 1.0]]),   # indefinite
    np.diag([1.0, 0.0]),                  # singular
    -np.eye(2),                           # negative definite
])
def test_pencil_interval_requires_positive_definite_A(A):
    """No interval about p = 0 exists when A is not positive definite: ValueError naming A."""
    with pytest.raises(ValueError, match="positive definite"):
        pencil_interval(A, np.eye(2))


@PROPERTY
@given(n=st.integers(min_value=1, max_value=6), seed=st.integers(min_value=0, max_value=10**6))
def test_pencil_interval_matches_direct_definiteness_check(n, seed):
    """Random SPD A and symmetric C: A - p C is positive definite (eigvalsh > 0) for p strictly
    inside (lo, hi) and singular (smallest eigenvalue of A^-1/2 K A^-1/2 = 0) at a finite end."""
    rng = np.random.default_rng(seed)
    L = np.tril(rng.normal(size=(n, n)))
    np.fill_diagonal(L, np.abs(np.diag(L)) + 0.5)
    A = L @ L.T
    B = rng.normal(size=(n, n))
    C = B + B.T
    res = pencil_interval(A, C)
    assert res.lo < 0 < res.hi and res.residual < 1e-8
    Li = np.linalg.inv(L)
    for p in (res.lo, res.hi):
        if math.isfinite(p):
            for inside in (0.999 * p, 0.5 * p):
                assert np.linalg.eigvalsh(A - inside * C).min() > 0
            ev = np.linalg.eigvalsh(Li @ (A - p * C) @ Li.T)
            assert np.min(np.abs(ev)) <= 1e-8 * max(1.0, np.max(np.abs(ev)))
            assert np.linalg.eigvalsh(A - 1.001 * p * C).min() < 0


def _constrained_pencil(n: int, border: int, seed: int, a_jj: float = 4.0):
    """Banded SPD ``A`` (a 1D Laplacian plus a diagonal), ``border`` leading unknowns
    coupled to a few others with ``A_JJ = a_jj``, a symmetric banded ``C`` and two dense
    constraint rows (like an FE segment's closure ``int beta ds``)."""
    import scipy.sparse as sp

    rng = np.random.default_rng(seed)
    main = 2.0 + rng.uniform(0.0, 0.5, n)
    A = sp.diags([-np.ones(n - 1), main, -np.ones(n - 1)], [-1, 0, 1]).tolil()
    for j in range(border):
        A[j, j] = a_jj
        for i in (border + 3 * j, border + 3 * j + 1):
            A[j, i] = A[i, j] = 0.3
    c = rng.normal(size=n)
    C = sp.diags([0.2 * c[:-1], c, 0.2 * c[:-1]], [-1, 0, 1])
    G = np.zeros((2, n))
    G[0, border:] = rng.uniform(0.5, 1.0, n - border)
    G[1, :border] = 1.0
    G[1, border:(n + border) // 2] = rng.uniform(-1.0, 1.0, (n - border) // 2)
    return A.tocsc(), C.tocsc(), sp.csr_matrix(G)


def _dense_constrained(A, C, G):
    import scipy.linalg

    N = scipy.linalg.null_space(G.toarray())
    return pencil_interval(N.T @ A.toarray() @ N, N.T @ C.toarray() @ N), N


@pytest.mark.parametrize("border", [0, 3])
def test_sparse_constrained_pencil_matches_dense_null_space_solve(border):
    """Substructured Lanczos on ``G v = 0`` (n = 400 > DENSE_EIG_MAX) against LAPACK on the
    explicit null-space basis: both ends of the interval to 1e-10, the modes on the
    constraints and parallel to the dense ones."""
    A, C, G = _constrained_pencil(400, border, seed=7)
    res = pencil_interval_sparse(A, C, constraints=G, border=border)
    ref, N = _dense_constrained(A, C, G)
    assert res.converged and res.n_dof == 398
    assert res.hi == pytest.approx(ref.hi, rel=1e-10)
    assert res.lo == pytest.approx(ref.lo, rel=1e-10)
    for v, vr in ((res.mode_hi[:, 0], N @ ref.mode_hi[:, 0]),
                  (res.mode_lo[:, 0], N @ ref.mode_lo[:, 0])):
        assert np.abs(G @ v).max() <= 1e-10 * np.abs(v).max()
        cos = abs(v @ vr) / np.linalg.norm(v) / np.linalg.norm(vr)
        assert cos == pytest.approx(1.0, abs=1e-8)


def test_sparse_constrained_pencil_definiteness_is_on_the_constraints():
    """A border unknown of negative stiffness held at zero by a constraint row leaves ``A``
    positive definite on the constraints (the Haynsworth count must say so and the interval
    match the dense one); freed, it makes ``A`` indefinite and the solve refuses."""
    import scipy.sparse as sp

    A, C, _ = _constrained_pencil(400, 1, seed=3, a_jj=-1.0)
    n = A.shape[0]
    pin = sp.csr_matrix(([1.0], ([0], [0])), shape=(1, n))
    res = pencil_interval_sparse(A, C, constraints=pin, border=1)
    ref, _ = _dense_constrained(A, C, pin)
    assert res.hi == pytest.approx(ref.hi, rel=1e-10)
    with pytest.raises(ValueError, match="not positive definite"):
        pencil_interval_sparse(A, C, border=1)


def test_xtol_constant_is_relative_to_span():
    """Refined roots are accurate to XTOL * span: sin's root pi on a long interval [0.5, 1000.5]."""
    res = find_roots(math.sin, 0.5, 1000.5, n_scan=4000)
    assert res.values[0] == pytest.approx(math.pi, abs=XTOL * 1000 * 10)
    assert len(res.values) == 318  # k pi for k = 1 .. 318 (318 pi = 999.03)


@pytest.mark.parametrize("n", [50, 600], ids=["dense", "shift-invert Lanczos"])
def test_lowest_eigenpairs_of_a_shifted_laplacian_closed_form(n):
    """-u'' on n points minus a shift: eigenvalues 2 - 2 cos(j pi / (n + 1)) - s (closed
    form). With s between the 3rd and 4th Laplacian eigenvalue, three are negative, the
    farthest from 0 being the lowest, and a small positive one sits closest to 0: the
    Lanczos shift placed from the eigenvalue nearest 0 would miss the negatives."""
    import scipy.sparse as sp

    from rodstab import numerics

    j = np.arange(1, n + 1)
    exact = np.sort(2 - 2 * np.cos(j * np.pi / (n + 1)))
    s = 0.5 * (exact[2] + exact[3]) + 0.3 * (exact[3] - exact[2])
    A = sp.diags([-np.ones(n - 1), 2 * np.ones(n) - s, -np.ones(n - 1)], [-1, 0, 1]).tocsc()
    assert (n > numerics.DENSE_EIG_MAX) == (n == 600)
    vals, vecs = numerics.lowest_eigenpairs(A, 5)
    assert np.allclose(vals, exact[:5] - s, rtol=0, atol=1e-12)
    assert np.sum(vals < 0) == 3 and abs(vals[3]) < abs(vals[0])
    assert np.allclose(np.abs(vecs.T @ vecs), np.eye(5), atol=1e-8)


def test_jacobi_scaling_gives_a_unit_diagonal_and_keeps_the_inertia():
    """D A D has diag 1 (|diag| > 0) and the same number of negative eigenvalues (Sylvester)."""
    from rodstab.numerics import jacobi_scaling

    rng = np.random.default_rng(3)
    Q = np.linalg.qr(rng.standard_normal((8, 8)))[0]
    A = Q @ np.diag([-3.0, -1e-3, 2e-4, 1.0, 5.0, 9.0, 1e3, 1e6]) @ Q.T
    d = jacobi_scaling(A)
    S = d[:, None] * A * d[None, :]
    assert np.allclose(np.abs(np.diag(S)), 1.0)
    assert np.sum(np.linalg.eigvalsh(S) < 0) == np.sum(np.linalg.eigvalsh(A) < 0) == 2


def test_refine_root_refines_a_bracket_without_scanning():
    """A sign-change bracket refined by Brent alone: cos on [1, 2] gives pi/2 to XTOL in a few
    evaluations (a scan would take dozens); no sign change is refused naming the interval."""
    from rodstab.errors import RodstabInputError
    from rodstab.numerics import refine_root

    calls = []

    def f(x):
        calls.append(x)
        return math.cos(x)

    assert refine_root(f, 2.0, 1.0) == pytest.approx(math.pi / 2, abs=1e-13)
    assert len(calls) < 15
    with pytest.raises(RodstabInputError, match=r"no sign change on \[0.0, 1.0\]"):
        refine_root(math.cos, 0.0, 1.0)


def test_sigma_min_2x2_equals_lapack_and_keeps_its_digits_at_a_root():
    """Closed-form smallest singular values of symmetric 2x2 matrices against LAPACK's SVD on
    random ones; on an exactly singular one shifted by 1e-12 in ``a22`` the closed form reads
    the shift's effect (|det| / sigma_max = a11 1e-12 / F^(1/2)) to 1e-3 relative (the
    shift itself is stored in y = 4.5 + 1e-12 to ~5e-4)."""
    rng = np.random.default_rng(5)
    a11, a22, a12 = rng.normal(size=(3, 200))
    got = sigma_min_2x2(a11, a22, a12)
    ref = [np.linalg.svd(np.array([[x, z], [z, y]]), compute_uv=False)[-1]
           for x, y, z in zip(a11, a22, a12, strict=True)]
    assert np.allclose(got, ref, rtol=1e-10, atol=1e-15)
    x, z = 2.0, 3.0
    y = z * z / x + 1e-12  # det = x * 1e-12
    F = x * x + y * y + 2 * z * z
    assert sigma_min_2x2(np.array(x), np.array(y), np.array(z)) == pytest.approx(
        x * 1e-12 / math.sqrt(F), rel=1e-3)
