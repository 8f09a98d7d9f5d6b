"""Adversarial review tests for the continuation features (independent reviewer).

Each test states the expected behaviour; a failing test is a finding. References are closed
forms or independent code paths, never the continuation's own output.

Closed forms used:
* straight rod, clamped + sliding-clamp, natural curvature 1: critical load factor of the held
  state from :func:`rodstab.nonlinear.solve.critical_load_factor` (independent root finder).
* small in-plane end rotation ``th`` of a straight rod (clamped + sliding-clamp, B3 = L = 1):
  linear beam ``w(0)=w'(0)=w(L)=0, w'(L)=th`` gives ``E = 2 B3 th^2 / L``.
* uniform twist ``phi`` of a straight isotropic rod below Greenhill's load: ``E = B2 phi^2 /
  (2 L)`` (up to the O(h^2) discrete measure).
"""

from __future__ import annotations

import json
import math
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

from rodstab.errors import NotConverged, RodstabInputError
from rodstab.io.design import parse_design
from rodstab.io.vary import set_design_value
from rodstab.model import Assembly, Segment
from rodstab.nonlinear.continuation import (
    arclength_from_bifurcation,
    continuation,
    imperfection_sensitivity,
)
from rodstab.nonlinear.continuation import run as P
from rodstab.nonlinear.parameters import parameter
from rodstab.nonlinear.solve import critical_load_factor, equilibrium
from rodstab.sections import circle

ROOT = Path(__file__).resolve().parent.parent
C = circle()
TWISTED_TOML = ROOT / "examples" / "twisted_rod.toml"


def straight(kappa_n: float = 1.0, end: str = "sliding-clamp", rot=()) -> Assembly:
    return Assembly(segments=(Segment(name="rod", length=1.0, curvature=0.0,
                                      natural_curvature=kappa_n, B1=C.b1, B2=C.b2, B3=1.0),),
                    supports=(("rod", "start", "clamped"), ("rod", "end", end)),
                    end_rotations=rot)


STRAIGHT_TOML = """
[section]
shape = "circle"
[[segment]]
name = "rod"
length = 1.0
natural_curvature = 1.0
[[support]]
end = "rod.start"
type = "clamped"
[[support]]
end = "rod.end"
type = "{end}"
[analysis]
elements = 8
"""


@pytest.fixture()
def straight_toml(tmp_path):
    p = tmp_path / "straight.toml"
    p.write_text(STRAIGHT_TOML.format(end="sliding-clamp"))
    return p


def one_line_error(r, needle: str) -> None:
    assert r.exit_code == 2, (r.exit_code, r.stderr)
    lines = [ln for ln in r.stderr.splitlines() if ln.strip()]
    assert "Traceback" not in r.stderr, r.stderr
    assert len(lines) == 1, r.stderr
    assert needle in lines[0], lines[0]


# ------------------------------------------------------------------ 1. input validation (CLI)
@pytest.mark.parametrize("vary, needle", [
    ("load_factor=nan:2", "nan"),
    ("load_factor=1:inf", "inf"),
    ("load_factor=2:2", "2"),
    ("load_factor=1:2:0", "0"),
    ("load_factor=1:2:-3", "-3"),
    ("load_factor=1:2:2.5", "2.5"),
    ("load_factor=1:2:3:4", "3:4"),
    ("=1:2", "''"),
    ("foo=1:2", "foo"),
    ("segment.nope.natural_curvature=0:1", "nope"),
    ("segment.rod.B3=1:2", "B3"),  # (a segment's length can be continued since session 35)
    ("segment.nope.length=1:2", "nope"),
    ("support.-1.rotation.tangent=0:1", "-1"),
    ("support.5.rotation.tangent=0:1", "5"),
    ("support.x.rotation.tangent=0:1", "x"),
    ("support.1.rotation.spin=0:1", "spin"),
    ("support.0.rotation=0:1", "support.0.rotation"),
    # overflow: |stop - start| = inf; must still be ONE line
    ("load_factor=1e308:-1e308", "1e+308"),
])
def test_cli_continue_bad_vary_one_line_exit_2(run_cli, straight_toml, vary, needle):
    r = run_cli(["continue", str(straight_toml), "--vary", vary, "--no-progress", "--elements",
                 "6", "--branch-steps", "0"])
    one_line_error(r, needle)


