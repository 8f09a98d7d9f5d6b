"""Energy barriers (issue 11, part 4): the saddle by continuation and by the string method.

The six-sided ring (h/t = 4, 8 el./rod) at kappa_n R0 = 1, the experiment's load (Fig. 10c).
The two methods share no code up to their saddles (a branch traced from the folded state's
bifurcation; a path relaxed between the two states), so the same saddle is a cross-check.
"""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from rodstab.errors import RodstabInputError
from rodstab.multistable.barrier import Barrier, barrier_from_bifurcation, monotone_from_saddle
from rodstab.problems import folded_ring
from rodstab.problems.barrier_states import one_loop_assembly, state_assembly
from rodstab.sections import rectangle

R4 = rectangle(aspect=4.0)
THETA = 2 * math.pi / 3
N = 8


@pytest.fixture(scope="module")
def six_ring() -> Barrier:
    p = folded_ring.Params(section=R4)
    return barrier_from_bifurcation(folded_ring.build(p), THETA, upper=8.0, elements_per_segment=N,
                                    name="folded", named={"one-loop": one_loop_assembly(p)})


def test_saddle_has_index_one_and_the_path_converges(six_ring: Barrier) -> None:
    assert six_ring.saddle_index == 1
    assert six_ring.converged
    assert six_ring.load_factor == THETA


@pytest.mark.slow
def test_row_T_six_saddle_energy_equals_the_barrier(six_ring: Barrier, string_six: tuple,
                                                   reproduction) -> None:
    """Cross-check: row T-six reads the barrier off the saddle branch landed on kappa_n R0 = 1.

    Its number at 8 el. (the report's run, the session's reproduction, which computes it
    anyway) is the barrier by the string method at 8 el. (an independent method: a path
    relaxed between the two states, no continuation; measured 1.1200392 both, agreeing to
    ~1e-12) and the fixture's by the same continuation. The folded state's energy is the
    closed form 6 x 1/2 kappa_n^2 L = 3 theta^2. (It replaces the 1.12004 that an earlier
    run printed.)
    """
    out, summary = reproduction
    figures = json.loads((out / "results.json").read_text())["figures"]
    t_six = figures["beyond"]["six_path"]["barriers_by_mesh"][str(N)]
    string, _ = string_six
    assert six_ring.energy_from == pytest.approx(3 * THETA**2, rel=1e-12)
    assert string.converged and string.saddle_index == 1
    assert t_six == pytest.approx(string.barrier_forward, rel=1e-8)  # independent method
    assert six_ring.barrier_forward == pytest.approx(t_six, abs=1e-8)  # same method, rerun


def test_descent_lands_on_the_folded_and_one_loop_states(six_ring: Barrier) -> None:
    """Independent of the continuation: both descents end on named minima (same_state).

    The one-loop ring at kappa_n R0 = 1 is stress-free (closed form: energy 0; the discrete
    ring's is O(l_e^2)), so the backward barrier is about the saddle's whole energy.
    """
    assert (six_ring.from_state, six_ring.to_state) == ("folded", "one-loop")
    assert abs(six_ring.energy_to) < 1e-3
    assert six_ring.barrier_backward == pytest.approx(six_ring.energy_saddle, abs=1e-3)
    assert six_ring.barrier_backward > six_ring.barrier_forward > 0


def test_energy_falls_monotonically_from_the_saddle_on_both_sides(six_ring: Barrier) -> None:
    e = six_ring.energies
    k = six_ring.saddle_position
    assert e[k] == max(e) == six_ring.energy_saddle
    assert e[0] == pytest.approx(six_ring.energy_from, rel=1e-12)
    assert e[-1] == pytest.approx(six_ring.energy_to, abs=1e-12)
    assert 0 < k < len(e) - 1
    assert monotone_from_saddle(six_ring)


def test_a_load_outside_the_stable_interval_is_refused_naming_it() -> None:
    """The folded ring loses stability at kappa_n R0 = 2.25 (row T-six): 3 is outside."""
    folded = folded_ring.build(folded_ring.Params(section=R4))
    with pytest.raises(RodstabInputError, match="load factor 6.28.*not a stable"):
        barrier_from_bifurcation(folded, 3 * THETA, upper=8.0)


