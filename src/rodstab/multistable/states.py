"""Closed planar held states of uniform moment of a ring of welded rods.

Rods that differ (lengths, sections, natural curvatures, weld angles) are :class:`Ring`'s
general case: there a state is named by its mean turning and closes by the rotation condition
``n theta + sum_i alpha_i = 2 pi j`` and a chain built from each rod's own turning
(:meth:`Ring.states`). The rest of this docstring derives the identical-rod case, whose
closed form the general enumeration reproduces (``tests/test_states.py``).

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
  (:meth:`Ring.rotation_closing`);
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
from typing import Any

import numpy as np

from ..errors import RodstabInputError, require_finite, require_positive, require_positive_int
from ..model import Assembly, Segment
from ..results import Result

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


#: A weld's tangent turn within this (radians) of pi or 0 is a cusp or smooth weld.
WELD_ANGLE_TOL = 1e-7

Weld = str | float


def _require_weld(weld: Weld) -> Weld:
    """Return ``weld``: ``"cusp"``, ``"smooth"``, or a tangent turn in radians in ``(-pi, pi]``.

    A turn within :data:`WELD_ANGLE_TOL` of ``pi`` or ``0`` is returned as ``"cusp"`` or
    ``"smooth"`` (one name per weld kind, so labels and the Bloch method recognise it).
    """
    if isinstance(weld, str):
        if weld not in WELDS:
            raise RodstabInputError(f"weld must be one of {WELDS} or a turn angle in radians, "
                                    f"got {weld!r}")
        return weld
    if isinstance(weld, bool) or not isinstance(weld, (int, float)) or not math.isfinite(weld):
        raise RodstabInputError(f"weld must be one of {WELDS} or a turn angle in radians, "
                                f"got {weld!r}")
    turn = math.remainder(float(weld), 2 * math.pi)
    if abs(abs(turn) - math.pi) <= WELD_ANGLE_TOL:
        return "cusp"
    if abs(turn) <= WELD_ANGLE_TOL:
        return "smooth"
    return turn


def weld_turn(weld: Weld) -> float:
    """Turn of the tangent across a weld (radians): ``pi`` (cusp), ``0`` (smooth), or ``weld``."""
    w = _require_weld(weld)
    return math.pi if w == "cusp" else 0.0 if w == "smooth" else float(w)


def weld_name(weld: Weld) -> str:
    """``"cusp"``, ``"smooth"`` or the turn in degrees (``"37.5deg"``), for tables and JSON."""
    w = _require_weld(weld)
    return w if isinstance(w, str) else f"{math.degrees(w):.6g}deg"


def _require_segments(segments: int) -> int:
    n = require_positive_int("segments", segments)
    if n > MAX_SEGMENTS:
        raise RodstabInputError(f"segments must be at most {MAX_SEGMENTS}, got {segments!r}")
    return n


def step_angle(theta: float, weld: Weld) -> float:
    """Rotation ``psi`` of the tangent from one rod's start to the next one's (radians).

    ``psi = theta + pi`` across a cusp, ``theta`` across a smooth weld, ``theta + alpha``
    across a weld turning the tangent by ``alpha``.
    """
    return theta + weld_turn(weld)


def ring_assembly(segments: int, theta: float, *, weld: Weld = "cusp", length: float = 1.0,
                  natural_curvature: float = 0.0, B1: float = 1.0, B2: float = 1.0,
                  B3: float = 1.0, reference_load: float | None = None) -> Assembly:
    """Chain ``segments`` arcs of turning ``theta`` from the origin and weld them into a ring.

    Rod 1 starts at the origin along ``+x``; rod ``i + 1`` starts at rod ``i``'s end with the
    tangent continued (smooth) or reversed (cusp). Every rod has held curvature
    ``theta / length`` and natural curvature ``natural_curvature`` (per unit load factor).
    :func:`rodstab.model.validate` (run by :class:`~rodstab.model.Assembly`) refuses a chain
    whose last end does not meet the first start, naming the gap. The ring of rods ``"1"`` ..
    ``"n"`` welded end to start is :meth:`Ring.held` of :func:`uniform_ring`.
    """
    return uniform_ring(segments, weld=weld, length=length,
                        natural_curvature=natural_curvature, B1=B1, B2=B2,
                        B3=B3).held(require_finite("theta", theta), reference_load=reference_load)


@dataclasses.dataclass(frozen=True)
class RingRod:
    """One rod of a ring as the ring traverses it (:attr:`Ring.rods`).

    ``natural_curvature``: per unit load factor, signed with the traversal (a rod run backwards
    carries the opposite of its own). Stiffnesses ``B1, B2, B3`` (force x length^2).
    """

    name: str
    length: float
    natural_curvature: float
    B1: float
    B2: float
    B3: float


@dataclasses.dataclass(frozen=True)
class Ring:
    """A ring of ``segments`` rods, each welded to the next (:func:`ring_of`, :func:`uniform_ring`).

    ``order``: the rods in the order the ring is traversed, each ``(name, direction)`` with
    direction ``+1`` when the ring runs from the rod's start to its end and ``-1`` when it runs
    backwards; ``welds[i]`` joins rod ``i``'s outgoing end to rod ``i + 1``'s incoming end (as
    ``((name, end), (name, end))``) and turns the tangent by ``turns[i]`` (radians,
    :func:`weld_turn`). ``rods[i]``: rod ``i`` along the traversal (:class:`RingRod`). A rod
    traversed backwards carries the opposite signed curvatures in its own frame, which is how
    the folded six-ring of Section 5 (alternately oriented rods with alternating natural
    curvature) is a ring of identical rods.

    **Held states of uniform moment.** Moment balance at every weld at every load factor
    (:func:`rodstab.model.validate`) makes ``c = B3_i k_i`` and ``d = B3_i kappa_n,i`` the same
    in every rod (``k_i`` the held, ``kappa_n,i`` the natural curvature along the traversal),
    so a held state is one number. It is named by the **mean turning** ``theta = sum_i k_i L_i
    / n`` (radians): ``k_i = c / B3_i`` with ``c = n theta / sum_i (L_i / B3_i)``. The
    equivalent identical ring has ``length`` = the mean rod length ``Lbar``, ``B3`` =
    ``sum L_i / sum (L_i / B3_i)`` and ``natural_curvature`` = ``d / B3`` (so that the energy
    ``n B3 (theta / Lbar - mu kappa_n)^2 Lbar / 2`` and the stress-free load
    ``theta / (Lbar kappa_n)`` keep the identical-ring formulas); ``B1, B2`` and ``weld`` are
    rod 1's and weld 1's. They are the ring's own when the rods and welds are all alike
    (:attr:`identical`), which the Bloch method and the named labels need.
    """

    order: tuple[tuple[str, int], ...]
    welds: tuple[tuple[tuple[str, str], tuple[str, str]], ...]
    rods: tuple[RingRod, ...]
    turns: tuple[float, ...]

    @property
    def segments(self) -> int:
        """Number of rods."""
        return len(self.rods)

    @property
    def weld(self) -> Weld:
        """Weld 1's kind (:func:`_require_weld` of its turn): every weld's when alike."""
        return _require_weld(self.turns[0])

    @property
    def length(self) -> float:
        """Mean rod length ``Lbar``."""
        return math.fsum(r.length for r in self.rods) / self.segments

    @property
    def B3(self) -> float:
        """``sum L_i / sum (L_i / B3_i)``: rod 1's ``B3`` when all agree."""
        b3 = self.rods[0].B3
        if all(r.B3 == b3 for r in self.rods):
            return b3
        return math.fsum(r.length for r in self.rods) / math.fsum(r.length / r.B3
                                                                  for r in self.rods)

    @property
    def natural_curvature(self) -> float:
        """``B3_i kappa_n,i / B3`` (per unit load factor): rod 1's when all ``B3`` agree."""
        r = self.rods[0]
        b3 = self.B3
        return r.natural_curvature if r.B3 == b3 else r.B3 * r.natural_curvature / b3

    @property
    def B1(self) -> float:
        """Rod 1's ``B1``."""
        return self.rods[0].B1

    @property
    def B2(self) -> float:
        """Rod 1's ``B2``."""
        return self.rods[0].B2

    @property
    def identical(self) -> bool:
        """Whether all rods and welds are alike (:meth:`difference` is empty).

        Every rod the same length, stiffnesses and natural curvature along the traversal and
        every weld the same turn of the tangent (to :data:`SAME_ROD_RTOL`).
        """
        return not self.difference()

    def difference(self) -> str:
        """Say how the rods or welds differ (``""`` when the ring is :attr:`identical`)."""
        ref = self.rods[0]
        for r in self.rods[1:]:
            for what in ("length", "B1", "B2", "B3", "natural_curvature"):
                got, want = getattr(r, what), getattr(ref, what)
                if abs(got - want) > SAME_ROD_RTOL * max(abs(want), 1.0):
                    return (f"segment {r.name!r} has {what.replace('_', ' ')} {got:.6g}, "
                            f"segment {ref.name!r} {want:.6g}")
        for i, t in enumerate(self.turns):
            if abs(math.remainder(t - self.turns[0], 2 * math.pi)) > WELD_ANGLE_TOL:
                return (f"weld {i + 1} turns the tangent by {math.degrees(t):.6g} deg, weld 1 "
                        f"by {math.degrees(self.turns[0]):.6g} deg")
        return ""

    def require_identical(self, what: str) -> None:
        """Raise :class:`RodstabInputError` naming ``what`` and the first difference, if any."""
        diff = self.difference()
        if diff:
            raise RodstabInputError(f"{what} needs a ring of identical rods and welds: {diff}")

    @property
    def weld_label(self) -> str:
        """:func:`weld_name` of the welds when alike, else every weld's turn in degrees."""
        if all(abs(math.remainder(t - self.turns[0], 2 * math.pi)) <= WELD_ANGLE_TOL
               for t in self.turns):
            return weld_name(self.weld)
        return "mixed (" + ", ".join(f"{math.degrees(t):.6g}" for t in self.turns) + " deg)"

    def curvatures(self, theta: float) -> np.ndarray:
        """Held curvature ``k_i`` of every rod (1/length) of the state of mean turning ``theta``."""
        compliance = np.array([r.length / r.B3 for r in self.rods])
        c = self.segments * theta / float(compliance.sum())
        return np.array([c / r.B3 for r in self.rods])

    def held(self, theta: float, *, reference_load: float | None = None) -> Assembly:
        """Return the ring held with every rod an arc, mean turning ``theta`` (radians).

        Rod ``i`` turns by ``k_i L_i`` (:meth:`curvatures`). Rod 1 starts at the origin along
        ``+x`` (along the traversal); each next rod starts where the previous one ends with the
        tangent turned by its weld. The segments keep their names and directions (a backwards
        rod gets start, angle and curvatures of the reversed arc), so the held states of one
        design are one assembly's states. :func:`rodstab.model.validate` refuses a chain that
        does not close, naming the gap.
        """
        segs = []
        pos, ang = np.zeros(2), 0.0
        for (name, d), rod, k, alpha in zip(self.order, self.rods, self.curvatures(theta),
                                            self.turns, strict=True):
            k = float(k)
            probe = Segment(name=name, length=rod.length, curvature=k, natural_curvature=0.0,
                            B1=rod.B1, B2=rod.B2, B3=rod.B3,
                            start=(float(pos[0]), float(pos[1])), angle=ang)
            end = probe.end_point("end")
            if d > 0:
                segs.append(dataclasses.replace(probe, natural_curvature=rod.natural_curvature))
            else:
                segs.append(dataclasses.replace(
                    probe, curvature=-k, natural_curvature=-rod.natural_curvature,
                    start=(float(end[0]), float(end[1])), angle=ang + k * rod.length + math.pi))
            pos = end
            ang = math.remainder(ang + k * rod.length + alpha, 2 * math.pi)
        return Assembly(segments=tuple(segs), welds=self.welds, reference_load=reference_load)

    def forward(self) -> Ring:
        """Return this ring with every rod run from its start to its end (same names).

        A backwards rod becomes the same rod described from its other end (its natural
        curvature along the ring unchanged), so code that walks a ring rod by rod from start to
        end (contact, transitions) sees the ring as it is traversed.
        """
        welds = tuple(((self.order[i][0], "end"), (self.order[(i + 1) % self.segments][0],
                                                    "start")) for i in range(self.segments))
        return dataclasses.replace(self, order=tuple((nm, 1) for nm, _ in self.order),
                                   welds=welds)

    def stress_free_load(self, theta: float) -> float | None:
        """Load factor at which the held state ``theta`` is stress-free (``None`` if none)."""
        if self.natural_curvature == 0.0:
            return None
        return theta / (self.length * self.natural_curvature)

    def states(self, *, load_factor: float = 1.0, max_turns: float = 1.0) -> RingStates:
        """Return the closed planar held states of uniform moment, energies at a load.

        ``load_factor`` scales :attr:`natural_curvature`; states with
        ``|theta| <= 2 pi max_turns`` (``0 < max_turns <=`` :data:`MAX_TURNS_LIMIT`) by
        increasing ``theta``. Raises :class:`RodstabInputError` naming the ring when none
        closes.
        """
        require_finite("load_factor", load_factor)
        if not (isinstance(max_turns, (int, float)) and 0 < max_turns <= MAX_TURNS_LIMIT):
            raise RodstabInputError(f"max_turns must be in (0, {MAX_TURNS_LIMIT:g}], got "
                                    f"{max_turns!r}")
        n, L = self.segments, self.length
        kappa = self.natural_curvature * load_factor
        alike = self.weld_label == weld_name(self.weld)
        found = []
        for theta in self.rotation_closing(max_turns):
            gap, tangent_gap = self.chain_gap(theta)
            if gap > CLOSURE_TOL or tangent_gap > CLOSURE_TOL:
                continue  # the chords do not sum to zero: the chain is open
            a = self.held(theta)  # validate: ends meet, moments balance
            tol = SAME_POINT_TOL * min(r.length for r in self.rods)
            k = theta / L
            found.append(HeldState(
                label=self.label(theta), theta=theta, held_curvature=k,
                turning_number=n * theta / (2 * math.pi),
                distinct_weld_points=distinct_points(_weld_points(a), tol),
                covering=_covering(a, self.order, tol),
                energy=0.5 * n * self.B3 * (k - kappa) ** 2 * L,
                mirror=self.label(-theta) if alike else "", closure_gap=gap))
        if not found:
            kind = self.weld_label
            if not self.identical:
                raise RodstabInputError(
                    f"no planar held state of uniform moment of this ring closes with |mean "
                    f"turning| <= {max_turns:g} turns per rod (its rods differ: "
                    f"{self.difference()}; each rod is an arc only if the chords of the arcs "
                    "sum to zero): its equilibria are elasticas, for the nonlinear engine "
                    "(rodstab equilibrium, discover, diagram)")
            raise RodstabInputError(
                f"segments {n} with {kind} welds: no closed state with |theta| <= "
                f"{max_turns:g} turns per rod (a ring of {n} {kind}-welded rod"
                f"{'s' if n > 1 else ''} cannot close{' in this range' if n > 1 else ''})")
        return RingStates(segments=n, weld=self.weld_label, length=L,
                          natural_curvature=kappa, max_turns=max_turns, states=tuple(found),
                          method="rotation closure sum_i (k_i L_i + weld turn_i) = 0 mod 2 pi "
                                 "with B3_i k_i equal, chains built and validated")

    def rotation_closing(self, max_turns: float) -> list[float]:
        """Return the mean turnings whose rods and welds turn the tangent by whole turns.

        Every ``theta`` in ``[-2 pi max_turns, 2 pi max_turns]`` with ``n theta + sum_i
        alpha_i = 2 pi j`` (``alpha_i`` the welds' turns, ``j`` integer), increasing.
        """
        n = self.segments
        offset = -math.fsum(self.turns) / n
        top = 2 * math.pi * max_turns
        j_lo = math.ceil((-top - offset) * n / (2 * math.pi) - 1e-9)
        j_hi = math.floor((top - offset) * n / (2 * math.pi) + 1e-9)
        return [2 * math.pi * j / n + offset for j in range(j_lo, j_hi + 1)]

    def chain_gap(self, theta: float) -> tuple[float, float]:
        """Position gap (over the total length) and tangent mismatch after chaining the arcs.

        Rod ``i``'s chord ``L_i sinc(theta_i / 2)`` points along the tangent turned by half its
        turning ``theta_i = k_i L_i``; the next rod starts turned by ``theta_i + alpha_i``.
        """
        pos = np.zeros(2)
        ang = 0.0
        for rod, k, alpha in zip(self.rods, self.curvatures(theta), self.turns, strict=True):
            th = float(k) * rod.length
            chord = rod.length * float(np.sinc(0.5 * th / math.pi))
            pos = pos + chord * np.array([math.cos(ang + 0.5 * th), math.sin(ang + 0.5 * th)])
            ang += th + alpha
        total = math.fsum(r.length for r in self.rods)
        return float(np.linalg.norm(pos)) / total, abs(math.remainder(ang, 2 * math.pi))

    def label(self, theta: float) -> str:
        """Name the state of mean turning ``theta`` (:func:`state_label`).

        With welds that differ: ``theta=<deg>deg``.
        """
        alike = self.weld_label == weld_name(self.weld)
        return state_label(self.segments, theta, self.weld if alike else float("nan"))

    def state(self, label: str, max_turns: float = 1.0) -> HeldState:
        """Return the state called ``label``; raise naming it and listing the states if none."""
        listed = self.states(max_turns=max_turns).states
        for st in listed:
            if st.label == label:
                return st
        raise RodstabInputError(f"state {label!r} does not exist for this ring of "
                                f"{self.segments} {weld_name(self.weld)}-welded rods; the "
                                f"states are {[st.label for st in listed]}")


