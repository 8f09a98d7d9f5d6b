"""Benchmark: what an analysis costs, how it grows, and what a sweep costs on 1, 8, 64 workers.

Issue 12 ("Scale past one machine"). Everything docs/performance.md quotes is printed here;
rerun this script to re-measure it (after a change to an engine, on another machine).

1. **Cost per analysis type** (median of >= 5): analytic answers (ring, clamped arc, Michell),
   the linear FE engine on the folded six-ring at several meshes, a nonlinear equilibrium +
   Hessian stability check, one atlas point (the hexagram's four states, transfer method: what
   one task of ``rodstab atlas`` solves per grid value) and one sweep point (the clamped arc
   of examples/clamped_arc.toml: design re-read + linear solve, per point of a serial sweep).
2. **Growth law**: least-squares exponent of time against dof, log-log, for the linear engine
   (folded ring) and the nonlinear check (straightened rod, a fixed smooth perturbation so
   that Newton's iteration count measures the method, as in bench_nonlinear.py), and
   ``equilibrium(perturb=...)`` from a random mix of the softest modes (iterations grow).
3. **Memory per dof**: peak resident memory of one linear solve in a fresh process per size
   (``/proc/self/status`` VmHWM, or ``ru_maxrss``; SuperLU's C allocations included), minus
   the peak after imports and a small warm-up solve; fitted bytes per dof.
4. **dask overhead**: start of a LocalCluster (:func:`rodstab.executor.open_executor`) and the
   workers' first task, the wall time of a task that solves nothing on 1 and 2 workers, and
   its CPU time split into a worker part (divided among the workers) and a scheduler + client
   part (one process: serial); a run's fixed cost on a warm cluster.
5. **Projection** of a 10^4-point linear sweep, a 10^3-point atlas and 10^3 nonlinear checks
   to 1, 8 and 64 workers with the model printed below, checked against a measured 2-worker
   sweep and atlas on the same points as their serial runs.

Run: ``OMP_NUM_THREADS=1 OPENBLAS_NUM_THREADS=1 python benchmarks/bench_scale.py [--quick]``
(default ~1.5 min on 2 cores; ``--quick`` < 1 min with fewer and smaller sizes).
"""

from __future__ import annotations

import argparse
import datetime
import functools
import json
import math
import os
import platform
import statistics
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import scipy
from bench_nonlinear import straight_rod

from rodstab.analytic.arc import clamped_arc_stability
from rodstab.analytic.michell import michell_stability
from rodstab.analytic.ring import ring_stability
from rodstab.executor import cores, open_executor, task_size
from rodstab.io.design import load_design
from rodstab.limits import DEFAULT as DEFAULT_LIMITS
from rodstab.linear.solve import linear_stability
from rodstab.multistable.atlas import grid_values, ring_atlas
from rodstab.multistable.states import Ring, ring_of
from rodstab.nonlinear.discrete import discretise
from rodstab.nonlinear.solve import equilibrium, lowest_eigenvalues, newton
from rodstab.problems import folded_ring
from rodstab.sections import circle, rectangle
from rodstab.sweep import design_at, sweep

ROOT = Path(__file__).resolve().parent.parent
SWEEP_DESIGN = ROOT / "examples" / "clamped_arc.toml"
ATLAS_DESIGN = ROOT / "examples" / "hexagram.toml"
KEY = "section.aspect"
STATES = ("line", "star", "daisy", "eight")
#: Workloads projected (issue 12) and the worker counts.
SWEEP_POINTS = 10_000
ATLAS_POINTS = 1_000
NONLINEAR_POINTS = 1_000
PROJECTED_WORKERS = (1, 8, 64)
#: Elements of the nonlinear check in the cost table and the projection.
NONLINEAR_ELEMENTS = 32

