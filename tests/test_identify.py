"""The one identification of ring states (multistable/identify.py, issue 20).

Oracles: known transforms (a state moved rigidly, reflected, its rods relabelled along the ring
or the ring reversed, each built here independently of :func:`identify.ring_nodes`, is the
same state: distance 0), closed forms (the held states' turning numbers ``n theta / 2 pi`` and
weld points, :mod:`rodstab.multistable.states`), and a table of the inputs on which the two
formulas this module replaced disagreed with those oracles.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from rodstab.io.design import load_design
from rodstab.multistable import identify as idf
from rodstab.multistable.states import ring_of, uniform_ring
from rodstab.nonlinear.discrete import discretise
from rodstab.nonlinear.jets import rodrigues
from rodstab.nonlinear.parameters import parameter
from rodstab.nonlinear.solve import newton
from rodstab.problems import hexagram as hx
from rodstab.sections import rectangle

N = 8
SECTION = rectangle(aspect=4.0)
HEXAGRAM = uniform_ring(hx.SEGMENTS, length=1.0, natural_curvature=hx.L_OVER_R0,
                        B1=SECTION.b1, B2=SECTION.b2)
FOLDED = ring_of(load_design("examples/folded_six_ring.toml").assembly)


def _rod(ring, label: str, elements: int = N):
    return discretise(ring.held(ring.state(label).theta), elements, 1.0)


def _traversal(ring, rod) -> np.ndarray:
    """Node ids along the ring from Ring.order (each rod reversed where the ring runs
    backwards), each once: the reference for ring_nodes, built from the ring, not the rod."""
    ids = []
    for k, (_, d) in enumerate(ring.order):
        en = rod.edge_nodes[k * N:(k + 1) * N]
        seg = np.concatenate([en[:, 0], en[-1:, 1]])
        ids += list(seg[::d][:-1])
    return np.array(ids)


def _bent(rod, seed: int = 0, size: float = 0.05):
    """``rod`` in a generic 3D shape (no symmetry left): every node moved by up to ``size``."""
    r = rod.copy()
    rng = np.random.default_rng(seed)
    r.x = r.x + size * rng.uniform(-1, 1, r.x.shape)
    r.align_frames()
    return r


@pytest.mark.parametrize("ring", [HEXAGRAM, FOLDED], ids=["hexagram", "folded six-ring"])
def test_ring_nodes_follow_the_ring_each_node_once(ring):
    """The folded six-ring's rods run alternately backwards: the walk over the joints gives
    the same traversal as Ring.order, and Ring.order's directions."""
    rod = _rod(ring, "star")
    nodes = idf.ring_nodes(rod)
    assert np.array_equal(nodes, _traversal(ring, rod))
    assert sorted(nodes) == list(range(len(rod.x)))
    assert idf.ring_directions(rod) == tuple(d for _, d in ring.order)


@pytest.mark.parametrize("ring", [HEXAGRAM, FOLDED], ids=["hexagram", "folded six-ring"])
@pytest.mark.parametrize("shift", [0, 1, 2, 5])
@pytest.mark.parametrize("reverse", [False, True])
@pytest.mark.parametrize("reflect", [False, True])
def test_a_moved_relabelled_reflected_state_is_the_same_state(ring, shift, reverse, reflect):
    """A generic 3D state, rotated, translated, optionally mirrored, its ring started ``shift``
    rods later and optionally run backwards (the positions permuted along the traversal of
    Ring.order), is at aligned distance 0 from itself: identified as the same state; a
    different state (the daisy) is not."""
    rod = _bent(_rod(ring, "star"))
    a = idf.Snapshot.of(rod)
    order = _traversal(ring, rod)
    seq = a.x[order]
    if reverse:
        seq = np.concatenate([seq[:1], seq[:0:-1]])
    seq = np.roll(seq, shift * N, axis=0)
    x = a.x.copy()
    x[order] = seq
    Q = rodrigues(np.array([[0.3, -1.1, 0.7]]))[0]
    if reflect:
        Q = Q @ np.diag([1.0, -1.0, 1.0])
    b = idf.Snapshot(x @ Q.T + np.array([1.0, -2.0, 0.5]), a.R_edge, a.R_joint)
    assert idf.aligned_distance(rod, a, b) < 1e-12
    assert idf.same_state(rod, a, b, 1.0, 1.0)
    daisy = idf.Snapshot.of(_rod(ring, "daisy"))
    assert idf.aligned_distance(rod, a, daisy) > 0.1


