"""Stimuli as continuation parameters and transitions between the hexagram's states.

Oracles: finite differences of the exact gradient (dg/dp of the weld stimuli, the moment's
work term), a closed form (a point moment on a weld of a planar ring turns it by M / k_rot
with the stiffness from the Hessian -- here the exact linear response, checked by Newton), and
the identification of a known transition (line -> star when the natural curvature grows past
the line's upper limit, Lu et al.'s hexagram).
"""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
from contact_checks import judged_pairs, segment_gap, smallest_distance

from rodstab.cli import main
from rodstab.errors import RodstabInputError
from rodstab.multistable.identify import invariants
from rodstab.multistable.transitions import pair_distances
from rodstab.nonlinear.discrete import discretise
from rodstab.nonlinear.jets import rotation_jet, rotation_vector
from rodstab.nonlinear.parameters import WeldForce, WeldMoment, WeldRotation, parameter
from rodstab.nonlinear.solve import newton
from rodstab.problems import hexagram as hx
from rodstab.problems import ring_transitions as rt
from rodstab.sections import rectangle

#: The hexagram's line in two columns (odd rods on one side, even on the other, layers 0-2).
TWO_COLUMNS = "1=-0.5:0,3=-0.5:1,5=-0.5:2,2=0.5:0,4=0.5:1,6=0.5:2"

N = 8
SECTION = rectangle(aspect=4.0)


def _ring(state: str = "star"):
    a = hx.build(hx.Params(section=SECTION, state=state))
    rod = discretise(a, N, 2.0)
    assert newton(rod)[0]
    return a, rod


def _perturbed(rod, seed: int = 0, size: float = 1e-3):
    rng = np.random.default_rng(seed)
    dq = np.zeros(rod.n_dof)
    dq[rod.free_dofs()] = size * rng.standard_normal(len(rod.free_dofs()))
    rod.apply(dq)
    return rod


@pytest.mark.parametrize("key", ["welds.0,3.rotation.binormal", "welds.1,4.rotation.normal",
                                 "weld.2.moment.binormal", "weld.4.moment.tangent",
                                 "weld.3.force.normal", "weld.1.force.binormal",
                                 "load_factor"])
def test_dgrad_matches_finite_differences(key: str) -> None:
    """dg/dp of every stimulus equals the central difference of the exact gradient."""
    a, rod = _ring()
    p = parameter(a, key, N)
    p.prepare(rod)
    p0 = 2.0 if key == "load_factor" else 0.3
    p.set(rod, p0)
    _perturbed(rod)
    free = rod.free_dofs()
    # g is affine in mu and in a force: no truncation error, a large step beats round-off
    h = 1e-3 if key == "load_factor" or ".force." in key else 1e-6
    p.set(rod, p0 + h)
    gp = rod.energy_terms()[1]
    p.set(rod, p0 - h)
    gm = rod.energy_terms()[1]
    p.set(rod, p0)
    fd = (gp - gm)[free] / (2 * h)
    assert np.max(np.abs(p.dgrad(rod)[free] - fd)) <= 1e-6 * np.max(np.abs(fd))


