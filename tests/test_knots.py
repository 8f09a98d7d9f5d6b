"""Knot types of closed centrelines (rodstab.multistable.knots).

References from knot theory, not from the code: the torus knot T(p, 2) (p odd) has determinant
p (T(3, 2) the trefoil: 3, T(5, 2): 5), T(p, 1) is the unknot (determinant 1), a mirror image
has the same determinant; an embedded planar curve is the unknot.
"""

from __future__ import annotations

import itertools

import numpy as np
import pytest

from rodstab.multistable.knots import (
    KnotClass,
    apart_by_topology,
    clearance,
    knot_class,
    ring_polygon,
)

T = np.linspace(0.0, 2 * np.pi, 90, endpoint=False)


def torus(p: int, q: int) -> np.ndarray:
    """The (p, q) torus curve on a torus of radii 2 and 0.7, 90 vertices."""
    return np.stack([(2 + 0.7 * np.cos(q * T)) * np.cos(p * T),
                     (2 + 0.7 * np.cos(q * T)) * np.sin(p * T), 0.7 * np.sin(q * T)], axis=1)


@pytest.mark.parametrize(("p", "q", "kind", "det"), [
    (3, 1, "unknot", 1), (1, 3, "unknot", 1), (3, 2, "knotted", 3), (2, 3, "knotted", 3),
    (5, 2, "knotted", 5), (2, 5, "knotted", 5)])
def test_torus_curves_have_their_knot_types(p, q, kind, det):
    k = knot_class(torus(p, q))
    assert k.kind == kind and k.determinant == det


def test_a_mirror_trefoil_is_knotted_with_the_same_determinant_and_a_wavy_circle_is_not():
    mirror = torus(3, 2) * np.array([1.0, 1.0, -1.0])
    assert knot_class(mirror) == KnotClass("knotted", 3, 90, knot_class(mirror).left)
    wavy = np.stack([np.cos(T), np.sin(T), 0.1 * np.sin(5 * T)], axis=1)
    assert knot_class(wavy).kind == "unknot" and knot_class(wavy).left == 3


def test_a_curve_that_meets_itself_has_no_knot_type():
    """A figure of eight drawn in the plane crosses itself at the origin."""
    eight = np.stack([np.sin(2 * T), np.sin(T), 0 * T], axis=1)
    assert clearance(eight) < 1e-12
    assert knot_class(eight).kind == "meets itself"


def test_only_certified_different_knots_are_kept_apart():
    unknot, tre = KnotClass("unknot", 1, 9, 3), KnotClass("knotted", 3, 9, 7)
    five, open_ = KnotClass("knotted", 5, 9, 7), KnotClass("undecided", None, 9, 9)
    assert apart_by_topology(unknot, tre) and apart_by_topology(tre, five)
    assert not apart_by_topology(unknot, unknot) and not apart_by_topology(tre, tre)
    assert not apart_by_topology(unknot, open_) and not apart_by_topology(open_, tre)


def test_the_hexagram_states_and_the_stacked_line_in_two_columns():
    """The planar star and daisy are unknots. The line stacked in two columns (6 el./rod) has
    its three cusps at x = 0 joined across the layers by links that cross one another: its
    centreline meets itself, so the model gives it no knot type. Staggered in x in any of the
    six orders (each link then clear of the others) it is the unknot every time: topology does
    not keep it from the star."""
    from rodstab.multistable.discover import common_rod
    from rodstab.multistable.identify import ring_order, segment_nodes
    from rodstab.multistable.layered import lift, stacked_model
    from rodstab.nonlinear.equilibrium import rod_contact_model
    from rodstab.nonlinear.newton import newton
    from rodstab.problems.barrier_states import state_assembly
    from rodstab.sections import rectangle

    sec = rectangle(aspect=4.0)
    for state in ("star", "daisy"):
        r = common_rod(state_assembly("hexagram", sec, state), 6, 1.5)
        assert newton(r)[0]
        poly = ring_polygon(r)
        assert len(poly) == 36 and knot_class(poly).kind == "unknot"
    line = state_assembly("hexagram", sec, "line")
    planar = common_rod(line, 6, 1.0)
    assert newton(planar)[0]
    two = {"1": (-0.5, 0), "3": (-0.5, 1), "5": (-0.5, 2),
           "2": (0.5, 0), "4": (0.5, 1), "6": (0.5, 2)}
    rod = lift(stacked_model(planar, two, rod_contact_model(line, 0.02, 0.1)), planar, planar)
    assert knot_class(ring_polygon(rod)).kind == "meets itself"
    order = ring_order(rod)
    assert order is not None
    welds = [(segment_nodes(rod, k)[::d][-1], segment_nodes(rod, k2)[::d2][0])
             for (k, d), (k2, d2) in zip(order, order[1:] + order[:1], strict=True)]
    at0 = [w for w in welds if abs(rod.x[w[0], 0]) < 1e-9]
    assert len(at0) == 3
    for shifts in itertools.permutations((-1, 0, 1)):
        x = rod.x.copy()
        for (end, start), s in zip(at0, shifts, strict=True):
            x[[end, start], 0] += 0.005 * s
        k = knot_class(ring_polygon(rod, x))
        assert k.kind == "unknot" and k.determinant == 1, shifts


def test_certificates_that_disagree_leave_the_type_undecided(monkeypatch):
    """Either certificate alone would decide; a contradiction (a defect) decides nothing."""
    import rodstab.multistable.knots as knots

    wavy = np.stack([np.cos(T), np.sin(T), 0.1 * np.sin(5 * T)], axis=1)
    monkeypatch.setattr(knots, "knot_determinant", lambda poly: 3)
    k = knot_class(wavy)
    assert k.left == 3 and k.kind == "undecided"
    assert knots.describe("ring", KnotClass("undecided", None, 9, 9)) == (
        "ring undecided (not reduced below 9 vertices, determinant not given)")