def test_too_few_elements_are_refused_naming_them() -> None:
    folded = folded_ring.build(folded_ring.Params(section=R4))
    with pytest.raises(RodstabInputError, match="elements_per_segment.*got 3"):
        barrier_from_bifurcation(folded, THETA, upper=8.0, elements_per_segment=3)


def test_unknown_state_is_refused_naming_it() -> None:
    with pytest.raises(RodstabInputError, match="'square'"):
        state_assembly("hexagram", R4, "square")


def test_cli_barrier_json(six_ring: Barrier, capsys: pytest.CaptureFixture[str],
                          monkeypatch: pytest.MonkeyPatch) -> None:
    """``rodstab barrier --json`` prints the library's barrier. The library call is replaced by
    the fixture's result for the same arguments (checked), so the CLI's wiring and JSON are
    tested without the 8 s computation a second time."""
    import rodstab.multistable.barrier as nb
    from rodstab.cli import main

    seen = {}

    def same(a, mu, **kwargs):
        seen.update(kwargs, mu=mu, segments=len(a.segments))
        return six_ring

    monkeypatch.setattr(nb, "barrier_from_bifurcation", same)
    main(["barrier", "--method", "continuation", "--structure", "six-ring", "--shape",
          "rectangle", "--aspect", "4", "--load-factor", "1", "--elements", "8", "--json"])
    out = json.loads(capsys.readouterr().out)
    assert out["saddle_index"] == 1
    assert (out["from"], out["to"]) == ("folded", "one-loop")
    assert out["barrier_forward"] == pytest.approx(six_ring.barrier_forward, abs=1e-8)
    assert out["barrier_backward"] == pytest.approx(six_ring.barrier_backward, abs=1e-6)
    assert len(out["energies"]) > 2
    assert seen["elements_per_segment"] == 8 and seen["segments"] == 6


@pytest.mark.parametrize(("args", "named"), [
    (["--load-factor", "3"], "--load-factor 3.0"),
    (["--elements", "3"], "--elements must be an integer >= 4, got 3"),
    (["--from", "one-loop", "--to", "one-loop"], "--to 'one-loop' is the --from state"),
    (["--from", "square"], "--from 'square'"),
    (["--method", "continuation", "--structure", "hexagram", "--from", "star", "--to",
      "daisy", "--load-factor", "1.5"], "'star' is curved in its held geometry"),
    (["--images", "2"], "--images must be an integer >= 3, got 2"),
    (["--method", "continuation", "--images", "9"], "--images, --animation, --out and"),
    (["--method", "continuation", "--workers", "2"], "--workers are options of --method string"),
    (["--workers", "0"], "'--workers': 0"),
    (["--animation", "path.png"], "--animation"),
    (["--structure", "hexagram", "--from", "star", "--to", "square"], "--to 'square'"),
])
def test_cli_bad_input_exits_2_naming_the_value(args: list[str], named: str,
                                                capsys: pytest.CaptureFixture[str]) -> None:
    from rodstab.cli import main

    with pytest.raises(SystemExit) as exc:
        main(["barrier", "--shape", "rectangle", "--aspect", "4", *args])
    assert exc.value.code == 2
    assert named in capsys.readouterr().err


def test_a_state_curved_in_its_held_geometry_is_refused_by_the_continuation() -> None:
    """The hexagram star's held rods are arcs: the continuation's model of it (chords, held
    Cayley curvature) is not the common model the ends are named in (energies 13.1648 vs
    13.0226 at 8 el.), so the continuation barrier refuses it rather than mix the two."""
    star = state_assembly("hexagram", R4, "star")
    with pytest.raises(RodstabInputError, match="'star' is curved in its held geometry"):
        barrier_from_bifurcation(star, 1.0, upper=2.0, name="star")


def test_the_folded_ring_is_one_model_for_both_discretisations() -> None:
    """The folded ring's held rods are straight: discretise and common_rod agree exactly."""
    from rodstab.multistable.barrier import same_model
    from rodstab.multistable.discover import common_rod
    from rodstab.nonlinear.discrete import discretise

    folded = state_assembly("six-ring", R4, "folded")
    one = state_assembly("six-ring", R4, "one-loop")
    assert same_model(discretise(folded, N, THETA), common_rod(folded, N, THETA))
    assert not same_model(discretise(one, N, THETA), common_rod(one, N, THETA))


