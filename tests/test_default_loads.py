"""Defaults that work on a design nobody tried (issue 20, the designer's interface).

The built-in structures of ``transitions`` and ``barrier`` used fixed default loads
(``kappa_n R0`` = 2 and 1) at which the circle section's states are not all stable: both runs
exited 2. Now a state unstable at the default load is skipped with a line, and the barrier's
default load is the middle of the two states' common stable interval (Bloch), checked here
against the FE engine on the held states themselves (an independent method).
"""

from __future__ import annotations

import json

import pytest


@pytest.mark.slow
def test_transitions_default_skips_the_states_unstable_at_the_load(run_cli):
    # circle, kappa_n R0 = 2: the line (+-0.43301), star (0.57569, 1.43004) and eight are
    # unstable there (docs/guide/multistable.md); the daisy is loaded.
    r = run_cli(["transitions", "--elements", "6", "--json"])
    assert r.exit_code == 0, r.stderr
    out = json.loads(r.stdout)
    skipped = {s["state"] for s in out["skipped"]}
    assert {"line", "star"} <= skipped and "daisy" not in skipped
    assert all(e["from"] not in skipped for e in out["edges"])


def test_transitions_a_state_named_must_be_stable(run_cli):
    r = run_cli(["transitions", "--elements", "6", "--state", "line"])
    assert r.exit_code == 2 and "'line'" in r.stderr and "not stable" in r.stderr


def test_barrier_circle_default_names_both_intervals(run_cli):
    r = run_cli(["barrier", "--elements", "6", "--images", "7"])
    assert r.exit_code == 2
    assert "never stable together" in r.stderr
    assert "folded (-0.433013, 0.433013)" in r.stderr and "one-loop (0.575694" in r.stderr


@pytest.mark.slow
def test_barrier_default_load_is_inside_both_fe_intervals(run_cli):
    from rodstab.linear.solve import converged_stability
    from rodstab.problems.barrier_states import model_load_factor, state_assembly
    from rodstab.sections import rectangle

    r = run_cli(["barrier", "--elements", "6", "--images", "7", "--shape", "rectangle",
                 "--aspect", "4", "--json"])
    assert r.exit_code == 0, r.stderr
    out = json.loads(r.stdout)
    lo, hi = out["load_factor_chosen_in"]
    assert out["kappa_R0"] == pytest.approx(0.5 * (lo + hi), rel=1e-12)
    # the FE on the six-ring's folded state (stress-free at kappa_n R0 = 0, so its pencil has
    # a stable reference): its upper limit is the common interval's upper end
    folded = converged_stability(state_assembly("six-ring", rectangle(aspect=4.0), "folded"),
                                 32)
    unit = model_load_factor("six-ring", 1.0)
    f_lo, f_hi = (x / unit for x in folded.load_factor_interval)
    assert f_lo <= lo and hi == pytest.approx(f_hi, rel=1e-6)
