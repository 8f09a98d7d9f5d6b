"""Self-linking of a ring's ribbon (rodstab.multistable.linking), issue 21 section 4.

References: a circle whose frame turns n times positively about its tangent has Lk = n
(closed form: twist n, writhe 0); a mirror image has
-Lk; a rigid motion keeps it. On the hexagram, every director d3 of the planar states and of
the stacked line is the plane's normal, so the push-off is a translation along z and Lk is
the writhe of the top view (the signed crossings of the centreline with itself seen along z,
the blackboard framing): counted here independently of the module, whose two evaluations
(Gauss's integral and C-over-P crossings) are not used for it.
"""

from __future__ import annotations

import numpy as np
import pytest

from rodstab.multistable.linking import (
    apart_by_linking,
    crossing_linking,
    gauss_linking,
    self_linking,
)

T = np.linspace(0.0, 2.0 * np.pi, 240, endpoint=False)
CIRCLE = np.c_[np.cos(T), np.sin(T), 0.0 * T]


def _twisted(n: int, eps: float = 0.05) -> np.ndarray:
    # the director turns from the radius towards -z: about +tangent, n times (right-handed)
    d = np.c_[np.cos(n * T) * np.cos(T), np.cos(n * T) * np.sin(T), -np.sin(n * T)]
    return CIRCLE + eps * d


@pytest.mark.parametrize("n", [-3, -1, 0, 1, 2, 5])
def test_a_frame_turning_n_times_round_a_circle_links_it_n_times(n):
    P = _twisted(n)
    assert gauss_linking(CIRCLE, P) == pytest.approx(n, abs=1e-9)
    assert crossing_linking(CIRCLE, P, 1) == n
    assert crossing_linking(CIRCLE, P, 2) == n


def test_a_mirror_image_negates_and_a_rigid_motion_keeps_the_linking_number():
    rng = np.random.default_rng(3)
    q, _ = np.linalg.qr(rng.normal(size=(3, 3)))
    q *= np.sign(np.linalg.det(q))  # a rotation
    shift = rng.normal(size=3)
    C, P = CIRCLE @ q.T + shift, _twisted(3) @ q.T + shift
    assert round(gauss_linking(C, P)) == 3 and crossing_linking(C, P, 7) == 3
    flip = np.diag([1.0, 1.0, -1.0])
    assert round(gauss_linking(C @ flip, P @ flip)) == -3
    assert crossing_linking(C @ flip, P @ flip, 7) == -3


def test_the_hopf_link_links_once():
    other = np.c_[1.0 + np.cos(T), 0.0 * T, np.sin(T)]
    assert abs(gauss_linking(CIRCLE, other)) == pytest.approx(1.0, abs=1e-9)
    assert crossing_linking(CIRCLE, other, 1) == round(gauss_linking(CIRCLE, other))


def _blackboard_writhe(C: np.ndarray) -> int:
    """Signed self-crossings of closed polygon ``C`` seen from +z (right-hand rule)."""
    m = len(C)
    total = 0
    for i in range(m):
        p, r = C[i], C[(i + 1) % m] - C[i]
        for j in range(i + 2, m):
            if i == 0 and j == m - 1:
                continue
            q, s = C[j], C[(j + 1) % m] - C[j]
            den = r[0] * s[1] - r[1] * s[0]
            if abs(den) < 1e-14:
                continue
            w = q - p
            t = (w[0] * s[1] - w[1] * s[0]) / den
            u = (w[0] * r[1] - w[1] * r[0]) / den
            if 0.0 < t < 1.0 and 0.0 < u < 1.0:
                zi, zj = p[2] + t * r[2], q[2] + u * s[2]
                over, under = (r, s) if zi > zj else (s, r)
                total += int(np.sign(over[0] * under[1] - over[1] * under[0]))
    return total