@pytest.fixture(scope="module")
def ends() -> tuple:
    """The folded and one-loop six-rings in the common model, Newton-relaxed, one gauge."""
    from rodstab.multistable.discover import common_rod
    from rodstab.multistable.string_method import to_gauge
    from rodstab.nonlinear.solve import newton

    rods = [common_rod(state_assembly("six-ring", R4, s), N, THETA)
            for s in ("folded", "one-loop")]
    for r in rods:
        assert newton(r)[0]
    to_gauge(rods[1], rods[0])
    return rods[0], rods[1]


def test_to_gauge_is_a_rigid_motion_onto_the_gauge_joint(ends: tuple) -> None:
    """The energy is invariant under rigid motions (so unchanged); the gauge joint's position
    and frame, which no free unknown moves, become the other state's."""
    from rodstab.multistable.discover import common_rod

    a, b = ends
    fresh = common_rod(state_assembly("six-ring", R4, "one-loop"), N, THETA)
    from rodstab.nonlinear.solve import newton

    newton(fresh)
    j, nd = a.fixed_joints[0], a.fixed_nodes[0]
    assert b.energy() == pytest.approx(fresh.energy(), rel=1e-9)
    assert b.R_joint[j] == pytest.approx(a.R_joint[j], abs=1e-14)
    assert b.x[nd] == pytest.approx(a.x[nd], abs=1e-14)


def test_chart_difference_is_inverted_by_apply(ends: tuple) -> None:
    """``a.apply(chart_difference(a, b))`` is ``b`` (rotation vectors of R_a^T R_b < pi)."""
    from rodstab.multistable.string_method import chart_difference

    a, b = ends
    r = a.copy()
    r.apply(chart_difference(a, b))
    assert r.x == pytest.approx(b.x, abs=1e-12)
    assert r.R_edge == pytest.approx(b.R_edge, abs=1e-9)
    assert r.R_joint == pytest.approx(b.R_joint, abs=1e-9)


def test_belt_path_joins_the_states_inextensibly_with_finite_energy(ends: tuple) -> None:
    """The initial band: ends are the two states, every image unstretched and unsheared (the
    frames' tangents close round the ring), energies finite. The folded ring's frame loop
    differs from the one-loop's by two full turns (Dirac's belt trick), which the lift closes;
    with a single geodesic per frame the band's middle image has energy ~7600 (the log's
    branch jumps between neighbouring frames)."""
    from rodstab.multistable.string_method import belt_path
    from rodstab.nonlinear.solve import max_strain

    a, b = ends
    band = belt_path(a, b, 5)
    assert band[0].x == pytest.approx(a.x) and band[-1].R_edge == pytest.approx(b.R_edge)
    energies = [r.energy() for r in band]
    assert all(math.isfinite(e) for e in energies)
    j, nd = a.fixed_joints[0], a.fixed_nodes[0]
    for r in band:  # one gauge: no rigid motion along the path (module docstring of mep)
        assert r.R_joint[j] == pytest.approx(a.R_joint[j], abs=1e-12)
        assert r.x[nd] == pytest.approx(a.x[nd], abs=1e-12)
    assert max(energies) < 10 * energies[0]
    assert max(max_strain(r) for r in band) < 1e-9


def test_belt_path_refuses_frame_loops_an_odd_number_of_turns_apart() -> None:
    """No continuous path of frames joins two loops an odd number of turns apart (pi_1(SO(3))
    = Z_2). The hexagram's line (turning number 0) and its 60-degree state (turning number 1:
    six 60-degree arcs) are such a pair; belt_path says so, naming the turns."""
    from rodstab.multistable.discover import common_rod
    from rodstab.multistable.states import uniform_ring
    from rodstab.multistable.string_method import belt_path, to_gauge
    from rodstab.problems import hexagram as hx

    ring = uniform_ring(hx.SEGMENTS, length=1.0, natural_curvature=hx.L_OVER_R0,
                        B1=R4.b1, B2=R4.b2)
    line, sixty = (common_rod(ring.held(ring.state(s).theta), N, 1.0)
                   for s in ("line", "theta=60deg"))
    to_gauge(sixty, line)
    with pytest.raises(RodstabInputError, match="differ by -?1 turns"):
        belt_path(line, sixty, 5)


