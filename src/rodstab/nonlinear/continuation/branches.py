"""Branches from a bifurcation: their directions, tracing and post-buckling verdict.

Tracing by arclength or amplitude control; the one post-buckling verdict is
:func:`.path.post_buckling`.

**Directions.** At a simple critical eigenvalue the branch leaves along the critical mode. At a
double one (a symmetric structure: the folded six-sided ring, a uniform ring, an isotropic
twisted rod) any combination ``v(phi) = cos phi v1 + sin phi v2`` of the two modes is a
candidate. With the reduced equations of the two-mode kernel (odd in the amplitude, the
symmetric case: the cubic terms vanish), the pinned solution at a small amplitude ``eps`` along
``v(phi)`` -- equilibrium with the orthogonal combination ``z(phi)`` held by a phase row,
:func:`.corrector.correct` -- has ``p - p_c = eps^2 P(phi) + O(eps^4)`` with ``P`` a
trigonometric polynomial of degree 4 (a quartic form on the circle), and the branches leave
exactly along the critical points of ``P`` (where the pin's force vanishes). ``P`` is sampled
at ``PROBE_SCAN`` directions, fitted (its fit residual is checked), and the roots of ``P'``
found by the one root finder (scan, then refine). A ``P`` that does not vary is a continuous
family (one branch up to symmetry). The directions are returned most dangerous first (the one
whose parameter moves farthest towards the primary's stable side), so the verdict of a double
bifurcation is that of its worst branch, independent of which basis of the eigenspace the
eigen solver returned.

**Tracing.** Both tracers use the same corrector and the same amplitude ``xi``:
:func:`trace_branch` steps by pseudo-arclength (through folds), :func:`amplitude_branch`
prescribes the displacement of the free unknown that the mode moves most (bordered Newton with
the amplitude row).
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from ...errors import RodstabInputError, require_finite, require_int
from ...model import Assembly
from ...numerics import find_roots
from ..discrete import DiscreteRod, discretise
from ..parameters import LoadFactor, Parameter
from ..solve import critical_load_factor, lowest_modes, newton
from .corrector import Corrected, Stepper, correct, pinned_equilibrium
from .path import Path, SpecialKind, mode_out_of_plane, post_buckling, reference_length, xi
from .special import crossed, locate, lowest

#: Two lowest eigenvalues closer than this (relative to the gap to the third) are a double one
#: (at a branch point located by the root finder both vanish: folded six-ring 1e-16 against
#: 2e-8; the bi-rod's simple one has its second at 0.07 of its third).
DOUBLE_RTOL = 1e-3
#: Amplitude of the direction probe (largest node displacement / reference length).
PROBE_XI = 2e-3
#: Branch points with |xi| up to this enter the fit of p/p_c = 1 + a xi + b xi^2 (+ xi^3, xi^4
#: terms), when there are at least five.
FIT_XI = 0.04
#: Directions probed in [0, pi) for the quartic form P(phi).
PROBE_SCAN = 12
#: P varies by less than this relative to its mean: a continuous family of branches.
FAMILY_RTOL = 1e-4
#: Largest residual of the degree-4 trigonometric fit of P, relative to its range, for its
#: stationary points to be used (the O(eps^2) terms of p - p_c are ~PROBE_XI^2 relative);
#: beyond it the sampled extremes are used.
FIT_RTOL = 1e-2


@dataclasses.dataclass(frozen=True)
class Direction:
    """A branch direction at a bifurcation.

    The mode (free unknowns), the phase pin (the orthogonal critical mode at a double eigenvalue,
    else None) and ``P`` (module docstring; NaN at a simple eigenvalue).
    """

    mode: np.ndarray
    phase: np.ndarray | None
    curvature: float


def _scale_to_xi(rod: DiscreteRod, vec: np.ndarray, target: float, length: float) -> float:
    w = mode_out_of_plane(rod, vec)
    full = np.zeros(rod.n_dof)
    full[rod.free_dofs()] = vec
    m = max(float(np.max(np.abs(w))), 1e-3 * float(np.max(np.abs(full[: 3 * len(rod.x)]))))
    return target * length / max(m, 1e-300)


def _pinned(rod: DiscreteRod, param: Parameter, v: np.ndarray, z: np.ndarray, eps: float
            ) -> float:
    """Parameter of the solution at amplitude ``eps`` along ``v`` with ``z`` pinned."""
    r = rod.copy()
    dq = np.zeros(r.n_dof)
    dq[r.free_dofs()] = eps * v
    r.apply(dq)
    if correct(r, param, v, 0.0, eps, acc_q=eps * v, acc_p=0.0, phase=z) is None:
        raise RuntimeError("the direction probe at a double eigenvalue did not converge")
    return param.get(r)


def _probe(rod: DiscreteRod, param: Parameter, v: np.ndarray, z: np.ndarray, eps: float
           ) -> float:
    """Return ``P = (p(2 eps) - p(eps)) / (3 eps^2)``, the parameter's quadratic coefficient.

    The coefficient of the pinned solution's parameter, free of the offset of ``rod`` from the exact
    bifurcation (a located branch point is off by ~1e-4 in ``p``, which would swamp
    ``(p - p0) / eps^2``).
    """
    return (_pinned(rod, param, v, z, 2 * eps) - _pinned(rod, param, v, z, eps)) / (3 * eps**2)


def _harmonics(phi: np.ndarray) -> np.ndarray:
    return np.column_stack([np.ones_like(phi), np.cos(2 * phi), np.sin(2 * phi),
                            np.cos(4 * phi), np.sin(4 * phi)])


def branch_directions(rod: DiscreteRod, param: Parameter, stable_side: float,
                      length: float) -> list[Direction]:
    """Branch directions at the bifurcation ``rod`` (module docstring), most dangerous first."""
    vals, vecs = lowest_modes(rod, 3)
    if abs(vals[1] - vals[0]) > DOUBLE_RTOL * abs(vals[2] - vals[0]):
        return [Direction(vecs[:, 0] / np.linalg.norm(vecs[:, 0]), None, math.nan)]
    v1 = vecs[:, 0] / np.linalg.norm(vecs[:, 0])
    v2 = vecs[:, 1] - (vecs[:, 1] @ v1) * v1
    v2 /= np.linalg.norm(v2)

    def pair(phi: float) -> tuple[np.ndarray, np.ndarray]:
        return (math.cos(phi) * v1 + math.sin(phi) * v2,
                -math.sin(phi) * v1 + math.cos(phi) * v2)

    eps = _scale_to_xi(rod, v1, PROBE_XI, length)
    grid = np.linspace(0.0, math.pi, PROBE_SCAN, endpoint=False)
    P = np.array([_probe(rod, param, *pair(float(f)), eps) for f in grid])
    spread = float(np.ptp(P))
    if spread <= FAMILY_RTOL * max(float(np.max(np.abs(P))), 1e-300):
        # A family: every combination alike (an axis of symmetry), so v1 is whichever the
        # eigensolver gave, and round-off chose it: the twisted rod's subcritical branch
        # then fell to 0.97976 or 0.99425 of phi_c over its 8 steps (xi, the out-of-plane
        # field, and the first step depend on the phase). Take the combination whose
        # out-of-plane field is largest: node i's is a_i cos(phi) + b_i sin(phi), largest at
        # phi = atan2(b_i, a_i) (nodes tied by a symmetry give images of one branch).
        a_w, b_w = mode_out_of_plane(rod, v1), mode_out_of_plane(rod, v2)
        i = int(np.argmax(np.hypot(a_w, b_w)))
        return [Direction(*pair(math.atan2(float(b_w[i]), float(a_w[i]))),
                          float(np.mean(P)))]
    coef, *_ = np.linalg.lstsq(_harmonics(grid), P, rcond=None)
    misfit = float(np.max(np.abs(_harmonics(grid) @ coef - P)))
    if misfit > FIT_RTOL * spread:
        # P too flat to resolve its stationary points (near a change of character of the
        # bifurcation, where b ~ 0 in every direction): take the sampled extremes.
        order = np.argsort(-P * stable_side)
        return [Direction(*pair(float(grid[i])), float(P[i])) for i in order[[0, -1]]]
    k = np.array([0, 2, 2, 4, 4])

    def dP(phi: float) -> float:
        h = _harmonics(np.array([phi]))[0]
        d = np.array([0.0, -h[2], h[1], -h[4], h[3]]) * k  # derivative of each harmonic
        return float(d @ coef)

    found = find_roots(dP, -0.01, math.pi - 0.01, n_scan=4 * PROBE_SCAN)
    phis: list[float] = []
    for root in found.roots:
        phi = root.x % math.pi
        if all(min(abs(phi - q), math.pi - abs(phi - q)) > 1e-6 for q in phis):
            phis.append(phi)
    dirs = [(phi, float(_harmonics(np.array([phi]))[0] @ coef)) for phi in phis]
    dirs.sort(key=lambda d: -d[1] * stable_side)  # most dangerous first
    return [Direction(*pair(phi), curv) for phi, curv in dirs]


class _Snapshots:
    """The states of one side of a branch kept for the pictures.

    They become :class:`.path.Path`'s ``shapes``, ``shape_values``, ``frames`` and
    ``shape_moments``.
    """

    def __init__(self) -> None:
        self.shapes: list[np.ndarray] = []
        self.values: list[float] = []
        self.frames: list[np.ndarray] = []
        self.moments: list[np.ndarray] = []

    def add(self, rod: DiscreteRod, value: float) -> None:
        """Keep ``rod``'s node positions, edge frames and internal moments at ``value``."""
        self.shapes.append(rod.x.copy())
        self.values.append(value)
        self.frames.append(rod.R_edge.copy())
        self.moments.append(rod.edge_moments())