def uniform_ring(segments: int, *, weld: Weld = "cusp", length: float = 1.0,
                 natural_curvature: float = 0.0, B1: float = 1.0, B2: float = 1.0,
                 B3: float = 1.0) -> Ring:
    """Return the ring of rods ``"1"`` .. ``"n"``, each welded end to start to the next."""
    n = _require_segments(segments)
    require_positive("length", length)
    require_finite("natural_curvature", natural_curvature)
    for key, v in (("B1", B1), ("B2", B2), ("B3", B3)):
        require_positive(key, v)
    names = [str(i) for i in range(1, n + 1)]
    welds = tuple(((names[i], "end"), (names[(i + 1) % n], "start")) for i in range(n))
    rod = RingRod("", float(length), float(natural_curvature), float(B1), float(B2), float(B3))
    return Ring(order=tuple((nm, 1) for nm in names), welds=welds,
                rods=tuple(dataclasses.replace(rod, name=nm) for nm in names),
                turns=(weld_turn(weld),) * n)


#: Rods of a ring read from a design must agree in length, stiffness and natural curvature to
#: this relative tolerance.
SAME_ROD_RTOL = 1e-9


def traversal_angle(seg: Segment, end: str, direction: int) -> float:
    """Held angle of the traversal tangent at ``end`` of ``seg`` (direction ``-1``: reversed)."""
    t = seg.tangent(0.0 if end == "start" else seg.length) * direction
    return math.atan2(float(t[1]), float(t[0]))