def test_moment_work_gradient_and_hessian_match_finite_differences() -> None:
    """The work term -M . theta: gradient and Hessian against differences of the energy."""
    a, rod = _ring("daisy")
    p = WeldMoment(a, 3, "binormal")
    p.prepare(rod)
    rod.joint_moment[2] = np.array([0.4, -0.7, 1.3])  # weld 2's joint (weld i -> joint i)
    rod.R_joint[2] = rod.R_joint[2] @ np.linalg.qr(np.eye(3) + 0.3 * np.array(
        [[0, -1, 0.5], [1, 0, -0.2], [-0.5, 0.2, 0]]))[0]  # a finite rotation from reference
    def work(r):  # the work term alone (its jet: value, gradient, Hessian in the joint's phi)
        j = r._moment_work(np.array([2]))
        return j.v[0], j.g[0], j.H[0]

    def at(phi):  # the work at R_J exp(hat(phi)) (one exponential: the jets' coordinates)
        r = rod.copy()
        dq = np.zeros(r.n_dof)
        dq[r.joint_dofs(2)] = phi
        r.apply(dq)
        return work(r)[0]

    _, g, H = work(rod)
    h, e = 1e-4, np.eye(3)
    for a in range(3):
        assert (at(h * e[a]) - at(-h * e[a])) / (2 * h) == pytest.approx(g[a], rel=1e-7)
        for b in range(3):
            fd = (at(h * (e[a] + e[b])) - at(h * (e[a] - e[b])) - at(h * (e[b] - e[a]))
                  + at(-h * (e[a] + e[b]))) / (4 * h * h)
            assert fd == pytest.approx(H[a, b], rel=1e-5, abs=1e-6)
    # ... and the assembled energy carries it: gradient of (with - without) the moment.
    bare = rod.copy()
    bare.joint_moment = {}
    dg = rod.energy_terms()[1] - bare.energy_terms()[1]
    assert np.allclose(dg[rod.joint_dofs(2)], g, rtol=1e-8, atol=1e-9)


def test_rotation_vector_is_the_log_map() -> None:
    """theta = h(|c|^2) c recovers the rotation vector, also near zero (series branch)."""
    from rodstab.nonlinear.jets import rodrigues

    for th in (np.array([1e-9, 0.0, 0.0]), np.array([0.05, -0.02, 0.01]),
               np.array([1.0, 2.0, -0.5])):
        got = np.array([j.v[0] for j in rotation_vector(rotation_jet(rodrigues(th[None]), 3,
                                                                      0))])
        assert np.allclose(got, th, rtol=1e-12, atol=1e-18)


def test_weld_moment_in_plane_linear_response_is_reciprocal() -> None:
    """Maxwell-Betti: a small in-plane moment at weld 2 turns weld 4 as much as one at weld 4
    turns weld 2 (linear response, both through Newton on the full model)."""
    a, rod = _ring("star")
    turns = []
    for load, probe in ((2, 4), (4, 2)):
        r = rod.copy()
        p = WeldMoment(a, load, "binormal")
        p.prepare(r)
        WeldMoment(a, probe, "binormal").prepare(r)
        p.set(r, 1e-4)
        assert newton(r)[0]
        j = probe  # weld i is joint i in the ring
        assert r.R_joint_held is not None
        P = r.R_joint_held[j].T @ r.R_joint[j]
        turns.append(rotation_vector(rotation_jet(P[None], 3, 0))[2].v[0])
    assert turns[0] == pytest.approx(turns[1], rel=1e-3)


def test_weld_force_reciprocity_and_envelope_theorem() -> None:
    """Two physical laws for the dead force of weld.<i>.force.<axis> (each through Newton on
    the full model): Maxwell-Betti -- a small in-plane force along weld 2's normal moves weld 4
    along its normal as much as the same force at weld 4 moves weld 2; and the envelope
    theorem -- d(potential at equilibrium)/dF = -(displacement along the force), checked by a
    central difference at a finite force."""
    a, rod = _ring("star")
    moved = []
    for load, probe in ((2, 4), (4, 2)):
        r = rod.copy()
        p = WeldForce(a, load, "normal")
        q = WeldForce(a, probe, "normal")
        p.prepare(r)
        q.prepare(r)
        p.set(r, 1e-4)
        assert newton(r)[0]
        _, direction, x_ref = r.node_force[(q._node(r), 0)]
        moved.append(float(direction @ (r.x[q._node(r)] - x_ref)))
    assert moved[0] == pytest.approx(moved[1], rel=1e-3)
    assert abs(moved[0]) > 1e-9  # a response, not two zeros
    p = WeldForce(a, 3, "normal")
    r = rod.copy()
    p.prepare(r)

    def potential(F: float) -> tuple[float, float]:
        p.set(r, F)
        assert newton(r)[0]
        _, direction, x_ref = r.node_force[(p._node(r), 0)]
        return r.energy(), float(direction @ (r.x[p._node(r)] - x_ref))

    F, h = 0.5, 1e-3
    (ep, _), (em, _), (_, u) = potential(F + h), potential(F - h), potential(F)
    assert (ep - em) / (2 * h) == pytest.approx(-u, rel=1e-5)


