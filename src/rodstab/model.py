"""Planar assemblies of naturally curved Kirchhoff rods held in circular or straight states.

A :class:`Segment` is a rod of length ``L`` held in the plane with constant signed curvature
``curvature`` (``1/R``, positive turning left; 0 for straight), starting at ``start`` with
tangent angle ``angle``. Its natural curvature (about the same e3 axis, same sign convention)
at load factor 1 is ``natural_curvature``; at load factor ``mu`` it is ``mu * natural_curvature``.
A segment may also carry a natural twist (rate of rotation of the cross-section about the
tangent in the natural state, scaled by ``mu`` likewise); the held state itself is untwisted, so
a natural twist is an imposed twist of the opposite sign (Michell's ring, Section 3.3). Only
the nonlinear model accepts it: the linear P2 (2.12) assumes no initial twist.
Welds join segment ends (any angle in the plane): they share out-of-plane displacement and the
full rotation of the cross-section. Supports act on joints; what each kind holds, and which
method implements it, is the one table :data:`SUPPORT_KINDS`.

Units: any consistent set (lengths, stiffnesses as force x length^2). Nothing is rescaled.
"""

from __future__ import annotations

import collections
import dataclasses
import math

import numpy as np

from .errors import RodstabInputError, require_finite, require_positive

#: Ends meet when their held-state positions differ by less than this times the total length.
POSITION_TOL = 1e-8
#: Held-state moment balance at a joint is checked to this relative tolerance.
MOMENT_TOL = 1e-8
#: Axes of a segment end's held frame, in this order: normal ``n = t x e3``, tangent ``t``,
#: binormal ``e3``. They name the rotations a support holds (:class:`SupportKind`) and the
#: components of an imposed end rotation (``Assembly.end_rotations``, the design key
#: ``support.<i>.rotation.<axis>``).
ROTATION_AXES = ("normal", "tangent", "binormal")
#: Largest |component| of an imposed end rotation (radians): a hundred turns. Checked in
#: design files and at both ends of a continuation in an end rotation.
MAX_END_ROTATION = 200 * math.pi
#: Defaults of contact between rods (the design keys ``analysis.contact_thickness`` and
#: ``analysis.contact_dhat``, the options ``--contact-thickness`` and ``--contact-dhat``): the
#: rods' thickness over the rod length, ``h / L``, and the barrier's reach over it, ``dhat /
#: h`` (the contact model's rule, rodstab.nonlinear.contact_model).
CONTACT_THICKNESS_RATIO = 0.02
CONTACT_DHAT_FRACTION = 0.1


def held_frame(tangent: np.ndarray) -> np.ndarray:
    """Held frame(s) ``(..., 3, 3)`` of in-plane unit tangent(s) ``(..., 2)``, lab frame.

    Columns in the order of :data:`ROTATION_AXES`: ``n = t x e3``, ``t``, ``e3``.
    """
    t = np.asarray(tangent, dtype=float)
    t3 = np.zeros(t.shape[:-1] + (3,))
    t3[..., :2] = t
    e3 = np.zeros_like(t3)
    e3[..., 2] = 1.0
    n = np.cross(t3, e3)
    return np.stack([n, t3, e3], axis=-1)


#: Names of the methods that read the support table (:attr:`SupportKind.methods`): the FE of
#: the linear P2 (:mod:`rodstab.linear`), the discrete geometrically exact rod
#: (:mod:`rodstab.nonlinear`, with its continuation) and the full system of exact general
#: solutions of straight segments (:func:`rodstab.transfer.straight_assembly_matrix`).
LINEAR, NONLINEAR, FULL_SYSTEM = "linear", "nonlinear", "full-system"