def test_a_mirror_image_in_3d_is_not_a_proper_rotation():
    """The reflected generic state above is at distance 0 only because reflections are
    allowed: the best proper rotation leaves it far (the mirror images are distinct point
    sets), which is why transitions' proper-rotation Kabsch was replaced (table below)."""
    rod = _bent(_rod(HEXAGRAM, "star"))
    x = rod.x[idf.ring_nodes(rod)]
    y = x @ np.diag([1.0, 1.0, -1.0])
    assert idf.kabsch_rms(x, y) < 1e-12
    a, b = x - x.mean(axis=0), y - y.mean(axis=0)
    U, _, Vt = np.linalg.svd(a.T @ b)
    D = np.diag([1.0, 1.0, float(np.sign(np.linalg.det(U @ Vt)))])
    proper = float(np.sqrt(np.mean(np.sum((a @ U @ D @ Vt - b) ** 2, axis=1))))
    assert proper > 1e-3


@pytest.mark.parametrize("ring, name", [(HEXAGRAM, "hexagram"), (FOLDED, "folded six-ring")])
def test_held_states_have_their_closed_form_invariants(ring, name):
    """Turning number ``n theta / 2 pi`` and distinct weld points of every closed held state
    (Ring.states, exact), measured on the discrete rod in its held state."""
    for st in ring.states().states:
        rod = _rod(ring, st.label)
        inv = idf.invariants(rod)
        assert inv.turning_number == pytest.approx(st.turning_number, abs=1e-9), st.label
        assert inv.distinct_weld_points == st.distinct_weld_points, st.label
        assert inv.planar and inv.max_out_of_plane < 1e-12


def _old_transitions_turning(rod, n: int = N) -> float:
    """transitions.py's turning number before issue 20: chord turnings inside each rod, times
    n / (n - 1) for the two half-joints (exact only if every rod turns uniformly)."""
    x = rod.x
    c = x.mean(axis=0)
    normal = np.linalg.svd(x - c)[2][2]
    if normal @ rod.R_edge[:, :, 2].mean(axis=0) < 0:
        normal = -normal
    chord = x[rod.edge_nodes[:, 1]] - x[rod.edge_nodes[:, 0]]
    turn = 0.0
    for s in range(len(rod.assembly.segments)):
        t = chord[s * n:(s + 1) * n]
        turn += float(np.sum(np.arctan2(np.cross(t[:-1], t[1:]) @ normal,
                                        np.einsum("ij,ij->i", t[:-1], t[1:]))))
    return turn * n / (n - 1) / (2 * math.pi)


def _reshaped(rod, amplitude: float):
    """The rod with rod 0's inner nodes moved in the plane by ``amplitude sin(pi s / L)`` along
    the in-plane normal, its welds and their frames kept: the turning is no longer uniform
    along rod 0, and its total (end tangent minus start tangent) is unchanged."""
    r = rod.copy()
    inner = r.edge_nodes[1:N, 0]
    s = np.arange(1, N) / N
    t = r.R_edge[:N, :, 1]
    nrm = np.cross([0.0, 0.0, 1.0], 0.5 * (np.vstack([t[:1], t[:-1]]) + t)[1:])
    r.x[inner] += amplitude * np.sin(math.pi * s)[:, None] * nrm
    r.align_frames()
    return r


#: Inputs on which an old formula disagreed with the closed form: (state, in-plane amplitude
#: over L, exact turning number). The held states' turning is exact for both; a rod whose
#: turning is not uniform (a state under a weld moment, a 3D state) is where transitions' chord
#: formula (x n / (n - 1)) is off, by the end chords' extra turning.
NON_UNIFORM = [("star", 0.05, 2.0), ("star", -0.05, 2.0), ("daisy", 0.05, 4.0),
               ("eight", 0.03, 6.0)]


@pytest.mark.parametrize("label, amplitude, exact", NON_UNIFORM)
def test_turning_number_counts_the_half_joints_exactly(label, amplitude, exact):
    """The one turning number (discover's formula: end frames included) keeps the closed form
    on a rod reshaped with its end tangents held; transitions' old chord formula was off."""
    rod = _reshaped(_rod(HEXAGRAM, label), amplitude)
    assert idf.invariants(rod).turning_number == pytest.approx(exact, abs=1e-9)
    assert abs(_old_transitions_turning(rod) - exact) > 1e-3


def test_the_line_state_is_planar_about_its_frames_normal():
    """The line's nodes are collinear (no plane of their own): the plane normal is the frames'
    mean d3 and the turning is 0."""
    rod = _rod(HEXAGRAM, "line")
    c, n = idf.best_fit_plane(rod.x, rod.R_edge[:, :, 2])
    assert abs(abs(n[2]) - 1.0) < 1e-12
    inv = idf.invariants(rod)
    assert inv.turning_number == pytest.approx(0.0, abs=1e-12) and inv.planar
    assert inv.distinct_weld_points == 2