def _branch_path(key: str, p_c: float, sides: dict, start: tuple, stable_side: float,
                 converged: bool, method: str, shots: _Snapshots,
                 specials: tuple = (), states: tuple = ()) -> Path:
    """Return a branch in path order: the negative side reversed, the bifurcation, the positive."""
    pts = sides.get(-1.0, [])[::-1] + [start] + sides.get(1.0, [])
    X = np.array([q[0] for q in pts])
    V = np.array([q[1] for q in pts])
    # Initial post-buckling: fit where xi is small; a coarse branch falls back on its inner
    # 60 % (stated by the verdict's coefficients only as far as the points allow).
    small = np.abs(X) <= FIT_XI
    if small.sum() < 5:
        small = np.abs(X) <= 0.6 * np.max(np.abs(X))
    verdict, a, b = post_buckling(X[small], V[small], p_c, stable_side)
    return Path(key, tuple(V), tuple(q[2] for q in pts), tuple(q[3] for q in pts), tuple(X),
                "xi: largest out-of-plane node displacement (free rigid motion removed) / L, "
                "signed along the critical mode", converged, method, p_c, (a, b), verdict,
                specials, (), 0, tuple(shots.shapes), tuple(shots.values), states,
                frames=tuple(shots.frames), shape_moments=tuple(shots.moments))


