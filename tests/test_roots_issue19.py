"""Issue 19 items 2-4: the transfer-matrix methods never miss or invent a root.

References, all independent of the code under test: the closed form (3.3) for rings
(:func:`rodstab.analytic.ring.ring_stability`, Fourier modes, no shooting); the characteristic
equations (3.7)/(3.8) for clamped arcs (:func:`rodstab.analytic.arc.clamped_arc_stability`,
general solution (3.5), no matrix exponential); the FE engine's -56.80 (multiplicity 2) for the
five-rod cusp ring of item 4 (issue 19, measured on main a0083b5); for the root finder,
functions with known roots.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from rodstab import problems, transfer
from rodstab.analytic.arc import clamped_arc_stability
from rodstab.analytic.ring import ring_stability
from rodstab.errors import RodstabInputError
from rodstab.numerics import matrix_roots
from rodstab.sections import from_ratios, rectangle

#: Both methods are exact; the agreement is the root finder's.
EXACT_RTOL = 1e-8


@pytest.mark.parametrize("section, loops", [
    # Issue reproducer: the old monodromy scan gave (5.112, 15.822) in (L/2 pi) kappa_n.
    (rectangle(aspect=3.0), 9),
    # Issue reproducer: the old scan missed the uniform twist M = b1 and returned -9.27.
    (from_ratios(b1=0.27, b2=10.0), 1),
    # Roots next to M = 0 of a strongly anisotropic section (old scan: missed both).
    (from_ratios(b1=0.059216404833046715, b2=5.240221755080958), 5),
])
def test_ring_transfer_finds_the_closed_form_ends(section, loops):
    """Monodromy (half-ring shooting) ends = closed form (3.3) ends, relative 1e-8."""
    ring = problems.REGISTRY["ring"]
    p = ring.Params(section=section, loops=loops)
    got, ref = ring.METHODS["transfer"](p), ring.METHODS["analytic"](p)
    for key, value in ref.items():
        assert got[key] == pytest.approx(value, rel=EXACT_RTOL), key


def test_ring_window_holds_the_closed_form_ends():
    """The test-mode window (-2 sqrt(b1 b2) < M_lo, M_hi <= b1) contains (3.3)'s ends."""
    rng = np.random.default_rng(19)
    for _ in range(200):
        b1, b2 = np.exp(rng.uniform(math.log(0.05), math.log(50.0), 2))
        N = int(rng.integers(1, 10))
        lo, hi = ring_stability(b1, b2, N).M_interval
        w_lo, w_hi = transfer.ring_root_window(b1, b2)
        assert w_lo < lo < 0.0 < hi < w_hi


@pytest.mark.parametrize("b1, b2, L_over_R, side, mode", [
    # Issue reproducer: old window missed it (-inf); root near L/R (1 - b1).
    (50.0, 1.3, 6.0, "L_kappa_n_lower", None),
    # Issue reproducer: old scan returned the symmetric 17.940467 of a close pair.
    (0.19, 0.24, 16.6, "L_kappa_n_upper", "antisymmetric"),
    # Found by benchmarks/diff_transfer_roots.py (seed 7): a false root at -8.48 where the
    # exponents are real (FE: -276.30).
    (46.8994, 0.0611344, 6.01744, "L_kappa_n_lower", None),
])
def test_arc_transfer_finds_the_characteristic_equation_ends(b1, b2, L_over_R, side, mode):
    """Shooting matrix per family = roots of (3.7)/(3.8), relative 1e-8, both ends."""
    arc = problems.REGISTRY["clamped-arc"]
    p = arc.Params(section=from_ratios(b1=b1, b2=b2), L_over_R=L_over_R)
    got = arc.METHODS["transfer"](p)
    ref = clamped_arc_stability(b1, b2, L_over_R)
    for key, value in zip(("L_kappa_n_lower", "L_kappa_n_upper"), ref.L_kappa_interval,
                          strict=True):
        assert math.isfinite(got[key]) and got[key] == pytest.approx(value, rel=EXACT_RTOL)
    if mode is not None:
        assert ref.critical_mode == mode


def test_arc_window_holds_the_characteristic_equation_ends():
    """The test-field bounds contain (3.7)/(3.8)'s ends, the straight limit included."""
    rng = np.random.default_rng(19)
    for _ in range(15):
        b1, b2 = np.exp(rng.uniform(math.log(0.05), math.log(50.0), 2))
        Lb = float(rng.uniform(0.0, 20.0)) if _ else 0.0
        lo, hi = clamped_arc_stability(b1, b2, Lb).L_kappa_interval
        w_lo, w_hi = transfer.arc_root_window(Lb, b1, b2)
        assert w_lo < lo < hi < w_hi