#: Equilibria of transitions' own stimulus (a binormal moment on weld 2, B3 / L, at kappa_n R0
#: = 2, h/t = 4) on which transitions' old chord formula was off: (state, moment, elements).
#: A planar closed ring of cusp-welded rods turns by a whole number of turns (the cusps' pi
#: each not counted): the closed form is the held state's ``n theta / 2 pi``. Measured before
#: the merge: 2.0104, 2.0087, 4.0012, 3.9985 (transitions --json reported such numbers as
#: target_invariants.turning_number; its hexagram run with a circle section named a state
#: under load other(w=6,T=4.01)).
WELD_MOMENT = [("star", 3.0, 6), ("star", 3.0, 8), ("daisy", 3.0, 8), ("daisy", 6.0, 6)]


@pytest.mark.parametrize("label, moment, elements", WELD_MOMENT)
def test_turning_number_of_a_state_under_a_weld_moment_is_whole(label, moment, elements):
    """Under a weld moment the rods turn non-uniformly: the one turning number stays the held
    state's whole number; the old chord formula (x n / (n - 1)) did not."""
    a = hx.build(hx.Params(section=SECTION, state=label))
    rod = discretise(a, elements, 2.0)
    p = parameter(a, "weld.2.moment.binormal", elements)
    p.prepare(rod)
    p.set(rod, moment)
    assert newton(rod)[0]
    exact = HEXAGRAM.state(label).turning_number
    inv = idf.invariants(rod)
    assert inv.planar and inv.turning_number == pytest.approx(exact, abs=1e-9)
    assert abs(_old_transitions_turning(rod, elements) - exact) > 1e-3


def _old_discover_distance(rod, x: np.ndarray, y: np.ndarray) -> float:
    """discover.py's aligned distance before issue 20: every rod's nodes in the rod's own
    direction, relabelled by whole rods (cyclic shift; rods and nodes both reversed)."""
    n_seg = len(rod.assembly.segments)
    en = rod.edge_nodes.reshape(n_seg, N, 2)
    seg = np.concatenate([en[:, :, 0], en[:, -1:, 1]], axis=1)
    Pa, Pb = x[seg].reshape(-1, 3), y[seg]
    return min(idf.kabsch_rms(Pa, np.roll(img, r, axis=0).reshape(-1, 3))
               for img in (Pb, Pb[::-1, ::-1]) for r in range(n_seg)) * n_seg \
        / rod.assembly.total_length


#: Relabellings of the folded six-ring (its rods run alternately backwards along the ring) that
#: discover's old distance missed: the images it tried put a rod's nodes, in the rod's own
#: direction, where the ring runs the other way. (shift by whole rods, reversed). Not reached
#: by the states `rodstab discover` finds on it (each found once; their held-like shapes are
#: symmetric enough that the images it did try matched), but a generic state and its image
#: were two states to it.
FOLDED_MISSED = [(1, False), (3, False), (5, False), (0, True), (2, True), (4, True)]


@pytest.mark.parametrize("shift, reverse", FOLDED_MISSED)
def test_relabellings_of_a_ring_with_backward_rods_are_the_same_state(shift, reverse):
    """A generic state of the folded six-ring relabelled along the ring is at distance 0 to
    the one distance (the traversal of Ring.order, each node once); it was ~0.07 L to the old."""
    rod = _bent(_rod(FOLDED, "star"))
    order = _traversal(FOLDED, rod)
    seq = rod.x[order]
    if reverse:
        seq = np.concatenate([seq[:1], seq[:0:-1]])
    x = rod.x.copy()
    x[order] = np.roll(seq, shift * N, axis=0)
    a, b = idf.Snapshot.of(rod), idf.Snapshot(x, rod.R_edge, rod.R_joint)
    assert idf.aligned_distance(rod, a, b) < 1e-12
    assert _old_discover_distance(rod, rod.x, x) > 0.01


#: The eight (all six welds at one point) as an equilibrium of discover's common rod at
#: kappa_n R0 = 2 (Newton from its held geometry): its welds are split by the discretisation,
#: by 0.0257, 0.0105, 0.0012, 0.00015 L at 6, 8, 16, 32 elements per rod (third order). A
#: fixed WELD_POINT_TOL (1e-2 L, discover's; transitions had 2e-2) counts 2 weld points on
#: the coarse meshes, so `rodstab discover --elements 8` names the eight "unnamed" (w=2,
#: T=6). Kept as it was (its recorded output names it so); a tolerance that follows the mesh is
#: a change of labels, left to a decision: strict xfail until then.
EIGHT_WELDS = [(6, True), (8, True), (16, False), (32, False)]


