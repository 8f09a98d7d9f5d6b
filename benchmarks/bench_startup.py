"""Benchmark: start-up cost of the closed-form commands against bare imports (issue 12, target 1).

Targets: ``rodstab section|ring|michell --json`` at most 2x the time of ``python -c "import
numpy"``; every other analytic command (``arc``, ``arc-max-length``) at most 1.5x ``python -c
"import numpy, scipy.optimize"``; ``rodstab --help`` imports no scipy (a test checks that).
Each command and its baseline run interleaved, round after round, in fresh processes; the
medians and their ratios are printed.

Run: ``python benchmarks/bench_startup.py [rounds]`` (default 9 rounds).
"""

from __future__ import annotations

import statistics
import subprocess
import sys
import time

BASE_NUMPY = [sys.executable, "-c", "import numpy"]
BASE_SCIPY = [sys.executable, "-c", "import numpy, scipy.optimize"]
RODSTAB = [sys.executable, "-m", "rodstab.cli"]
#: (command, baseline, target ratio)
CASES = [
    (["--help"], BASE_NUMPY, 2.0),
    (["section", "--shape", "rectangle", "--aspect", "2", "--json"], BASE_NUMPY, 2.0),
    (["ring", "--loops", "3", "--json"], BASE_NUMPY, 2.0),
    (["michell", "--loops", "1", "--nu", "0.5", "--json"], BASE_NUMPY, 2.0),
    (["arc", "--L-over-R", "2", "--json"], BASE_SCIPY, 1.5),
    (["arc-max-length", "--json"], BASE_SCIPY, 1.5),
]


def _wall(cmd: list[str]) -> float:
    t = time.perf_counter()
    subprocess.run(cmd, check=True, capture_output=True)
    return time.perf_counter() - t


def main(rounds: int = 9) -> None:
    times: dict[str, list[float]] = {}
    for _ in range(rounds):
        for args, base, _ in CASES:
            times.setdefault(" ".join(args), []).append(_wall(RODSTAB + args))
            times.setdefault(" ".join(base[1:]), []).append(_wall(base))
    print(f"{'command':58s} {'median':>8s} {'baseline':>9s} {'ratio':>6s} {'target':>6s}")
    for args, base, target in CASES:
        m = statistics.median(times[" ".join(args)])
        b = statistics.median(times[" ".join(base[1:])])
        verdict = "met" if m / b <= target else "MISSED"
        print(f"rodstab {' '.join(args):50s} {m * 1e3:6.0f}ms {b * 1e3:7.0f}ms "
              f"{m / b:6.2f} {target:6.1f}  {verdict}")


if __name__ == "__main__":
    main(int(sys.argv[1]) if len(sys.argv) > 1 else 9)
