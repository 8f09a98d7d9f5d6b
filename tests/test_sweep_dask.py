"""Issue 13 (part 4): design sweeps on dask.distributed, streamed tables, kill and resume.

Oracles: the serial sweep (the same function in this process) for every number computed on
the workers, bit for bit; the sweep's own design-validation errors for failing points; the
files a killed run leaves, read back by the rerun.

The cluster is a real 2-worker ``LocalCluster`` of processes (``processes=True``, as
``--workers 2`` starts it, through :func:`rodstab.executor.open_executor`): threads would not
test that the tasks and their arguments pickle, nor the workers' environment. It is started
once for the module (~2 s); the kill-and-resume test starts its own, in the killed process.
"""

from __future__ import annotations

import csv
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

import rodstab
import rodstab.executor
import rodstab.sweep
from rodstab.errors import RodstabInputError
from rodstab.executor import WORKER_ENV, auto_workers, open_executor, task_size
from rodstab.io.design import load_design, parse_design
from rodstab.io.vary import set_design_value
from rodstab.sweep import INVALID, OK, SweepRow, columns, sweep

ROOT = Path(__file__).resolve().parent.parent
ARC = ROOT / "examples" / "clamped_arc.toml"
KEY = "section.aspect"
#: Every column but the wall-clock time of a point's solve.
NUMBERS = [c for c in columns(KEY) if c != "seconds"]


@pytest.fixture(name="client", scope="module")
def _client():
    with open_executor(2) as ex:  # the --workers 2 cluster
        yield ex.client


def _same(a: SweepRow, b: SweepRow) -> bool:
    """Rows equal in every column but ``seconds`` (NaN equal to NaN)."""
    ra, rb = a.record(KEY), b.record(KEY)
    return all(ra[c] == rb[c] or (isinstance(ra[c], float) and math.isnan(ra[c])
                                   and math.isnan(rb[c])) for c in NUMBERS)


def _csv_rows(path: Path) -> list[dict[str, str]]:
    with path.open() as fh:
        return list(csv.DictReader(fh))


# ------------------------------------------------------------------------- on the cluster

def test_local_cluster_workers_are_processes_with_one_blas_thread(client):
    """Fair speed-up and no oversubscription: every worker process runs one BLAS/OpenMP
    thread (rodstab.executor.WORKER_ENV) in a process other than this one."""
    env = client.run(lambda: {k: os.environ.get(k) for k in WORKER_ENV} | {"pid": os.getpid()})
    assert len(env) == 2
    for found in env.values():
        assert found.pop("pid") != os.getpid()
        assert found == WORKER_ENV


def test_dask_sweep_gives_the_serial_numbers_bit_for_bit(client):
    """Same function, same inputs: every column but the timing is identical, whatever the
    grouping of points into tasks (one task of 5 points, or 5 tasks)."""
    d = load_design(ARC)
    values = np.linspace(1.0, 6.0, 5)
    serial = sweep(d, KEY, values, workers=0)
    assert serial.executor == "serial"
    for per_task in (1, 5):
        on_dask = sweep(d, KEY, values, client=client, points_per_task=per_task)
        assert on_dask.executor.startswith("dask client tcp://")
        assert [r.index for r in on_dask.rows] == list(range(5))
        assert all(_same(a, b) for a, b in zip(serial.rows, on_dask.rows, strict=True))
        assert all(r.status == OK for r in on_dask.rows)
    # --scheduler: the same code on an existing cluster, reached by its address.
    remote = sweep(d, KEY, values, scheduler=client.scheduler.address)
    assert remote.executor == f"scheduler {client.scheduler.address}"
    assert all(_same(a, b) for a, b in zip(serial.rows, remote.rows, strict=True))


def test_workers_with_another_rodstab_are_refused(client, monkeypatch):
    """Numbers from another version of the code would be mixed into the table: refused,
    naming a worker and both versions."""
    monkeypatch.setattr(rodstab.executor, "__version__", "9.9.9")
    with pytest.raises(RodstabInputError, match=r"--scheduler: worker tcp://\S+ has rodstab "
                                                r"\S+, this is rodstab 9\.9\.9 \(2 of 2"):
        sweep(load_design(ARC), KEY, [1.0], scheduler=client.scheduler.address)


