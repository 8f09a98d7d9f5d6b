"""Stacked states free of interpenetration (issue 21, part 2): rodstab.multistable.stacking.

Oracles: closed forms of the (N, 1) torus curve (strand distances, length, bending excess
coefficient derived by series, module doc), brute-force distances on a dense sampling, the
contact model's own check, and the thin limit h / L -> 0.
"""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from rodstab.errors import RodstabInputError
from rodstab.multistable.layer_orders import overlapping_segments, polygon_offsets, traversal_layers
from rodstab.multistable.stacking import (
    StackingError,
    bending_excess_coefficient,
    default_model,
    stack_layers,
    stack_loops,
    strand_distance,
    torus_curve,
    torus_length,
    torus_point,
)
from rodstab.multistable.states import ring_of, uniform_ring
from rodstab.nonlinear.contact import contact_energy, mesh_of_rod, segment_distance
from rodstab.nonlinear.discrete import discretise
from rodstab.problems import birod, folded_ring, ring


def _ring_rod(loops: int, elements: int):
    return discretise(ring.build(ring.Params(loops=loops)), elements, 1.0)


@pytest.mark.parametrize("N", [2, 3, 4, 5])
@pytest.mark.slow
def test_torus_nearest_strands_are_one_spacing_apart_in_3d(N):
    """True 3D nearest-strand distance = h + g0, every strand pair (m = 1 .. N - 1).

    Brute force, not using the module's distance formula: points of the curve at 720 N
    parameters against the points of strand m at ``phi + 2 pi m + delta``, ``|delta| <= 0.05``
    on a grid of 401 (the nearest point is within it: ``|delta*| ~ a^2 / N R^2``). The sampled
    minimum is >= the true one and above it by < 1e-6 relative (grid error ~ (R ddelta / 2)^2).
    """
    L, h = 2 * math.pi * N, 0.2
    tc = torus_curve(N, L, h, 0.05 * h)
    assert tc.strand_distance == pytest.approx(tc.spacing, rel=1e-10)
    if N > 2:
        assert tc.meridian_distance > tc.spacing  # inclined strands come nearer
    phi = np.arange(720 * N) * (2 * math.pi / 720)
    P = torus_point(phi, N, tc.R, tc.a)
    delta = np.linspace(-0.05, 0.05, 401)
    best = np.inf
    for m in range(1, N):
        Q = torus_point((phi[:, None] + 2 * math.pi * m + delta).ravel(), N, tc.R, tc.a)
        d = np.linalg.norm(Q.reshape(len(phi), len(delta), 3) - P[:, None, :], axis=2)
        best = min(best, float(d.min()))
    assert best >= tc.spacing * (1 - 1e-12)
    assert best == pytest.approx(tc.spacing, rel=1e-6)


@pytest.mark.parametrize("N, a", [(3, 0.003), (5, 0.004), (4, 0.01)])
def test_inclined_strands_closer_than_the_meridian_chord_by_the_closed_form(N, a):
    """``D_mer^2 - D_min^2 = a^4 sin^2(2 pi / N) / (N^2 (R^2 - 2 R a cos(pi / N)))`` (m = 1);
    for N = 4 the opposite strands (m = 2) sit exactly ``2 a`` apart (no inclination term).
    """
    R = 1.0
    dm = 2 * a * math.sin(math.pi / N)
    pred = a**4 * math.sin(2 * math.pi / N) ** 2 / (N**2 * (R * R - 2 * R * a
                                                            * math.cos(math.pi / N)))
    assert (dm**2 - strand_distance(N, R, a, 1) ** 2) / pred == pytest.approx(1.0, abs=0.01)
    if N == 4:
        assert strand_distance(N, R, a, 2) == pytest.approx(2 * a, rel=1e-12)


@pytest.mark.parametrize("N", [2, 3, 6])
def test_torus_length_equals_L_and_the_excess_at_R0_is_the_closed_form(N):
    """Length at the solved R is L; at R0 = L / 2 pi N the curve is longer by
    ``pi a^2 / (N sqrt(R0^2 - a^2))`` to O(a^4)."""
    L, h = 2 * math.pi * N, 0.01
    tc = torus_curve(N, L, h, 0.05 * h)
    assert tc.length_check == pytest.approx(L, rel=1e-12)
    assert torus_length(N, tc.R, tc.a) == pytest.approx(L, rel=1e-12)
    assert tc.R < tc.R0
    excess = math.pi * tc.a**2 / (N * math.sqrt(tc.R0**2 - tc.a**2))
    assert tc.length_excess_at_R0 == pytest.approx(excess, rel=1e-3)


