"""The general FE engine (rodstab.linear) against closed forms and the independent methods."""

from __future__ import annotations

import math

import numpy as np
import pytest
import scipy.linalg

from rodstab.analytic.arc import clamped_arc_stability
from rodstab.analytic.folded_ring import folded_ring_paper_method
from rodstab.analytic.ring import ring_stability
from rodstab.errors import RodstabInputError
from rodstab.linear.assembly import discretise, quadratic_forms
from rodstab.linear.solve import linear_pencil, linear_stability, stable_at
from rodstab.model import Assembly, Segment
from rodstab.numerics import matrix_roots
from rodstab.sections import circle, rectangle
from rodstab.transfer import ASSEMBLY_RIGID_NULLITY, straight_assembly_matrix

EXPECTED_ORDER = 4.0  # Hermite w (h^4) and quadratic omega (h^4) eigenvalue errors
CIRCLE = circle()
RECT2 = rectangle(aspect=2.0)


def clamped(L, k, kn, s, *, start=(0.0, 0.0), angle=0.0):
    seg = Segment(name="a", length=L, curvature=k, natural_curvature=kn, B1=s.b1, B2=s.b2, B3=1.0,
                  start=start, angle=angle)
    return Assembly(segments=(seg,), supports=(("a", "start", "clamped"), ("a", "end", "clamped")))


def ring(N, s):
    seg = Segment(name="a", length=2 * math.pi * N, curvature=1.0, natural_curvature=1.0, B1=s.b1,
                  B2=s.b2, B3=1.0)
    return Assembly(segments=(seg,), welds=((("a", "start"), ("a", "end")),))


def birod(s, clamp=True):
    segs = (Segment(name="u", length=1.0, curvature=0.0, natural_curvature=1.0, B1=s.b1, B2=s.b2,
                    B3=1.0),
            Segment(name="l", length=1.0, curvature=0.0, natural_curvature=-1.0, B1=s.b1, B2=s.b2,
                    B3=1.0))
    welds = ((("u", "start"), ("l", "start")), (("u", "end"), ("l", "end")))
    return Assembly(segments=segs, welds=welds,
                    supports=(("u", "start", "clamped"),) if clamp else ())


def six_ring(s):
    segs = tuple(Segment(name=str(i), length=1.0, curvature=0.0,
                         natural_curvature=-1.0 if i % 2 else 1.0, B1=s.b1, B2=s.b2, B3=1.0)
                 for i in range(1, 7))
    welds = tuple(((str(i), "end" if i % 2 else "start"), (str(i % 6 + 1), "end" if i % 2
                                                            else "start")) for i in range(1, 7))
    return Assembly(segments=segs, welds=welds)


def _order(ns, errs):
    return -np.polyfit(np.log(ns), np.log(errs), 1)[0]


def test_eq_3_9_straight_clamped_rod_converges_at_fourth_order():
    """Closed form (3.9): L kappa_n = 2 pi sqrt(b1 b2); FE error ~ h^4 over four meshes."""
    exact = 2 * math.pi * CIRCLE.sqrt_b1b2
    ns = [2, 4, 8, 16]
    errs = [abs(linear_stability(clamped(1.0, 0.0, 1.0, CIRCLE), n).load_factor_critical
                - exact) / exact for n in ns]
    assert _order(ns, errs) >= EXPECTED_ORDER - 0.2
    assert linear_stability(clamped(1.0, 0.0, 1.0, CIRCLE), 48).load_factor_critical == \
        pytest.approx(exact, rel=1e-6)


def test_ring_N1_lower_limit_converges_at_fourth_order():
    """Eq (3.3) (circle, N = 1): M_C^- = 7/8 - sqrt(1/64 + 3); mu = 1 - M for R = 1."""
    exact = 1 - (7 / 8 - math.sqrt(1 / 64 + 3))
    ns = [8, 16, 32, 64]
    errs = [abs(linear_stability(ring(1, CIRCLE), n).load_factor_interval[1] - exact) / exact
            for n in ns]
    assert _order(ns, errs) >= EXPECTED_ORDER - 0.2


