"""Eigenvector following from one minimum to a saddle (multistable.saddle_search).

Its saddles are checked against the string method's (an independent method: a path relaxed
between two named states, :func:`~rodstab.multistable.string_method.string_barrier`), on
two transitions of the paper's rings at 6 elements per rod.
"""

from __future__ import annotations

import numpy as np
import pytest

from rodstab.multistable.discover import common_rod
from rodstab.multistable.landscape import Landscape
from rodstab.multistable.saddle_search import CLIMB_EIGS, follow_mode
from rodstab.nonlinear.solve import lowest_modes, newton, zero_eigenvalue_tol
from rodstab.problems.barrier_states import state_assembly
from rodstab.sections import rectangle

R4 = rectangle(aspect=4.0)
N = 6


def _relaxed(structure: str, state: str, mu: float):
    r = common_rod(state_assembly(structure, R4, state), N, mu)
    assert newton(r)[0]
    return r


@pytest.fixture(scope="module")
def string_line_star():
    """The hexagram's line -> star at kappa_n R0 = 1 by the string method (7 images): the
    barrier and its path (the highest image replaced by the Newton-refined saddle)."""
    from rodstab.multistable.string_method import string_barrier

    b, path = string_barrier(state_assembly("hexagram", R4, "line"),
                             state_assembly("hexagram", R4, "star"), 1.0,
                             elements_per_segment=N, images=7, name_a="line", name_b="star")
    assert b.converged and b.saddle_index == 1
    return b, path


@pytest.fixture(scope="module")
def line_saddle(string_line_star):
    """The hexagram's line at kappa_n R0 = 1 and the line -> star saddle, as rods.

    The saddle is the string method's. (Eigenvector following from the line reached it too,
    along the line's third mode, until the retraction's solves were reordered (session 25):
    that climb passes a crossing of two eigenvalues, where round-off picks the mode it
    follows; :func:`test_a_climb_from_the_line_claims_no_saddle_but_the_strings`.)
    """
    b, path = string_line_star
    line = _relaxed("hexagram", "line", 1.0)
    r = line.copy()
    path[b.saddle_position].put(r)
    return line, r


@pytest.mark.slow
def test_a_climb_from_the_line_claims_no_saddle_but_the_strings(string_line_star,
                                                                 line_saddle) -> None:
    """From the hexagram's line along its third softest mode (the climb that reached the string
    method's saddle while the retraction solved dense): a saddle it reports is the string's,
    of index exactly one, at the string's energy (to Newton's tolerance), descending to both
    states; else it says it found none.

    Which it is, round-off decides: at step 39 the followed eigenvalue crosses another (gap
    3e-10 of 1.2e-7), then meets a cluster of three, and the mode it tracks by overlap (0.63
    against 0.78 with dense solves, 0.70 against 0.71 with banded ones that agree with them to
    1e-9) differs. Of the eight climbs along modes 0-3 from the line, only this one reached a
    saddle, and only with the dense solves; with trust radii 0.01 and 0.005 neither order
    reaches it in 1200 steps (docs/theory/contact.md).
    """
    b, _ = string_line_star
    line, saddle = line_saddle
    r = line.copy()
    climb = follow_mode(r, 2, -1)
    assert climb.outcome in ("saddle", "out of steps"), climb
    if climb.found:
        assert climb.index == 1
        assert climb.energy == pytest.approx(b.energy_saddle, rel=1e-9)
        star = _relaxed("hexagram", "star", 1.0)
        assert Landscape.of([("line", line), ("star", star)]).joins(r, "line", "star")
    vals = lowest_modes(saddle, 3)[0]
    tol = zero_eigenvalue_tol(saddle)
    assert vals[0] < -tol < tol < vals[1]


@pytest.mark.slow
def test_climbs_from_both_ends_meet_on_the_star_daisy_saddle() -> None:
    """Hexagram at kappa_n R0 = 1.5: from the star and from the daisy, one saddle.

    Its energy minus the star's is the barrier the string method gives at 6 el. (4.97423,
    docs/theory/contact.md's table, computed by ``rodstab barrier --from star --to daisy``).
    """
    star, daisy = _relaxed("hexagram", "star", 1.5), _relaxed("hexagram", "daisy", 1.5)
    found = []
    for start, mode in ((star, 1), (daisy, 0)):
        r = start.copy()
        climb = follow_mode(r, mode, 1)
        assert climb.found, climb
        found.append(climb.energy)
    assert found[0] == pytest.approx(found[1], rel=1e-10)
    assert found[0] - star.energy() == pytest.approx(4.97423, abs=5e-6)