def ring_of(a: Any) -> Ring:
    """Read the ring of a design: rods each welded to the next, closing into one cycle.

    ``a``: an :class:`~rodstab.model.Assembly`, or a parsed design
    (:class:`rodstab.io.design.Design`, from ``load_design``), whose assembly is read.

    The assembly must have no supports or imposed end rotations, every weld must join two
    ends, and following the welds from the first segment must visit every segment once and
    come back. Along that traversal (turned round if needed so that rod 1's natural curvature
    is ``>= 0``) the rods have no natural twist and equal ``B3`` x natural curvature (which
    :func:`rodstab.model.validate` already requires); their lengths, sections and natural
    curvatures may differ, and each weld's turn of the tangent (measured on the design's held
    geometry) is its own (:class:`Ring`; :attr:`Ring.identical` says whether all agree).
    Each violation is a :class:`RodstabInputError` naming the segment or weld and its value.
    """
    if not isinstance(a, Assembly) and isinstance(getattr(a, "assembly", None), Assembly):
        a = a.assembly
    if not isinstance(a, Assembly):
        raise RodstabInputError(f"ring_of needs an Assembly or a design from load_design, got "
                                f"{type(a).__name__}")
    if a.supports or a.end_rotations:
        raise RodstabInputError(f"a ring has no supports; the design has {list(a.supports)!r}")
    for w in a.welds:
        if len(w) != 2:
            raise RodstabInputError(f"every weld of a ring joins two ends, got "
                                    f"{[f'{nm}.{e}' for nm, e in w]}")
    partner = {}
    for (n1, e1), (n2, e2) in a.welds:
        partner[(n1, e1)], partner[(n2, e2)] = (n2, e2), (n1, e1)
    first = a.segments[0].name
    order: list[tuple[str, int]] = [(first, 1)]
    welds = []
    while True:
        name, d = order[-1]
        out_end = "end" if d > 0 else "start"
        if (name, out_end) not in partner:
            raise RodstabInputError(f"the ring is open: end {name}.{out_end} is not welded")
        nxt, in_end = partner[(name, out_end)]
        welds.append(((name, out_end), (nxt, in_end)))
        if nxt == first:
            if in_end != "start":
                raise RodstabInputError(f"the welds do not form a ring: {name}.{out_end} is "
                                        f"welded to {nxt}.{in_end}")
            break
        if any(nxt == nm for nm, _ in order):
            raise RodstabInputError(f"the welds do not form a ring: segment {nxt!r} is reached "
                                    "twice")
        order.append((nxt, 1 if in_end == "start" else -1))
    missing = [s.name for s in a.segments if s.name not in dict(order)]
    if missing:
        raise RodstabInputError(f"the welds form more than one ring: segments {missing} are not "
                                f"on the ring through {first!r}")
    segs = [a.segment(nm) for nm, _ in order]
    kappa = [d * s.natural_curvature for s, (_, d) in zip(segs, order, strict=True)]
    if kappa[0] < 0 or (kappa[0] == 0 and order[0][1] * segs[0].curvature < 0):
        # run the other way round, so the natural curvature (or the held one) is >= 0
        order = [(nm, -d) for nm, d in reversed(order)]
        welds = [(w[1], w[0]) for w in reversed(welds)]
        order = order[-1:] + order[:-1]  # the welds need no turning: they start at rod 1
        segs = [a.segment(nm) for nm, _ in order]
        kappa = [d * s.natural_curvature for s, (_, d) in zip(segs, order, strict=True)]
    ref = segs[0]
    for s, k in zip(segs, kappa, strict=True):
        # validate() balances B3 x natural curvature at every weld; checked again so a ring
        # built around it says what the held states need.
        moment, moment_ref = s.B3 * k, ref.B3 * kappa[0]
        if abs(moment - moment_ref) > SAME_ROD_RTOL * max(abs(moment_ref), 1e-300):
            raise RodstabInputError(
                f"segment {s.name!r} has B3 x natural curvature along the ring {moment!r}, "
                f"segment {ref.name!r} {moment_ref!r}: the held states need them equal "
                "(moment balance at every weld at every load factor)")
        if s.natural_twist != 0.0:
            raise RodstabInputError(f"segment {s.name!r} has natural_twist {s.natural_twist!r}: "
                                    "the ring states are planar rods without natural twist")
    dirs = dict(order)
    turns = []
    for (n1, e1), (n2, e2) in welds:
        t_out = traversal_angle(a.segment(n1), e1, dirs[n1])
        t_in = traversal_angle(a.segment(n2), e2, dirs[n2])
        turns.append(weld_turn(math.remainder(t_in - t_out, 2 * math.pi)))
    rods = tuple(RingRod(s.name, s.length, k, s.B1, s.B2, s.B3)
                 for s, k in zip(segs, kappa, strict=True))
    return Ring(order=tuple(order), welds=tuple(welds), rods=rods, turns=tuple(turns))