@pytest.mark.parametrize("N", [1, 3, 5])
@pytest.mark.parametrize("sec", [CIRCLE, RECT2], ids=["circle", "rect2"])
def test_engine_reproduces_ring_intervals(N, sec):
    """Section 3.1 (analytic module, itself checked by the monodromy method) to 1e-6."""
    r = linear_stability(ring(N, sec), 150 * N)
    M_lo, M_hi = ring_stability(sec.b1, sec.b2, N).M_interval
    lo, hi = r.load_factor_interval
    assert 1 - hi == pytest.approx(M_lo, rel=1e-6)
    assert 1 - lo == pytest.approx(M_hi, rel=1e-6)
    assert r.n_rigid_modes == 3


@pytest.mark.parametrize("L_over_R", [0.5, 2.0, 4.0])
@pytest.mark.parametrize("sec", [CIRCLE, RECT2], ids=["circle", "rect2"])
def test_engine_reproduces_clamped_arcs(L_over_R, sec):
    """Section 3.2 (3.7)/(3.8) (checked by shooting) to 1e-6: mu = kappa_n R, L kappa_n = L/R mu."""
    r = linear_stability(clamped(L_over_R, 1.0, 1.0, sec), 96)
    lo, hi = clamped_arc_stability(sec.b1, sec.b2, L_over_R).L_kappa_interval
    assert L_over_R * r.load_factor_interval[1] == pytest.approx(hi, rel=1e-6)
    assert L_over_R * r.load_factor_interval[0] == pytest.approx(lo, rel=1e-6)


@pytest.mark.parametrize("sec", [CIRCLE, RECT2, rectangle(aspect=0.75)],
                         ids=["circle", "rect2", "rect075"])
def test_section_4_birod_critical_load_is_pi_by_engine_and_full_system(sec):
    """Bi-rod clamped at one end: the full system of general solutions + all joint conditions
    (geometric and natural, none at the clamp) gives lam_c = pi (sin(lam) = 0, the mode
    with both rods deflecting together and opposite twists), not the paper's 2 pi; the engine
    agrees. The paper's 2 pi is the next eigenvalue (double)."""
    g = sec.sqrt_b1b2
    a = birod(sec)
    full = matrix_roots(lambda mu: straight_assembly_matrix(a, mu), 0.05 * g, 7 * g,
                        n_scan=300)
    assert full.roots[0].x / g == pytest.approx(math.pi, rel=1e-9)
    assert full.roots[1].x / g == pytest.approx(2 * math.pi, rel=1e-9)
    r = linear_stability(a, 40)
    assert r.load_factor_critical / g == pytest.approx(math.pi, rel=1e-6)
    assert r.multiplicity == 1
    free = linear_stability(birod(sec, clamp=False), 40)
    assert free.load_factor_critical == pytest.approx(r.load_factor_critical, rel=1e-9)


@pytest.mark.parametrize("sec", [CIRCLE, RECT2, rectangle(aspect=4.0)],
                         ids=["circle", "rect2", "rect4"])
def test_section_5_folded_six_ring_is_pi_over_3_double_by_three_methods(sec):
    """Folded 6-sided ring: engine, full system and the paper's own monodromy (5.8)-(5.12)
    all give lam_c = pi/3 with multiplicity 2, for every B2/B1 (paper: 2 pi)."""
    g = sec.sqrt_b1b2
    a = six_ring(sec)
    r = linear_stability(a, 24)
    assert r.load_factor_critical / g == pytest.approx(math.pi / 3, rel=1e-6)
    assert r.multiplicity == 2
    full = matrix_roots(lambda mu: straight_assembly_matrix(a, mu), 0.05 * g, 4 * g,
                        n_scan=300, known_nullity=ASSEMBLY_RIGID_NULLITY)
    assert full.roots[0].x / g == pytest.approx(math.pi / 3, rel=1e-9)
    assert full.roots[0].multiplicity == 2


def test_refinement_error_falls_to_round_off_and_stays_there():
    """Six-ring (circle), against the closed form pi/3 sqrt(b1 b2): the error falls as h^4
    and stays at round-off on fine meshes. The earlier fourth-order formulation in ``w``
    (Hermite cubics) lost digits as n^4: 2.4e-6 at 1024 and 1.5e-3 with the wrong
    multiplicity at 4096 elements per segment; the (beta, omega) form reads 2e-15 and 7e-16."""
    a = six_ring(CIRCLE)
    exact = math.pi / 3 * CIRCLE.sqrt_b1b2
    errs = {n: abs(linear_stability(a, n).load_factor_critical - exact) / exact
            for n in (16, 32, 2048)}
    assert math.log2(errs[16] / errs[32]) == pytest.approx(4.0, abs=0.15)
    fine = linear_stability(a, 2048)
    assert errs[2048] < 1e-12 and fine.multiplicity == 2 and fine.multiplicity_lo == 2
    lo = fine.load_factor_interval[0]
    assert abs(-lo - exact) / exact < 1e-12  # the ring's interval is symmetric