def test_a_failed_climb_says_why_and_claims_no_saddle() -> None:
    """Too few steps: 'out of steps', no index, and the start is not reported as a saddle."""
    r = _relaxed("hexagram", "star", 1.5)
    climb = follow_mode(r, 1, 1, max_iter=5)
    assert not climb.found and climb.outcome == "out of steps" and climb.index is None
    assert np.isfinite(climb.energy)


@pytest.mark.slow
def test_a_ceiling_below_the_saddle_stops_the_climb_that_would_reach_it() -> None:
    """The star -> daisy saddle is 4.97 above the star: a ceiling of 1 stops that climb there."""
    star = _relaxed("hexagram", "star", 1.5)
    r = star.copy()
    climb = follow_mode(r, 1, 1, max_rise=1.0)
    assert climb.outcome == "rose past the ceiling" and not climb.found
    assert 1.0 < climb.energy - star.energy() < 1.5  # stopped at the first step past it
    assert follow_mode(star.copy(), 1, 1, max_rise=6.0).found  # above the saddle: no effect


@pytest.mark.parametrize("mode, sign", [(-1, 1), (CLIMB_EIGS, 1), (0, 0)])
def test_a_mode_or_sign_out_of_range_is_refused(mode: int, sign: int) -> None:
    with pytest.raises(ValueError, match="mode must be"):
        follow_mode(_relaxed("hexagram", "star", 1.5), mode, sign)


def test_disconnectivity_joins_superbasins_at_their_lowest_saddle() -> None:
    """Four minima, four saddles (two redundant), one minimum joined by none: by hand."""
    from rodstab.multistable.landscape import disconnectivity

    tree = disconnectivity({"a": 0.0, "b": 1.0, "c": 2.0, "d": 5.0},
                           [(4.0, "b", "c"), (3.5, "a", "b"), (10.0, "c", "a"),
                            (3.0, "b", "a")])
    assert [(m.energy, m.left, m.right) for m in tree.merges] == [
        (3.0, ("b",), ("a",)), (4.0, ("b", "a"), ("c",))]
    got = {frozenset((x, y)): (lvl, {x: bx, y: by}) for x, y, lvl, bx, by in tree.barriers}
    assert got == {frozenset("ab"): (3.0, {"a": 3.0, "b": 2.0}),
                   frozenset("ac"): (4.0, {"a": 4.0, "c": 2.0}),
                   frozenset("bc"): (4.0, {"b": 3.0, "c": 2.0})}
    assert tree.order[-1] == "d" and set(tree.order[:3]) == set("abc")


@pytest.mark.slow
def test_cli_discover_climbs_to_the_saddle_and_names_the_state_beyond_it(run_cli,
                                                                       tmp_path) -> None:
    """``discover --saddle-modes 2`` from the star alone: the star -> daisy saddle, and the daisy.

    With no other seed the daisy is not among the states found; the saddle's second descent
    reaches it and it is listed as a new minimum, with the energy of the daisy relaxed on its
    own (Newton from its held geometry in the same model).
    """
    import json

    res = run_cli(["discover", "--shape", "rectangle", "--aspect", "4", "--load-factor", "1.5",
                   "--elements", str(N), "--starts", "0", "--no-seed-states",
                   "--saddle-modes", "2", "--climb-steps", "150", "--json",
                   "--graph", str(tmp_path / "graph.png")])
    assert res.exit_code == 0, res.stderr
    out = json.loads(res.stdout)["saddle_search"]
    # 2 modes x 2 signs, less the mirror images of a planar star's out-of-plane modes
    assert len(out["climbs"]) + out["mirrored"] == 4 and out["modes"] == 2
    (sd,) = out["saddles"]
    assert sorted(sd["joins"]) == ["#1 star", "new 1"]
    daisy = _relaxed("hexagram", "daisy", 1.5).energy()
    assert out["new_minima"] == [["new 1", pytest.approx(daisy, rel=1e-9)]]
    star_side = sd["barriers"][sd["joins"].index("#1 star")]
    assert star_side == pytest.approx(4.97423, abs=5e-6)  # the string method's (docstring above)
    payload = json.loads(res.stdout)
    (row,) = payload["disconnectivity"]["barriers"]
    assert row[2] == pytest.approx(sd["energy"], rel=1e-12)
    assert (tmp_path / "graph.png").stat().st_size > 1000


