"""The hexagram's eight with rods of thickness: its braid (rodstab.multistable.braid).

References are geometry: the braid's ends at the weld point on two circles at 60 degrees'
spacing, welds across the tangent, the rods' own length, and the contact model's refusal of a
rod whose two ends meet.
"""

from __future__ import annotations

import json
import re

import numpy as np
import pytest

from rodstab.errors import RodstabInputError
from rodstab.multistable.braid import braid_eight, braid_limits
from rodstab.multistable.discover import common_rod
from rodstab.multistable.stacking import _segment_nodes
from rodstab.nonlinear.contact import attach_contact
from rodstab.nonlinear.equilibrium import rod_contact_model
from rodstab.problems.barrier_states import state_assembly
from rodstab.sections import rectangle

H = 0.02


@pytest.fixture(scope="module")
def eight():
    return state_assembly("hexagram", rectangle(aspect=4.0), "eight")


@pytest.fixture(scope="module")
def braided(eight):
    return braid_eight(eight, 16, 3.0, H, 0.05 * H)


def _ends(st):
    rod = st.rod
    return [(rod.x[_segment_nodes(rod, k)[0]], rod.x[_segment_nodes(rod, k)[-1]])
            for k in range(len(rod.assembly.segments))]


def test_the_braid_holds_every_pair_apart(braided) -> None:
    """The contact model's check: every non-neighbouring pair at least g0 apart."""
    assert braided.check.holds
    assert braided.check.min_gap >= 0.05 * H


def test_at_the_weld_point_each_lobes_ends_sit_on_a_circle_60_degrees_apart(braided) -> None:
    """Three strands a lobe, six ends at P: a regular hexagon on the lobe's tube circle, in
    the plane across the tangent (x = 0), so each rod's own ends are one radius apart."""
    ends = _ends(braided)
    for lobe in (0, 1):
        pts = np.array([p for k in range(lobe, 6, 2) for p in ends[k]])
        assert np.allclose(pts[:, 0], 0.0, atol=1e-12)
        c = pts.mean(axis=0)
        rel = pts[:, 1:] - c[1:]
        r = np.linalg.norm(rel, axis=1)
        assert np.allclose(r, r[0], rtol=1e-9)
        ang = np.sort(np.degrees(np.arctan2(rel[:, 1], rel[:, 0])) % 360.0)
        assert np.allclose(np.diff(np.append(ang, ang[0] + 360.0)), 60.0, atol=1e-7)
        for k in range(lobe, 6, 2):
            assert np.linalg.norm(ends[k][1] - ends[k][0]) == pytest.approx(r[0], rel=1e-9)


def test_every_weld_joins_one_tube_angle_across_the_tangent(braided) -> None:
    """Rod k's end and rod k + 1's start differ only across the tangent in the plane (y),
    all six by one length: the connectors are one translation (no two cross)."""
    ends = _ends(braided)
    gaps = []
    for k in range(6):
        d = ends[(k + 1) % 6][0] - ends[k][1]
        assert abs(d[0]) < 1e-12 and abs(d[2]) < 1e-12
        gaps.append(abs(d[1]))
    assert np.allclose(gaps, gaps[0], rtol=1e-9)


def test_every_strand_has_the_rods_length(eight) -> None:
    """The braid's strands are made exactly as long as the rods (1): sampled finely (64 el.),
    each polyline is shorter by its chords' shortfall only (l^2 kappa^2 / 24 of the length,
    about 5e-4 here; measured 3.9e-4 to 4.3e-4; asserted below 2e-3)."""
    st = braid_eight(eight, 64, 3.0, H, 0.05 * H)
    rod = st.rod
    for k in range(6):
        x = rod.x[_segment_nodes(rod, k)]
        length = float(np.sum(np.linalg.norm(np.diff(x, axis=0), axis=1)))
        assert length == pytest.approx(1.0, abs=2e-3)
        assert length < 1.0  # chords are shorter than the strand


def test_one_rigid_offset_per_rod_cannot_hold_the_eight(eight) -> None:
    """Flat layers (each rod translated as a whole): every rod is a full circle, so its own
    first and last elements meet at P and the contact model refuses the state there."""
    model = rod_contact_model(eight, H, 0.1)
    rod = common_rod(eight, 8, 3.0, layers={"1": 0.0, "3": 0.021, "5": 0.042,
                                            "2": 0.063, "4": 0.084, "6": 0.105})
    with pytest.raises(RodstabInputError, match="interpenetrate") as err:
        attach_contact(rod, model)
    first, last = (int(v) for v in re.findall(r"elements (\d+) and (\d+)", str(err.value))[0])
    assert rod.edge_segment[first] == rod.edge_segment[last]
    mine = np.flatnonzero(rod.edge_segment == rod.edge_segment[first])
    assert {first, last} == {int(mine[0]), int(mine[-1])}


