"""The N-loop ring folded from an untwisted ring: flat layers that swap (multistable.folding).

Reference numbers: the ribbon's self-linking of the untwisted one-loop ring (0, exactly) and
of the wound ring on the torus curve (-(N - 1), tested in test_linking.py against an
independently counted writhe); the paper's Sec. 3.1 statement that a ring folds without twist
into an odd number of loops; the construction's own placement of each swap (the middle of its
azimuth window, by the smoothstep's symmetry) for :func:`layer_swaps`.
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest

from rodstab.errors import RodstabInputError
from rodstab.multistable.folding import alternating, flat_foldings, fold_loops, layer_swaps
from rodstab.multistable.linking import self_linking
from rodstab.multistable.stacked import describe, relax, stacked_ring
from rodstab.nonlinear.discrete import discretise
from rodstab.problems import ring as rings
from rodstab.sections import circle


def _coincident(N: int, n: int):
    a = rings.build(rings.Params(section=circle(), loops=N))
    return a, discretise(a, n, 1.0)


@pytest.mark.parametrize(("N", "n", "hL"), [(3, 16, 0.01), (3, 32, 0.01), (5, 32, 0.004),
                                            (7, 24, 0.002)])
def test_the_folded_ring_links_like_the_untwisted_ring_and_keeps_its_gaps(N, n, hL):
    a, rod = _coincident(N, n)
    h = hL * a.total_length
    g0 = 0.05 * h
    st = fold_loops(rod, h, g0)
    assert st.check.holds and st.check.min_gap >= g0
    lk = self_linking(st.rod)
    # Gauss's integral and the crossings of two projections agree on 0, as for one loop
    assert lk.value == 0 and abs(lk.gauss) < 1e-6 and lk.crossings == (0, 0)
    # the loops' lengths are kept: an element's stretch is at most a chord's shortfall on an
    # arc of the curve's largest curvature, l^2 kappa^2 / 24 (kappa from chord_error = l^2
    # kappa / 4)
    l = 2.0 * math.pi / n
    kappa = 4.0 * st.chord_error / l**2
    assert st.max_strain <= 1.1 * l * l * kappa * kappa / 24.0
    # each swap sits in the middle of its window of 360 / (N - 1) degrees, to half an element
    # (the heights are interpolated linearly between nodes)
    w = 2.0 * math.pi / (N - 1)
    expected = (np.arange(N - 1) + 0.5) * w
    found = layer_swaps(st.rod)
    assert len(found) == N - 1
    assert np.max(np.abs(np.sort(found) - expected)) <= math.pi / n


@pytest.mark.slow
def test_the_linking_number_is_the_sum_of_the_swaps_senses():
    """Lk = Wr (the strip flat) = the sum of the swaps' signs, one convention for every
    sequence; all alike gives the wound ring's |Lk| = N - 1."""
    a, rod = _coincident(5, 24)
    h = 0.004 * a.total_length
    rng = np.random.default_rng(3)
    signs = set()
    for senses in [(1, 1, 1, 1), (-1, -1, -1, -1), (1, -1, 1, -1), (1, 1, -1, 1),
                   *(tuple(int(v) for v in rng.choice([-1, 1], 4)) for _ in range(3))]:
        lk = self_linking(fold_loops(rod, h, 0.05 * h, senses=senses).rod)
        assert lk.reason == "" and abs(lk.value) == abs(sum(senses)), senses
        if sum(senses):
            signs.add(int(np.sign(lk.value)) * int(np.sign(sum(senses))))
    assert len(signs) == 1
    assert alternating(5) == (1, -1, 1, -1)


@pytest.mark.parametrize("N", [2, 4, 1])
def test_an_even_number_of_loops_has_no_untwisted_flat_folding(N):
    a, rod = _coincident(N, 16)
    with pytest.raises(RodstabInputError, match="odd number of loops"):
        fold_loops(rod, 0.002 * a.total_length, 1e-4)


def test_bad_senses_are_refused_naming_them():
    a, rod = _coincident(3, 16)
    with pytest.raises(RodstabInputError, match=r"senses must be 2 values"):
        fold_loops(rod, 0.01 * a.total_length, 1e-3, senses=(1, 0))


