"""rodstab.limits: the size estimates are exact counts, and runs past a limit are refused."""

from __future__ import annotations

from pathlib import Path

import pytest

from rodstab import limits
from rodstab.errors import RodstabInputError
from rodstab.io.design import load_design
from rodstab.linear.assembly import discretise as linear_discretise
from rodstab.nonlinear.discrete import discretise as nonlinear_discretise

ROOT = Path(__file__).resolve().parent.parent
#: Examples without natural twist or imposed end rotation (the linear engine refuses those).
EXAMPLES_LINEAR = [str(p) for p in sorted((ROOT / "examples").glob("*.toml"))
                   if p.stem != "twisted_rod"]


@pytest.mark.parametrize("path", EXAMPLES_LINEAR)
@pytest.mark.parametrize("n", [12, 17])
def test_unknown_counts_equal_the_discretisations(path, n):
    a = load_design(path).assembly
    ns = [n] * len(a.segments)
    J = len(a.joints())
    assert limits.linear_dof(ns, J) == linear_discretise(a, n).n_global
    assert limits.nonlinear_dof(ns, J) == nonlinear_discretise(a, n).n_dof


def test_runs_past_a_limit_are_refused_naming_cause_estimate_and_override():
    with pytest.raises(RodstabInputError, match=r"--elements 100000000.*unknowns.*--max-dof"):
        limits.require_linear([100_000_000], 2, "--elements 100000000")
    # 400k elements (1.6 million unknowns) fit the default unknown limit, not 1 GiB of memory.
    with pytest.raises(RodstabInputError, match=r"memory.*GiB.*--max-memory"):
        limits.require_linear([400_000], 2, "--elements 400000",
                              limits.Limits(max_memory=2**30))
    with pytest.raises(RodstabInputError, match=r"--max-dof"):
        limits.require_nonlinear([10_000_000], 2, "--elements 10000000")
    with pytest.raises(RodstabInputError, match=r"--vary .*1e\+09 steps.*--max-steps"):
        limits.require_steps(1_000_000_000, "--vary load_factor=1:4:1000000000")
    big = limits.Limits(max_dof=10**9, max_memory=2**50)
    assert limits.require_linear([32_000], 2, "x", big) == 3 * 2 + 4 * 32_000 - 2


@pytest.mark.parametrize("bad", [0, -1, 1.5, True, "8"])
def test_limits_must_be_positive_integers(bad):
    with pytest.raises(RodstabInputError, match="max-steps"):
        limits.Limits(max_steps=bad)