@pytest.fixture(scope="module")
def string_six() -> tuple:
    """The string method on the folded/one-loop six-ring (11 images): barrier and path."""
    from rodstab.multistable.string_method import string_barrier

    p = folded_ring.Params(section=R4)
    return string_barrier(folded_ring.build(p), one_loop_assembly(p), THETA,
                          elements_per_segment=N, images=11, name_a="folded",
                          name_b="one-loop")


def test_string_saddle_is_the_continuation_saddle(six_ring: Barrier, string_six: tuple) -> None:
    """Two independent methods, one saddle: a local maximum of the string refined by Newton and
    the subcritical branch from the folded state's bifurcation land on the same stationary
    point, index 1 in both. Energies measured 3e-13 apart (relative), asserted to 1e-8: a
    Newton residual at the tolerance (1e-10 x the penalty force scale) can move the energy of a
    saddle with soft modes by ~1e-7 relative (mep.refine_saddle)."""
    b, _ = string_six
    assert b.converged and b.saddle_index == 1 and six_ring.saddle_index == 1
    assert b.energy_saddle == pytest.approx(six_ring.energy_saddle, rel=1e-8)
    assert b.barrier_forward == pytest.approx(six_ring.barrier_forward, rel=1e-8)
    assert b.energy_from == pytest.approx(3 * THETA**2, rel=1e-12)  # closed form (folded)


def test_string_saddle_descends_to_both_states(string_six: tuple) -> None:
    """The steepest descents from the string's saddle (retracted steps) end on the folded and
    the one-loop ring (same_state), in far fewer steps than unretracted descents (458 and 934,
    measured at 8 el. when the continuation method's descents were unretracted)."""
    b, _ = string_six
    assert sorted(b.descent_ends) == ["folded", "one-loop"]
    assert max(b.descent_steps) < 100
    assert b.energy_to == pytest.approx(_one_loop_energy(), abs=1e-12)


def _one_loop_energy() -> float:
    """The one-loop ring's energy in the common model at 8 el. (Newton from its held state)."""
    from rodstab.multistable.discover import common_rod
    from rodstab.nonlinear.solve import newton

    r = common_rod(one_loop_assembly(folded_ring.Params(section=R4)), N, THETA)
    assert newton(r)[0]
    return r.energy()


def test_string_path_runs_from_state_to_state_through_the_saddle(string_six: tuple) -> None:
    """The path's ends are the two states, its arclength grows from 0 to 1, the saddle is an
    interior point and every path state is unstretched to the retraction's accuracy."""
    from rodstab.multistable.discover import common_rod
    from rodstab.nonlinear.solve import max_strain

    b, path = string_six
    e, s = b.energies, b.path_arclength
    assert len(path) == len(e) == len(s) == b.images == 11
    assert e[0] == pytest.approx(b.energy_from, rel=1e-12)
    assert e[-1] == pytest.approx(b.energy_to, abs=1e-12)
    assert e[b.saddle_position] == b.energy_saddle
    assert 0 < b.saddle_position < len(e) - 1
    assert s[0] == 0.0 and s[-1] == pytest.approx(1.0) and all(np.diff(s) > 0)
    rod = common_rod(folded_ring.build(folded_ring.Params(section=R4)), N, THETA)
    for snap in path:
        snap.put(rod)
        assert max_strain(rod) < 1e-6


def test_reparametrise_spaces_the_images_equally(ends: tuple) -> None:
    """Piecewise-geodesic reparametrisation evens the string: the new images sit at equal chart
    arclength along the old string and are then retracted onto the inextensible states, which
    moves them off it by a little (new segments 0.18 .. 0.21 here, the old 0.12 .. 0.28: the
    spread falls 5.6x). The ends are kept."""
    from rodstab.multistable.string_method import arclength, belt_path, reparametrise

    a, b = ends
    band = belt_path(a, b, 7)
    uneven = [band[0], band[1], band[3], band[4], band[5], band[6]]  # a gap of two segments
    new = reparametrise(uneven, a.free_dofs())
    before, after = np.diff(arclength(uneven)), np.diff(arclength(new))
    assert np.ptp(before) > 0.1
    assert np.ptp(after) < 0.25 * np.ptp(before)
    assert new[0] is uneven[0] and new[-1] is uneven[-1]