def test_a_failing_point_is_recorded_and_the_sweep_goes_on(client):
    """analysis.elements = 8, 10.67, 13.33, 16: the two values that are not integers are
    invalid designs (set_design_value's error, naming the value); the others are solved."""
    df = rodstab.sweep(ARC, vary={"analysis.elements": "8:16:4"}, client=client)
    assert list(df["status"]) == [OK, INVALID, INVALID, OK]
    for i in (1, 2):
        assert "takes integer values" in df["error"][i]
        assert repr(float(df["analysis.elements"][i])) in df["error"][i]
        assert math.isnan(df["load_factor_critical"][i]) and df["multiplicity"].isna()[i]
    assert (df["load_factor_critical"][[0, 3]] > 0).all() and list(df["error"][[0, 3]]) == ["", ""]


def test_python_api_returns_a_dataframe_one_row_per_point(client):
    """rodstab.sweep(design, vary={...}, client=...) -> DataFrame with the table's columns,
    also after `import rodstab.sweep` (the module is callable: its import would replace a
    function of that name in rodstab/__init__)."""
    import pandas as pd

    df = rodstab.sweep(load_design(ARC), vary={KEY: [1.0, 2.0, 3.0]}, client=client)
    assert isinstance(df, pd.DataFrame)
    assert list(df.columns) == list(columns(KEY)) and len(df) == 3
    assert list(df[KEY]) == [1.0, 2.0, 3.0] and list(df["index"]) == [0, 1, 2]
    assert str(df["multiplicity"].dtype) == "Int64" and df.attrs["key"] == KEY
    assert df.attrs["executor"].startswith("dask client")
    single = sweep(load_design(ARC), KEY, [2.0], workers=0).rows[0]
    assert df["load_factor_critical"][1] == single.load_factor_critical


def test_atlas_grid_on_the_cluster_gives_the_serial_atlas(client):
    """rodstab atlas uses the same executor, one grid value per point: every interval, mode,
    mutual set and coexistence range equal to the serial atlas (the ring is built on the
    workers by a closure, pickled by value)."""
    from rodstab.multistable.atlas import ring_atlas
    from rodstab.multistable.states import ring_of
    from rodstab.sweep import design_at

    base = load_design(ROOT / "examples" / "hexagram.toml")

    def ring_at(aspect: float):
        return ring_of(design_at(base, KEY, aspect).assembly)

    grid = [3.0, 3.5, 4.0]
    serial = ring_atlas(ring_at, grid, ("line", "star"), key=KEY, workers=0)
    on_dask = ring_atlas(ring_at, grid, ("line", "star"), key=KEY, client=client)
    assert serial.executor == "serial" and on_dask.executor.startswith("dask client")
    assert {k: v for k, v in on_dask.to_dict().items() if k != "executor"} == \
        {k: v for k, v in serial.to_dict().items() if k != "executor"}
    assert len(on_dask.intervals) == 3 and on_dask.coexistence


# ------------------------------------------------------------- kill a running sweep, resume

