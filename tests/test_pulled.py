"""A path inside the contact model built by pulling (rodstab.multistable.pulled)."""

from __future__ import annotations

import json

import numpy as np
import pytest
from contact_checks import central_differences, judged_pairs, smallest_distance

from rodstab.errors import RodstabInputError
from rodstab.multistable.discover import common_rod
from rodstab.multistable.layered import lift, stacked_model
from rodstab.multistable.pulled import STAGES, PulledRod, pulled_path
from rodstab.multistable.string_method import to_gauge
from rodstab.nonlinear.contact import mesh_of_rod
from rodstab.nonlinear.equilibrium import rod_contact_model
from rodstab.nonlinear.newton import newton
from rodstab.problems.barrier_states import state_assembly
from rodstab.sections import rectangle

H = 0.02  # capsule diameter over the rod length


def _line_and_star(n: int = 6, order: tuple[int, int, int] = (0, 2, 1)):
    """The hexagram's line stacked in two staggered columns (layers ``order`` for rods 1, 3, 5
    and 2, 4, 6; shifts 0, 1, 1, 2, 2, 0) and the star lifted into its model, relaxed with
    contact (rectangle h/t = 4, kappa_n R0 = 1)."""
    sec = rectangle(aspect=4.0)
    a = state_assembly("hexagram", sec, "line")
    model = rod_contact_model(a, H)
    ra, rb = common_rod(a, n, 1.0), common_rod(state_assembly("hexagram", sec, "star"), n, 1.0)
    newton(ra)
    newton(rb)
    to_gauge(rb, ra)
    shifts = {"1": 0, "2": 1, "3": 1, "4": 2, "5": 2, "6": 0}
    lay = dict(zip("135", order, strict=True)) | dict(zip("246", order, strict=True))
    layers = {s: (-0.5 if int(s) % 2 else 0.5, lay[s], shifts[s]) for s in "123456"}
    stacked = stacked_model(ra, layers, model)
    line, star = lift(stacked, ra, ra), lift(stacked, ra, rb)
    for r in (line, star):
        r.contact = mesh_of_rod(r, model)
        assert newton(r)[0]
    return a, stacked, line, star


def test_the_springs_have_exact_derivatives():
    # The pulled rod's energy is the rod's plus (k/2)|x - target|^2: its gradient and Hessian
    # against differences of its own energy, at a state off the target (positions only).
    _, _, line, star = _line_and_star(4)
    r = PulledRod(**{k: getattr(line, k) for k in line.__dataclass_fields__
                     if line.__dataclass_fields__[k].init}, target=star.x.copy(), pull=3.0)
    r.contact = None  # the springs alone on top of the rod (contact has its own tests)
    plain = line.copy()
    plain.contact = None
    E0, g0, H0 = r.energy_terms()
    Ep, gp, Hp = plain.energy_terms()
    d = (r.x - star.x).ravel()
    assert E0 - Ep == pytest.approx(0.5 * 3.0 * d @ d, rel=1e-12)
    np.testing.assert_allclose((g0 - gp)[: d.size], 3.0 * d, rtol=1e-12, atol=1e-12)
    diff = (H0 - Hp).toarray()
    np.testing.assert_allclose(diff[: d.size, : d.size], 3.0 * np.eye(d.size), atol=1e-9)
    assert np.abs(diff[d.size:]).max() < 1e-9

    def energy(x):
        q = r.copy()
        q.x = x
        E, g, Hm = q.energy_terms()
        return E, g[: x.size], Hm

    gf, _ = central_differences(energy, r.x, 1e-6)
    np.testing.assert_allclose(gf, g0[: r.x.size], rtol=1e-5, atol=1e-5 * np.abs(g0).max())


def test_bad_input_is_refused_naming_it():
    _, _, line, star = _line_and_star(4)
    bare = line.copy()
    bare.contact = None
    with pytest.raises(RodstabInputError, match="start.contact is None"):
        pulled_path(bare, star)
    with pytest.raises(RodstabInputError, match="stages must be positive"):
        pulled_path(line, star, stages=(1.0, -2.0))
    with pytest.raises(RodstabInputError, match="tolerance"):
        pulled_path(line, star, tolerance=-1e-6)
    with pytest.raises(RodstabInputError, match="nodes"):
        pulled_path(line, common_rod(state_assembly("hexagram", rectangle(aspect=4.0),
                                                    "star"), 5, 1.0))


def test_an_early_release_ends_the_path_where_it_first_settles_on_the_end():
    """From a start inside the star's basin (the star with its nodes moved by a seeded 0.2 h at
    most, the gauge kept), each stage cut to two Newton steps so that the first stops short of
    the star (0.018 L away), the release after it settles on the star, so the path ends there:
    one stage run, released_after 0, the star reached, the release taking steps and descending
    (each state's energy at most the last's, to 1e-10 B3/L of round-off) and no higher than
    the path without early releases, which runs every stage first."""
    _, _, _, star = _line_and_star(4)
    start = star.copy()
    dq = np.zeros(start.n_dof)
    free = start.free_dofs()
    free = free[free < start.x.size]  # free node positions (the gauge stays: no rigid motion)
    dq[free] = np.random.default_rng(3).uniform(-1.0, 1.0, free.size)
    start.apply(0.2 * H * dq / np.abs(dq).max())
    start.energy()  # inside the model
    early = pulled_path(start, star, max_steps=2)
    full = pulled_path(start, star, early_release=False)
    assert early.reached and full.reached
    assert early.released_after == 0 and len(early.stages) == 1 and full.released_after == -1
    assert early.stages[0][1] is False and early.stages[0][3] > 1e-3  # the stage fell short
    assert len(full.stages) == len(STAGES) and len(early.states) < len(full.states)
    n0 = 1 + early.stages[0][2]  # start, then the stage's accepted states
    tail = np.array(early.energies[n0 - 1:])  # the stage's last state, then the release's
    assert len(tail) > 1 and np.all(np.diff(tail) <= 1e-10)
    assert early.highest_energy <= full.highest_energy
    assert early.to_dict()["released_after"] == 0