def _weld_points(a: Assembly) -> np.ndarray:
    """Positions ``(n_welds, 2)`` of the welds of ``a``, held state, lab frame."""
    return np.array([a.segment(w[0][0]).end_point(w[0][1]) for w in a.welds])


def distinct_points(points: np.ndarray, tol: float) -> int:
    """Points ``(n, 3)`` counted once within ``tol`` (a length) of one counted before them.

    The one count of distinct weld points: of a held state here, of a discrete state in
    :func:`rodstab.multistable.identify.invariants`.
    """
    kept: list[np.ndarray] = []
    for p in points:
        if not any(float(np.linalg.norm(p - q)) <= tol for q in kept):
            kept.append(p)
    return len(kept)


def _covering(a: Assembly, order: tuple[tuple[str, int], ...], tol: float) -> int:
    """Rods lying on rod 1 traversed alike (same start, same tangent along the ring), itself too.

    Starts and tangents are the traversal's: a rod run backwards starts at its own end.
    """
    def start_and_tangent(name: str, d: int) -> tuple[np.ndarray, np.ndarray]:
        seg = a.segment(name)
        if d > 0:
            return seg.end_point("start"), seg.tangent(0.0)
        return seg.end_point("end"), -seg.tangent(seg.length)

    p0, t0 = start_and_tangent(*order[0])
    return sum(1 for nm, d in order
               if float(np.linalg.norm(start_and_tangent(nm, d)[0] - p0)) <= tol
               and float(np.linalg.norm(start_and_tangent(nm, d)[1] - t0)) <= tol)