#: Sizes and counts per mode: default (about 3 minutes) and --quick (under a minute).
SETTINGS = {
    "default": dict(repeats=5, linear_costs=(8, 32, 128, 512),
                    linear_growth=(32, 64, 128, 256, 512, 1024, 2048, 4096, 8192),
                    nonlinear_growth=(32, 64, 128, 256, 512), relax_growth=(16, 64, 256),
                    memory=(512, 1024, 2048, 4096, 8192), empty_tasks=200,
                    check_sweep=200, check_atlas=20, rounds=3),
    "quick": dict(repeats=5, linear_costs=(8, 32, 128),
                  linear_growth=(32, 64, 128, 256, 512, 1024),
                  nonlinear_growth=(32, 64, 128, 256), relax_growth=(16, 64),
                  memory=(256, 1024, 2048), empty_tasks=100,
                  check_sweep=80, check_atlas=6, rounds=1),
}

# A fresh process: imports, a small warm-up solve, then the peak before and after one solve.
MEMORY_PROBE = """
import json, resource, sys
from rodstab.linear.solve import linear_stability
from rodstab.problems import folded_ring
from rodstab.sections import circle

def peak_bytes():
    try:
        with open("/proc/self/status") as f:
            for line in f:
                if line.startswith("VmHWM:"):
                    return int(line.split()[1]) * 1024
    except OSError:
        pass
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024  # kB on Linux

a = folded_ring.build(folded_ring.Params(section=circle()))
linear_stability(a, 4)
base = peak_bytes()
r = linear_stability(a, int(sys.argv[1]))
print(json.dumps({"dof": r.n_dof, "base": base, "peak": peak_bytes()}))
"""


# ----------------------------------------------------------------------------- helpers
def timed(fn) -> float:
    t = time.perf_counter()
    fn()
    return time.perf_counter() - t


def median_time(fn, repeats: int) -> float:
    return statistics.median(timed(fn) for _ in range(repeats))


def fit_power(x, y) -> float:
    """Least-squares slope of log y against log x."""
    return float(np.polyfit(np.log(x), np.log(y), 1)[0])


def hexagram_ring(base, aspect: float) -> Ring:
    """The hexagram at ``section.aspect = aspect`` (module level: pickles to a worker)."""
    return ring_of(design_at(base, KEY, aspect).assembly)


def unsolved(design, key: str, points: list) -> list:
    """A task that solves nothing (with a sweep task's arguments): dask's own cost of a task."""
    return points


def nonlinear_check(a, mu: float, n: int) -> tuple[int, int, bool]:
    """Discretise at ``mu``, perturb smoothly, Newton, then the Hessian's lowest eigenvalue.

    The perturbation is bench_nonlinear.py's: edge frames turned by 0.05 sin(pi s) about the
    normal and 0.03 sin(2 pi s) about the tangent, the same on every mesh. Returns (free dof,
    Newton iterations, stable).
    """
    rod = discretise(a, n, mu)
    s_mid = rod.x[rod.edge_nodes].mean(axis=1)[:, 0]
    phi = np.stack([0.05 * np.sin(np.pi * s_mid), 0.03 * np.sin(2 * np.pi * s_mid),
                    0.0 * s_mid], axis=1)
    dq = np.zeros(rod.n_dof)
    dq[rod.edge_dofs(np.arange(len(s_mid))).ravel()] = phi.ravel()
    rod.apply(dq)
    ok, its, _ = newton(rod)
    if not ok:
        raise RuntimeError(f"Newton did not converge at {n} elements")
    return len(rod.free_dofs()), its, bool(lowest_eigenvalues(rod, 1)[0] > 0)


def section(title: str) -> None:
    print(f"\n== {title}")


