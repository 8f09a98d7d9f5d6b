"""Issue 10, recoverable runs: output paths checked before any computation, a damaged or
foreign resume state set aside with one warning, one run at a time in a ``--out`` directory
(run.lock), ``continue --restart``, and sweeps that keep their finished rows.

Every refusal is exit 2 with one stderr line naming the option (or the running process) and
the path. The computations are replaced by functions that fail the test, so that "refused
before any computation" is asserted directly, not by timing.
"""

from __future__ import annotations

import csv
import json
import os
import socket
import subprocess
import sys
import threading
from pathlib import Path

import numpy as np
import pytest

import rodstab.linear.solve
import rodstab.nonlinear.continuation
import rodstab.nonlinear.solve
import rodstab.report.reproduce
import rodstab.sweep
from rodstab.errors import NotConverged, RodstabInputError, RodstabWarning
from rodstab.io import outputs
from rodstab.io.outputs import check_output

ROOT = Path(__file__).resolve().parent.parent
STRAIGHT = str(ROOT / "examples" / "straight_clamped_rod.toml")
IS_ROOT = hasattr(os, "geteuid") and os.geteuid() == 0

#: (--no-pictures: these tests are about the saved run; the pictures, ~0.5 s a run, are
#: tested in tests/test_paths.py)
CONTINUE = ["continue", STRAIGHT, "--vary", "load_factor=0:1:3", "--no-pictures", "--elements",
            "6", "--branch-steps", "0", "--no-progress", "--json"]

#: (option, is a directory, the command line before the path, the computation it calls)
OUTPUT_OPTIONS = [
    ("--plot", False, ["analyze", STRAIGHT, "--elements", "6", "--plot"],
     (rodstab.linear.solve, "linear_stability")),
    ("--render", False, ["equilibrium", STRAIGHT, "--elements", "6", "--render"],
     (rodstab.nonlinear.solve, "equilibrium")),
    ("--html", False, ["equilibrium", STRAIGHT, "--elements", "6", "--html"],
     (rodstab.nonlinear.solve, "equilibrium")),
    ("--out", True, [*CONTINUE, "--out"], (rodstab.nonlinear.continuation, "continuation")),
    ("--out", True, ["sweep", STRAIGHT, "--vary", "section.nu=0:0.3:3", "--elements", "6",
                     "--no-progress", "--out"], (rodstab.sweep, "sweep")),
    ("--out", True, ["reproduce", "--no-progress", "--out"],
     (rodstab.report.reproduce, "run_reproduction")),
]
OUTPUT_IDS = [f"{args[0]} {opt}" for opt, _, args, _ in OUTPUT_OPTIONS]


def _no_computation(monkeypatch, target) -> None:
    module, name = target

    def fail(*args, **kwargs):
        raise AssertionError(f"{name} was called: the output path was not checked first")
    monkeypatch.setattr(module, name, fail)


def _bad_path(kind: str, tmp_path: Path, is_dir: bool) -> str:
    """An output path of the given kind that cannot be written."""
    afile = tmp_path / "afile"
    afile.write_text("a regular file\n")
    name = "out" if is_dir else "picture.png"
    if kind == "under a regular file":
        return str(afile / "sub" / name)
    if kind == "the wrong kind" and is_dir:
        return str(afile)
    if kind == "the wrong kind":  # a file wanted, a directory given
        return str(tmp_path)
    if kind == "empty":
        return ""
    assert kind == "unwritable directory"
    if IS_ROOT:  # chmod does not stop root: use a path that cannot be written at all
        return str(afile / name)
    ro = tmp_path / "read-only"
    ro.mkdir()
    ro.chmod(0o555)
    return str(ro / "sub" / name)


@pytest.mark.parametrize("kind", ["under a regular file", "the wrong kind", "empty",
                                  "unwritable directory"])