@pytest.mark.parametrize("N, expected_order", [(2, 2.0), (3, 2.0), (5, 2.0)])
def test_bending_excess_vanishes_at_second_order_with_the_series_coefficient(N, expected_order):
    """``int kappa^2 ds / (L / R0^2) - 1 -> c (a / R0)^2``, ``c = (N^2-1)(N^2-2) / 2N^4``
    (sympy series of the module doc); fitted order over 4 thicknesses within 0.2 of 2."""
    L = 2 * math.pi * N
    hs = [0.04, 0.02, 0.01, 0.005]
    curves = [torus_curve(N, L, h, 0.05 * h) for h in hs]
    ex = [c.bending_excess for c in curves]
    slope = np.polyfit(np.log(hs), np.log(ex), 1)[0]
    assert abs(slope - expected_order) <= 0.2
    c = bending_excess_coefficient(N)
    assert ex[-1] / (curves[-1].a / curves[-1].R0) ** 2 == pytest.approx(c, rel=2e-3)
    assert all(e > 0 for e in ex)


@pytest.mark.parametrize("N, elements", [(2, 32), (3, 32), (4, 24)])
def test_stacked_ring_keeps_gap_g0_under_the_contact_model(N, elements):
    """Every non-excluded element pair of the discrete stacked ring has gap >= g0 (the chord
    allowance covers the chords' sag); contact_energy does not raise; frames follow the
    chords with d3 near e3; joint frames follow the curve's tangent."""
    rod = _ring_rod(N, elements)
    h, g0 = 0.05, 0.0025
    st = stack_loops(rod, h, g0)
    assert st.check.holds and st.check.min_gap >= g0
    model = default_model(h)
    energy, _, _ = contact_energy(mesh_of_rod(st.rod, model), st.rod.x)
    assert energy >= 0.0
    # independent of the broad phase: every element pair more than a quarter loop apart
    x, E = st.rod.x, st.rod.edge_nodes
    i, j = np.triu_indices(len(E), 1)
    sep = np.abs(i - j)
    sep = np.minimum(sep, len(E) - sep)
    keep = sep > elements // 4
    d = segment_distance(x[E[i[keep], 0]], x[E[i[keep], 1]], x[E[j[keep], 0]],
                         x[E[j[keep], 1]])
    assert d.min() - h >= g0
    # curve spacing = h + g0 + allowance; elements at most the chord error nearer
    assert d.min() >= st.torus.spacing - st.chord_error
    chord = x[E[:, 1]] - x[E[:, 0]]
    chord /= np.linalg.norm(chord, axis=1)[:, None]
    assert np.allclose(np.einsum("ei,ei->e", st.rod.R_edge[:, :, 1], chord), 1.0, atol=1e-12)
    assert np.min(st.rod.R_edge[:, 2, 2]) > math.cos(4 * st.torus.a / st.torus.R0)
    for R in list(st.rod.R_edge) + list(st.rod.R_joint):
        assert np.allclose(R.T @ R, np.eye(3), atol=1e-12)
    assert st.max_strain < 1e-3


def test_coarse_mesh_without_allowance_states_the_chord_error():
    """Without the allowance the strands are h + g0 apart and the elements may stand up to the
    stated chord error nearer: the check then asks only g >= g0 - chord error."""
    rod = _ring_rod(2, 64)
    h, g0 = 0.05, 0.0025
    st = stack_loops(rod, h, g0, chord_allowance=False)
    assert st.torus.spacing == pytest.approx(h + g0, rel=1e-12)
    assert st.check.min_gap >= g0 - st.chord_error
    assert st.check.min_gap < g0  # the sag is real at 64 elements per loop


def test_rings_stacked_flat_must_interpenetrate():
    """Three loops in flat layers 0, 1, 2: the weld from the top loop back to the bottom one
    ramps through the middle layer; refused, naming the weld and both rods."""
    rod = _ring_rod(3, 32)
    h = 0.05
    with pytest.raises(StackingError, match=r"ring1\.start layer 0 - ring3\.end layer 2"):
        stack_layers(rod, {"ring1": 0, "ring2": 1, "ring3": 2}, h, 0.05 * h)


def test_folded_six_ring_in_flat_layers_is_refused_and_the_hexagon_holds():
    """Sec. 5 folded ring (6 straight rods on [0, L]): layers along e3 alone cannot hold its 6
    cusps (a cycle of 6 adjacencies in a path of 6 layers); the traversal order is refused at
    cusp 1.end - 2.end (layers 0 and 5, x = L). On the hexagon (polygon_offsets in traversal
    order) every cusp joins neighbouring vertices and the gaps hold."""
    rod = discretise(folded_ring.build(folded_ring.Params()), 32, 1.0)
    h, g0 = 0.02, 0.001
    assert len(overlapping_segments(rod, h)) == 15  # all six lie on one another
    layers = traversal_layers(rod, h)
    assert sorted(layers.values()) == list(range(6))
    with pytest.raises(StackingError, match=r"1\.end layer 0 - 2\.end layer 5 at \(1, 0\)"):
        stack_layers(rod, layers, h, g0)
    with pytest.raises(StackingError, match="interpenetrates"):
        stack_layers(rod, {str(i): i - 1 for i in range(1, 7)}, h, g0)
    order = [nm for nm, _ in ring_of(rod.assembly).order]
    st = stack_layers(rod, polygon_offsets(order), h, g0)
    assert st.check.min_gap >= g0 - st.chord_error and st.check.min_gap > 0
    assert len(st.changes) == 6
    # neighbouring vertices are one spacing apart, the others further
    off = polygon_offsets(order)
    for a, b in zip(order, order[1:] + order[:1], strict=True):
        assert math.dist(off[a], off[b]) == pytest.approx(1.0, rel=1e-12)