@dataclasses.dataclass(frozen=True, kw_only=True)
class SupportKind:
    """What one kind of support holds at a joint, and which methods implement it.

    Every method reads these fields; none tests support names.

    Parameters
    ----------
    name : str
        The name used in an :class:`Assembly`'s ``supports`` and in design files.
    holds_deflection : bool
        The out-of-plane displacement ``w`` of the joint is 0. The nonlinear rod also holds
        the joint's in-plane position (except along the tangent if ``slides_along_tangent``).
    held_rotations : frozenset of str
        Axes of :data:`ROTATION_AXES` (the supported end's held frame) about which the
        cross-section cannot turn. The linear P2 has no in-plane rotation unknown, so there
        only ``normal`` and ``tangent`` matter.
    slides_along_tangent : bool
        The joint may move along the end's held tangent (the paper's modified support after
        (3.8)); this changes nothing in the linear P2, whose unknowns are out of plane.
    methods : frozenset of str
        The methods (:data:`LINEAR`, :data:`NONLINEAR`, :data:`FULL_SYSTEM`) that implement
        this kind; the others raise :class:`~rodstab.errors.RodstabInputError` naming it.
    """

    name: str
    holds_deflection: bool
    held_rotations: frozenset[str]
    slides_along_tangent: bool
    methods: frozenset[str]

    def __post_init__(self) -> None:
        unknown = sorted(self.held_rotations - set(ROTATION_AXES))
        if unknown:
            raise ValueError(f"support kind {self.name!r}: held_rotations {unknown} are not "
                             f"in {ROTATION_AXES}")

    @property
    def holds_all_rotations(self) -> bool:
        """The end's frame is held: the cross-section turns about no axis (a clamp)."""
        return self.held_rotations == frozenset(ROTATION_AXES)

    @property
    def accepts_end_rotation(self) -> bool:
        """An end rotation can be imposed here: only on a frame the support holds."""
        return self.holds_all_rotations

    @property
    def holds_rigid_motions(self) -> bool:
        """Alone, this support holds every out-of-plane rigid motion of the structure.

        Those are the translation along e3 and the rotations about the two in-plane axes
        (normal and tangent of the end).
        """
        return self.holds_deflection and {"normal", "tangent"} <= self.held_rotations


_ALL = frozenset((LINEAR, NONLINEAR, FULL_SYSTEM))
#: The one support table, in the order of :data:`SUPPORTS`. Which method implements which kind:
#:
#: ============== ====== ========= ===========
#: kind           linear nonlinear full-system
#: ============== ====== ========= ===========
#: clamped        yes    yes       yes
#: sliding-clamp  yes    yes       yes
#: fork           yes    no        no
#: pinned         yes    no        no
#: free           yes    yes       yes
#: ============== ====== ========= ===========
SUPPORT_KINDS: dict[str, SupportKind] = {k.name: k for k in (
    # w = 0, all rotations 0.
    SupportKind(name="clamped", holds_deflection=True, held_rotations=frozenset(ROTATION_AXES),
                slides_along_tangent=False, methods=_ALL),
    # A clamp that lets the end slide along its tangent (the paper's modified support after
    # (3.8)): the same as a clamp for the linear P2, different for the inextensible rod.
    SupportKind(name="sliding-clamp", holds_deflection=True,
                held_rotations=frozenset(ROTATION_AXES), slides_along_tangent=True,
                methods=_ALL),
    # Pinned with a fork: w = 0, no rotation about the tangent (no twist).
    SupportKind(name="fork", holds_deflection=True, held_rotations=frozenset({"tangent"}),
                slides_along_tangent=False, methods=frozenset({LINEAR})),
    # w = 0 only. A held moment here is an applied end moment, taken as the one a bearing along
    # the end's tangent carrying a pin along its normal transmits (its second-order work:
    # rodstab.linear.assembly.applied_moment_terms).
    SupportKind(name="pinned", holds_deflection=True, held_rotations=frozenset(),
                slides_along_tangent=False, methods=frozenset({LINEAR})),
    # Holds nothing.
    SupportKind(name="free", holds_deflection=False, held_rotations=frozenset(),
                slides_along_tangent=False, methods=_ALL),
)}
#: Names of the support kinds (the keys of :data:`SUPPORT_KINDS`).
SUPPORTS = tuple(SUPPORT_KINDS)


def support_kind(name: str) -> SupportKind:
    """Return the :class:`SupportKind` called ``name``; raise naming it if there is none."""
    kind = SUPPORT_KINDS.get(name) if isinstance(name, str) else None
    if kind is None:
        raise RodstabInputError(f"support type must be one of {SUPPORTS}, got {name!r}")
    return kind