@pytest.mark.slow
def test_killed_sweep_on_2_workers_keeps_its_rows_and_a_rerun_resumes(run_cli, tmp_path):
    """The issue's done-when: a sweep on a 2-worker LocalCluster is killed (SIGKILL to its
    process group: the command, the scheduler in it and both workers) after some rows; the
    table it leaves is readable; the rerun takes over the stale lock, solves only the missing
    points, and the finished table has every point once, in order, equal to a serial run."""
    n = 40
    out = tmp_path / "s"
    args = ["sweep", str(ARC), "--vary", f"{KEY}=1:6:{n}", "--out", str(out), "--no-progress",
            "--points-per-task", "2"]
    proc = subprocess.Popen([sys.executable, "-m", "rodstab.cli", *args, "--workers", "2"],
                            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                            start_new_session=True)  # its own process group, workers included
    table = out / "sweep.csv"
    try:
        deadline = time.monotonic() + 60
        while time.monotonic() < deadline and proc.poll() is None:
            if table.exists() and table.read_bytes().count(b"\n") >= 1 + 6:
                break
            time.sleep(0.02)
        assert proc.poll() is None, "the sweep ended before it could be killed"
    finally:
        os.killpg(proc.pid, signal.SIGKILL)
        proc.wait(timeout=30)
    gone = time.monotonic() + 10  # every process of the group (the workers too) is gone
    while time.monotonic() < gone:
        try:
            os.killpg(proc.pid, 0)
        except ProcessLookupError:
            break
        time.sleep(0.05)
    else:
        pytest.fail("processes of the killed sweep are still running")
    data = table.read_bytes()  # a last line without its newline was cut: the rerun drops it
    left = list(csv.DictReader(data[:data.rfind(b"\n") + 1].decode().splitlines()))
    assert 6 <= len(left) < n
    assert all(row["status"] == OK and float(row["load_factor_critical"]) > 0 for row in left)

    r = run_cli([*args, "--workers", "2", "--json"])
    assert r.exit_code == 0, r.stderr
    assert "took over a stale lock" in r.stderr
    payload = json.loads(r.stdout)
    assert len(left) <= payload["resumed"] < n and payload["executor"] == "LocalCluster(2 workers)"
    rows = _csv_rows(table)
    assert [int(row["index"]) for row in rows] == list(range(n))  # all, once each, in order
    reference = sweep(load_design(ARC), KEY, np.linspace(1, 6, n), workers=0)
    assert [{c: row[c] for c in NUMBERS} for row in rows] == \
        [{c: row[c] for c in NUMBERS} for row in _csv_rows_of(reference.rows)]


def _csv_rows_of(rows) -> list[dict[str, str]]:
    """The rows as sweep.csv writes them (strings)."""
    from rodstab.sweep import _csv_lines

    text = _csv_lines(KEY, rows, header=True)
    return list(csv.DictReader(text.splitlines()))


# ----------------------------------------------------------------- the table in --out (serial)

def _count_solves(monkeypatch) -> list[float]:
    calls: list[float] = []
    solve = rodstab.sweep.converged_stability

    def counted(*args, **kwargs):
        calls.append(1.0)
        return solve(*args, **kwargs)
    monkeypatch.setattr(rodstab.sweep, "converged_stability", counted)
    return calls


def test_rerun_solves_only_missing_points_and_drops_a_cut_last_line(tmp_path, monkeypatch):
    d = load_design(ARC)
    values = [1.0, 1.5, 2.0, 2.5, 3.0]
    first = sweep(d, KEY, values, workers=0, out=tmp_path)
    table = tmp_path / "sweep.csv"
    lines = table.read_text().splitlines(keepends=True)
    # As a kill leaves it: rows in completion order, the last one cut mid-number.
    table.write_text(lines[0] + lines[4] + lines[1] + lines[2][:17])
    calls = _count_solves(monkeypatch)
    again = sweep(d, KEY, values, workers=0, out=tmp_path)
    assert len(calls) == 3 and again.resumed == 2  # points 0 and 3 were kept
    assert all(_same(a, b) for a, b in zip(first.rows, again.rows, strict=True))
    rows = _csv_rows(table)
    assert [int(r["index"]) for r in rows] == [0, 1, 2, 3, 4]
    assert [float(r[KEY]) for r in rows] == values  # repr floats read back exactly