def state_label(segments: int, theta: float, weld: Weld) -> str:
    """Name of the state of turning ``theta`` (see :class:`HeldState`)."""
    n = segments
    theta = 0.0 if abs(theta) <= 1e-12 else theta  # no "-0"
    deg = math.degrees(theta)
    prefix = "mirror-" if theta < 0 else ""
    if weld == "smooth":
        j = round(n * theta / (2 * math.pi))
        return f"{prefix}circle-{abs(j)}"
    if weld == "cusp" and n >= 4 and n % 2 == 0:
        named = {"line": 0.0, "star": math.pi - 2 * math.pi / n,
                 "daisy": math.pi + 2 * math.pi / n, "eight": 2 * math.pi}
        for name, value in named.items():
            if abs(abs(theta) - value) <= 1e-9:
                return name if value == 0.0 else prefix + name
    return f"theta={deg:.6g}deg"


def closed_states(segments: int, *, weld: Weld = "cusp", length: float = 1.0,
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
    return uniform_ring(segments, weld=weld, length=length,
                        natural_curvature=natural_curvature, B3=B3).states(max_turns=max_turns)


def state_centrelines(ring: Ring, theta: float, n_points: int = 60) -> list[np.ndarray]:
    """Centreline ``(n_points, 2)`` of every rod of the held state ``theta`` (lab frame)."""
    a = ring.held(theta)
    return [s.position(np.linspace(0.0, s.length, n_points)) for s in a.segments]