def kinds_of(method: str) -> tuple[str, ...]:
    """Names of the support kinds that ``method`` implements, in the order of :data:`SUPPORTS`."""
    return tuple(k.name for k in SUPPORT_KINDS.values() if method in k.methods)


ENDS = ("start", "end")


@dataclasses.dataclass(frozen=True, kw_only=True)
class Segment:
    """One rod segment in its held (reference) state; see the module docstring."""

    name: str
    length: float
    curvature: float
    natural_curvature: float
    B1: float
    B2: float
    B3: float
    start: tuple[float, float] = (0.0, 0.0)
    angle: float = 0.0
    natural_twist: float = 0.0

    def __post_init__(self) -> None:
        for key in ("length", "B1", "B2", "B3"):
            require_positive(f"segment {self.name!r} {key}", getattr(self, key))
        for key in ("curvature", "natural_curvature", "angle", "natural_twist"):
            require_finite(f"segment {self.name!r} {key}", getattr(self, key))
        # The held state turns by curvature x length: it must be a number, not an overflow.
        require_finite(f"segment {self.name!r} curvature x length", self.curvature * self.length)
        for v in self.start:
            require_finite(f"segment {self.name!r} start", v)

    def tangent(self, s: float | np.ndarray) -> np.ndarray:
        """Return the unit tangent ``(..., 2)`` at arc length ``s``, held state, lab frame."""
        phi = self.angle + self.curvature * np.asarray(s, dtype=float)
        return np.stack([np.cos(phi), np.sin(phi)], axis=-1)

    def position(self, s: float | np.ndarray) -> np.ndarray:
        """Centreline position ``(..., 2)`` at arc length ``s`` in the held state."""
        s = np.asarray(s, dtype=float)
        k, a = self.curvature, self.angle
        x0, y0 = self.start
        # The chord of an arc of turning k s is s sinc(k s / 2) along the mid-angle. Unlike
        # (sin(a + k s) - sin a) / k it has no cancellation for small k s (that form was off by
        # 3e-6 at k = 3e-11, found by tests/test_engine_properties.py) and needs no straight
        # special case.
        mid = a + 0.5 * k * s
        chord = s * np.sinc(0.5 * k * s / math.pi)
        return np.stack([x0 + chord * np.cos(mid), y0 + chord * np.sin(mid)], axis=-1)

    def end_point(self, end: str) -> np.ndarray:
        """Held-state position of ``"start"`` or ``"end"``."""
        return self.position(0.0 if end == "start" else self.length)

    def held_moments(self, load_factor: float) -> tuple[float, float]:
        """Return the internal moments ``(M3, M2)`` of the held state at ``load_factor``.

        ``M3 = B3 (k - mu kappa_n)`` bends the rod in the plane (the paper's uniform moment of
        Section 5, ``M3 = B3 (kappa_0 - kappa_n)``) and ``M2 = -B2 mu tau_n`` twists it (the
        held state is untwisted). Units: stiffness / length (N m for B in N m^2, m).
        """
        mu = load_factor
        return (self.B3 * (self.curvature - mu * self.natural_curvature),
                -self.B2 * mu * self.natural_twist)

    def held_energy(self, load_factor: float) -> float:
        """Return the elastic energy stored in the held state at ``load_factor``.

        ``L/2 (B3 (k - mu kappa_n)^2 + B2 (mu tau_n)^2)`` (the energy density of (5.1) with no
        out-of-plane curvature). Units: stiffness / length (J for B in N m^2, L in m).
        """
        M3, M2 = self.held_moments(load_factor)
        return 0.5 * self.length * (M3 * M3 / self.B3 + M2 * M2 / self.B2)


