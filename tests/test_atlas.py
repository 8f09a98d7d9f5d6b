"""The stability atlas of a ring's held states (rodstab.multistable.atlas, ``rodstab atlas``).

Oracles: the Bloch transfer method against the FE engine on the whole ring (every limit and
its multiplicity, 1e-6); the six-sided ring's folded state against the full system of general
solutions of problems/folded_ring.py (lambda_c = pi / 3) and its one-loop state against
problems/unfolded_ring.py's own ring (units converted: the design's load factor is kappa_n,
kappa_n R0 = load factor x 3 / (2 pi)); the hexagram's threshold h/t* (nu = 1/3; the FE
engine and a closed form, tests/references.py) as the start of the atlas's four-state range; a
brute-force search over all subsets for the k-overlap.
"""

from __future__ import annotations

import itertools
import json
import math
from pathlib import Path

import numpy as np
import pytest

from rodstab.cli import main
from rodstab.errors import RodstabInputError
from rodstab.io.design import load_design
from rodstab.multistable import atlas as A
from rodstab.multistable.states import ring_of, uniform_ring
from rodstab.problems import folded_ring, unfolded_ring
from rodstab.sections import rectangle
from rodstab.sweep import design_at

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"
HEXAGRAM = str(EXAMPLES / "hexagram.toml")
SIX_RING = str(EXAMPLES / "folded_six_ring.toml")
FOUR = ("line", "star", "daisy", "eight")


def ring_at(design: str, aspect: float):
    return ring_of(design_at(load_design(design), "section.aspect", aspect).assembly)


@pytest.mark.parametrize("design,aspect,labels", [(HEXAGRAM, 4.0, FOUR),
                                                  (SIX_RING, 2.5, None)],
                         ids=["hexagram h/t=4", "six-ring h/t=2.5, every state"])
@pytest.mark.slow
def test_transfer_and_fe_agree_on_every_limit_and_multiplicity(design, aspect, labels):
    """Bloch harmonics vs the FE engine (Richardson 32/64): 1e-6 (relative above 1)."""
    ring = ring_at(design, aspect)
    labels = labels or A.default_states(ring)
    for state in A.select_states(ring, labels):
        tr, fe = A.transfer_interval(ring, state), A.fe_interval(ring, state)
        assert tr.stable_at_stress_free and fe.stable_at_stress_free
        assert tr.lower.load_factor < tr.stress_free_load < tr.upper.load_factor
        for a, b in ((tr.lower, fe.lower), (tr.upper, fe.upper)):
            assert abs(a.load_factor - b.load_factor) <= 1e-6 * max(1.0, abs(b.load_factor)), \
                (state.label, a, b)
            assert a.multiplicity == b.multiplicity, (state.label, a, b)
            # a pair of harmonics m, n - m is a two-dimensional null space
            assert (a.mode_type == A.PAIR) <= (a.multiplicity == 2)


def test_six_ring_folded_state_is_the_full_systems_and_section_5s():
    """The line of the folded six-ring: upper limit = lambda_c sqrt(b1 b2) / L, lambda_c by the
    full system of general solutions (folded_ring.full_system) and in closed form pi / 3."""
    sec = rectangle(aspect=4.0)
    ring = ring_at(SIX_RING, 4.0)
    line = A.transfer_interval(ring, ring.state("line"))
    lam = folded_ring.full_system(folded_ring.Params(section=sec)).lambda_c
    assert line.upper.load_factor == pytest.approx(lam * sec.sqrt_b1b2, rel=1e-8)
    assert line.upper.load_factor == pytest.approx(math.pi / 3 * sec.sqrt_b1b2, rel=1e-10)
    assert line.lower.load_factor == pytest.approx(-line.upper.load_factor, rel=1e-10)


