"""Contact inside the nonlinear engine (issue 21, part 1): energy, Newton, stability, validation.

The assemblies. rodstab's ``Assembly`` holds disconnected segments (no weld needed), each with
its own supports, so two rods are one assembly of two segments and four supported ends. Its
held states lie in the plane ``z = 0``:

* stacked rods (case a) lie side by side *in the plane*, centrelines ``h`` apart along ``y``,
  loaded along ``-y`` (in-plane bending, stiffness ``B3``);
* crossing rods (case b) need two heights: the second rod is translated by ``-(h + g0) e3``
  after :func:`discretise` -- a rigid motion of an unloaded straight rod, which stays an
  equilibrium (its supports hold its nodes where they are).

Each rod is clamped at one end and *sliding-clamped* at the other (rotations and deflection
held, the end free to slide along the rod): an inextensible rod clamped at both ends at the
distance of its length cannot deflect at first order, so the linear clamped-clamped beam
(deflection ``F L^3 / (192 B)`` under a midspan force ``F``) is the sliding-clamped rod's.
"""

import contextlib
import math
from pathlib import Path

import numpy as np
import pytest
import scipy.sparse as sp
from contact_checks import sampled_min_gap

from rodstab.io.design import load_design
from rodstab.model import Assembly, Segment
from rodstab.nonlinear import contact as C
from rodstab.nonlinear import newton as N
from rodstab.nonlinear.discrete import discretise
from rodstab.nonlinear.newton import newton
from rodstab.nonlinear.stability import kirchhoff_eigenvalues, lowest_eigenvalues, lowest_modes
from rodstab.numerics import lowest_eigenpairs_on
from rodstab.problems import folded_ring
from rodstab.sections import circle

ROOT = Path(__file__).resolve().parents[1]
L, B, H = 1.0, 1.0, 0.01  # rod length, bending stiffness, thickness (capsule radius H / 2)
DELTA = 1e-3  # midspan deflection of the linear solutions, over L: (delta / L)^2 ~ 1e-6
EXPECTED_ORDER_DHAT = 1.0  # barrier gap ~ dhat (kappa by the rule, held at a fixed fraction)
EXPECTED_ORDER_MESH = 2.0  # Cayley curvature between edge frames: O(l_e^2)


# ---------------------------------------------------------------- builders
def _segment(name, *, stiffness=B, start=(0.0, 0.0), angle=0.0):
    return Segment(name=name, length=L, curvature=0.0, natural_curvature=0.0, B1=stiffness,
                   B2=stiffness / 1.3, B3=stiffness, start=start, angle=angle)


def _supports(*names):
    return tuple(s for n in names for s in ((n, "start", "clamped"), (n, "end", "sliding-clamp")))


def _nodes_of(rod, k):
    """Node indices of segment ``k`` (every segment has the same number of edges)."""
    return np.unique(rod.edge_nodes[rod.edge_segment == k])


def _load(rod, node, component, P):
    direction = np.zeros(3)
    direction[component] = -1.0
    rod.node_force[(int(node), component)] = (P, direction, rod.x[node].copy())


def _contact(rod, dhat, line_load):
    kappa = C.stiffness_for_line_load(line_load, dhat)
    rod.contact = C.mesh_of_rod(rod, C.ContactModel.from_thickness(H, dhat=dhat, stiffness=kappa))