def test_weld_rotation_holds_the_gauge_at_weld_i() -> None:
    """welds.i,j.rotation: weld i's node and both weld frames are held, joint 0 released."""
    a, rod = _ring("star")
    p = WeldRotation(a, (1, 4), "binormal")
    p.prepare(rod)
    assert set(rod.fixed_joints) == {1, 4}
    p.set(rod, 0.2)
    assert newton(rod)[0]
    assert p.get(rod) == pytest.approx(0.2)


def test_pair_distance_of_crossing_segments() -> None:
    """Two skew unit segments crossing at right angles 0.3 apart: distance 0.3 along z."""
    x = np.array([[-0.5, 0, 0], [0.5, 0, 0], [0, -0.5, 0.3], [0, 0.5, 0.3]])
    d, w = pair_distances(x, np.array([[0, 1], [2, 3]]), np.array([[0, 1]]))
    assert d[0] == pytest.approx(0.3) and np.allclose(w[0], [0, 0, 0.3])


def _two_parallel_rods(monkeypatch):
    """A tracker on two parallel elements along x (one judged pair), ``h = 0.05``."""
    from types import SimpleNamespace

    import rodstab.multistable.transitions as tr

    monkeypatch.setattr(tr, "judged_pairs", lambda rod: np.array([[0, 1]]))
    rod = SimpleNamespace(edge_nodes=np.array([[0, 1], [2, 3]]),
                          assembly=SimpleNamespace(total_length=2.0, segments=[0, 1]))

    def at(y: float, z: float) -> np.ndarray:
        return np.array([[-1.0, 0, 0], [1.0, 0, 0], [-1.0, y, z], [1.0, y, z]])

    return (lambda: tr.ContactTracker(rod, 0.05, at(0.0, 0.2))), at


@pytest.mark.parametrize("joined_inside", [False, True])
def test_a_pass_through_between_two_samples_both_h_apart_is_seen(monkeypatch, joined_inside):
    """The second rod moves from 4 h above the first to 4 h below: at both samples the pair is
    further apart than h, so a rule judging samples alone misses it; the straight path between
    them passes through (distance 0, separation reversed). Unless the samples are joined by
    filtered steps (then the straight path is not the path, and is not judged)."""
    tracker, at = _two_parallel_rods(monkeypatch)
    rep = tracker().stretch("s", [(0.0, at(0.0, 0.2)), (1.0, at(0.0, -0.2))],
                            joined_inside=joined_inside)
    assert rep.min_distance == pytest.approx(4.0)
    assert rep.pass_through is (not joined_inside)
    assert rep.pass_through_at == (None if joined_inside else 1.0)


def test_a_pair_going_round_the_other_h_apart_is_no_pass_through(monkeypatch):
    """The separation turns by 120 degrees at 4 h (reversed: cos = -0.5) while the straight
    path between the samples stays 2 h apart: the rod went round, not through."""
    tracker, at = _two_parallel_rods(monkeypatch)
    turned = at(0.2 * np.sin(2 * np.pi / 3), 0.2 * np.cos(2 * np.pi / 3))
    rep = tracker().stretch("s", [(0.0, at(0.0, 0.2)), (1.0, turned)])
    assert rep.pass_through is False and rep.min_distance == pytest.approx(4.0)


def test_invariants_of_the_basic_states() -> None:
    """Held states: weld points, turning numbers of multistable.states (line 2/0 .. eight 1/6)."""
    expect = {"line": (2, 0.0), "star": (6, 2.0), "daisy": (6, 4.0), "eight": (1, 6.0)}
    for state, (w, t) in expect.items():
        inv = invariants(_ring(state)[1])
        assert inv.distinct_weld_points == w
        assert inv.turning_number == pytest.approx(t, abs=1e-9)  # exact: end frames counted
        assert inv.max_out_of_plane < 1e-9