@pytest.mark.parametrize("opt, needle", [
    (("--elements", "-3"), "-3"), (("--elements", "0"), "0"), (("--elements", "1"), "1"),
    (("--branch-steps", "-1"), "-1")])
def test_cli_continue_bad_options(run_cli, straight_toml, opt, needle):
    r = run_cli(["continue", str(straight_toml), "--vary", "load_factor=1:2:2", "--no-progress",
                 *opt])
    one_line_error(r, needle)


def test_cli_continue_rotation_on_pinned_support(run_cli, tmp_path):
    p = tmp_path / "pinned.toml"
    p.write_text(STRAIGHT_TOML.format(end="pinned"))
    r = run_cli(["continue", str(p), "--vary", "support.1.rotation.tangent=0:1", "--no-progress"])
    one_line_error(r, "pinned")


BASE = {"segment": [{"name": "r", "length": 1.0}],
        "support": [{"end": "r.start"}, {"end": "r.end", "rotation": [0.0, 0.5, 0.0]}]}


def _with_rotation(rot, typ="clamped"):
    return {**BASE, "support": [{"end": "r.start"},
                                {"end": "r.end", "type": typ, "rotation": rot}]}


@pytest.mark.parametrize("rot", [[0, 0], [0, 0, 0, 0], ["0", 0, 0], 0.5, [[0], 0, 0],
                                 [math.nan, 0, 0], [math.inf, 0, 0]])
def test_design_rotation_rejects_bad_lists(rot):
    with pytest.raises(RodstabInputError):
        parse_design(_with_rotation(rot))


@pytest.mark.parametrize("rot", [[True, 0, 0], [0, False, 1]])
def test_design_rotation_rejects_bools(rot):
    """A bool is not an angle: TOML ``rotation = [true, 0, 0]`` must not become 1 rad."""
    with pytest.raises(RodstabInputError, match="rotation"):
        parse_design(_with_rotation(rot))


def test_set_design_value_bool_rotation_is_rejected():
    with pytest.raises(RodstabInputError):
        parse_design(set_design_value(BASE, "support.1.rotation.normal", True))


@pytest.mark.parametrize("typ", ["pinned", "fork", "free"])
def test_design_rotation_on_non_clamp(typ):
    with pytest.raises(RodstabInputError, match="clamped or sliding-clamp"):
        parse_design(_with_rotation([0, 0.1, 0], typ))


def test_design_two_conflicting_rotations_on_one_end_are_rejected():
    """Two [[support]] tables on the same end with different rotations: silently the last wins."""
    data = {**BASE, "support": [{"end": "r.start"}, {"end": "r.end", "rotation": [0, 0.1, 0]},
                                {"end": "r.end", "rotation": [0, 0.3, 0]}]}
    with pytest.raises(RodstabInputError):
        parse_design(data)


@pytest.mark.parametrize("key, needle", [
    ("support.-1.rotation.tangent", "-1"), ("support.5.rotation.tangent", "5"),
    ("support.0.rotation.twist", "twist"), ("segment.q.natural_twist", "q"),
    ("segment.r.B3", "B3"), ("segment.q.length", "q"), ("", "''"),
    ("load_factor.x", "load_factor.x")])
def test_api_parameter_bad_keys(key, needle):
    a = parse_design(BASE).assembly
    with pytest.raises(RodstabInputError, match=None) as ei:
        parameter(a, key, 6)
    assert needle in str(ei.value)


@pytest.mark.parametrize("n", [1, 0, -3, 2.5, True])
def test_api_continuation_bad_elements_raise_input_error(n):
    a = parse_design(BASE).assembly
    with pytest.raises(RodstabInputError, match=repr(n)):
        continuation(a, "load_factor", 1, 2, 2, elements_per_segment=n, branch_steps=0)