def _land(rod: DiscreteRod, param: Parameter, value: float, phase: np.ndarray | None
          ) -> DiscreteRod | None:
    """Return the equilibrium at ``value`` next to ``rod`` on its branch, or None.

    The corrector with the parameter held (row ``(0, 1)``), i.e. plain Newton, which stays on a
    saddle branch where the descent safeguards of :func:`..solve.newton` would leave it; in 1, 2, 4
    or 8 equal parameter steps. None if none converges.
    """
    zero = np.zeros(len(rod.free_dofs()))
    p0 = param.get(rod)
    for m in (1, 2, 4, 8):
        trial = rod.copy()
        for k in range(1, m + 1):
            p_prev, p_next = param.get(trial), p0 + (value - p0) * k / m
            param.set(trial, p_next)
            result = correct(trial, param, zero, 1.0, p_next - p_prev, acc_q=zero,
                             acc_p=p_next - p_prev, phase=phase)
            if not pinned_equilibrium(trial, result, phase):
                break
        else:
            return trial
    return None


def trace_branch(rod: DiscreteRod, param: Parameter, stable_side: float, ds: float,
                 n_steps: int, *, length: float, signs: tuple[float, ...] = (1.0, -1.0),
                 direction: Direction | None = None, stop_at_special: bool = False,
                 stop_kinds: tuple[SpecialKind, ...] = tuple(SpecialKind),
                 window: tuple[float, float] | None = None, first_step: float = 1.0,
                 land_at: tuple[float, ...] = ()) -> Path:
    """Trace the branch leaving the bifurcation ``rod`` by pseudo-arclength.

    ``n_steps`` steps each way (``signs``), about ``ds`` (length unit) of amplitude per step, up to
    4 ``ds``.

    ``direction``: default the most dangerous of :func:`branch_directions`. With
    ``stop_at_special`` the special points are located (in ``special_points``; the states there
    in ``states``) and a side stops at the first one of a kind in ``stop_kinds``; ``window``: a
    side stops once the parameter leaves it, on a point landed exactly on its edge.
    ``first_step``: the first step as a fraction of ``ds`` (steps then grow by 1.5), so that a
    coarse branch still has points at small amplitude for the post-buckling fit. ``land_at``:
    parameter values on which a point is landed exactly (as on a window's edge) each time the
    path crosses them, kept in ``landed``; the path itself goes on from its own point.
    """
    p_c = param.get(rod)
    d = direction or branch_directions(rod, param, stable_side, length)[0]
    mode_w = mode_out_of_plane(rod, d.mode)
    ref = rod.x.copy()
    h = _scale_to_xi(rod, d.mode, ds / length, length)
    sides: dict[float, list] = {}
    specials, states, ok_all, ends, crossings = [], [], True, [], []
    shots = _Snapshots()
    shots.add(rod, p_c)
    for sign in signs:
        pts = sides.setdefault(sign, [])
        r = rod.copy()
        path = Stepper(r, param, sign * d.mode, 0.0, first_step * h, 4 * h, phase=d.phase)
        e_prev = None
        for _ in range(n_steps):
            prev, prev_tq, prev_tp = r.copy(), path.tq.copy(), path.tp
            if not path.step():
                ok_all = False
                break
            p_prev, p_now = param.get(prev), param.get(r)
            for value in land_at:
                if (p_prev >= value) != (p_now >= value):
                    landing = _land(prev, param, value, d.phase)
                    if landing is not None:
                        crossings.append((value, landing))
            left = window is not None and not window[0] <= p_now <= window[1]
            if left:
                # Land exactly on the window's edge: the corrector with the parameter held
                # (row (0, 1)) from the last point inside -- plain Newton, which stays on a
                # saddle branch where the descent safeguards of solve.newton would leave it.
                edge = min(window, key=lambda w: abs(w - param.get(r)))  # type: ignore[arg-type]
                landed = _land(prev, param, edge, d.phase)
                if landed is not None:
                    r.assign(landed)
            # The stepper's Hessian is the point's unless it was landed on the window's edge.
            e1 = lowest(r, None if left or path.terms is None else path.terms[2])
            if stop_at_special and e_prev is not None and crossed(e_prev, e1, prev_tp, path.tp):
                point, at = locate(r, param, prev, prev_tq, prev_tp, path.last_h, e_prev, e1,
                                   path.tp, phase=d.phase)
                specials.append(point)
                states.append((point["value"], at))
                if SpecialKind(point["kind"]) in stop_kinds:
                    pts.append((xi(r, r.x, ref, mode_w, length), param.get(r), r.energy(), e1))
                    if sign > 0:
                        shots.add(r, param.get(r))
                    break
            e_prev = e1
            pts.append((xi(r, r.x, ref, mode_w, length), param.get(r), r.energy(), e1))
            if sign > 0:
                shots.add(r, param.get(r))
            if left:
                break
        ends.append((param.get(r), r.copy()))
    branch = _branch_path(str(param.key), p_c, sides, (0.0, p_c, rod.energy(), lowest(rod)),
                          stable_side, ok_all,
                          "pseudo-arclength from the bifurcation along the critical mode"
                          + (" (double eigenvalue: phase pinned)" if d.phase is not None
                             else ""),
                          shots, tuple(specials), tuple(states))
    return dataclasses.replace(branch, end_states=tuple(ends), landed=tuple(crossings))