@pytest.mark.parametrize("option, is_dir, args, target", OUTPUT_OPTIONS, ids=OUTPUT_IDS)
def test_unwritable_output_exits_2_naming_it_before_computing(run_cli, tmp_path, monkeypatch,
                                                             kind, option, is_dir, args,
                                                             target):
    _no_computation(monkeypatch, target)
    path = _bad_path(kind, tmp_path, is_dir)
    try:
        r = run_cli([*args, path], cwd=tmp_path)
    finally:
        if (tmp_path / "read-only").exists():
            (tmp_path / "read-only").chmod(0o755)
    assert r.exit_code == 2, r
    lines = r.stderr.splitlines()
    assert len(lines) == 1, r.stderr
    assert lines[0].startswith("rodstab: error: ")
    assert option in lines[0], lines[0]
    assert (repr(path) if path else "''") in lines[0] or path in lines[0], lines[0]
    assert r.stdout == ""
    assert sorted(p.name for p in tmp_path.iterdir()) in (["afile"],
                                                          ["afile", "read-only"])


@pytest.mark.parametrize("option, is_dir, args, target", OUTPUT_OPTIONS, ids=OUTPUT_IDS)
def test_missing_output_directory_is_created(run_cli, tmp_path, monkeypatch, option, is_dir,
                                             args, target):
    path = tmp_path / "new" / "deeper" / ("out" if is_dir else "picture.png")
    if args[0] == "reproduce":  # the directory must exist before the (long) reproduction
        def fake(out_dir, progress=True):
            assert Path(out_dir).is_dir()
            return {"report_md": "m", "report_html": "h", "results_json": "j", "n_claims": 0,
                    "n_reproduced": 0, "n_differs": 0}
        monkeypatch.setattr(rodstab.report.reproduce, "run_reproduction", fake)
    if option == "--html":
        pytest.importorskip("plotly")
    r = run_cli([*args, str(path)], cwd=tmp_path)
    assert r.exit_code == 0, r.stderr
    assert path.is_dir() if is_dir else path.is_file()


def test_plot_of_an_unknown_picture_type_exits_2(run_cli, tmp_path, monkeypatch):
    _no_computation(monkeypatch, (rodstab.linear.solve, "linear_stability"))
    r = run_cli(["analyze", STRAIGHT, "--plot", str(tmp_path / "mode.xyz")])
    assert r.exit_code == 2 and "--plot" in r.stderr and "'.xyz'" in r.stderr, r.stderr


def test_reproduce_under_a_file_exits_2_in_a_real_process(tmp_path, run_cli):
    (tmp_path / "afile").write_text("")
    r = run_cli(["reproduce", "--no-progress", "--out", str(tmp_path / "afile" / "r")],
                fresh_process=True, timeout=60)
    assert r.exit_code == 2 and len(r.stderr.splitlines()) == 1, r.stderr
    assert "--out" in r.stderr and "afile" in r.stderr


def test_check_output_returns_the_path_and_leaves_no_probe(tmp_path):
    p = check_output("--out", tmp_path / "a" / "b", directory=True)
    assert p == tmp_path / "a" / "b" and p.is_dir() and list(p.iterdir()) == []
    f = check_output("--plot", str(tmp_path / "c" / "x.png"), directory=False,
                     suffixes={".png"})
    assert f.parent.is_dir() and not f.exists() and list(f.parent.iterdir()) == []


# ------------------------------------------------------------------ continue: resume state

def _run(run_cli, out: Path, *extra: str):
    r = run_cli([*CONTINUE, "--out", str(out), *extra])
    return r, (json.loads(r.stdout) if r.exit_code == 0 else None)