@pytest.mark.parametrize("args, value", [
    (["--saddle-modes", "-1"], "-1"), (["--saddle-modes", str(CLIMB_EIGS + 1)], "7"),
    (["--saddle-modes", "1", "--climb-steps", "0"], "0"),
    (["--saddle-modes", "0", "--climb-steps", "5"], "5"),
    (["--saddle-modes", "0", "--strings", "0", "--graph", "g.png"], "g.png"),
    (["--saddle-modes", "1", "--max-barrier", "-1"], "-1"),
    (["--saddle-modes", "0", "--max-barrier", "3"], "3"), (["--strings", "-1"], "-1"),
    (["--contact", "--strings", "2"], "2")])
def test_cli_saddle_options_out_of_range_exit_2_naming_them(run_cli, args: list[str],
                                                            value: str) -> None:
    res = run_cli(["discover", "--elements", "4", *args])
    assert res.exit_code == 2 and args[-2] in res.stderr and value in res.stderr


def _crossing_sign(x: np.ndarray, edge_nodes: np.ndarray, pair: np.ndarray) -> float:
    """Sign of ``(t_a x t_b) . w``: which way element b passes element a (w: a to b)."""
    from rodstab.multistable.transitions import pair_distances

    _, w = pair_distances(x, edge_nodes, pair[None, :])
    a, b = edge_nodes[pair[0]], edge_nodes[pair[1]]
    return float(np.sign(np.cross(x[a[1]] - x[a[0]], x[b[1]] - x[b[0]]) @ w[0]))


def test_the_line_star_saddle_without_contact_passes_rods_through_each_other(line_saddle
                                                                           ) -> None:
    """Without contact the line -> star saddle is the moment two pairs of rods cross.

    At the saddle (hexagram, rectangle h/t = 4, 6 el., kappa_n R0 = 1) exactly two pairs of
    elements of non-neighbouring rods intersect (distance below 1e-5 L, the saddle's position
    error: 2e-11 or 3e-7 L with different BLAS kernels), and along
    the two steepest descents each pair passes on opposite sides: a crossing change of the
    centreline at the saddle itself. Rods that cannot pass through each other cannot take this
    path: with contact the barrier is set by another saddle (docs/theory/contact.md). (The
    signs of the two crossings are not asserted: on the string's saddle, pairs (9, 32) and
    (14, 27), they agree; on the saddle the climb from the line reached, pairs (3, 26) and
    (8, 21), at the same energy to 1e-16, they were opposite. Not explained.)
    """
    from rodstab.multistable.barrier import descents_from_saddle
    from rodstab.multistable.contact_saddle import CROSSING
    from rodstab.multistable.transitions import judged_pairs, pair_distances

    r = line_saddle[1].copy()
    pairs = judged_pairs(r)
    dist = pair_distances(r.x, r.edge_nodes, pairs)[0]
    crossing = pairs[dist < CROSSING]
    assert len(crossing) == 2
    assert np.sort(dist)[2] > 0.02  # every other pair is more than h = 0.02 L apart (0.039 L)
    vals, vecs = lowest_modes(r, 4)
    traces: tuple[list, list] = ([], [])
    descents_from_saddle(r, vals, vecs, retract=True, traces=traces)
    sides = [[_crossing_sign(t[3].x, r.edge_nodes, p) for p in crossing] for t in traces]
    assert all(s != 0 for s in sides[0] + sides[1])
    assert sides[0] == [-s for s in sides[1]]  # each pair crosses at the saddle


