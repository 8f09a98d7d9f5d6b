"""Issue 10: hostile inputs end in exit 2 (one stderr line naming the input) or exit 3 (not
converged, after the output) -- never a traceback, a hang or a silent success.

Each row is one class of the issue's catalogue with the example it listed; the resource rows
must be refused before any allocation (they would otherwise run for minutes or exhaust memory).
"""

from __future__ import annotations

import pytest

E = "examples/"

#: (argv, exit status, words the one stderr line must contain)
CASES = [
    # unbounded before: loops, segments, steps, points, elements
    (["ring", "--loops", "1000000000"], 2, ["loops 1000000000", "--max-steps"]),
    (["ring", "--loops", "99999999999999999999"], 2, ["--max-steps"]),
    (["michell", "--loops", "1000000000"], 2, ["loops 1000000000", "--max-steps"]),
    (["folded-ring", "--segments", "100000"], 2, ["unknowns", "--max-dof"]),
    (["continue", E + "birod.toml", "--vary", "load_factor=1:4:1000000000", "--no-progress"],
     2, ["--vary load_factor=1:4:1000000000", "--max-steps"]),
    (["sweep", E + "birod.toml", "--vary", "section.nu=0.1:0.3:1000000000", "--no-progress",
      "--out", "{tmp}/s"], 2, ["sweep points", "--max-steps"]),
    (["analyze", E + "birod.toml", "--elements", "100000000"], 2, ["100000000", "--max-dof"]),
    (["equilibrium", E + "birod.toml", "--elements", "100000000"], 2, ["100000000",
                                                                         "--max-dof"]),
    (["continue", E + "birod.toml", "--vary", "load_factor=0:1:2", "--elements", "100000000",
      "--no-progress"], 2, ["100000000", "--max-dof"]),
    (["analyze", E + "birod.toml", "--elements", "200000", "--max-memory", "1"], 2,
     ["GiB", "--max-memory"]),
    (["ring", "--loops", "5", "--max-steps", "13"], 2, ["14 Fourier modes", "--max-steps"]),
    (["analyze", E + "birod.toml", "--max-dof", "0"], 2, ["--max-dof", "0"]),
    (["analyze", E + "birod.toml", "--max-memory", "-1"], 2, ["--max-memory", "-1"]),
    # overflow and derived quantities, blamed on the input
    (["section", "--shape", "rectangle", "--aspect", "1e308"], 2, ["aspect", "1e+308"]),
    (["section", "--shape", "rectangle", "--aspect", "1e-300"], 2, ["aspect", "1e-300"]),
    (["section", "--b1", "1e308", "--b2", "1e308"], 2, ["b1", "1e+308"]),
    (["equilibrium", E + "birod.toml", "--load-factor", "1e300"], 2, ["load factor 1e+300"]),
    (["continue", E + "birod.toml", "--vary", "load_factor=0:1e300:3", "--no-progress"], 2,
     ["load factor 1e+300"]),
    (["equilibrium", E + "ring_3_loops.toml", "--elements", "3"], 2,
     ["elements per segment 3", "at least 8"]),
    # accepted silently before
    (["arc", "--L-over-R", "1e9"], 2, ["L_over_R", "1000000000.0"]),
    (["folded-ring", "--arc-angle", "720"], 2, ["arc_angle_deg", "720"]),
    (["folded-ring", "--arc-angle", "1e308"], 2, ["arc_angle_deg"]),
    (["folded-ring", "--arc-angle", "1e-320"], 2, ["arc_angle_deg"]),
    # found by benchmarks/fuzz.py
    (["arc", "--L-over-R", "1e-300"], 2, ["L_over_R", "1e-300", "straight limit"]),
    (["arc", "--L-over-R", "1e-14", "--shape", "ellipse"], 2, ["L_over_R", "1e-14"]),
    (["folded-ring", "--segments", "106638", "--max-dof", "20000"], 2,
     ["segments 106638", "--max-dof"]),
    (["folded-ring", "--segments", "1000000000000"], 2, ["segments 1000000000000",
                                                         "--max-dof"]),
    (["continue", E + "twisted_rod.toml", "--vary", "support.0.rotation.tangent=-1e308:1:4",
      "--elements", "4", "--no-progress"], 2, ["support.0.rotation.tangent", "-1e+308"]),
    (["continue", E + "twisted_rod.toml", "--vary",
      "support.0.rotation.tangent=0:3.0464138875641794e+289:1", "--elements", "4",
      "--no-progress"], 2, ["support.0.rotation.tangent", "3.04641e+289"]),
    (["continue", E + "twisted_rod.toml", "--vary", "segment.rod.natural_curvature=0:1e300:2",
      "--elements", "4", "--no-progress"], 2, ["segment.rod.natural_curvature", "1e+300"]),
    # issue 19 item 10: ran for minutes / had no --max-dof (the string's images are relaxed
    # together: 8 el./rod, six rods = 306 unknowns each, at most 500000 // 306 = 1633 images)
    (["barrier", "--images", "100000000"], 2, ["--images 100000000", "at most 1,633",
                                               "--max-dof"]),
    (["barrier", "--images", "17", "--max-dof", "1000"], 2, ["--images 17", "at most 3",
                                                             "--max-dof"]),
    (["barrier", "--method", "continuation", "--elements", "100000"], 2,
     ["--elements 100000", "--max-dof"]),
    (["transitions", "--elements", "100000"], 2, ["100000 elements per rod", "--max-dof"]),
    (["transitions", "--max-dof", "100"], 2, ["8 elements per rod", "306 unknowns",
                                              "--max-dof"]),
]


