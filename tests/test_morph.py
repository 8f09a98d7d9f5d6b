"""Carrying equilibria to a ring no design holds (multistable/morph.py, `discover --morph`).

Oracles: a ring whose six rods are all morphed to length 1.1 is the identical ring of length
1.1, whose common rod is built from its own design (`uniform_ring`): the morphed star is its
star, to Newton's tolerance; a morph there and back returns the state it started from.
"""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from rodstab.cli import main
from rodstab.errors import RodstabInputError
from rodstab.multistable import morph as mo
from rodstab.multistable.discover import common_rod, deflated_newton
from rodstab.multistable.identify import Snapshot, aligned_distance
from rodstab.multistable.states import uniform_ring

KAPPA = 2 * math.pi / 3  # the hexagram's natural curvature per unit load factor


def _star(length: float, elements: int = 6, mu: float = 2.0):
    ring = uniform_ring(6, length=length, natural_curvature=KAPPA)
    rod = common_rod(ring.held(ring.state("star").theta), elements, mu)
    assert deflated_newton(rod, []).converged
    return rod, Snapshot.of(rod)


def test_every_rod_morphed_is_the_identical_ring_of_that_length():
    rod, star = _star(1.0)
    states = [("star", star)]
    for name in ("1", "2", "3", "4", "5", "6"):
        (m,) = mo.morph_states(rod, states, name, 1.1, 4)
        assert m.state is not None and m.reached == pytest.approx(1.1)
        states = [("star", m.state)]
    states[0][1].put(rod)
    E = rod.energy()
    ref, ref_star = _star(1.1)
    assert np.allclose(rod.rest_length, ref.rest_length, rtol=1e-12)
    assert E == pytest.approx(ref.energy(), rel=1e-9)
    assert aligned_distance(ref, states[0][1], ref_star) < 1e-6


def test_a_morph_there_and_back_returns_the_state():
    rod, star = _star(1.0, elements=4)
    (out,) = mo.morph_states(rod, [("star", star)], "1", 1.1, 4)
    (back,) = mo.morph_states(rod, [("star", out.state)], "1", 1.0, 4)
    assert back.state is not None
    assert aligned_distance(rod, back.state, star) < 1e-6
    assert aligned_distance(rod, out.state, star) > 1e-3  # it did move


@pytest.mark.parametrize("text, words", [
    ("segment.1.natural_curvature=2", ["segment.NAME.length"]),
    ("segment.1.length=-1", ["positive"]),
    ("segment.1.length=1.1:0", ["STEPS >= 1"]),
    ("segment.1.length=x", ["VALUE must be a number"]),
])
def test_bad_morph_text_is_refused_naming_it(text, words):
    with pytest.raises(RodstabInputError) as exc:
        mo.parse_morph(text)
    for w in words:
        assert w in str(exc.value)


def test_an_unknown_segment_is_refused_naming_the_segments():
    rod, _ = _star(1.0, elements=2)
    for f in (lambda: mo.set_segment_length(rod, "r9", 1.1),
              lambda: mo.morph_seeds("segment.r9.length=1.1", rod, [])):
        with pytest.raises(RodstabInputError, match="segment 'r9' is not in the design"):
            f()


@pytest.mark.slow
def test_cli_discover_on_the_hexagram_with_one_rod_longer(capsys):
    """examples/hexagram.toml with r1 10 % longer at kappa_n R0 = 2 (6 el.): every seed is
    carried; the daisy and the star stay stable (labelled by their turning numbers)."""
    main(["discover", "examples/hexagram.toml", "--elements", "6", "--load-factor", "2",
          "--saddle-modes", "0", "--strings", "0", "--starts", "0", "--morph",
          "segment.r1.length=1.1:5"])
    out = capsys.readouterr().out
    assert "morphed      segment.r1.length 1 -> 1.1 in 5 steps: 11 of 11 seeds carried" in out
    rows = {line.split()[0]: line.split() for line in out.splitlines()
            if line.strip().startswith(("star ", "daisy "))}
    assert rows["star"][3] == "True" and rows["daisy"][3] == "True"