# ----------------------------------------------------------------------------- 1. costs
def costs(cfg: dict) -> dict[str, float]:
    section(f"1. cost per analysis type (median of {cfg['repeats']}, one process, warm)")
    reps = cfg["repeats"]
    s = rectangle(aspect=2.0)
    out: dict[str, float] = {}
    rows: list[tuple[str, int | str, float]] = []
    for name, fn in (("analytic ring N=3", lambda: ring_stability(s.b1, s.b2, 3)),
                     ("analytic clamped arc L/R=2", lambda: clamped_arc_stability(s.b1, s.b2,
                                                                                  2.0)),
                     ("analytic Michell N=1", lambda: michell_stability(0.75, 1))):
        fn()
        rows.append((name, "-", median_time(fn, max(reps, 15))))
    fr = folded_ring.build(folded_ring.Params(section=circle()))
    for n in cfg["linear_costs"]:
        dof = linear_stability(fr, n).n_dof
        rows.append((f"linear, folded ring, {n} el/seg", dof,
                     median_time(lambda n=n: linear_stability(fr, n), reps)))
    rod = straight_rod("sliding-clamp")
    mu = 0.9 * linear_stability(rod, 64).load_factor_critical
    dof, its, _ = nonlinear_check(rod, mu, NONLINEAR_ELEMENTS)
    t_nl = median_time(lambda: nonlinear_check(rod, mu, NONLINEAR_ELEMENTS), reps)
    rows.append((f"nonlinear eq.+stability, {NONLINEAR_ELEMENTS} el ({its} Newton its)", dof,
                 t_nl))
    t_eq = median_time(lambda: equilibrium(rod, load_factor=mu,
                                           elements_per_segment=NONLINEAR_ELEMENTS), reps)
    rows.append((f"rodstab equilibrium (held start), {NONLINEAR_ELEMENTS} el", dof, t_eq))
    base = load_design(ATLAS_DESIGN)
    ring_at = functools.partial(hexagram_ring, base)
    atlas_point = functools.partial(grid_values, ring_at, STATES, "transfer", 1.0,
                                    DEFAULT_LIMITS, [3.0])
    atlas_point()
    t_atlas = median_time(atlas_point, reps)
    rows.append(("atlas point: hexagram, 4 states, transfer", "-", t_atlas))
    d = load_design(SWEEP_DESIGN)
    vals = np.linspace(1.0, 6.0, 50).tolist()
    sweep(d, KEY, vals[:2], workers=0)
    t_sweep = median_time(lambda: sweep(d, KEY, vals, workers=0), reps) / len(vals)
    rows.append((f"sweep point: clamped arc, {d.elements} el (serial sweep / 50)",
                 linear_stability(d.assembly, d.elements).n_dof, t_sweep))
    print(f"{'analysis':58s} {'dof':>7s} {'median ms':>10s}")
    for name, dof, t in rows:
        print(f"{name:58s} {dof!s:>7s} {t * 1e3:10.3f}")
    out.update(nonlinear=t_nl, atlas=t_atlas, sweep=t_sweep)
    return out