@pytest.mark.parametrize("argv, status, words", CASES,
                         ids=[" ".join(c[0][:4]) for c in CASES])
def test_hostile_input_gets_its_exit_status_and_one_line_naming_it(argv, status, words,
                                                                   run_cli, tmp_path):
    r = run_cli([a.replace("{tmp}", str(tmp_path)) for a in argv])
    assert r.exit_code == status, (r.exit_code, r.stderr[-2000:])
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("rodstab: "), r.stderr
    for w in words:
        assert w in lines[0], (w, lines[0])
    if status == 2:
        assert not r.stdout.strip()
    else:
        assert r.stdout.strip()  # the output is printed before the exit 3


def test_folded_ring_above_the_full_system_size_says_it_did_not_run_it(run_cli):
    """24 segments: the engine answers (lam_c = 2 pi / 24 within its mesh error) and the
    full system is reported as not run, in the table and as null in the JSON."""
    import json
    import math

    r = run_cli(["folded-ring", "--segments", "24", "--json"])
    assert r.exit_code == 0, r.stderr
    d = json.loads(r.stdout)
    assert d["lambda_c_full_system"] is None and d["multiplicity_full_system"] is None
    assert d["lambda_c"] == pytest.approx(2 * math.pi / 24, rel=1e-6)
    assert "full system not run" in run_cli(["folded-ring", "--segments", "24"]).stdout


def test_a_design_without_natural_curvature_on_the_sparse_path_is_stable_everywhere(run_cli):
    """Found by benchmarks/fuzz.py: >= 400 unknowns and no natural curvature (C = 0) raised
    ARPACK's "Starting vector is zero"; now the whole line, as the dense path says."""
    import json

    r = run_cli(["analyze", E + "twisted_rod.toml", "--elements", "257", "--json"])
    assert r.exit_code == 0, r.stderr
    d = json.loads(r.stdout)
    assert d["n_dof"] >= 400 and d["load_factor_interval"] == [None, None]  # infinite
    small = json.loads(run_cli(["analyze", E + "twisted_rod.toml", "--elements", "8",
                                "--json"]).stdout)
    assert small["n_dof"] < 400 and small["load_factor_interval"] == [None, None]


def test_not_converged_eigen_solve_exits_3_after_its_output(run_cli, monkeypatch):
    """Exit 3 with the table printed first when the FE eigen solve misses its residual test.

    Provoked by a residual tolerance of 0: since the (beta, omega) formulation no example
    mesh up to the unknown limit misses it (residual 2.4e-7 at 10^6 unknowns; it was 2048
    elements of the straight rod under the earlier formulation in w).
    """
    import rodstab.numerics.eigen

    monkeypatch.setattr(rodstab.numerics.eigen, "SPARSE_RESIDUAL_TOL", 0.0)
    r = run_cli(["analyze", E + "straight_clamped_rod.toml", "--elements", "128"])
    assert r.exit_code == 3, (r.exit_code, r.stderr[-2000:])
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("rodstab: ")
    assert "residual" in lines[0] and "fewer elements" in lines[0]
    assert r.stdout.strip()


def test_atlas_respects_the_lock_of_a_running_continue(run_cli, tmp_path):
    """Issue 19 item 10: atlas --out wrote into a folder a running `continue` had locked; now
    it takes the same run.lock (rodstab.io.outputs.run_lock) and exits 2 naming the folder and
    the lock, leaving the other run's lock alone."""
    import json
    import os
    import socket

    out = tmp_path / "busy"
    out.mkdir()
    lock = out / "run.lock"
    lock.write_text(json.dumps({"pid": os.getpid(), "host": socket.gethostname(),
                                "started": "2024-01-01T00:00:00+00:00"}))
    before = lock.read_text()
    r = run_cli(["atlas", E + "unfolded_six_ring.toml", "--vary", "section.aspect=1:2:3",
                 "--out", str(out), "--no-progress"])
    assert r.exit_code == 2, (r.exit_code, r.stderr[-2000:])
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("rodstab: error: "), r.stderr
    for w in ("--out", str(out), "in use by another rodstab run", str(lock)):
        assert w in lines[0], (w, lines[0])
    assert lock.read_text() == before and sorted(p.name for p in out.iterdir()) == ["run.lock"]
