"""Deflated Newton (nonlinear/discover.py, Farrell, Beentjes and Birkisson) and `rodstab discover`.

Oracles: finite differences of the deflation operator and of the deflated residual; the
clamped straightened rod above its buckling load (straight state unstable, two mirror buckled
states stable: the classic three solutions deflation must find from one start); rigid motions
and relabellings of a ring state leave the aligned distance zero; the hexagram's four basic
states, stable together at kappa_n R0 = 2 for h/t = 4 (rodstab hexagram: 1.903 < mu < 2.248).
"""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from rodstab.cli import main
from rodstab.multistable import discover as dv
from rodstab.multistable import identify as idf
from rodstab.nonlinear import constraint, solve
from rodstab.nonlinear.jets import rodrigues
from rodstab.problems import hexagram as hx
from rodstab.problems import straightened_rod as sr
from rodstab.sections import rectangle


def _straight_rod(elements: int = 8) -> dv.DiscreteRod:
    p = sr.Params()
    mu_c = 2 * math.pi / sr.to_paper(1.0, p)["lambda"]  # lambda_c = 2 pi (eq. 3.9)
    return dv.common_rod(sr.build(p), elements, 1.2 * mu_c)


def _hexagram_rod(state: str, elements: int = 8) -> dv.DiscreteRod:
    return dv.common_rod(hx.build(hx.Params(section=rectangle(aspect=4), state=state)),
                         elements, 2.0)


def test_common_rod_energy_depends_only_on_the_natural_curvature():
    """The eight's geometry has the same energy in the rods built from the star and the eight."""
    star, eight = _hexagram_rod("star"), _hexagram_rod("eight")
    moved = star.copy()
    dv.Snapshot.of(eight).put(moved)
    assert moved.energy() == pytest.approx(eight.energy(), rel=1e-12)
    line = _hexagram_rod("line")
    dv.Snapshot.of(star).put(line)
    assert line.energy() == pytest.approx(star.energy(), rel=1e-12)


def _random_state(rod: dv.DiscreteRod, rng: np.random.Generator, size: float) -> None:
    dq = np.zeros(rod.n_dof)
    dq[rod.free_dofs()] = size * rng.standard_normal(len(rod.free_dofs()))
    rod.apply(dq)


def test_deflation_operator_derivative_matches_finite_differences():
    """grad(log M) and the chart derivative of M g, ``M (H v - v x g / 2) + g (grad M . v)``.

    The ``- v x g / 2`` of each rotation block is the chart's (``R exp(phi)``) correction to the
    Hessian away from an equilibrium; Newton drops it (it vanishes at the solution).
    """
    rng = np.random.default_rng(1)
    rod = _straight_rod()
    known = []
    for _ in range(2):
        other = rod.copy()
        _random_state(other, rng, 0.05)
        known.append(dv.Snapshot.of(other))
    _random_state(rod, rng, 0.02)
    v = np.zeros(rod.n_dof)
    v[rod.free_dofs()] = rng.standard_normal(len(rod.free_dofs()))
    M, glog = dv.deflation(rod, known)
    _, g, H = rod.energy_terms()
    h = 1e-6

    def at(eps: float) -> tuple[float, np.ndarray]:
        r = rod.copy()
        r.apply(eps * v)
        return dv.deflation(r, known)[0], r.energy_terms()[1]

    (Mp, gp), (Mm, gm) = at(h), at(-h)
    assert (math.log(Mp) - math.log(Mm)) / (2 * h) == pytest.approx(glog @ v, rel=1e-6)
    Jv = M * (H @ v) + g * (M * (glog @ v))
    nx = 3 * len(rod.x)
    Jv[nx:] -= 0.5 * M * np.cross(v[nx:].reshape(-1, 3), g[nx:].reshape(-1, 3)).ravel()
    fd = (Mp * gp - Mm * gm) / (2 * h)
    free = rod.free_dofs()
    assert np.max(np.abs(fd[free] - Jv[free])) <= 1e-5 * np.max(np.abs(Jv[free]))


