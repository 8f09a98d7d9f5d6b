"""Benchmark: the hexagram's eight held with contact on its braid, and its stable interval.

The braided eight (:func:`rodstab.multistable.braid.braid_eight`: rectangle h/t = 4, three
strands a lobe on tubes one spacing in radius, one whole turn round the tube a rod), relaxed
with contact at kappa_n R0 = 3 (:data:`START`) and followed both ways in the load factor
(:func:`~rodstab.multistable.braid.braid_limits`); then the same braided model without
contact (its rods free to pass). Printed per thickness and mesh: the relaxed state's energy
above the planar eight's (the same model, ``common_rod``, rods coincident, relaxed), its
closest pair, its contact forces, the lowest and highest verdict eigenvalue met within one of
the no-contact interval, and the two limits (or how each side's branch ended). To compare:
the planar eight's limits without contact, :data:`NO_CONTACT`, and the cone's at zero gap
(C-eight-limits: 1.413, 5.164 at 32-48 el.).

Run: ``OMP_NUM_THREADS=1 python benchmarks/eight_braid_hold.py [h/L ...] [--elements N ...]
[--dhat dhat/h ...]`` (default 0.01 0.005, 16 elements; ``--dhat``: the rows with contact at
each ``dhat / h``, for its convergence; default 0.1 with and without contact).
"""

from __future__ import annotations

import math
import sys
import time

from rodstab.errors import RodstabInputError
from rodstab.multistable.braid import braid_limits
from rodstab.multistable.discover import common_rod
from rodstab.nonlinear.newton import newton
from rodstab.problems.barrier_states import state_assembly
from rodstab.sections import rectangle

#: The eight's stable interval without contact at h/t = 4 (atlas, ``kappa_n R0``; the load
#: factor of the hexagram's model is ``kappa_n R0``).
NO_CONTACT = (1.9031, 4.2393)
#: Where the braid is relaxed first: the planar eight's stress-free load (its rods' natural
#: curvature equals the held one). At h/L = 0.005, 32 el., Newton from the built braid did
#: not converge at the interval's middle (3.0712).
START = 3.0


def _side(s) -> str:  # noqa: ANN001
    return "-" if s is None else s.outcome()


def main(thicknesses: list[float], meshes: list[int], dhats: list[float] | None = None
         ) -> None:
    """Print the module doc's rows (``dhats``: only the rows with contact, at each)."""
    a = state_assembly("hexagram", rectangle(aspect=4.0), "eight")
    print(f"{'h/L':>7} {'el.':>4} {'dhat/h':>6} {'contact':>7} {'E - planar':>11} "
          f"{'closest/h':>9} {'force':>8} {'eigenvalues':>19}  lower; upper")
    runs = [(q, c) for q in dhats for c in (True,)] if dhats else [(0.1, True), (0.1, False)]
    for n in meshes:
        for h in thicknesses:
            for q, contact in runs:
                t = time.perf_counter()
                try:
                    r = braid_limits(a, NO_CONTACT, thickness_ratio=h, elements_per_segment=n,
                                     start_load_factor=START, contact=contact,
                                     dhat_fraction=q)
                except RodstabInputError as exc:
                    print(f"{h:7.4g} {n:4d} {q:6.3g} {contact!s:>7} {exc}", flush=True)
                    continue
                f = r.start
                planar = common_rod(a, n, f.load_factor)  # the braid's model, coincident
                newton(planar)
                lam = [p[1] for s in (r.lower, r.upper) for p in s.path
                       if NO_CONTACT[0] - 1.0 <= p[0] <= NO_CONTACT[1] + 1.0]
                closest = (f.min_gap + h) / h if math.isfinite(f.min_gap) else math.nan
                print(f"{h:7.4g} {n:4d} {q:6.3g} {contact!s:>7} "
                      f"{f.energy - planar.energy():11.4e} "
                      f"{closest:9.5f} {f.contact_total:8.4g} {min(lam):9.2e} "
                      f"{max(lam):9.2e}  {_side(r.lower)}; {_side(r.upper)} "
                      f"({time.perf_counter() - t:.0f} s)", flush=True)


def _list(args: list[str], flag: str) -> list[str]:
    """The values after ``flag`` up to the next flag."""
    if flag not in args:
        return []
    rest = args[args.index(flag) + 1:]
    return rest[:next((i for i, v in enumerate(rest) if v.startswith("--")), len(rest))]


if __name__ == "__main__":
    args = sys.argv[1:]
    first = next((i for i, v in enumerate(args) if v.startswith("--")), len(args))
    main([float(x) for x in args[:first]] or [0.01, 0.005],
         [int(x) for x in _list(args, "--elements")] or [16],
         [float(x) for x in _list(args, "--dhat")] or None)