def test_six_ring_one_loop_state_is_the_unfolded_rings():
    """The star of the folded design is problems/unfolded_ring.py's one-loop ring: its load
    factor is kappa_n (L = 1), theirs kappa_n R0 with R0 = L / (2 pi / 3). Their FE at 64
    elements per arc (h^4 error ~2e-5, problems/hexagram.py FE_MESHES note)."""
    sec = rectangle(aspect=4.0)
    star = A.transfer_interval(ring_at(SIX_RING, 4.0), ring_at(SIX_RING, 4.0).state("star"))
    theirs = unfolded_ring.engine_stability(unfolded_ring.Params(section=sec), 64)
    R0 = 3 / (2 * math.pi)
    for ours, their in zip(star.interval, theirs.load_factor_interval, strict=True):
        assert ours * R0 == pytest.approx(their, rel=1e-4, abs=1e-4)
    # the same state in the design with R0 = 1 (examples/unfolded_six_ring.toml)
    unf = ring_of(design_at(load_design(str(EXAMPLES / "unfolded_six_ring.toml")),
                            "section.aspect", 4.0).assembly)
    direct = A.transfer_interval(unf, unf.state("star")).interval
    assert np.allclose(direct, np.array(star.interval) * R0, rtol=1e-9)


@pytest.mark.slow
def test_hexagram_four_state_range_begins_at_the_threshold():
    """nu = 1/3: all four mutually stable from h/t* to the grid's end; the overlap width changes
    sign within the stated tolerance of the refined start. h/t* is the root of the eight's lower
    limit by the FE engine less the line's upper limit in closed form (tests/references.py,
    3.5102042), not the atlas's Bloch method nor a number from an earlier run."""
    from references import hexagram_threshold_fe

    base = load_design(HEXAGRAM)

    def ring(aspect: float):
        return ring_of(design_at(base, "section.aspect", aspect).assembly)

    at = A.ring_atlas(ring, [1.0, 2.0, 3.0, 4.0, 5.0, 6.0], FOUR, key="section.aspect",
                      ks=(3, 4))
    four = at.coexistence[1]
    assert four.k == 4 and len(four.ranges) == 1
    start, end = four.ranges[0]
    assert end == 6.0
    assert start == pytest.approx(hexagram_threshold_fe(), abs=max(four.tolerance, 3e-6))
    assert four.brackets[0] == ((3.0, 4.0), None)
    step = 10 * four.tolerance

    def width(aspect: float) -> float:
        return A.best_overlap({s.label: s.interval for s in
                               (A.transfer_interval(ring(aspect), st)
                                for st in A.select_states(ring(aspect), FOUR))}, 4).width

    assert width(start - step) < 0 < width(start + step)
    # at each grid value: inside a k-range exactly when some k states share a load
    for k_ranges in at.coexistence:
        for p, sets in zip(at.values, at.mutual, strict=True):
            inside = any(a <= p <= b for a, b in k_ranges.ranges)
            assert inside == (max(o.k for o in sets) >= k_ranges.k), (k_ranges.k, p)
    # the binding limits at the threshold are the published ones
    assert A.best_overlap(dict(zip(FOUR, ((s.interval) for s in at.intervals[3]),
                                   strict=True)), 4).binding == ("eight.lower", "line.upper")


def _brute_force(intervals, k):
    return max(min(intervals[s][1] for s in c) - max(intervals[s][0] for s in c)
               for c in itertools.combinations(intervals, k))


def test_best_overlap_is_the_best_of_all_subsets():
    rng = np.random.default_rng(7)
    for _ in range(40):
        n = int(rng.integers(1, 8))
        lo = rng.uniform(-3, 3, n).round(1)  # rounded: ties between lower limits occur
        intervals = {f"s{i}": (float(a), float(a + w)) for i, (a, w) in
                     enumerate(zip(lo, rng.uniform(0.1, 4, n), strict=True))}
        for k in range(1, n + 1):
            best = A.best_overlap(intervals, k)
            assert best.width == pytest.approx(_brute_force(intervals, k), abs=1e-12)
            assert len(best.members) == k
            members = [intervals[m] for m in best.members]
            assert best.width == pytest.approx(min(b for _, b in members)
                                               - max(a for a, _ in members), abs=1e-12)