def test_deflation_finds_the_straight_and_both_buckled_rods():
    """Straightened clamped rod at 1.2 lambda_c: three equilibria from one start and its mirror.

    Starts +-0.01 L along the straight state's unstable mode, every solution found deflated:
    the straight state (index 1), then the two buckled states (stable, mirror images: one
    state modulo reflection), then nothing more.
    """
    rod = _straight_rod()
    straight = dv.Snapshot.of(rod)
    _, vecs = solve.lowest_modes(rod, 1)
    known: list[dv.Snapshot] = []
    indices = []
    for sign in (1, -1, 1, -1):
        r = rod.copy()
        straight.put(r)
        dq = np.zeros(rod.n_dof)
        dq[rod.free_dofs()] = vecs[:, 0]
        r.apply(sign * 0.01 * dq / np.max(np.abs(dq[: 3 * len(rod.x)])))
        if not dv.deflated_newton(r, known).converged:
            break
        known.append(dv.Snapshot.of(r))
        ev = solve.lowest_eigenvalues(r, 3)
        indices.append(int(np.sum(ev < -solve.zero_eigenvalue_tol(r))))
    assert indices == [1, 0, 0]
    E = []
    for s in known:
        s.put(rod)
        E.append(rod.energy())
    assert E[1] < E[0] and E[2] == pytest.approx(E[1], rel=1e-9)
    assert known[1].x[:, 2].sum() * known[2].x[:, 2].sum() < 0  # on opposite sides
    assert dv.same_state(rod, known[1], known[2], E[1], E[2])  # modulo reflection
    assert not dv.same_state(rod, known[0], known[1], E[0], E[1])


def test_aligned_distance_is_zero_modulo_rigid_motion_and_relabelling():
    """A star moved rigidly and relabelled (rods shifted by two) is the same state.

    (More transforms, a 3D state and the folded ring: tests/test_identify.py.)
    """
    rod = _hexagram_rod("star")
    s = dv.Snapshot.of(rod)
    Q = rodrigues(np.array([[0.3, -1.1, 0.7]]))[0]
    seg = np.array([idf.segment_nodes(rod, k) for k in range(6)])
    x = s.x.copy()
    x[seg] = np.roll(s.x[seg], 2, axis=0)
    moved = dv.Snapshot(x @ Q.T + np.array([1.0, -2.0, 0.5]), s.R_edge, s.R_joint)
    assert idf.aligned_distance(rod, s, moved) < 1e-12
    daisy = dv.Snapshot.of(_hexagram_rod("daisy"))
    assert idf.aligned_distance(rod, s, daisy) > 0.1


@pytest.mark.slow
def test_hexagram_discover_finds_the_four_basic_states_from_the_star(tmp_path, capsys):
    """Rectangle h/t = 4, kappa_n R0 = 2, 16 elements per rod: from the star's seed and the
    held geometries of the other closed states (rodstab states), the line, star, daisy and
    eight are found, each once, stable; the mirror states are found unstable."""
    main(["discover", "--shape", "rectangle", "--aspect", "4", "--load-factor", "2",
          "--saddle-modes", "0", "--strings", "0", "--starts", "0", "--elements", "16",
          "--plot", str(tmp_path / "g.png"), "--json"])
    out = json.loads(capsys.readouterr().out)
    labels = [s["label"] for s in out["states"]]
    for state in hx.STATES:
        assert labels.count(state) == 1
        assert next(s for s in out["states"] if s["label"] == state)["stable"]
    for s in out["states"]:
        # Newton's tolerance: 1e-10 x the stiff force scale PENALTY b1 / l_e = 1e3 x 16 x 16.
        assert s["residual"] <= 1e-10 * 1e3 * 16 * 16
        if s["label"].startswith("mirror-"):
            assert s["index"] >= 1 and not s["stable"]
    assert (tmp_path / "g.png").exists()


@pytest.mark.slow
def test_discover_reads_the_ring_of_a_design_file(capsys):
    """examples/folded_six_ring.toml (alternately oriented rods, rodstab states names its
    one-loop state the star) at kappa_n L = 2 pi / 3 (kappa_n R0 = 1), 8 elements, seeds only:
    the held straight line is an exact discrete equilibrium of energy 6 x (kappa_n L)^2 / 2; the
    star (stress-free there) and the daisy are found stable and labelled by their turning
    numbers along the ring (2 and 4: the backwards rods' turning counted with their sign)."""
    mu = 2 * math.pi / 3
    main(["discover", "examples/folded_six_ring.toml", "--load-factor", repr(mu),
          "--saddle-modes", "0", "--strings", "0", "--starts",
          "0", "--elements", "8", "--state", "line", "--json"])
    out = json.loads(capsys.readouterr().out)
    by = {s["label"]: s for s in out["states"]}
    assert {"line", "star", "daisy"} <= set(by)
    assert all(by[k]["stable"] for k in ("line", "star", "daisy"))
    assert by["line"]["energy"] == pytest.approx(3 * mu**2, rel=1e-9)
    assert by["star"]["energy"] < 1e-3 * by["line"]["energy"]
    assert by["daisy"]["invariants"]["turning_number"] == pytest.approx(4.0, abs=1e-6)
    assert out["structure"] == "examples/folded_six_ring.toml" and out["segments"] == 6