def _truncated(path: Path) -> None:
    data = path.read_bytes()
    path.write_bytes(data[:len(data) // 2])


def _garbage(path: Path) -> None:
    path.write_bytes(np.random.default_rng(0).bytes(100))


def _foreign(path: Path) -> None:
    with path.open("wb") as fh:
        np.savez(fh, a=np.zeros(3), b=np.arange(4))


def _wrong_shapes(path: Path) -> None:
    with np.load(path) as st:
        arrays = {k: st[k] for k in st.files}
    arrays["x"] = arrays["x"][:3]
    with path.open("wb") as fh:
        np.savez(fh, **arrays)


def _empty(path: Path) -> None:
    path.write_bytes(b"")


@pytest.mark.parametrize("damage, needle", [
    (_garbage, "not an npz"), (_truncated, "cannot be read"), (_foreign, "not a rodstab run"),
    (_wrong_shapes, "shape"), (_empty, "not an npz")],
    ids=["100 bytes of garbage", "truncated", "foreign npz", "wrong shapes", "empty"])
def test_unusable_state_is_set_aside_with_one_warning(run_cli, tmp_path, damage, needle):
    out = tmp_path / "c"
    r, first = _run(run_cli, out)
    assert r.exit_code == 0, r.stderr
    damage(out / "state.npz")
    r, again = _run(run_cli, out)
    assert r.exit_code == 0, r.stderr
    lines = r.stderr.splitlines()
    assert len(lines) == 1, r.stderr
    assert lines[0].startswith("rodstab: warning: ")
    assert "state.npz" in lines[0] and needle in lines[0] and "corrupt-1" in lines[0]
    assert "starting afresh" in lines[0]
    assert again["resumed_steps"] == 0
    assert again["value"] == pytest.approx(first["value"])
    assert (out / "state.npz.corrupt-1").exists() and (out / "state.npz").exists()
    r, third = _run(run_cli, out)  # the new state is good: resumed, no warning
    assert r.exit_code == 0 and r.stderr == "" and third["resumed_steps"] == len(first["value"])


def test_second_set_aside_keeps_the_first(run_cli, tmp_path):
    out = tmp_path / "c"
    out.mkdir()
    _garbage(out / "state.npz")
    assert _run(run_cli, out)[0].exit_code == 0
    _garbage(out / "state.npz")
    r, _ = _run(run_cli, out)
    assert "corrupt-2" in r.stderr
    assert (out / "state.npz.corrupt-1").exists() and (out / "state.npz.corrupt-2").exists()


def test_state_of_other_arguments_is_replaced_silently(run_cli, tmp_path):
    out = tmp_path / "c"
    assert _run(run_cli, out)[0].exit_code == 0
    r = run_cli([*CONTINUE[:-4], "--elements", "8", "--branch-steps", "0", "--no-progress",
                 "--json", "--out", str(out)])
    assert r.exit_code == 0 and r.stderr == ""
    assert json.loads(r.stdout)["resumed_steps"] == 0
    assert not list(out.glob("*corrupt*"))


def test_restart_ignores_the_saved_run(run_cli, tmp_path):
    out = tmp_path / "c"
    _, first = _run(run_cli, out)
    r, resumed = _run(run_cli, out)
    assert resumed["resumed_steps"] == len(first["value"])
    r, fresh = _run(run_cli, out, "--restart")
    assert r.exit_code == 0 and r.stderr == ""
    assert fresh["resumed_steps"] == 0 and fresh["value"] == pytest.approx(first["value"])


def test_restart_without_out_exits_2(run_cli):
    r = run_cli([*CONTINUE, "--restart"])
    assert r.exit_code == 2 and "--restart" in r.stderr and "--out" in r.stderr


def test_library_restart_and_no_temporaries_left(tmp_path):
    from rodstab.io.design import load_design

    a = load_design(STRAIGHT).assembly
    kw = dict(elements_per_segment=6, branch_steps=0, out_dir=tmp_path)
    first = rodstab.nonlinear.continuation.continuation(a, "load_factor", 0, 1, 2, **kw)
    (tmp_path / ".state.npz.abc.tmp").write_text("left by a killed run")
    again = rodstab.nonlinear.continuation.continuation(a, "load_factor", 0, 1, 2, **kw,
                                                        restart=True)
    assert again.resumed_steps == 0 and first.value == pytest.approx(again.value)
    assert not list(tmp_path.glob(".*.tmp")) and not (tmp_path / outputs.LOCK).exists()


# ------------------------------------------------------------------- continue: the lock

def _lock(out: Path, pid: int, host: str | None = None) -> Path:
    out.mkdir(parents=True, exist_ok=True)
    lock = out / outputs.LOCK
    lock.write_text(json.dumps({"pid": pid, "host": host or socket.gethostname(),
                                "started": "2024-01-01T00:00:00+00:00"}))
    return lock


def _dead_pid() -> int:
    proc = subprocess.run([sys.executable, "-c", "import os; print(os.getpid())"],
                          capture_output=True, text=True, check=True)
    return int(proc.stdout)


@pytest.mark.parametrize("who", ["live process", "other host"])
def test_held_lock_exits_2_naming_the_running_process(run_cli, tmp_path, monkeypatch, who):
    _no_computation(monkeypatch, (rodstab.nonlinear.continuation, "continuation"))
    out = tmp_path / "c"
    pid = os.getpid() if who == "live process" else 1234567
    lock = _lock(out, pid, None if who == "live process" else "elsewhere.example")
    before = lock.read_text()
    r = run_cli([*CONTINUE, "--out", str(out)])
    assert r.exit_code == 2, r
    lines = r.stderr.splitlines()
    assert len(lines) == 1 and lines[0].startswith("rodstab: error: "), r.stderr
    assert f"process {pid}" in lines[0] and "--out" in lines[0] and str(out) in lines[0]
    if who == "other host":
        assert "elsewhere.example" in lines[0]
    assert lock.read_text() == before  # the other run's lock is left alone


@pytest.mark.parametrize("content, needle", [("stale", "stale lock of process"),
                                             ("not json", "unreadable lock")])
def test_stale_lock_is_taken_over_with_a_warning(run_cli, tmp_path, content, needle):
    out = tmp_path / "c"
    if content == "stale":
        pid = _dead_pid()
        _lock(out, pid)
        needle += f" {pid}"
    else:
        out.mkdir()
        (out / outputs.LOCK).write_text("{half a lock")
    r, p = _run(run_cli, out)
    assert r.exit_code == 0, r.stderr
    lines = r.stderr.splitlines()
    assert len(lines) == 1 and lines[0].startswith("rodstab: warning: "), r.stderr
    assert needle in lines[0] and "--out" in lines[0]
    assert len(p["value"]) == 4
    assert not (out / outputs.LOCK).exists()  # released at the end


def test_run_leaves_no_lock_and_lock_is_reentrant(run_cli, tmp_path):
    out = tmp_path / "c"
    assert _run(run_cli, out)[0].exit_code == 0
    assert not (out / outputs.LOCK).exists()
    with outputs.run_lock(out):
        held = (out / outputs.LOCK).read_text()
        assert json.loads(held)["pid"] == os.getpid()
        with outputs.run_lock(out):  # the CLI holds it while continuation() takes it again
            assert (out / outputs.LOCK).read_text() == held
        assert (out / outputs.LOCK).read_text() == held
    assert not (out / outputs.LOCK).exists()


def test_library_run_lock_refuses_a_live_holder(tmp_path):
    _lock(tmp_path, os.getpid())
    with pytest.raises(RodstabInputError, match=f"process {os.getpid()}"), \
            outputs.run_lock(tmp_path):
        pass
    _lock(tmp_path, _dead_pid())
    with pytest.warns(RodstabWarning, match="stale lock"), outputs.run_lock(tmp_path):
        pass


def test_concurrent_atomic_writes_do_not_collide(tmp_path):
    """Two writers of one file (as two runs once did) never fail on the rename."""
    errors: list[BaseException] = []

    def writer(tag: str) -> None:
        try:
            for i in range(200):
                outputs.write_atomic(tmp_path / "primary.csv", f"{tag} {i}\n")
        except BaseException as exc:  # pragma: no cover - the failure being tested
            errors.append(exc)

    threads = [threading.Thread(target=writer, args=(t,)) for t in "ab"]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert errors == []
    assert (tmp_path / "primary.csv").read_text().split()[1] == "199"
    assert [p.name for p in tmp_path.iterdir()] == ["primary.csv"]


# ---------------------------------------------------------------------------- sweeps

def _third_solve_raises(monkeypatch, failure: BaseException) -> None:
    calls = []
    solve = rodstab.sweep.converged_stability

    def third_fails(*args, **kwargs):
        calls.append(1)
        if len(calls) == 3:
            raise failure
        return solve(*args, **kwargs)
    monkeypatch.setattr(rodstab.sweep, "converged_stability", third_fails)


def _sweep_rows(out: Path) -> list[dict[str, str]]:
    with (out / "sweep.csv").open() as fh:
        return list(csv.DictReader(fh))


def test_interrupted_sweep_keeps_its_finished_rows(run_cli, tmp_path, monkeypatch):
    _third_solve_raises(monkeypatch, KeyboardInterrupt())
    out = tmp_path / "s"
    r = run_cli(["sweep", STRAIGHT, "--vary", "section.nu=0:0.3:5", "--elements", "6",
                 "--no-progress", "--out", str(out)])
    assert r.exit_code == 130, r.stderr
    rows = _sweep_rows(out)
    assert [float(row["section.nu"]) for row in rows] == pytest.approx([0.0, 0.075])
    assert all(float(row["load_factor_critical"]) > 0 for row in rows)


def test_a_point_that_does_not_converge_is_recorded_and_the_sweep_goes_on(run_cli, tmp_path,
                                                                          monkeypatch):
    """Issue 13: a failing point records its status and error; the others are solved; exit 3
    after the table."""
    _third_solve_raises(monkeypatch, NotConverged("third point"))
    out = tmp_path / "s"
    r = run_cli(["sweep", STRAIGHT, "--vary", "section.nu=0:0.3:5", "--elements", "6",
                 "--no-progress", "--out", str(out)])
    assert r.exit_code == 3, r.stderr
    assert "1 of 5 points" in r.stderr and "0.15: third point" in r.stderr
    assert "not_converged" in r.stdout  # the table was printed first
    rows = _sweep_rows(out)
    assert [row["status"] for row in rows] == ["ok", "ok", "not_converged", "ok", "ok"]
    assert rows[2]["error"] == "third point" and rows[2]["load_factor_critical"] == ""
    assert all(float(row["load_factor_critical"]) > 0 for i, row in enumerate(rows) if i != 2)


def test_finished_sweep_csv_is_the_json_rows(run_cli, tmp_path):
    out = tmp_path / "s"
    r = run_cli(["sweep", STRAIGHT, "--vary", "section.nu=0:0.3:3", "--elements", "6",
                 "--no-progress", "--json", "--out", str(out)])
    assert r.exit_code == 0, r.stderr
    rows = _sweep_rows(out)
    assert [{k: v if k in ("status", "error") else float(v) for k, v in row.items()}
            for row in rows] == json.loads(r.stdout)["rows"]


def test_check_output_names_a_directory_it_cannot_write(tmp_path, monkeypatch):
    """The read-only case without chmod (ineffective for root): the write probe fails."""
    import rodstab.io.outputs

    def denied(*args, **kwargs):
        raise PermissionError(13, "Permission denied")
    monkeypatch.setattr(rodstab.io.outputs.tempfile, "mkstemp", denied)
    with pytest.raises(RodstabInputError, match=r"--out .*not writable \(Permission denied\)"):
        check_output("--out", tmp_path / "d", directory=True)
    monkeypatch.setattr(Path, "mkdir", denied)
    with pytest.raises(RodstabInputError, match=r"--plot .*cannot create the directory"):
        check_output("--plot", tmp_path / "e" / "x.png", directory=False)


def test_outputs_get_the_users_umask_not_mkstemps_0600(tmp_path, monkeypatch, run_cli):
    """An output written atomically is readable as a plain ``open`` would leave it (0o666 less
    the umask): mkstemp's 0600 hid a sweep's CSV from the user's group (issue 20)."""
    for mask in (0o022, 0o077):
        monkeypatch.setattr(outputs, "_UMASK", mask)
        outputs.write_atomic(tmp_path / f"m{mask:o}.csv", "x\n")
        assert (tmp_path / f"m{mask:o}.csv").stat().st_mode & 0o777 == 0o666 & ~mask
    monkeypatch.setattr(outputs, "_UMASK", 0o022)
    r = run_cli(["sweep", "examples/clamped_arc.toml", "--vary", "section.aspect=1:2:2",
                 "--elements", "8", "--out", str(tmp_path / "sw"), "--no-progress"])
    assert r.exit_code == 0, r.stderr
    assert (tmp_path / "sw" / "sweep.csv").stat().st_mode & 0o777 == 0o644