def _advance(rod: DiscreteRod, param: Parameter, k: int, target: float, direction: np.ndarray,
             phase: np.ndarray | None, depth: int = 0) -> Corrected | None:
    """Move the branch to amplitude ``target`` of free unknown ``k``.

    Predictor along ``direction``, the amplitude row in :func:`.corrector.correct`; on failure
    restore the state and take two half steps (at most 5 halvings). Returns the corrector's
    result at the point reached, or None.
    """
    free = rod.free_dofs()
    saved = rod.copy()
    cur = rod.x.reshape(-1)[free[k]]
    dq = np.zeros(rod.n_dof)
    dq[free] = direction * (target - cur)
    rod.apply(dq)
    ek = np.zeros(len(free))
    ek[k] = 1.0
    result = correct(rod, param, ek, 0.0, target - cur, acc_q=direction * (target - cur),
                     acc_p=0.0, phase=phase)
    if result is not None and pinned_equilibrium(rod, result, phase):
        return result
    rod.assign(saved)
    if depth >= 5:
        return None
    mid = 0.5 * (cur + target)
    if _advance(rod, param, k, mid, direction, phase, depth + 1) is None:
        return None
    return _advance(rod, param, k, target, direction, phase, depth + 1)


def amplitude_branch(rod: DiscreteRod, param: Parameter, stable_side: float,
                     xis: np.ndarray, *, length: float, direction: Direction | None = None
                     ) -> Path:
    """Branch from the bifurcation ``rod`` under amplitude control.

    The free unknown that the critical mode moves most is prescribed so that ``xi`` is about each of
    ``xis`` (both signs), the parameter solved for. Passes folds of the parameter; cannot pass a
    fold of the amplitude (use :func:`trace_branch`).
    """
    p_c = param.get(rod)
    d = direction or branch_directions(rod, param, stable_side, length)[0]
    mode_w = mode_out_of_plane(rod, d.mode)
    free = rod.free_dofs()
    z_free = [i for i, dof in enumerate(free) if dof < 3 * len(rod.x) and dof % 3 == 2]
    k = max(z_free, key=lambda i: abs(d.mode[i]))
    unit = d.mode / d.mode[k]
    per_xi = _scale_to_xi(rod, unit, 1.0, length)  # displacement of k per unit xi (first order)
    ref = rod.x.copy()
    sides: dict[float, list] = {}
    ok_all = True
    shots = _Snapshots()
    shots.add(rod, p_c)
    for sign in (1.0, -1.0):
        pts = sides.setdefault(sign, [])
        r = rod.copy()
        base = r.x.reshape(-1)[free[k]]
        for target in xis:
            reached = _advance(r, param, k, base + sign * target * per_xi, unit, d.phase)
            if reached is None:
                ok_all = False
                break
            pts.append((xi(r, r.x, ref, mode_w, length), param.get(r), r.energy(),
                        lowest(r, reached.terms[2])))
            if sign > 0:
                shots.add(r, param.get(r))
    return _branch_path(str(param.key), p_c, sides, (0.0, p_c, rod.energy(), lowest(rod)),
                        stable_side, ok_all,
                        "amplitude-controlled bordered Newton from the critical mode", shots)