@pytest.mark.parametrize("n", [6, 64], ids=["dense", "substructured"])
def test_verdict_by_inertia_agrees_with_the_interval(n):
    """``stable_at`` (one factorisation, no eigen solve) says stable exactly inside the
    interval of ``linear_stability``: the six-ring 1 % inside and outside both ends, and a
    clamped arc, through the dense (small) and the substructured (large) paths."""
    for a in (six_ring(RECT2), clamped(2.0, 1.0, 1.0, CIRCLE)):
        lo, hi = linear_stability(a, n).load_factor_interval
        pen = linear_pencil(a, n)
        for mu in (0.99 * hi, 1.01 * hi) + ((0.99 * lo, 1.01 * lo) if math.isfinite(lo) else ()):
            assert pen.stable_at(mu) == (lo < mu < hi), (mu, lo, hi)
        assert stable_at(a, 0.5 * hi, n) and not stable_at(a, 1.01 * hi, n)


def test_quadratic_forms_from_strains_equal_the_assembled_products():
    """The Rayleigh quotient's energies, element by element from strains, are x^T K x."""
    d = discretise(six_ring(RECT2), 6)
    x = np.random.default_rng(1).normal(size=d.n_global)
    e0, e1 = quadratic_forms(d, x)
    assert e0 == pytest.approx(x @ d.K0 @ x, rel=1e-12)
    assert e1 == pytest.approx(x @ d.K1 @ x, rel=1e-12)


def test_section_5_paper_method_own_equations_give_pi_over_3():
    """(5.12): det A^(1) already vanishes at pi/3, 2pi/3, pi, 4pi/3, 5pi/3 before 2 pi."""
    r = folded_ring_paper_method(0.05, 7.0, 700)
    assert np.allclose(np.array(r.det_A1_roots[:6]) / math.pi,
                       [1 / 3, 2 / 3, 1, 4 / 3, 5 / 3, 2], rtol=1e-9)
    assert r.lam_critical == pytest.approx(math.pi / 3, rel=1e-9)
    assert r.multiplicity == 2
    assert r.first_columns_residual < 1e-9  # (5.11): first three columns of A - I vanish


@pytest.mark.parametrize("shift, turn", [((3.0, -2.0), 0.0), ((0.0, 0.0), 1.1),
                                         ((5.0, 1.0), -2.5)])
def test_rigid_motion_of_the_held_geometry_leaves_result_unchanged(shift, turn):
    """Translating/rotating the whole assembly in its plane changes nothing."""
    base = linear_stability(clamped(2.0, 1.0, 1.0, RECT2), 16).load_factor_interval
    moved = linear_stability(clamped(2.0, 1.0, 1.0, RECT2, start=shift, angle=turn),
                             16).load_factor_interval
    assert np.allclose(moved, base, rtol=1e-10)


def test_reversing_a_segment_leaves_result_unchanged():
    """The same arc described from its other end: start and tangent reversed, signed
    curvatures (held and natural) change sign."""
    fwd = clamped(2.0, 1.0, 1.0, RECT2)
    seg = fwd.segments[0]
    end = seg.end_point("end")
    t = seg.tangent(seg.length)
    rev = clamped(2.0, -1.0, -1.0, RECT2, start=tuple(end), angle=math.atan2(-t[1], -t[0]))
    assert np.allclose(linear_stability(rev, 16).load_factor_interval,
                       linear_stability(fwd, 16).load_factor_interval, rtol=1e-10)


def test_global_matrices_are_symmetric():
    d = discretise(six_ring(RECT2), 6)
    for K in (d.K0, d.K1):
        assert abs(K - K.T).max() <= 1e-12 * abs(K).max()


def _unit(name="a", **kw):
    """A unit straight segment (all stiffnesses 1) with ``kw`` overriding any field."""
    return Segment(**({"name": name, "length": 1.0, "curvature": 0.0, "natural_curvature": 0.0,
                       "B1": 1.0, "B2": 1.0, "B3": 1.0} | kw))