@pytest.mark.slow
def test_the_folded_ring_is_held_with_contact_its_swaps_half_a_turn_apart():
    """Relaxed with contact at load factor 1 (stress-free coincident loops): converged,
    stable, still linking 0 times, its two swaps half a turn apart (the construction put them
    half a turn apart too; from other spacings: benchmarks/folded_three_loops.py --hold), and
    the energy above the coincident ring is of the order of the wound ring's (h^2)."""
    a = rings.build(rings.Params(section=circle(), loops=3))
    out = {}
    for stacking in ("folded", "wound"):
        rod, st = stacked_ring(a, thickness_ratio=0.01, elements_per_loop=16,
                               dhat_fraction=0.1, stacking=stacking)
        ok, its, res = relax(rod, 1.0)
        out[stacking] = (describe(rod, st.rod, ok, its, res), self_linking(rod), rod)
    held, lk, rod = out["folded"]
    assert held.converged and held.stable
    assert lk.value == 0 and out["wound"][1].value == -2
    swaps = np.sort(layer_swaps(rod))
    assert len(swaps) == 2 and abs(swaps[1] - swaps[0] - math.pi) < math.radians(10.0)
    # rods apart: the barrier holds them within dhat, never through one another
    assert 0.0 < held.min_gap < held.dhat
    ratio = (held.energy - held.energy_coincident) / (out["wound"][0].energy
                                                      - out["wound"][0].energy_coincident)
    assert 0.5 < ratio < 2.0


@pytest.mark.slow
def test_cli_equilibrium_holds_the_folded_and_the_wound_three_loop_ring(run_cli):
    """`equilibrium --layers folded|wound` on the paper's 3-loop ring (one segment of three
    turns): held with contact, linking 0 and -2 (the untwisted ring's and the torus curve's),
    the folded ring's two swaps half a turn apart."""
    args = ["equilibrium", "examples/ring_3_loops.toml", "--contact", "--contact-thickness",
            "0.003", "--elements", "48", "--layers"]
    text = run_cli([*args, "folded"])
    assert text.exit_code == 0, text.stderr
    assert "layers       folded: 3 flat layers" in text.stdout
    assert "linking      the stacked ring +0" in text.stdout
    assert "stability    stable" in text.stdout
    line = next(ln for ln in text.stdout.splitlines() if ln.startswith("swaps"))
    swaps = sorted(float(v) for v in line.split("azimuth")[1].split("deg")[0].split(","))
    assert len(swaps) == 2 and abs(swaps[1] - swaps[0] - 180.0) < 10.0
    wound = run_cli([*args, "wound", "--json"])
    assert wound.exit_code == 0, wound.stderr
    out = json.loads(wound.stdout)
    assert out["converged"] and out["stable"]
    assert out["layers"]["stacking"]["method"].startswith("(3, 1) torus curve")
    assert out["layers"]["linking"]["value"] == -2 and len(out["layers"]["swaps_deg"]) == 2


def test_cli_folded_layers_refuse_what_has_no_folded_state(run_cli, tmp_path):
    two = tmp_path / "two.toml"
    two.write_text(ROOT_RING.replace("18.84955592153876", str(4.0 * math.pi)))
    r = run_cli(["equilibrium", str(two), "--contact", "--contact-thickness", "0.003",
                 "--layers", "folded", "--elements", "32"])
    assert r.exit_code == 2 and "--layers folded" in r.stderr and "odd number of loops" in r.stderr
    r = run_cli(["equilibrium", "examples/ring_3_loops.toml", "--contact", "--layers", "folded",
                 "--elements", "48"])
    assert r.exit_code == 2 and "too large" in r.stderr and "contact thickness 0.02" in r.stderr
    r = run_cli(["equilibrium", "examples/ring_3_loops.toml", "--contact", "--layers", "wound",
                 "--laminate", "12", "--elements", "48"])
    assert r.exit_code == 2 and "--laminate" in r.stderr
    r = run_cli(["equilibrium", "examples/birod.toml", "--contact", "--layers", "folded",
                 "--elements", "8"])
    assert r.exit_code == 2 and "--layers folded" in r.stderr


ROOT_RING = (Path(__file__).resolve().parent.parent / "examples" / "ring_3_loops.toml").read_text()


def test_flat_foldings_give_lk_0_for_odd_n_only():
    """Row 3.1j's computation: the smallest |Lk| of the flat foldings is the parity of N - 1
    (module doc), by Gauss's integral and by crossings alike, with the strip untwisted."""
    for N, expected in ((2, 1), (3, 0), (4, 1)):
        gauss, crossings, twist = flat_foldings(_coincident(N, 16)[1], 0.008 * math.pi)
        assert gauss == crossings == expected and twist < 0.05