def _hexagram_rods():
    from rodstab.multistable.discover import common_rod
    from rodstab.multistable.string_method import to_gauge
    from rodstab.nonlinear.solve import newton
    from rodstab.problems.barrier_states import state_assembly
    from rodstab.sections import rectangle

    rods = {}
    for s in ("line", "star", "daisy"):
        rods[s] = common_rod(state_assembly("hexagram", rectangle(aspect=4.0), s), 6, 1.0)
        assert newton(rods[s])[0]
    for s in ("star", "daisy"):
        to_gauge(rods[s], rods["line"])
    return rods


#: The line's rods in two columns, welds staggered along the line (docs/theory/contact.md):
#: rods 1, 3, 5 in one column, 2, 4, 6 in the other, each column's layers in the given order.
def _staggered(left: tuple[int, int, int], right: tuple[int, int, int]) -> str:
    shift = {"1": 0, "2": 1, "3": 1, "4": 2, "5": 2, "6": 0}
    col = {"1": (-0.5, left[0]), "3": (-0.5, left[1]), "5": (-0.5, left[2]),
           "2": (0.5, right[0]), "4": (0.5, right[1]), "6": (0.5, right[2])}
    return ",".join(f"{k}={u}:{lay}:{shift[k]}" for k, (u, lay) in sorted(col.items()))


@pytest.mark.parametrize(("order", "expected"), [((0, 1, 2), -2), ((0, 2, 1), 0),
                                                 ((1, 2, 0), 2)])
def test_the_stacked_lines_linking_is_the_writhe_of_its_top_view_and_the_stars_is_zero(
        order, expected):
    """Three layer orders of the staggered line (both columns alike, welds clear of one
    another): Lk = -2, 0 and +2 by the module's two evaluations, equal to the top view's
    writhe counted here. The star and the daisy lifted into the same model, and planar: 0 (a
    planar curve and its translate off the plane do not link). So the line of the first and
    the third order cannot reach the star or the daisy without passing rods through each
    other, and the second can as far as this invariant tells."""
    from rodstab.cli.contact_options import parse_layers
    from rodstab.multistable.knots import ring_polygon
    from rodstab.multistable.layered import lift, stacked_model
    from rodstab.nonlinear.equilibrium import rod_contact_model

    rods = _hexagram_rods()
    line = rods["line"]
    model = rod_contact_model(line.assembly, 0.02)
    names = [s.name for s in line.assembly.segments]
    stacked = stacked_model(line, parse_layers(_staggered(order, order), names), model)
    d3 = stacked.R_edge[:, :, 2]
    assert np.abs(np.abs(d3[:, 2]) - 1.0).max() < 1e-12  # the push-off is a translation
    lk = self_linking(stacked)
    assert lk.director == "d3" and lk.value == expected, lk
    assert lk.crossings == (expected, expected)
    assert _blackboard_writhe(ring_polygon(stacked)) == expected
    for s in ("star", "daisy"):
        planar, lifted = self_linking(rods[s]), self_linking(lift(stacked, line, rods[s]))
        assert planar.value == 0 and lifted.value == 0, (s, planar, lifted)
        assert _blackboard_writhe(ring_polygon(lift(stacked, line, rods[s]))) == 0
        assert apart_by_linking(lk, lifted) == (expected != 0)


def test_a_centreline_that_meets_itself_has_no_linking_number():
    """The planar line: its layers coincide, so no push-off is clear of it."""
    lk = self_linking(_hexagram_rods()["line"])
    assert lk.value is None and "meets itself" in lk.reason
    assert not apart_by_linking(lk, lk)