@pytest.fixture(scope="module")
def hexagram_line():
    """The hexagram's line loaded in the natural curvature (kappa_n R0 from 2 to 4), 8 el."""
    res = rt.transitions(rt.hexagram_ring(SECTION), load_factor=2.0, elements=N, load=("line",),
                         stimuli={"line": (("load_factor", 4.0),)})
    (edge,) = res.graph.edges
    return edge


@pytest.mark.slow
def test_line_snaps_to_a_six_cusp_state_as_natural_curvature_grows(hexagram_line) -> None:
    """The line loses stability near its upper limit (kappa_n R0 ~ 2.25, FE 2.248 at h/t 4)
    at a DOUBLE critical eigenvalue, and says so: pushed along one direction of the
    eigenspace (round-off picks it) it snaps to the star with OpenBLAS's Haswell and SkylakeX
    kernels, to the daisy with its Nehalem ones (identified by their aligned geometry); along
    the most dangerous branch direction, to the daisy with all three (docs/development.md).
    So the target is either, and the edge is marked as not unique. Pushed along every branch
    direction of the eigenspace both ways (basis-free), it reaches both: ``reachable`` lists
    the star and the daisy whichever the solver's own push reached (independent reference:
    the two BLAS kernel sets' targets above)."""
    edge = hexagram_line
    assert edge.double_mode
    assert edge.target in ("star", "daisy") and edge.target_rms < 0.01
    assert edge.reachable == ("daisy", "star")
    assert edge.threshold == pytest.approx(2.25, abs=0.03)
    assert edge.target_invariants is not None
    assert edge.target_invariants.distinct_weld_points == 6


@pytest.mark.slow
def test_a_double_mode_whose_direction_probe_fails_pushes_along_the_solvers_pair(
        monkeypatch) -> None:
    """If branch_directions' probe does not converge (RuntimeError), the line's edge still
    lists what it reaches, pushing along both vectors of the eigen solver's pair: at least the
    edge's own target, each a six-cusp state of the hexagram (6 el.)."""
    import rodstab.nonlinear.continuation.branches as branches

    def fail(*args, **kwargs):
        raise RuntimeError("the direction probe at a double eigenvalue did not converge")

    monkeypatch.setattr(branches, "branch_directions", fail)
    res = rt.transitions(rt.hexagram_ring(SECTION), load_factor=2.0, elements=6,
                         load=("line",), stimuli={"line": (("load_factor", 4.0),)})
    (edge,) = res.graph.edges
    assert edge.double_mode and edge.target in edge.reachable
    assert set(edge.reachable) <= {"star", "daisy"}