@pytest.mark.parametrize("change, needle", [
    ({"values": [1.0, 2.0, 3.0, 4.0]},
     "it has 3 values from 1.0 to 3.0 of section.aspect, this run 4 values from 1.0 to 4.0"),
    ({"values": [1.0, 2.5, 3.0]}, "its value 1 of section.aspect is 2.0, this run's 2.5"),
    ({"key": "section.nu", "values": [0.1, 0.2, 0.3]},
     "it varies 'section.aspect', this run 'section.nu'"),
    ({"elements": 8}, "its --elements is the design's own, this run's 8"),
    ({"design": "nu"}, "the design differs: section.nu is new"),
])
@pytest.mark.slow
def test_rerun_of_another_sweep_is_refused_naming_the_difference(tmp_path, monkeypatch,
                                                                  change, needle):
    d = load_design(ARC)
    sweep(d, KEY, [1.0, 2.0, 3.0], workers=0, out=tmp_path)
    before = (tmp_path / "sweep.csv").read_text()
    other = parse_design(set_design_value(d.raw, "section.nu", 0.25)) \
        if change.get("design") else d
    calls = _count_solves(monkeypatch)
    kwargs = {"elements": change.get("elements"), "workers": 0, "out": tmp_path}
    with pytest.raises(RodstabInputError, match="--restart") as info:
        sweep(other, change.get("key", KEY), change.get("values", [1.0, 2.0, 3.0]), **kwargs)
    assert needle in str(info.value) and "holds another sweep" in str(info.value)
    assert calls == [] and (tmp_path / "sweep.csv").read_text() == before  # nothing touched
    fresh = sweep(other, change.get("key", KEY), change.get("values", [1.0, 2.0, 3.0]),
                  restart=True, **kwargs)
    assert fresh.resumed == 0 and len(_csv_rows(tmp_path / "sweep.csv")) == len(fresh.rows)


def test_a_table_that_is_not_this_sweeps_is_refused(tmp_path):
    d = load_design(ARC)
    (tmp_path / "sweep.csv").write_text("section.aspect,load_factor_critical\n1,2\n")
    with pytest.raises(RodstabInputError, match=r"has a sweep\.csv but no run\.json"):
        sweep(d, KEY, [1.0, 2.0], workers=0, out=tmp_path)
    sweep(d, KEY, [1.0, 2.0], workers=0, out=tmp_path, restart=True)
    table = tmp_path / "sweep.csv"
    lines = table.read_text().splitlines(keepends=True)
    table.write_text(lines[0] + lines[1].replace(",ok,", ",fine,") + lines[2])
    with pytest.raises(RodstabInputError, match=r"line 2 of .*status 'fine'"):
        sweep(d, KEY, [1.0, 2.0], workers=0, out=tmp_path)


# --------------------------------------------------------------------------- the command

def test_cli_interior_points_invalid_prints_the_table_then_exits_2(run_cli, tmp_path):
    r = run_cli(["sweep", str(ARC), "--vary", "analysis.elements=8:16:4", "--workers", "0",
                 "--no-progress", "--out", str(tmp_path)])
    assert r.exit_code == 2
    assert r.stdout.count("invalid: --vary key 'analysis.elements' takes integer values") == 2
    (line,) = r.stderr.splitlines()
    assert "invalid at 2 of 4 values (10.6667, 13.3333)" in line and "sweep.csv" in line
    assert [row["status"] for row in _csv_rows(tmp_path / "sweep.csv")] == \
        [OK, INVALID, INVALID, OK]


def test_cli_parquet_is_the_csv_table(run_cli, tmp_path):
    import pandas as pd

    r = run_cli(["sweep", str(ARC), "--vary", f"{KEY}=1:2:3", "--workers", "0", "--parquet",
                 "--no-progress", "--json", "--out", str(tmp_path)])
    assert r.exit_code == 0, r.stderr
    pq = pd.read_parquet(json.loads(r.stdout)["parquet"])
    table = pd.read_csv(tmp_path / "sweep.csv", keep_default_na=False)
    assert list(pq.columns) == list(columns(KEY))
    for c in columns(KEY):
        assert list(pq[c]) == list(table[c]), c