@pytest.mark.parametrize("elements, coarse", EIGHT_WELDS)
def test_the_eight_has_one_weld_point_on_every_mesh(elements, coarse, request):
    """One weld point for the eight whatever the mesh (the continuum's); fails below 16
    elements per rod (the weld gap is the mesh's O(l_e^3), above the fixed tolerance)."""
    from rodstab.multistable.discover import common_rod

    if coarse:
        request.applymarker(pytest.mark.xfail(strict=True, reason="fixed WELD_POINT_TOL "
                                              "below the coarse mesh's weld gap"))
    rod = common_rod(HEXAGRAM.held(HEXAGRAM.state("eight").theta), elements, 2.0)
    assert newton(rod)[0]
    inv = idf.invariants(rod)
    assert inv.turning_number == pytest.approx(6.0, abs=1e-9)
    assert inv.distinct_weld_points == 1


def _proper_rms(x: np.ndarray, y: np.ndarray) -> float:
    """transitions.py's Kabsch before issue 20: proper rotations only."""
    a, b = x - x.mean(axis=0), y - y.mean(axis=0)
    U, _, Vt = np.linalg.svd(a.T @ b)
    D = np.diag([1.0, 1.0, float(np.sign(np.linalg.det(U @ Vt))) or 1.0])
    return float(np.sqrt(np.mean(np.sum((a @ U @ D @ Vt - b) ** 2, axis=1))))


@pytest.mark.parametrize("seed", range(4))
def test_against_a_planar_reference_reflections_change_nothing(seed):
    """transitions' references are planar held states: for any state (here generic, 3D) the
    distance with reflections allowed equals transitions' old proper-rotation one, over every
    relabelling (the cross-covariance with a planar set has a zero singular value)."""
    ref = _rod(HEXAGRAM, "star")
    rod = _bent(ref, seed=seed, size=0.2)
    x, y = rod.x[idf.ring_nodes(rod)], ref.x[idf.ring_nodes(ref)]
    for image in (x, np.concatenate([x[:1], x[:0:-1]])):
        for k in range(6):
            xs = np.roll(image, k * N, axis=0)
            assert idf.kabsch_rms(xs, y) == pytest.approx(_proper_rms(xs, y), rel=1e-12)


@pytest.mark.parametrize("ring", [HEXAGRAM, FOLDED], ids=["hexagram", "folded six-ring"])
@pytest.mark.slow
def test_discover_deduplicates_as_before_on_the_states_it_finds(ring):
    """Every pair of equilibria discover finds from the held states (8 elements, kappa_n R0
    = 2 -- the folded ring's load in its units): the one distance and discover's old one are
    on the same side of SAME_STATE_DISTANCE, and the states found are all distinct."""
    from rodstab.multistable import discover as dv

    mu = 2.0 if ring is HEXAGRAM else 2.0 * 2 * math.pi / 3
    rod, seeds, known = dv.ring_seeds(ring, "star", N, mu, True)
    found, snaps = dv.discover(rod, seeds, known, starts=0,
                               directions=tuple(d for _, d in ring.order))
    assert len(snaps) == len(seeds)  # each seed its own state
    for i, a in enumerate(snaps):
        for b in snaps[i + 1:]:
            new = idf.aligned_distance(rod, a, b) < idf.SAME_STATE_DISTANCE
            old = _old_discover_distance(rod, a.x, b.x) < idf.SAME_STATE_DISTANCE
            assert new == old
    labels = [s.label for s in found.states]
    assert {"star", "daisy", "line"} <= set(labels)


UNEQUAL = ring_of(load_design("examples/hexagram_unequal.toml").assembly)


@pytest.mark.parametrize("ring,expected", [
    (HEXAGRAM, {(f, k) for f in (False, True) for k in range(6)}),
    (FOLDED, {(f, k) for f in (False, True) for k in range(6)}),
    # rods alternating 1.45 / 0.55: shifts by two rods, and the reversals that put a long
    # rod on a long one (slot m holds rod k - 1 - m: k odd)
    (UNEQUAL, {(False, 0), (False, 2), (False, 4), (True, 1), (True, 3), (True, 5)}),
], ids=["hexagram", "folded six-ring", "alternating lengths"])
def test_relabellings_are_the_rings_symmetries(ring, expected):
    assert set(idf.ring_relabellings(_rod(ring, "star"))) == expected


@pytest.mark.parametrize("shift,same", [(1, False), (2, True), (3, False)])
def test_a_state_shifted_by_a_rod_that_is_no_symmetry_is_another_state(shift, same):
    """On the ring of alternating lengths a generic state started one rod later puts the long
    rods' shapes on the short rods: no longer the same state (it was, before relabellings were
    restricted to the ring's symmetries); two rods later it is."""
    rod = _bent(_rod(UNEQUAL, "star"))
    a = idf.Snapshot.of(rod)
    order = _traversal(UNEQUAL, rod)
    x = a.x.copy()
    x[order] = np.roll(a.x[order], shift * N, axis=0)
    b = idf.Snapshot(x, a.R_edge, a.R_joint)
    assert (idf.aligned_distance(rod, a, b) < 1e-12) is same