def test_a_difference_along_the_sliding_field_is_no_distance_and_any_other_is():
    """The follower's return test (stacked.unslid_distance): a state moved along the ring's
    sliding field (node part of the field, any amount, either way) is the same state pinned
    elsewhere; a move across it (heights only: the field of a near-planar ring is nearly
    horizontal) keeps its node distance."""
    from rodstab.multistable.stacked import ring_sliding_field, unslid_distance

    a = rings.build(rings.Params(section=circle(), loops=3))
    rod, _ = stacked_ring(a, thickness_ratio=0.01, elements_per_loop=16, dhat_fraction=0.1,
                          stacking="folded")
    v = ring_sliding_field(rod)
    assert v is not None
    full = np.zeros(rod.n_dof)
    full[rod.free_dofs()] = v
    f = np.array([full[rod.node_dofs(k)] for k in range(len(rod.x))])
    for amount in (0.3, -0.9):
        slid = rod.copy()
        slid.x = rod.x + amount * f
        assert unslid_distance(slid, rod) == 0.0
    lifted = rod.copy()
    lifted.x = rod.x + np.array([0.0, 0.0, 1e-3]) * np.sin(np.arange(len(rod.x)))[:, None]
    assert unslid_distance(lifted, rod) == pytest.approx(
        float(np.max(np.abs(lifted.x[:, 2] - rod.x[:, 2]))))


@pytest.mark.slow
def test_cli_analyze_contact_takes_the_folded_stacking(run_cli):
    """`analyze --contact --layers folded`: the cone at zero gap of the ring folded flat,
    built and checked first (its ribbon links 0 times); both limits move outward from eq.
    (3.3)'s (mu = 2.147 / 3 and 3.859 / 3); too thick to build: exit 2 naming the thickness."""
    r = run_cli(["analyze", "examples/ring_3_loops.toml", "--contact", "--contact-thickness",
                 "0.003", "--layers", "folded", "--elements", "48"])
    assert r.exit_code == 0, r.stderr
    assert "links +0 times" in r.stdout
    assert r.stdout.count("moved outward by contact") == 2
    bad = run_cli(["analyze", "examples/ring_3_loops.toml", "--contact", "--layers", "folded",
                   "--elements", "48"])
    assert bad.exit_code == 2 and "thickness_ratio h/L = 0.02" in bad.stderr


def test_layer_swaps_of_a_ring_that_winds_once_is_empty():
    """The one-loop ring (what the folded ring snaps open into) has no layers to swap."""
    a = rings.build(rings.Params(section=circle(), loops=1))
    assert len(layer_swaps(discretise(a, 32, 1.0))) == 0


@pytest.mark.slow
def test_arclength_continuation_of_the_held_folded_ring_first_folds_by_sliding():
    """The folded ring held with contact at load 1 (16 el. per loop, h/L 0.01, dhat 0.1 h),
    followed up and down by arclength: each way the first special point is a fold whose lowest
    eigenmode is the ring's sliding field (measured cosines 0.988 and 0.998, at 3.677 and 2.907
    in (L/2pi) kappa_n): the mesh pins the swap pattern and each pinned copy folds after a
    short stretch (docs/theory/contact.md, 'Followed by arclength'). The cosine is computed
    here from the Hessian's lowest eigenvector, independently of the follower's slide test."""
    from scipy.sparse.linalg import eigsh

    from rodstab.multistable.stacked import hold_loops, ring_sliding_field
    from rodstab.nonlinear.continuation.run import continuation

    a = rings.build(rings.Params(section=circle(), loops=3))
    _, rod, ok, _, _ = hold_loops(a, 16, 1.0, 0.01 * len(a.segments), 0.1, "folded")
    assert ok
    for end in (2.0, 0.3):
        p = continuation(a, "load_factor", 1.0, end, 40, elements_per_segment=16,
                         rod=rod.copy(), contact=rod.contact.model, branch_steps=0,
                         stop_at_first=True)
        assert p.special_points and p.special_points[0]["kind"] == "fold"
        value, state = p.states[0]
        assert 1.0 < value < 1.3 if end > 1 else 0.7 < value < 1.0  # a short stretch
        free = state.free_dofs()
        H = state.energy_terms()[2][free][:, free]
        d = 1.0 / np.sqrt(np.abs(H.diagonal()))
        A = (H.multiply(d[:, None]).multiply(d[None, :])).tocsc()
        _, V = eigsh(0.5 * (A + A.T), k=1, sigma=-1e-6, which="LM")
        mode, s = d * V[:, 0], ring_sliding_field(state)
        assert abs(mode @ s) / (np.linalg.norm(mode) * np.linalg.norm(s)) > 0.9
