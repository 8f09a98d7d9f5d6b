"""The diagram's held states against the linear engine: band ends on two meshes (issue 22).

A held state's shape does not change with the load factor, so the ends of its stable band in
a :class:`~.diagram.Diagram` are where an eigenvalue of that one state crosses zero. They are
located again on twice the elements, extrapolated (Richardson, order 2) and compared with the
linear engine's interval (:mod:`.atlas`, or `rodstab analyze` for a design that is not a
ring): :func:`held_band_ends`. The status of each end is computed, not asserted.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable

from ..nonlinear.discrete import DiscreteRod
from ..numerics.roots import find_roots
from ..results import Result
from .diagram import LOCATE_RTOL, Diagram, _Unlocated, eigenvalue_at
from .discover import deflated_newton
from .identify import Snapshot


@dataclasses.dataclass(frozen=True)
class BandEnd(Result):
    """One end of a held state's stable band: the diagram's, the finer mesh's, the atlas's.

    ``coarse``: located on the diagram's mesh; ``fine``: on twice its elements (same held state,
    same root finder); ``extrapolated``: Richardson (order 2) of the two, ``mesh_error`` =
    ``|coarse - extrapolated|``; ``atlas``: the linear engine's end (:mod:`.atlas`: the Bloch
    method, or the FE engine when the rods differ); ``agrees``:
    ``|atlas - extrapolated| <= AGREE_FRACTION * mesh_error + AGREE_ATOL``, i.e. the
    difference is the mesh's (computed, not asserted). ``fine`` and the rest are None where
    the crossing was not bracketed on the finer mesh.
    """

    state: str
    side: str
    coarse: float
    fine: float | None
    extrapolated: float | None
    mesh_error: float | None
    atlas: float
    agrees: bool | None


#: The finer mesh's band end is sought within this many grid steps of the coarse one.
FINE_WINDOW = 3


def _nearest_crossing(f: Callable[[float], float], x: float, h: float, inside: int
                      ) -> float | None:
    """Return the zero of ``f`` nearest ``x`` where ``f`` turns positive towards ``inside``.

    Every root of ``f`` within :data:`FINE_WINDOW` grid steps ``h`` of ``x``, by the project's
    root finder (:func:`rodstab.numerics.find_roots`, scanned in quarter steps); of those where
    ``f`` changes sign in the sense ``inside`` (+1: negative below, positive above), the one
    nearest ``x``; None if there is none.
    """
    seen: dict[float, float] = {}

    def g(p: float) -> float:
        if p not in seen:
            seen[p] = f(p)
        return seen[p]

    step = 0.25 * h
    # roots to LOCATE_RTOL of a quarter step, as the index changes are to their brackets
    search = find_roots(g, x - FINE_WINDOW * h, x + FINE_WINDOW * h, n_scan=8 * FINE_WINDOW,
                        rel_xtol=LOCATE_RTOL / (8 * FINE_WINDOW))
    good = []
    for r in search.roots:
        a, b = r.bracket if r.kind == "sign-change" else (r.x - step, r.x + step)
        below, above = g(a), g(b)
        if (below < 0 < above) if inside > 0 else (above < 0 < below):
            good.append(r.x)
    return min(good, key=lambda r: abs(r - x), default=None)


#: A band end agrees with the atlas when the extrapolated end is this fraction of the coarse
#: mesh's error from it (plus :data:`AGREE_ATOL`): the mesh explains the difference.
AGREE_FRACTION = 0.25
AGREE_ATOL = 1e-6


def held_band_ends(d: Diagram, atlas: dict[str, tuple[float, float]],
                   fine_rod: Callable[[str], DiscreteRod]) -> tuple[BandEnd, ...]:
    """Compare every held state's band ends in ``d`` with ``atlas`` (label -> interval).

    A held branch's shape does not change with the load factor, so its band ends are where an
    eigenvalue of that one state crosses zero; they are located again on ``fine_rod(label)``
    (the same state with twice the elements per rod) inside the coarse bracket widened by a
    grid step, and extrapolated. Ends at the range's edge (not crossings) are not compared.
    """
    out = []
    h = d.values[1] - d.values[0]
    for b in d.branches:
        if b.label not in atlas or b.found_from != f"seed {b.label}":
            continue
        for lo, hi in d.bands.get(b.id, ()):
            for side, x, ref in (("lower", lo, atlas[b.label][0]),
                                 ("upper", hi, atlas[b.label][1])):
                if x in (d.values[0], d.values[-1]):
                    continue
                rod = fine_rod(b.label)
                if not deflated_newton(rod, []).converged:  # as built it is not the model's
                    out.append(BandEnd(b.label, side, x, None, None, None, ref, None))
                    continue

                state = Snapshot.of(rod)

                def f(p: float, rod: DiscreteRod = rod, state: Snapshot = state) -> float:
                    return eigenvalue_at(rod, state, p, 0)

                try:
                    fine = _nearest_crossing(f, x, h, +1 if side == "lower" else -1)
                except _Unlocated:
                    fine = None
                if fine is None:
                    out.append(BandEnd(b.label, side, x, None, None, None, ref, None))
                    continue
                ext = fine + (fine - x) / 3.0  # Richardson, ratio 2, order 2
                err = abs(x - ext)
                out.append(BandEnd(b.label, side, x, fine, ext, err, ref,
                                   abs(ref - ext) <= AGREE_FRACTION * err + AGREE_ATOL))
    return tuple(out)