def test_a_refused_reparametrisation_is_counted_and_the_string_kept(ends: tuple,
                                                                   monkeypatch) -> None:
    """With contact an interpolated image can lie outside the model; the string is then kept
    as it is (inside) and the refusal counted, so an unconverged barrier can say why its images
    bunched (docs/theory/contact.md: the stacked line -> star stalled that way). Here every
    reparametrisation is made to fail on an uneven string that asks for one each iteration."""
    import rodstab.multistable.string_method as sm
    from rodstab.nonlinear.contact_model import Interpenetration

    a, b = ends
    band = sm.belt_path(a, b, 7)
    uneven = [band[0], band[1], band[3], band[4], band[5], band[6]]

    def refuse(*args, **kwargs):
        raise Interpenetration("an interpolated image overlaps")

    monkeypatch.setattr(sm, "reparametrise", refuse)
    out, saddle, run = sm.relax_string(uneven, max_iter=3, try_every=100)
    assert saddle is None and run.iterations == 3
    assert run.refused_reparametrisations == 3 and run.reparametrisations == 0
    assert len(out) == len(uneven) and out[0] is uneven[0] and out[-1] is uneven[-1]


def test_a_string_stopped_by_its_predicate_ends_there_unconverged(ends: tuple) -> None:
    """``stop`` is asked every STOP_EVERY iterations, with the string as it is then, and ends
    the relaxation at the first True (no saddle, not converged): how the soft stages of
    contact end once their string is far enough inside the model."""
    import rodstab.multistable.string_method as sm

    seen: list[int] = []

    def stop(band: list) -> bool:
        seen.append(len(band))
        return len(seen) == 2

    out, saddle, run = sm.relax_string(sm.belt_path(*ends, 5), max_iter=50, try_every=100,
                                       stop=stop)
    assert saddle is None and not run.converged
    assert run.iterations == 2 * sm.STOP_EVERY and seen == [5, 5]


def test_cli_barrier_string_json_plot_and_animation(string_six: tuple, tmp_path,
                                                    capsys: pytest.CaptureFixture[str],
                                                    monkeypatch: pytest.MonkeyPatch) -> None:
    """``rodstab barrier`` (string, the default) prints the library's barrier and writes the
    energy plot and the GIF of the path (one frame per path state). The library call is
    replaced by the fixture's result for the same arguments (checked)."""
    from PIL import Image

    import rodstab.multistable.string_method as mep
    from rodstab.cli import main

    seen = {}

    def same(a, b, mu, **kwargs):
        seen.update(kwargs, mu=mu, segments=len(a.segments))
        return string_six

    monkeypatch.setattr(mep, "string_barrier", same)
    png, gif = tmp_path / "e.png", tmp_path / "p.gif"
    # --load-factor 1: the fixture's load (the default is now the common interval's middle)
    main(["barrier", "--shape", "rectangle", "--aspect", "4", "--images", "11", "--plot",
          str(png), "--animation", str(gif), "--load-factor", "1", "--json"])
    out = json.loads(capsys.readouterr().out)
    b, path = string_six
    assert (out["method"], out["images"], out["converged"]) == ("string", 11, True)
    assert out["barrier_forward"] == pytest.approx(b.barrier_forward, abs=1e-12)
    assert out["saddle_index"] == 1 and (out["from"], out["to"]) == ("folded", "one-loop")
    from rodstab.limits import Limits

    assert seen == {"elements_per_segment": 8, "images": 11, "name_a": "folded",
                    "name_b": "one-loop", "mu": pytest.approx(THETA), "segments": 6,
                    "limits": Limits(), "contact": None,
                    "layers": None, "named": {}, "cusp_width": None, "pool": None,
                    "ends": None, "named_states": None}
    # default limits; no contact, no layers, point welds, the images stepped in this process;
    # the six-ring has no other state to name a minimum with; its states built here (a ring)
    assert png.stat().st_size > 0
    assert Image.open(gif).n_frames == len(path)