@pytest.mark.parametrize("args, needle", [
    (["--workers", "-1"], "--workers must be an integer from 0 (serial) to"),
    (["--workers", "2", "--scheduler", "tcp://127.0.0.1:8786"], "--workers and --scheduler"),
    (["--points-per-task", "0"], "--points-per-task must be a positive integer, got 0"),
    (["--scheduler", ""], "--scheduler must be an address"),
    (["--scheduler", "tcp://127.0.0.1:9"], "--scheduler 'tcp://127.0.0.1:9': cannot use it"),
])
def test_cli_where_to_run_bad_input_exits_2_naming_it(run_cli, tmp_path, monkeypatch, args,
                                                      needle):
    monkeypatch.setattr(rodstab.executor, "CONNECT_TIMEOUT", 1.0)
    calls = _count_solves(monkeypatch)
    r = run_cli(["sweep", str(ARC), "--vary", f"{KEY}=1:2:3", "--no-progress", "--out",
                 str(tmp_path / "s"), *args])
    assert r.exit_code == 2 and r.stdout == ""
    (line,) = r.stderr.splitlines()
    assert needle in line, line
    assert calls == []


def test_cli_workers_without_dask_exits_2_and_the_default_runs_serially(run_cli, tmp_path,
                                                                        monkeypatch):
    monkeypatch.setattr(rodstab.executor, "distributed_installed", lambda: False)
    r = run_cli(["sweep", str(ARC), "--vary", f"{KEY}=1:2:3", "--workers", "2",
                 "--no-progress", "--out", str(tmp_path)])
    assert r.exit_code == 2 and 'pip install "rodstab[distributed]"' in r.stderr
    assert "--workers 2 needs dask.distributed" in r.stderr
    r = run_cli(["sweep", str(ARC), "--vary", f"{KEY}=1:2:3", "--no-progress", "--json",
                 "--out", str(tmp_path)])
    assert r.exit_code == 0, r.stderr
    assert json.loads(r.stdout)["executor"] == \
        'serial (default: dask.distributed is not installed (pip install "rodstab[distributed]"' \
        ' for --workers N))'


@pytest.mark.slow
def test_help_closed_form_and_serial_sweep_import_no_dask_pandas_or_pyarrow(tmp_path):
    """The optional dependencies are imported only where used: not by --help, a closed-form
    command, `import rodstab`, nor a serial sweep (which needs none of them)."""
    code = ("import sys\nfrom rodstab.cli import main\nfor argv in {argvs!r}:\n"
            "    try:\n        main(argv)\n    except SystemExit:\n        pass\n"
            "print('OPTIONAL', sorted({{m.split('.')[0] for m in sys.modules}} & "
            "{{'dask', 'distributed', 'pandas', 'pyarrow'}}))")
    argvs = [["--help"], ["sweep", "--help"], ["section", "--json"],
             ["sweep", str(ARC), "--vary", f"{KEY}=1:2:2", "--workers", "0", "--no-progress",
              "--out", str(tmp_path)]]
    r = subprocess.run([sys.executable, "-c", code.format(argvs=argvs)], capture_output=True,
                       text=True, timeout=120)
    assert r.stdout.splitlines()[-1] == "OPTIONAL []", r.stdout + r.stderr
    assert (tmp_path / "sweep.csv").exists()  # the serial sweep did run


# ------------------------------------------------------------------- choices of the executor

def test_task_size_groups_points_so_each_worker_gets_about_8_tasks():
    assert task_size(200, 2) == 13  # ceil(200 / 16)
    assert task_size(3, 2) == 1
    assert task_size(100_000, 2) == rodstab.executor.MAX_POINTS_PER_TASK
    assert task_size(200, 2, requested=5) == 5


def test_default_starts_workers_only_when_the_serial_estimate_pays_for_them(monkeypatch):
    monkeypatch.setattr(rodstab.executor, "cores", lambda: 2)
    assert auto_workers(100.0, 50)[0] == 2
    assert auto_workers(1.0, 50) == (0, "the remaining 50 points take ~1 s serially, below "
                                        "the 6 s that pays for starting workers")
    assert auto_workers(100.0, 1)[0] == 0
    monkeypatch.setattr(rodstab.executor, "cores", lambda: 1)
    assert auto_workers(100.0, 50) == (0, "this process may use only one core")
