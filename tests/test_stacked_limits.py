"""N-loop rings held with contact and their limits with contact: rodstab.multistable.stacked.

Oracles: the closed form (3.3) of the no-contact interval (the same routine with contact off),
the thin limit h / L -> 0 (the planar coincident held state, its energy at second order), the
balance of internal forces (the contact forces of a free body sum to zero, force and moment),
the equilibrium of each loop (the elastic forces on its inner nodes balance the contact forces
there), and the bracket's own signs re-evaluated from fresh relaxations.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from rodstab.analytic.ring import ring_stability
from rodstab.errors import RodstabInputError
from rodstab.multistable.stacked import (
    _crossing,
    _side,
    contact_forces,
    describe,
    relax,
    stacked_contact_model,
    stacked_limits,
    stacked_ring,
    verdict_eigenvalue,
)
from rodstab.problems import ring
from rodstab.sections import circle

N = 3
#: Elements per loop of the tests (the benchmark uses 32): the thinnest ring here, h / L =
#: 0.005, has elements 2.2 h long; the chord allowance of the start stays below a / 2.
ELEMENTS = 12
EXPECTED_ORDER_ENERGY = 2.0  # the torus excess and the layers' both vanish as (h / L)^2
EXPECTED_ORDER_HEIGHT = 1.0  # the layers stand ~h apart
EXPECTED_ORDER_MESH = 2.0


def _ring():
    return ring.build(ring.Params(loops=N, section=circle()))


def _no_contact():
    s = circle()
    M_lo, M_hi = ring_stability(s.b1, s.b2, N).M_interval
    return 1.0 - M_hi, 1.0 - M_lo


@pytest.fixture(scope="module")
def relaxed():
    """The stacked ring (h / L = 0.01, dhat = 0.1 h) relaxed with contact at mu = 0.9."""
    a = _ring()
    rod, st = stacked_ring(a, thickness_ratio=0.01, elements_per_loop=ELEMENTS,
                           dhat_fraction=0.1, load_factor=0.9)
    ok, its, res = relax(rod, 0.9)
    assert ok
    return rod, st, describe(rod, st.rod, ok, its, res)


@pytest.mark.slow
def test_relaxed_state_tends_to_the_planar_held_state_as_h_vanishes(relaxed):
    """h / L = 0.01 and 0.005 at mu = 0.9: the relaxed ring's largest height falls like h
    (order 1 +- 0.2) and its energy's excess over the coincident planar ring (the held state,
    the same mesh and mu) like h^2 (order 2 +- 0.2), so both tend to the planar held state;
    every relaxed state carries contact (gap below dhat) and is stable."""
    a = _ring()
    rod, st = stacked_ring(a, thickness_ratio=0.005, elements_per_loop=ELEMENTS,
                           dhat_fraction=0.1, load_factor=0.9)
    ok, its, res = relax(rod, 0.9)
    thin = describe(rod, st.rod, ok, its, res)
    thick = relaxed[2]
    heights = np.array([thick.max_height, thin.max_height])
    excess = np.array([d.energy / d.energy_coincident - 1 for d in (thick, thin)])
    assert np.all(excess > 0) and np.all(heights > 0)
    assert abs(np.log(heights[0] / heights[1]) / np.log(2) - EXPECTED_ORDER_HEIGHT) <= 0.2
    assert abs(np.log(excess[0] / excess[1]) / np.log(2) - EXPECTED_ORDER_ENERGY) <= 0.2
    for d in (thick, thin):
        assert d.converged and d.stable and 0 < d.min_gap < d.dhat and d.contact_total > 0


def test_contact_forces_balance_over_free_bodies(relaxed):
    """The whole ring is a free body: its contact forces sum to zero, in force and in moment
    about any point (to round-off of their size). One loop is another: at equilibrium the
    elastic force on each of its inner nodes (not the welds) balances the contact force
    there, so the two totals over the loop's inner nodes are opposite (to Newton's
    tolerance)."""
    rod = relaxed[0]
    f = contact_forces(rod)
    scale = float(np.abs(f).sum())
    assert scale > 0
    assert np.abs(f.sum(axis=0)).max() <= 1e-12 * scale
    assert np.abs(np.cross(rod.x - rod.x[0], f).sum(axis=0)).max() <= 1e-11 * scale
    bare = rod.copy()
    bare.contact = None
    g = bare.gradient()[: 3 * len(rod.x)].reshape(-1, 3)  # elastic force = -g
    weld_nodes = {int(rod.edge_nodes[e, k]) for e, _, _, end in rod.end_links
                  for k in ((0,) if end == "start" else (1,))}
    for k in range(N):
        inner = sorted(set(rod.edge_nodes[rod.edge_segment == k].ravel().tolist()) - weld_nodes)
        fc, fe = f[inner].sum(axis=0), -g[inner].sum(axis=0)
        assert np.linalg.norm(fc) > 0 or np.abs(f[inner]).max() > 0
        assert np.linalg.norm(fc + fe) <= 1e-6 * scale


@pytest.mark.parametrize("elements", [16, 32])
@pytest.mark.slow
def test_without_contact_the_routine_gives_the_closed_form_interval(elements):
    """Contact off (the coincident planar ring, no contact model): the same following, scan
    and refinement gives eq. (3.3)'s interval, 2.1472 < (L/2pi) kappa_n < 3.8593 for the
    circle, to the mesh's O(l_e^2) error: below 1e-2 at 16 elements per loop and 3e-3 at 32,
    and falling at order 2 +- 0.3 between them (checked by the second parameter)."""
    lo, hi = _no_contact()
    r = stacked_limits(_ring(), (lo, hi), elements_per_loop=elements, contact=False)
    errs = np.array([abs(r.lower.limit - lo), abs(r.upper.limit - hi)]) * N
    assert np.all(errs < (1e-2 if elements == 16 else 3e-3))
    for side in (r.lower, r.upper):
        assert side.eigenvalues[0] > 0 > side.eigenvalues[1]
        assert min(side.bracket) <= side.limit <= max(side.bracket)
        assert "smooth crossing" in side.how
    test_without_contact_the_routine_gives_the_closed_form_interval.errs[elements] = errs
    if len(test_without_contact_the_routine_gives_the_closed_form_interval.errs) == 2:
        e16, e32 = (test_without_contact_the_routine_gives_the_closed_form_interval.errs[n]
                    for n in (16, 32))
        assert np.all(np.abs(np.log(e16 / e32) / np.log(2) - EXPECTED_ORDER_MESH) <= 0.3)


test_without_contact_the_routine_gives_the_closed_form_interval.errs = {}  # type: ignore


def test_following_with_contact_reports_no_unbracketed_limit(relaxed):
    """Following the relaxed ring with contact from mu = 0.9 down to 0.7 (steps of 0.05,
    halved where they leave the branch): every state on the recorded path is an
    equilibrium of the same branch, and a limit is reported only with a bracket whose two
    ends, recomputed here by fresh relaxations along the recorded path, have eigenvalues of
    opposite sign beyond the zero tolerance; with no limit, no recorded state is unstable."""
    rod, st, _ = relaxed
    side = _side(rod.copy(), st.rod, 0.9, -0.05, 0.7)
    lams = [p[1] for p in side.path]
    r = rod.copy()
    tol = verdict_eigenvalue(r)[1]
    for mu, lam, _, energy in side.path[1:]:
        assert relax(r, mu)[0]
        assert r.energy() == pytest.approx(energy, rel=1e-6)  # the same branch, recomputed
        assert np.sign(verdict_eigenvalue(r)[0]) == np.sign(lam)
    if math.isfinite(side.limit):
        a, b = side.bracket
        assert side.eigenvalues[0] > tol and side.eigenvalues[1] < -tol
        assert min(a, b) < side.limit < max(a, b) and "smooth" in side.how
    else:
        assert all(v > -tol for v in lams), side.how


def test_the_crossing_probe_tells_a_smooth_crossing_from_a_jump():
    """:func:`_crossing` on closed forms: ``f = 0.5 - mu`` crosses smoothly at 0.5; a step
    function (+1 below 0.5, -1 above: a state leaving its branch) is a jump, as is a function
    positive on both sides of the refined point (the unstable end reached on another branch,
    the 64-element case of :func:`_side`'s docstring)."""
    assert _crossing(lambda m: 0.5 - m, 0.5, 0.4, 0.6, 0.1, -0.1)[0] == "smooth"
    assert _crossing(lambda m: 1.0 if m < 0.5 else -1.0, 0.5, 0.4, 0.6, 1.0, -1.0)[0] == "jump"
    assert _crossing(lambda m: 1.0 if m < 0.5999 else -1.0, 0.5999, 0.4, 0.6, 1.0,
                     -1.0)[0] == "jump"


@pytest.mark.parametrize("case", ["smooth", "kink", "jump"])
def test_a_state_that_leaves_its_branch_is_a_branch_end_not_a_limit(relaxed, monkeypatch, case):
    """:func:`_side` with Newton replaced by a closed form in which every node moves by
    ``(mu - 0.9) v`` (``|v|`` = 0.01 L out of plane, ``L`` the mean segment length), and

    * "kink": below ``mu`` = 0.8 five times as fast (a branch bending sharply, as where a
      contact zone sets in): the secant misses, but relaxed back the state returns;
    * "jump": below 0.8 Newton lands on another branch 0.05 L away in the plane (as past a
      fold: the braided eight, the comment at :data:`JUMP_SECANT`), and a state there stays
      on it when relaxed at any load.

    Smooth and kinked, the search runs to its end; with the jump it halves its step
    :data:`HALVINGS` times and reports the branch's end bracketed at 0.8, with no limit."""
    import rodstab.multistable.stacked as stacked

    rod, st, _ = relaxed
    L = stacked.mean_length(rod)
    x0, v, J = rod.x.copy(), np.zeros_like(rod.x), np.zeros_like(rod.x)
    v[:, 2], J[:, 0] = 0.01 * L, 0.05 * L

    def closed_form(r, mu):
        on_other = case == "jump" and np.mean(r.x[:, 0] - x0[:, 0]) > 0.025 * L
        r.load_factor = float(mu)
        r.x = x0 + (mu - 0.9) * v
        if case == "kink" and mu < 0.8:
            r.x = x0 + (0.8 - 0.9) * v + 5.0 * (mu - 0.8) * v
        if on_other or (case == "jump" and mu < 0.8):
            r.x = r.x + J
        return True, 0, 0.0

    monkeypatch.setattr(stacked, "relax", closed_form)
    monkeypatch.setattr(stacked, "verdict_eigenvalue", lambda r: (1.0, 1e-12, False))
    side = _side(rod.copy(), st.rod, 0.9, -0.05, 0.7)
    assert math.isnan(side.limit)
    if case != "jump":
        assert side.searched_to == pytest.approx(0.7) and "no sign change" in side.how
        return
    lo, hi = sorted(side.bracket)
    assert lo < 0.8 <= hi and hi - lo <= 0.05 / 2**stacked.HALVINGS + 1e-12
    assert side.branch_end == lo and "JUMPS" in side.how and "no limit" in side.how
    assert side.outcome() == f"ends in ({hi:.4f}, {lo:.4f}): jumps"


@pytest.mark.parametrize("call, key", [
    (lambda: stacked_ring(_ring(), thickness_ratio=0.0, elements_per_loop=8,
                          dhat_fraction=0.1), "thickness_ratio"),
    (lambda: stacked_ring(_ring(), thickness_ratio=-0.01, elements_per_loop=8,
                          dhat_fraction=0.1), "thickness_ratio"),
    (lambda: stacked_ring(_ring(), thickness_ratio=0.01, elements_per_loop=8,
                          dhat_fraction=0.0), "dhat_fraction"),
    (lambda: stacked_ring(_ring(), thickness_ratio=0.01, elements_per_loop=8,
                          dhat_fraction=1.5), "dhat_fraction"),
    (lambda: stacked_ring(_ring(), thickness_ratio=0.01, elements_per_loop=0,
                          dhat_fraction=0.1), "elements_per_loop"),
    (lambda: stacked_contact_model(-1.0, 0.1, 0.1, 1.0, 1.0), "thickness"),
    (lambda: stacked_limits(_ring(), _no_contact(), start_load_factor=2.0), "start_load_factor"),
    (lambda: stacked_limits(_ring(), _no_contact(), start_load_factor=0.5), "start_load_factor"),
    (lambda: stacked_limits(_ring(), _no_contact(), start_load_factor=math.nan),
     "start_load_factor"),
    (lambda: stacked_limits(_ring(), (1.2, 0.8)), "no_contact"),
    (lambda: stacked_limits(_ring(), _no_contact(), scan_steps=0), "scan_steps"),
    (lambda: stacked_limits(_ring(), _no_contact(), window=-1.0), "window"),
])
def test_bad_input_names_the_key_and_value(call, key):
    """Each bad input raises RodstabInputError naming the key (and its value)."""
    with pytest.raises(RodstabInputError, match=key):
        call()