def test_mutual_sets_are_the_maximal_cliques():
    """a (0, 3), b (1, 4), c (2, 5), d (3.5, 6): maximal sets {a, b, c} on (2, 3) and
    {b, c, d} on (3.5, 4)."""
    sets = A.mutual_sets({"a": (0.0, 3.0), "b": (1.0, 4.0), "c": (2.0, 5.0),
                          "d": (3.5, 6.0)})
    assert [(o.members, o.load_interval) for o in sets] == [
        (("a", "b", "c"), (2.0, 3.0)), (("b", "c", "d"), (3.5, 4.0))]


@pytest.mark.parametrize("m,n,kind", [(0, 6, A.ALL_ALIKE), (1, 6, A.PAIR), (2, 6, A.PAIR),
                                      (3, 6, A.ALTERNATING), (2, 5, A.PAIR), (0, 1, A.ALL_ALIKE)])
def test_mode_type_by_harmonic(m, n, kind):
    assert A.mode_type(m, n) == kind


def test_mirror_state_interval_is_the_negated_one():
    """Why default_states leaves out theta < 0: the reflected state at -mu."""
    ring = ring_at(HEXAGRAM, 3.0)
    star = A.transfer_interval(ring, ring.state("star")).interval
    mirror = A.transfer_interval(ring, ring.state("mirror-star")).interval
    assert mirror == pytest.approx((-star[1], -star[0]), rel=1e-9)
    assert "mirror-star" not in A.default_states(ring)


@pytest.mark.parametrize("call,name", [
    (lambda: A.mode_type(4, 6), "4"),
    (lambda: A.bloch_interval(uniform_ring(6, weld=1.0, natural_curvature=1.0), 0.5),
     "theta = 0.5"),
    (lambda: A.bloch_interval(uniform_ring(6), 2 * math.pi / 6 - math.pi), "natural_curvature"),
    (lambda: A.select_states(uniform_ring(6, natural_curvature=1.0), ["tulip"]), "tulip"),
    (lambda: A.ring_atlas(lambda p: uniform_ring(6, natural_curvature=1.0), [1.0]), "1"),
    (lambda: A.state_interval(uniform_ring(6, natural_curvature=1.0),
                              uniform_ring(6).state("star"), "guess"), "guess"),
])
def test_bad_input_names_the_value(call, name):
    with pytest.raises(RodstabInputError, match=name):
        call()


def test_cli_atlas_writes_json_and_chart(tmp_path, capsys):
    out = tmp_path / "atlas"
    main(["atlas", HEXAGRAM, "--vary", "section.aspect=3:4:3", "--state", "star",
          "--state", "eight", "--out", str(out), "--json", "--no-progress"])
    payload = json.loads(capsys.readouterr().out)
    assert json.loads((out / "atlas.json").read_text()) == payload
    assert (out / "atlas.png").stat().st_size > 0
    assert payload["values"] == [3.0, 3.5, 4.0] and list(payload["states"]) == ["star", "eight"]
    ring = ring_at(HEXAGRAM, 3.5)
    star = A.transfer_interval(ring, ring.state("star"))
    assert payload["states"]["star"]["lower"][1] == star.lower.load_factor
    assert payload["states"]["star"]["upper_mode"] == [A.ALL_ALIKE] * 3
    assert payload["states"]["eight"]["lower_multiplicity"] == [2, 2, 2]
    assert "load factor" in payload["load_factor"]
    assert [c["k"] for c in payload["coexistence"]] == [1, 2]


@pytest.mark.parametrize("argv,name", [
    ([str(EXAMPLES / "clamped_arc.toml"), "--vary", "section.aspect=1:2:3"], "clamped_arc"),
    ([HEXAGRAM, "--vary", "section.aspect=1:2:3", "--state", "tulip"], "tulip"),
    ([HEXAGRAM, "--vary", "section.colour=1:2:3"], "colour"),
    ([HEXAGRAM, "--vary", "section.aspect=1:2:1"], "N 1"),
    ([HEXAGRAM, "--vary", "section.aspect=2:2:3"], "2"),
    ([HEXAGRAM, "--vary", "section.aspect=1:2:3", "--method", "guess"], "guess"),
    ([HEXAGRAM, "--vary", "section.aspect=1:2:3", "--max-turns", "0"], "max_turns"),
    ([HEXAGRAM, "--vary", "section.aspect=-1:2:3"], "-1"),
])
def test_cli_atlas_bad_input_exits_2_naming_the_value(tmp_path, capsys, argv, name):
    with pytest.raises(SystemExit) as exc:
        main(["atlas", *argv, "--out", str(tmp_path / "o"), "--no-progress"])
    assert exc.value.code == 2
    err = capsys.readouterr()
    assert err.out == "" and name in err.err and len(err.err.strip().splitlines()) == 1