def test_a_climb_ending_on_another_stationary_point_lists_it_once(monkeypatch) -> None:
    """'not a saddle' ends: a given minimum is skipped, another state listed once with its count.

    The climbs are replaced by ones that end on the daisy (twice) or on the star itself, so the
    bookkeeping is checked without depending on where real climbs go.
    """
    from rodstab.multistable import saddle_search
    from rodstab.multistable.discover import Snapshot
    from rodstab.multistable.saddle_search import Climb, search_saddles

    star, daisy = _relaxed("hexagram", "star", 1.5), _relaxed("hexagram", "daisy", 1.5)
    ends = iter([daisy, star, daisy, star])

    def fake(rod, mode, sign, **_):
        end = next(ends)
        Snapshot.of(end).put(rod)
        return Climb(mode, sign, "not a saddle", 1, float(rod.energy()), 0, 0.0)

    monkeypatch.setattr(saddle_search, "follow_mode", fake)
    monkeypatch.setattr(saddle_search, "mirror_climbs", lambda rod, modes: (False,) * modes)
    out = search_saddles(star.copy(), [("star", Snapshot.of(star))], 2)
    assert len(out.climbs) == 4 and not out.saddles
    ((energy, index, planar, src, count),) = out.other_stationary
    assert energy == pytest.approx(daisy.energy(), rel=1e-12)
    assert (index, planar, src, count) == (0, True, "star mode 0+", 2)


# --------------------------------------------------------------- saddles continued into contact
@pytest.mark.slow
def test_the_crossing_saddle_continued_into_contact_keeps_index_one_and_its_sides(line_saddle
                                                                                ) -> None:
    """With contact the line -> star saddle continues to an index-1 saddle the rods can reach.

    Capsules h = 0.02 L, dhat = 0.1 h; both intersecting pairs pushed to side +1. The state
    reached is a stationary point of rod plus contact energy (Newton's residual below its
    tolerance) of index exactly one, inside the model; the two pairs touch (gap within dhat:
    contact holds them) on the sides they were pushed to, so the continuation never passed them
    through each other; every other pair is at least h apart; and it lies above the saddle
    without contact (the rods bend round one another).
    """
    from rodstab.multistable.contact_saddle import crossing_pairs, stiffen_saddle
    from rodstab.multistable.transitions import judged_pairs, pair_distances
    from rodstab.nonlinear.equilibrium import rod_contact_model

    saddle = line_saddle[1]
    crossing = crossing_pairs(saddle)
    assert len(crossing) == 2
    model = rod_contact_model(saddle.assembly, 0.02, 0.1)
    res, r = stiffen_saddle(saddle, model, (1, 1))
    assert res.found and res.index == 1, res.outcome
    assert r.contact is not None and r.contact.model == model
    vals = lowest_modes(r, 3)[0]
    tol = zero_eigenvalue_tol(r)
    assert vals[0] < -tol < tol < vals[1]
    assert res.eigenvalues[:2] == pytest.approx(tuple(vals[:2]), rel=1e-6, abs=tol)
    assert res.gap is not None and 0.0 < res.gap < model.dhat
    assert [_crossing_sign(r.x, r.edge_nodes, p) for p in crossing] == [1.0, 1.0]
    dist = pair_distances(r.x, r.edge_nodes, judged_pairs(r))[0]
    assert dist.min() > 0.02
    assert res.energy > saddle.energy() + 1e-3
    assert res.distances[-1] > 1.0 and res.stiffnesses[-1] == pytest.approx(model.stiffness)


@pytest.mark.slow
def test_a_saddle_that_touches_nothing_is_its_own_continuation() -> None:
    """Star <-> daisy at kappa_n R0 = 1.5: no pair within reach, the same saddle with contact.

    The barrier vanishes beyond dhat, so a saddle whose every gap is wider is a stationary
    point of both energies with the same index: the continuation must return it unchanged.
    """
    from rodstab.multistable.contact_saddle import crossing_pairs, stiffen_saddle
    from rodstab.nonlinear.contact import mesh_of_rod, smallest_gap
    from rodstab.nonlinear.equilibrium import rod_contact_model

    saddle = _relaxed("hexagram", "star", 1.5)
    assert follow_mode(saddle, 1, 1).found
    model = rod_contact_model(saddle.assembly, 0.02, 0.1)
    near = smallest_gap(mesh_of_rod(saddle, model), saddle.x)
    assert near is None or near[0] > model.dhat
    assert not len(crossing_pairs(saddle))
    res, r = stiffen_saddle(saddle, model, ())
    assert res.found and res.index == 1
    assert res.energy == pytest.approx(saddle.energy(), rel=1e-10)
    assert np.max(np.abs(r.x - saddle.x)) < 1e-8


