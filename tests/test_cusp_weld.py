"""Cusp welds of finite width (``discretise(..., cusp_width=w)``, issue 21).

Two rods of thickness h cannot both leave a point along one line; with contact the point cusp
weld forces them apart within an element, at a cost that grows as the elements shorten
(docs/theory/contact.md). A cusp weld of width w holds the two ends w apart across the tangent.
"""

from __future__ import annotations

import numpy as np
import pytest

from rodstab.errors import RodstabInputError
from rodstab.multistable.discover import common_rod
from rodstab.nonlinear.contact import attach_contact, smallest_gap
from rodstab.nonlinear.discrete import discretise
from rodstab.nonlinear.equilibrium import rod_contact_model
from rodstab.nonlinear.solve import newton
from rodstab.problems.barrier_states import state_assembly
from rodstab.sections import rectangle

H = 0.02


def _star():
    return state_assembly("hexagram", rectangle(aspect=4.0), "star")


@pytest.mark.parametrize("width", [None, 0.0])
def test_no_width_is_the_point_weld(width) -> None:
    a = _star()
    r0, r1 = discretise(a, 8), discretise(a, 8, cusp_width=width)
    assert r1.offsets is None and np.array_equal(r0.x, r1.x)


def test_a_cusp_weld_holds_the_ends_apart_across_the_tangent() -> None:
    """Every one of the star's six cusps: its two end nodes w apart, across the tangent."""
    a, w = _star(), 0.03
    r = discretise(a, 8, cusp_width=w)
    on, oj, ov, _ = r.offsets
    assert len(oj) == 12 and sorted(set(oj.tolist())) == list(range(6))
    for k in range(6):
        ends = on[oj == k, 1]
        gap = r.x[ends[0]] - r.x[ends[1]]
        assert np.linalg.norm(gap) == pytest.approx(w, rel=1e-12)
        t = r.R_joint[k][:, 1]  # the held frame's columns: n, t, e3
        assert abs(gap @ t) < 1e-12 and abs(gap[2]) < 1e-15


def test_the_stress_free_star_opens_its_cusps_at_no_cost() -> None:
    """Hexagram star at kappa_n R0 = 1 (stress-free arcs): every arc translated radially opens
    every cusp across its tangent, so relaxed with welds of width w it keeps the point-weld
    energy (the discretisation's own, 3.6e-4 at 8 el.) to Newton's tolerance."""
    a = _star()
    point = common_rod(a, 8, 1.0)
    assert newton(point)[0]
    wide = common_rod(a, 8, 1.0, cusp_width=0.03)
    assert newton(wide)[0]
    assert wide.energy() == pytest.approx(point.energy(), rel=1e-6, abs=1e-12)


def test_with_welds_of_width_the_fine_star_is_inside_the_contact_model() -> None:
    """16 el./rod, h = 0.02 L: with point cusp welds the star's rods overlap at its cusps
    (outside the model); with welds h + 1.5 dhat wide nothing is within the barrier's reach
    after relaxing, so the energy with contact is the one without."""
    a = _star()
    model = rod_contact_model(a, H, 0.1)
    point = common_rod(a, 16, 1.0)
    assert newton(point)[0]
    with pytest.raises(RodstabInputError, match="interpenetrate"):
        attach_contact(point, model)
    wide = common_rod(a, 16, 1.0, cusp_width=H + 1.5 * model.dhat)
    assert newton(wide)[0]
    e = wide.energy()
    attach_contact(wide, model)
    assert newton(wide)[0]
    near = smallest_gap(wide.contact, wide.x)
    assert near is None or near[0] > model.dhat
    assert wide.energy() == pytest.approx(e, rel=1e-9, abs=1e-12)


def test_a_negative_width_is_refused() -> None:
    with pytest.raises(RodstabInputError, match="cusp_width"):
        discretise(_star(), 8, cusp_width=-0.01)


def test_moving_the_ends_leaves_the_welds_natural_curvature_as_at_a_point_weld() -> None:
    """discretise balances each weld's natural curvature against the held state's moments;
    the shear of end edges whose end nodes were moved (cusp_width, end_offsets) is the
    construction's, not a moment of the held state, and must not enter it (it did: the built
    eight with cusps 0.01 wide had energy 7.6e7 where the point-weld state has 0)."""
    a = _star()
    point, wide = discretise(a, 8, 1.0), discretise(a, 8, 1.0, cusp_width=0.03)
    for k0p, k0w in zip(point.k0_links, wide.k0_links, strict=True):
        assert np.allclose(k0w, k0p, rtol=1e-9, atol=1e-9)


@pytest.mark.parametrize("state, twin", [("star", True), ("daisy", True), ("line", False)])
def test_a_wide_weld_state_is_the_point_weld_one_with_its_rods_translated_where_the_offsets_close(
        state, twin) -> None:
    """Relaxed at kappa_n R0 = 1.5 (rectangle h/t = 4, 8 el., w = 0.023): the star and the
    daisy with welds of width w have the point-weld energy, edge frames and chords, each rod
    translated rigidly, because the welds' offsets close round the ring there (sum over the
    joints of R_J (o_end - o_start) = 0); the line's do not, and its energy is higher. The
    reason the barriers star <-> daisy are the same with and without wide welds
    (docs/theory/contact.md)."""
    a = state_assembly("hexagram", rectangle(aspect=4.0), state)
    point, wide = common_rod(a, 8, 1.5), common_rod(a, 8, 1.5, cusp_width=0.023)
    assert newton(point)[0] and newton(wide)[0]
    on, oj, ov, _ = wide.offsets
    closure = np.zeros(3)
    for node, k, o in zip(on[:, 1], oj, ov, strict=True):
        starts = wide.edge_nodes[:, 0] == node
        closure += (1.0 if starts.any() else -1.0) * (wide.R_joint[k] @ o)
    if not twin:
        assert np.linalg.norm(closure) > 1e-3
        assert wide.energy() > point.energy() + 1e-3
        return
    assert np.linalg.norm(closure) < 1e-12
    assert wide.energy() == pytest.approx(point.energy(), rel=1e-9, abs=1e-12)
    # to Newton's tolerance (the star's in-plane turn is soft: frames agree to 2e-7)
    assert np.abs(wide.R_edge - point.R_edge).max() < 1e-6
    for s in range(6):  # the nodes of each rod's edges, moved by one vector
        e = np.arange(8 * s, 8 * s + 8)
        shift = wide.x[wide.edge_nodes[e, 1]] - point.x[point.edge_nodes[e, 1]]
        assert np.abs(shift - shift.mean(axis=0)).max() < 1e-6
        assert np.linalg.norm(shift.mean(axis=0)) > 1e-3  # and they did move