@dataclasses.dataclass(frozen=True, kw_only=True)
class Assembly:
    """Segments, welds (groups of segment ends) and supports (on segment ends).

    ``welds``: each a sequence of ``(segment_name, end)`` joined into one joint. ``supports``:
    ``(segment_name, end, type)``, ``type`` a key of :data:`SUPPORT_KINDS` (which says what it
    holds and which methods implement it); a support on any end of a joint holds the whole
    joint.
    ``reference_load``: a load factor at which the held state is known to be stable (default:
    the stress-free value if one exists, else 0); the stable interval is sought around it.
    ``end_rotations``: ``(segment_name, end, (r_n, r_t, r_b))``, a rotation imposed on a clamped
    (or sliding-clamped) end, as a rotation vector (radians) in that end's held frame: normal
    ``n = t x e3``, tangent ``t``, binormal ``e3`` (``r_t`` twists the end about the rod). The
    held state is then no longer an equilibrium: only the nonlinear model accepts it.
    """

    segments: tuple[Segment, ...]
    welds: tuple[tuple[tuple[str, str], ...], ...] = ()
    supports: tuple[tuple[str, str, str], ...] = ()
    reference_load: float | None = None
    end_rotations: tuple[tuple[str, str, tuple[float, float, float]], ...] = ()

    def __post_init__(self) -> None:
        validate(self)

    def segment(self, name: str) -> Segment:
        """Return the segment called ``name``."""
        # A dict built once (a frozen dataclass has no other place to cache it): validation
        # looks up every end, which a linear search made quadratic in the number of segments.
        by_name = self.__dict__.get("_by_name")
        if by_name is None:
            by_name = {s.name: s for s in self.segments}
            object.__setattr__(self, "_by_name", by_name)
        try:
            return by_name[name]
        except (KeyError, TypeError):
            known = list(by_name)
            listed = ", ".join(known[:10]) + (f", ... ({len(known)} in all)"
                                              if len(known) > 10 else "")
            raise RodstabInputError(
                f"unknown segment {name!r}; the segments are {listed}") from None

    def joints(self) -> list[tuple[tuple[str, str], ...]]:
        """Every segment end grouped into joints (welded ends together, others alone)."""
        seen: dict[tuple[str, str], int] = {}
        groups: list[list[tuple[str, str]]] = []
        for w in self.welds:
            idx = None
            for e in w:
                if e in seen:
                    idx = seen[e]
            if idx is None:
                groups.append([])
                idx = len(groups) - 1
            for e in w:
                if e in seen and seen[e] != idx:  # merge two groups
                    old = seen[e]
                    for e2 in groups[old]:
                        seen[e2] = idx
                        groups[idx].append(e2)
                    groups[old] = []
                if e not in seen:
                    seen[e] = idx
                    groups[idx].append(e)
        for s in self.segments:
            for end in ENDS:
                if (s.name, end) not in seen:
                    seen[(s.name, end)] = len(groups)
                    groups.append([(s.name, end)])
        return [tuple(g) for g in groups if g]

    @property
    def total_length(self) -> float:
        """Sum of the segment lengths."""
        return sum(s.length for s in self.segments)


def _holds_something(kind: SupportKind) -> bool:
    return kind.holds_deflection or bool(kind.held_rotations)


