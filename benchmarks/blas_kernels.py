"""Check: the report is the same whichever BLAS kernels run (OpenBLAS's core types).

OpenBLAS picks its kernels by the CPU (``DYNAMIC_ARCH``), so two machines round differently;
``OPENBLAS_CORETYPE`` forces a kernel set on one machine. Session 26 found six tests failing
on an AMD host (Haswell kernels) that passed with the SkylakeX kernels, and report rows whose
numbers moved with them (a string too coarse; a double mode's margin and phase). This runs
``rodstab reproduce`` once per core type, each in a fresh process, and prints every report
cell (``rodstab``, ``second``, ``status``) that differs, with the largest relative difference
of the numbers in it. Cells that print round-off (a mismatch of 1e-15) differ harmlessly; a
status or a converged number that differs is a defect.

Run: ``python benchmarks/blas_kernels.py [CORETYPE ...]`` (default Haswell SkylakeX; the host
must support each: SkylakeX needs AVX-512).
"""

from __future__ import annotations

import json
import os
import re
import subprocess
import sys
import tempfile
from pathlib import Path

NUMBER = re.compile(r"[-+]?\d*\.?\d+(?:[eE][-+]?\d+)?")


def _claims(core: str, out: Path) -> dict[str, dict]:
    env = dict(os.environ, OPENBLAS_CORETYPE=core)
    subprocess.run([sys.executable, "-m", "rodstab.cli", "reproduce", "--out", str(out)], env=env,
                   check=True, capture_output=True)
    return {c["id"]: c for c in json.loads((out / "results.json").read_text())["claims"]}


def _difference(x: str, y: str) -> float:
    nx, ny = NUMBER.findall(x), NUMBER.findall(y)
    if len(nx) != len(ny):
        return float("inf")
    return max((abs(float(a) - float(b)) / max(abs(float(a)), abs(float(b)), 1e-300)
                for a, b in zip(nx, ny, strict=True)), default=0.0)


def main(cores: list[str]) -> None:
    with tempfile.TemporaryDirectory() as tmp:
        runs = {c: _claims(c, Path(tmp) / c) for c in cores}
    first, *others = cores
    for other in others:
        a, b = runs[first], runs[other]
        rows = [(k, f, _difference(str(a[k].get(f)), str(b[k].get(f))))
                for k in a for f in ("rodstab", "second", "status")
                if str(a[k].get(f)) != str(b[k].get(f))]
        print(f"{first} against {other}: {len(a)} rows, {len(rows)} cells differ")
        for k, f, d in sorted(rows, key=lambda r: -r[2]):
            print(f"  {k:12s} {f:8s} largest relative difference {d:.2g}:\n"
                  f"    {str(a[k].get(f))[:90]}\n    {str(b[k].get(f))[:90]}")


if __name__ == "__main__":
    main(sys.argv[1:] or ["Haswell", "SkylakeX"])