@pytest.mark.parametrize("n", [0, -2, 2.5])
def test_api_continuation_bad_n_steps_raise_input_error(n):
    a = parse_design(BASE).assembly
    with pytest.raises(RodstabInputError):
        continuation(a, "load_factor", 1, 2, n, elements_per_segment=6, branch_steps=0)


def test_api_continuation_negative_branch_steps():
    a = parse_design(BASE).assembly
    with pytest.raises(RodstabInputError, match="-1"):
        continuation(a, "load_factor", 1, 2, 2, elements_per_segment=6, branch_steps=-1)


@pytest.mark.parametrize("start", ["1", None, True])
def test_api_continuation_non_number_start(start):
    a = parse_design(BASE).assembly
    with pytest.raises(RodstabInputError):
        continuation(a, "load_factor", start, 2, 2, elements_per_segment=6, branch_steps=0)


@pytest.mark.parametrize("start, stop", [(math.nan, 1), (0, math.inf), (1, 1)])
def test_api_continuation_nonfinite_or_equal(start, stop):
    a = parse_design(BASE).assembly
    with pytest.raises(RodstabInputError):
        continuation(a, "load_factor", start, stop, 2, elements_per_segment=6)


# ------------------------------------------------------------------ 2. resumability
KEY, A, B, N = "support.1.rotation.tangent", 0.0, 13.0, 26
KW = dict(elements_per_segment=12, branch_steps=2)


@pytest.fixture(scope="module")
def twisted():
    from rodstab.io.design import load_design
    return load_design(TWISTED_TOML).assembly


@pytest.fixture(scope="module")
def full_run(twisted):
    return continuation(twisted, KEY, A, B, N, **KW)


class Killed(BaseException):
    pass


def _interrupted(twisted, d, after):
    cnt = [0]

    def prog():
        cnt[0] += 1
        if cnt[0] == after:
            raise Killed()
    with pytest.raises(Killed):
        continuation(twisted, KEY, A, B, N, out_dir=d, progress=prog, **KW)


def _sp(c):
    return [(s["kind"], round(s["value"], 9)) for s in c.special_points]


@pytest.mark.parametrize("after", [5, 20, 24])
@pytest.mark.slow
def test_resume_after_interruption_matches_uninterrupted(twisted, full_run, tmp_path, after):
    _interrupted(twisted, tmp_path, after)
    r = continuation(twisted, KEY, A, B, N, out_dir=tmp_path, **KW)
    assert r.resumed_steps >= after - 1
    assert _sp(r) == _sp(full_run)
    assert np.allclose(r.value, full_run.value)


#: Rows of primary.csv (start point included) after which the SIGKILL test kills the run: the
#: uninterrupted path has 27 rows and its branch point at row 23, so the kill lands well inside
#: the path and before the special point (the resumed run must find it and trace its branch).
KILL_AT_ROWS = 3


def _csv_data_rows(path: Path) -> int:
    """Complete data rows of primary.csv (0 if absent; files are replaced atomically)."""
    try:
        return max(path.read_bytes().count(b"\n") - 1, 0)
    except FileNotFoundError:
        return 0