def test_the_length_parameters_derivative_predicts_the_states_move():
    """SegmentLength.dgrad: the tangent -H^-1 dg/dL at the hexagram's star (4 el., load 2)
    against the central difference of Newton's solutions at r1 = 1 +- 1e-3 (second order:
    4e-7 of the move measured, 3.6e-6 at +- 3e-3; each solve iterates, so the difference is
    not the solver's tolerance: at 1e-5 one-sided it was)."""
    import scipy.sparse.linalg as spla

    from rodstab.nonlinear.parameters import SegmentLength

    rod, star = _star(1.0, elements=4)
    par = SegmentLength(rod.assembly, "1")
    star.put(rod)
    free = rod.free_dofs()
    E, g, H = rod.energy_terms()
    Hf = H[free][:, free].tocsc()
    v = np.zeros(rod.n_dof)
    v[free] = spla.spsolve(0.5 * (Hf + Hf.T), -par.dgrad(rod, (E, g, H))[free])
    dx = v[: 3 * len(rod.x)].reshape(-1, 3)
    h = 1e-3
    xs = []
    for length in (1.0 + h, 1.0 - h):
        par.set(rod, length)
        assert par.get(rod) == pytest.approx(length, rel=1e-12)
        star.put(rod)
        assert deflated_newton(rod, []).converged
        xs.append(rod.x.copy())
    moved = (xs[0] - xs[1]) / (2 * h)
    assert np.max(np.abs(moved - dx)) < 2e-5 * np.max(np.abs(dx))


@pytest.mark.slow
def test_a_diagram_in_a_rods_length_meets_the_morphed_states():
    """The diagram continued in r1's length (tangent predictor, SegmentLength) and the morph
    (plain steps) reach the same star and daisy at 1.1: the same equilibria, energies to 1e-9."""
    from rodstab.multistable.diagram import deflated_diagram
    from rodstab.multistable.discover import ring_seeds
    from rodstab.nonlinear.parameters import SegmentLength

    ring = uniform_ring(6, natural_curvature=KAPPA)
    rod, seeds, known = ring_seeds(ring, "star", 4, 2.0, True)
    seeds = [(lab, s) for lab, s in seeds if lab in ("star", "daisy")]
    d = deflated_diagram(rod, seeds, known, [1.0, 1.05, 1.1], starts=0,
                         param=SegmentLength(rod.assembly, "1"))
    assert d.key == "segment.1.length"
    at = {b.label: b.points[-1] for b in d.branches if b.points[-1].value == 1.1}
    rod2, seeds2, _ = ring_seeds(ring, "star", 4, 2.0, True)
    for m in mo.morph_states(rod2, [(lab, s) for lab, s in seeds2 if lab in at], "1", 1.1, 4):
        m.state.put(rod2)
        assert rod2.energy() == pytest.approx(at[m.label].energy, rel=1e-9)


@pytest.mark.slow
def test_continue_in_a_rods_length_buckles_the_straightened_rod_at_eq_3_9(run_cli, tmp_path):
    """examples/straight_clamped_rod.toml (kappa_n = 1, circle, nu = 1/3) continued in its
    length at load factor 1: it buckles where kappa_n L = 2 pi sqrt(b1 b2) (eq. 3.9, the
    clamped straightened rod), L = 2 pi sqrt(0.75) = 5.441398; 16 / 32 el. extrapolated."""
    r = run_cli(["continue", "examples/straight_clamped_rod.toml", "--vary",
                 "segment.rod.length=1:6:25", "--elements", "16", "--out", tmp_path / "c",
                 "--json"])
    assert r.exit_code == 0, r.stderr
    (sp,) = json.loads(r.stdout)["special_points"]
    assert sp["kind"].startswith("branch point")
    exact = 2 * math.pi * math.sqrt(0.75)
    assert abs(sp["value_extrapolated"] - exact) < 0.02 * sp["error_estimate"]
    assert abs(sp["value"] - exact) > 0.5 * sp["error_estimate"]  # the mesh error is real
