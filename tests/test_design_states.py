"""Barriers on a design that is no ring: its states by deflation, a state's mirror image.

The bi-rod of Section 4 (examples/birod.toml, B3 = L = 1) past its buckling load has one
stable state up to reflection: buckled out of its plane to either side. Its held straight
state is then the saddle between the two, of energy ``2 x B3 mu^2 L / 2 = mu^2`` (closed form,
as in tests/test_discover.py).
"""

from __future__ import annotations

import json

import numpy as np
import pytest

from rodstab.errors import RodstabInputError
from rodstab.io.design import load_design
from rodstab.multistable.design_states import design_states, mirror_image, pick_state
from rodstab.multistable.identify import kabsch_rms


def test_proper_alignment_tells_a_chiral_shape_from_its_mirror_image() -> None:
    """A helix and its mirror image: the same shape with reflections allowed, apart without."""
    t = np.linspace(0.0, 4 * np.pi, 60)
    helix = np.stack([np.cos(t), np.sin(t), 0.2 * t], axis=1)
    mirror = helix * np.array([1.0, 1.0, -1.0])
    turned = helix @ np.array([[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]]).T + 3.0
    assert kabsch_rms(helix, mirror) < 1e-12
    assert kabsch_rms(helix, mirror, proper=True) > 0.1
    assert kabsch_rms(helix, turned, proper=True) < 1e-12


@pytest.fixture(scope="module")
def birod_states():
    return design_states(load_design("examples/birod.toml").assembly, 8, 3.0)


@pytest.mark.slow
def test_the_buckled_birod_is_listed_with_its_mirror_image(birod_states) -> None:
    """At load factor 3 (8 el.): one stable state up to reflection, and its mirror image in the
    held plane -- an equilibrium of the same energy, another state without reflections."""
    (lab1, r1), (lab2, r2) = birod_states
    assert (lab1, lab2) == ("#1", "#1 mirror")
    assert r2.energy() == pytest.approx(r1.energy(), rel=1e-12)
    assert r1.energy() < 9.0  # below the held state's mu^2: it buckled
    g = r2.energy_terms()[1][r2.free_dofs()]
    assert np.max(np.abs(g)) < 1e-6
    assert kabsch_rms(r1.x, r2.x) < 1e-12 < 1e-3 < kabsch_rms(r1.x, r2.x, proper=True)
    assert mirror_image(r1, r1) is None  # the buckled state has no plane to reflect in
    assert pick_state(birod_states, "#1 mirror", "--to")[0] == "#1 mirror"
    with pytest.raises(RodstabInputError, match="--to 'held'"):
        pick_state(birod_states, "held", "--to")


@pytest.mark.slow
def test_cli_barrier_between_the_buckled_birod_and_its_mirror_image(run_cli) -> None:
    """``rodstab barrier examples/birod.toml --load-factor 3``: the saddle is the held straight
    state, energy mu^2 = 9 (closed form), index 1; both barriers equal (mirror images), each
    9 - E_buckled; its descents end on the two states."""
    res = run_cli(["barrier", "examples/birod.toml", "--load-factor", "3", "--elements", "8",
                   "--json"])
    assert res.exit_code == 0, res.stderr
    out = json.loads(res.stdout)
    assert out["converged"] and out["saddle_index"] == 1
    assert out["energy_saddle"] == pytest.approx(9.0, rel=1e-9)
    assert sorted(out["descent_ends"]) == ["#1", "#1 mirror"]
    assert out["barrier_forward"] == pytest.approx(out["barrier_backward"], rel=1e-9)
    assert out["barrier_forward"] == pytest.approx(9.0 - out["energy_from"], rel=1e-9)


@pytest.mark.parametrize("args, named", [
    ([], "--load-factor is required"),
    pytest.param(["--load-factor", "2"], "1 stable state(s)", marks=pytest.mark.slow),
    (["--load-factor", "3", "--contact"], "--contact needs a ring"),
    pytest.param(["--load-factor", "3", "--from", "nosuch"], "--from 'nosuch'",
                 marks=pytest.mark.slow),
])
def test_cli_barrier_on_a_design_that_is_no_ring_refuses_naming_why(run_cli, args, named):
    res = run_cli(["barrier", "examples/birod.toml", "--elements", "4", *args])
    assert res.exit_code == 2 and named in res.stderr


@pytest.mark.parametrize("command", [["states"], ["transitions"],
                                     ["atlas", "--vary", "section.aspect=2:4:2"]])
def test_ring_commands_on_a_design_that_is_no_ring_say_which_commands_take_it(run_cli,
                                                                              command):
    res = run_cli([*command[:1], "examples/birod.toml", *command[1:]])
    assert res.exit_code == 2
    assert "examples/birod.toml is not a ring (a ring has no supports" in res.stderr
    assert f"`rodstab {command[0]}` needs rods welded in one cycle" in res.stderr
    assert "`rodstab discover`, `diagram` and `barrier` take any design" in res.stderr
