"""Benchmark: the hexagram's star -> daisy barrier with contact, with cusp welds of width.

At a point cusp weld two rods of thickness h leave one point along one line, so their end
elements overlap under the contact model, and more so as the mesh refines (the star is outside
the model from 16 el. on; docs/theory/contact.md, "Cusp welds of finite width"). Welds of width
``w = h + 1.5 dhat`` (:func:`rodstab.multistable.discover.common_rod`'s ``cusp_width``) hold
the two ends apart. Printed per mesh (rectangle h/t = 4, kappa_n R0 = 1.5, h = 0.02 L,
dhat = 0.1 h, 17 images): the string method's barriers star -> daisy and back

* without contact, point welds;
* without contact, wide welds;
* with contact, wide welds: the string brought inside the model by the soft stages
  (``soft`` = (iterations per stage, most stages), default 60 and 14), then relaxed with the
  barrier; the stages used, the closest pair after them, and whether two neighbouring images
  of that path have rods passed through each other between them (None: no).

Run: ``OMP_NUM_THREADS=1 python benchmarks/wide_cusp_barrier.py [elements ...] [--soft IT
STAGES] [--no-contact]`` (default 6 8).
"""

from __future__ import annotations

import sys
import time

from rodstab.errors import NotConverged, RodstabInputError
from rodstab.multistable.string_method import string_barrier
from rodstab.nonlinear.contact import Interpenetration
from rodstab.nonlinear.equilibrium import rod_contact_model
from rodstab.problems.barrier_states import state_assembly
from rodstab.sections import rectangle

H, DHAT, LOAD = 0.02, 0.1, 1.5


def _row(label: str, star, daisy, **kw) -> None:  # noqa: ANN001, ANN003
    t = time.perf_counter()
    try:
        b, _ = string_barrier(star, daisy, LOAD, **kw)
    except (NotConverged, RodstabInputError, Interpenetration) as exc:
        print(f"  {label:28s} {type(exc).__name__}: {str(exc)[:160]} "
              f"({time.perf_counter() - t:.0f} s)", flush=True)
        return
    extra = ""
    stages = getattr(b.string_run, "contact_stages", None)
    if stages is not None:
        extra = (f"; {len(stages.stiffnesses)} soft stages, closest pair after them "
                 f"{stages.distances[-1] / H:.4f} h, rods pass between images "
                 f"{stages.start_crossing}")
    print(f"  {label:28s} forward {b.barrier_forward:.7f}  backward {b.barrier_backward:.7f}"
          f"  converged {b.converged}{extra} ({time.perf_counter() - t:.0f} s)", flush=True)


def main(meshes: list[int], soft: tuple[int, int], contact: bool) -> None:
    """Print the module doc's rows for each mesh."""
    sec = rectangle(aspect=4.0)
    star = state_assembly("hexagram", sec, "star")
    daisy = state_assembly("hexagram", sec, "daisy")
    model = rod_contact_model(star, H, DHAT)
    w = H + 1.5 * model.dhat
    for n in meshes:
        print(f"{n} el. per rod (cusp width {w:g}):", flush=True)
        kw = dict(elements_per_segment=n, images=17, name_a="star", name_b="daisy")
        _row("no contact, point welds", star, daisy, **kw)
        _row("no contact, wide welds", star, daisy, cusp_width=w, **kw)
        if contact:
            _row("contact, wide welds", star, daisy, cusp_width=w, contact=model, soft=soft,
                 **kw)


if __name__ == "__main__":
    args = sys.argv[1:]
    soft = (60, 14)
    if "--soft" in args:
        i = args.index("--soft")
        soft = (int(args[i + 1]), int(args[i + 2]))
        del args[i:i + 3]
    contact = "--no-contact" not in args
    args = [a for a in args if a != "--no-contact"]
    main([int(a) for a in args] or [6, 8], soft, contact)