def test_birod_two_layers_ramp_at_both_welds():
    """Bi-rod (Sec. 4): upper and lower overlap along their length; traversal layers 0, 1;
    both welds change layer; gaps hold away from the welds and nothing interpenetrates."""
    rod = discretise(birod.build(birod.Params()), 32, 1.0)
    h, g0 = 0.02, 0.001
    layers = traversal_layers(rod, h)
    assert layers == {"upper": 0, "lower": 1}
    st = stack_layers(rod, layers, h, g0)
    assert len(st.changes) == 2
    assert st.check.min_gap == pytest.approx(g0, rel=1e-9)
    mid = st.rod.x[np.abs(st.rod.x[:, 0] - 0.5) < 0.2]
    assert np.allclose(np.sort(np.unique(np.round(mid[:, 2] / (h + g0), 9))), [0.0, 1.0])


def test_thin_limit_returns_to_the_coincident_rings():
    """h / L -> 0 (mesh refined with sqrt(h), so the chord allowance scales with h): the
    stacked ring tends to the coincident one, its largest displacement O(h); the discrete
    rod's own energy (load factor 0: pure bending and twist of the held curvature) exceeds the
    coincident ring's at second order, by at least the curve's bending excess (twist and
    stretch only add), an independent check of the series through the rod model."""
    hs, moves, excess = [0.04, 0.01, 0.0025], [], []
    for h, n in zip(hs, [32, 64, 128], strict=True):
        rod = discretise(ring.build(ring.Params(loops=3)), n, 0.0)
        st = stack_loops(rod, h, 0.05 * h)
        moves.append(st.max_offset)
        excess.append(st.rod.energy() / rod.energy() - 1.0)
        assert st.check.holds
        assert excess[-1] >= 0.9 * st.torus.bending_excess
    assert np.polyfit(np.log(hs), np.log(moves), 1)[0] >= 1.0 - 0.2
    assert abs(np.polyfit(np.log(hs), np.log(excess), 1)[0] - 2.0) <= 0.2
    assert moves[-1] < 0.05
    tc = torus_curve(3, 6 * math.pi, 1e-8, 1e-10)
    phi = np.linspace(0.0, 6 * math.pi, 50)
    planar = np.stack([np.cos(phi), np.sin(phi), 0 * phi], axis=1)
    assert np.max(np.abs(torus_point(phi, 3, tc.R, tc.a) - planar)) < 1e-7


@pytest.mark.parametrize("call, key", [
    (lambda: torus_curve(3, 1.0, -0.1, 0.01), "thickness"),
    (lambda: torus_curve(3, 1.0, 0.01, 0.0), "gap"),
    (lambda: torus_curve(0, 1.0, 0.01, 0.001), "loops"),
    (lambda: torus_curve(3, 1.0, 0.1, 0.01), "too large"),
    (lambda: stack_loops(discretise(folded_ring.build(folded_ring.Params()), 8, 1.0), 0.02,
                         0.001), "coincident circular loops"),
    (lambda: stack_layers(_ring_rod(2, 16), {"ring1": 0}, 0.05, 0.001), "missing"),
    (lambda: stack_layers(_ring_rod(2, 16), {"ring1": 0, "ring2": "top"}, 0.05, 0.001),
     "layers"),
])
def test_bad_input_names_the_parameter(call, key):
    """Each bad input raises RodstabInputError naming the parameter or the fault."""
    with pytest.raises(RodstabInputError, match=key):
        call()


def test_hexagram_line_holds_on_the_hexagon_and_the_star_in_two_layers():
    """Hexagram (six cusp-welded rods, Ring.held): the line refuses flat layers in traversal
    order at the closing cusp 6 -> 1 and holds on the hexagon (rods run alternately, the
    in-plane offset follows the first rod's sense); the star, whose rods overlap only their
    neighbours near the cusps, needs only layers 0 and 1 alternating."""
    ring6 = uniform_ring(6, weld="cusp", natural_curvature=1.0)
    h, g0 = 0.02, 0.001
    line = discretise(ring6.held(ring6.state("line").theta), 32, 1.0)
    with pytest.raises(StackingError, match=r"6\.end layer 5 - 1\.start layer 0"):
        stack_layers(line, traversal_layers(line, h), h, g0)
    st = stack_layers(line, polygon_offsets([str(i) for i in range(1, 7)]), h, g0)
    assert st.check.min_gap >= g0 - st.chord_error and len(st.changes) == 6
    star = discretise(ring6.held(ring6.state("star").theta), 32, 1.0)
    layers = traversal_layers(star, h)
    assert layers == {str(i): (i - 1) % 2 for i in range(1, 7)}
    st = stack_layers(star, layers, h, g0)
    assert st.check.min_gap >= g0 - st.chord_error and len(st.changes) == 6
    assert json.loads(json.dumps(st.to_dict()))["changes"] == list(st.changes)