# ----------------------------------------------------------------------------- 2. growth
def growth(cfg: dict) -> None:
    section("2. growth law: time vs dof, least-squares exponent of log t on log dof")
    reps = 3
    fr = folded_ring.build(folded_ring.Params(section=circle()))
    lin = []
    for n in cfg["linear_growth"]:
        r = linear_stability(fr, n)
        lin.append((n, r.n_dof, median_time(lambda n=n: linear_stability(fr, n), reps)))
    rod = straight_rod("sliding-clamp")
    mu = 0.9 * linear_stability(rod, 64).load_factor_critical
    nl = []
    for n in cfg["nonlinear_growth"]:
        dof, its, _ = nonlinear_check(rod, mu, n)
        nl.append((n, dof, median_time(lambda n=n: nonlinear_check(rod, mu, n), reps), its))
    print(f"linear engine, folded six-ring (median of {reps}):")
    print(f"  {'el/seg':>7s} {'dof':>8s} {'ms':>10s} {'us/dof':>8s}")
    for n, dof, t in lin:
        print(f"  {n:>7d} {dof:>8d} {t * 1e3:10.2f} {t / dof * 1e6:8.2f}")
    big = [row for row in lin if row[1] >= 10_000] or lin
    print(f"  exponent over {lin[0][1]}..{lin[-1][1]} dof: "
          f"{fit_power([r[1] for r in lin], [r[2] for r in lin]):.2f}; over "
          f"{big[0][1]}..{big[-1][1]} dof: "
          f"{fit_power([r[1] for r in big], [r[2] for r in big]):.2f}")
    print(f"nonlinear check, straightened rod at 0.9 mu_c, smooth perturbation (median of {reps}):")
    print(f"  {'elements':>8s} {'dof':>8s} {'Newton its':>10s} {'ms':>10s} {'ms/it':>8s}")
    for n, dof, t, its in nl:
        print(f"  {n:>8d} {dof:>8d} {its:>10d} {t * 1e3:10.2f} {t / max(its, 1) * 1e3:8.2f}")
    print(f"  exponent over {nl[0][1]}..{nl[-1][1]} dof: time "
          f"{fit_power([r[1] for r in nl], [r[2] for r in nl]):.2f}, time per Newton iteration "
          f"{fit_power([r[1] for r in nl], [r[2] / max(r[3], 1) for r in nl]):.2f}")
    print("rodstab equilibrium(perturb=0.01): a seeded random mix of the softest modes, "
          "relaxed (one run each):")
    print(f"  {'elements':>8s} {'dof':>8s} {'iterations':>10s} {'ms':>10s}")
    rel = []
    for n in cfg["relax_growth"]:
        t = time.perf_counter()
        e, _ = equilibrium(rod, load_factor=mu, elements_per_segment=n, perturb=0.01)
        rel.append((e.n_dof, time.perf_counter() - t))
        print(f"  {n:>8d} {e.n_dof:>8d} {e.iterations:>10d} {rel[-1][1] * 1e3:10.2f}")
    print(f"  exponent over {rel[0][0]}..{rel[-1][0]} dof: time "
          f"{fit_power([r[0] for r in rel], [r[1] for r in rel]):.2f}")


# ----------------------------------------------------------------------------- 3. memory
def memory(cfg: dict) -> None:
    section("3. memory of one linear solve (folded ring), fresh process per size")
    env = dict(os.environ, OMP_NUM_THREADS="1", OPENBLAS_NUM_THREADS="1")
    rows = []
    for n in cfg["memory"]:
        r = subprocess.run([sys.executable, "-c", MEMORY_PROBE, str(n)], check=True,
                           capture_output=True, text=True, env=env)
        m = json.loads(r.stdout.strip().splitlines()[-1])
        rows.append((n, m["dof"], m["base"], m["peak"] - m["base"]))
    print(f"  {'el/seg':>7s} {'dof':>8s} {'base MB':>8s} {'extra peak MB':>13s} {'B/dof':>7s}")
    for n, dof, base, extra in rows:
        print(f"  {n:>7d} {dof:>8d} {base / 1e6:8.1f} {extra / 1e6:13.1f} {extra / dof:7.0f}")
    dofs = np.array([r[1] for r in rows], float)
    extra = np.array([r[3] for r in rows], float)
    slope, icpt = np.polyfit(dofs, extra, 1)
    print(f"  fit extra = {slope:.0f} B/dof x dof + {icpt / 1e6:.1f} MB "
          f"(over {int(dofs[0])}..{int(dofs[-1])} dof); the baseline (interpreter, numpy, "
          f"scipy, rodstab) is {rows[0][2] / 1e6:.0f} MB per process")


# ----------------------------------------------------------------------------- 4-5. dask
def worker_cpu(client) -> float:
    """CPU seconds (user + system) used so far by all the client's workers together."""
    def used() -> float:
        import psutil

        t = psutil.Process().cpu_times()
        return t.user + t.system

    return sum(client.run(used).values())


def empty_task_cost(ex, design, n: int, rounds: int) -> tuple[float, float, float]:
    """Per one-point task that solves nothing, medians: wall, CPU here, CPU of the workers.

    "Here" is the client and, for a LocalCluster, its scheduler (a thread of this process).
    """
    fn = functools.partial(unsolved, design, KEY)
    tasks = [[(i, float(i))] for i in range(n)]
    list(ex.map_unordered(fn, tasks))
    walls, here, workers = [], [], []
    for _ in range(max(rounds, 3)):
        c0, w0, t0 = time.process_time(), worker_cpu(ex.client), time.perf_counter()
        list(ex.map_unordered(fn, tasks))
        walls.append(time.perf_counter() - t0)
        here.append(time.process_time() - c0)
        workers.append(worker_cpu(ex.client) - w0)
    return tuple(statistics.median(x) / n for x in (walls, here, workers))