@pytest.mark.slow
def test_cli_graph_json_schema_on_a_design(tmp_path, capsys, hexagram_line) -> None:
    """--json on examples/folded_six_ring.toml: states, edges with from/to/stimulus/threshold/
    contact; the figure is written. The ring is the hexagram's read from a file (alternately
    oriented rods, load factor kappa_n L = (2 pi / 3) kappa_n R0): its line snaps to the star at
    the hexagram's load in its own units."""
    unit = 2 * math.pi / 3
    main(["transitions", "examples/folded_six_ring.toml", "--load-factor", repr(2 * unit),
          "--state", "line", "--stimulus", f"line=load_factor:{4 * unit!r}", "--out",
          str(tmp_path / "g"), "--json"])
    data = json.loads(capsys.readouterr().out)
    assert set(data) >= {"states", "edges", "no_transition"}
    assert set(data["states"]) >= set(hx.STATES)
    (edge,) = data["edges"]
    assert {"from", "to", "stimulus", "threshold", "contact", "physical"} <= set(edge)
    # a double critical eigenvalue: the star or the daisy (see the test above)
    assert edge["from"] == "line" and edge["stimulus"] == "load_factor" and edge["double_mode"]
    assert edge["to"] in ("star", "daisy") and edge["reachable"] == ["daisy", "star"]
    assert edge["threshold"] / unit == pytest.approx(hexagram_line.threshold, rel=1e-6)
    for c in edge["contact"]:
        assert {"stretch", "min_distance", "touching", "pass_through"} <= set(c)
    # The keys since e0b77e8 (issue 20 merged the identifications, not the JSON); the target's
    # turning number along the ring (backwards rods counted with their sign) is whole: 2 for
    # the star, 4 for the daisy.
    inv = edge["target_invariants"]
    assert set(inv) == {"distinct_weld_points", "turning_number", "mean_radius", "planarity"}
    assert inv["turning_number"] == pytest.approx({"star": 2.0, "daisy": 4.0}[edge["to"]],
                                                  abs=1e-9)
    assert (tmp_path / "g" / "transitions.png").stat().st_size > 0
    # The edge's sampled states in a path file (rodstab.io.path_file): the stretches in
    # order, the default thickness, and the pairs stacked in its first state -- recomputed
    # from the file alone (contact_checks) -- as the loading's contact report counts them.

    from rodstab.io.path_file import read_path_file

    z = read_path_file(edge["path_file"])
    assert [s for s, _ in edge["path_stretches"]] == [c["stretch"] for c in edge["contact"]]
    assert z["x"].shape[0] == sum(n for _, n in edge["path_stretches"])
    assert [n for _, n in edge["path_stretches"]] == [c["samples"] for c in edge["contact"]]
    assert z["thickness"] == 0.02 and "energy" not in z
    stacked = [p for p in judged_pairs(z["edges"], 6) if segment_gap(z["x"][0], z["edges"], *p)
               < z["thickness"]]
    assert len(stacked) == edge["contact"][0]["stacked_pairs"] > 0


@pytest.mark.parametrize(("args", "named"), [
    (["--state", "square"], "'square'"),
    (["examples/folded_six_ring.toml", "--structure", "hexagram"], "--structure"),
    (["examples/birod.toml"], "support"),
    (["--state", "theta=60deg"], "'theta=60deg' has no stimulus"),
    (["--stimulus", "star=welds.0,7.rotation.binormal:1"], "'7'"),
    (["--stimulus", "star=weld.9.moment.binormal:1"], "'9'"),
    (["--stimulus", "star=welds.0.rotation.binormal:1"], "'0'"),
    (["--stimulus", "star=twist.everything:1"], "twist.everything"),
    (["--stimulus", "hexagon=load_factor:3"], "'hexagon'"),
    (["--stimulus", "star=load_factor:x"], "'x'"),
    (["--stimulus", "star=welds.0,3.rotation.sideways:1"], "'sideways'"),
    (["--state", "line", "--layers", TWO_COLUMNS], "--contact"),
    (["--contact", "--layers", TWO_COLUMNS], "one --state"),
    (["--contact", "--state", "line", "--layers", "torus"], "'torus'"),
    (["--contact", "--state", "line", "--layers", "1=0,2=1"], "'3'"),
    (["--contact", "--state", "line", "--layers", TWO_COLUMNS, "--stimulus",
      "line=weld.2.moment.binormal:12"], "--stimulus line=weld.2.moment.binormal:12"),
])
@pytest.mark.slow
def test_bad_inputs_exit_2_naming_the_value(args, named, capsys) -> None:
    """Bad states, weld indices and stimulus keys: exit 2, one stderr line naming the value."""
    with pytest.raises(SystemExit) as exc:
        main(["transitions", *args])
    assert exc.value.code == 2
    err = capsys.readouterr().err
    assert named in err and len(err.strip().splitlines()) == 1


