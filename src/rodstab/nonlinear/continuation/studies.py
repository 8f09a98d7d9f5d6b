"""Studies built on continuation: critical loads off the held state, imperfection sensitivity.

The critical load along a primary path that is not the held state, and imperfection sensitivity.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from ...errors import RodstabInputError
from ...model import Assembly
from ...results import Result
from ..discrete import DiscreteRod, discretise, held_curvatures
from ..parameters import parameter
from .branches import branch_directions
from .path import SpecialKind, reference_length
from .run import continuation


@dataclasses.dataclass(frozen=True)
class PrimaryCritical(Result):
    """First loss of stability along the primary equilibrium path (found by continuation)."""

    load_factor_critical: float
    bracket: tuple[float, float]
    steps: int
    method: str


def critical_along_primary(a: Assembly, mu_start: float, mu_stop: float, *,
                           elements_per_segment: int = 32, ds: float = 0.05) -> PrimaryCritical:
    """Find the critical load of a primary path that is NOT the held state (e.g. a twisted ring).

    The first branch point or fold of :func:`.continuation` in the load factor (no branch traced),
    located in a bracket re-traced to ``ds / 64`` (error well below the discretisation's).
    """
    c = continuation(a, "load_factor", mu_start, mu_stop,
                     max(1, int(math.ceil(abs(mu_stop - mu_start) / ds))),
                     elements_per_segment=elements_per_segment, branch_steps=0,
                     stop_at_first=True)
    if c.lowest_eigenvalue[0] <= 0:
        return PrimaryCritical(math.nan, (math.nan, math.nan), 0,
                               "no stable equilibrium at mu_start")
    lost = [s for s in c.special_points if s["kind"] != SpecialKind.REGAINED.value]
    if not lost:
        return PrimaryCritical(math.nan, (math.nan, math.nan), len(c.value),
                               "no loss of stability before mu_stop")
    return PrimaryCritical(float(lost[0]["value"]), tuple(lost[0]["bracket"]), len(c.value),
                           "pseudo-arclength along the primary path, eigenvalue sign change")


@dataclasses.dataclass(frozen=True)
class ImperfectionSensitivity(Result):
    """Limit values of imperfect structures (imperfection ``eps L`` times the critical mode)."""

    key: str
    value_critical: float
    epsilon: tuple[float, ...]
    limit_value: tuple[float, ...]
    paths: tuple[tuple[tuple[float, float], ...], ...]  # per eps: (p, largest displacement)
    exponent: float
    verdict: str
    method: str


def imperfect(state: DiscreteRod, target: DiscreteRod, vec: np.ndarray, eps: float
              ) -> DiscreteRod:
    """Return ``target`` (a held state) whose natural shape contains ``eps`` times a mode.

    The mode is ``vec`` (free unknowns) of ``state``: every joint's natural curvature changes by the
    curvature change that the displacement ``eps * vec`` causes at ``state``; the supports stay.
    """
    moved = state.copy()
    dq = np.zeros(state.n_dof)
    dq[state.free_dofs()] = eps * vec
    moved.apply(dq)
    kp0, kl0 = held_curvatures(state)
    kp1, kl1 = held_curvatures(moved)
    imp = target.copy()
    imp.k_held_pairs = target.k_held_pairs + (kp1 - kp0)
    assert target.k0_links is not None  # set by discretise
    a, b = target.k0_links
    imp.k0_links = (a + (kl1 - kl0), b)
    return imp


def imperfection_sensitivity(a: Assembly, key: str, start: float, stop: float, *,
                             epsilons: tuple[float, ...] = (1e-3, 2e-3, 4e-3, 8e-3),
                             elements_per_segment: int = 16,
                             n_steps: int = 20) -> ImperfectionSensitivity:
    """Find the limit value ``p_max(eps)`` of parameter ``key`` for imperfections of size ``eps``.

    Imperfections of amplitude ``eps L`` (``L``: total length; mode scaled to a largest entry of 1)
    shaped like the critical mode of the perfect structure.

    The perfect path from ``start`` towards ``stop`` gives the critical value ``p_c`` and its
    mode (:func:`.continuation`); each imperfect structure is followed from ``start`` by the
    same continuation up to its first fold or loss of stability. No such point before ``stop``
    means imperfection-insensitive at that amplitude (NaN). The exponent is the slope of
    ``log |p_c - p_max|`` against ``log eps`` (2/3 for an unstable symmetric bifurcation, 1/2
    for an asymmetric one).
    """
    n = elements_per_segment
    if not epsilons or any(isinstance(e, bool) or not isinstance(e, (int, float)) or
                           not math.isfinite(e) or e <= 0 for e in epsilons):
        raise RodstabInputError(f"epsilons must be one or more positive numbers, got "
                                f"{epsilons!r}")
    perfect = continuation(a, key, start, stop, n_steps, elements_per_segment=n,
                           branch_steps=0, stop_at_first=True)
    if not perfect.states:
        raise RodstabInputError(f"the perfect structure does not lose stability between "
                                f"{key} = {start!r} and {stop!r}")
    p_c, state = perfect.states[0]
    # The imperfection is shaped like the critical mode -- at a double eigenvalue the most
    # dangerous branch direction, so the result does not depend on the eigen solver's basis.
    side = math.copysign(1.0, start - p_c)
    mode = branch_directions(state, parameter(a, key, n), side, reference_length(a))[0].mode
    v = mode / np.max(np.abs(mode))
    limits, paths = [], []
    for eps in epsilons:
        imp = imperfect(state, discretise(a, n), v, eps * a.total_length)
        c = continuation(a, key, start, stop, n_steps, elements_per_segment=n, branch_steps=0,
                         stop_at_first=True, rod=imp)
        # An imperfection breaks the bifurcation: the first loss of stability is a fold. A
        # long step may jump past it onto a nearby branch, but the bracket is re-traced with
        # small steps from the stable side, which stops at the fold's zero eigenvalue; a
        # result that does not grow with eps is reported as inconclusive below.
        lost = [s for s in c.special_points if s["kind"] != SpecialKind.REGAINED.value]
        limits.append(float(lost[0]["value"]) if lost else math.nan)
        paths.append(tuple(zip(c.value, c.amplitude, strict=True)))
    lim = np.array(limits)
    side = math.copysign(1.0, start - p_c)  # the stable side of p_c
    ok = np.isfinite(lim) & ((lim - p_c) * side > 0)
    slope = (np.polyfit(np.log(np.array(epsilons)[ok]), np.log(np.abs(lim[ok] - p_c)), 1)[0]
             if ok.sum() >= 2 else math.nan)
    if ok.sum() >= 2 and slope > 0:
        exponent = float(slope)
        verdict = f"imperfection-sensitive: |p_c - p_max| ~ eps^{exponent:.3f}"
    elif ok.any():
        exponent = math.nan
        verdict = ("inconclusive: limit points found but they do not grow with the "
                   "imperfection (refine n_steps or the mesh)")
    else:
        exponent = math.nan
        verdict = (f"no limit point between {start:g} and {stop:g} for these amplitudes: "
                   "imperfection-insensitive (stable post-buckling)")
    return ImperfectionSensitivity(key, float(p_c), tuple(epsilons), tuple(limits),
                                   tuple(paths), exponent, verdict,
                                   "pseudo-arclength continuation, folds and Hessian eigenvalues")