@pytest.mark.parametrize(("args", "name"), [
    (["examples/folded_six_ring.toml", "--structure", "six-ring"], "--structure"),
    (["examples/folded_six_ring.toml", "--nu", "0.3"], "--nu"),
    (["examples/birod.toml", "--state", "star"], "--state 'star' is a ring's"),
    (["--elements", "1"], "--elements"),
    (["--starts", "-1"], "--starts"),
    (["--load-factor", "nan"], "--load-factor"),
    (["--state", "nosuch"], "nosuch"),
    (["--structure", "six-ring", "--segments", "5"], "--segments"),
    (["--segments", "8"], "--segments"),
    (["--starts", "10", "--max-steps", "5"], "--starts"),
])
def test_bad_inputs_exit_2_naming_the_value(args, name, capsys):
    """Each bad input: exit status 2, one stderr line naming it."""
    with pytest.raises(SystemExit) as exc:
        main(["discover", *args])
    assert exc.value.code == 2
    err = capsys.readouterr().err
    assert name in err and err.count("\n") == 1


def _turned_folded_ring(angle: float) -> tuple[dv.DiscreteRod, dv.DiscreteRod]:
    """The folded six-ring (straight held rods: unstrained), and a copy whose edge frames are
    turned in the chart about their normals d3 by ``angle sin(2 pi e / n + 1)`` (edge e of n)."""
    from rodstab.problems import folded_ring

    p = folded_ring.Params(section=rectangle(aspect=4.0))
    rod = dv.common_rod(folded_ring.build(p), 8, p.theta)
    ne = len(rod.R_edge)
    dq = np.zeros(rod.n_dof)
    dq[rod.edge_dofs(np.arange(ne))[:, 2]] = angle * np.sin(2 * math.pi * np.arange(ne) / ne + 1)
    turned = rod.copy()
    turned.apply(dq)
    return rod, turned


@pytest.mark.parametrize("angle", [0.1, 0.3, 1.0])
def test_restore_inextensible_removes_the_strain_restore_positions_leaves(angle):
    """Turning frames in the chart opens the ring's closure (sum l_e d2_e != 0) at second order:
    positions alone cannot take up that misfit, least turns of the frames can (an unstrained
    state exists: the turned frames' shape with its closure gap shared out). Strain before:
    restore_positions only; after: restore_inextensible, to Gauss-Newton's quadratic accuracy."""
    _, turned = _turned_folded_ring(angle)
    only_positions = turned.copy()
    constraint.restore_positions(only_positions)
    constraint.restore_inextensible(turned)
    assert solve.max_strain(only_positions) > 1e-5
    assert solve.max_strain(turned) < 1e-8
    assert turned.energy() < only_positions.energy()


@pytest.mark.parametrize("angle", [0.1, 1.0])
def test_retraction_banded_dense_and_sparse_solves_agree(angle, monkeypatch):
    """The retraction solves its reduced system banded when its bandwidth in the reverse
    Cuthill-McKee order is small (a ring: 5 coordinates here), else dense up to
    constraint.DENSE_MAX unknowns and sparse above: all are direct solves of one SPD system,
    so the retracted states agree to round-off times its condition number (~1/INEXTENSIBLE_REG
    times the graph Laplacian's, a few hundred here): measured 6e-11 of the ring's size at 1
    rad (dense against sparse); bound 1e-9."""
    _, turned = _turned_folded_ring(angle)
    assert 3 * len(turned.x) < constraint.DENSE_MAX  # the dense path, when not banded
    constraint._TOPOLOGIES.clear()
    band = constraint._topology(turned).band
    assert band is not None and band[1] <= 8  # the default takes the banded path here
    banded, dense, sparse = turned.copy(), turned.copy(), turned.copy()
    constraint.restore_inextensible(banded)
    constraint._TOPOLOGIES.clear()
    monkeypatch.setattr(constraint, "BANDED_FRACTION", -1.0)
    constraint.restore_inextensible(dense)
    constraint._TOPOLOGIES.clear()
    monkeypatch.setattr(constraint, "DENSE_MAX", 0)
    constraint.restore_inextensible(sparse)
    constraint._TOPOLOGIES.clear()
    size = np.ptp(turned.x, axis=0).max()
    for other in (dense, sparse):
        assert np.abs(banded.x - other.x).max() < 1e-9 * size
        assert np.abs(banded.R_edge - other.R_edge).max() < 1e-9
        assert solve.max_strain(other) < 1e-8
    assert solve.max_strain(banded) < 1e-8