@pytest.mark.parametrize("build, needle", [
    (lambda: Assembly(segments=(_unit("a"), _unit("b", start=(0.5, 0.0))),
                      welds=((("a", "end"), ("b", "start")),)), "do not meet"),
    (lambda: Assembly(segments=(_unit(natural_curvature=1.0),)), "moment equilibrium"),
    (lambda: Assembly(segments=(_unit(),), supports=(("a", "start", "glued"),)), "glued"),
    (lambda: _unit(length=-1.0), "length"),
    (lambda: _unit(B2=0.0), "B2"),
    (lambda: Assembly(segments=(_unit(),), welds=((("a", "middle"), ("a", "end")),)), "middle"),
    (lambda: Assembly(segments=(_unit(),), supports=(("zz", "start", "clamped"),)), "zz"),
])
def test_bad_assemblies_raise_naming_the_problem(build, needle):
    with pytest.raises(RodstabInputError, match=needle):
        build()


def test_free_straight_assembly_has_exactly_three_rigid_modes_ungauged():
    """Stress-free folded ring (mu = 0, straight segments, which the elements represent
    exactly): the ungauged K0 on the closure rows' null space (``w`` single valued along every
    segment) has exactly 3 zero eigenvalues (translation, two rotations). Without the closure
    rows each joint ``w`` would be a further zero-energy unknown."""
    d = discretise(six_ring(RECT2), 4)
    N = scipy.linalg.null_space(d.B.toarray())
    ev = np.linalg.eigvalsh(N.T @ d.K0.toarray() @ N)
    zero = np.abs(ev) <= 1e-10 * np.abs(ev).max()
    assert zero.sum() == 3
    assert ev[~zero].min() > 0


def test_mixed_sections_welded_rod_matches_full_system():
    """Two welded segments of different sections, clamped at both outer ends, held straight
    with natural curvature: engine vs exact general solutions with all joint conditions."""
    s1, s2 = CIRCLE, rectangle(aspect=2.0)
    # Held moments B3 kappa_n must balance at the weld: kappa_n = 1/1.5 in b (B3 = 1.5).
    segs = (Segment(name="a", length=0.6, curvature=0.0, natural_curvature=1.0, B1=s1.b1, B2=s1.b2,
                    B3=1.0),
            Segment(name="b", length=0.4, curvature=0.0, natural_curvature=1 / 1.5, B1=s2.b1 * 1.5,
                    B2=s2.b2 * 1.5, B3=1.5, start=(0.6, 0.0)))
    a = Assembly(segments=segs, welds=((("a", "end"), ("b", "start")),),
                 supports=(("a", "start", "clamped"), ("b", "end", "clamped")))
    full = matrix_roots(lambda mu: straight_assembly_matrix(a, mu), 0.2, 20.0, n_scan=400)
    r = linear_stability(a, 48)
    assert r.load_factor_critical == pytest.approx(full.roots[0].x, rel=1e-6)


def test_weld_out_of_moment_equilibrium_is_rejected():
    """A weld joining ends with different held moments B3 kappa_n is not an equilibrium."""
    segs = (Segment(name="a", length=0.6, curvature=0.0, natural_curvature=1.0, B1=1.0, B2=0.75,
                    B3=1.0),
            Segment(name="b", length=0.4, curvature=0.0, natural_curvature=1.0, B1=2.0, B2=1.0,
                    B3=1.5, start=(0.6, 0.0)))
    with pytest.raises(RodstabInputError, match="moment equilibrium"):
        Assembly(segments=segs, welds=((("a", "end"), ("b", "start")),),
                 supports=(("a", "start", "clamped"), ("b", "end", "clamped")))


@pytest.mark.parametrize("sec", [CIRCLE, RECT2], ids=["circle", "rect2"])
def test_eq_3_13_longest_arc_by_the_engine(sec):
    """Straight rod (kappa_n = 0) bent into a clamped arc: the engine's stable interval of the
    natural curvature loses mu = 0 at the L/R of (3.13)/(3.14) (analytic module, which the
    shooting method confirms)."""
    from rodstab.analytic.arc import max_arc_length
    from rodstab.numerics import find_roots

    target = max_arc_length(sec.b1, sec.b2).L_over_R_max

    def lower_end(L_over_R: float) -> float:  # natural curvature mu / R, R = 1
        r = linear_stability(clamped(L_over_R, 1.0, 1.0, sec), 128)
        return r.load_factor_interval[0]

    found = find_roots(lower_end, target - 0.3, target + 0.3, n_scan=6)
    assert found.roots[0].x == pytest.approx(target, rel=1e-6)
