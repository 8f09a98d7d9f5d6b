"""Benchmark: the string method's images stepped in one process against a pool of processes.

The hexagram's star -> daisy barrier (rectangle h/t = 4, kappa_n R0 = 1.5) with contact
(h = 0.02 L, dhat = 0.1 h) and cusp welds of width 1.15 h, 17 images, at the meshes given
(default 16 el. per rod: issue 21's target, under 60 s on 2 cores). Each mesh is run with the
images stepped here (``pool=None``) and in a pool of ``--workers`` processes
(:func:`rodstab.numerics.threads.process_pool`), side by side in one run; printed: both wall
times, their ratio and whether the two barriers are equal to the last bit (they must be: the
same arithmetic in every process).

Run: ``python benchmarks/string_workers.py [elements ...] [--workers N]`` (alone on the
machine: the pool's processes need the cores).
"""

from __future__ import annotations

import sys
import time

from rodstab.multistable.string_method import string_barrier
from rodstab.nonlinear.equilibrium import rod_contact_model
from rodstab.numerics.threads import process_pool, serial_blas
from rodstab.problems.barrier_states import state_assembly
from rodstab.sections import rectangle

H, DHAT, LOAD, WIDTH = 0.02, 0.1, 1.5, 1.15


def _run(n: int, pool) -> tuple[float, float, float]:  # noqa: ANN001
    sec = rectangle(aspect=4.0)
    star, daisy = (state_assembly("hexagram", sec, s) for s in ("star", "daisy"))
    t = time.perf_counter()
    b, _ = string_barrier(star, daisy, LOAD, elements_per_segment=n, name_a="star",
                          name_b="daisy", contact=rod_contact_model(star, H, DHAT),
                          cusp_width=WIDTH * H, pool=pool)
    assert b.converged, "the barrier did not converge"
    return time.perf_counter() - t, b.barrier_forward, b.barrier_backward


def main(argv: list[str]) -> None:
    workers = 2
    if "--workers" in argv:
        k = argv.index("--workers")
        workers = int(argv[k + 1])
        argv = argv[:k] + argv[k + 2:]
    meshes = [int(a) for a in argv] or [16]
    print(f"{'el.':>4} {'one process s':>14} {f'{workers} processes s':>14} {'ratio':>6}  "
          "barriers equal")
    for n in meshes:
        with serial_blas():
            t1, f1, b1 = _run(n, None)
        with process_pool(workers) as pool:
            t2, f2, b2 = _run(n, pool)
        print(f"{n:4d} {t1:14.1f} {t2:14.1f} {t1 / t2:6.2f}  {(f1, b1) == (f2, b2)} "
              f"({f1:.8f} / {b1:.8f})", flush=True)


if __name__ == "__main__":
    main(sys.argv[1:])