def test_continuing_into_contact_refuses_bad_sides_and_a_state_with_contact(line_saddle
                                                                           ) -> None:
    from rodstab.errors import RodstabInputError
    from rodstab.multistable.contact_saddle import stiffen_saddle
    from rodstab.nonlinear.contact import mesh_of_rod
    from rodstab.nonlinear.equilibrium import rod_contact_model

    saddle = line_saddle[1]
    model = rod_contact_model(saddle.assembly, 0.02, 0.1)
    for sides in [(1,), (1, 0), (1, 1, 1)]:
        with pytest.raises(RodstabInputError, match="sides must be"):
            stiffen_saddle(saddle, model, sides)
    star = _relaxed("hexagram", "star", 1.5)
    star.contact = mesh_of_rod(star, model)
    with pytest.raises(RodstabInputError, match="already has a contact model"):
        stiffen_saddle(star, model, ())


@pytest.mark.slow
def test_cli_into_contact_that_reaches_no_saddle_prints_every_branch_and_exits_3(
        run_cli, monkeypatch) -> None:
    """``barrier --into-contact``: a branch that fails says why; none held -> exit 3.

    The continuations are replaced by ones that fail (the real ones are the tests above), so
    the command's bookkeeping is checked: one line and one JSON record per choice of sides of
    the two intersecting pairs, printed before the exit.
    """
    import json

    from rodstab.multistable import contact_saddle
    from rodstab.multistable.contact_saddle import StiffenedSaddle

    def failing(saddle, final):
        pairs = tuple(tuple(int(v) for v in p) for p in contact_saddle.crossing_pairs(saddle))
        return [(StiffenedSaddle("newton did not converge", pairs, sides, (), (), (), 0),
                 saddle) for sides in [(1, 1), (1, -1), (-1, 1), (-1, -1)]]

    monkeypatch.setattr(contact_saddle, "stiffen_all", failing)
    res = run_cli(["barrier", "--structure", "hexagram", "--shape", "rectangle", "--aspect",
                   "4", "--load-factor", "1", "--elements", str(N), "--images", "7",
                   "--into-contact", "--json"])
    assert res.exit_code == 3, res.stderr
    assert "no branch reached a saddle with contact" in res.stderr
    out = json.loads(res.stdout)["into_contact"]
    assert out["thickness"] == 0.02 and out["dhat"] == 0.1 and len(out["pairs"]) == 2
    assert [b["outcome"] for b in out["branches"]] == ["newton did not converge"] * 4


@pytest.mark.parametrize("extra", [["--contact"], ["--method", "continuation"]])
def test_cli_into_contact_needs_a_string_without_contact(run_cli, extra: list[str]) -> None:
    res = run_cli(["barrier", "--structure", "six-ring", "--elements", str(N), "--into-contact",
                   *extra])
    assert res.exit_code == 2
    assert "--into-contact continues the saddle of a barrier computed without contact" in (
        res.stderr)


def test_a_planar_minimums_out_of_plane_modes_are_climbed_one_way() -> None:
    """The star (kappa_n R0 = 1, planar) has modes out of its plane: climbed both ways, each
    ends at the same energy (the two climbs are mirror images), so discover climbs them one
    way. A non-planar state has no such mode."""
    from rodstab.multistable.saddle_search import mirror_climbs

    star = _relaxed("hexagram", "star", 1.0)
    flags = mirror_climbs(star, 4)
    assert any(flags) and not all(flags)
    for k in (k for k, f in enumerate(flags) if f):
        ends = []
        for sign in (1, -1):
            r = star.copy()
            c = follow_mode(r, k, sign, max_rise=1.0)
            ends.append((c.outcome, c.steps, c.energy))
        # mirror images: the same outcome and energy (the step count may differ by round-off
        # in an acceptance test, so it is not compared)
        assert ends[0][0] == ends[1][0]
        assert ends[0][2] == pytest.approx(ends[1][2], rel=1e-6)
    bent = star.copy()
    bent.x[:, 2] += 0.05 * np.sin(3 * np.arctan2(bent.x[:, 1], bent.x[:, 0]))  # out of plane
    assert mirror_climbs(bent, 3) == (False, False, False)