@pytest.mark.slow
def test_resume_after_sigkill_mid_path_cli(run_cli, tmp_path):
    """``rodstab continue --out`` killed by SIGKILL in the middle of its primary path, then rerun.

    The kill is sent once primary.csv shows KILL_AT_ROWS rows, and where it landed is read
    back from what the killed run left (state.npz, the single source of a resume, and
    primary.csv): strictly inside the path. The rerun takes over the dead run's lock, resumes
    exactly the saved rows (``resumed_steps``; their values are the saved ones, not
    recomputed) and ends equal to an uninterrupted run: every row of primary.csv, and the
    special point with its branch."""
    args = ["continue", str(TWISTED_TOML), "--vary", f"{KEY}=0:13:26", "--elements", "12",
            "--branch-steps", "2", "--no-progress", "--no-pictures", "--json"]
    ref_dir = tmp_path / "full"
    r = run_cli([*args, "--out", str(ref_dir)])
    assert r.exit_code == 0, r.stderr
    full = json.loads(r.stdout)
    n_full = len(full["value"])
    assert n_full > KILL_AT_ROWS + 5 and full["resumed_steps"] == 0

    d = tmp_path / "k"
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(
        [str(ROOT / "src")] + ([os.environ["PYTHONPATH"]] if os.environ.get("PYTHONPATH")
                               else [])))
    proc = subprocess.Popen([sys.executable, "-m", "rodstab.cli", *args, "--out", str(d)],
                            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, env=env)
    try:
        deadline = time.monotonic() + 300  # imports and 3 steps; minutes only when starved
        while proc.poll() is None and time.monotonic() < deadline:
            if _csv_data_rows(d / "primary.csv") >= KILL_AT_ROWS:
                break
            time.sleep(0.005)
        assert proc.poll() is None, "the run ended (or the wait timed out) before the kill"
    finally:
        proc.send_signal(signal.SIGKILL)
        proc.wait(timeout=60)
    assert proc.returncode == -signal.SIGKILL

    # Where the kill landed: the state holds k rows (the CSV k, or k - 1 if the kill fell
    # between saving the state and exporting the CSV), strictly inside the path.
    with np.load(d / "state.npz") as st:
        saved = st["rows"]
    k = len(saved)
    assert KILL_AT_ROWS <= k < n_full - 1, (k, n_full)
    assert _csv_data_rows(d / "primary.csv") in (k - 1, k)
    first_special = full["special_points"][0]["value"]
    assert saved[-1, 0] < first_special  # before the branch point: the rerun must find it

    r = run_cli([*args, "--out", str(d)])
    assert r.exit_code == 0, r.stderr
    assert "stale lock" in r.stderr
    resumed = json.loads(r.stdout)
    assert resumed["resumed_steps"] == k
    assert resumed["value"][:k] == saved[:, 0].tolist()  # the saved rows, not recomputed
    # Equal to the uninterrupted run: the rerun continues from the saved state and stepper
    # (tangent, step size), so the steps after the kill are the same computations (measured:
    # equal bit for bit; asserted to 1e-9, which a BLAS of another summation order keeps).
    assert len(resumed["value"]) == n_full
    for col in ("value", "energy", "lowest_eigenvalue"):
        assert resumed[col] == pytest.approx(full[col], rel=1e-9, abs=1e-12), col
    kinds = [[s["kind"] for s in p["special_points"]] for p in (resumed, full)]
    assert kinds[0] == kinds[1] and kinds[0]
    assert [s["value"] for s in resumed["special_points"]] == pytest.approx(
        [s["value"] for s in full["special_points"]], rel=1e-9)
    assert [s.get("post_buckling") for s in resumed["special_points"]] == \
        [s.get("post_buckling") for s in full["special_points"]]
    assert (d / "primary.csv").read_text().splitlines()[0] == \
        (ref_dir / "primary.csv").read_text().splitlines()[0]
    got = np.loadtxt(d / "primary.csv", delimiter=",", skiprows=1, usecols=(0, 1, 2, 3))
    want = np.loadtxt(ref_dir / "primary.csv", delimiter=",", skiprows=1, usecols=(0, 1, 2, 3))
    assert got.shape == want.shape == (n_full, 4)
    assert np.allclose(got, want, rtol=1e-9, atol=1e-12)


def test_resume_after_deleting_last_csv_rows_loses_no_more_than_a_step(twisted, full_run,
                                                                       tmp_path):
    """Delete the last 4 rows of an interrupted run: the rerun must continue from the CSV's last
    row (or refuse), not silently leave a 4-step gap (state.npz is ahead of the CSV)."""
    _interrupted(twisted, tmp_path, 15)
    lines = (tmp_path / "primary.csv").read_text().splitlines()
    (tmp_path / "primary.csv").write_text("\n".join(lines[:-4]) + "\n")
    r = continuation(twisted, KEY, A, B, N, out_dir=tmp_path, **KW)
    assert np.max(np.diff(r.value)) <= 1.5 * np.max(np.diff(full_run.value)), r.value