def test_cli_barrier_unconverged_exits_3_after_the_output(string_six: tuple,
                                                          capsys: pytest.CaptureFixture[str],
                                                          monkeypatch: pytest.MonkeyPatch
                                                          ) -> None:
    """A string barrier that did not converge is printed, then exit 3 names why."""
    import dataclasses

    import rodstab.multistable.string_method as mep
    from rodstab.cli import main

    b, path = string_six
    failed = dataclasses.replace(b, converged=False, saddle_index=2, other_saddles=(
        {"energy": 14.5, "descent_ends": ("folded", "unnamed"), "end_energies": (13.0, 12.0),
         "ends_converged": (True, False)},))
    monkeypatch.setattr(mep, "string_barrier", lambda *a, **k: (failed, path))
    with pytest.raises(SystemExit) as exc:
        main(["barrier", "--shape", "rectangle", "--aspect", "4", "--json"])
    captured = capsys.readouterr()
    assert exc.value.code == 3
    assert json.loads(captured.out)["converged"] is False
    assert "did not converge" in captured.err and "saddle index 2" in captured.err
    stalled = dataclasses.replace(failed, string_run=dataclasses.replace(
        b.string_run, converged=False, refused_reparametrisations=4))
    monkeypatch.setattr(mep, "string_barrier", lambda *a, **k: (stalled, path))
    with pytest.raises(SystemExit):
        main(["barrier", "--shape", "rectangle", "--aspect", "4", "--json"])
    assert ("4 of the string's reparametrisations were refused because the path between "
            "neighbouring images passes rods through each other") in capsys.readouterr().err
    from rodstab.multistable.string_contact import ContactStages

    crossed = dataclasses.replace(failed, string_run=dataclasses.replace(
        b.string_run, converged=False, refused_reparametrisations=4,
        contact_stages=ContactStages((1.0,), 0.03, (0.01, 0.03), start_crossing=2)))
    monkeypatch.setattr(mep, "string_barrier", lambda *a, **k: (crossed, path))
    with pytest.raises(SystemExit):
        main(["barrier", "--shape", "rectangle", "--aspect", "4", "--json"])
    assert ("passes rods through each other between its images 2 and 3"
            in capsys.readouterr().err)  # the cause named before its symptom
    with pytest.raises(SystemExit):  # as text: the highest image, not called a saddle
        main(["barrier", "--shape", "rectangle", "--aspect", "4"])
    out = capsys.readouterr().out
    assert "highest image (no saddle joining the two states was found): index 2" in out
    assert "iterations; highest: image" in out and "saddle from" not in out
    assert "\nsaddle " not in out
    assert ("other saddle index 1, energy 14.5, descents end on folded 13, unnamed 12 (not "
            "converged)") in out
    # a chain: a link with its saddle, one bounded by its path, one with neither
    from rodstab.multistable.chain import Chain, Link

    links = (Link("folded", "m1", 13.0, 13.2, 14.5, True, 3, 10, 0, 14.51, 14.5),
             Link("m1", "m2", 13.2, 13.1, math.nan, False, -1, 0, 0, 13.9, 13.5),
             Link("m2", "one-loop", 13.1, 0.5, math.nan, False, -1, 300, 0, math.inf, 13.4))
    chained = dataclasses.replace(failed, chain=Chain(
        ("folded", "m1", "m2", "one-loop"), (13.0, 13.2, 13.1, 0.5), links, False, math.nan,
        ("m1", "m2")))
    monkeypatch.setattr(mep, "string_barrier", lambda *a, **k: (chained, path))
    with pytest.raises(SystemExit):
        main(["barrier", "--shape", "rectangle", "--aspect", "4"])
    out = capsys.readouterr().out
    assert ("chain        folded 13 -[14.5]-> m1 13.2 -[<= 13.9]-> m2 13.1 -[~ 13.4]-> one-loop "
            "0.5 (not converged)") in out


def test_cli_barrier_reads_the_states_of_a_design_ring(string_six: tuple,
                                                      capsys: pytest.CaptureFixture[str],
                                                      monkeypatch: pytest.MonkeyPatch) -> None:
    """``rodstab barrier DESIGN --from line --to star``: the states are the design ring's held
    states of those labels (Ring.held; rodstab states names the folded ring's states line and
    star), at the design's load factor. The library call is replaced (wiring only; the full
    run gives the built-in six-ring's 1.12004, docs/guide/multistable.md)."""
    import rodstab.multistable.string_method as mep
    from rodstab.cli import main

    seen = {}

    def same(a, b, mu, **kwargs):
        seen.update(kwargs, mu=mu, held=[[s.curvature for s in x.segments] for x in (a, b)])
        return string_six

    monkeypatch.setattr(mep, "string_barrier", same)
    main(["barrier", "examples/folded_six_ring.toml", "--from", "line", "--to", "star",
          "--load-factor", repr(THETA), "--json"])
    out = json.loads(capsys.readouterr().out)
    assert out["structure"] == "examples/folded_six_ring.toml"
    assert (seen["name_a"], seen["name_b"], seen["mu"]) == ("line", "star", THETA)
    assert seen["held"][0] == [0.0] * 6  # the line: straight rods
    assert [abs(k) for k in seen["held"][1]] == pytest.approx([THETA] * 6)  # the star's arcs


