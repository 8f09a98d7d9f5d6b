"""Closed planar held states of uniform moment of a ring of identical welded rods.

A ring of ``n`` identical rods of length ``L``, rod ``i`` welded end to start to rod ``i + 1``
(rod ``n`` to rod 1), each weld either a **cusp** (the tangent reverses, the plane normal is
shared; the curved-sided hexagram of Lu, Leanza, Zhao and Hutchinson has six) or **smooth**
(the tangent continues). A planar held state of uniform moment has every rod a circular arc of
the same signed held curvature ``k`` (moment balance at a two-rod weld, checked by
:func:`rodstab.model.validate`, forces ``k`` equal on both sides), turning by
``theta = k L``. Closure, derived here and solved, not assumed:

* rotation: the tangent turns by ``psi = theta + pi`` from rod to rod at a cusp (``theta`` at a
  smooth weld), and must come back after ``n`` rods: ``n psi = 0 (mod 2 pi)``, i.e.
  ``theta = 2 pi j / n - pi`` (cusps) or ``theta = 2 pi j / n`` (smooth), ``j`` integer
  (:func:`rotation_closing_turnings`);
* position: rod ``i``'s chord is the first one rotated by ``i psi``, so the chords sum to
  ``c sum_i exp(i i psi)``: zero when ``exp(i psi) != 1`` (the ``n``-th roots of unity sum to
  zero), else only when the chord ``c = L sinc(theta / 2)`` vanishes (``theta = 2 pi m``,
  ``m != 0``: every rod a full circle).

The candidates of the rotation condition are built as an :class:`~rodstab.model.Assembly`
(chained rod by rod, :func:`ring_assembly`) and kept only if the chain closes (gap and tangent
mismatch below :data:`CLOSURE_TOL`) and the assembly validates; ``tests/test_states.py`` checks
the kept set against the position condition above. Each state's invariants are measured on the
built assembly: distinct weld points, the covering multiplicity (rods lying on rod 1: the state
is an ``n / c``-rod state traversed ``c`` times), the turning number ``n theta / (2 pi)`` (the
total turning of the arcs in full turns; the cusps' reversals are not counted), and the stored
energy ``n B3 (k - kappa_n)^2 L / 2`` at a given natural curvature ``kappa_n``. The mirror state
(``theta -> -theta``: the same shape reflected, its held curvature against the natural one)
closes whenever the state does.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from .errors import RodstabInputError, require_finite, require_positive, require_positive_int
from .model import Assembly, Segment
from .results import Result

#: The chain of rods closes when its end is within this times the ring's total length of its
#: start and the tangents agree to this (radians).
CLOSURE_TOL = 1e-9
#: Weld points (and rods) closer than this times the rod length are the same point (rod).
SAME_POINT_TOL = 1e-7
#: Largest turning of one rod, in full turns, that :func:`closed_states` enumerates.
MAX_TURNS_LIMIT = 20.0
#: Largest number of rods of a ring.
MAX_SEGMENTS = 1000
#: Weld kinds: the tangent reverses (``cusp``) or continues (``smooth``).
WELDS = ("cusp", "smooth")


@dataclasses.dataclass(frozen=True)
class HeldState(Result):
    """One closed planar held state of uniform moment of the ring.

    Attributes
    ----------
    label : str
        ``line``, ``star``, ``daisy``, ``eight`` for an even ring of ``n >= 4`` cusp-welded rods
        (``mirror-`` prefixed for ``theta < 0``), ``circle-<j>`` for a smooth ring (a circle
        covered ``j`` times), else ``theta=<deg>deg``.
    theta : float
        Turning of each rod ``k L`` (radians, signed, positive turning left).
    held_curvature : float
        ``k = theta / L``.
    turning_number : float
        ``n theta / (2 pi)``: the arcs' total turning in full turns (cusps not counted).
    distinct_weld_points : int
        Number of distinct points at which the ``n`` welds lie.
    covering : int
        How many rods lie on rod 1 (itself included): the state is an ``n / covering``-rod
        state traversed ``covering`` times.
    energy : float
        Stored energy ``n B3 (k - kappa_n)^2 L / 2`` at the requested natural curvature.
    mirror : str
        Label of the mirror state (``theta -> -theta``; itself for ``theta = 0``).
    closure_gap : float
        Distance from the chain's end to its start, over the total length (<= CLOSURE_TOL).
    """

    label: str
    theta: float
    held_curvature: float
    turning_number: float
    distinct_weld_points: int
    covering: int
    energy: float
    mirror: str
    closure_gap: float


@dataclasses.dataclass(frozen=True)
class RingStates(Result):
    """The closed held states of a ring: its description and the states by increasing turning."""

    segments: int
    weld: str
    length: float
    natural_curvature: float
    max_turns: float
    states: tuple[HeldState, ...]
    method: str


def _require_weld(weld: str) -> str:
    if weld not in WELDS:
        raise RodstabInputError(f"weld must be one of {WELDS}, got {weld!r}")
    return weld


def _require_segments(segments: int) -> int:
    n = require_positive_int("segments", segments)
    if n > MAX_SEGMENTS:
        raise RodstabInputError(f"segments must be at most {MAX_SEGMENTS}, got {segments!r}")
    return n


def step_angle(theta: float, weld: str) -> float:
    """Rotation ``psi`` of the tangent from one rod's start to the next one's (radians).

    ``psi = theta + pi`` across a cusp, ``theta`` across a smooth weld.
    """
    return theta + (math.pi if _require_weld(weld) == "cusp" else 0.0)


def rotation_closing_turnings(segments: int, weld: str, max_turns: float) -> list[float]:
    """Every ``theta`` in ``[-2 pi max_turns, 2 pi max_turns]`` with ``n psi = 0 (mod 2 pi)``.

    ``theta = 2 pi j / n - pi`` (cusps) or ``2 pi j / n`` (smooth), ``j`` integer; increasing.
    """
    n = _require_segments(segments)
    offset = -math.pi if _require_weld(weld) == "cusp" else 0.0
    top = 2 * math.pi * max_turns
    j_lo = math.ceil((-top - offset) * n / (2 * math.pi) - 1e-9)
    j_hi = math.floor((top - offset) * n / (2 * math.pi) + 1e-9)
    return [2 * math.pi * j / n + offset for j in range(j_lo, j_hi + 1)]


def ring_assembly(segments: int, theta: float, *, weld: str = "cusp", length: float = 1.0,
                  natural_curvature: float = 0.0, B1: float = 1.0, B2: float = 1.0,
                  B3: float = 1.0, reference_load: float | None = None) -> Assembly:
    """Chain ``segments`` arcs of turning ``theta`` from the origin and weld them into a ring.

    Rod 1 starts at the origin along ``+x``; rod ``i + 1`` starts at rod ``i``'s end with the
    tangent continued (smooth) or reversed (cusp). Every rod has held curvature
    ``theta / length`` and natural curvature ``natural_curvature`` (per unit load factor).
    :func:`rodstab.model.validate` (run by :class:`~rodstab.model.Assembly`) refuses a chain
    whose last end does not meet the first start, naming the gap.
    """
    n = _require_segments(segments)
    require_positive("length", length)
    require_finite("theta", theta)
    k = theta / length
    segs = []
    pos, ang = (0.0, 0.0), 0.0
    flip = math.pi if _require_weld(weld) == "cusp" else 0.0
    for i in range(1, n + 1):
        s = Segment(name=str(i), length=length, curvature=k, natural_curvature=natural_curvature,
                    B1=B1, B2=B2, B3=B3, start=pos, angle=ang)
        segs.append(s)
        end = s.end_point("end")
        pos = (float(end[0]), float(end[1]))
        ang = math.remainder(ang + theta + flip, 2 * math.pi)
    welds = tuple(((str(i), "end"), (str(i % n + 1), "start")) for i in range(1, n + 1))
    return Assembly(segments=tuple(segs), welds=welds, reference_load=reference_load)


def _chain_gap(segments: int, theta: float, weld: str, length: float) -> tuple[float, float]:
    """Position gap (over the total length) and tangent mismatch after chaining the rods."""
    psi = step_angle(theta, weld)
    pos = np.zeros(2)
    ang = 0.0
    for _ in range(segments):
        chord = length * float(np.sinc(0.5 * theta / math.pi))
        pos = pos + chord * np.array([math.cos(ang + 0.5 * theta), math.sin(ang + 0.5 * theta)])
        ang += psi
    tangent_gap = abs(math.remainder(ang, 2 * math.pi))
    return float(np.linalg.norm(pos)) / (segments * length), tangent_gap


def _weld_points(a: Assembly) -> np.ndarray:
    """Positions ``(n_welds, 2)`` of the welds of ``a``, held state, lab frame."""
    return np.array([a.segment(w[0][0]).end_point(w[0][1]) for w in a.welds])


def _count_distinct(points: np.ndarray, tol: float) -> int:
    distinct: list[np.ndarray] = []
    for p in points:
        if not any(float(np.linalg.norm(p - q)) <= tol for q in distinct):
            distinct.append(p)
    return len(distinct)


def _covering(a: Assembly, tol: float) -> int:
    """Rods whose centreline coincides with rod 1's (same start, same tangent), rod 1 included."""
    first = a.segments[0]
    t0 = first.tangent(0.0)
    return sum(1 for s in a.segments
               if float(np.linalg.norm(s.end_point("start") - first.end_point("start"))) <= tol
               and float(np.linalg.norm(s.tangent(0.0) - t0)) <= tol)