def test_resume_kill_between_csv_append_and_special_points_write(twisted, full_run, tmp_path,
                                                                 monkeypatch):
    """A kill after the state (the single source of a resume) is saved but before the CSV/JSON
    exports are written must not lose the special point: the resumed run reports it."""
    import rodstab.nonlinear.continuation.storage as P

    orig = P.export

    def export(out, rows, specials):
        if specials:
            raise Killed()
        return orig(out, rows, specials)
    monkeypatch.setattr(P, "export", export)
    with pytest.raises(Killed):
        continuation(twisted, KEY, A, B, N, out_dir=tmp_path, **KW)
    monkeypatch.setattr(P, "export", orig)
    r = continuation(twisted, KEY, A, B, N, out_dir=tmp_path, **KW)
    assert _sp(r) == _sp(full_run)
    assert json.loads((tmp_path / "special_points.json").read_text())

def test_resume_with_truncated_last_csv_line_is_not_a_traceback(run_cli, tmp_path):
    args = ["continue", str(TWISTED_TOML), "--vary", f"{KEY}=0:5:5", "--elements", "8",
            "--branch-steps", "0", "--no-progress", "--no-pictures", "--out", str(tmp_path)]
    assert run_cli(args).exit_code == 0
    t = (tmp_path / "primary.csv").read_text()
    (tmp_path / "primary.csv").write_text(t[:-25])  # a kill in the middle of the append
    r = run_cli(args)
    assert "Traceback" not in r.stderr, r.stderr
    assert r.exit_code in (0, 2)


@pytest.mark.slow
def test_rerun_with_another_design_into_same_dir_does_not_mix(run_cli, tmp_path):
    other = tmp_path / "tw_nu0.toml"
    other.write_text(TWISTED_TOML.read_text().replace("nu = 0.3", "nu = 0.0"))
    d = tmp_path / "out"
    common = ["--vary", f"{KEY}=0:13:10", "--elements", "6", "--branch-steps", "0",
              "--no-progress", "--no-pictures", "--json"]
    run_cli(["continue", str(TWISTED_TOML), *common, "--out", str(d)])
    fresh = json.loads(run_cli(["continue", str(other), *common]).stdout)
    mixed = json.loads(run_cli(["continue", str(other), *common, "--out", str(d)]).stdout)
    assert mixed["resumed_steps"] == 0
    assert mixed["special_points"][0]["value"] == pytest.approx(
        fresh["special_points"][0]["value"])


@pytest.mark.slow
def test_rerun_with_other_branch_steps_into_same_dir_does_not_mix(run_cli, tmp_path):
    common = ["continue", str(TWISTED_TOML), "--vary", f"{KEY}=0:13:10", "--elements", "6",
              "--no-progress", "--no-pictures", "--json", "--out", str(tmp_path)]
    run_cli([*common, "--branch-steps", "2"])
    p = json.loads(run_cli([*common, "--branch-steps", "0"]).stdout)
    assert all("post_buckling" not in s for s in p["special_points"]), p["special_points"]


@pytest.mark.slow
def test_rerun_into_same_dir_leaves_no_stale_animation(run_cli, tmp_path):
    base = ["continue", str(TWISTED_TOML), "--elements", "12", "--branch-steps", "2",
            "--no-progress", "--json", "--out", str(tmp_path)]
    run_cli([*base, "--vary", f"{KEY}=0:13:26"])
    assert (tmp_path / "branch.gif").exists()
    p = json.loads(run_cli([*base, "--vary", f"{KEY}=0:5:10"]).stdout)
    assert "animation" not in p
    assert not (tmp_path / "branch.gif").exists(), "branch.gif of the previous run is left"
    assert (tmp_path / "diagram.png").exists()
    # --no-pictures draws none and leaves none of an earlier run's; the tables are written
    p = json.loads(run_cli([*base, "--vary", f"{KEY}=0:5:10", "--no-pictures"]).stdout)
    assert not {"diagram", "animation", "interactive"} & set(p)
    assert not (tmp_path / "diagram.png").exists(), "diagram.png of the previous run is left"
    assert (tmp_path / "primary.csv").exists()