def test_cli_atlas_out_not_writable_exits_2(tmp_path, capsys):
    blocker = tmp_path / "file"
    blocker.write_text("x")
    with pytest.raises(SystemExit) as exc:
        main(["atlas", HEXAGRAM, "--vary", "section.aspect=1:2:3", "--out", str(blocker)])
    assert exc.value.code == 2 and str(blocker) in capsys.readouterr().err


def test_hexagram_example_is_the_star_of_the_hexagram_module(run_cli):
    """`rodstab analyze examples/hexagram.toml` (FE, 32 el./rod, reference 1): the star's
    interval of kappa_n R0 by the Bloch method of problems/hexagram.py, to the FE error at 32
    elements per rod (~4e-4, the FE_MESHES note there)."""
    from rodstab.problems import hexagram as hx

    r = run_cli(["analyze", HEXAGRAM, "--json"])
    assert r.exit_code == 0, r.stderr
    lo, hi = json.loads(r.stdout)["load_factor_interval"]
    want = hx.transfer_interval(hx.Params(section=rectangle(aspect=4.0), state="star"))
    assert (lo, hi) == pytest.approx(want, rel=1e-3, abs=1e-3)


def test_common_load_is_the_middle_of_the_states_overlap_by_an_independent_method():
    """``rodstab barrier DESIGN`` without --load-factor takes the middle of the two states'
    common stable interval (it exited 2 at a default 1.0, issue 20). Reference: the same
    overlap from the FE atlas (an independent method); states never stable together are an
    input error naming both intervals (the hexagram's star and daisy, circle section)."""
    from rodstab.multistable.atlas import common_load, select_states, state_interval
    from rodstab.multistable.states import uniform_ring
    from rodstab.sections import circle, rectangle

    sec = rectangle(aspect=4.0)
    ring = uniform_ring(4, weld="cusp", length=1.0, natural_curvature=math.pi / 2, B1=sec.b1,
                        B2=sec.b2)
    mu, (lo, hi) = common_load(ring, ("star", "daisy"))
    fe = [state_interval(ring, s, "fe").interval
          for s in select_states(ring, ("star", "daisy"))]
    assert lo == pytest.approx(max(i[0] for i in fe), rel=1e-6)
    assert hi == pytest.approx(min(i[1] for i in fe), rel=1e-6)
    assert mu == pytest.approx(0.5 * (lo + hi), rel=1e-12) and lo < mu < hi
    sec = circle()
    hexagram = uniform_ring(6, weld="cusp", length=1.0, natural_curvature=2 * math.pi / 3,
                            B1=sec.b1, B2=sec.b2)
    with pytest.raises(RodstabInputError, match="never stable together.*star.*daisy"):
        common_load(hexagram, ("star", "daisy"))


# ---------------------------------------------------------------------------------------------
# Rings whose rods differ (issue 22, section 4): the FE engine on the whole ring
def _alternating(L1: float, b1: float | None = None, b2: float | None = None):
    import dataclasses

    r = ring_of(load_design("examples/hexagram_unequal.toml"))
    rods = tuple(dataclasses.replace(x, length=L1 if i % 2 == 0 else 2.0 - L1,
                                     B1=x.B1 if b1 is None else b1 * x.B3,
                                     B2=x.B2 if b2 is None else b2 * x.B3)
                 for i, x in enumerate(r.rods))
    return dataclasses.replace(r, rods=rods)