def test_half_arc_families_are_singular_at_the_full_arc_loads():
    """Each family's 3x3 is singular at its load; the full-arc shooting matrix agrees."""
    b1, b2, Lb = 0.19, 0.24, 16.6
    ref = clamped_arc_stability(b1, b2, Lb)
    p = ref.L_kappa_interval[1]
    anti = np.linalg.svd(transfer.clamped_half_arc_matrix(p, Lb, b1, b2, "antisymmetric"),
                         compute_uv=False)
    sym = np.linalg.svd(transfer.clamped_half_arc_matrix(p, Lb, b1, b2, "symmetric"),
                        compute_uv=False)
    full = np.linalg.svd(transfer.clamped_arc_matrix(p, Lb, b1, b2), compute_uv=False)
    assert anti[-1] / anti[0] < 1e-9 < sym[-1] / sym[0]
    assert full[-1] / full[0] < 1e-9
    with pytest.raises(RodstabInputError, match="family"):
        transfer.clamped_half_arc_matrix(p, Lb, b1, b2, "both")


THETA = math.radians(36.0)


def test_bloch_ring_finds_the_root_beyond_the_old_span():
    """Five cusp rods, b1 = 90, b2 = 1.4, theta = 36 deg: lower end -56.80 (FE), a pair."""
    r = transfer.cyclic_ring_interval(THETA, 1.0, 90.0, 1.4, 5, "cusp", THETA)
    assert r.converged and r.reason == ""
    assert r.lo == pytest.approx(-56.80, abs=0.01)
    assert r.multiplicity_lo == 2


def test_bloch_ring_without_a_certified_end_says_so(monkeypatch):
    """A side with no singular load up to the proven bound: converged False, a reason, inf."""
    monkeypatch.setattr(transfer.cyclic, "arc_root_window", lambda Lb, b1, b2: (Lb - 3.0, Lb + 3.0))
    r = transfer.cyclic_ring_interval(THETA, 1.0, 90.0, 1.4, 5, "cusp", THETA)
    assert not r.converged and r.lo == -math.inf and "no singular load below" in r.reason


def test_matrix_roots_absolute_measure_sees_a_matrix_that_vanishes_as_a_whole():
    """A(x) = sin(5x) e^x diag(1, 0.01 (1 + x/10)): roots k pi/5; sigma_min/sigma_max has no
    dip there (a slow trend, no local minimum), sigma_min over the median size does."""
    def A(x: float) -> np.ndarray:
        return math.sin(5 * x) * math.exp(x) * np.diag([1.0, 0.01 * (1 + 0.1 * x)])

    found = matrix_roots(A, 0.1, 6.0, n_scan=120, absolute=True, touch_tol=1e-8)
    expected = [k * math.pi / 5 for k in range(1, 10)]
    assert found.values == pytest.approx(expected, abs=1e-9)
    assert all(r.multiplicity == 2 for r in found.roots)


def test_matrix_roots_grid_is_validated_and_used():
    """A grid must run from lo to hi, increasing; a root between its points is found."""
    def A(x: float) -> np.ndarray:
        return np.array([[x - 0.3001, 0.0], [0.0, 1.0]])

    grid = np.concatenate([np.linspace(0.0, 0.29, 3), np.linspace(0.3, 0.302, 9), [1.0]])
    assert matrix_roots(A, 0.0, 1.0, grid=grid).values == pytest.approx([0.3001], abs=1e-12)
    with pytest.raises(RodstabInputError, match="grid"):
        matrix_roots(A, 0.0, 1.0, grid=grid[::-1])


def test_atlas_interval_carries_the_bloch_methods_non_convergence(monkeypatch):
    """StateInterval.converged (JSON 'converged', CLI exit 3) is the Bloch result's, with why."""
    from rodstab.multistable import atlas
    from rodstab.multistable.states import uniform_ring

    ring = uniform_ring(5, weld="cusp", natural_curvature=1.0, B1=90.0, B2=1.4)
    state = next(s for s in ring.states(max_turns=1.0).states
                 if abs(s.theta - THETA) < 1e-9)
    monkeypatch.setattr(transfer.cyclic, "arc_root_window", lambda Lb, b1, b2: (Lb - 3.0, Lb + 3.0))
    r = atlas.transfer_interval(ring, state)
    assert not r.converged and "no singular load below" in r.reason