@pytest.mark.parametrize(("args", "named"), [
    (["examples/folded_six_ring.toml", "--from", "line"], "--from and --to name two states"),
    (["examples/folded_six_ring.toml", "--from", "line", "--to", "nosuch"], "'nosuch'"),
    (["examples/folded_six_ring.toml", "--from", "line", "--to", "star", "--method",
      "continuation"], "--method continuation is for the built-in structures"),
    (["examples/folded_six_ring.toml", "--from", "line", "--to", "star", "--shape", "circle"],
     "--shape"),
])
def test_cli_barrier_design_bad_input_exits_2(args: list[str], named: str,
                                              capsys: pytest.CaptureFixture[str]) -> None:
    from rodstab.cli import main

    with pytest.raises(SystemExit) as exc:
        main(["barrier", *args])
    assert exc.value.code == 2
    assert named in capsys.readouterr().err


@pytest.mark.slow
def test_string_runs_a_rejected_saddles_descents_once(monkeypatch) -> None:
    """A saddle whose descents do not join the two states is rejected; the string refines the
    same saddle again at its next tries, and its descents (minutes with contact) are not run
    again. Here every saddle is made to fail (its descents' ends relabelled)."""
    import rodstab.multistable.landscape as land
    import rodstab.multistable.string_method as mep

    calls, energies = {"accept": 0}, []
    real = land.descents_from_saddle

    def counted(saddle, *args, **kwargs):
        energies.append(saddle.energy())
        return real(saddle, *args, **kwargs)

    real_refine = mep.refine_saddle

    def refine(r, **kwargs):
        calls["accept"] += 1  # each refinement may reach the acceptance test
        return real_refine(r, **kwargs)

    monkeypatch.setattr(land, "descents_from_saddle", counted)
    monkeypatch.setattr(mep, "refine_saddle", refine)
    monkeypatch.setattr(land.Landscape, "name", lambda self, r, add=True: "elsewhere")
    p = folded_ring.Params(section=R4)
    b, _ = mep.string_barrier(folded_ring.build(p), one_loop_assembly(p), THETA,
                              elements_per_segment=N, images=11, name_a="folded",
                              name_b="one-loop", max_iter=60, chain_depth=0)
    assert not b.converged and b.chain is None
    assert len(energies) >= 1 and calls["accept"] > len(energies)
    distinct = [e for i, e in enumerate(energies)
                if all(abs(e - f) > 1e-9 * abs(e) for f in energies[:i])]
    assert len(distinct) == len(energies), energies
    # each rejected saddle is reported with where its descents end
    assert [o["energy"] for o in b.other_saddles] == pytest.approx(energies, rel=1e-12)
    assert all(o["descent_ends"] == ("elsewhere", "elsewhere") for o in b.other_saddles)
    assert all(len(o["end_energies"]) == 2 and o["end_energies"][0] < o["energy"]
               for o in b.other_saddles)


def test_saddle_step_outside_the_model_falls_back_to_plain_then_halves(monkeypatch) -> None:
    """``saddle._inside``: a retraction that leaves the contact model gives way to the plain
    step (the one the filter bounded); a step outside even plain gives None (refine_saddle
    halves it)."""
    import rodstab.multistable.saddle as S
    from rodstab.nonlinear.contact import Interpenetration
    from rodstab.nonlinear.discrete import discretise

    rod = discretise(folded_ring.build(folded_ring.Params(section=R4)), 4, 1.0)
    dq = np.zeros(rod.n_dof)
    dq[: 3 * len(rod.x)] = 1e-3

    def outside(*args, **kwargs):
        raise Interpenetration("retraction outside")

    monkeypatch.setattr(S, "retract_step", outside)
    found = S._inside(rod, dq)
    assert found is not None
    assert np.allclose(found[0].x, rod.x + dq[: 3 * len(rod.x)].reshape(-1, 3))
    monkeypatch.setattr(type(rod), "energy_terms", outside)
    assert S._inside(rod, dq) is None