def state_label(segments: int, theta: float, weld: str) -> str:
    """Name of the state of turning ``theta`` (see :class:`HeldState`)."""
    n = segments
    theta = 0.0 if abs(theta) <= 1e-12 else theta  # no "-0"
    deg = math.degrees(theta)
    prefix = "mirror-" if theta < 0 else ""
    if weld == "smooth":
        j = round(n * theta / (2 * math.pi))
        return f"{prefix}circle-{abs(j)}"
    if n >= 4 and n % 2 == 0:
        named = {"line": 0.0, "star": math.pi - 2 * math.pi / n,
                 "daisy": math.pi + 2 * math.pi / n, "eight": 2 * math.pi}
        for name, value in named.items():
            if abs(abs(theta) - value) <= 1e-9:
                return name if value == 0.0 else prefix + name
    return f"theta={deg:.6g}deg"


def closed_states(segments: int, *, weld: str = "cusp", length: float = 1.0,
                  natural_curvature: float = 0.0, B3: float = 1.0,
                  max_turns: float = 1.0) -> RingStates:
    """Enumerate the closed planar held states of uniform moment of a ring (module docstring).

    Parameters
    ----------
    segments : int
        Number ``n`` of identical rods, ``1 <= n <=`` :data:`MAX_SEGMENTS`.
    weld : {"cusp", "smooth"}
        Every weld reverses the tangent (cusp) or continues it (smooth).
    length : float
        Length ``L`` of each rod.
    natural_curvature : float
        ``kappa_n`` (1/length, signed like the held curvature) at which the energy is given.
    B3 : float
        In-plane bending stiffness (energy only).
    max_turns : float
        States with ``|theta| <= 2 pi max_turns`` are listed (``0 < max_turns <=``
        :data:`MAX_TURNS_LIMIT`).

    Returns
    -------
    RingStates
        The states by increasing ``theta``. Raises :class:`RodstabInputError` naming
        ``segments`` when no state closes in the range (e.g. one rod with a cusp).
    """
    n = _require_segments(segments)
    _require_weld(weld)
    require_positive("length", length)
    require_finite("natural_curvature", natural_curvature)
    require_positive("B3", B3)
    if not (isinstance(max_turns, (int, float)) and 0 < max_turns <= MAX_TURNS_LIMIT):
        raise RodstabInputError(f"max_turns must be in (0, {MAX_TURNS_LIMIT:g}], got "
                                f"{max_turns!r}")
    found = []
    for theta in rotation_closing_turnings(n, weld, max_turns):
        gap, tangent_gap = _chain_gap(n, theta, weld, length)
        if gap > CLOSURE_TOL or tangent_gap > CLOSURE_TOL:
            continue  # the chords do not sum to zero: the chain is open
        a = ring_assembly(n, theta, weld=weld, length=length)  # validate: ends meet, balance
        tol = SAME_POINT_TOL * length
        k = theta / length
        found.append(HeldState(
            label=state_label(n, theta, weld), theta=theta, held_curvature=k,
            turning_number=n * theta / (2 * math.pi),
            distinct_weld_points=_count_distinct(_weld_points(a), tol),
            covering=_covering(a, tol),
            energy=0.5 * n * B3 * (k - natural_curvature) ** 2 * length,
            mirror=state_label(n, -theta, weld), closure_gap=gap))
    if not found:
        raise RodstabInputError(
            f"segments {n} with {weld} welds: no closed state with |theta| <= "
            f"{max_turns:g} turns per rod (a ring of {n} {weld}-welded rod"
            f"{'s' if n > 1 else ''} cannot close{' in this range' if n > 1 else ''})")
    return RingStates(segments=n, weld=weld, length=length, natural_curvature=natural_curvature,
                      max_turns=max_turns, states=tuple(found),
                      method="rotation closure n psi = 0 mod 2 pi, chains built and validated")


def state_turning(segments: int, weld: str, label: str, max_turns: float = 1.0) -> float:
    """Return ``theta`` of the state called ``label``; raise naming it if there is none."""
    states = closed_states(segments, weld=weld, max_turns=max_turns).states
    for s in states:
        if s.label == label:
            return s.theta
    raise RodstabInputError(f"state {label!r} does not exist for {segments} {weld}-welded "
                            f"rods; the states are {[s.label for s in states]}")


def state_centrelines(ring: RingStates, state: HeldState, n_points: int = 60
                      ) -> list[np.ndarray]:
    """Centreline ``(n_points, 2)`` of every rod of ``state`` (held state, lab frame)."""
    a = ring_assembly(ring.segments, state.theta, weld=ring.weld, length=ring.length)
    return [s.position(np.linspace(0.0, s.length, n_points)) for s in a.segments]