def test_the_retraction_cache_gives_the_cold_results_and_follows_the_supports():
    """The per-mesh cache (constraint._topology) is arithmetic the cold path does too: the
    same state retracted with a warm and an emptied cache is bit for bit the same; a support
    added in place (the same list object) is not served from the old entry."""
    _, turned = _turned_folded_ring(0.3)
    warm, cold = turned.copy(), turned.copy()
    constraint.restore_inextensible(warm)  # builds (or reuses) the entry
    constraint.restore_inextensible(turned.copy())
    constraint._TOPOLOGIES.clear()
    constraint.restore_inextensible(cold)
    assert np.array_equal(warm.x, cold.x) and np.array_equal(warm.R_edge, cold.R_edge)
    entry = constraint._topology(warm)
    free_node = next(k for k in range(len(warm.x)) if not entry.held[k].any())
    warm.fixed_components.append((free_node, [2]))
    try:
        assert constraint._topology(warm) is not entry
        assert constraint._topology(warm).held[free_node, 2]
    finally:
        warm.fixed_components.pop()


def test_restore_inextensible_leaves_an_unstrained_state_where_it_is():
    """The held folded ring is exactly inextensible (straight rods, rest length = chord)."""
    rod, _ = _turned_folded_ring(0.0)
    moved = rod.copy()
    constraint.restore_inextensible(moved)
    assert solve.max_strain(rod) < 1e-14
    assert moved.x == pytest.approx(rod.x, abs=1e-12)
    assert moved.R_edge == pytest.approx(rod.R_edge, abs=1e-12)


def test_the_retraction_eliminating_the_turns_takes_the_full_gauss_newton_step():
    """restore_inextensible solves for the node moves with the frame turns eliminated edge by
    edge (a Schur complement). Reference: one Gauss-Newton step of the whole least-squares
    problem over node moves and turns, assembled here from its definition (misfit r_e = x_j -
    x_i - l_e d2_e, weights K_e / l_e, Tikhonov INEXTENSIBLE_REG K_e l_e on the turns) and
    solved by numpy's lstsq; one iteration of each from the same state agree to 1e-9."""
    from rodstab.nonlinear.jets import hat, rodrigues

    _, turned = _turned_folded_ring(0.3)
    ref, ours = turned.copy(), turned.copy()
    constraint.restore_positions(ref)
    rod = ref
    w = rod.stretch_stiffness(per_length=True)
    le = rod.rest_length
    i, j = rod.edge_nodes[:, 0], rod.edge_nodes[:, 1]
    held = constraint._held_components(rod)
    col = np.full(held.shape, -1)
    col[~held] = np.arange(int((~held).sum()))
    nx, ne = int((~held).sum()), len(le)
    J = np.zeros((3 * ne + 3 * ne, nx + 3 * ne))
    d2 = rod.R_edge[:, :, 1]
    for e in range(ne):
        for c in range(3):
            if col[j[e], c] >= 0:
                J[3 * e + c, col[j[e], c]] += 1.0
            if col[i[e], c] >= 0:
                J[3 * e + c, col[i[e], c]] -= 1.0
        J[3 * e:3 * e + 3, nx + 3 * e:nx + 3 * e + 3] = le[e] * hat(d2[e])
        J[3 * ne + 3 * e:3 * ne + 3 * e + 3, nx + 3 * e:nx + 3 * e + 3] = np.eye(3)
    misfit = (rod.x[j] - rod.x[i] - le[:, None] * d2).ravel()
    sw = np.concatenate([np.repeat(np.sqrt(w), 3),
                         np.repeat(np.sqrt(constraint.INEXTENSIBLE_REG * w * le**2), 3)])
    z = np.linalg.lstsq(sw[:, None] * J, -sw * np.concatenate([misfit, np.zeros(3 * ne)]),
                        rcond=None)[0]
    ref.x[~held] += z[:nx]
    ref.R_edge = rodrigues(z[nx:].reshape(-1, 3)) @ ref.R_edge
    constraint.restore_positions(ref)
    monkey = constraint.INEXTENSIBLE_ITER
    try:
        constraint.INEXTENSIBLE_ITER = 1
        constraint.restore_inextensible(ours)
    finally:
        constraint.INEXTENSIBLE_ITER = monkey
    size = np.ptp(turned.x, axis=0).max()
    assert np.abs(ours.x - ref.x).max() < 1e-9 * size
    assert np.abs(ours.R_edge - ref.R_edge).max() < 1e-9