def _bifurcation(a: Assembly, lo: float, hi: float, n: int) -> tuple[DiscreteRod, float]:
    crit = critical_load_factor(a, lo, hi, elements_per_segment=n)
    if not math.isfinite(crit.load_factor_critical):
        raise RodstabInputError(f"the held state does not lose stability for load factors in "
                                f"({lo!r}, {hi!r}]: no bifurcation to start from")
    rod = discretise(a, n, crit.load_factor_critical)
    below = discretise(a, n, lo)
    if crit.relaxed:
        # The discrete held state carries an O(l_e^2) joint moment (unequal elements at a
        # weld): start from the equilibrium critical_load_factor judged, not the held state.
        newton(rod)
        newton(below)
    # The held state is stable below mu_c unless the lower end of the bracket says otherwise.
    side = -1.0 if lowest(below) > 0 else 1.0
    return rod, side


def post_buckling_branch(a: Assembly, lo: float, hi: float, *, elements_per_segment: int = 24,
                         amplitudes: np.ndarray | None = None,
                         reference_segment: str | None = None) -> Path:
    """Branch from the first bifurcation of the held state under amplitude control.

    The first bifurcation in the load factor in ``(lo, hi]``, traced by :func:`amplitude_branch`;
    ``amplitudes``: the values of ``xi`` (default 12 up to 0.02).
    """
    rod, side = _bifurcation(a, lo, hi, elements_per_segment)
    xis = np.linspace(0.0, 0.02, 13)[1:] if amplitudes is None else np.asarray(amplitudes)
    return amplitude_branch(rod, LoadFactor(), side, xis,
                            length=reference_length(a, reference_segment))


def arclength_from_bifurcation(a: Assembly, lo: float, hi: float, *,
                               elements_per_segment: int = 24, ds: float = 0.05,
                               n_steps: int = 60, mu_window: tuple[float, float] | None = None,
                               both_sides: bool = False, stop_at_special: bool = False,
                               stop_kinds: tuple[SpecialKind, ...] = tuple(SpecialKind),
                               reference_segment: str | None = None,
                               land_at: tuple[float, ...] = ()) -> Path:
    """Branch from the first bifurcation of the held state by pseudo-arclength.

    The first bifurcation in the load factor in ``(lo, hi]``, traced by :func:`trace_branch`, one
    side (the mode's sign) unless ``both_sides``; stops after ``n_steps``, when the load leaves
    ``mu_window`` or, with ``stop_at_special``, at the first special point of a kind in
    ``stop_kinds`` (located). Points landed exactly on the loads ``land_at`` as the path
    crosses them are in the path's ``landed``.
    """
    lo, hi = require_finite("lo", lo), require_finite("hi", hi)
    if not lo < hi:
        raise RodstabInputError(f"arclength_from_bifurcation needs lo < hi, got {lo!r}, {hi!r}")
    if require_finite("ds", ds) <= 0:
        raise RodstabInputError(f"ds must be > 0, got {ds!r}")
    n_steps = require_int("n_steps", n_steps, 1)
    rod, side = _bifurcation(a, lo, hi, elements_per_segment)
    return trace_branch(rod, LoadFactor(), side, ds, n_steps,
                        length=reference_length(a, reference_segment),
                        signs=(1.0, -1.0) if both_sides else (1.0,),
                        stop_at_special=stop_at_special, stop_kinds=stop_kinds,
                        window=mu_window, land_at=land_at)