LAYERS_021 = "1=-0.5:0:0,2=0.5:0:1,3=-0.5:2:1,4=0.5:2:2,5=-0.5:1:2,6=0.5:1:0"
LAYERS_012 = "1=-0.5:0:0,2=0.5:0:1,3=-0.5:1:1,4=0.5:1:2,5=-0.5:2:2,6=0.5:2:0"
PULL = ["barrier", "--structure", "hexagram", "--shape", "rectangle", "--aspect", "4",
        "--from", "line", "--to", "star", "--load-factor", "1", "--elements", "6",
        "--method", "pull"]


def test_a_bound_is_drawn_as_a_bound_not_a_saddle():
    # barrier --method pull's figure: the highest point is marked as a bound, the arrows read
    # "<=" with the differences of the energies given; without bound=True, a saddle as before
    from rodstab.plot.plots import plot_barrier_path

    for bound, mark, prefix in ((True, "at most", "<= "), (False, "saddle (index 1)", "")):
        ax = plot_barrier_path([0.0, 0.4, 1.0], [1.0, 3.5, 0.25], 1, bound=bound).axes[0]
        assert any(mark in t.get_text() for t in ax.get_legend().get_texts())
        texts = [t.get_text() for t in ax.texts]
        assert any(t.startswith(f" {prefix}2.5 ") for t in texts), texts
        assert any(t.startswith(f" {prefix}3.25 ") for t in texts), texts


@pytest.mark.parametrize("extra, named", [
    ([], "contact off, --layers None"),
    (["--contact"], "--layers None"),
    (["--layers", LAYERS_021], "is a setting of contact, which is off"),
    (["--contact", "--layers", LAYERS_021, "--images", "5"], "--images"),
    (["--contact", "--layers", LAYERS_021, "--animation", "a.gif"], "--animation"),
    (["--contact", "--layers", LAYERS_021, "--workers", "2"], "--workers"),
    (["--contact", "--layers", LAYERS_021, "--into-contact"], "--into-contact"),
])
def test_pull_refuses_what_it_cannot_do_naming_it(run_cli, extra, named):
    # before any work: exit 2, the offending option named
    r = run_cli([*PULL, *extra])
    assert r.exit_code == 2, (r.stdout, r.stderr)
    assert named in r.stderr


@pytest.mark.slow
def test_an_lk2_order_is_blocked_before_the_pull(run_cli):
    # layers 0, 1, 2: the ribbon self-links -2 (session 27), the star 0: no path, said as the
    # string says it (the pull is not run)
    r = run_cli([*PULL, "--contact", "--layers", LAYERS_012, "--json"])
    assert r.exit_code == 0, r.stderr
    payload = json.loads(r.stdout)
    assert payload["blocked_by_contact"] and payload["barrier_forward"] is None
    assert "pull" not in payload


@pytest.mark.slow
def test_the_lk0_line_is_pulled_to_the_star_without_rods_crossing(run_cli, tmp_path):
    # Session 30: the line on layers 0, 2, 1 (Lk 0) and the star (Lk 0) are joined inside the
    # model; from the command line (session 31). Checked by what the pull does not use: the
    # ends against the line and the star built and relaxed here by hand, the written path's
    # smallest centreline distance sampled by the tests' own code (within the sampling's
    # bound of h), the bound against the energies printed.
    r = run_cli([*PULL, "--contact", "--layers", LAYERS_021, "--json", "--out", tmp_path,
                 "--plot", tmp_path / "pull.png"])
    assert r.exit_code == 0, r.stderr
    payload = json.loads(r.stdout)
    _, _, line, star = _line_and_star(6)
    assert payload["converged"] is True and payload["pull"]["reached"] is True
    assert (payload["from"], payload["to"]) == (payload["from_state"], payload["to_state"]) \
        == ("line", "star")
    assert payload["energy_from"] == pytest.approx(line.energy(), abs=1e-9)
    assert payload["energy_to"] == pytest.approx(star.energy(), abs=1e-9)
    assert payload["barrier_forward"] is None and payload["barrier_backward"] is None
    top = max(payload["pull"]["energies"])
    assert payload["upper_bound_forward"] == pytest.approx(top - line.energy(), abs=1e-9)
    assert payload["upper_bound_backward"] == pytest.approx(top - star.energy(), abs=1e-9)
    assert top > line.energy() > star.energy()
    assert payload["contact"]["pass_through"] is False
    assert payload["plot"] == str(tmp_path / "pull.png") and (tmp_path / "pull.png").stat().st_size
    assert {v["value"] for v in payload["contact"]["linking"].values()} == {0}
    z = np.load(tmp_path / "path.npz")
    xs, edges = z["x"], z["edges"]
    assert len(xs) == len(payload["pull"]["energies"]) and float(z["thickness"]) == H
    pairs = judged_pairs(edges, 6)
    spacing = np.linalg.norm(xs[:, edges[:, 1]] - xs[:, edges[:, 0]], axis=2).max() / 100
    closest = min(smallest_distance(x, edges, pairs) for x in xs[:: max(1, len(xs) // 60)])
    assert closest > H - spacing
    assert np.abs(xs[-1] - star.x).max() < 1e-6 and np.abs(xs[0] - line.x).max() < 1e-9
