"""Continuation in any parameter (rodstab.nonlinear.continuation / .parameters).

References: Greenhill's twisted rod (closed form tan x = x), Koiter's 2/3 law for an unstable
symmetric bifurcation, the held-state critical loads of the discrete model (an independent
root-finder path), finite differences of the exact gradient, the closed-form energies of
circular rings.
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest
import scipy.optimize as so

from rodstab.errors import RodstabInputError
from rodstab.io.design import parse_design
from rodstab.io.vary import set_design_value
from rodstab.linear.solve import linear_stability
from rodstab.model import Assembly, Segment
from rodstab.nonlinear.continuation import continuation, imperfection_sensitivity
from rodstab.nonlinear.discrete import discretise
from rodstab.nonlinear.parameters import parameter
from rodstab.nonlinear.solve import critical_load_factor
from rodstab.sections import circle

ROOT = Path(__file__).resolve().parent.parent
B2_ISO = 1.0 / 1.3  # circle, nu = 0.3: B2 / B1
#: Greenhill: clamped twisted rod, zero axial force: M L / B = 2 x (first root of tan x = x).
GREENHILL = 2 * so.brentq(lambda x: math.tan(x) - x, 4.0, 4.6)


def _twisted(n_end: str = "sliding-clamp", B2: float = B2_ISO) -> Assembly:
    return Assembly(segments=(Segment(name="rod", length=1.0, curvature=0.0, natural_curvature=0.0,
                                      B1=1.0, B2=B2, B3=1.0),),
                    supports=(("rod", "start", "clamped"), ("rod", "end", n_end)))


KEYS = ("load_factor", "segment.rod.natural_curvature", "segment.rod.natural_twist",
        "support.1.rotation.normal", "support.1.rotation.tangent",
        "support.1.rotation.binormal")


@pytest.mark.parametrize("key", KEYS)
def test_parameter_derivative_of_the_gradient_is_exact(key):
    """dg/dp against a central difference of the exact gradient on a random state (affine
    parameters: exact difference, so a wide step; rotations: a small one)."""
    a = Assembly(segments=(Segment(name="rod", length=1.0, curvature=0.0, natural_curvature=1.0,
                                   B1=1.2, B2=0.8, B3=1.0, natural_twist=0.5),),
                 supports=(("rod", "start", "clamped"), ("rod", "end", "clamped")),
                 end_rotations=(("rod", "end", (0.1, 0.3, -0.2)),))
    rng = np.random.default_rng(1)
    rod = discretise(a, 8)
    P = parameter(a, key, 8)
    dq = np.zeros(rod.n_dof)
    dq[rod.free_dofs()] = 0.05 * rng.standard_normal(len(rod.free_dofs()))
    rod.apply(dq)
    p0, d = P.get(rod), P.dgrad(rod)
    h = 1e-5 if key.startswith("support") else 1e-2
    r1, r2 = rod.copy(), rod.copy()
    P.set(r1, p0 + h)
    P.set(r2, p0 - h)
    fd = (r1.energy_terms()[1] - r2.energy_terms()[1]) / (2 * h)
    f = rod.free_dofs()
    assert np.linalg.norm(d[f] - fd[f]) <= 1e-7 * np.linalg.norm(fd[f])


@pytest.mark.slow
def test_end_rotation_critical_twist_converges_to_greenhill_at_order_two():
    """Critical end rotation of the twisted rod: phi_c B2 / (B1 L) -> 2 x 4.4934 (Greenhill),
    error falling at order 2 (three meshes), Richardson value within 0.1 %."""
    vals = []
    for n in (16, 32, 64):
        c = continuation(_twisted(), "support.1.rotation.tangent", 0.0, 14.0, 14,
                         elements_per_segment=n, branch_steps=0, stop_at_first=True)
        (sp,) = c.special_points
        assert sp["kind"] == "branch point (stability lost)"
        vals.append(sp["value"] * B2_ISO)
    err = np.abs(np.array(vals) - GREENHILL)
    order = np.log2(err[:-1] / err[1:])
    assert np.all((order > 1.8) & (order < 2.2)), order
    rich = vals[2] + (vals[2] - vals[1]) / 3
    assert abs(rich - GREENHILL) / GREENHILL < 1e-3


@pytest.mark.slow
def test_twisted_rod_buckles_subcritically_with_koiter_two_thirds_law():
    """Rotation control, zero axial force: the branch from the Greenhill point lies at smaller
    rotations (unstable symmetric); imperfections shaped like the mode lower the limit
    rotation as eps^(2/3) (Koiter), the fitted exponent within 0.02."""
    c = continuation(_twisted(), "support.1.rotation.tangent", 0.0, 13.0, 13,
                     elements_per_segment=12, branch_steps=6)
    (b,) = c.branches
    assert "subcritical" in b.verdict
    # every point off the bifurcation (xi != 0) lies at a smaller rotation
    assert max(v for x, v in zip(b.amplitude, b.value, strict=True) if x != 0) < b.value_critical
    r = imperfection_sensitivity(_twisted(), "support.1.rotation.tangent", 0.0, 13.0,
                                 epsilons=(5e-4, 1e-3, 2e-3), elements_per_segment=12,
                                 n_steps=13)
    assert abs(r.exponent - 2 / 3) < 0.02, r.exponent
    assert all(v < r.value_critical for v in r.limit_value)
    assert abs(r.value_critical - b.value_critical) < 1e-6 * b.value_critical


def test_twisted_rod_with_both_ends_fixed_has_the_same_linear_threshold():
    """Fixed end distance does not enter the linear problem: same critical rotation as the
    sliding end (within the bracket interpolation)."""
    vals = []
    for end in ("clamped", "sliding-clamp"):
        c = continuation(_twisted(end), "support.1.rotation.tangent", 0.0, 14.0, 14,
                         elements_per_segment=8, branch_steps=0, stop_at_first=True)
        vals.append(c.special_points[0]["value"])
    assert vals[0] == pytest.approx(vals[1], rel=1e-6)


@pytest.mark.slow
def test_segment_natural_curvature_key_matches_the_held_state_critical_load():
    """Varying a segment's natural curvature (incremental natural-shape update) at load factor
    1 locates the same critical value as the held-state root finder in the load factor."""
    C = circle()
    a = Assembly(segments=(Segment(name="ring", length=6 * math.pi, curvature=1.0,
                                   natural_curvature=1.0, B1=C.b1, B2=C.b2, B3=1.0),),
                 welds=((("ring", "end"), ("ring", "start")),))
    held = critical_load_factor(a, 0.6, 1.0, elements_per_segment=36).load_factor_critical
    c = continuation(a, "segment.ring.natural_curvature", 1.0, 0.6, 8, elements_per_segment=36,
                     branch_steps=4)
    sp = c.special_points[0]
    assert sp["value"] == pytest.approx(held, rel=1e-6)
    # 3-loop ring losing stability as kappa_n falls: the branch lies below (supercritical).
    assert "supercritical" in sp["post_buckling"]


def test_one_loop_ring_path_reaches_the_three_loop_ring(reproduction):
    """Arclength from the 1-loop bifurcation (the report's T-ring path, 48 elements): the
    natural curvature rises monotonically, the path is stable all the way (no barrier) and the
    ring closes on three loops (radius -> R/3, near-neutral there); the start energy is the
    circular ring's pi (kappa - 1)^2 (B3 = 1, L = 2 pi) within 1 %. The end point's order-2
    convergence to the analytic 3-loop bifurcation is the T-ring row's computed status
    (tests/test_checks.py)."""
    out, _ = reproduction
    rp = json.loads((out / "results.json").read_text())["figures"]["beyond"]["ring_path"]
    mu, rad = np.array(rp["mu"]), np.array(rp["radius"])
    ev, en = np.array(rp["lowest_eigenvalue"]), np.array(rp["energy"])
    i = len(mu) - 1  # the data end at the smallest radius
    assert int(np.argmin(rad)) == i and abs(rad[i] - 1 / 3) < 0.01
    assert np.all(np.diff(mu) > -1e-9)
    assert np.all(ev[1:i] > 0)
    # near-neutral at the sampled point nearest the 3-loop ring
    assert abs(ev[i]) < 0.1 * ev[1:i].max()
    assert en[0] == pytest.approx(math.pi * (mu[0] - 1) ** 2, rel=1e-2)


def test_end_rotation_design_validation_and_linear_refusal():
    base = {"segment": [{"name": "r", "length": 1.0}],
            "support": [{"end": "r.start"}, {"end": "r.end", "rotation": [0.0, 0.5, 0.0]}]}
    assert parse_design(base).assembly.end_rotations == (("r", "end", (0.0, 0.5, 0.0)),)
    with pytest.raises(RodstabInputError, match="linear engine"):
        linear_stability(parse_design(base).assembly)
    bad = set_design_value(base, "support.1.rotation.normal", 0.2)
    assert bad["support"][1]["rotation"] == [0.2, 0.5, 0.0]
    with pytest.raises(RodstabInputError, match="support index '5'"):
        set_design_value(base, "support.5.rotation.normal", 0.2)
    with pytest.raises(RodstabInputError, match="rotation axis 'twist'"):
        set_design_value(base, "support.1.rotation.twist", 0.2)
    with pytest.raises(RodstabInputError, match=r"rotation must be three numbers"):
        parse_design({**base, "support": [{"end": "r.start", "rotation": [1, 2]}]})
    with pytest.raises(RodstabInputError, match="needs a clamped or sliding-clamp"):
        parse_design({**base, "support": [{"end": "r.start", "type": "pinned",
                                           "rotation": [0, 1, 0]}]})
    a = parse_design(base).assembly
    with pytest.raises(RodstabInputError, match="cannot be continued"):
        parameter(a, "segment.r.B3", 8)
    with pytest.raises(RodstabInputError, match="cannot be continued"):
        parameter(a, "section.aspect", 8)
    with pytest.raises(RodstabInputError, match="only a clamped or sliding-clamp"):
        parameter(parse_design({**base, "support": [{"end": "r.start", "type": "pinned"}]})
                  .assembly, "support.0.rotation.tangent", 8)


@pytest.mark.slow
def test_cli_continue_in_an_end_rotation_resumes_and_reports_subcritical(run_cli, tmp_path):
    args = ["continue", "examples/twisted_rod.toml", "--vary",
            "support.1.rotation.tangent=0:13:13", "--elements", "16", "--branch-steps", "4",
            "--out", str(tmp_path), "--no-progress", "--json"]
    r = run_cli(args)
    assert r.exit_code == 0, r.stderr
    p = json.loads(r.stdout)
    (sp,) = p["special_points"]
    assert abs(sp["value"] * B2_ISO - GREENHILL) / GREENHILL < 0.025  # 16 elements: 1.9 %
    assert "subcritical" in sp["post_buckling"]
    for name in ("primary.csv", "branches.csv", "special_points.json", "diagram.png",
                 "branch.gif"):
        assert (tmp_path / name).exists()
    again = json.loads(run_cli(args).stdout)
    assert again["resumed_steps"] == len(p["value"])
    assert again["special_points"][0]["value"] == pytest.approx(sp["value"])


@pytest.mark.parametrize("vary, message", [
    ("segment.rod.B3=1:2", "cannot be continued"),
    ("support.0.rotation.spin=0:1", "rotation axis 'spin'"),
    ("load_factor=1", "KEY=START:STOP"),
    ("load_factor=1:1", "two different values"),
])
def test_cli_continue_rejects_bad_vary_with_a_one_line_error(run_cli, vary, message):
    r = run_cli(["continue", "examples/twisted_rod.toml", "--vary", vary, "--no-progress"])
    assert r.exit_code == 2
    assert message in r.stderr and "Traceback" not in r.stderr


@pytest.mark.slow
def test_folded_six_ring_bifurcation_is_subcritical_and_its_saddle_reaches_the_one_loop_ring(
        reproduction):
    """Six-sided ring, h/t = 4: the folded state's branch point is the linear engine's critical
    load (0.5 %, 8 elements), its critical eigenvalue is double and both branch directions
    (critical points of the quartic form on the two-mode kernel) are subcritical. The saddle
    path along the most dangerous one runs to smaller kappa_n and turns on the one-loop state
    at that state's lower stability limit, with the one-loop state's shape (radius within
    1 %). Start energy: the folded state's closed form 6 x 1/2 kappa_n^2 L (B3 = 1, L = 1)."""
    from rodstab.nonlinear.continuation.branches import branch_directions
    from rodstab.nonlinear.parameters import LoadFactor
    from rodstab.problems import folded_ring, unfolded_ring
    from rodstab.sections import rectangle

    r4 = rectangle(aspect=4.0)
    theta = 2 * math.pi / 3
    a = folded_ring.build(folded_ring.Params(section=r4))
    lin = linear_stability(a, 16).load_factor_critical
    c = continuation(a, "load_factor", 1.0, 6.0, 10, elements_per_segment=8, branch_steps=6)
    (sp,) = c.special_points
    assert abs(sp["value"] - lin) / lin < 5e-3
    assert "subcritical" in sp["post_buckling"]
    (_, at), = c.states
    dirs = branch_directions(at, LoadFactor(), -1.0, 1.0)
    assert len(dirs) == 2 and all(d.curvature < 0 for d in dirs)  # both lower the load
    # The saddle path (the report's T-six data, 12 elements): from the folded state's closed
    # form energy down to its turning point on the one-loop state, which is located within
    # 5 % of the one-loop state's lower limit here (the Richardson value within 0.5 % is the
    # T-six row's computed status), with the one-loop shape.
    out, _ = reproduction
    six = json.loads((out / "results.json").read_text())["figures"]["beyond"]["six_path"]
    k, rad, en = np.array(six["kappa_R0"]), np.array(six["radius"]), np.array(six["energy"])
    assert np.all(np.diff(k) < 1e-9)
    one = unfolded_ring.build(unfolded_ring.Params(section=r4, radius=1 / theta))
    lo = linear_stability(one, 24).load_factor_interval[0]  # kappa_n R0
    assert abs(k[-1] - lo) / lo < 0.05
    x = discretise(one, 12).x
    r_one = float(np.max(np.linalg.norm(x - x.mean(axis=0), axis=1)))
    assert rad[-1] == pytest.approx(r_one, rel=1e-2)
    assert en[0] == pytest.approx(3 * (k[0] * theta) ** 2, rel=1e-3)


@pytest.mark.parametrize("case", ["unstable straight rod", "three-loop ring"])
def test_sparse_lowest_eigenvalues_match_the_dense_solver(case, monkeypatch):
    """Shift-invert Lanczos (used above DENSE_EIG_MAX unknowns) returns the same lowest
    eigenvalues as the dense solver, negative ones included, on the tiny clustered spectrum of
    the penalty-scaled Hessian."""
    import rodstab.nonlinear.solve as S
    from rodstab.numerics import eigen

    C = circle()
    if case == "unstable straight rod":
        a = Assembly(segments=(Segment(name="a", length=1.0, curvature=0.0, natural_curvature=1.0,
                                       B1=C.b1, B2=C.b2, B3=1.0),),
                     supports=(("a", "start", "clamped"), ("a", "end", "sliding-clamp")))
        rod = discretise(a, 60, 9.0)  # mu_c = 5.56: one or more negative eigenvalues
    else:
        a = Assembly(segments=(Segment(name="ring", length=6 * math.pi, curvature=1.0,
                                       natural_curvature=1.0, B1=C.b1, B2=C.b2, B3=1.0),),
                     welds=((("ring", "end"), ("ring", "start")),))
        rod = discretise(a, 90, 1.0)
    dense = S.lowest_modes(rod, 4)[0]
    monkeypatch.setattr(eigen, "DENSE_EIG_MAX", 10)
    sparse = S.lowest_modes(rod, 4)[0]
    assert np.allclose(sparse, dense, rtol=1e-6, atol=1e-9 * np.max(np.abs(dense)))
    if case == "unstable straight rod":
        assert dense[0] < 0


def test_equilibrium_reports_the_strain_of_an_impossible_end_motion():
    """Turning a clamped end in-plane while both ends are fixed in position cannot be done by
    an inextensible rod: the equilibrium's stretch strain is reported and exceeds the warning
    level; with the end free to slide the same rotation leaves the rod unstretched."""
    from rodstab.nonlinear.solve import STRAIN_WARN, equilibrium

    def rod(end: str) -> Assembly:
        return Assembly(segments=(Segment(name="rod", length=1.0, curvature=0.0,
                                          natural_curvature=0.0, B1=1.0, B2=B2_ISO, B3=1.0),),
                        supports=(("rod", "start", "clamped"), ("rod", "end", end)),
                        end_rotations=(("rod", "end", (0.0, 0.0, 0.5)),))

    fixed, _ = equilibrium(rod("clamped"), elements_per_segment=32)
    sliding, _ = equilibrium(rod("sliding-clamp"), elements_per_segment=32)
    assert fixed.converged and sliding.converged
    assert fixed.max_strain > STRAIN_WARN > 100 * sliding.max_strain


def test_design_rotation_beyond_pi_keeps_its_twist():
    """A design end rotation of 4 rad about the tangent (more than pi) is applied gradually:
    the rod carries a twist of 4 rad, energy B2 phi^2 / (2 L) (below Greenhill's load), not
    the twist 4 - 2 pi of the same end frame."""
    from rodstab.nonlinear.solve import equilibrium

    a = Assembly(segments=(Segment(name="rod", length=1.0, curvature=0.0, natural_curvature=0.0,
                                   B1=1.0, B2=B2_ISO, B3=1.0),),
                 supports=(("rod", "start", "clamped"), ("rod", "end", "sliding-clamp")),
                 end_rotations=(("rod", "end", (0.0, 4.0, 0.0)),))
    r, _ = equilibrium(a, elements_per_segment=32)
    assert r.converged and r.stable
    # Cayley twist measure: + (phi/n)^2 / 6 relative at n elements (0.26 % here).
    assert r.energy == pytest.approx(B2_ISO * 4.0**2 / 2, rel=5e-3)


@pytest.mark.slow
def test_interactive_html_views_are_written(run_cli, tmp_path):
    """equilibrium --html writes a self-contained plotly page; continue --out adds
    branch.html with one frame per traced shape."""
    pytest.importorskip("plotly")
    r = run_cli(["equilibrium", "examples/twisted_rod.toml", "--elements", "8", "--html",
                 str(tmp_path / "eq.html"), "--json"])
    assert r.exit_code == 0, r.stderr
    text = (tmp_path / "eq.html").read_text()
    assert "plotly" in text.lower() and "scatter3d" in text  # the segments' outlines
    assert '"intensitymode":"cell"' in text  # the rods' boxes, coloured per face
    r = run_cli(["continue", "examples/twisted_rod.toml", "--vary",
                 "support.1.rotation.tangent=0:13:13", "--elements", "8", "--branch-steps", "3",
                 "--out", str(tmp_path / "c"), "--no-progress", "--json"])
    assert r.exit_code == 0, r.stderr
    page = (tmp_path / "c" / "branch.html").read_text()
    assert page.count('"name":"') >= 4  # the branch point and three steps: animation frames


def test_a_double_modes_phase_does_not_change_the_twisted_rods_branch_direction(monkeypatch):
    """Greenhill's rod has a double critical mode (an axis of symmetry): every combination of
    the two is the same buckling rotated about the axis, and which one an eigensolver returns
    is round-off (it differed between two BLAS kernel sets, and so did the report's PB-twist
    and IMP-twist numbers: the branch's first step and the imperfection, both scaled by the
    mode's largest entry, depend on the phase). With the eigenbasis turned by 0.7 rad before
    the branch is chosen, the branch direction (the imperfection's shape too) is the same mode
    up to sign: the combination with the largest out-of-plane field."""
    import rodstab.nonlinear.continuation.branches as br
    from rodstab.nonlinear.parameters import parameter
    from rodstab.nonlinear.solve import lowest_modes

    key = "support.1.rotation.tangent"
    c = continuation(_twisted(), key, 0.0, 13.0, 13, elements_per_segment=12, branch_steps=0,
                     stop_at_first=True)
    _, state = c.states[0]
    param = parameter(_twisted(), key, 12)
    (d,) = br.branch_directions(state, param, -1.0, 1.0)

    def turned(rod, k, *args):
        vals, vecs = lowest_modes(rod, k, *args)
        c_, s_ = math.cos(0.7), math.sin(0.7)
        vecs = vecs.copy()
        vecs[:, :2] = vecs[:, :2] @ np.array([[c_, -s_], [s_, c_]])
        return vals, vecs

    monkeypatch.setattr(br, "lowest_modes", turned)
    (e,) = br.branch_directions(state, param, -1.0, 1.0)
    assert abs(abs(float(d.mode @ e.mode)) - 1.0) < 1e-8


def test_a_branch_point_whose_refinement_finds_no_equilibrium_says_so(monkeypatch):
    """Brent on the eigenvalue needs an equilibrium at each trial value; where Newton finds
    none (measured: the folded 3-loop ring with contact at 64 el.) the continuation must not
    stop on a NaN: the point keeps the interpolation in its bracket and says it is not
    refined, and a run with refinement gives a value inside that bracket."""
    from rodstab.nonlinear.continuation import special

    c = continuation(_twisted(), "support.1.rotation.tangent", 0.0, 14.0, 14,
                     elements_per_segment=8, branch_steps=0, stop_at_first=True)
    (ref,) = c.special_points
    assert "refined" not in ref
    monkeypatch.setattr(special, "newton", lambda rod: (False, 0, math.nan))
    c = continuation(_twisted(), "support.1.rotation.tangent", 0.0, 14.0, 14,
                     elements_per_segment=8, branch_steps=0, stop_at_first=True)
    (sp,) = c.special_points
    assert sp["kind"] == "branch point (stability lost)"
    assert "not refined" in sp["refined"] and "interpolated" in sp["refined"]
    lo, hi = sp["bracket"]
    assert lo < sp["value"] < hi and lo < ref["value"] < hi
    assert sp["value"] != ref["value"]