# ------------------------------------------------------------------ 3. physics sanity
@pytest.mark.parametrize("n", [8, 12])
@pytest.mark.slow
def test_load_factor_critical_matches_held_state_root_finder_both_directions(n):
    a = straight()
    held = critical_load_factor(a, 1.0, 8.0, elements_per_segment=n).load_factor_critical
    up = continuation(a, "load_factor", 1, 8, 14, elements_per_segment=n, branch_steps=0)
    down = continuation(a, "load_factor", 8, 1, 14, elements_per_segment=n, branch_steps=0)
    neg = continuation(a, "load_factor", 1, -8, 18, elements_per_segment=n, branch_steps=0)
    assert [s["kind"] for s in up.special_points] == ["branch point (stability lost)"]
    assert [s["kind"] for s in down.special_points] == ["branch point (stability regained)"]
    assert up.special_points[0]["value"] == pytest.approx(held, rel=1e-6)
    assert down.special_points[0]["value"] == pytest.approx(held, rel=1e-6)
    assert neg.special_points[0]["value"] == pytest.approx(-held, rel=1e-6)


@pytest.mark.parametrize("start, stop", [(1, 8), (8, 1)])
def test_natural_curvature_key_matches_load_factor(start, stop):
    a = straight()
    held = critical_load_factor(a, 1.0, 8.0, elements_per_segment=10).load_factor_critical
    c = continuation(a, "segment.rod.natural_curvature", start, stop, 14,
                     elements_per_segment=10, branch_steps=0)
    assert c.special_points[0]["value"] == pytest.approx(held, rel=1e-6)


@pytest.mark.parametrize("th", [0.02, 0.1])
def test_small_binormal_end_rotation_is_in_plane_stable_and_matches_beam_energy(th):
    vals = []
    for n in (10, 20):
        r, rod = equilibrium(straight(0.0, rot=(("rod", "end", (0, 0, th)),)), load_factor=1.0,
                             elements_per_segment=n, perturb=1e-3)
        assert r.converged and r.stable
        assert np.max(np.abs(rod.x[:, 2])) < 1e-8
        vals.append(r.energy / (2 * th * th))
    assert abs(vals[1] - 1) < 0.01 and abs(vals[1] - 1) < abs(vals[0] - 1)


def test_binormal_continuation_stays_stable_for_small_angles():
    c = continuation(straight(0.0), "support.1.rotation.binormal", 0, 0.3, 6,
                     elements_per_segment=10, branch_steps=0)
    assert c.converged and not c.special_points and min(c.lowest_eigenvalue) > 0


def test_continuation_does_not_report_beyond_stop():
    """The last step overshoots STOP (0:0.3:1 ends at 0.495); a special point beyond STOP is
    reported (the Greenhill point at 11.32 for STOP = 11.3)."""
    c = continuation(straight(0.0), "support.1.rotation.binormal", 0, 0.3, 1,
                     elements_per_segment=10, branch_steps=0)
    assert c.value[-1] <= 0.3 * (1 + 1e-9), c.value
    from rodstab.io.design import load_design
    a = load_design(TWISTED_TOML).assembly
    c = continuation(a, KEY, 0, 11.3, 2, elements_per_segment=12, branch_steps=0)
    assert all(s["value"] <= 11.3 for s in c.special_points), c.special_points


def test_full_turn_by_continuation_is_not_zero():
    c = continuation(straight(0.0), KEY, 0, 2 * math.pi, 8, elements_per_segment=10,
                     branch_steps=0)
    twist = 0.5 * C.b2 * c.value[-1] ** 2
    assert c.energy[-1] == pytest.approx(twist, rel=0.1)


@pytest.mark.parametrize("r", [4.0, 2 * math.pi])
def test_design_end_rotation_beyond_pi_is_not_wrapped(r):
    """A design ``rotation = [0, r, 0]`` (twist r, below Greenhill's 11.98 rad): the rod must
    be twisted by r, energy B2 r^2 / 2 (the continuation of 0 -> r gives that); the held
    state + Newton silently gives the twist r - 2 pi (and 2 pi == 0)."""
    a = straight(0.0, rot=(("rod", "end", (0, r, 0)),))
    res, _ = equilibrium(a, load_factor=1.0, elements_per_segment=10)
    assert res.energy == pytest.approx(0.5 * C.b2 * r * r, rel=0.1)
    c = continuation(a, KEY, r, r + 0.1, 2, elements_per_segment=10, branch_steps=0)
    assert c.energy[0] == pytest.approx(0.5 * C.b2 * r * r, rel=0.1)


