"""Contact model (issue 21, part 1): barrier, exact derivatives, parallel rods, exclusions,
broad phase, step filter, C1 events, bad input.

Oracles: closed forms of the barrier (its Taylor expansion at dhat), of parallel rods (``L b(g)``)
and of a perpendicular crossing (``(l_a + l_b) / 4 b(g)``); central differences for the
derivatives; brute force for the broad phase; dense sampling of the segments for the step filter.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from contact_checks import central_differences, sampled_min_gap

from rodstab.errors import RodstabInputError
from rodstab.model import Assembly, Segment
from rodstab.nonlinear import contact as C
from rodstab.nonlinear.contact import (
    ContactModel,
    Interpenetration,
    barrier,
    candidate_pairs,
    contact_energy,
    contact_energy_value,
    contact_mesh,
    max_step_fraction,
    mesh_of_rod,
    near_type_switch,
    segment_distance,
    stiffness_for_line_load,
    type_switch_crossings,
)
from rodstab.nonlinear.discrete import discretise

R_CAP, DHAT, KAPPA = 0.05, 0.02, 3.0  # capsule radius, activation distance, stiffness
MODEL = ContactModel(R_CAP, DHAT, KAPPA)
FD_STEP = 1e-6
FD_TOL = 1e-6  # relative error of the analytic gradient / Hessian against central differences


def b_of(g: float) -> float:
    return float(barrier(np.array([g]), DHAT, KAPPA)[0][0])


def db_of(g: float) -> float:
    return float(barrier(np.array([g]), DHAT, KAPPA)[1][0])


def chain(n: int, offset: int = 0, closed: bool = False) -> np.ndarray:
    k = np.arange(n)
    return offset + np.stack([k, (k + 1) % (n + (not closed))], axis=1)


def mesh_for(x: np.ndarray, edges: np.ndarray, model: ContactModel = MODEL, **kw):
    L = np.linalg.norm(x[edges[:, 1]] - x[edges[:, 0]], axis=1)
    return contact_mesh(edges, L, x, model, **kw)


def two_rods(xa: np.ndarray, xb: np.ndarray, model: ContactModel = MODEL):
    """Two open rods given by their node rows; return (positions, mesh)."""
    na, nb = len(xa) - 1, len(xb) - 1
    x = np.vstack([xa, xb])
    return x, mesh_for(x, np.vstack([chain(na), chain(nb, na + 1)]), model)


def candidate_pairs_brute(mesh, x, inflate=None):
    """Every pair tested against the bounding spheres (quadratic; the k-d tree's reference)."""
    m, R = C._bounds(mesh, x, inflate)
    a, b = np.triu_indices(len(m), 1)
    keep = np.linalg.norm(m[a] - m[b], axis=1) <= R[a] + R[b]
    return np.stack([a[keep], b[keep]], axis=1)


def line(s: np.ndarray, y: float = 0.0, z: float = 0.0) -> np.ndarray:
    return np.stack([s, np.full_like(s, y), np.full_like(s, z)], axis=1)


# ---------------------------------------------------------------- barrier
def test_barrier_is_c2_at_dhat_with_the_taylor_coefficients_of_b3():
    """b''' (dhat) = -6 kappa / dhat, b = b' = b'' = 0: b ~ kappa e^3 / dhat, b' ~ -3 kappa e^2
    / dhat, b'' ~ 6 kappa e / dhat at g = dhat - e (closed form, sympy-checked)."""
    for e in (1e-3 * DHAT, 1e-4 * DHAT):
        b, db, d2b = barrier(np.array([DHAT - e]), DHAT, KAPPA)
        assert b[0] == pytest.approx(KAPPA * e**3 / DHAT, rel=5e-3)
        assert db[0] == pytest.approx(-3 * KAPPA * e**2 / DHAT, rel=5e-3)
        assert d2b[0] == pytest.approx(6 * KAPPA * e / DHAT, rel=5e-3)
    b, db, d2b = barrier(np.array([DHAT, 2 * DHAT]), DHAT, KAPPA)
    assert not b.any() and not db.any() and not d2b.any()


def test_barrier_derivatives_match_differences_of_its_value():
    g = np.linspace(0.05, 0.95, 7) * DHAT
    h = 1e-7 * DHAT
    b, db, d2b = barrier(g, DHAT, KAPPA)
    bp, bm = barrier(g + h, DHAT, KAPPA)[0], barrier(g - h, DHAT, KAPPA)[0]
    np.testing.assert_allclose(db, (bp - bm) / (2 * h), rtol=1e-6)
    h2 = 1e-4 * DHAT  # a second difference needs a larger step (round-off ~ u b / h^2)
    bp, bm = barrier(g + h2, DHAT, KAPPA)[0], barrier(g - h2, DHAT, KAPPA)[0]
    np.testing.assert_allclose(d2b, (bp - 2 * b + bm) / h2**2, rtol=1e-4)


def test_stiffness_rule_holds_the_line_load_at_the_chosen_gap():
    """-b'(f dhat) = q per unit length: two long parallel rods pressed by q sit at f dhat."""
    q, f = 7.5, 0.3
    k = stiffness_for_line_load(q, DHAT, f)
    g, h = f * DHAT, 1e-7 * DHAT
    load = -(barrier(np.array([g + h]), DHAT, k)[0] - barrier(np.array([g - h]), DHAT, k)[0])
    assert load[0] / (2 * h) == pytest.approx(q, rel=1e-6)


# ---------------------------------------------------------------- exact derivatives
def _kinds(mesh, x):
    """Which kinds of terms are active: point-interior, point-end, partition zone, edge-edge
    (full), edge-edge (mollifier zone)."""
    nt, on, ee = C._active(mesh, x)
    kinds = set()
    clamped = nt.start | nt.end
    if np.any(on & clamped):
        kinds.add("point-end")
    if np.any(on & ~clamped & (nt.weight == 1.0)):
        kinds.add("point-interior")
    if np.any(on & (nt.weight > 0) & (nt.weight < 1)):
        kinds.add("partition")
    if len(ee):
        ea, eb = (x[mesh.edges[ee[:, k], 1]] - x[mesh.edges[ee[:, k], 0]] for k in (0, 1))
        sin2 = (np.linalg.norm(np.cross(ea, eb), axis=1)
                / (np.linalg.norm(ea, axis=1) * np.linalg.norm(eb, axis=1))) ** 2
        kinds.add("edge-edge" if np.any(sin2 >= C.EE_SIN2_ON) else "edge-edge-mollified")
    return kinds


def _config(kind: str, rng: np.random.Generator):
    """A small configuration in which the named kind of term is active."""
    j = lambda s: 0.1 * s * rng.uniform(-1, 1, 3)  # noqa: E731
    d0 = 2 * R_CAP + 0.5 * DHAT
    if kind == "point-interior":  # B's end node over A's interior, B steep (no edge-edge)
        xa = np.array([[0, 0, 0], [1, 0, 0.0]]) + j(0.01)
        xb = np.array([[0.4, 0, d0], [0.4, 0.1, d0 + 1.0]]) + j(0.005)
    elif kind == "point-end":  # B's node beyond A's free end, nearer than the reach
        xa = np.array([[0, 0, 0], [1, 0, 0.0]]) + j(0.01)
        xb = np.array([[1 + 0.4 * d0, 0, 0.9 * d0], [1.5, 0.1, 2.0]]) + j(0.003)
    elif kind == "partition":  # B's node over A's smooth node, inside the partition zone
        xa = np.array([[0, 0, 0], [1, 0, 0], [2, 0.05, 0.0]]) + j(0.01)
        xb = np.array([[1.001, 0, d0], [1.001, 0.2, d0 + 1.0]]) + j(0.005)
    elif kind == "edge-edge":  # an X, closest points mid-segment
        xa = np.array([[-0.5, 0, 0], [0.5, 0, 0.0]]) + j(0.01)
        xb = np.array([[0, -0.5, d0], [0.05, 0.5, d0]]) + j(0.01)
    elif kind == "edge-edge-mollified":  # an X at 3 deg: sin^2 between EE_SIN2_OFF and _ON
        a = 0.05 + 0.005 * rng.uniform(-1, 1)
        xa = np.array([[-0.5, 0, 0], [0.5, 0, 0.0]])
        xb = np.array([[-0.5 * math.cos(a), -0.5 * math.sin(a), d0],
                       [0.5 * math.cos(a), 0.5 * math.sin(a), d0]]) + j(1e-4)
    else:  # near-parallel: tilted by 1e-3 rad out of the plane, three elements each
        s = np.linspace(0, 1, 4)
        xa = line(s) + 0.001 * rng.uniform(-1, 1, (4, 3))
        xb = line(s + 0.1, 0, d0) + np.outer(s - 0.5, [0, 0, 1e-3])
    return two_rods(xa, xb)


@pytest.mark.parametrize("kind", ["point-interior", "point-end", "partition", "edge-edge",
                                  "edge-edge-mollified", "near-parallel"])
def test_gradient_and_hessian_match_central_differences(kind):
    rng = np.random.default_rng(sum(map(ord, kind)))  # a fixed seed per kind
    for _ in range(2):
        x, mesh = _config(kind, rng)
        kinds = _kinds(mesh, x)
        expected = "point-interior" if kind == "near-parallel" else kind
        assert expected in kinds, (kind, kinds)
        E, g, H = contact_energy(mesh, x)
        assert E > 0
        gf, Hf = central_differences(lambda y, m=mesh: contact_energy(m, y), x, FD_STEP)
        Hd = H.toarray()
        assert np.linalg.norm(g - gf) <= FD_TOL * np.linalg.norm(g), kind
        assert np.linalg.norm(Hd - Hf) <= FD_TOL * np.linalg.norm(Hd), kind
        np.testing.assert_allclose(Hd, Hd.T, atol=1e-12 * np.abs(Hd).max())


# ---------------------------------------------------------------- parallel, tilted, crossing
N_TILT, L_TILT, G_TILT = 8, 1.0, 0.5 * DHAT


def _tilted(theta: float, axis: str, shift: float = 0.3) -> np.ndarray:
    """Rod B over rod A at gap G_TILT, B turned by theta about z (an X in parallel planes) or
    about y (out of the plane: one end dips). Both have 8 elements, A's nodes shifted by
    ``shift`` and B's by ``-shift / 2`` elements so that the turning centre lies inside an
    element of each (an X there is an edge-edge contact)."""
    s = np.linspace(-L_TILT / 2, L_TILT / 2, N_TILT + 1)
    h = L_TILT / N_TILT
    sb = s - 0.5 * shift * h
    d0 = 2 * R_CAP + G_TILT
    c, sn = math.cos(theta), math.sin(theta)
    xb = (np.stack([sb * c, sb * sn, np.full_like(s, d0)], 1) if axis == "z"
          else np.stack([sb * c, 0 * s, d0 + sb * sn], 1))
    return np.vstack([line(s + shift * h), xb])


TILT_MESH = two_rods(_tilted(0.0, "z")[:N_TILT + 1], _tilted(0.0, "z")[N_TILT + 1:])[1]


@pytest.mark.parametrize("theta, axis", [(0.0, "z"), (1e-3, "z"), (1e-3, "y"), (math.pi / 2, "z"),
                                         (0.7, "z")])
def test_parallel_tilted_and_crossing_pairs_repel(theta, axis):
    """Energy > 0 at gap < dhat, and lifting B (+z) lowers it: the force pushes them apart."""
    x = _tilted(theta, axis)
    E, g, _ = contact_energy(TILT_MESH, x)
    assert E > 0
    lift = np.zeros_like(x)
    lift[N_TILT + 1:, 2] = 1.0
    assert g @ lift.ravel() < 0
    assert g[2:3 * (N_TILT + 1):3].sum() > 0  # A pushed down


def test_exactly_parallel_pair_carries_b_per_unit_length():
    assert contact_energy_value(TILT_MESH, _tilted(0.0, "z", shift=0.0)) == pytest.approx(
        L_TILT * b_of(G_TILT), rel=1e-12)


def test_perpendicular_crossing_is_one_edge_edge_term_in_closed_form():
    """Two single elements crossing mid-segment: only the edge-edge term, (l_a + l_b)/4 b(g)."""
    d0 = 2 * R_CAP + G_TILT
    x, mesh = two_rods(np.array([[-0.5, 0, 0], [0.5, 0, 0.0]]),
                       np.array([[0, -0.7, d0], [0, 0.7, d0]]))
    assert contact_energy_value(mesh, x) == pytest.approx((1.0 + 1.4) / 4 * b_of(G_TILT),
                                                          rel=1e-12)


def test_tilted_pair_crosses_inside_elements_of_both():
    """The X of the in-plane tilt is an edge-edge contact (interior closest points)."""
    assert "edge-edge" in _kinds(TILT_MESH, _tilted(0.7, "z"))


@pytest.mark.parametrize("axis", ["z", "y"])
def test_energy_is_smooth_in_the_tilt_through_parallel(axis):
    """One-sided differences of E(theta) at 0 agree, their difference shrinking like eps; a
    min-distance barrier (d = d0 - L/2 |theta| for the out-of-plane tilt) would differ by
    L |b'(g)| (the scale compared with)."""
    E = lambda t: contact_energy_value(TILT_MESH, _tilted(t, axis))  # noqa: E731
    kink = L_TILT * abs(db_of(G_TILT))
    jumps = []
    for eps in (1e-3, 1e-4):
        Dp, Dm = (E(eps) - E(0.0)) / eps, (E(0.0) - E(-eps)) / eps
        jumps.append(abs(Dp - Dm))
    assert jumps[0] < 0.05 * kink
    assert jumps[1] < 0.15 * jumps[0]  # O(eps): a continuous derivative


def test_energy_is_smooth_as_a_crossing_slides_over_a_node():
    """A perpendicular X slides along A through A's middle node: the edge-edge terms of A's two
    elements hand over to the node's terms; E(u) has equal one-sided slopes at the node."""
    d0 = 2 * R_CAP + G_TILT
    xb = np.array([[0.0, -0.5, d0], [0.0, 0.0, d0], [0.0, 0.5, d0]]) + [0, 0.1, 0]

    def E(u):
        xa = line(np.array([-0.5, 0.0, 0.5]) + u)
        x, mesh = two_rods(xa, xb)
        return contact_energy_value(mesh, x)

    on = np.sqrt(2 * C.EE_NODE_EXCESS * DHAT * 2 * R_CAP)  # offset where the X is fully on
    for u0 in (0.0, 0.3 * on, 0.6 * on, 1.0 * on, 0.1):
        eps = 1e-6
        Dp, Dm = (E(u0 + eps) - E(u0)) / eps, (E(u0) - E(u0 - eps)) / eps
        assert abs(Dp - Dm) < 1e-3 * abs(db_of(G_TILT)), u0


# ---------------------------------------------------------------- mesh independence
@pytest.mark.parametrize("na, nb", [(7, 13), (20, 9), (3, 40)])
def test_parallel_rods_energy_per_length_is_b_on_any_pair_of_meshes(na, nb):
    """Tributary weights and the partition of unity make the node sum exact for straight
    parallel rods: E = L b(g), total force L |b'(g)|, on non-matching, jittered meshes."""
    rng = np.random.default_rng(na * nb)
    L, g = 2.0, 0.4 * DHAT

    def nodes(n):
        s = np.linspace(0, L, n + 1)
        s[1:-1] += 0.3 * (L / n) * rng.uniform(-1, 1, n - 1)
        return s

    x, mesh = two_rods(line(nodes(na)), line(nodes(nb), 0.0, 2 * R_CAP + g))
    E, grad, _ = contact_energy(mesh, x)
    assert E == pytest.approx(L * b_of(g), rel=1e-12)
    assert grad[3 * (na + 1) + 2::3].sum() == pytest.approx(L * db_of(g), rel=1e-12)


RING_R, RING_H = 1.0, 0.1


def _stacked_rings(n: int, gap: float) -> tuple[np.ndarray, C.ContactMesh]:
    nb = int(1.5 * n) + 1

    def ring(m, z, phase):
        ph = 2 * np.pi * (np.arange(m) + phase) / m
        return np.stack([RING_R * np.cos(ph), RING_R * np.sin(ph), np.full(m, z)], 1)

    x = np.vstack([ring(n, 0.0, 0.0), ring(nb, RING_H + gap, 0.3)])
    edges = np.vstack([chain(n, closed=True), chain(nb, n, closed=True)])
    return x, mesh_for(x, edges, ContactModel.from_thickness(RING_H, dhat=DHAT, stiffness=KAPPA))


EXPECTED_RING_ORDER = 2.0  # weights from chord lengths: the polygon's perimeter, O(n^-2)


def test_stacked_rings_energy_per_length_converges_at_second_order():
    """Two stacked circles (non-matching meshes, n and 1.5 n + 1 elements) at gap g: E / (2 pi
    R) -> b(g). Below the polygon-perimeter error (weights are chord lengths) the rest, from
    the curvature (partition at bent nodes, near-parallel edge-edge terms), is below 1e-5."""
    g = 0.5 * DHAT
    ns = np.array([192, 256, 384, 512])
    err, rest = [], []
    for n in ns:
        x, mesh = _stacked_rings(int(n), g)
        E = contact_energy_value(mesh, x)
        err.append(abs(E / (2 * np.pi * RING_R * b_of(g)) - 1))
        rest.append(abs(E / (0.5 * mesh.rest_length.sum() * b_of(g)) - 1))
    slope = -np.polyfit(np.log(ns), np.log(err), 1)[0]
    assert slope >= EXPECTED_RING_ORDER - 0.2, (slope, err)
    assert max(rest) < 1e-5


@pytest.mark.parametrize("n", [16, 32])
def test_rings_side_by_side_in_their_plane_hold_gaps_above_the_partition_error(n):
    """Two concentric rings in one plane, 0.2 dhat apart: the inner ring's lines extended past
    its bent nodes stand out toward the outer ring by delta sin(turn) <= 0.1 dhat (module doc),
    so the gap stays positive in every term (with delta = 0.4 l alone, 0.4 l^2 / R = 0.06 R
    at 16 elements, the state was refused as interpenetrating)."""
    g, nb = 0.2 * DHAT, int(1.5 * n) + 1
    ph, phb = 2 * np.pi * np.arange(n) / n, 2 * np.pi * (np.arange(nb) + 0.3) / nb
    Rb = (RING_R + RING_H + g) / math.cos(math.pi / nb)  # outer chords tangent to R + h + g
    x = np.vstack([np.stack([np.cos(ph), np.sin(ph), 0 * ph], 1),
                   np.stack([Rb * np.cos(phb), Rb * np.sin(phb), 0 * phb], 1)])
    mesh = mesh_for(x, np.vstack([chain(n, closed=True), chain(nb, n, closed=True)]),
                    ContactModel.from_thickness(RING_H, dhat=DHAT, stiffness=KAPPA))
    turn = 2 * np.pi / n
    assert mesh.delta[:n].max() * math.sin(turn) <= C.PHANTOM_FRACTION * DHAT * (1 + 1e-12)
    assert contact_energy_value(mesh, x) > 0


# ---------------------------------------------------------------- exclusions
def _circle(n: int, R: float, z: float = 0.0, offset: int = 0):
    ph = 2 * np.pi * np.arange(n) / n
    return np.stack([R * np.cos(ph), R * np.sin(ph), np.full(n, z)], 1), chain(n, offset, True)


def test_tightly_curved_rod_does_not_touch_itself():
    """A circle of radius 5 h at 64 elements: nodes two apart are 2 (5 h) sin(2 pi / 64) =
    0.98 h apart (their capsules overlap), yet the energy is zero: they are excluded."""
    h = 2 * R_CAP
    x, edges = _circle(64, 5 * h)
    assert np.linalg.norm(x[2] - x[0]) == pytest.approx(10 * h * math.sin(2 * math.pi / 64))
    assert np.linalg.norm(x[2] - x[0]) < h
    mesh = mesh_for(x, edges)
    E, g, H = contact_energy(mesh, x)
    assert E == 0.0 and not g.any() and H.nnz == 0
    # the same rod with a second loop stacked on it at gap dhat/2 does touch
    x2, e2 = _circle(64, 5 * h, h + 0.5 * DHAT, 64)
    X, Ed = np.vstack([x, x2]), np.vstack([edges, e2])
    E2 = contact_energy_value(mesh_for(X, Ed), X)
    assert E2 == pytest.approx(mesh.rest_length.sum() * b_of(0.5 * DHAT), rel=1e-12)


def test_extra_connections_count_as_adjacency():
    """Two rods welded end to end through different nodes: without the connection their end
    elements (centrelines 0.5 h apart) overlap; with it they are neighbours."""
    h = 2 * R_CAP
    x = np.vstack([line(np.linspace(-1, 0, 11)), line(np.linspace(0.0, 1, 11), 0.0, 0.5 * h)])
    edges = np.vstack([chain(10), chain(10, 11)])
    with pytest.raises(Interpenetration, match="elements 9 and 10"):
        contact_energy(mesh_for(x, edges), x)
    assert contact_energy_value(mesh_for(x, edges, connections=[(10, 11)]), x) == 0.0


def test_graph_distance_lookup_is_the_sparse_matrix_entry():
    """The sorted-key lookup of the distances along the structure against scipy's indexing of
    the same sparse matrix, on every node pair of two welded rods (in reach or not)."""
    h = 2 * R_CAP
    x = np.vstack([line(np.linspace(-1, 0, 11)), line(np.linspace(0.0, 1, 11), 0.0, 0.5 * h)])
    edges = np.vstack([chain(10), chain(10, 11)])
    mesh = mesh_for(x, edges, connections=[(10, 11)])
    p, q = (a.ravel() for a in np.meshgrid(np.arange(22), np.arange(22)))
    v = np.asarray(mesh.near[p, q]).ravel()
    expected = np.where(v > 0.0, v - 1.0, np.inf)
    np.testing.assert_array_equal(mesh.graph_distance(p, q), expected)
    assert np.isfinite(expected).sum() > 22 and np.isinf(expected).sum() > 22
    assert mesh.graph_distance(np.zeros(0, int), np.zeros(0, int)).shape == (0,)


def _ring(loops: int) -> Assembly:
    s = Segment(name="r", length=2 * math.pi * loops, curvature=1.0, natural_curvature=1.0,
                B1=1.0, B2=1.0, B3=1.0)
    return Assembly(segments=(s,), welds=((("r", "start"), ("r", "end")),))


def test_discrete_rod_ring_is_free_and_coincident_stacked_loops_interpenetrate():
    """On a DiscreteRod: a one-loop ring does not touch itself (its weld shares a node, whose
    dofs lead the rod's); the 3-loop ring, analysed today with coincident loops, is refused."""
    model = ContactModel.from_thickness(0.1, dhat=0.01, stiffness=1.0)
    rod = discretise(_ring(1), 16)
    E, g, H = contact_energy(mesh_of_rod(rod, model), rod.x)
    assert E == 0.0 and g.shape == (3 * len(rod.x),) and H.shape == (g.size, g.size)
    np.testing.assert_array_equal(rod.node_dofs(np.arange(len(rod.x))).ravel(),
                                  np.arange(g.size))
    rod3 = discretise(_ring(3), 48)
    with pytest.raises(Interpenetration, match="gap -0.1 <= 0"):
        contact_energy(mesh_of_rod(rod3, model), rod3.x)


# ---------------------------------------------------------------- broad phase
@pytest.mark.parametrize("seed", [0, 1, 2])
def test_broad_phase_equals_brute_force_and_holds_every_close_pair(seed):
    rng = np.random.default_rng(seed)
    n = 60
    a0 = rng.uniform(0, 1.5, (n, 3))
    a1 = a0 + rng.normal(0, 0.12, (n, 3))
    x = np.empty((2 * n, 3))
    x[0::2], x[1::2] = a0, a1
    edges = np.stack([2 * np.arange(n), 2 * np.arange(n) + 1], 1)
    mesh = mesh_for(x, edges, ContactModel(0.01, 0.02, 1.0))
    P = candidate_pairs(mesh, x)
    np.testing.assert_array_equal(P, candidate_pairs_brute(mesh, x))
    # every pair within reach (true segment distance < r_a + r_b + dhat) is a candidate
    a, b = np.triu_indices(n, 1)
    d = segment_distance(a0[a], a1[a], a0[b], a1[b])
    close = {(int(i), int(j)) for i, j, dd in zip(a, b, d, strict=True) if dd < 0.04}
    assert close and close <= {tuple(p) for p in P.tolist()}


def test_candidate_count_grows_linearly_on_a_long_helix():
    """A helix whose coils touch (pitch h + dhat / 2): each added element adds the same number
    of candidates (linear growth; quadratic or N log N growth would not)."""
    h = 2 * R_CAP
    counts, Ns = [], np.array([200, 400, 800, 1600])
    for N in Ns:
        t = np.arange(N + 1) * 0.05
        x = np.stack([np.cos(t), np.sin(t), (h + 0.5 * DHAT) * t / (2 * np.pi)], 1)
        mesh = mesh_for(x, chain(N))
        counts.append(len(candidate_pairs(mesh, x)))
    per_element = np.diff(counts) / np.diff(Ns)  # the first coil has no coil below: an offset
    assert per_element.max() < 1.1 * per_element.min(), counts
    assert contact_energy_value(mesh, x) > 0  # the coils do touch


# ---------------------------------------------------------------- step filter
def _sampled_min_gap(x, dx, mesh, alpha, n_time=400, n_pts=81):
    """Smallest gap of non-neighbouring elements along the step (contact_checks)."""
    pairs = candidate_pairs_brute(mesh, x, inflate=np.full(len(mesh.edges), 10.0))
    pairs = pairs[~mesh.excluded_elements(pairs[:, 0], pairs[:, 1])]
    return sampled_min_gap(mesh, x, dx, alpha, pairs, n_time=n_time, n_pts=n_pts)


def test_step_filter_stops_a_crossing_that_would_tunnel():
    d0 = 2 * R_CAP + 0.5 * DHAT
    x, mesh = two_rods(np.array([[-0.5, 0, 0], [0.5, 0, 0.0]]),
                       np.array([[0, -0.5, d0], [0, 0.5, d0]]))
    dx = np.zeros_like(x)
    dx[2:, 2] = -6 * R_CAP  # B straight down through A, ending below it
    assert _sampled_min_gap(x, dx, mesh, 1.0, 60, 41) < -R_CAP  # a full step tunnels
    alpha = max_step_fraction(mesh, x, dx, safety=0.9)
    # closed form: one segment translated at speed 6 R toward the other, gap 0.5 dhat
    assert alpha == pytest.approx(0.9 * 0.5 * DHAT / (6 * R_CAP), rel=1e-9)
    assert _sampled_min_gap(x, dx, mesh, alpha, 60, 41) > 0
    contact_energy(mesh, x + alpha * dx)  # still inside the model


def test_step_filter_stops_parallel_rods_passing_through_each_other():
    s = np.linspace(0, 1, 6)
    x, mesh = two_rods(line(s), line(s + 0.07, 0.0, 2 * R_CAP + 0.3 * DHAT))
    rng = np.random.default_rng(5)
    dx = np.zeros_like(x)
    dx[6:] = [0.03, 0.0, -5 * R_CAP] + 0.02 * rng.uniform(-1, 1, (6, 3))
    assert _sampled_min_gap(x, dx, mesh, 1.0, 40, 21) < 0
    alpha = max_step_fraction(mesh, x, dx)
    assert 0 < alpha < 1
    assert _sampled_min_gap(x, dx, mesh, alpha, 200, 41) > 0
    assert np.isfinite(contact_energy_value(mesh, x + alpha * dx))


def test_step_filter_allows_the_full_step_far_from_contact():
    x, mesh = two_rods(line(np.linspace(0, 1, 4)), line(np.linspace(0, 1, 4), 0.0, 1.0))
    dx = np.zeros_like(x)
    dx[:, 0] = 0.3
    assert max_step_fraction(mesh, x, dx) == 1.0


# ---------------------------------------------------------------- where the energy is only C1
def test_switch_report_finds_a_node_at_a_clamped_end_and_the_hessian_jumps_there():
    """B's node slides past A's free end: the distance switches from segment to end node, the
    gradient is continuous and the Hessian jumps (C1); at a smooth node (partition) it does
    not, and the report stays silent there."""
    d0 = 2 * R_CAP + 0.5 * DHAT

    def at(u, three=False):
        xa = np.array([[0, 0, 0], [1, 0, 0], [2, 0, 0.0]])[: 3 if three else 2]
        return two_rods(xa, np.array([[1 + u, 0, d0], [1 + u, 0.3, d0 + 1.0]]))

    for three, jumps in ((False, True), (True, False)):
        (xm, mesh), (xp, _) = at(-1e-7, three), at(1e-7, three)
        Em, gm, Hm = contact_energy(mesh, xm)
        Ep, gp, Hp = contact_energy(mesh, xp)
        assert np.linalg.norm(gp - gm) < 1e-4 * np.linalg.norm(gm)
        jump = np.linalg.norm((Hp - Hm).toarray()) / np.linalg.norm(Hm.toarray())
        assert (jump > 1e-2) == jumps, (three, jump)
        rep = near_type_switch(mesh, xm, tol=1e-3)
        assert rep.near == jumps
        if jumps:
            assert rep.node.tolist() == [2] and rep.element.tolist() == [0]
            assert rep.offset[0] == pytest.approx(-1e-7, abs=1e-12)
    x, mesh = at(-0.3)
    assert not near_type_switch(mesh, x, tol=1e-3).near


def test_a_node_sliding_past_a_clamped_end_is_a_crossing_event_and_nothing_else_is():
    """type_switch_crossings, between two states: B's node (2) slides past A's free end (the
    end of element 0) -- one crossing; moved on one side only, or past a smooth node (where
    the partition of unity keeps the energy C2), none."""
    d0 = 2 * R_CAP + 0.5 * DHAT

    def at(u, three=False):
        xa = np.array([[0, 0, 0], [1, 0, 0], [2, 0, 0.0]])[: 3 if three else 2]
        return two_rods(xa, np.array([[1 + u, 0, d0], [1 + u, 0.3, d0 + 1.0]]))

    (x0, mesh), (x1, _) = at(-0.01), at(0.01)
    assert type_switch_crossings(mesh, x0, x1) == [(2, 0, 1)]
    assert type_switch_crossings(mesh, x1, x0) == [(2, 0, 1)]
    assert type_switch_crossings(mesh, x0, at(-0.02)[0]) == []
    (y0, smooth), (y1, _) = at(-0.01, True), at(0.01, True)
    assert type_switch_crossings(smooth, y0, y1) == []
    # a state on the switch says so (its Hessian is one-sided); near it, or at a smooth
    # node, not
    on_end, mesh = at(0.0)
    assert C.contact_state(mesh, on_end).at_switch == 1
    assert C.contact_state(mesh, x0).at_switch == 0
    assert C.contact_state(smooth, at(0.0, True)[0]).at_switch == 0


# ---------------------------------------------------------------- bad input
BAD = [
    (lambda: ContactModel(0.0, DHAT, KAPPA), "radius", "0.0"),
    (lambda: ContactModel(-1.0, DHAT, KAPPA), "radius", "-1.0"),
    (lambda: ContactModel((0.1, -0.2), DHAT, KAPPA), "radius[1]", "-0.2"),
    (lambda: ContactModel(float("nan"), DHAT, KAPPA), "radius", "nan"),
    (lambda: ContactModel(R_CAP, 0.0, KAPPA), "dhat", "0.0"),
    (lambda: ContactModel(R_CAP, -0.01, KAPPA), "dhat", "-0.01"),
    (lambda: ContactModel(R_CAP, DHAT, 0.0), "stiffness", "0.0"),
    (lambda: ContactModel(R_CAP, DHAT, KAPPA, exclusion_factor=0.5), "exclusion_factor", "0.5"),
    (lambda: ContactModel.from_thickness(0.0, dhat=DHAT, stiffness=KAPPA), "thickness", "0.0"),
    (lambda: ContactModel.from_thickness(-0.1, dhat=DHAT, stiffness=KAPPA), "thickness", "-0.1"),
    (lambda: mesh_for(line(np.linspace(0, 1, 3)), chain(2), ContactModel(R_CAP, 5.0, KAPPA)),
     "dhat", "5.0"),
    (lambda: contact_mesh(chain(2), np.array([1.0, -1.0]), line(np.linspace(0, 1, 3)), MODEL),
     "rest_length", "-1."),
    (lambda: contact_mesh(np.array([[0, 7]]), np.array([1.0]), line(np.linspace(0, 1, 3)),
                          MODEL), "edges", "(1, 2)"),
    (lambda: contact_energy(TILT_MESH, np.zeros((3, 3))), "x", "(3, 3)"),
    (lambda: stiffness_for_line_load(1.0, DHAT, 1.0), "gap_fraction", "1.0"),
    (lambda: stiffness_for_line_load(-1.0, DHAT), "line_load", "-1.0"),
    (lambda: max_step_fraction(TILT_MESH, _tilted(0.0, "z"), 0 * _tilted(0.0, "z"), 1.5),
     "safety", "1.5"),
    (lambda: near_type_switch(TILT_MESH, _tilted(0.0, "z"), 0.0), "tol", "0.0"),
]


@pytest.mark.parametrize("call, key, value", BAD, ids=[f"{k}={v}" for _, k, v in BAD])
def test_bad_input_names_the_key_and_value(call, key, value):
    with pytest.raises(RodstabInputError) as err:
        call()
    assert key in str(err.value) and value in str(err.value)


@pytest.mark.parametrize("config", ["parallel", "crossing"])
def test_interpenetrating_input_raises_a_clear_error(config):
    if config == "parallel":  # centrelines 1.5 r apart
        x, mesh = two_rods(line(np.linspace(0, 1, 4)), line(np.linspace(0, 1, 4), 0, 1.5 * R_CAP))
    else:  # an X in one plane: the segments cut each other
        x, mesh = two_rods(np.array([[-0.5, 0, 0], [0.5, 0, 0.0]]),
                           np.array([[0, -0.5, 0], [0, 0.5, 0.0]]))
    for f in (contact_energy, contact_energy_value, lambda m, y: max_step_fraction(m, y, 0 * y)):
        with pytest.raises(Interpenetration, match=r"interpenetrate: gap -?[0-9.e-]+ <= 0"):
            f(mesh, x)
    with pytest.raises(Interpenetration):
        barrier(np.array([0.0]), DHAT, KAPPA)


# ---------------------------------------------------------------- crossings near nodes
def _crossing(theta: float, sa: float, sb: float, g: float):
    """Rod A along x (nodes -0.5, 0, 0.5), rod B above it at angle ``theta`` in plan, the two
    centrelines crossing (in plan) ``sa`` along A and ``sb`` along B from their middle nodes, true
    capsule gap ``g``."""
    xa = line(np.array([-0.5, 0.0, 0.5]))
    u = np.array([math.cos(theta), math.sin(theta), 0.0])
    c = np.array([sa, 0.0, 2 * R_CAP + g])
    xb = c + np.outer(np.array([-0.5, 0.0, 0.5]) - sb, u)
    return two_rods(xa, xb)


@pytest.mark.parametrize("theta_deg", [10.0, 17.0, 45.0, 90.0])
def test_a_crossing_near_nodes_is_held_by_its_true_gap(theta_deg):
    """Wherever a crossing lies relative to the nodes, the barrier pushes the rods apart at
    least as hard as half of one term at the true gap plus ``EE_NODE_EXCESS dhat``: either the
    edge-edge term is fully on or an end node's term sees the gap within that excess (module
    doc). Measured defect this guards: with the edge-edge term faded over a fixed 0.4 of each
    segment, a crossing 8 % from two nodes at 17 degrees was held by 0.3 % of its term."""
    theta = math.radians(theta_deg)
    on = math.sqrt(2 * C.EE_NODE_EXCESS * DHAT * 2 * R_CAP) / math.sin(theta)
    worst = np.inf
    for g in (1e-2 * DHAT, 1e-3 * DHAT):
        ref = 0.25 * abs(db_of(g + C.EE_NODE_EXCESS * DHAT))  # weight (l_a + l_b) / 4 = 0.25
        for sa in np.linspace(0.0, min(3 * on, 0.2), 7):
            for sb in np.linspace(0.0, min(3 * on, 0.2), 7):
                x, mesh = _crossing(theta, sa, sb, g)
                _, grad, _ = contact_energy(mesh, x)
                worst = min(worst, -grad[3 * 3 + 2::3].sum() / ref)
    assert worst >= 0.5, worst


def test_step_filter_lets_pressed_rods_slide_and_turn_over_one_another():
    """B presses on A at 1e-3 dhat, crossing at 15 degrees, and slides 0.2 along itself while
    turning 10 degrees about the contact normal: the gap never changes (a rigid motion of B
    that keeps its plane), so the step is allowed whole; the relative speed bound alone
    allowed 0.9 g / (max node move), 1e-4 of it."""
    g0 = 1e-3 * DHAT
    th = math.radians(15.0)
    u = np.array([math.cos(th), math.sin(th), 0.0])
    xa = line(np.array([-0.5, 0.0, 0.5]))
    xb = np.array([0.0, 0.0, 2 * R_CAP + g0]) + np.outer([-0.5, 0.0, 0.5], u)
    x, mesh = two_rods(xa, xb)
    turn = math.radians(10.0)
    Rz = np.array([[math.cos(turn), -math.sin(turn), 0], [math.sin(turn), math.cos(turn), 0],
                   [0, 0, 1]])
    dx = np.zeros_like(x)
    dx[3:] = (xb + 0.2 * u) @ Rz.T - xb  # end state: slid and turned (nodes move linearly)
    alpha = max_step_fraction(mesh, x, dx)
    assert alpha > 0.99, alpha
    assert _sampled_min_gap(x, dx, mesh, alpha, 100, 201) > 0.1 * g0


@pytest.mark.slow
def test_step_filter_is_certified_on_random_moves_near_contact():
    """Random pairs of segments within dhat of one another and random moves: along the step
    the filter allows, the densely sampled gap (independent of rodstab's distance code) keeps
    (1 - safety) of its starting value."""
    rng = np.random.default_rng(21)
    for _ in range(30):
        c = rng.uniform(-0.1, 0.1, 3)
        a = rng.normal(size=3)
        b = rng.normal(size=3)
        n = np.cross(a, b)
        n /= np.linalg.norm(n)
        g0 = DHAT * 10 ** rng.uniform(-3, 0)
        xa = c + np.outer([-0.3, 0.0, 0.3], a / np.linalg.norm(a))
        xb = c + (2 * R_CAP + g0) * n + np.outer([-0.3, 0.0, 0.3], b / np.linalg.norm(b))
        x, mesh = two_rods(xa, xb)
        dx = rng.normal(size=x.shape) * 10 ** rng.uniform(-3, -1)
        start = _sampled_min_gap(x, dx, mesh, 0.0, 1, 101)
        alpha = max_step_fraction(mesh, x, dx, safety=0.9)
        assert 0 < alpha <= 1
        assert _sampled_min_gap(x, dx, mesh, alpha, 40, 101) >= 0.1 * start - 1e-9 * R_CAP


def test_partition_width_is_bounded_by_dhat_for_the_barrier_and_by_the_turn_for_a_penalty():
    """A straight rod of 0.5-long elements: the barrier's partition at a smooth node is at most
    0.1 dhat / sin(TAPER_MAX_TURN) (a phantom line stays within 0.1 dhat up to that turn in any
    state); the soft penalty's is the reference state's, 0.4 of the element on a straight rod."""
    x = line(np.array([0.0, 0.5, 1.0, 1.5]))
    hard = mesh_for(x, chain(3), MODEL)
    soft = mesh_for(x, chain(3), ContactModel(R_CAP, DHAT, KAPPA, soft=True))
    inner = hard.delta[hard.delta > 0]
    assert inner.size and np.allclose(inner, 0.1 * DHAT / math.sin(C.TAPER_MAX_TURN))
    assert np.allclose(soft.delta[soft.delta > 0], 0.4 * 0.5)


def test_the_pruned_sampled_distance_of_the_checks_equals_the_full_one():
    """contact_checks.smallest_distance skips pairs by a bounding-sphere lower bound: on random
    segments (some near, some far) it returns exactly sampled_distance over all pairs."""
    from contact_checks import sampled_distance, smallest_distance

    rng = np.random.default_rng(5)
    for _ in range(5):
        x = rng.uniform(-1.0, 1.0, (40, 3))
        edges = np.arange(40).reshape(20, 2)
        pairs = [(a, b) for a in range(20) for b in range(a + 1, 20)]
        assert smallest_distance(x, edges, pairs, n=11) == pytest.approx(
            sampled_distance(x, edges, pairs, 11), rel=1e-12)  # chunks may round apart


def test_remembered_exclusions_answer_as_the_rule_does_in_any_order() -> None:
    # The mesh remembers each exclusion it decided: asked again, in another order, with the
    # pair reversed, mixed with new pairs, every answer must be the rule's (undecided pairs,
    # computed directly), and a mesh made by dataclasses.replace must start afresh.
    import dataclasses

    _, mesh = _stacked_rings(12, 0.5 * DHAT)
    ne = len(mesh.edges)
    i, j = np.triu_indices(ne, 1)
    rule = mesh._elements(i, j)
    p, e = np.divmod(np.arange(mesh.n_nodes * ne), ne)
    rule_node = mesh._node_element(p, e)
    assert rule.any() and not rule.all() and rule_node.any() and not rule_node.all()
    rng = np.random.default_rng(7)
    for _ in range(4):
        k = rng.choice(len(i), size=len(i) // 3)
        a, b = (i[k], j[k]) if rng.random() < 0.5 else (j[k], i[k])
        np.testing.assert_array_equal(mesh.excluded_elements(a, b), rule[k])
        q = rng.choice(len(p), size=len(p) // 3)
        np.testing.assert_array_equal(mesh.excluded_node_element(p[q], e[q]), rule_node[q])
    np.testing.assert_array_equal(mesh.excluded_elements(j, i), rule)
    assert dataclasses.replace(mesh).memo == {} and mesh.memo