@pytest.mark.slow
def test_barrier_with_contact_between_ends_that_link_differently_is_blocked_without_a_run(
        capsys):
    """`rodstab barrier` from the staggered line of Lk -2 to the star (Lk 0), with contact:
    the ends are certified apart before any string is run, so the answer is "blocked by
    contact" with the two numbers and no barrier (exit 0: a certified answer). Its JSON
    (``blocked_by_contact``, the barriers None) from the same printer, on the same verdict
    kind."""
    import json

    from conftest import run_cli

    from rodstab.cli.barrier_contact import apart_output
    from rodstab.multistable.knots import KnotClass
    from rodstab.multistable.linking import Linking, Topology
    from rodstab.sections import rectangle

    layers = _staggered((0, 1, 2), (0, 1, 2))
    out = run_cli(["barrier", "--structure", "hexagram", "--from", "line", "--to", "star",
                   "--shape", "rectangle", "--aspect", "4", "--load-factor", "1", "--contact",
                   "--contact-thickness", "0.02", "--layers", layers, "--elements", "6"])
    assert out.exit_code == 0, out.stdout + out.stderr
    assert "line -> star: BLOCKED BY CONTACT (ribbons self-link -2 and +0)" in out.stdout
    assert "line -2; star +0: different" in out.stdout
    unknot = KnotClass("unknot", 1, 42, 3)
    verdict = Topology(("line", "star"), (unknot, unknot),
                       (Linking(-2, "d3", 1e-3, -2.0, (-2, -2)), Linking(0, "d3", 1e-3, 0.0,
                                                                         (0, 0))),
                       True, "ribbons self-link -2 and +0")
    apart_output(verdict, "hexagram", 1.0, rectangle(aspect=4.0), 6, None, True)
    data = json.loads(capsys.readouterr().out)
    assert data["barrier_forward"] is None and data["barrier_backward"] is None
    assert [lk["value"] for lk in data["blocked_by_contact"]["linking"]] == [-2, 0]
    assert [k["kind"] for k in data["blocked_by_contact"]["knots"]] == ["unknot", "unknot"]


def test_the_line_on_the_hexagon_and_the_star_link_alike_and_relaxing_with_contact_keeps_it():
    """The cone's default order for the line (rods on the vertices of a hexagon in traversal
    order, welds spanning the layers): two of its spans stand along d3, so the push-off turns
    normal to them at their ends (linking.ribbon); the line and the star lifted into the same
    model then have one number, so topology does not keep them apart. Newton with contact
    (capsules h = 0.02 L) moves the line without passing rods through each other: the
    number is kept (an invariant, not a property of the construction)."""
    from rodstab.multistable.discover import common_rod
    from rodstab.multistable.layer_orders import layer_translations, polygon_offsets
    from rodstab.multistable.layered import lift
    from rodstab.nonlinear.equilibrium import attach_contact, rod_contact_model
    from rodstab.nonlinear.solve import newton

    rods = _hexagram_rods()
    line = rods["line"]
    model = rod_contact_model(line.assembly, 0.02)
    h, g0 = 2 * model.radius, 0.5 * model.dhat
    order = [str(k) for k in range(1, 7)]
    hexagon = common_rod(line.assembly, 6, 1.0,
                         layers=layer_translations(line, polygon_offsets(order), h, g0))
    on_line, on_star = self_linking(hexagon), self_linking(lift(hexagon, line, rods["star"]))
    assert on_line.value is not None and on_line.value == on_star.value, (on_line, on_star)
    assert not apart_by_linking(on_line, on_star)
    pressed = hexagon.copy()
    pressed.load_factor = 1.5
    attach_contact(pressed, model)
    assert newton(pressed)[0]
    assert np.abs(pressed.x - hexagon.x).max() > 1e-4 * h  # it moved
    assert self_linking(pressed).value == on_line.value