def stacked(n, gap, P, dhat=None, *, stiffness=B):
    """Case (a): lower rod on y = 0, upper on y = H + gap, P along -y at the upper midspan."""
    a = Assembly(segments=(_segment("lo", stiffness=stiffness),
                           _segment("up", stiffness=stiffness, start=(0.0, H + gap))),
                 supports=_supports("lo", "up"))
    rod = discretise(a, n, 0.0)
    lo_mid, up_mid = (int(rod.edge_nodes[k * n + n // 2, 0]) for k in (0, 1))
    _load(rod, up_mid, 1, P)
    if dhat is not None:
        _contact(rod, dhat, P / L)
    return rod, lo_mid, up_mid


def single(n, P, stiffness):
    """One sliding-clamped rod, P along -y at its midspan, no contact."""
    rod = discretise(Assembly(segments=(_segment("a", stiffness=stiffness),),
                              supports=_supports("a")), n, 0.0)
    mid = int(rod.edge_nodes[n // 2, 0])
    _load(rod, mid, 1, P)
    return rod, mid


def contact_force(rod, nodes, component):
    """Total contact force (lab component) on ``nodes``: minus the contact energy's gradient."""
    g = C.contact_energy(rod.contact, rod.x)[1].reshape(-1, 3)
    return -float(g[nodes, component].sum())


def slope(x, y):
    return float(np.polyfit(np.log(x), np.log(y), 1)[0])


# ---------------------------------------------------------------- (c) no contact: nothing changes
def _fingerprints():
    """Evaluation and Newton numbers of two structures at a perturbed state (contact None).

    Projections on a fixed random vector ``w`` stand for the arrays: ``E``, ``g . w``,
    ``w . H w``, ``energy()``, ``gradient() . w``, the Frobenius norms of the Kirchhoff ``A``
    and ``G``; then Newton's ``ok`` and iterations, ``|x|``, ``x . w`` and the sum of the edge
    frames' entries at its end."""
    out = {}
    cases = {"six": discretise(folded_ring.build(folded_ring.Params(section=circle())), 8, 0.5),
             "hexagram": discretise(load_design(ROOT / "examples/hexagram.toml").assembly, 4,
                                    1.0)}
    for name, rod in cases.items():
        rng = np.random.default_rng(21)
        dq = np.zeros(rod.n_dof)
        free = rod.free_dofs()
        dq[free] = 1e-3 * rng.standard_normal(len(free))
        rod.apply(dq)
        E, g, Hs = rod.energy_terms()
        kh = rod.kirchhoff_hessian()
        w = np.random.default_rng(5).standard_normal(len(g))
        out[name] = [E, float(g @ w), float(w @ (Hs @ w)), rod.energy(), float(rod.gradient() @ w),
                     float(np.linalg.norm(kh.A.toarray())), float(np.linalg.norm(kh.G.toarray()))]
        ok, its, _ = newton(rod)
        xw = float(np.sum(rod.x * w[:rod.x.size].reshape(-1, 3)))
        out[name] += [ok, its, float(np.linalg.norm(rod.x)), xw, float(np.sum(rod.R_edge))]
    return out


#: Computed by this file's ``_fingerprints`` with the code of the merge commit 6cdfb9b (before
#: contact entered the engine; ``git archive 6cdfb9b src``), one BLAS thread. A regression
#: record, not a reference value. Compared to round-off, not bit for bit (a hash of the bytes
#: was recorded first: it would fail on a machine or numpy release that rounds differently):
#: the evaluations to ``EVAL_RTOL``, Newton's end state to ``NEWTON_RTOL`` (it stops at its
#: tolerance, where round-off may leave another last step), its iteration count exactly.
BEFORE_CONTACT = {
    "six": [68.7502104076787, -8393.07765196938, 102612186.65295006, 68.7502104076787,
             -8393.07765196938, 96029.34599699127, 5.809922132115764, True,
             4, 4.015594601052255, -1.1874869058195694, 48.00000006447759],
    "hexagram": [72.02293304136369, -32633.17166385584, 130170262.5981412, 72.02293304136369,
             -32633.17166385584, 549356.6628865802, 6.1104528491668795, True,
             5, 5.107552232668299, -11.559042141494478, 23.99999999986685],
}
EVAL_RTOL = 1e-12
NEWTON_RTOL = 1e-9


def test_no_contact_keeps_every_number_of_the_engine_before_contact():
    """``contact = None`` (the default): energy, gradient, Hessian (absolute and Kirchhoff) and a
    Newton solve of the folded six-ring and the hexagram are those of the commit before contact
    entered the engine (bit for bit on the machine that recorded them: checked then)."""
    now = _fingerprints()
    for name, before in BEFORE_CONTACT.items():
        got = now[name]
        assert got[:7] == pytest.approx(before[:7], rel=EVAL_RTOL), name
        assert got[7:9] == before[7:9], name
        assert got[9:] == pytest.approx(before[9:], rel=NEWTON_RTOL, abs=NEWTON_RTOL), name


def test_contact_out_of_reach_changes_no_bit():
    """A contact mesh whose pairs are all beyond reach (rods 10 h apart) adds exact zeros: the
    energy, gradient and Hessian are ``==`` those without contact, and Newton takes the same
    iterations to the same bits -- the with-contact code path adds nothing where nothing
    touches (the filter allows full steps)."""
    rods = []
    for with_contact in (False, True):
        rod, _, _ = stacked(8, 10 * H, 384 * B * DELTA / L**3, 1e-4 if with_contact else None)
        rods.append(rod)
    a, b = rods
    assert b.contact is not None and a.contact is None
    Ea, ga, Ha = a.energy_terms()
    Eb, gb, Hb = b.energy_terms()
    assert Ea == Eb and np.array_equal(ga, gb) and (Ha != Hb).nnz == 0
    ra, rb = newton(a), newton(b)
    assert ra == rb and np.array_equal(a.x, b.x) and np.array_equal(a.R_edge, b.R_edge)


# ---------------------------------------------------------------- energy and its derivatives
def pressed(kappa=1e4, dhat=1e-3, n=8, seed=3):
    """Case (a) with the rods at gap 0.3 dhat (no load), randomly perturbed by 1e-5: a state
    with active contact, not an equilibrium."""
    a = Assembly(segments=(_segment("lo"), _segment("up", start=(0.0, H + 0.3 * dhat))),
                 supports=_supports("lo", "up"))
    rod = discretise(a, n, 0.0)
    rod.contact = C.mesh_of_rod(rod, C.ContactModel.from_thickness(H, dhat=dhat,
                                                                   stiffness=kappa))
    rng = np.random.default_rng(seed)
    dq = np.zeros(rod.n_dof)
    free = rod.free_dofs()
    dq[free] = 1e-5 * rng.standard_normal(len(free))
    rod.apply(dq)
    return rod


def _pad(rod, Hc):
    n = rod.n_dof
    return sp.csr_matrix((Hc.tocoo().data, (Hc.tocoo().row, Hc.tocoo().col)), shape=(n, n))


def test_energy_gradient_hessian_are_rod_plus_contact():
    """With contact the rod's energy, gradient and Hessian are those without it plus
    :func:`contact_energy` (positions are the first 3 n_nodes dofs), at every order;
    ``gradient()`` is bit-identical to ``energy_terms()``'s; ``copy()`` shares the mesh."""
    rod = pressed()
    bare = rod.copy()
    bare.contact = None
    Ec, gc, Hc = C.contact_energy(rod.contact, rod.x)
    assert Ec > 0 and np.any(gc)
    E, g, Hs = rod.energy_terms()
    E0, g0, H0 = bare.energy_terms()
    assert E == pytest.approx(E0 + Ec, rel=1e-14)
    assert rod.energy() == E
    assert np.array_equal(rod.gradient(), g)
    np.testing.assert_allclose(g[: gc.size], g0[: gc.size] + gc, rtol=1e-12,
                               atol=1e-12 * abs(g).max())
    assert np.array_equal(g[gc.size:], g0[gc.size:])
    D = (Hs - H0 - _pad(rod, Hc)).toarray()
    assert np.max(np.abs(D)) <= 1e-12 * np.max(np.abs(Hs.toarray()))
    assert rod.copy().contact is rod.contact


def test_kirchhoff_hessian_with_contact_keeps_the_inertia():
    """Sylvester: in Kirchhoff coordinates (positions as sums of chords, contact added as
    ``T^T H_c T``) the free Hessian has as many negative eigenvalues as in the absolute
    coordinates (dense spectra), on a pressed state where contact *makes* them: the barrier's
    ``b'(g) < 0`` times the distance's curvature sideways lets the pressed rods roll off one
    another (two directions at kappa = 1e4; the rods alone: none). And the two quadratic forms
    agree on every increment: ``z^T A z = v^T H v`` for ``v`` = ``from_kirchhoff(z)``, as do
    the first variations (``g_z . z = g . v``)."""
    rod = pressed()
    free = rod.free_dofs()
    Hs = rod.energy_terms()[2][free][:, free].toarray()
    absolute = np.linalg.eigvalsh(0.5 * (Hs + Hs.T))
    kh = rod.kirchhoff_hessian()
    kirchhoff = lowest_eigenpairs_on(kh.A, kh.G, kh.border, kh.A.shape[0])[0]
    bare = rod.copy()
    bare.contact = None
    H0 = bare.energy_terms()[2][free][:, free].toarray()
    assert np.sum(np.linalg.eigvalsh(0.5 * (H0 + H0.T)) < 0) == 0
    assert len(kirchhoff) == len(free)
    assert np.sum(absolute < 0) == 2
    assert np.sum(kirchhoff < 0) == np.sum(absolute < 0)
    # The same quadratic form: z in the null space of G, mapped to the free increment v.
    G = kh.G.toarray()
    _, s, Vt = np.linalg.svd(G)
    null = Vt[np.sum(s > 1e-12 * s[0]):].T
    rng = np.random.default_rng(5)
    for _ in range(3):
        z = null @ rng.standard_normal(null.shape[1])
        v = rod.from_kirchhoff(kh, z)[free]
        assert z @ (kh.A @ z) == pytest.approx(v @ (Hs @ v), rel=1e-8)
        # and the same first variation (the gradient carries T^T g_c)
        assert kh.gradient @ z == pytest.approx(rod.gradient()[free] @ v, rel=1e-8)


def test_stability_uses_rod_plus_contact_hessian():
    """``lowest_modes`` and the verdict's eigenvalues (absolute and Kirchhoff coordinates) use
    the rod's Hessian plus the contact's, unprojected, with nothing to switch on: on the
    pressed state they equal those of ``H_rod + H_c`` assembled here and are negative (the
    rods roll off one another), while the rods alone are stable."""
    rod = pressed()
    bare = rod.copy()
    bare.contact = None
    Hsum = bare.energy_terms()[2] + _pad(rod, C.contact_energy(rod.contact, rod.x)[2])
    vals = lowest_modes(rod, 3)[0]
    np.testing.assert_allclose(vals, lowest_modes(rod, 3, hessian=Hsum)[0], rtol=1e-8)
    assert lowest_eigenvalues(rod, 1)[0] < 0 < lowest_eigenvalues(bare, 1)[0]
    assert kirchhoff_eigenvalues(rod, 1)[0] < 0 < kirchhoff_eigenvalues(bare, 1)[0]


def test_stacked_beams_roll_off_at_the_closed_form_load():
    """Stability with contact, against a closed form. In case (a) the lower rod carries
    F = P/2 at midspan, along the line of the centres. A sideways (z) shift u of the upper
    midspan relative to the lower tilts that line by u / h: the force gets a sideways part
    F u / h that pushes the shift on (a dead load on a cylinder), a negative stiffness F / h,
    against the relative z stiffness of the two clamped rods in series, 192 B1 / L^3 / 2. So
    the stacked equilibrium is stable while P < P_c = 192 B1 h / L^3 (the midspan deflection
    then reaches h / 2 when B3 = B1), and loses stability to the antisymmetric roll-off mode
    (upper and lower midspans opposite in z). Nothing about contact is switched on in the
    stability code: ``lowest_modes`` and the verdict's eigenvalues (absolute and Kirchhoff
    coordinates) see it through the energy. 32 elements, dhat = 1e-5: the sign changes
    between 0.95 and 1.05 P_c; the linearly interpolated root is within 1 % of P_c (measured
    0.997; the mesh's z compliance is 0.8 % high at 32 elements)."""
    from rodstab.nonlinear.stability import stability_eigenvalues

    Pc = 192 * B * H / L**3
    ev = []
    for f in (0.95, 1.05):
        rod, lo, up = stacked(32, 1e-5, f * Pc, 1e-5)
        assert newton(rod)[0]
        vals, vecs = lowest_modes(rod, 1)
        v = np.zeros(rod.n_dof)
        v[rod.free_dofs()] = vecs[:, 0]
        X = v[: 3 * len(rod.x)].reshape(-1, 3)
        assert X[up, 2] * X[lo, 2] < 0 and np.abs(X[:, 2]).max() == pytest.approx(
            max(abs(X[up, 2]), abs(X[lo, 2])))  # the midspans roll off, opposite ways
        assert np.abs(X[:, 1]).max() < 1e-6 * np.abs(X[:, 2]).max()
        verdict = stability_eigenvalues(rod, 1)[0][0]
        assert np.sign(verdict) == np.sign(vals[0]) == np.sign(kirchhoff_eigenvalues(rod, 1)[0])
        ev.append(vals[0])
    assert ev[0] > 0 > ev[1]
    root = 0.95 + 0.1 * ev[0] / (ev[0] - ev[1])
    assert root == pytest.approx(1.0, abs=0.01)


def test_stacked_beams_are_in_the_linear_limit(monkeypatch):
    """P -> 0: at fixed dhat / delta (= 1/100) the problem is scale-invariant in the linear
    limit (the rule's kappa ~ P / dhat makes the barrier's force scale with P), so the
    relative errors of the midspan deflection and of the contact force must not change
    between delta / L = 1e-3 and 1e-4 (32 elements): they agree to 1e-4 (geometric terms are
    (delta / L)^2 ~ 1e-6). Newton runs to 1/100 of its default tolerance, which is fixed in
    force and so at delta = 1e-4 leaves the deflection uncertain by up to 1.6e-4 of delta
    (measured: 0.0033223 or 0.0034870 by two iteration paths; 0.0034861 at 1/100)."""
    default = N.residual_tolerance
    monkeypatch.setattr(N, "residual_tolerance", lambda r: 1e-2 * default(r))
    rel = []
    for delta in (1e-3, 1e-4):
        P = 384 * B * delta / L**3
        rod, lo, _ = stacked(32, delta / 100, P, delta / 100)
        assert newton(rod)[0]
        F = -contact_force(rod, _nodes_of(rod, 0), 1)
        rel.append((-rod.x[lo, 1] / delta - 1, F / (P / 2) - 1))
    assert rel[0][0] == pytest.approx(rel[1][0], abs=1e-4)
    assert rel[0][1] == pytest.approx(rel[1][1], abs=1e-4)


# ---------------------------------------------------------------- Newton
@contextlib.contextmanager
def _fractions():
    """Record every step fraction the filter gives Newton (``newton.contact_fraction``)."""
    seen: list[float] = []
    orig = N.contact_fraction

    def spy(r, free, step):
        seen.append(orig(r, free, step))
        return seen[-1]

    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(N, "contact_fraction", spy)
        yield seen


def test_newton_filters_steps_and_never_interpenetrates():
    """Case (a) at 16 elements from the unloaded state: the first Newton step (the upper rod
    alone, deflecting 2 delta through a gap of dhat) is shortened by the step filter, no trial
    closes a gap (every evaluated state has positive gaps: :class:`Interpenetration` is never
    raised), and Newton converges."""
    rod, _, _ = stacked(16, 1e-4, 384 * B * DELTA / L**3, 1e-4)
    with _fractions() as alphas:
        ok, its, _ = newton(rod)
    assert ok and alphas[0] < 0.2 and len(alphas) >= its
    assert C.contact_energy_value(rod.contact, rod.x) > 0  # in contact


def test_a_step_the_filter_cuts_to_a_sliver_raises_the_shift_first():
    """Case (a) at 16 elements from the unloaded state, the rods 1e-5 L apart (dhat too): the
    pure Newton step (the upper rod through the lower one, 2e-3 L) would be cut below
    ``CUT_RETRY`` of itself. ``lm_step`` then counts it as a rejection and raises the shift
    until the filter leaves at least that fraction (or the shift reaches ``LAM_CUT_MAX``): it
    does not take the sliver at the pure Newton shift 0. (Taking such slivers, each lowering
    the energy a little, was how Newton crawled: 600 iterations on a stacked line,
    docs/theory/contact.md.)"""
    rod, _, _ = stacked(16, 1e-5, 384 * B * DELTA / L**3, 1e-5)
    free = rod.free_dofs()
    E, g, H = rod.energy_terms()
    Hf = H[free][:, free].tocsc()
    with _fractions() as taken:
        terms, lam = N.lm_step(rod, free, E, g[free], 0.5 * (Hf + Hf.T), 0.0, 1e-12)
    assert terms is not None and taken[0] < N.CUT_RETRY  # the pure Newton step: a sliver
    assert lam > 0.0 and (taken[-1] >= N.CUT_RETRY or lam >= N.LAM_CUT_MAX)


def test_newton_rejects_trials_that_interpenetrate():
    """With the step filter switched off (fraction 1), the first full step puts the upper rod
    into the lower one: that trial raises :class:`Interpenetration` inside ``lm_step``, which
    rejects it like an energy increase (the shift grows); Newton still converges to the
    filtered solve's equilibrium, and no exception leaves it."""
    P = 384 * B * DELTA / L**3
    ref, _, up = stacked(16, 1e-4, P, 1e-4)
    assert newton(ref)[0]
    rod, _, _ = stacked(16, 1e-4, P, 1e-4)
    raised = []
    orig = C.contact_terms

    def spy(mesh, x, order):
        try:
            return orig(mesh, x, order)
        except C.Interpenetration:
            raised.append(order)
            raise

    import rodstab.nonlinear.discrete as D

    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(N, "contact_fraction", lambda r, f, s: 1.0)
        mp.setattr(D, "contact_terms", spy)
        ok = newton(rod, max_iter=200)[0]
    assert raised and ok
    assert rod.x[up, 1] == pytest.approx(ref.x[up, 1], rel=1e-6)


def test_a_retraction_into_interpenetration_is_dropped():
    """``_retract_if_lower`` with contact: when the retraction moves nodes into interpenetration
    the plain trial is kept (no exception), as it is when the retraction raises the energy."""
    import rodstab.nonlinear.constraint as K

    rod, _, up = stacked(8, 1e-4, 1.0, 1e-4)
    nodes = _nodes_of(rod, 1)

    def sink(trial, dq):  # a "retraction" that pushes the upper rod into the lower one
        trial.x[nodes, 1] -= 2 * H

    plain = rod.copy()
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(K, "retract_step", sink)
        N._retract_if_lower(rod, np.zeros(rod.n_dof))
    assert np.array_equal(rod.x, plain.x)


# ---------------------------------------------------------------- (a) stacked beams
DHATS_A = (1e-4, 3e-5, 1e-5, 3e-6)


def test_stacked_clamped_beams_deflect_as_one_beam_of_twice_the_stiffness():
    """Two identical sliding-clamped rods (L, B) stacked at centreline distance h + dhat (gap
    dhat: touching, no preload), a dead force P = 384 B delta / L^3 at the upper midspan
    towards the lower one. Linear limit (delta / L = 1e-3): both deflect as one clamped beam
    of stiffness 2B, midspan deflection ``P L^3 / (384 B) = delta`` (Roark, fixed-fixed beam
    with a centre load, F L^3 / (192 E I), with E I = 2B).

    Where the force goes (derived): with equal deflections ``w_up = w_lo = w``, ``B w'''' =
    P delta_D(x - L/2) - q`` (upper) and ``B w'''' = q`` (lower) give ``q = P/2
    delta_D(x - L/2)``: the lower rod carries P/2, all of it at midspan, none elsewhere
    (although the rods touch over their whole length). So: total contact force -> P/2, and
    concentrated at midspan.

    Convergence, 64 elements per rod, kappa by the rule (P/L held at dhat/2). Errors of the
    lower rod's midspan deflection against the discrete limit dhat -> 0 on the same mesh (one
    rod of 2B, no contact: equal discrete rods sharing the midspan force P/2 deflect as one,
    exactly), and of the contact force against P/2 (measured 2026-12-05):

    ====== ============ ========== ============== ========= ===========
    dhat   delta_lo/δ-1 vs limit    F_lo/(P/2)-1  order (F) Newton its
    ====== ============ ========== ============== ========= ===========
    1e-4   -3.45e-2     -3.65e-2    2.61e-2                 6
    3e-5   -1.02e-2     -1.21e-2    1.66e-2       0.37      6
    1e-5   -2.40e-3     -4.36e-3    8.91e-3       0.57      7
    3e-6   +5.72e-4     -1.39e-3    4.10e-3       0.62      8
    ====== ============ ========== ============== ========= ===========

    Observed order of the deflection 0.91, 0.93, 0.95 (expected 1: the upper rod stands
    ``dhat - g`` above the lower, ``g`` a fixed fraction of dhat); of the force below 1 and
    rising (the force spreads over the span where the gap is below dhat, which shrinks more
    slowly). The mesh part (one rod of 2B vs the closed form) is order 2: +1.96e-3 at 64.
    Newton's iterations were 4, 8, 10, 23 and more than 60 at dhat = 1e-6 while the step filter
    bounded each pair by its nodes' relative speed (a gap ~1e-3 of the deflection let a step
    close at most 0.9 of it); with the sampled certificate (``max_step_fraction``), 10 at 1e-6.
    """
    n = 64
    P = 384 * B * DELTA / L**3
    exact = P * L**3 / (384 * B)
    limit_rod, mid = single(n, P, 2 * B)
    assert newton(limit_rod)[0]
    limit = -limit_rod.x[mid, 1]
    e_lo, e_up, e_f, conc = [], [], [], []
    for dhat in DHATS_A:
        rod, lo, up = stacked(n, dhat, P, dhat)
        ok = newton(rod)[0]
        assert ok
        d_lo, d_up = -rod.x[lo, 1], (H + dhat) - rod.x[up, 1]
        e_lo.append(abs(d_lo - limit) / exact)
        e_up.append(abs(d_up - limit) / exact)
        lower = _nodes_of(rod, 0)
        F = -contact_force(rod, lower, 1)  # along -y
        e_f.append(abs(F / (P / 2) - 1))
        g = -C.contact_energy(rod.contact, rod.x)[1].reshape(-1, 3)[lower, 1]
        central = np.abs(rod.x[lower, 0] - L / 2) <= 0.1 * L
        conc.append(-g[central].sum() / F)
        assert 0 < d_up - d_lo < dhat  # the upper rod above the lower, within the barrier
    assert slope(DHATS_A, e_lo) >= EXPECTED_ORDER_DHAT - 0.2
    assert slope(DHATS_A, e_up) >= EXPECTED_ORDER_DHAT - 0.2 - 0.3  # + (dhat - g): same order
    assert all(a > b for a, b in zip(e_f, e_f[1:], strict=False)) and e_f[-1] < 5e-3
    assert all(a < b for a, b in zip(conc, conc[1:], strict=False)) and conc[-1] > 0.9
    # Against the closed form: the mesh part (order 2) plus the dhat part.
    assert abs(limit / exact - 1) < 2.5e-3
    assert e_lo[-1] + abs(limit / exact - 1) < 4e-3


def test_the_dhat_limit_of_stacked_beams_converges_to_the_closed_form_with_the_mesh():
    """The discrete limit dhat -> 0 of case (a) (one rod of 2B under P) against ``P L^3 /
    (384 B)`` at 8, 16, 32, 64 elements: observed order 2 (errors 0.126, 0.0314, 0.00786,
    0.00196, measured)."""
    P = 384 * B * DELTA / L**3
    errs = []
    ns = (8, 16, 32, 64)
    for n in ns:
        rod, mid = single(n, P, 2 * B)
        assert newton(rod)[0]
        errs.append(abs(-rod.x[mid, 1] / (P * L**3 / (384 * B)) - 1))
    assert -slope(ns, errs) >= EXPECTED_ORDER_MESH - 0.2


# ---------------------------------------------------------------- (b) crossing on a rigid rod
DHATS_B = (1e-4, 1e-5, 1e-6)


def _clamped_deflection(x, a):
    """Clamped-clamped beam (L, B): deflection at ``x`` under a unit force at ``a`` (Roark,
    fixed-fixed beam, intermediate load: ``b^2 x^2 (3 a L - (3 a + b) x) / (6 B L^3)``)."""
    if x > a:
        x, a = L - x, L - a
    b = L - a
    return b * b * x * x * (3 * a * L - (3 * a + b) * x) / (6 * B * L**3)


def crossing(n, g0, P, dhat):
    """Rod A on the x axis, rod B along y under A's midspan at centreline distance H + g0
    (B's nodes held: a rigid rod); P along -z, half on each node of A's middle element."""
    a = Assembly(segments=(_segment("a"), _segment("b", start=(L / 2, -L / 2),
                                                   angle=math.pi / 2)),
                 supports=_supports("a", "b"))
    rod = discretise(a, n, 0.0)
    nb = _nodes_of(rod, 1)
    rod.x[nb, 2] -= H + g0
    rod.fixed_nodes = sorted(set(rod.fixed_nodes) | set(nb.tolist()))
    mid = rod.edge_nodes[(n - 1) // 2]
    for k in mid:
        _load(rod, k, 2, P / 2)
    _contact(rod, dhat, P / L)
    return rod, mid, nb


def test_rod_pressed_onto_a_crossing_rigid_rod():
    """A sliding-clamped rod (L, B) pressed by P along -z onto a perpendicular rod crossing
    under its midspan at gap g0 = delta, P = 2 x 192 B g0 / L^3 (free deflection 2 g0). The
    second rod is rigid (its nodes held): the limit of B x 1e4, which Newton's tolerance
    cannot resolve (it scales with the largest stiffness: 0.033 on forces of 0.2 at 1e4,
    measured). 33 elements per rod, so the crossing is at the middle of both middle elements
    and only the edge-edge (X) term acts (asserted).

    Closed forms: the midspan deflection is g0 minus the barrier's gap (< dhat, -> 0 with
    it: order 1); the contact force is ``P - 192 B g0 / L^3`` (= P/2 here) in the continuum,
    and ``P - 2 w / c`` for the discrete loading (P/2 and F/2 on the two nodes of the middle
    element, ``c = G(a, a) + G(L - a, a)`` the clamped beam's influence, w their deflection).
    Measured (2026-12-05):

    ===== ====== ========== ===== ======================== ==============
    n     dhat   w/g0 - 1   order F/(P - 192 B g0/L^3) - 1 F/(P - 2w/c)-1
    ===== ====== ========== ===== ======================== ==============
    33    1e-4   -2.89e-3         +4.75e-3                 +7.18e-3
    33    1e-5   -2.89e-4   1.00  +2.16e-3                 +7.22e-3
    33    1e-6   -2.90e-5   1.00  +1.90e-3                 +7.23e-3
    65    1e-5   -1.41e-4         +6.43e-4                 +1.90e-3
    ===== ====== ========== ===== ======================== ==============

    The last column is the discrete rod's compliance error (order 2 in the mesh: 3.8x from 33
    to 65 elements); against the continuum form it partly cancels the split loading's -0.5 %.
    """
    n, g0 = 33, DELTA
    P = 2 * 192 * B * g0 / L**3
    errs = []
    for dhat in DHATS_B:
        rod, mid, nb = crossing(n, g0, P, dhat)
        assert newton(rod)[0]
        nt, on, ee = C._active(rod.contact, rod.x)
        assert not on.any() and len(ee) == 1  # the X term alone
        w = -float(rod.x[mid, 2].mean())
        assert 0 < g0 - w < dhat
        errs.append(g0 - w)
        F = -contact_force(rod, nb, 2)  # along -z on the lower rod
        assert F == pytest.approx(P - 192 * B * g0 / L**3, rel=1e-2)
        a = L / 2 + L / (2 * n)
        c = _clamped_deflection(a, a) + _clamped_deflection(L - a, a)
        assert F == pytest.approx(P - 2 * w / c, rel=1e-2)
    assert abs(slope(DHATS_B, errs) - EXPECTED_ORDER_DHAT) <= 0.2
    mesh_err = []
    for m in (n, 2 * n - 1):  # odd: the crossing stays mid-element
        rod, mid, nb = crossing(m, g0, P, DHATS_B[1])
        assert newton(rod)[0]
        w = -float(rod.x[mid, 2].mean())
        a = L / 2 + L / (2 * m)
        c = _clamped_deflection(a, a) + _clamped_deflection(L - a, a)
        mesh_err.append(abs(-contact_force(rod, nb, 2) / (P - 2 * w / c) - 1))
    assert np.log(mesh_err[0] / mesh_err[1]) / np.log((2 * n - 1) / n) >= EXPECTED_ORDER_MESH - 0.2


# ---------------------------------------------------------------- the step filter, rods together
def _sampled_min_gap(mesh, x, dx, alpha, n_time=80, n_pts=41):
    """Smallest gap of all non-excluded element pairs along the step (contact_checks)."""
    E = mesh.edges
    pairs = [(a, b) for a in range(len(E)) for b in range(a + 1, len(E))
             if not mesh.excluded_elements(np.array([a]), np.array([b]))[0]]
    return sampled_min_gap(mesh, x, dx, alpha, pairs, n_time=n_time, n_pts=n_pts)


def test_step_filter_lets_stacked_rods_turn_together_and_still_stops_closing():
    """Two stacked rods (4 elements each, gap 0.2 dhat) turned together by a linearised
    rotation of 0.3 rad about an axis across them: distances cannot shrink under it
    (``|r + w x r| >= |r|``), so the full step is allowed -- the pair's mean translation alone
    would allow only ~gap / (rotation x length). Adding a closing motion of the upper rod
    (5 gaps towards the lower one) brings the fraction back below 1, and the sampled gaps
    along the filtered step stay positive."""
    r, dhat = 0.05, 0.01
    s = np.linspace(0.0, 1.0, 5)
    x = np.concatenate([np.stack([s, 0 * s, 0 * s], 1),
                        np.stack([s, 0 * s, 0 * s + 2 * r + 0.2 * dhat], 1)])
    edges = np.array([[i, i + 1] for i in range(4)] + [[5 + i, 6 + i] for i in range(4)])
    mesh = C.contact_mesh(edges, np.full(8, 0.25), x, C.ContactModel(r, dhat, 1.0))
    w = np.array([0.0, 0.3, 0.0])  # about y: the rods' ends move along z, opposite ways
    dx = np.cross(w, x - x.mean(axis=0))
    assert C.max_step_fraction(mesh, x, dx) == 1.0
    assert _sampled_min_gap(mesh, x, dx, 1.0) > 0
    dx[5:, 2] -= 5 * 0.2 * dhat
    alpha = C.max_step_fraction(mesh, x, dx)
    assert 0 < alpha < 0.25
    assert _sampled_min_gap(mesh, x, dx, 1.0) < 0  # the full step would interpenetrate
    assert _sampled_min_gap(mesh, x, dx, alpha) > 0


# ------------------------------------------------------- rodstab equilibrium DESIGN --contact
def test_equilibrium_with_contact_where_nothing_touches_is_the_same_equilibrium(run_cli):
    """The clamped arc (examples/clamped_arc.toml, L = 2) never comes near itself: with
    --contact the barrier has no term within reach, so the energy, residual and eigenvalues are
    those without contact (to round-off), and the contact block says so (no pair within reach,
    zero force), with the rule's model: h = 0.02 L = 0.04, dhat = 0.1 h."""
    import json

    args = ["equilibrium", "examples/clamped_arc.toml", "--elements", "16", "--json"]
    plain = json.loads(run_cli(args).stdout)
    r = run_cli([*args, "--contact"])
    assert r.exit_code == 0, r.stderr
    got = json.loads(r.stdout)
    assert got["energy"] == pytest.approx(plain["energy"], abs=1e-14)
    assert got["lowest_eigenvalues"] == pytest.approx(plain["lowest_eigenvalues"], rel=1e-9)
    assert "contact" not in plain
    c = got["contact"]
    assert c["thickness"] == pytest.approx(0.04, rel=1e-12)
    assert c["dhat"] == pytest.approx(0.004, rel=1e-12)
    assert c["thickness_ratio"] == 0.02
    assert c["smallest_gap"] is None and c["active_pairs"] == 0 and c["total_force"] == 0.0


@pytest.mark.parametrize("extra, words", [
    (["--contact"], "already interpenetrate"),  # the folded ring's rods coincide
    (["--contact"], "need a layer order that stacks them apart (--layers"),  # what to do
    (["--contact-thickness", "0.05"], "--contact-thickness is a setting of contact, which is "
                                      "off"),
    (["--contact", "--contact-dhat", "1"], "--contact-dhat must be below 1"),
    (["--contact", "--contact-thickness", "-0.1"], "--contact-thickness must be a finite"),
    (["--contact", "--contact-thickness", "2"], "--contact-thickness must be at most 1"),
])
def test_equilibrium_contact_bad_input_exits_2_naming_it(run_cli, extra, words):
    """A held state whose rods already interpenetrate, contact options without --contact, a
    dhat of h or more, a thickness outside (0, 1] of L: exit 2 naming the option or elements."""
    r = run_cli(["equilibrium", "examples/folded_six_ring.toml", "--elements", "4", *extra])
    assert r.exit_code == 2, r.stderr
    assert words in r.stderr


def test_contact_state_of_pressed_stacked_beams_reports_gap_and_force():
    """Case (a) relaxed (16 elements per rod, dhat = 1e-5): the contact state's smallest gap is
    inside (0, dhat), between an element of each rod; its contact force -- half the sum of the
    node forces' magnitudes -- is the force on the lower rod (every node's force points one
    way along y on each rod, up to the slope), which the derivation of the stacked-beams test
    gives as P / 2 (the lower rod carries half the midspan force), within the dhat error
    measured there."""
    n, dhat = 16, 1e-5
    P = 384 * B * DELTA / L**3
    rod, _, _ = stacked(n, dhat, P, dhat)
    assert newton(rod)[0]
    st = C.contact_state(rod.contact, rod.x)
    assert 0.0 < st.smallest_gap < st.dhat == dhat
    assert (st.pair[0] < n) != (st.pair[1] < n)  # one element of each rod
    assert st.active_pairs > 0 and st.thickness == pytest.approx(H, rel=1e-12)
    lower = _nodes_of(rod, 0)
    # Magnitudes, not y components: the contact normals tilt with the rods' slope (~delta/L),
    # which adds (1e-3)^2 / 2 relative.
    assert st.total_force == pytest.approx(-contact_force(rod, lower, 1), rel=1e-5)
    assert st.total_force == pytest.approx(P / 2, rel=0.03)


def test_design_file_asks_for_contact_and_the_command_line_overrides_it(run_cli, tmp_path):
    """``[analysis] contact = true`` (with its thickness and dhat) turns contact on for
    ``equilibrium``; ``--no-contact`` turns it off for one run (no contact block, the
    numbers without contact); ``--contact-thickness`` replaces the design's thickness. A
    contact setting without ``contact = true`` and a dhat of h or more are refused, naming
    the key and value (exit 2)."""
    import json

    base = (ROOT / "examples" / "clamped_arc.toml").read_text()
    f = tmp_path / "arc.toml"
    f.write_text(base + "\n[analysis]\ncontact = true\ncontact_thickness = 0.03\n"
                 "contact_dhat = 0.2\n")
    args = ["equilibrium", str(f), "--elements", "12", "--json"]
    on = json.loads(run_cli(args).stdout)["contact"]
    assert on["thickness_ratio"] == 0.03
    assert on["thickness"] == pytest.approx(0.03 * 2.0, rel=1e-12)  # L = 2
    assert on["dhat"] == pytest.approx(0.2 * 0.06, rel=1e-12)
    assert "contact" not in json.loads(run_cli([*args, "--no-contact"]).stdout)
    over = json.loads(run_cli([*args, "--contact-thickness", "0.01"]).stdout)["contact"]
    assert over["thickness_ratio"] == 0.01 and over["dhat"] == pytest.approx(0.2 * 0.02)
    for extra, words in (("contact_thickness = 0.03", "analysis.contact_thickness is a "
                          "setting of analysis.contact = true"),
                         ("contact = true\ncontact_dhat = 1.0", "analysis.contact_dhat must "
                          "lie in (0, 1)")):
        bad = tmp_path / "bad.toml"
        bad.write_text(base + f"\n[analysis]\n{extra}\n")
        r = run_cli(["equilibrium", str(bad), "--elements", "12"])
        assert r.exit_code == 2 and words in r.stderr, r.stderr



@pytest.mark.parametrize("command", [["sweep", "--vary", "section.aspect=1:2:2"]],
                         ids=["sweep"])
def test_a_design_asking_for_contact_is_refused_where_there_is_no_contact_model(
        run_cli, tmp_path, command):
    """``[analysis] contact = true`` in a command without a contact model (a sweep): exit 2
    naming the key and the command, instead of dropping it (analyze has the cone test:
    tests/test_cone.py)."""
    f = tmp_path / "arc.toml"
    f.write_text((ROOT / "examples" / "clamped_arc.toml").read_text()
                 + "\n[analysis]\ncontact = true\n")
    r = run_cli([command[0], str(f), *command[1:], "--out", str(tmp_path / "o")]
                if command[0] != "analyze" else [command[0], str(f)])
    assert r.exit_code == 2, r.stderr
    assert "analysis.contact = true" in r.stderr and f"rodstab {command[0]}" in r.stderr


# ---------------------------------------------------- continuation with contact (rodstab continue)
def _pushed_pair(theta=0.0, gap=0.002):
    """Two sliding-clamped rods side by side in the plane, ``h + gap`` apart; the upper one's
    clamped start turned by ``theta`` about e3 (negative: towards the lower rod)."""
    rot = (("up", "start", (0.0, 0.0, theta)),) if theta else ()
    return Assembly(segments=(_segment("lo"), _segment("up", start=(0.0, H + gap))),
                    supports=_supports("lo", "up"), end_rotations=rot)


def test_continuation_with_contact_reaches_newtons_equilibrium_and_keeps_every_gap():
    """Turning the upper rod's clamp by up to -0.05 rad pushes it onto the lower rod (without
    contact it bends 0.0074 L, through the lower rod: its centreline ends closer than h). The
    continuation with contact (corrector with the step filter) and Newton from the held state
    with the clamp turned at once (an independent path) reach the same equilibrium: energies
    equal to 1e-9, the same smallest gap, inside (0, dhat); every point of the path keeps a
    positive gap (an overlap would raise)."""
    from rodstab.nonlinear.continuation import continuation
    from rodstab.nonlinear.equilibrium import equilibrium

    model = C.ContactModel.for_rods(H, dhat_fraction=0.1, bending_stiffness=B, length=L)
    path = continuation(_pushed_pair(), "support.2.rotation.binormal", 0.0, -0.05, 10,
                        elements_per_segment=16, branch_steps=0, contact=model)
    assert path.converged and path.value[-1] == -0.05
    c = path.contact
    assert c is not None and 0.0 < c["smallest_gap"] < model.dhat
    assert c["smallest_gap_value"] == -0.05 and c["points_checked"] >= 10
    # the rods lie end over end: their end nodes project on the ends themselves, which is no
    # side of them (SWITCH_SIDE_TOL), so pressing them together is no C1 event
    assert c["events"] == []
    eq, rod = equilibrium(_pushed_pair(-0.05), elements_per_segment=16, contact=model)
    assert eq.converged and eq.stable
    assert eq.energy == pytest.approx(path.energy[-1], rel=1e-9)
    assert eq.contact.smallest_gap == pytest.approx(c["smallest_gap"], rel=1e-6)
    free, _ = equilibrium(_pushed_pair(-0.05), elements_per_segment=16)
    # Contact only removes states (a minimum over fewer states), so without it the energy is
    # lower; and there the upper rod passes through the lower one (checked below).
    assert free.energy < eq.energy
    plain = C.mesh_of_rod(rod, model)
    rod_free = discretise(_pushed_pair(-0.05), 16, 0.0)
    assert newton(rod_free)[0]
    with pytest.raises(C.Interpenetration):
        C.contact_state(plain, rod_free.x)


def test_continue_with_contact_where_nothing_touches_keeps_the_numbers(run_cli):
    """``rodstab continue --contact`` on the straightened rod (one straight rod buckling out of
    plane, never near itself): the same path and branch point as without contact (to 1e-9),
    and a JSON contact block whose smallest gap is the nearest pair the exclusion keeps."""
    import json

    args = ["continue", "examples/straight_clamped_rod.toml", "--vary", "load_factor=4:7:3",
            "--elements", "8", "--branch-steps", "0", "--no-progress", "--no-error-estimate",
            "--json"]
    plain = json.loads(run_cli(args).stdout)
    r = run_cli([*args, "--contact"])
    assert r.exit_code == 0, r.stderr
    got = json.loads(r.stdout)
    assert "contact" not in plain and got["contact"]["thickness_ratio"] == 0.02
    assert got["value"] == pytest.approx(plain["value"], rel=1e-12)
    assert got["energy"] == pytest.approx(plain["energy"], rel=1e-9, abs=1e-14)
    assert [p["value"] for p in got["special_points"]] == \
        pytest.approx([p["value"] for p in plain["special_points"]], rel=1e-9)
    gap = got["contact"]["smallest_gap"]  # None: no pair within reach at any point
    assert gap is None or gap > got["contact"]["dhat"]


def test_continue_design_with_contact_from_the_command_line(run_cli, tmp_path):
    """The pushed pair as a design file with ``[analysis] contact = true`` (h/L = 0.01, the
    rule's dhat): ``rodstab continue`` reaches the equilibrium that Newton finds from the held
    state with the clamp turned at once (same smallest gap, energy to 1e-9); ``--no-contact``
    lets the upper rod through (its end energy is the free rod's, lower)."""
    import json

    from rodstab.io.design import load_design
    from rodstab.nonlinear.equilibrium import equilibrium, rod_contact_model

    text = ("[[segment]]\nname = 'lo'\nlength = 1.0\n[[segment]]\nname = 'up'\nlength = 1.0\n"
            f"start = [0.0, {H + 0.002!r}]\n"
            "[[support]]\nend = 'lo.start'\n[[support]]\nend = 'lo.end'\ntype = 'sliding-clamp'\n"
            "[[support]]\nend = 'up.start'\nrotation = [0.0, 0.0, 0.0]\n"
            "[[support]]\nend = 'up.end'\ntype = 'sliding-clamp'\n"
            "[analysis]\ncontact = true\ncontact_thickness = 0.01\n")
    f = tmp_path / "pushed.toml"
    f.write_text(text)
    args = ["continue", str(f), "--vary", "support.2.rotation.binormal=0:-0.05:10", "--elements",
            "16", "--branch-steps", "0", "--no-progress", "--json"]
    r = run_cli(args)
    assert r.exit_code == 0, r.stderr
    got = json.loads(r.stdout)
    d = load_design(f)
    turned = load_design(f).assembly
    turned = type(turned)(segments=turned.segments, supports=turned.supports,
                          end_rotations=(("up", "start", (0.0, 0.0, -0.05)),))
    eq, _ = equilibrium(turned, elements_per_segment=16,
                        contact=rod_contact_model(d.assembly, *d.contact))
    assert got["energy"][-1] == pytest.approx(eq.energy, rel=1e-9)
    assert got["contact"]["smallest_gap"] == pytest.approx(eq.contact.smallest_gap, rel=1e-6)
    free = json.loads(run_cli([*args, "--no-contact"]).stdout)
    # Without contact the minimum is over more states: a lower energy (the rod goes through).
    assert "contact" not in free and free["energy"][-1] < got["energy"][-1]


def test_a_special_point_whose_bracket_meets_a_contact_event_says_so():
    """The path's contact block lists the C1 switches met between two points, and marks a
    special point whose bracket meets one (its eigenvalue sign change may be the Hessian's
    jump there): brackets that overlap an event's, and one that does not."""
    from rodstab.nonlinear.continuation.run import _contact_block

    model = C.ContactModel.for_rods(H, dhat_fraction=0.1, bending_stiffness=B, length=L)
    events = [{"kind": "C1 switch", "node": 3, "element": 7, "end": "end",
               "bracket": [0.2, 0.3]}]
    specials = [{"value": 0.25, "bracket": [0.24, 0.26]}, {"value": 0.5, "bracket": [0.45, 0.55]},
                {"value": 0.31, "bracket": [0.35, 0.29]}]
    block = _contact_block(model, [], 0, events, specials, 4)
    assert block["events"] == events and block["points_checked"] == 4
    assert [sp["at_contact_event"] for sp in specials] == [True, False, True]


def test_event_marks_are_set_as_points_are_recorded_and_never_cleared():
    """The marks are set where the points are recorded, so ``special_points.json`` (written
    at every point) carries them (it was written before they were set); a resumed run, which
    has not the events met before its resume, keeps a mark it read back."""
    from rodstab.nonlinear.continuation.run import _mark_events

    specials = [{"value": 0.25, "bracket": [0.24, 0.26]},
                {"value": 0.5, "bracket": [0.45, 0.55], "at_contact_event": True}]
    _mark_events(specials, [{"bracket": [0.2, 0.3]}])
    assert [sp["at_contact_event"] for sp in specials] == [True, True]
    _mark_events(specials, [])
    assert [sp["at_contact_event"] for sp in specials] == [True, True]
    fresh = [{"value": 0.5}]
    _mark_events(fresh, [{"bracket": [0.2, 0.3]}])
    assert fresh[0]["at_contact_event"] is False


def _tip_under_a_rod(theta=0.0):
    """A cantilever (clamped at x = 0, free end 3e-5 past x = L/2) below a rod clamped at both
    ends, ``h + 0.002`` apart; the cantilever's clamp turned by ``theta`` about e3 (positive:
    towards the upper rod, which its tip then presses)."""
    lo = Segment(name="lo", length=0.5 * L + 3e-5, curvature=0.0, natural_curvature=0.0, B1=B,
                 B2=B / 1.3, B3=B, start=(0.0, 0.0), angle=0.0)
    rot = (("lo", "start", (0.0, 0.0, theta)),) if theta else ()
    return Assembly(segments=(lo, _segment("up", start=(0.0, H + 0.002))),
                    supports=(("lo", "start", "clamped"), ("up", "start", "clamped"),
                              ("up", "end", "clamped")), end_rotations=rot)


def test_continuation_reports_where_a_node_slides_past_a_free_end():
    """The cantilever's tip pressed up into the other rod (clamp turned 0 -> 0.04 rad, 16 el.):
    the upper rod's node above the tip (x = L/2) has its closest point on the cantilever's last
    element, 3e-5 inside its free end, and past it once the tip has retracted. The path
    reports that one C1 event, node over the end of element 15. Independently (Newton with
    the clamp turned at once to each end of the event's bracket, and the projection measured
    here): the node projects inside the element at the bracket's start, past its end at the
    bracket's end."""
    from rodstab.nonlinear.continuation import continuation
    from rodstab.nonlinear.equilibrium import equilibrium

    model = C.ContactModel.for_rods(H, dhat_fraction=0.1, bending_stiffness=B, length=L)
    path = continuation(_tip_under_a_rod(), "support.0.rotation.binormal", 0.0, 0.04, 30,
                        elements_per_segment=16, branch_steps=0, contact=model)
    assert path.converged
    (ev,) = path.contact["events"]
    assert (ev["element"], ev["end"]) == (15, "end")
    node = ev["node"]
    for theta, inside in zip(ev["bracket"], (True, False), strict=True):
        eq, rod = equilibrium(_tip_under_a_rod(theta), elements_per_segment=16, contact=model)
        assert eq.converged
        a, b = rod.x[rod.edge_nodes[15]]
        along = float((rod.x[node] - a) @ (b - a) / np.linalg.norm(b - a))
        assert (along < np.linalg.norm(b - a)) == inside


def test_a_command_without_contact_refuses_a_contact_design_naming_those_with_one(run_cli,
                                                                               tmp_path):
    """`rodstab states` on a design asking for contact: exit 2, naming the design's key and
    every command that does model contact (the list checked against the command line's own
    options), never a silent run without it."""
    from rodstab.cli.main import cli
    from rodstab.io.design import CONTACT_COMMANDS

    text = (Path(__file__).parents[1] / "examples" / "hexagram.toml").read_text()
    assert text.count("[analysis]") == 1
    design = tmp_path / "ring.toml"
    design.write_text(text.replace("[analysis]", "[analysis]\ncontact = true"))
    r = run_cli(["states", str(design)])
    assert r.exit_code == 2, r.stderr
    assert "analysis.contact = true" in r.stderr and "set contact = false" in r.stderr
    for c in CONTACT_COMMANDS:
        assert f"`rodstab {c}`" in r.stderr
    # The list is the command line's: the commands reading a design that take --contact.
    takes = {name for name, c in cli.commands.items()
             if {"with_contact", "design_file"} <= {p.name for p in c.params}}
    assert takes == set(CONTACT_COMMANDS)