@pytest.mark.slow
def test_cli_equilibrium_holds_the_braided_eight_with_contact(run_cli) -> None:
    """`rodstab equilibrium examples/hexagram_eight.toml --contact --layers braid` (h = 0.01 L,
    16 el., kappa_n R0 = 3, the eight's stress-free load): the braid relaxed with contact
    converges, stays inside the contact model with pairs pressed (smallest gap within
    dhat), and its Hessian verdict is stable; the JSON names the braid."""
    r = run_cli(["equilibrium", "examples/hexagram_eight.toml", "--load-factor", "3",
                 "--contact", "--contact-thickness", "0.01", "--layers", "braid", "--json"])
    assert r.exit_code == 0, r.stderr
    out = json.loads(r.stdout)
    assert out["converged"] and out["stable"]
    assert 0.0 < out["contact"]["smallest_gap"] < out["contact"]["dhat"]
    assert "braid" in out["layers"]["braid"]["method"]
    assert out["layers"]["relaxed"]["converged"]


@pytest.mark.parametrize("args, words", [
    (["examples/hexagram_eight.toml", "--layers", "braid"], "--layers is a setting of contact"),
    (["examples/hexagram.toml", "--contact", "--layers", "braid"], "needs a figure-eight"),
    (["examples/hexagram_eight.toml", "--contact", "--layers", "braid", "--laminate", "12"],
     "--laminate")])
def test_cli_braid_bad_input_exits_2_naming_it(run_cli, args, words) -> None:
    r = run_cli(["equilibrium", *args, "--elements", "8"])
    assert r.exit_code == 2 and words in r.stderr, r.stderr


@pytest.mark.parametrize("kw, match", [
    ({"tube": 0.5}, "tube"), ({"turns": 0}, "turns"), ({"turns": 1.5}, "turns")])
def test_bad_braid_input_is_named(eight, kw, match) -> None:
    with pytest.raises(RodstabInputError, match=match):
        braid_eight(eight, 16, 3.0, H, 0.05 * H, **kw)


def test_a_figure_eight_of_unequal_lobes_is_refused_naming_the_lengths(eight) -> None:
    """Rods of lobe B 10 % longer (a larger circle, still a figure-eight; stiffer by as much,
    so that the welds' moments balance): the construction takes one lobe radius and rod
    length, so it refuses rather than build a wrong braid."""
    import dataclasses

    segs = tuple(sg if k % 2 == 0 else dataclasses.replace(
        sg, length=1.1 * sg.length, curvature=sg.curvature / 1.1,
        natural_curvature=sg.natural_curvature / 1.1, B1=1.1 * sg.B1, B2=1.1 * sg.B2,
        B3=1.1 * sg.B3) for k, sg in enumerate(eight.segments))
    odd = dataclasses.replace(eight, segments=segs)
    with pytest.raises(RodstabInputError, match="two equal lobes"):
        braid_eight(odd, 8, 3.0, H, 0.05 * H)


def test_a_ring_that_is_not_a_figure_eight_is_refused() -> None:
    star = state_assembly("hexagram", rectangle(aspect=4.0), "star")
    with pytest.raises(RodstabInputError, match="figure-eight"):
        braid_eight(star, 8, 1.0, H, 0.05 * H)


@pytest.mark.parametrize("kw, match", [
    ({"no_contact": (4.0, 2.0)}, "no_contact"),
    ({"start_load_factor": 5.0}, "start_load_factor"),
    ({"thickness_ratio": -0.01}, "thickness_ratio")])
def test_bad_limit_search_input_is_named(eight, kw, match) -> None:
    args = {"no_contact": (1.9031, 4.2393), **kw}
    with pytest.raises(RodstabInputError, match=match):
        braid_limits(eight, args.pop("no_contact"), **args)


@pytest.mark.slow
def test_past_the_no_contact_limit_the_braid_is_held_where_the_planar_eight_leaves(eight):
    """kappa_n R0 = 4.8 (the planar eight's interval ends at 4.24): the braid relaxed with
    contact (h = 0.01 L, 16 el.) is stable by both verdicts (the barrier's Hessian, and the
    Hessian holding every active gap), and moved at random (no gap closing) and relaxed it
    comes back; the planar eight there, moved as much, falls to another state far below."""
    from rodstab.multistable.braid import hold_braid
    from rodstab.multistable.stacked import (
        held_closed_eigenvalue,
        random_move,
        verdict_eigenvalue,
    )
    from rodstab.nonlinear.newton import newton, relax
    from rodstab.nonlinear.solve import zero_eigenvalue_tol

    _, rod, ok, _, _ = hold_braid(eight, 16, 4.8, 0.01, 0.1)
    lam, tol = verdict_eigenvalue(rod)[0], zero_eigenvalue_tol(rod)
    assert ok and lam > tol
    # the hard-contact verdict (every active gap held) is stable too, and never below
    held, terms, rank = held_closed_eigenvalue(rod)
    assert terms > 0 and rank > 0 and held >= lam - tol and held > tol
    moved = rod.copy()
    size = random_move(moved, 0.2 * 0.1 * 0.01, np.random.default_rng(1))
    assert size > 1e-6 and relax(moved)[0]
    assert moved.energy() == pytest.approx(rod.energy(), rel=1e-12)
    assert np.max(np.abs(moved.x - rod.x)) < 1e-8
    planar = common_rod(eight, 16, 4.8)
    assert newton(planar)[0]
    e = planar.energy()
    random_move(planar, size, np.random.default_rng(1))
    relax(planar)
    assert planar.energy() < 0.5 * e