def start_cluster(workers: int):
    """Enter open_executor(workers); return (context, executor, seconds)."""
    t = time.perf_counter()
    ctx = open_executor(workers)
    ex = ctx.__enter__()
    return ctx, ex, time.perf_counter() - t


def predict(n: int, t_point: float, workers: int, o_task: float, s_task: float,
            serial: float) -> float:
    """Time of ``n`` points on ``workers`` once the cluster is up (model in dask_and_model)."""
    p = task_size(n, workers)
    tasks = math.ceil(n / p)
    return math.ceil(tasks / workers) * (p * t_point + o_task) + tasks * s_task + serial


def dask_and_model(cfg: dict, cost: dict[str, float]) -> None:
    section("4. dask overhead (LocalCluster of single-threaded worker processes)")
    rounds, n_empty = cfg["rounds"], cfg["empty_tasks"]
    d = load_design(SWEEP_DESIGN)
    base = load_design(ATLAS_DESIGN)
    ring_at = functools.partial(hexagram_ring, base)
    h: dict[int, tuple[float, float, float]] = {}
    start: dict[int, tuple[float, float]] = {}
    checks: dict[str, list[float]] = {}
    on_points: dict[str, list[float]] = {}  # the sweep's points' own seconds (SweepRow.seconds)
    w_cpu: dict[str, list[float]] = {}  # CPU seconds of the workers during the sweep
    a_cpu: dict[str, list[float]] = {}  # CPU seconds of an atlas: here + workers
    sweep_vals = np.linspace(1.0, 6.0, cfg["check_sweep"]).tolist()
    atlas_vals = np.linspace(1.0, 6.0, cfg["check_atlas"]).tolist()

    def atlas(**kw):
        return ring_atlas(ring_at, atlas_vals, STATES, key=KEY, method="transfer", **kw)

    for w in (1, 2):
        ctx, ex, t_up = start_cluster(w)
        try:
            # first real task on every worker: unpickling it imports rodstab, scipy
            t_first = timed(lambda ex=ex, w=w: sweep(d, KEY, sweep_vals[:w], client=ex.client,
                                                     points_per_task=1))
            start[w] = (t_up, t_first)
            h[w] = empty_task_cost(ex, d, n_empty, rounds)
            if w == 2:
                atlas(client=ex.client)  # warm the atlas's imports on the workers
                for _ in range(max(rounds, 3)):  # a run's fixed cost: one point, one task
                    checks.setdefault("one-point sweep", []).append(timed(
                        lambda ex=ex: sweep(d, KEY, sweep_vals[:1], client=ex.client)))
                for _ in range(rounds):
                    for name, kw in (("serial", {"workers": 0}),
                                     ("2 workers", {"client": ex.client})):
                        w0 = worker_cpu(ex.client)
                        t = time.perf_counter()
                        rows = sweep(d, KEY, sweep_vals, **kw).rows
                        checks.setdefault(f"sweep {name}", []).append(time.perf_counter() - t)
                        w_cpu.setdefault(name, []).append(worker_cpu(ex.client) - w0)
                        on_points.setdefault(name, []).append(sum(r.seconds for r in rows))
                        c0, w0 = time.process_time(), worker_cpu(ex.client)
                        checks.setdefault(f"atlas {name}", []).append(timed(
                            lambda kw=kw: atlas(**kw)))
                        a_cpu.setdefault(name, []).append(
                            time.process_time() - c0 + worker_cpu(ex.client) - w0)
                    # the atlas's grid alone, serially: its t_point, next to the runs above
                    c0 = time.process_time()
                    checks.setdefault("atlas grid", []).append(timed(
                        lambda: grid_values(ring_at, STATES, "transfer", 1.0, DEFAULT_LIMITS,
                                            atlas_vals)))
                    a_cpu.setdefault("grid", []).append(time.process_time() - c0)
        finally:
            ctx.__exit__(None, None, None)
    # CPU per task: s in the scheduler + client (one process: serial), o on a worker
    s_task, o_task = h[2][1], h[2][2]
    print(f"  cluster start (LocalCluster + Client up): 1 worker {start[1][0]:.2f} s, "
          f"2 workers {start[2][0]:.2f} s")
    print(f"  then the first task on each worker: 1 worker {start[1][1]:.2f} s, 2 workers "
          f"{start[2][1]:.2f} s (start = the sum; the workers, spawned, import what this "
          "script imports while they start, as a command's workers import rodstab.cli)")
    print(f"  empty task ({n_empty} one-point tasks, nothing solved), per task: wall "
          f"{h[1][0] * 1e3:.2f} ms on 1 worker, {h[2][0] * 1e3:.2f} ms on 2; CPU on 2 workers: "
          f"s = {s_task * 1e3:.2f} ms in the scheduler + client (one process: serial), "
          f"o = {o_task * 1e3:.2f} ms on the workers (divides by w)")
    med = {k: statistics.median(v) for k, v in checks.items()}
    t_sweep = med["sweep serial"] / len(sweep_vals)
    run = max(0.0, med["one-point sweep"] - t_sweep - o_task - s_task)
    print(f"  fixed cost of a run on a warm cluster (one-point sweep - its point, o, s; the "
          f"workers' version check): {run * 1e3:.1f} ms")
    slow = statistics.median(on_points["2 workers"]) / statistics.median(on_points["serial"])
    print(f"  the sweep's points solved on 2 workers took {slow:.2f}x their serial seconds "
          f"(SweepRow.seconds); the workers' CPU seconds in that sweep were "
          f"{statistics.median(w_cpu['2 workers']) / statistics.median(on_points['2 workers']):.0%}"
          f" of the points' wall seconds (below 100%: waiting for a core)")
    t_atlas = med["atlas grid"] / len(atlas_vals)
    refine = max(0.0, med["atlas serial"] - med["atlas grid"])
    ac = {k: statistics.median(v) for k, v in a_cpu.items()}
    print(f"  atlas of {len(atlas_vals)} points: grid alone {med['atlas grid']:.2f} s "
          f"({t_atlas * 1e3:.0f} ms a point), whole serial atlas {med['atlas serial']:.2f} s "
          f"(refinement, in the client: {refine:.2f} s); CPU seconds (here + workers): grid "
          f"{ac['grid']:.2f}, serial atlas {ac['serial']:.2f}, on 2 workers "
          f"{ac['2 workers']:.2f}")
    start2 = sum(start[2])

    section("5. model and projection")
    print("  T(w) = start + ceil(tasks / w) x (p x t_point + o) + tasks x s + run + serial")
    print("    p = points per task (rodstab.executor.task_size: ~8 tasks per worker, <= 16 "
          "points), tasks = ceil(N / p)")
    print("    measured here: t_point (serial, warm; sweep and atlas in the rounds of the check,"
          " nonlinear in section 1), o and s (CPU of empty tasks, 2 workers), "
          "start (2 workers), run (a run's fixed cost on a warm cluster), serial (the atlas: "
          "root refinement of the coexistence ranges in the client = serial atlas - N x "
          "t_point)")
    print("    assumed: every worker a separate core as fast as this one, one thread each; "
          "start(8) = start(64) = start(2) (workers start in parallel; a real cluster adds "
          "provisioning); o and s independent of w; the refinement independent of N")
    print(f"  check, 2 workers, warm cluster (median of {rounds}; cores here: {cores()}):")
    print(f"    {'workload':22s} {'serial s':>9s} {'measured':>9s} {'predicted':>9s} "
          f"{'meas/pred':>9s} {'pred. slowed':>12s} {'meas/slowed':>11s}")
    for kind, n, t_pt, serial in (("sweep", len(sweep_vals), t_sweep, 0.0),
                                  ("atlas", len(atlas_vals), t_atlas, refine)):
        pred = predict(n, t_pt, 2, o_task, s_task, run + serial)
        slowed = predict(n, t_pt * slow, 2, o_task, s_task, run + serial)
        meas = med[f"{kind} 2 workers"]
        print(f"    {f'{kind}, {n} points':22s} {med[f'{kind} serial']:9.3f} {meas:9.3f} "
              f"{pred:9.3f} {meas / pred:9.2f} {slowed:12.3f} {meas / slowed:11.2f}")
    print(f"    (pred. slowed: t_point x {slow:.2f}, the sweep points' measured slow-down on "
          "the workers, applied to both: the model with the cores this machine gave them)")
    print(f"    (speed-up measured: sweep {med['sweep serial'] / med['sweep 2 workers']:.2f}x, "
          f"atlas {med['atlas serial'] / med['atlas 2 workers']:.2f}x; not in these: the "
          f"2-worker cluster's start, {start2:.2f} s)")
    print(f"  projection (start = {start2:.2f} s, o = {o_task * 1e3:.2f} ms, s = "
          f"{s_task * 1e3:.2f} ms per task, run = {run * 1e3:.0f} ms, atlas serial = "
          f"{refine:.2f} s):")
    print(f"    {'workload':42s} {'t_point ms':>10s} {'no dask':>8s} "
          + " ".join(f"{f'{w} w':>8s}" for w in PROJECTED_WORKERS)
          + f" {'serial share 64 w':>17s} {'max speed-up':>12s}")
    for name, n, t_pt, serial in (
            (f"linear sweep (clamped arc), {SWEEP_POINTS} pts", SWEEP_POINTS, t_sweep, 0.0),
            (f"atlas (hexagram, transfer), {ATLAS_POINTS} pts", ATLAS_POINTS, t_atlas, refine),
            (f"nonlinear checks ({NONLINEAR_ELEMENTS} el), {NONLINEAR_POINTS} pts",
             NONLINEAR_POINTS, cost["nonlinear"], 0.0)):
        proj = [start2 + predict(n, t_pt, w, o_task, s_task, run + serial)
                for w in PROJECTED_WORKERS]
        fixed = math.ceil(n / task_size(n, 64)) * s_task + run + serial  # does not divide by w
        alone = n * t_pt + serial
        print(f"    {name:42s} {t_pt * 1e3:10.2f} {alone:7.1f}s "
              + " ".join(f"{t:7.1f}s" for t in proj)
              + f" {fixed / proj[-1]:17.0%} {alone / (start2 + fixed):11.0f}x")
    print("    (serial share: scheduler, run and refinement terms / T(64); max speed-up: no "
          "dask / (start + those terms), the limit of many workers)")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="fewer, smaller sizes (< 1 min)")
    args = parser.parse_args()
    cfg = SETTINGS["quick" if args.quick else "default"]
    t0 = time.perf_counter()
    print(f"bench_scale.py{' --quick' if args.quick else ''}, "
          f"{datetime.datetime.now().astimezone():%Y-%m-%d %H:%M %Z}")
    print(f"{platform.platform()}, {platform.processor() or platform.machine()}, "
          f"{cores()} cores; Python {platform.python_version()}, numpy {np.__version__}, "
          f"scipy {scipy.__version__}; OMP_NUM_THREADS={os.environ.get('OMP_NUM_THREADS')}, "
          f"OPENBLAS_NUM_THREADS={os.environ.get('OPENBLAS_NUM_THREADS')}")
    print(f"load average before: {', '.join(f'{x:.2f}' for x in os.getloadavg())}")
    cost = costs(cfg)
    growth(cfg)
    memory(cfg)
    dask_and_model(cfg, cost)
    print(f"\nload average after: {', '.join(f'{x:.2f}' for x in os.getloadavg())}; "
          f"total {time.perf_counter() - t0:.0f} s")


if __name__ == "__main__":
    main()