@pytest.mark.parametrize("loops", [2, 3, 4])
def test_the_stacked_n_loop_ring_on_the_torus_curve_links_n_minus_1_times(loops):
    """stacking.stack_loops' N-loop ring (the (N, 1) torus curve, the strip kept flat): its
    twist is ~0 (the frame's own turning, independent of the linking code) and its linking
    number -(N - 1), so its writhe tends to -(N - 1) as h -> 0 (the (N, 1) torus curve's, a
    top view has N - 1 crossings of one sign, counted here). The untwisted one-loop ring
    has 0 (a planar circle and its translate). So this stacked ring is not the state an
    untwisted one-loop ring folds into without passing through itself: that one keeps Lk = 0,
    and with no twist (the paper's odd N, Sec. 3.1) its writhe must vanish too."""
    from rodstab.multistable.knots import ring_polygon
    from rodstab.multistable.stacking import stack_loops
    from rodstab.nonlinear.discrete import discretise
    from rodstab.problems import ring

    rod = discretise(ring.build(ring.Params(loops=loops)), 32, 0.0)
    one = discretise(ring.build(ring.Params(loops=1)), 64, 0.0)
    assert self_linking(one).value == 0
    for h in (0.05, 0.02):
        stacked = stack_loops(rod, h, 0.05 * h).rod
        lk = self_linking(stacked)
        assert lk.value == -(loops - 1) and lk.crossings == (lk.value, lk.value)
        assert _blackboard_writhe(ring_polygon(stacked)) == -(loops - 1)  # counted here
        twist = float(np.sum(stacked.edge_twist())) / (2.0 * np.pi)
        assert abs(twist) < 0.1 * h / 0.05 * loops / 3  # measured 3.0e-3 at h = 0.05, 3 loops
        assert abs((lk.value - twist) + (loops - 1)) < 0.01



def test_the_printed_verdict_claims_agreement_only_where_both_numbers_are_given():
    """barrier's `linking` line: with one number not given it says so and gives no verdict
    (the planar line's layers coincide); with two equal numbers, that rods keep it."""
    from rodstab.cli.barrier_contact import _topology_text
    from rodstab.multistable.knots import KnotClass
    from rodstab.multistable.linking import Linking, Topology

    unknot = KnotClass("unknot", 1, 10, 3)
    given = Linking(0, "d3", 1e-3, 0.0, (0, 0))
    missing = Linking(None, "d3", 0.0, None, (), "the centreline meets itself")
    text = _topology_text(Topology(("line", "star"), (unknot, unknot), (missing, given), False,
                                   ""))[1]
    assert "not certified for both" in text and "no verdict" in text and "agree" not in text
    text = _topology_text(Topology(("a", "b"), (unknot, unknot), (given, given), False, ""))[1]
    assert "Gauss's integral and crossings agree" in text
    assert "rods that cannot cross keep it" in text
    # ends apart by knot type whose numbers differ too: each line says its own verdict
    trefoil = KnotClass("knotted", 3, 10, 6)
    other = Linking(-2, "d3", 1e-3, -2.0, (-2, -2))
    knots, links = _topology_text(Topology(("a", "b"), (unknot, trefoil), (given, other),
                                           True, "different knot types"))
    assert "different knots" in knots and "different: no path" in links


def test_equilibrium_with_layers_prints_the_stacked_rings_linking_and_an_open_rod_none():
    """`equilibrium --contact --layers` on the bi-rod (a ring of two rods): its stacked state's
    number (0: two parallel layers, welds spanning them, no crossing) in the text and the JSON
    ``layers.linking``. A rod that is no closed ring has none (not given, named)."""
    import json

    from conftest import run_cli

    from rodstab.io.design import load_design
    from rodstab.multistable.linking import NOT_A_RING
    from rodstab.nonlinear.discrete import discretise

    args = ["equilibrium", "examples/birod.toml", "--load-factor", "3.5", "--elements", "8",
            "--contact", "--layers", "upper=1,lower=0"]
    out = run_cli(args)
    assert out.exit_code == 0, out.stderr
    assert "linking      the stacked ring +0" in out.stdout
    assert json.loads(run_cli([*args, "--json"]).stdout)["layers"]["linking"]["value"] == 0
    arc = discretise(load_design("examples/clamped_arc.toml").assembly, 8, 1.0)
    lk = self_linking(arc)
    assert lk.value is None and lk.reason == NOT_A_RING