def test_active_gap_gradients_are_the_gaps_derivatives(braided) -> None:
    """Each row of active_gap_gradients against central differences of that term's gap,
    measured directly (node to segment, or line to line), along random directions; on the
    built braid, with a reach (dhat = 0.9 h) that takes in its nearest pairs."""
    from rodstab.nonlinear.contact import active_gap_gradients, mesh_of_rod
    from rodstab.nonlinear.contact_model import _active

    rod = braided.rod
    mesh = mesh_of_rod(rod, rod_contact_model(rod.assembly, H, 0.9))
    x = rod.x
    nt, on, ee = _active(mesh, x)
    G = active_gap_gradients(mesh, x)
    assert len(G) == int(on.sum()) + len(ee) > 0
    E = mesh.edges

    def gaps(y):
        out = []
        for p, e, st, en in zip(nt.p[on], nt.e[on], nt.start[on], nt.end[on], strict=True):
            a, b = y[E[e, 0]], y[E[e, 1]]
            t = 0.0 if st else 1.0 if en else (y[p] - a) @ (b - a) / ((b - a) @ (b - a))
            out.append(np.linalg.norm(y[p] - a - t * (b - a)))
        for ea, eb in ee:
            a0, a1, b0, b1 = y[E[ea, 0]], y[E[ea, 1]], y[E[eb, 0]], y[E[eb, 1]]
            n = np.cross(a1 - a0, b1 - b0)
            out.append(abs((a0 - b0) @ n) / np.linalg.norm(n))
        return np.array(out)

    rng = np.random.default_rng(0)
    for _ in range(3):
        v = rng.standard_normal(x.shape)
        step = 1e-7
        fd = (gaps(x + step * v) - gaps(x - step * v)) / (2 * step)
        assert np.allclose(G @ v.ravel(), fd, rtol=1e-5, atol=1e-6)


def test_active_gap_gradient_of_two_crossing_rods() -> None:
    """Two clamped straight rods crossing at right angles, one lifted 1.05 h (h = 0.02): their
    crossing elements' edge-edge term; its row against central differences of the lines'
    distance."""
    from rodstab.model import Assembly, Segment
    from rodstab.nonlinear.contact import active_gap_gradients, mesh_of_rod
    from rodstab.nonlinear.contact_model import ContactModel, _active
    from rodstab.nonlinear.discrete import discretise

    segs = (Segment(name="a", length=1.0, curvature=0.0, natural_curvature=0.0, B1=1.0, B2=1.0,
                    B3=1.0, start=(-0.5, 0.03), angle=0.0),
            Segment(name="b", length=1.0, curvature=0.0, natural_curvature=0.0, B1=1.0, B2=1.0,
                    B3=1.0, start=(0.03, -0.5), angle=0.5 * np.pi))
    a = Assembly(segments=segs, supports=(("a", "start", "clamped"), ("b", "start", "clamped")))
    rod = discretise(a, 8, 0.0, layers={"b": 1.05 * H})
    mesh = mesh_of_rod(rod, ContactModel.from_thickness(H, dhat=0.1 * H, stiffness=1.0))
    x = rod.x
    _, on, ee = _active(mesh, x)
    assert len(ee) == 1
    G = active_gap_gradients(mesh, x)
    E = mesh.edges
    (ea, eb), = ee

    def dist(y):
        a0, a1, b0, b1 = y[E[ea, 0]], y[E[ea, 1]], y[E[eb, 0]], y[E[eb, 1]]
        n = np.cross(a1 - a0, b1 - b0)
        return abs((a0 - b0) @ n) / np.linalg.norm(n)

    v = np.random.default_rng(0).standard_normal(x.shape)
    fd = (dist(x + 1e-7 * v) - dist(x - 1e-7 * v)) / 2e-7
    assert (G[int(on.sum())] @ v.ravel()) == pytest.approx(fd, rel=1e-6)
