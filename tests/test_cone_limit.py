"""The limits with contact at zero gap: the certified cone decision and its two discretisations.

Oracles: the closed form of copositivity of a 2 x 2 matrix; a local minimiser (SLSQP from
many starts, no code shared with the decision) on random small forms and cones; the FE engine
against eq. (3.2)'s closed-form Fourier pencils for the N-loop rings on the torus; the cone
test's own verdicts (:mod:`rodstab.multistable.cone`: a kept limit has a witness at once).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.optimize import brentq, minimize

from rodstab.errors import RodstabInputError
from rodstab.multistable.cone import contact_cone
from rodstab.multistable.cone_limit import cone_limits, ring_cone_limits
from rodstab.numerics.copositive import NOT_POSITIVE, POSITIVE, UNDECIDED, positive_on_cone
from rodstab.problems import birod, ring
from rodstab.sections import circle

#: The searches' bracket width here (relative): far below every tolerance asserted.
XT = 1e-4


def _slsqp_minimum(K: np.ndarray, D: np.ndarray, rng: np.random.Generator,
                   starts: int = 30) -> float:
    """Smallest v^T K v over {D v >= 0, |v| = 1} found by SLSQP from random starts."""
    best = math.inf
    for _ in range(starts):
        v0 = rng.normal(size=len(K))
        res = minimize(lambda v: v @ K @ v, v0 / np.linalg.norm(v0), jac=lambda v: 2 * K @ v,
                       method="SLSQP",
                       constraints=[{"type": "ineq", "fun": lambda v: D @ v, "jac": lambda v: D},
                                    {"type": "eq", "fun": lambda v: v @ v - 1,
                                     "jac": lambda v: 2 * v}])
        if np.min(D @ res.x) > -1e-8 and abs(res.x @ res.x - 1) < 1e-6:
            best = min(best, float(res.fun))
    return best


@pytest.mark.parametrize(("a", "b", "c"), [(1.0, -0.9, 1.0), (1.0, -1.1, 1.0), (2.0, 5.0, -0.1),
                                           (0.5, 3.0, 0.5), (-0.2, 1.0, 1.0),
                                           (4.0, -1.9, 1.0), (4.0, -2.1, 1.0)])
def test_two_by_two_on_the_orthant_is_the_closed_form(a: float, b: float, c: float) -> None:
    """[[a, b], [b, c]] is strictly copositive iff a > 0, c > 0 and b > -sqrt(a c)."""
    K = np.array([[a, b], [b, c]])
    expected = a > 0 and c > 0 and b > -math.sqrt(a * c)
    d = positive_on_cone(K, np.eye(2))
    assert d.status == (POSITIVE if expected else NOT_POSITIVE)
    if d.witness is not None:
        v = d.witness
        assert np.all(v >= -1e-9 * np.linalg.norm(v)) and v @ K @ v < 0


def test_random_forms_agree_with_a_local_minimiser() -> None:
    """Seeded: 40 random forms with 1-2 negative directions on random cones, n <= 7."""
    rng = np.random.default_rng(21)
    for _ in range(40):
        n, m, k = int(rng.integers(3, 8)), int(rng.integers(1, 8)), int(rng.integers(1, 3))
        Q, _ = np.linalg.qr(rng.normal(size=(n, n)))
        lam = np.r_[-rng.uniform(0, 1, k) * rng.choice([0.05, 1.0]), rng.uniform(0.2, 2, n - k)]
        K = Q @ np.diag(lam) @ Q.T
        D = rng.normal(size=(m, n))
        d = positive_on_cone(K, D)
        low = _slsqp_minimum(K, D, rng, starts=15)
        assert d.status in (POSITIVE, NOT_POSITIVE)
        if d.status == POSITIVE:
            assert low > -1e-7 and d.lower_bound > 0
        else:
            assert low < 1e-7


def test_random_forms_with_three_negative_directions_agree_with_a_local_minimiser() -> None:
    """Seeded: 25 random forms with 3 non-positive directions (the sphere's faces), n <= 8."""
    rng = np.random.default_rng(33)
    decided = 0
    for _ in range(25):
        n, m = int(rng.integers(4, 9)), int(rng.integers(2, 9))
        Q, _ = np.linalg.qr(rng.normal(size=(n, n)))
        lam = np.r_[-rng.uniform(0, 1, 3) * rng.choice([0.05, 1.0]), rng.uniform(0.2, 2, n - 3)]
        K = Q @ np.diag(lam) @ Q.T
        D = rng.normal(size=(m, n))
        d = positive_on_cone(K, D)
        assert d.negative_directions == 3
        low = _slsqp_minimum(K, D, rng, starts=15)
        if d.status == POSITIVE:
            assert low > -1e-7 and d.lower_bound > 0
        elif d.status == NOT_POSITIVE:
            assert low < 1e-7 and d.witness is not None
            assert np.all(D @ d.witness >= -1e-9 * np.linalg.norm(d.witness))
        decided += d.status != UNDECIDED
    assert decided >= 20  # a coverage floor, not a reference: 199 of 200 such forms decide


def test_four_negative_directions_is_undecided_not_positive() -> None:
    d = positive_on_cone(np.diag([-1.0, -1.0, -1.0, -1.0, 2.0]), np.eye(5)[:1])
    assert d.status == UNDECIDED and "4 non-positive" in d.message
    assert positive_on_cone(np.eye(3), np.eye(3)).status == POSITIVE


@pytest.mark.parametrize("loops", [2, 3])
@pytest.mark.slow
def test_fe_and_the_closed_form_fourier_modes_agree_on_the_rings(loops: int) -> None:
    """Two discretisations of the torus's cone (FE 12 el./loop, Fourier j <= 16) within 2e-3.

    Both brackets are certified for their own discretisation; at 24 elements and j <= 48 they
    agree to 3e-4 (docs/theory/contact.md). The 2-loop ring's lower limit is kept (mode j = 1
    keeps every gap): both put it at the no-contact limit.
    """
    sec = circle()
    fe = cone_limits(ring.build(ring.Params(section=sec, loops=loops)), "torus", 12, xtol=XT)
    fo = ring_cone_limits(sec.b1, sec.b2, loops, 16, 96, xtol=XT)
    for a, b in ((fe.lower, fo.lower), (fe.upper, fo.upper)):
        assert a is not None and b is not None
        assert a.status == b.status == "bracketed"
        assert a.load_factor == pytest.approx(b.load_factor, rel=2e-3)
        assert a.shift >= -1e-9 and b.shift >= -1e-9  # contact only widens the interval
    kept = fo.lower if loops == 2 else None
    if kept is not None:
        assert kept.shift < 1e-4
    else:
        assert min(fo.lower.shift, fo.upper.shift) > 0.1  # type: ignore[union-attr]


def test_a_kept_limit_has_a_witness_at_once_and_a_moved_one_certified_past_it() -> None:
    """The LP verdicts of the cone test (bi-rod kept; 3-loop ring moved) against the search."""
    a = birod.build(birod.Params(section=circle()))
    lay = {"upper": 0, "lower": 1}
    cone, lim = contact_cone(a, lay, 16), cone_limits(a, lay, 16, xtol=XT)
    for side, v in ((lim.lower, cone.lower), (lim.upper, cone.upper)):
        assert side is not None and v is not None and v.unchanged
        assert side.bracket[0] == side.no_contact
        assert side.shift <= XT * abs(side.no_contact)  # half the bracket: kept
    r3 = ring.build(ring.Params(section=circle(), loops=3))
    cone3, lim3 = contact_cone(r3, "torus", 8), cone_limits(r3, "torus", 8, xtol=XT)
    for sign, side, v in ((-1, lim3.lower, cone3.lower), (1, lim3.upper, cone3.upper)):
        assert side is not None and v is not None and not v.unchanged
        assert sign * (side.bracket[0] - side.no_contact) > 0.1  # certified positive past it


@pytest.mark.slow
def test_the_rod_engine_agrees_with_the_fe_on_heights_and_in_plane_motions_only_bring_back():
    """A third discretisation: the nonlinear rod's inextensible Hessian on the same cone.

    With the normals' heights only it poses the FE's question (within 1.5 % at 12 elements per
    loop; O(h^2): 0.3 % at 24). With the full normals an in-plane motion can open a gap, so
    the limit moves out no further than with heights only -- and never inward (contact only
    removes perturbations). The bi-rod's limits stay kept.
    """
    from rodstab.multistable.cone_limit import rod_cone_limits

    a = ring.build(ring.Params(section=circle(), loops=3))
    fe = cone_limits(a, "torus", 12, xtol=XT)
    height = rod_cone_limits(a, "torus", 12, normals="height", xtol=XT)
    full = rod_cone_limits(a, "torus", 12, xtol=XT)
    for f, h, u in ((fe.lower, height.lower, full.lower), (fe.upper, height.upper, full.upper)):
        assert f is not None and h is not None and u is not None
        assert h.load_factor == pytest.approx(f.load_factor, rel=1.5e-2)
        assert -1e-6 <= u.shift <= h.shift + 1e-6
        assert u.shift > 0.05  # still moved: the 3-loop ring's modes close gaps either way
    b = rod_cone_limits(birod.build(birod.Params(section=circle())), {"upper": 0, "lower": 1}, 16,
                        xtol=XT)
    assert b.upper is not None and b.upper.shift <= XT * abs(b.upper.no_contact)
    assert b.upper.no_contact == pytest.approx(math.pi * math.sqrt(circle().b1 * circle().b2),
                                               rel=5e-3)  # its own limit: Sec. 4, lambda = pi


def test_rod_cone_limits_refuses_an_unknown_normals_model():
    from rodstab.errors import RodstabInputError
    from rodstab.multistable.cone_limit import rod_cone_limits

    with pytest.raises(RodstabInputError, match="normals must be 'full' or 'height', got 'z'"):
        rod_cone_limits(ring.build(ring.Params(loops=2)), "torus", 8, normals="z")


def test_no_constraints_is_plain_definiteness_with_a_witness():
    """An empty cone matrix (no touching pair) never reaches the least-squares solve."""
    d = positive_on_cone(np.diag([-1.0, 2.0]), np.zeros((0, 2)))
    assert d.status == NOT_POSITIVE and d.witness is not None
    assert d.witness @ np.diag([-1.0, 2.0]) @ d.witness < 0


@pytest.mark.slow
def test_a_flat_strip_ring_found_by_the_differential_test():
    """benchmarks/differential.py --family contact-rings --seed 21 --index 14: a 2-loop ring of
    a flat strip (rectangle h/t = 7.52, b1/b2 = 33). At 16 elements per loop the FE's upper
    limit with contact was 5.6e-3 above the Fourier modes' (6.5616 against 6.5253, j <= 64); at
    32 it is within 1e-3 -- the FE's mesh error, now the differential test's mesh."""
    from rodstab.sections import make_section

    s = make_section(shape="rectangle", nu=0.0599, aspect=7.52)
    fe = cone_limits(ring.build(ring.Params(section=s, loops=2)), "torus", 32, xtol=XT)
    fo = ring_cone_limits(s.b1, s.b2, 2, 64, 256, xtol=XT)
    assert fe.upper is not None and fo.upper is not None
    assert fe.upper.load_factor == pytest.approx(fo.upper.load_factor, rel=1e-3)


def test_an_undecided_scan_load_is_bisected_for_a_witness_before_it():
    """Differential test, seed 22 index 33 (5-loop circle): the FE's scan stepped from a
    certified load past the limit to one where the next modes had crossed (4 non-positive
    directions: undecided), while the Fourier modes found the limit in between. The search
    now bisects towards the undecided load. Here with decisions given: positive below 1.33,
    a witness on [1.33, 1.38), undecided beyond."""
    from types import SimpleNamespace

    from rodstab.multistable.cone_limit import _search

    def decide(mu: float):
        status = POSITIVE if mu < 1.33 else NOT_POSITIVE if mu < 1.38 else UNDECIDED
        return SimpleNamespace(status=status, message="K has 4 non-positive directions")

    lim = _search(decide, 1.0, 1.0, 4.0, "upper", 1e-6)  # scan step 0.1: 1.1, ..., 1.4
    assert lim.status == "bracketed"
    assert lim.bracket[0] < 1.33 <= lim.bracket[1] and lim.bracket[1] - lim.bracket[0] < 1e-5
    never = _search(lambda mu: SimpleNamespace(
        status=POSITIVE if mu < 1.33 else UNDECIDED, message="m"), 1.0, 1.0, 4.0, "upper", 1e-6)
    assert never.status == "undecided" and never.bracket[0] == pytest.approx(1.33, abs=1e-5)


def test_a_witness_past_an_undecided_load_closes_the_bracket_from_the_last_certified_one():
    """The rod engine's 3-loop ring at 48 el./loop: a scan load next to the limit stayed
    undecided (one arc not certified in 80 solves) and no witness lay before it; the witness is
    at the next scan load. Decisions given: positive below 1.3, undecided on [1.3, 1.36), a
    witness from 1.36 on: the bracket runs from the last load certified (just below 1.3, by the
    bisection towards the undecided load) to the witness at 1.4, and says where it stopped."""
    from types import SimpleNamespace

    from rodstab.multistable.cone_limit import _search

    def decide(mu: float):
        status = POSITIVE if mu < 1.3 else UNDECIDED if mu < 1.36 else NOT_POSITIVE
        return SimpleNamespace(status=status, message="1 arc not certified")

    lim = _search(decide, 1.0, 1.0, 4.0, "upper", 1e-6)  # scan: 1.1, 1.2, 1.3 (undecided), 1.4
    assert lim.status == "bracketed"
    assert 1.2 <= lim.bracket[0] < 1.3 and lim.bracket[1] == pytest.approx(1.4)
    assert "1 arc not certified" in lim.message


def _folded_ring_on_its_hexagon():
    from rodstab.multistable.layer_orders import polygon_offsets
    from rodstab.multistable.states import ring_of
    from rodstab.problems import folded_ring

    a = folded_ring.build(folded_ring.Params())
    return a, polygon_offsets([k for k, _ in ring_of(a).order])


@pytest.mark.slow
def test_samples_graded_toward_the_welds_make_the_limit_mesh_independent(monkeypatch):
    """The folded ring's limit with contact (circle): the FE's gap samples are graded toward
    the welds, where the layers' order ties the strands, and the limit no longer moves with the
    mesh. Uniform samples (grading off) give 1.2357 and 1.2399 at 8 and 12 el. (measured);
    graded, 1.24840 at both, and the rod engine (nodes, a joint-graded row) agrees (1.2489).
    """
    from rodstab.multistable import cone
    from rodstab.multistable.cone_limit import rod_cone_limits

    a, lay = _folded_ring_on_its_hexagon()
    graded = [cone_limits(a, lay, n, xtol=XT).upper for n in (8, 12)]
    rod = rod_cone_limits(a, lay, 12, normals="height", xtol=XT).upper
    monkeypatch.setattr(cone, "WELD_GRADING", 0)
    uniform = [cone_limits(a, lay, n, xtol=XT).upper for n in (8, 12)]
    g = [s.load_factor for s in graded if s is not None]
    u = [s.load_factor for s in uniform if s is not None]
    assert len(g) == len(u) == 2 and rod is not None
    assert abs(g[1] - g[0]) <= 2e-4 * g[1] < abs(u[1] - u[0])
    assert rod.load_factor == pytest.approx(g[1], rel=3e-3)


def _eight(loops_per_lobe: int = 3, aspect: float = 4.0):
    from rodstab.multistable.states import uniform_ring
    from rodstab.sections import rectangle

    sec = rectangle(aspect=aspect)
    rg = uniform_ring(2 * loops_per_lobe, weld="cusp", natural_curvature=2 * math.pi / 3,
                      B1=sec.b1, B2=sec.b2)
    return rg.held(2 * math.pi)


def test_the_eight_is_recognised_and_its_lobes_get_flat_layers():
    from rodstab.multistable.cone import default_layers, figure_eight
    from rodstab.problems import hexagram

    for m in (2, 3, 4):
        a = _eight(m)
        assert figure_eight(a) == m
        layers, how = default_layers(a)
        assert layers == {str(k + 1): k // 2 for k in range(2 * m)} and "eight" in how
    for state in ("line", "star", "daisy"):
        assert figure_eight(hexagram.build(hexagram.Params(state=state))) == 0
    assert figure_eight(ring.build(ring.Params(loops=3))) == 0


def test_an_eight_with_two_strands_of_a_lobe_on_one_layer_is_refused():
    from rodstab.multistable.cone import contact_cone
    from rodstab.multistable.stacking import StackingError

    a = _eight()
    with pytest.raises(StackingError, match="'1' and '3'"):
        contact_cone(a, {"1": 0, "3": 0, "5": 1, "2": 0, "4": 1, "6": 2}, 8)
    with pytest.raises(RodstabInputError, match="missing"):
        contact_cone(a, {"1": 0, "3": 1, "5": 2, "2": 0, "4": 1}, 8)


def test_the_held_ring_reduced_theory_against_an_independent_full_model():
    """analytic.ring.held_ring_interval (the common motion and the strands' triangle turning,
    from the (3.2) pencil) against a full mode computation written without this code (all
    modes to a cutoff, the pair constraints imposed at many azimuths, resolution 1e-3 in
    the load; docs/theory/contact.md): circle (0.001, 5.584); rectangle h/t = 2 (-8.999,
    7.966), bound by the turning's n = 1 component. The circle reaches the outer bound, N
    times the one-loop interval; the rectangle does not."""
    from rodstab.analytic.ring import held_ring_interval, ring_stability
    from rodstab.sections import rectangle

    for sec, ref, upper_by in ((circle(), (0.001, 5.584), "common j=2"),
                               (rectangle(aspect=2.0), (-8.999, 7.966), "turning n=1")):
        r = held_ring_interval(sec.b1, sec.b2)
        assert r.kappa_L_over_2pi_interval == pytest.approx(ref, abs=2e-3)
        assert r.binding[1] == upper_by
        lo1, hi1 = ring_stability(sec.b1, sec.b2, 1).kappa_L_over_2pi_interval
        assert 3 * lo1 - 1e-12 <= r.kappa_L_over_2pi_interval[0]
        assert r.kappa_L_over_2pi_interval[1] <= 3 * hi1 + 1e-12


@pytest.mark.slow
def test_held_closed_rings_by_the_rod_against_the_reduced_theory():
    """rod_cone_limits(held_closed=True) on the 3-loop ring (definiteness on D v = 0) against
    analytic.ring.held_ring_interval, Richardson from 24 and 48 el./loop: the circle
    (measured 3e-4 on its lower end, 5e-5 relative on its upper), which reaches the outer
    bound, and the rectangle h/t = 2 (1e-4), whose upper end the triangle's turning sets.
    Before the samples toward the loops' junctions were dropped (they over-constrained) the
    rod gave the bound, 8.4254."""
    from rodstab.analytic.ring import held_ring_interval
    from rodstab.multistable.cone_limit import rod_cone_limits
    from rodstab.sections import rectangle

    N = 3
    for sec, meshes, sides in ((circle(), (24, 48), ("lower", "upper")),
                               (rectangle(aspect=2.0), (24, 48), ("upper",))):
        a = ring.build(ring.Params(section=sec, loops=N))
        ref = held_ring_interval(sec.b1, sec.b2).kappa_L_over_2pi_interval
        runs = [rod_cone_limits(a, "torus", n, held_closed=True, sides=sides) for n in meshes]
        for side, k in (("lower", 0), ("upper", 1)):
            if side not in sides:
                continue
            c, f = (getattr(r, side) for r in runs)
            assert c.status == f.status == "bracketed"
            value = (4 * f.load_factor - c.load_factor) / 3 * N
            assert abs(value - ref[k]) <= 2e-3 * max(abs(ref[k]), 1.0), (side, value, ref)
        assert "holding every touching pair's gap closed" in runs[1].method


@pytest.mark.slow
def test_the_folded_ring_in_two_columns_reaches_the_independent_pi_over_two():
    """The folded ring stacked in two columns (one loop per layer): its out-of-plane limit with
    contact is lam = pi / 2 by an independent derivation (helper-14: twist eliminated, the
    cross-layer welds tie every gap and slope at x = 0, Poincare), 3/2 of the paper's pi / 3;
    the FE cone within 1e-3 (measured 3.9e-4) on a rectangle h/t = 4, both sides."""
    from rodstab.analytic.folded_ring import TWO_COLUMNS, two_column_contact_limit
    from rodstab.multistable.states import ring_of
    from rodstab.problems import folded_ring
    from rodstab.sections import rectangle

    sec = rectangle(aspect=4.0)
    a = folded_ring.build(folded_ring.Params(section=sec))
    layers = dict(zip([k for k, _ in ring_of(a).order], TWO_COLUMNS, strict=True))
    fe = cone_limits(a, layers, 8, xtol=XT)
    exact = two_column_contact_limit() * math.sqrt(sec.b1 * sec.b2)
    assert fe.upper is not None and fe.lower is not None
    assert fe.upper.no_contact == pytest.approx(math.pi / 3 * math.sqrt(sec.b1 * sec.b2),
                                                rel=1e-4)
    for side in (fe.upper, fe.lower):
        assert side.status == "bracketed"
        assert abs(side.load_factor) == pytest.approx(exact, rel=1e-3)


@pytest.mark.parametrize("section", ["rectangle 4", "circle"])
@pytest.mark.slow
def test_the_line_in_two_columns_held_closed_converges_to_the_independent_pi(section):
    """The hexagram's line (the folded six-ring) in two columns with every touching pair held
    closed: the rod engine (full normals, in-plane motions included) converges at order 2 to
    lam = pi (helper-16's independent derivation, by hand in ``two_column_held_limit``),
    three times the no-contact pi / 3. Richardson from 12 / 16 el. within 3e-4 (measured
    1.0e-4 on the rectangle), observed order 1.7-2.3 from 8 / 12 / 16 el."""
    from rodstab.analytic.folded_ring import two_column_held_limit
    from rodstab.multistable.cone_limit import rod_cone_limits
    from rodstab.problems.barrier_states import state_assembly
    from rodstab.problems.hexagram import L_OVER_R0
    from rodstab.sections import rectangle

    sec = rectangle(aspect=4.0) if section == "rectangle 4" else circle()
    line = state_assembly("hexagram", sec, "line")
    two = {"1": (-0.5, 0), "3": (-0.5, 1), "5": (-0.5, 2),
           "2": (0.5, 0), "4": (0.5, 1), "6": (0.5, 2)}
    mu = [rod_cone_limits(line, two, n, held_closed=True, sides=("upper",)).upper.load_factor
          for n in (8, 12, 16)]
    exact = two_column_held_limit() * math.sqrt(sec.b1 * sec.b2) / L_OVER_R0
    ratio = (mu[0] - mu[1]) / (mu[1] - mu[2])
    order = brentq(lambda p: (8.0**-p - 12.0**-p) / (12.0**-p - 16.0**-p) - ratio, 0.5, 6.0)
    assert 1.7 <= order <= 2.3, (mu, order)
    extrapolated = (16**2 * mu[2] - 12**2 * mu[1]) / (16**2 - 12**2)
    assert extrapolated == pytest.approx(exact, rel=3e-4), (mu, exact)
    assert all(m > exact for m in mu)  # the discrete rod is stiffer, as on every mesh here


def test_the_folded_ring_on_the_hexagon_reaches_the_independent_root():
    """The folded ring stacked on the hexagon (the default): its out-of-plane limit with
    contact is the smallest positive root of (5 cos lam - 2) sin lam = lam (4 cos^2 lam - 1),
    1.4421095 (helper-15's independent derivation and FE, order 4, certified on a relaxed
    cone); the FE cone's certified bracket contains it (circle, 8 el.)."""
    from rodstab.analytic.folded_ring import hexagon_contact_limit
    from rodstab.multistable.layer_orders import polygon_offsets
    from rodstab.multistable.states import ring_of
    from rodstab.problems import folded_ring

    lam = hexagon_contact_limit()
    assert lam == pytest.approx(0.4590377152 * math.pi, rel=1e-9)  # the helper's root
    a = folded_ring.build(folded_ring.Params(section=circle()))
    fe = cone_limits(a, polygon_offsets([k for k, _ in ring_of(a).order]), 8, xtol=XT).upper
    assert fe is not None and fe.status == "bracketed"
    exact = lam * math.sqrt(0.75)
    assert fe.bracket[0] <= exact <= fe.bracket[1]


def test_a_tall_rectangle_on_the_hexagon_is_bracketed_around_the_root():
    """Found by the differential test (``--family folded-hexagon --seed 24 --index 7``):
    rectangle h/t = 9.126, nu = 0.465. The FE's certification stops after 80 solves with a
    bracket 3.6e-2 wide whose middle is 1.5e-3 from the derived root: the root must lie in
    the certified bracket (the middle is no more accurate than the bracket)."""
    from rodstab.analytic.folded_ring import hexagon_contact_limit
    from rodstab.multistable.layer_orders import polygon_offsets
    from rodstab.multistable.states import ring_of
    from rodstab.problems import folded_ring
    from rodstab.sections import make_section

    s = make_section(shape="rectangle", nu=0.465, aspect=9.126)
    a = folded_ring.build(folded_ring.Params(section=s))
    fe = cone_limits(a, polygon_offsets([k for k, _ in ring_of(a).order]), 12).upper
    assert fe is not None and fe.status == "bracketed"
    assert fe.bracket[0] <= hexagon_contact_limit() * math.sqrt(s.b1 * s.b2) <= fe.bracket[1]


def test_pairs_given_instead_of_a_layer_order_are_the_ones_used():
    """cone_limits(pairs=...): the torus's pairs given explicitly give the torus's limits to
    round-off; with no pairs at all (nothing touches) the limits are the no-contact ones."""
    from rodstab.multistable.cone import touching_pairs
    from rodstab.problems import ring

    a = ring.build(ring.Params(loops=3))
    plain = cone_limits(a, "torus", 12, sides=("lower",))
    given = cone_limits(a, "ignored", 12, sides=("lower",), pairs=touching_pairs(a, "torus", 12))
    assert given.lower.load_factor == pytest.approx(plain.lower.load_factor, rel=1e-12)
    free = cone_limits(a, "ignored", 12, sides=("lower",), pairs=[])
    assert free.lower.load_factor == pytest.approx(free.lower.no_contact, rel=1e-5)  # XTOL
    assert free.lower.load_factor > plain.lower.load_factor  # contact moves it outward


def test_held_closed_on_the_fe_out_of_plane_leaves_one_ring_n_times_as_stiff():
    """FE (out of plane only), every touching pair's height difference held at zero: only the
    strands' common motion is left, one ring three times as stiff, so the interval is N times
    the one-loop interval of eq. (3.3) (analytic.ring, independent of the cone code), for the
    wound (torus) and the folded (flat layers that swap) stackings alike."""
    from rodstab.analytic.ring import ring_stability

    sec = circle()
    a = ring.build(ring.Params(section=sec, loops=3))
    one = ring_stability(sec.b1, sec.b2, 1).kappa_L_over_2pi_interval
    for layers in ("torus", "folded"):
        r = cone_limits(a, layers, 24, held_closed=True)
        lo, hi = (3.0 * side.load_factor for side in (r.lower, r.upper))
        assert abs(lo - 3.0 * one[0]) < 1e-3 and abs(hi - 3.0 * one[1]) < 2e-3 * hi


@pytest.mark.slow
def test_the_folded_rings_cone_by_the_fe_and_by_the_rod_agree():
    """The 3-loop ring folded flat (layers that swap, rodstab.multistable.folding) at zero gap:
    the FE's cone (out of plane) and the rod engine's (in-plane motions too, another
    discretisation) give the same limits with contact, to the meshes' difference at 24 el.
    (measured 2.7e-3 lower, 7e-5 upper; 8e-4 and 7e-5 at 48 el.)."""
    from rodstab.multistable.cone_limit import rod_cone_limits

    a = ring.build(ring.Params(section=circle(), loops=3))
    fe, rod = cone_limits(a, "folded", 24), rod_cone_limits(a, "folded", 24)
    for f, r in ((fe.lower, rod.lower), (fe.upper, rod.upper)):
        assert abs(f.load_factor - r.load_factor) < 5e-3 * abs(f.load_factor)
    # contact moves both limits outward: the no-contact interval (eq. 3.3) is 2.147..3.859
    assert 3.0 * fe.lower.load_factor < 2.0 and 3.0 * fe.upper.load_factor > 4.5
