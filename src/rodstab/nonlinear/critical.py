"""Critical load factors of a held state: where its lowest Hessian eigenvalue crosses zero.

:func:`critical_load_factor` on one mesh (the Hessian pencil, affine in the load, or a scan
refined by the one root finder; the held state relaxed by Newton when the discretisation leaves
it off equilibrium) and :func:`converged_critical_load_factor` on meshes refined until the
load is settled (Richardson extrapolation in the one element size of
:func:`uniform_elements`).

Split from :mod:`rodstab.nonlinear.solve` (issue 20), which re-exports every public name.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable, Sequence

import numpy as np
import scipy.sparse as sp

from ..errors import RodstabInputError
from ..limits import DEFAULT as DEFAULT_LIMITS
from ..limits import Limits, nonlinear_dof, require_nonlinear
from ..model import Assembly
from ..numerics import find_roots, jacobi_scaling, pencil_interval_sparse
from ..results import Result
from .discrete import MAX_ELEMENT_TURNING, DiscreteRod, discretise, element_counts
from .newton import newton
from .stability import lowest_eigenvalues, lowest_modes, sliding_mode, vee_log

#: :func:`uniform_elements` gives every segment at least this many elements.
MIN_SEGMENT_ELEMENTS = 2


def uniform_elements(a: Assembly, elements_per_segment: int) -> dict[str, int]:
    """Elements per segment (by name) of about one length ``h`` over the whole assembly.

    ``elements_per_segment x S`` elements in all (``S`` segments) shared in proportion to the
    segments' lengths: ``n_s = max(MIN_SEGMENT_ELEMENTS, round(S n L_s / L))``, and at least
    the held turning allows (:data:`~.discrete.MAX_ELEMENT_TURNING`). A single segment keeps
    ``elements_per_segment``. Why: at a weld between elements of unequal length the discrete
    held state carries an O(l_e^2) joint moment whose size grows with the length ratio (the
    split arc 13.6 / 0.2858 / 4.164 at 32 elements per segment, ratio 48: relaxation refused);
    with one element size the welds join elements of similar length, and the mesh's error is
    that of its one ``h`` rather than of its longest segment's. Doubling every count keeps the
    ratios, so Richardson extrapolation in ``h`` applies.
    """
    n = int(elements_per_segment)
    if len(a.segments) == 1:
        return {a.segments[0].name: n}
    total = n * len(a.segments)
    return {s.name: max(MIN_SEGMENT_ELEMENTS, round(total * s.length / a.total_length),
                        math.ceil(abs(s.curvature) * s.length / MAX_ELEMENT_TURNING))
            for s in a.segments}


@dataclasses.dataclass(frozen=True)
class NonlinearCritical(Result):
    """Load factor at which the held state's lowest Hessian eigenvalue crosses zero.

    ``held_residual``: the held state's largest free-gradient component over the loads searched
    (the gradient is affine in the load: the larger of the two ends). When it is above
    :data:`HELD_RTOL` (the discretisation's O(l_e^2) error, e.g. a weld between elements of
    unequal length) the held state is ``relaxed`` by Newton at each load before its stability
    is judged: ``relaxed_residual`` is the largest free gradient left after Newton and
    ``relaxation_shift`` the largest change it made: a node's displacement over the total
    length, or a frame's rotation (rad), whichever is larger (NaN when not relaxed).
    """

    load_factor_critical: float
    elements_per_segment: int | dict[str, int]
    residual: float
    method: str
    held_residual: float = 0.0
    relaxed: bool = False
    relaxed_residual: float = math.nan
    relaxation_shift: float = math.nan
    #: |cos| between the held state's free gradient and the critical mode at the load found
    #: (relaxed only, else NaN). ~0 when symmetry keeps them apart (a planar design's joint
    #: moments against an out-of-plane mode): the bifurcation is exact. Above
    #: :data:`COUPLING_TOL` the relaxation is an imperfection of the critical mode (the
    #: bifurcation becomes a nearby fold or is passed by), said in ``method``.
    mode_coupling: float = math.nan
    #: How far the load is settled by the relaxed fixed-point iteration: its last change when
    #: it stopped shrinking above :data:`RELAX_XTOL` (:data:`RELAX_STALL_RTOL`), else 0. A
    #: bound on the load's error from Newton's tolerance, beside the mesh's O(l_e^2).
    load_spread: float = 0.0


#: The held state is an equilibrium of the discrete model (used as it is) when its free
#: gradient is at most this times ``max|B| / min l_e`` (x ``max(1, |load factor|)``) at both
#: ends of the search; else it is relaxed by Newton (:func:`critical_load_factor`).
HELD_RTOL = 1e-8
#: A relaxation that moves a node by more than this fraction of the total length, or turns a
#: frame by more than this (rad), is larger than a correction of the held state's
#: discretisation error (an O(l_e^2) joint moment: the arc split 0.6 / 1.4 turns a frame by
#: 0.18, 0.019, 0.0036 rad at 2, 4, 8 elements per segment) should be on a usable mesh: it is
#: checked on the mesh twice as fine (:data:`RELAX_REFINE_RATIO`) and the held state refused
#: as not an equilibrium unless the move falls there like l_e^2.
RELAX_MAX_SHIFT = 0.1
#: ... unless the mesh twice as fine relaxes it by at most 1 / this of the move: then the move
#: is the discretisation's O(l_e^2) error (ratio ~4) on a coarse mesh, not a state off
#: equilibrium (whose move does not fall with the mesh). Measured on the split arc 13.6 /
#: 0.2858 / 4.164 at 16 elements per segment (elements of length ratio 48 at the welds):
#: 0.151, 0.039 and 0.0098 rad at 16, 32, 64 elements at load factor 1.29.
RELAX_REFINE_RATIO = 3.0
#: Fixed-point iterations of the relaxed pencil (:func:`critical_load_factor`) and the relative
#: change of the load at which they stop; the relaxation changes the critical load by
#: O(l_e^2), so each iteration gains about that factor (3-4 iterations measured).
RELAX_ITER = 12
RELAX_XTOL = 1e-8
#: ... or where the change stops shrinking (the relaxed state is converged only to Newton's
#: tolerance, so the load it gives wanders: measured 3e-7 and 8e-6 relative on split arcs
#: welded between elements of length ratio 48 and 110, assemblies index 12 and 64 of the
#: differential test at 32 elements per segment), when it is at most this (relative, above
#: 1): far below the O(l_e^2) error it corrects, and reported as
#: :attr:`NonlinearCritical.load_spread`. (Before, such a wander fell back to the scan, which
#: relaxed the state at every load of the window and refused it far past the critical one.)
RELAX_STALL_RTOL = 1e-4
#: :attr:`NonlinearCritical.mode_coupling` above this is reported as an imperfect bifurcation.
COUPLING_TOL = 1e-6


def relaxation_shift(held: DiscreteRod, rod: DiscreteRod) -> float:
    """Return how far ``rod`` is from ``held`` (dimensionless).

    The larger of the largest node displacement over the total length and the largest frame
    rotation (rad).
    """
    turn = vee_log(np.swapaxes(np.concatenate([held.R_edge, held.R_joint]), 1, 2)
                   @ np.concatenate([rod.R_edge, rod.R_joint]))
    return max(float(np.max(np.abs(rod.x - held.x))) / held.assembly.total_length,
               float(np.max(np.linalg.norm(turn, axis=1))))


def _refined_shift(a: Assembly, elements_per_segment: int | dict[str, int], mu: float
                   ) -> float:
    """Return :func:`relaxation_shift` of Newton from the held state on the mesh twice as fine.

    At load factor ``mu``; inf when Newton fails or that mesh is past the default limits.
    """
    counts = {k: 2 * n for k, n in element_counts(a, elements_per_segment).items()}
    if nonlinear_dof(counts.values(), len(a.joints())) > DEFAULT_LIMITS.max_dof_nonlinear:
        return math.inf
    held = discretise(a, counts, mu)
    rod = held.copy()
    ok = newton(rod)[0]
    return relaxation_shift(held, rod) if ok else math.inf


def critical_load_factor(a: Assembly, lo: float, hi: float, *,
                         elements_per_segment: int | dict[str, int] = 32,
                         n_scan: int = 12) -> NonlinearCritical:
    """First load factor from ``lo`` towards ``hi`` at which the held state loses stability.

    The held state of the continuum is an equilibrium at every load (P2); the discrete one is
    up to its discretisation error, which vanishes on uniform meshes of a uniform arc but not
    at a weld between elements of unequal length (an O(l_e^2) joint moment). Its free gradient
    is affine in the load factor, so it is checked at ``lo`` and ``hi``: within
    :data:`HELD_RTOL`, the held state is used as it is; above, it is relaxed by Newton
    (:func:`newton`, two iterations from the held state) at each load before the stability
    check, and the relaxation is reported (:class:`NonlinearCritical`). A relaxation that fails,
    or that moves the state by more than :data:`RELAX_MAX_SHIFT` (of the length, or rad) and
    not by ``1 / RELAX_REFINE_RATIO`` of that on the mesh twice as fine (a move that does not
    fall with the mesh is not a discretisation error), is refused: that state is not near the
    held one and is left for the continuation tools, as are imposed end rotations (refused
    first).

    The held configuration does not move with the load and the energy is quadratic in it, so
    the free Hessian is affine in the load factor: ``H(mu) = H(lo) + t (H(hi) - H(lo))``,
    ``t = (mu - lo) / (hi - lo)``. Stable at ``lo`` (``H(lo)`` positive definite), the state
    is first lost where this pencil is first singular above ``lo``: one generalized eigen
    solve (:func:`rodstab.numerics.pencil_interval_sparse`, both matrices Jacobi-scaled by
    ``H(lo)``'s diagonal). A relaxed state moves with the load (by O(l_e^2)): the pencil of the
    state relaxed at the load found is solved again until that load repeats
    (:data:`RELAX_ITER`, :data:`RELAX_XTOL`), or stops changing by more than Newton's
    tolerance lets it (:data:`RELAX_STALL_RTOL`; the change reported as ``load_spread``).
    Unstable at ``lo``, with a sliding zero mode, or when the iteration does not settle, the
    lowest eigenvalue of the (relaxed) scaled Hessian is scanned from ``lo`` (``n_scan``
    intervals, up to the first sign change: :func:`_first_crossing`) and that sign change
    refined by the one root finder. ``residual``: the lowest scaled eigenvalue at the load
    found. ``elements_per_segment``: one count, or a count per segment name (for an assembly
    :func:`uniform_elements`: welds between elements of similar length). Accuracy: O(l_e^2),
    not estimated here (:func:`converged_critical_load_factor` refines the mesh until it
    is). A relaxed result
    states how far the relaxation is from the critical mode (``mode_coupling``): planar joint
    moments cannot move an out-of-plane bifurcation (arc split 0.6 / 1.4: 8 elements per
    segment 7.5505, 16: 7.4568, 32: 7.4327, 64: 7.4267 against the closed form's 7.4246, h^2).
    """
    turned = [f"{name}.{end}" for name, end, r in a.end_rotations if any(r)]
    if turned:
        raise RodstabInputError(f"the held state is not an equilibrium: the design turns the "
                                f"clamped end(s) {', '.join(turned)}; critical_load_factor "
                                f"follows the held state only (use the continuation tools)")
    held = discretise(a, elements_per_segment, lo)
    rod = held.copy()
    free = rod.free_dofs()
    scale = float(np.max(rod.edge_B) / np.min(rod.rest_length))

    def held_gradient(mu: float) -> float:
        held.load_factor = mu
        return float(np.max(np.abs(held.gradient()[free]))) if free.size else 0.0

    ends = [(mu, held_gradient(mu)) for mu in (lo, hi)]
    held_res = max(g for _, g in ends)
    relax = any(g > HELD_RTOL * scale * max(1.0, abs(mu)) for mu, g in ends)
    # "refined": the largest shift shown by a mesh twice as fine to be a discretisation
    # error (RELAX_REFINE_RATIO), "finer": that mesh's shift.
    worst = {"residual": 0.0, "shift": 0.0, "refined": 0.0, "finer": 0.0}

    def state_at(mu: float) -> None:
        """Put ``rod`` in the held state at ``mu``, relaxed by Newton when needed."""
        rod.assign(held)
        rod.load_factor = mu
        if not relax:
            return
        ok, _, res = newton(rod)
        shift = relaxation_shift(held, rod)
        if ok and shift > max(RELAX_MAX_SHIFT, worst["refined"]):
            finer = _refined_shift(a, elements_per_segment, mu)
            if finer <= shift / RELAX_REFINE_RATIO:
                # A discretisation error (it falls like l_e^2): the held state is near an
                # equilibrium, the mesh coarse; loads up to this shift need no new check.
                worst["refined"] = shift
                worst["finer"] = max(worst["finer"], finer)
            else:
                why = (f"Newton moved it by {shift:.3g} (of the total length, or rad), above "
                       f"RELAX_MAX_SHIFT = {RELAX_MAX_SHIFT:g}, and by {finer:.3g} on the "
                       f"mesh twice as fine: not a discretisation error")
                raise RodstabInputError(
                    f"the held state is not an equilibrium of the discrete model at load "
                    f"factor {mu:g} (free gradient {held_gradient(mu):.3g}): {why}")
        if not ok:
            raise RodstabInputError(
                f"the held state is not an equilibrium of the discrete model at load factor "
                f"{mu:g} (free gradient {held_gradient(mu):.3g}) and relaxing it failed: "
                f"Newton did not converge (free gradient {res:.3g})")
        worst["residual"] = max(worst["residual"], res)
        worst["shift"] = max(worst["shift"], shift)

    def hessian(mu: float) -> sp.csr_matrix:
        """Free Hessian of the current state at ``mu``."""
        rod.load_factor = mu
        Hf = rod.energy_terms()[2][free][:, free]
        return 0.5 * (Hf + Hf.T)

    def lam_min(mu: float) -> float:
        state_at(mu)
        return float(lowest_eigenvalues(rod, 1)[0])

    def pencil_load() -> float:
        """First singular load from ``lo`` of the current state's (affine) Hessian, or NaN."""
        A, B = hessian(lo), hessian(hi)
        D = sp.diags(jacobi_scaling(A))
        # K(t) = A - t C with C = A - B: stable for t below the pencil's upper end.
        t = pencil_interval_sparse((D @ A @ D).tocsc(), (D @ (A - B) @ D).tocsc()).hi
        return float(lo + t * (hi - lo)) if t <= 1.0 else math.nan

    def result(x: float, residual: float, method: str) -> NonlinearCritical:
        coupling = math.nan
        if relax:
            method += (f"; held state relaxed by Newton at each load (free gradient "
                       f"{held_res:.3g} -> {worst['residual']:.3g}, largest move "
                       f"{worst['shift']:.3g} of the length or rad)")
            if worst["refined"]:
                method += (f"; moves above RELAX_MAX_SHIFT accepted as discretisation error "
                           f"(up to {worst['finer']:.3g} on the mesh twice as fine): a coarse "
                           "mesh for this design")
        if relax and math.isfinite(x):
            state_at(x)
            v = lowest_modes(rod, 1)[1][:, 0]
            held.load_factor = x
            g = held.gradient()[free]
            coupling = float(abs(v @ g) / max(np.linalg.norm(v) * np.linalg.norm(g), 1e-300))
            if coupling > COUPLING_TOL:
                method += (f"; the relaxation is not orthogonal to the critical mode (|cos| "
                           f"{coupling:.2g}): an imperfect bifurcation, the load is a nearby "
                           "fold's or the closest approach's, not converged at O(l_e^2)")
        return NonlinearCritical(x, elements_per_segment, residual, method, held_res, relax,
                                 worst["residual"] if relax else math.nan,
                                 worst["shift"] if relax else math.nan, coupling, spread)

    spread = 0.0
    if lam_min(lo) > 0 and sliding_mode(rod) is None:
        x = pencil_load()
        settled = not relax
        change = math.inf
        for _ in range(RELAX_ITER if relax else 0):
            m = x if math.isfinite(x) else hi
            state_at(m)
            x = pencil_load()
            if not math.isfinite(x):  # the state relaxed at hi has no singular load
                if m == hi:
                    settled = True
                    break
                continue
            last, change = change, abs(x - m)
            scale_x = max(1.0, abs(x))
            if change <= RELAX_XTOL * scale_x:  # the load repeats
                settled = True
                break
            if last <= change <= RELAX_STALL_RTOL * scale_x:
                # No longer contracting: Newton's tolerance, not the relaxation, moves it.
                settled, spread = True, change
                break
        if settled:
            res = abs(lam_min(x)) if math.isfinite(x) else math.nan
            method = ("lowest singular load of the held state's Hessian pencil (affine in the "
                      "load factor), generalized eigen solve")
            if spread:
                method += (f"; the relaxed load settled to {spread:.2g} (Newton's tolerance), "
                           "not to RELAX_XTOL")
            return result(x, res, method)
    x, residual = _first_crossing(lam_min, lo, hi, n_scan)
    return result(x, residual, "lowest Hessian eigenvalue of the held state, scan from lo + "
                  "Brent")


def _first_crossing(f: Callable[[float], float], lo: float, hi: float, n_scan: int
                    ) -> tuple[float, float]:
    """Return the sign change of ``f`` nearest ``lo`` on ``[lo, hi]`` and ``|f|`` there.

    ``lo`` may be above ``hi``.

    ``n_scan`` intervals from ``lo`` towards ``hi``, evaluated in that order up to the first
    sign change only: loads past the loss of stability are not the answer, and there the
    held state's relaxation (:func:`critical_load_factor`) grows with the load until it is
    refused. :func:`rodstab.numerics.find_roots` then refines on ``lo`` .. that grid point
    (its close pairs and grid zeros included; values memoised). ``(nan, nan)`` when ``f``
    keeps its sign.
    """
    memo: dict[float, float] = {}

    def g(x: float) -> float:
        if x not in memo:
            memo[x] = f(x)
        return memo[x]

    xs = [float(x) for x in np.linspace(lo, hi, n_scan + 1)]
    f0 = g(xs[0])
    end = n_scan
    for i in range(1, n_scan + 1):
        if f0 == 0.0 or np.sign(g(xs[i])) != np.sign(f0):
            end = i
            break
    a_, b_ = min(lo, xs[end]), max(lo, xs[end])
    found = find_roots(g, a_, b_, n_scan=end) if b_ > a_ else None
    crossing = sorted((r for r in (found.roots if found else ())
                       if r.kind in ("sign-change", "grid-point")), key=lambda r: abs(r.x - lo))
    return (crossing[0].x, crossing[0].residual) if crossing else (math.nan, math.nan)


#: :func:`converged_critical_load_factor` doubles the mesh until its error estimate is below
#: this (relative above 1): the Richardson estimate of the finer mesh's error, which bounds the
#: extrapolated value's in the asymptotic range (there ~1e-5: the clamped arc and the ring).
CONVERGED_RTOL = 1e-3
#: The finest mesh :func:`converged_critical_load_factor` goes to, in elements per segment on
#: average (``this x S`` elements in all for ``S`` segments).
CONVERGED_MAX_ELEMENTS = 1024
#: Ratio of successive load differences of three doubled meshes that the O(l_e^2) error
#: predicts (4), within which :func:`converged_critical_load_factor` trusts Richardson. Two
#: meshes alone cannot tell the asymptotic range: a split arc (rectangle h/t = 9.547, four
#: arcs of 18.8 in all; differential test seed 1, assemblies index 183) gave 2.06487,
#: 2.06770, 2.06528, 2.06527 on 128 ... 1024 elements, and the first two extrapolated to
#: 2.06864 +- 9.4e-4, 1.6e-3 off the closed form 2.0653186.
ASYMPTOTIC_RATIO = (2.0, 8.0)
#: Fraction of the tolerance below which two meshes' Richardson estimate is accepted without a
#: third (index 183's pair: 0.45 of it).
TWO_MESH_MARGIN = 0.1


@dataclasses.dataclass(frozen=True)
class ConvergedCritical(Result):
    """A discrete rod's critical load factor refined until its error estimate is small.

    ``load_factor_critical``: the order-2 Richardson value of the last two meshes (NaN when
    neither finds a loss of stability in the window); ``error``: its estimate (absolute,
    load-factor units): the finer mesh's Richardson error plus what the meshes'
    ``load_spread`` (Newton's tolerance) can move the extrapolation by; ``converged``:
    ``error <= target_rtol max(|value|, 1)``; never True otherwise. ``loads``: the critical
    load of each mesh, ``elements``: its elements in all, ``elements_per_segment``: the
    finest mesh's counts.
    """

    load_factor_critical: float
    error: float
    converged: bool
    target_rtol: float
    loads: tuple[float, ...]
    elements: tuple[int, ...]
    elements_per_segment: dict[str, int]
    method: str
    finest: NonlinearCritical


def _asymptotic(loads: Sequence[float], tol: float) -> bool:
    """Whether the last three loads of doubled meshes show the O(l_e^2) error's behaviour.

    The successive differences must shrink by :data:`ASYMPTOTIC_RATIO` (4 predicted), or both
    lie below a quarter of the tolerance ``tol`` (the sequence has settled within it, which a
    difference at round-off level makes any ratio of).
    """
    if len(loads) < 3:
        return False
    d1, d2 = loads[-2] - loads[-3], loads[-1] - loads[-2]
    if max(abs(d1), abs(d2)) <= tol / 4.0:
        return True
    return d2 != 0.0 and ASYMPTOTIC_RATIO[0] <= d1 / d2 <= ASYMPTOTIC_RATIO[1]


def converged_critical_load_factor(a: Assembly, lo: float, hi: float, *,
                                   elements_per_segment: int = 32,
                                   rtol: float = CONVERGED_RTOL,
                                   max_elements: int = CONVERGED_MAX_ELEMENTS,
                                   limits: Limits = DEFAULT_LIMITS) -> ConvergedCritical:
    """:func:`critical_load_factor` on meshes doubled until the Richardson estimate holds.

    Meshes ``m, 2 m, 4 m, ...`` with ``m = uniform_elements(a, elements_per_segment)`` (one
    element size: every count doubles, so the error ``~ C l_e^2`` of the discrete rod, second
    order, is extrapolated by :func:`rodstab.numerics.richardson` with ratio 2, order 2).
    Stops when the error estimate (:class:`ConvergedCritical`) is at most ``rtol max(|value|,
    1)``, with two meshes at most :data:`TWO_MESH_MARGIN` of it or else the last three in the
    asymptotic range (:func:`_asymptotic`: their differences shrink about fourfold), and returns
    the extrapolated value with it; stops unconverged (``converged`` False, the estimate reached
    in ``error``) when the next mesh would pass ``max_elements`` per segment on average or
    ``limits``, or when two meshes running find no loss of stability in the window. A fixed 32
    elements per segment was 52 % off on a clamped arc of L/R = 16 with b1 = 100, b2 = 30 (too
    few elements per mode wavelength to be in the asymptotic range), and 1.2e-2 on a split arc
    of L/R = 6.667 at load factor -18.9 (differential test, assemblies index 7).
    """
    from ..numerics import richardson

    base = uniform_elements(a, elements_per_segment)
    k = 1
    loads: list[float] = []
    totals: list[int] = []
    results: list[NonlinearCritical] = []
    value, err = math.nan, math.nan

    def finish(converged: bool, why: str) -> ConvergedCritical:
        last = results[-1]
        method = (f"discrete rod on {', '.join(str(t) for t in totals)} elements (one element "
                  f"size, doubled), order-2 Richardson of the last two; {why}; finest: "
                  f"{last.method}")
        return ConvergedCritical(value, err, converged, rtol, tuple(loads), tuple(totals),
                                 dict(last.elements_per_segment)
                                 if isinstance(last.elements_per_segment, dict) else {},
                                 method, last)

    while True:
        mesh = {name: n * k for name, n in base.items()}
        total = sum(mesh.values())
        if loads and (total > max_elements * len(a.segments) or nonlinear_dof(
                mesh.values(), len(a.joints())) > limits.max_dof_nonlinear):
            return finish(False, f"not converged: error estimate {err:.2g} above "
                          f"{rtol:g} x max(|value|, 1) with {totals[-1]} elements; the next "
                          f"mesh ({total}) is past the limit")
        require_nonlinear(mesh.values(), len(a.joints()), f"{total} elements", limits)
        found = critical_load_factor(a, lo, hi, elements_per_segment=mesh)
        results.append(found)
        loads.append(found.load_factor_critical)
        totals.append(total)
        if len(loads) >= 2:
            value, err = richardson(loads[-2], loads[-1], 2.0, 2)
            # Newton's tolerance moves each load by up to its spread; the extrapolation
            # (4 fine - coarse) / 3 carries 4/3 and 1/3 of them.
            err += (4.0 * results[-1].load_spread + results[-2].load_spread) / 3.0
            tol = rtol * max(abs(value), 1.0)
            # Two meshes are trusted only with a tenfold margin (in the asymptotic range the
            # estimate is ~1e-5); nearer the tolerance, three meshes must show the order.
            if math.isfinite(err) and (err <= TWO_MESH_MARGIN * tol
                                       or (err <= tol and _asymptotic(loads, tol))):
                return finish(True, f"error estimate {err:.2g}")
            if not any(math.isfinite(x) for x in loads[-2:]):
                value, err = math.nan, math.nan
                return finish(False, "no loss of stability in the window on the last two "
                              "meshes")
        k *= 2