@pytest.mark.slow
def test_the_stacked_line_with_contact_holds_past_the_planar_limit_rods_apart(tmp_path,
                                                                             capsys) -> None:
    """The line stacked in two columns with contact (`--layers`), loaded in the natural
    curvature: it loses stability above the planar line's limit without contact, 2.24825
    (rodstab hexagram, h/t = 4; contact only adds restrictions there: the derived zero-gap
    limit in two columns is 3/2 of it), and every judged pair of its written path stays at
    least h apart (dense sampling of the path file, no rodstab distance code). Its welds at x =
    0 overlap, which the output says."""
    main(["transitions", "--shape", "rectangle", "--aspect", "4", "--load-factor", "1",
          "--contact", "--state", "line", "--layers", TWO_COLUMNS, "--elements", "6", "--out",
          str(tmp_path), "--json"])
    out = json.loads(capsys.readouterr().out)
    (edge,) = out["edges"]
    assert edge["from"] == "line" and edge["physical"] and edge["converged"]
    assert 2.24825 * 1.05 < edge["threshold"] < 4.0
    # every two-column order has welds whose spans cross (tests/test_spanning_weld.py); the
    # relaxed stack keeps them within a small fraction of h
    welds = out["contact"]["welds"]
    assert len(welds["overlapping"]) == 3 and welds["clearance"] < 0.01
    z = np.load(edge["path_file"])
    pairs = judged_pairs(z["edges"], 6)
    smallest = min(smallest_distance(x, z["edges"], pairs, n=21)
                   for x in z["x"])
    assert smallest >= z["thickness"], smallest / z["thickness"]


def test_a_state_unstable_at_the_load_is_skipped_with_a_line_not_a_failure() -> None:
    """Every state loaded by default: one unstable at the chosen load is listed in ``skipped``
    (it made the whole run exit 2, issue 20); one asked for by name must be stable.

    Six cusp rods, circle section (nu = 1/3): at kappa_n R0 = 1 the line is unstable (its
    interval is +-0.43301 by Bloch and the FE, docs/guide/multistable.md) and the star stable
    (0.57569, 1.43004). No stimuli: only the states' stability is asked.
    """
    from rodstab.multistable.states import uniform_ring
    from rodstab.multistable.transitions import transition_graph
    from rodstab.sections import circle

    sec = circle()
    kn = 2 * math.pi / 3  # kappa_n R0 = 1 with R0 = 3 L / 2 pi, L = 1
    ring = uniform_ring(6, weld="cusp", length=1.0, natural_curvature=kn, B1=sec.b1, B2=sec.b2)
    states = {s: ring.held(ring.state(s).theta) for s in ("line", "star")}
    g = transition_graph(states, {}, load_factor=1.0, thickness=0.02)
    assert [s for s, _ in g.skipped] == ["line"]
    assert g.to_json()["skipped"][0]["why"].startswith("not stable at load factor 1")
    with pytest.raises(RodstabInputError, match="not stable"):
        transition_graph(states, {"line": [("load_factor", 2.0)]}, load_factor=1.0,
                         thickness=0.02, load=["line"])


def test_contact_thickness_is_h_over_the_rod_length_on_a_ring_of_any_size(monkeypatch):
    """``thickness`` is h / L: on a ring of rods of length 2 the transitions judge contact
    with h = 2 x thickness in the ring's own length unit (it was passed on as h itself, half
    the thickness asked for on such a ring). Checked at the call of the transition graph."""
    from rodstab.multistable.states import uniform_ring
    from rodstab.problems import ring_transitions as rt

    seen = {}

    def graph(assemblies, stimuli, *, thickness, **kwargs):
        seen["h"] = thickness
        raise RuntimeError("stop here")

    monkeypatch.setattr(rt, "transition_graph", graph)
    for length in (1.0, 2.0):
        ring = uniform_ring(6, weld="cusp", length=length, natural_curvature=1.0)
        with pytest.raises(RuntimeError, match="stop here"):
            rt.transitions(ring, load_factor=2.0, elements=4, thickness=0.02)
        assert seen["h"] == pytest.approx(0.02 * length, rel=1e-15)