def test_ramp_to_start_failure_is_not_silently_replaced_by_a_jump(monkeypatch):
    """continuation() reaches START from the design's value in steps; when a step's Newton
    fails it breaks out and jumps straight to START (the end value, not the path, then
    decides). Observed: binormal START = 7 or 30 rad jump after the ramp fails at 4 rad; the
    30-rad state has LESS energy (14.3) than the 7-rad one (30.0)."""
    calls = []
    orig = P.newton

    def nw(rod, *a, **k):
        r = orig(rod, *a, **k)
        calls.append(r[0])
        return r
    monkeypatch.setattr(P, "newton", nw)
    try:
        continuation(straight(0.0), "support.1.rotation.binormal", 30.0, 31.0, 1,
                     elements_per_segment=6, branch_steps=0)
    except (RodstabInputError, NotConverged):
        return  # refusing is fine
    assert all(calls), f"a ramp Newton failed ({calls}) yet a result at START was returned"


def test_path_that_runs_out_of_steps_is_not_reported_complete():
    """0 -> 12 rad in-plane: the step budget (8 x N) ends at 3.11 rad with converged=True."""
    c = continuation(straight(0.0), "support.1.rotation.binormal", 0, 12, 6,
                     elements_per_segment=6, branch_steps=0)
    assert c.value[-1] >= 12 or not c.converged, (c.value[-1], c.converged)


# ------------------------------------------------------------------ 4. edge cases
def test_imperfection_sensitivity_without_loss_of_stability_is_a_clear_error():
    with pytest.raises(RodstabInputError, match="does not lose stability"):
        imperfection_sensitivity(straight(), "load_factor", 1, 3, elements_per_segment=8,
                                 n_steps=4)


@pytest.mark.parametrize("lo, hi", [(1, 3), (8, 9)])
def test_arclength_from_bifurcation_without_critical_is_clear(lo, hi):
    """No loss of stability in (lo, hi]: observed ValueError 'array must not contain infs or
    NaNs' from numpy (critical_load_factor's NaN fed into discretise)."""
    try:
        p = arclength_from_bifurcation(straight(), lo, hi, elements_per_segment=8, n_steps=3)
    except RodstabInputError as exc:
        assert "stab" in str(exc) or "critical" in str(exc)
        return
    assert all(math.isnan(v) for v in p.load_factor) or not p.converged


@pytest.mark.parametrize("eps", [(-1e-3, -2e-3), ()])
def test_imperfection_sensitivity_bad_epsilons(eps):
    """Negative amplitudes: LinAlgError (+ LAPACK spam) from log(negative); no amplitudes:
    verdict 'imperfection-insensitive' from no data."""
    a = straight(0.0)
    with pytest.raises(RodstabInputError):
        imperfection_sensitivity(a, KEY, 0, 13, elements_per_segment=8, n_steps=13,
                                 epsilons=eps)


@pytest.mark.slow
def test_imperfection_sensitivity_supercritical_is_not_reported_sensitive():
    """The straight rod's branch is stable symmetric (continuation says supercritical). With 7
    steps the imperfect paths jump to the complementary branch and report a 'loss of
    stability' at 5.686 for eps = 1e-3 and 2e-3; the fit gives exponent -0.012 and the verdict
    'imperfection-sensitive' (a negative exponent is self-contradictory)."""
    r = imperfection_sensitivity(straight(), "load_factor", 1, 8, elements_per_segment=8,
                                 n_steps=7, epsilons=(1e-3, 2e-3, 4e-3))
    assert not (r.exponent < 0), (r.limit_value, r.exponent, r.verdict)
    assert "imperfection-sensitive" not in r.verdict, r.verdict
