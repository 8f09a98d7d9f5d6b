"""The meshes the discrete rod can represent: element counts, their checks, cusp offsets.

Split from :mod:`.discrete`, which re-exports every name. The limits come from the Cayley
measure of the rotation between neighbouring frames and from the energy's range.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from ..errors import RodstabInputError, require_finite, require_positive
from ..model import Assembly

__all__ = ["MAX_ELEMENT_TURNING", "MAX_NATURAL_TURNING", "check_mesh", "cusp_offsets",
           "element_counts"]

#: Largest held turning of one element (rad): the rotation between neighbouring edge frames is
#: stored as a Cayley vector ~ tan(theta / 2), singular at a half turn; 3/4 of it (a 3-loop
#: ring of 8 elements, used by the tests) keeps tan(theta / 2) below 2.5.
MAX_ELEMENT_TURNING = 0.75 * math.pi
#: Largest |load factor x natural curvature x length| of a segment: far beyond any held state
#: (a rod of natural radius 1e-8 of its length) and far from the energy's overflow.
MAX_NATURAL_TURNING = 1e8


def element_counts(a: Assembly, elements_per_segment: int | dict[str, int]) -> dict[str, int]:
    """Return the elements of each segment (by name): one count for all, or one per segment.

    As the linear engine's ``elements_per_segment``
    (:func:`rodstab.linear.solve.linear_stability`). Raises :class:`RodstabInputError` naming
    a count that is not an integer >= 2, or a segment without one.
    """
    if isinstance(elements_per_segment, dict):
        missing = [s.name for s in a.segments if s.name not in elements_per_segment]
        if missing:
            raise RodstabInputError(f"elements_per_segment has no count for segment(s) "
                                    f"{missing}")
        counts = {s.name: elements_per_segment[s.name] for s in a.segments}
    else:
        counts = {s.name: elements_per_segment for s in a.segments}
    for name, n in counts.items():
        if isinstance(n, bool) or not isinstance(n, (int, np.integer)) or n < 2:
            raise RodstabInputError(f"elements_per_segment must be an integer >= 2, got "
                                    f"{n!r}" + (f" for segment {name!r}"
                                                if isinstance(elements_per_segment, dict)
                                                else ""))
    return {name: int(n) for name, n in counts.items()}


def check_mesh(a: Assembly, elements_per_segment: int | dict[str, int],
               load_factor: float) -> None:
    """Refuse a mesh or load the discrete rod cannot represent, naming what to change.

    Every element turns by less than :data:`MAX_ELEMENT_TURNING` in the held state (a 3-loop
    ring of 3 elements would have each element close on itself), and every segment's natural
    turning ``|load_factor kappa_n L|`` is finite and at most :data:`MAX_NATURAL_TURNING`.
    ``elements_per_segment``: one count, or a count per segment name.
    """
    mu = require_finite("load factor", load_factor)
    counts = element_counts(a, elements_per_segment)
    for s in a.segments:
        turn = abs(s.curvature) * s.length / counts[s.name]
        if turn > MAX_ELEMENT_TURNING * (1 + 1e-12):
            need = math.ceil(abs(s.curvature) * s.length / MAX_ELEMENT_TURNING)
            raise RodstabInputError(
                f"elements per segment {counts[s.name]}: an element of segment "
                f"{s.name!r} turns by {math.degrees(turn):.4g} deg in the held state, the "
                f"discrete rod allows at most {math.degrees(MAX_ELEMENT_TURNING):g}; use at "
                f"least {need} elements")
        natural = abs(mu * s.natural_curvature) * s.length
        if not natural <= MAX_NATURAL_TURNING:  # also catches inf and nan
            raise RodstabInputError(
                f"load factor {load_factor:g}: segment {s.name!r} would have a natural "
                f"turning |load factor x natural_curvature x length| = {natural:.3g} rad, "
                f"above {MAX_NATURAL_TURNING:g}")


def cusp_offsets(a: Assembly, joints: list[Any], width: float | None
                  ) -> dict[tuple[str, str], np.ndarray]:
    """Return the offsets (lab frame) of the segment ends at every cusp weld of ``width``.

    A cusp: a joint of two segment ends whose outward tangents are equal (to 1e-9). Each end
    goes ``width / 2`` across the tangent in the plane, to the side its segment curves towards
    (the first-listed to ``+n``, ``n = e3 x t``, when they curve alike);
    :func:`~.discrete.discretise`'s ``cusp_width``. ``{}`` for ``width`` None or 0.
    """
    if width is None or width == 0.0:
        return {}
    w = require_positive("cusp_width", width)
    out: dict[tuple[str, str], np.ndarray] = {}
    for joint in joints:
        if len(joint) != 2:
            continue
        leave, bend = [], []
        for name, end in joint:
            seg = a.segment(name)
            s0, sign = (0.0, 1.0) if end == "start" else (seg.length, -1.0)
            t = sign * np.asarray(seg.tangent(s0), float)
            d = 1e-3 * seg.length
            b = np.asarray(seg.position(s0 + sign * d), float) - seg.position(s0)
            leave.append(np.array([t[0], t[1], 0.0]))
            bend.append(np.array([b[0], b[1], 0.0]))
        if float(np.dot(leave[0], leave[1])) < 1.0 - 1e-9:
            continue
        n = np.cross([0.0, 0.0, 1.0], leave[0])
        side = [float(np.sign(np.dot(b, n))) for b in bend]
        if side[0] == side[1] or 0.0 in side:
            side = [1.0, -1.0]
        for (name, end), sgn in zip(joint, side, strict=True):
            out[(name, end)] = 0.5 * w * sgn * n
    return out


def read_end_offsets(a: Assembly, offsets: dict[tuple[str, str], Any] | None
                 ) -> dict[tuple[str, str], np.ndarray]:
    """Return :func:`~.discrete.discretise`'s ``end_offsets`` checked: segment ends to 3-vectors."""
    out = {}
    for key, value in (offsets or {}).items():
        if not (isinstance(key, tuple) and len(key) == 2 and key[1] in ("start", "end")):
            raise RodstabInputError(f"end_offsets keys must be (segment, 'start' | 'end'), "
                                    f"got {key!r}")
        a.segment(key[0])  # raises naming an unknown segment
        v = np.asarray(value, float)
        if v.shape != (3,) or not np.all(np.isfinite(v)):
            raise RodstabInputError(f"end_offsets[{key!r}] must be a finite (x, y, z), got "
                                    f"{value!r}")
        out[(str(key[0]), str(key[1]))] = v
    return out