@pytest.mark.slow
def test_a_string_too_coarse_is_refined_and_reaches_the_saddle_it_would_with_more_images(
        ) -> None:
    """Five images between the hexagram's star and daisy (kappa_n R0 = 1.5, 6 el./rod) are too
    few: unrefined the string stops too coarse (neighbouring images more than MAX_GAP apart).
    Allowed to refine, it doubles its segments twice (5 -> 9 -> 17 images, as
    ``max_string_images`` allows) and converges to the saddle eigenvector following reaches
    from the star independently (star side 4.97423 B3/L, tests/test_saddle_search.py), its
    descents ending on the two states.

    Why this exists: with 17 images the same string converged with OpenBLAS's SkylakeX kernels
    and stopped too coarse with its Haswell kernels (round-off moves its images along soft
    directions), so ``rodstab barrier examples/hexagram.toml --from star --to daisy`` failed on
    one machine and not on another."""
    import rodstab.multistable.string_method as sm
    from rodstab.multistable.discover import common_rod
    from rodstab.nonlinear.solve import newton

    star, daisy = (state_assembly("hexagram", R4, s) for s in ("star", "daisy"))
    rods = [common_rod(s, 6, 1.5) for s in (star, daisy)]
    for r in rods:
        assert newton(r)[0]
    sm.to_gauge(rods[1], rods[0])
    _, saddle, run = sm.relax_string(sm.belt_path(*rods, 5), max_images=None)
    assert saddle is None and run.too_coarse and run.images == 5 and run.refinements == 0
    assert sm.max_string_images(5, 10**6) == 17 and sm.max_string_images(5, 11) == 11
    assert sm.max_string_images(5, 3) == 5
    b, path = sm.string_barrier(star, daisy, 1.5, elements_per_segment=6, images=5,
                                name_a="star", name_b="daisy", chain_depth=0)
    assert b.converged and b.saddle_index == 1 and sorted(b.descent_ends) == ["daisy", "star"]
    assert (b.images, b.string_run.refinements, len(path)) == (17, 2, 17)
    assert b.barrier_forward == pytest.approx(4.97423, abs=5e-6)


def test_images_stepped_in_a_pool_of_processes_give_the_same_string(ends: tuple) -> None:
    """Each image's step depends only on the string before the iteration, and every process
    does the same arithmetic with one BLAS thread: five iterations of the six-ring's string
    (8 el./rod, 7 images) stepped in two spawned processes equal those stepped here, bit for
    bit, energies and states."""
    from rodstab.multistable.string_method import belt_path, relax_string
    from rodstab.numerics.threads import process_pool, serial_blas

    a, b = ends
    with serial_blas():
        here, _, run_here = relax_string(belt_path(a, b, 7), max_iter=5, try_every=100)
    with process_pool(2) as pool:
        there, _, run_there = relax_string(belt_path(a, b, 7), max_iter=5, try_every=100,
                                           pool=pool)
    assert run_here.top_energies == run_there.top_energies and run_here.iterations == 5
    for r, s in zip(here, there, strict=True):
        assert np.array_equal(r.x, s.x) and np.array_equal(r.R_edge, s.R_edge)
        assert np.array_equal(r.R_joint, s.R_joint)


@pytest.mark.slow
def test_cli_barrier_with_workers_prints_the_same_barrier(run_cli) -> None:
    """``--workers 2`` steps the images in two processes: the six-ring's string barrier
    (6 el., 7 images) is the one of ``--workers 1``: the whole JSON is equal."""
    args = ["barrier", "--elements", "6", "--images", "7", "--shape", "rectangle", "--aspect",
            "4", "--load-factor", "1", "--json"]
    one, two = (run_cli([*args, "--workers", w]) for w in ("1", "2"))
    assert one.exit_code == two.exit_code == 0, two.stderr
    a, b = json.loads(one.stdout), json.loads(two.stdout)
    assert a == b and a["converged"]