@pytest.mark.parametrize("label", ["star", "daisy", "theta=300deg"])
def test_alternating_lengths_keep_the_hexagrams_intervals(label):
    """Rods alternating 1.45 / 0.55 (examples/hexagram_unequal.toml): the FE engine on the
    whole ring gives the identical hexagram's Bloch intervals for the star, the daisy and the
    300-degree state (measured, issue 22 section 4: to 1e-8 here; the issue's 4e-6 was the
    star at another mesh). The nonlinear engine agrees (`rodstab diagram` on the design: star
    (0.0717785, 2.3572), daisy (0.944242, 3.26999) extrapolated from 8 / 16 el.)."""
    unequal = ring_of(load_design("examples/hexagram_unequal.toml"))
    same = ring_of(load_design("examples/hexagram.toml"))
    fe = A.fe_interval(unequal, unequal.state(label))
    bloch = A.transfer_interval(same, same.state(label))
    assert fe.converged and fe.stable_at_stress_free
    assert fe.interval == pytest.approx(bloch.interval, rel=1e-6)
    with pytest.raises(RodstabInputError, match="Bloch method .*segment 'r2' has length 0.55"):
        A.transfer_interval(unequal, unequal.state(label))


@pytest.mark.parametrize("b1,b2", [(16.0, 1.26366), (9.0, 1.3), (4.0, 0.8)])
@pytest.mark.parametrize("L1", [1.3, 1.7])
def test_alternating_lengths_move_the_60_degree_states_lower_end_to_m_equal_b1(L1, b1, b2):
    """The state of mean turning 60 deg (one loop, N = 1): the identical ring's lower end is
    at M = 1 - R kappa_n = b2 (atlas.covered_circle_interval's docstring, Bloch); with rods
    alternating L1 / (2 - L1), L1 in [1.3, 1.7], the FE engine puts it at M = b1 instead
    (measured to 1e-8 on these three sections; at L1 = 1.05 and 1.2 it lies between: a
    finding, not derived). Load factor = (1 - M) x 0.5 (theta / (kappa_n L) = (pi / 3) /
    (2 pi / 3)). The nonlinear engine agrees for b1 = 16: `rodstab diagram
    examples/hexagram_unequal.toml --vary load_factor=-8:-7:10` locates -7.49875 / -7.50288 at
    8 / 16 el. against (1 - 16) / 2 = -7.5. The upper end is the identical ring's."""
    ring = _alternating(L1, b1, b2)
    same = _alternating(1.0, b1, b2)
    fe = A.fe_interval(ring, ring.state("theta=60deg"))
    ref = A.transfer_interval(same, same.state("theta=60deg"))
    assert fe.interval[0] == pytest.approx((1.0 - b1) * 0.5, rel=1e-6)
    assert ref.interval[0] == pytest.approx((1.0 - b2) * 0.5, rel=1e-6)
    assert fe.interval[1] == pytest.approx(ref.interval[1], rel=1e-6)


def test_the_nonlinear_rod_puts_the_alternating_60_degree_states_lower_end_at_m_b1():
    """A second method for the M = b1 finding above: the lowest Hessian eigenvalue of the
    nonlinear discrete rod (the common rod of `rodstab diagram`, Newton at every trial value)
    crosses zero at -7.49874 / -7.50288 at 8 / 16 el. for examples/hexagram_unequal.toml
    (b1 = 16): within 4e-4 relative of (1 - b1) / 2 = -7.5 on each mesh (the pair is not in the
    asymptotic range: it brackets -7.5, so no Richardson), far from the identical ring's
    (1 - b2) / 2 = -0.1318."""
    from rodstab.multistable.diagram import eigenvalue_at
    from rodstab.multistable.discover import common_rod, deflated_newton
    from rodstab.multistable.identify import Snapshot
    from rodstab.numerics import refine_root

    ring = ring_of(load_design("examples/hexagram_unequal.toml"))
    held = ring.held(ring.state("theta=60deg").theta)
    for n in (8, 16):
        rod = common_rod(held, n, -7.5)
        assert deflated_newton(rod, []).converged
        s = Snapshot.of(rod)
        end = refine_root(lambda p, rod=rod, s=s: eigenvalue_at(rod, s, p, 0), -7.8, -7.2,
                          rel_xtol=1e-5)
        assert end == pytest.approx((1.0 - 16.0) / 2, abs=0.01)
