"""Benchmark: issue 22's speed targets for the multistable commands, measured side by side.

Targets (issue 22, "Speed"): ``rodstab barrier`` line -> star and ``rodstab discover`` on the
hexagram at 8 elements per rod each at most 4x the whole-process time of ``rodstab equilibrium
examples/hexagram.toml --elements 8``; one energy + gradient + Hessian at most 1 us per unknown.
(The hexagram diagram over kappa_n R0 in [0, 4] under 2 min on 2 cores is timed by running
``rodstab diagram examples/hexagram.toml --vary load_factor=0:4:40 --elements 8``; not here,
it takes minutes.)

Every command runs in a fresh process, interleaved round after round with the baseline; the
medians and their ratios to the baseline are printed, with the target and whether it is met.
``discover`` is timed twice: with its default saddle search (climbs and strings, since session
36) and without it (``--saddle-modes 0 --strings 0``, the deflated Newton search alone).

Run: ``OMP_NUM_THREADS=1 python benchmarks/bench_multistable.py [rounds]`` (default 3).
"""

from __future__ import annotations

import statistics
import subprocess
import sys
import time

RODSTAB = [sys.executable, "-m", "rodstab.cli"]
HEX = "examples/hexagram.toml"
BASE = ["equilibrium", HEX, "--elements", "8"]
#: (label, command, target ratio to BASE)
CASES = [
    ("barrier line -> star, kappa_n R0 = 1",
     ["barrier", HEX, "--from", "line", "--to", "star", "--load-factor", "1", "--elements", "8"],
     4.0),
    ("discover, kappa_n R0 = 1, no saddles",
     ["discover", HEX, "--load-factor", "1", "--elements", "8", "--saddle-modes", "0",
      "--strings", "0"], 4.0),
    ("discover, kappa_n R0 = 1, default", ["discover", HEX, "--load-factor", "1", "--elements",
                                           "8"], 4.0),
]


def run(args: list[str]) -> float:
    t = time.perf_counter()
    subprocess.run(RODSTAB + args, check=True, capture_output=True)
    return time.perf_counter() - t


def per_unknown_us(repeats: int = 200) -> tuple[float, int]:
    """Median time of one energy + gradient + Hessian of the hexagram's star (8 el.), us/dof."""
    from rodstab.io.design import load_design
    from rodstab.multistable.discover import search_start
    from rodstab.multistable.states import ring_of
    from rodstab.nonlinear.solve import newton

    rod = search_start(ring_of(load_design(HEX)), None, "star", 8, 1.0, seed_states=False)[0]
    newton(rod)
    times = []
    for _ in range(repeats):
        t = time.perf_counter()
        rod.energy_terms()
        times.append(time.perf_counter() - t)
    return statistics.median(times) * 1e6 / rod.n_dof, rod.n_dof


def main() -> None:
    rounds = int(sys.argv[1]) if len(sys.argv) > 1 else 3
    base: list[float] = []
    times: dict[str, list[float]] = {label: [] for label, _, _ in CASES}
    for _ in range(rounds):
        for label, args, _ in CASES:
            base.append(run(BASE))
            times[label].append(run(args))
    b = statistics.median(base)
    print(f"baseline: rodstab {' '.join(BASE)}: median {b:.2f} s over {len(base)} runs")
    print(f"{'command':<40} {'median s':>9} {'ratio':>7} {'target':>7}  met")
    for label, _, target in CASES:
        m = statistics.median(times[label])
        print(f"{label:<40} {m:>9.2f} {m / b:>7.1f} {target:>7.1f}  {m / b <= target}")
    us, n = per_unknown_us()
    print(f"energy + gradient + Hessian: {us:.2f} us per unknown ({n} unknowns), target 1.0, "
          f"met {us <= 1.0}")


if __name__ == "__main__":
    main()