def test_a_design_that_is_no_ring_is_seeded_with_its_held_state(capsys):
    """The bi-rod of Section 4 (examples/birod.toml) below its buckling load (2.7207): its held
    straight state is found, stable, named after its seed, with the energy of two straight rods
    of natural curvature +-mu: 2 x B3 mu^2 L / 2 = 4 at mu = 2 (B3 = L = 1)."""
    main(["discover", "examples/birod.toml", "--load-factor", "2", "--elements", "8",
          "--saddle-modes", "0", "--strings", "0", "--starts", "0", "--json"])
    out = json.loads(capsys.readouterr().out)
    held = out["states"][0]
    assert held["label"] == "held" and held["stable"] and held["found_from"] == "seed held"
    assert held["energy"] == pytest.approx(4.0, rel=1e-9)


def test_deflated_newton_follows_the_birods_buckled_state_a_small_load_step():
    """From the bi-rod's buckled state relaxed at mu = 2.8 (8 el.), Newton at 2.81: the first
    step turns frames by 0.1 rad along the soft mode; brought back by moving the nodes
    (restore_positions) the merit rose 250x and deflated Newton stalled at residual 2e-3 for
    80 iterations, so the diagram could not follow the branch. Retracted (frames onto their
    edges) it converges in a few steps, to the equilibrium plain Newton finds."""
    from rodstab.io.design import load_design
    from rodstab.nonlinear.newton import newton
    from rodstab.nonlinear.solve import lowest_modes, relax

    a = load_design("examples/birod.toml").assembly
    rod = dv.common_rod(a, 8, 2.8)
    held = idf.Snapshot.of(rod)
    _, v = lowest_modes(rod, 1)
    dv.moved_along(rod, held, v[:, 0], 0.01)
    assert relax(rod)[0]
    start = idf.Snapshot.of(rod)
    rod.load_factor = 2.81
    run = dv.deflated_newton(rod, [])
    assert run.converged and run.iterations <= 10
    E = rod.energy()
    start.put(rod)
    assert newton(rod)[0] and rod.energy() == pytest.approx(E, rel=1e-10)


@pytest.mark.slow
def test_birods_held_state_past_buckling_is_the_saddle_between_the_buckled_mirrors(capsys):
    """The bi-rod at mu = 3 (past 2.7207): the held straight state (energy mu^2 = 9, closed
    form) is an index-1 equilibrium found by deflation; the climbs from the buckled state do
    not reach it, the saddle search judges it anyway (search_saddles' known): its two
    descents end on the buckled state and its mirror image (one state modulo reflection), over
    a barrier 9 - E(buckled)."""
    main(["discover", "examples/birod.toml", "--load-factor", "3", "--elements", "8",
          "--saddle-modes", "1", "--json"])
    out = json.loads(capsys.readouterr().out)
    held = next(s for s in out["states"] if s["label"] == "held")
    assert held["energy"] == pytest.approx(9.0, rel=1e-9) and held["index"] == 1
    buckled = out["states"][0]
    assert buckled["stable"] and not buckled["invariants"]["planar"]
    (saddle,) = out["saddle_search"]["saddles"]
    assert saddle["joins"] == ["#1", "#1"]
    assert saddle["barriers"][0] == pytest.approx(9.0 - buckled["energy"], rel=1e-9)
    assert saddle["found_from"] == "deflation: #2 held"
