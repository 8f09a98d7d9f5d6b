"""The nonlinear engine at fine meshes (issue 12, target 3): Newton's tolerance against the
gradient's round-off, the sparse stability check against the dense one, and the stability
verdict of a stable state at hundreds of elements per segment."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.linalg

from rodstab.design import load_design
from rodstab.nonlinear.discrete import discretise
from rodstab.nonlinear.solve import (
    lowest_eigenvalues,
    newton,
    residual_tolerance,
    zero_eigenvalue_tol,
)
from rodstab.numerics import DENSE_EIG_MAX, jacobi_scaling
from rodstab.problems import folded_ring

EXAMPLES = "examples/"


def test_sparse_lowest_eigenvalues_equal_the_dense_ones_on_the_six_ring():
    """Folded six-ring, 32 elements per segment (1164 free unknowns, the sparse shift-invert
    path): its 6 lowest scaled Hessian eigenvalues (4e-10..4e-9) equal LAPACK's dense
    ``eigh`` of the same Jacobi-scaled matrix to 4 u absolute (9e-16, 2e-6 relative): both are
    backward stable to ~u max|A| = u (unit diagonal); measured 3.8e-16."""
    rod = discretise(folded_ring.build(folded_ring.Params()), 32, 0.8)
    free = rod.free_dofs()
    assert len(free) > DENSE_EIG_MAX
    sparse = lowest_eigenvalues(rod, 6)
    H = rod.energy_terms()[2][free][:, free]
    H = 0.5 * (H + H.T)
    d = jacobi_scaling(H)
    A = (d[:, None] * H.toarray()) * d[None, :]
    dense = scipy.linalg.eigh(A, eigvals_only=True, subset_by_index=[0, 5])
    assert dense[0] > 0
    np.testing.assert_allclose(sparse, dense, rtol=0, atol=4 * np.finfo(float).eps)


def test_newton_tolerance_is_above_the_gradient_round_off():
    """The hexagram at 512 and 1024 elements per segment: a rigid translation, which leaves
    the exact gradient unchanged, changes the computed one by its round-off; Newton's
    tolerance must lie above that (below it Newton cannot converge: it stalled at 60
    iterations), and the relative tolerance alone does not."""
    a = load_design(EXAMPLES + "hexagram.toml").assembly
    for n in (512, 1024):
        rod = discretise(a, n, 1.0)
        free = rod.free_dofs()
        moved = rod.copy()
        moved.x = moved.x + np.array([0.3, 0.7, 0.1])
        noise = np.abs(moved.gradient()[free] - rod.gradient()[free])
        assert np.all(residual_tolerance(rod)[free] > 2 * noise)


def test_newton_converges_on_the_hexagram_at_1024_elements_per_segment():
    """From the held state (residual 5e-2, round-off of the held geometry) Newton converges in
    at most 3 iterations (it stalled at 60 iterations, residual 5e-3, before the tolerance
    knew the gradient's round-off)."""
    rod = discretise(load_design(EXAMPLES + "hexagram.toml").assembly, 1024, 1.0)
    ok, its, _ = newton(rod)
    free = rod.free_dofs()
    assert ok and its <= 3
    assert np.all(np.abs(rod.gradient()[free]) <= residual_tolerance(rod)[free])


def _twisted_straight_rod(n: int, amplitude: float):
    from rodstab.model import Assembly, Segment

    s = Segment(name="a", length=1.0, curvature=0.0, natural_curvature=0.0, B1=1.0, B2=0.75,
                B3=1.0)
    rod = discretise(Assembly(segments=(s,), supports=(("a", "start", "clamped"),
                                                        ("a", "end", "clamped"))), n, 1.0)
    ne = len(rod.R_edge)
    dq = np.zeros(rod.n_dof)
    dq[rod.edge_dofs(np.arange(ne))[:, 1]] = amplitude * np.sin(
        2 * np.pi * (np.arange(ne) + 0.5) / ne)
    rod.apply(dq)
    return rod


@pytest.mark.parametrize(("n", "amplitude"), [(2048, 0.05), (4096, 0.01)])
def test_a_twisted_straight_rod_is_no_equilibrium_at_fine_meshes(n, amplitude):
    """A smooth twist ``amplitude sin(2 pi s)`` rad on the clamped straight rod: its twisting
    moments (~1e-3, ~1e-4) are far below the positions' round-off bound (~7, ~30) and, at
    4096 elements, below the stiff scale's relative tolerance (4e-4); they are above the
    rotations' bound (bending scale, round-off), so Newton iterates and untwists the rod. (One
    bound for all unknowns passed it at 2048 elements, the stiff scale alone at 4096; both
    with 0 iterations.)"""
    rod = _twisted_straight_rod(n, amplitude)
    ok, its, _ = newton(rod)
    assert ok and its >= 1
    assert float(np.max(np.abs(rod.edge_twist()))) < 1e-6


@pytest.mark.parametrize("name", ["folded_six_ring.toml", "hexagram.toml"])
def test_a_stable_ring_is_stable_at_256_elements_per_segment(name):
    """The held states of the folded six-ring and the hexagram at their design loads are
    stable (as at 16-128 elements per segment). Their lowest scaled eigenvalue, ~2e-14 and
    ~6e-15, scales as (l_e / L)^4 (a displacement mode); the zero tolerance, scaled as
    (l_e / L)^2 alone, was 4e-14 and called them not stable."""
    rod = discretise(load_design(EXAMPLES + name).assembly, 256, 1.0)
    lam = lowest_eigenvalues(rod, 1)[0]
    assert lam > zero_eigenvalue_tol(rod)
    assert lam > 100 * float(np.finfo(float).eps) / 8  # well above the round-off floor


def test_newton_from_a_perturbed_six_ring_needs_as_many_iterations_on_a_fine_mesh():
    """From the held six-ring plus 0.01 L along its softest modes (``--perturb 0.01``), the
    relaxation takes the same few iterations at 16 and 256 elements per segment and returns to
    the stable held state (energy 3). Without retracting large steps onto the Kirchhoff
    constraint it took 131 and more than 600 (not converged): the second-order misfit a step
    leaves has a stiffness ~1 / l_e^2."""
    from rodstab.nonlinear.solve import equilibrium

    a = load_design(EXAMPLES + "folded_six_ring.toml").assembly
    its = []
    for n in (16, 256):
        r, _ = equilibrium(a, elements_per_segment=n, perturb=0.01)
        assert r.converged and r.stable and r.energy == pytest.approx(3.0, abs=1e-8)
        its.append(r.iterations)
    assert its[1] <= its[0] + 2 <= 12, its


def test_a_verdict_below_round_off_is_reported_unresolved_not_unstable(run_cli, monkeypatch):
    """The hexagram at 1024 elements per segment: its lowest scaled eigenvalue (~2e-17 here)
    is below what the absolute node positions resolve, so ``stable`` is False and the result
    says why (``stability_resolved`` False, a WARNING line); at 256 the same state is stable
    and resolved. The fine run raises the round-off floor from eps/4 to 4e-16 so that the
    test does not hang on another BLAS's last digits (2e-17 against 5.5e-17 here)."""
    import json

    import rodstab.nonlinear.solve as nsolve

    coarse = run_cli(["equilibrium", EXAMPLES + "hexagram.toml", "--elements", "256",
                      "--json"])
    c = json.loads(coarse.stdout)
    assert c["stable"] and c["stability_resolved"]
    monkeypatch.setattr(nsolve, "ZERO_EIG_ROUNDOFF", 4e-16)
    fine = run_cli(["equilibrium", EXAMPLES + "hexagram.toml", "--elements", "1024", "--json"])
    f = json.loads(fine.stdout)
    assert f["converged"] and not f["stable"] and not f["stability_resolved"]
    text = run_cli(["equilibrium", EXAMPLES + "hexagram.toml", "--elements", "1024"]).stdout
    assert "NOT RESOLVED" in text