def validate(a: Assembly) -> None:
    """Check names, ends, supports, that welded ends meet, and moment balance at joints."""
    names = [s.name for s in a.segments]
    if not names:
        raise RodstabInputError("an assembly needs at least one segment")
    dup = {n for n, c in collections.Counter(names).items() if c > 1}
    if dup:
        raise RodstabInputError(f"duplicate segment name(s) {sorted(dup)}")
    for w in a.welds:
        if len(w) < 2:
            raise RodstabInputError(f"a weld joins at least two ends, got {list(w)!r}")
        twice = sorted({f"{n}.{e}" for n, e in w if list(w).count((n, e)) > 1})
        if twice:
            raise RodstabInputError(f"a weld joins an end to itself: {twice} appear(s) twice "
                                    f"in {[f'{n}.{e}' for n, e in w]}")
        for name, end in w:
            a.segment(name)
            if end not in ENDS:
                raise RodstabInputError(f"weld end must be 'start' or 'end', got {end!r}")
    # An end in two welds (a [[weld]] pasted twice) would silently merge them into one joint:
    # a joint of three or more ends is one weld that lists them all.
    welded_in: dict[tuple[str, str], int] = {}
    for i, w in enumerate(a.welds):
        for n, e in w:
            j = welded_in.setdefault((n, e), i)
            if j != i:
                raise RodstabInputError(
                    f"end {n}.{e} is welded twice: in weld[{j}] "
                    f"{[f'{m}.{f}' for m, f in a.welds[j]]} and weld[{i}] "
                    f"{[f'{m}.{f}' for m, f in w]}; weld each end once (a joint of three or more "
                    f"ends is one weld listing them all)")
    for name, end, kind in a.supports:
        a.segment(name)
        if end not in ENDS:
            raise RodstabInputError(f"support end must be 'start' or 'end', got {end!r}")
        support_kind(kind)
    ends = [(n, e) for n, e, _ in a.supports]
    twice = sorted(f"{n}.{e}" for (n, e), c in collections.Counter(ends).items() if c > 1)
    if twice:
        raise RodstabInputError(f"end(s) {twice} carry more than one support")
    rot_ends = [(n, e) for n, e, _ in a.end_rotations]
    twice = sorted(f"{n}.{e}" for (n, e), c in collections.Counter(rot_ends).items() if c > 1)
    if twice:
        raise RodstabInputError(f"end(s) {twice} carry more than one imposed rotation")
    clamps = {(n, e) for n, e, k in a.supports if SUPPORT_KINDS[k].accepts_end_rotation}
    turnable = " or ".join(k.name for k in SUPPORT_KINDS.values() if k.accepts_end_rotation)
    for name, end, rot in a.end_rotations:
        if (name, end) not in clamps:
            raise RodstabInputError(f"an end rotation needs a {turnable} support at "
                                    f"{name}.{end}; supports are {list(a.supports)!r}")
        if len(rot) != 3:
            raise RodstabInputError(f"end rotation at {name}.{end} must be [r_n, r_t, r_b], "
                                    f"got {rot!r}")
        for v in rot:
            if isinstance(v, bool):
                raise RodstabInputError(f"end rotation at {name}.{end} must be numbers, got "
                                        f"{rot!r}")
            require_finite(f"end rotation at {name}.{end}", v)
    tol = POSITION_TOL * a.total_length
    for joint in a.joints():
        pts = [a.segment(n).end_point(e) for n, e in joint]
        for (n, e), p in zip(joint, pts, strict=True):
            gap = float(np.linalg.norm(p - pts[0]))
            if gap > tol:
                raise RodstabInputError(
                    f"welded ends do not meet: {joint[0][0]}.{joint[0][1]} at {pts[0].round(9)}"
                    f" and {n}.{e} at {p.round(9)} are {gap:.3g} apart (tolerance {tol:.3g})")
        # A support that holds something holds the joint's held (in-plane) state too, so its
        # moments are reacted; a "free" entry holds nothing and excuses nothing.
        supported = any((n, e) == (sn, se) for n, e in joint for sn, se, kind in a.supports
                        if _holds_something(support_kind(kind)))
        if supported:
            continue
        torque = np.zeros(2)
        tscale = 0.0
        for n, e in joint:
            s = a.segment(n)
            t = s.tangent(0.0 if e == "start" else s.length)
            tw = s.B2 * s.natural_twist * t
            torque += tw if e == "start" else -tw
            tscale += float(np.linalg.norm(tw))
        if tscale > 0 and np.linalg.norm(torque) > MOMENT_TOL * tscale:
            raise RodstabInputError(
                f"joint {[f'{n}.{e}' for n, e in joint]} is not in moment equilibrium "
                f"(unbalanced torque B2 x natural twist: {np.round(torque, 9).tolist()})")
        # An unsupported joint must be in moment equilibrium for every load factor: the held
        # moment B3 (k - mu kappa_n) enters with + at a start end and - at an end end.
        for attr in ("curvature", "natural_curvature"):
            total = 0.0
            scale = 0.0
            for n, e in joint:
                s = a.segment(n)
                v = s.B3 * getattr(s, attr)
                total += v if e == "start" else -v
                scale += abs(v)
            if abs(total) > MOMENT_TOL * max(scale, 1e-300) and scale > 0:
                what = "held curvature" if attr == "curvature" else "natural curvature"
                raise RodstabInputError(
                    f"joint {[f'{n}.{e}' for n, e in joint]} is not in moment equilibrium "
                    f"(unbalanced B3 x {what}: {total:.6g}); support it or balance the moments")