@pytest.mark.slow
def test_strings_between_unjoined_pairs_find_the_line_star_saddle(string_line_star) -> None:
    """pair_strings on the line and the star (6 el., kappa_n R0 = 1) finds the saddle that
    string_barrier found from 7 images (same energy to 1e-9); once the pair is connected no
    further run is made."""
    from rodstab.multistable.pair_strings import connected, pair_strings

    b, _ = string_line_star
    land = Landscape.of([("star", _relaxed("hexagram", "star", 1.0)),
                         ("line", _relaxed("hexagram", "line", 1.0))])
    done, saddles = pair_strings(land, ["star", "line"], 2)
    (pair,) = done
    assert pair.outcome == "saddle" and pair.states == ("line", "star")  # from the higher
    assert pair.energy == pytest.approx(b.energy_saddle, rel=1e-9)
    assert len(saddles) == 1
    root = connected(land)
    assert root["line"] == root["star"]
    assert pair_strings(land, ["star", "line"], 2) == ([], [])


@pytest.mark.slow
def test_discover_finds_the_line_star_saddle_without_being_told(run_cli) -> None:
    """Issue 22's acceptance: ``rodstab discover examples/hexagram.toml --load-factor 1
    --elements 8`` with no saddle option lists the line <-> star saddle: 14.2795117 B3/L,
    1.12004 out of the line -- the string method's (docs/guide/multistable.md, barrier table,
    six-ring folded -> one-loop at 8 el., the same ring in other units). Found by a climb from
    the line; the string method run by discover on that pair alone finds the same saddle."""
    import json

    base = ["discover", "examples/hexagram.toml", "--load-factor", "1", "--elements", "8",
            "--starts", "0", "--json"]
    energies = []
    for extra, source in (([], "#3 line mode"), (["--saddle-modes", "0", "--strings", "1"],
                                                  "string: #3 line - #1 star")):
        res = run_cli(base + extra)
        assert res.exit_code == 0, res.stderr
        out = json.loads(res.stdout)["saddle_search"]
        (sd,) = [s for s in out["saddles"] if sorted(s["joins"]) == ["#1 star", "#3 line"]]
        assert sd["found_from"].startswith(source)
        assert sd["energy"] == pytest.approx(14.2795117, abs=1e-6)
        assert sd["barriers"][sd["joins"].index("#3 line")] == pytest.approx(1.12004, abs=1e-5)
        energies.append(sd["energy"])
    assert energies[0] == pytest.approx(energies[1], rel=1e-9)


@pytest.mark.slow
def test_climbs_in_a_process_pool_are_the_climbs_made_here() -> None:
    """search_saddles with a pool of 2 processes: the same climbs (outcomes, and energies to
    round-off: the workers run one BLAS thread, this process may run several)."""
    from rodstab.multistable.discover import Snapshot
    from rodstab.multistable.saddle_search import search_saddles
    from rodstab.numerics.threads import process_pool

    star = _relaxed("hexagram", "star", 1.5)
    minima = [("star", Snapshot.of(star))]
    here = search_saddles(star.copy(), minima, 1, max_iter=60, max_rise=2.0)
    with process_pool(2) as pool:
        there = search_saddles(star.copy(), minima, 1, max_iter=60, max_rise=2.0, pool=pool)
    assert len(here.climbs) + here.mirrored == 2 and len(here.climbs) == len(there.climbs)
    for a, b in zip(here.climbs, there.climbs, strict=True):
        assert (a.mode, a.sign, a.outcome) == (b.mode, b.sign, b.outcome)
        assert a.energy == pytest.approx(b.energy, rel=1e-8)
