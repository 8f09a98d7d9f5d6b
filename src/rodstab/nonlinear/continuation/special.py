"""Special points of a path: folds and branch points, told apart and located.

From the Hessian (lowest eigenvalue of the Jacobi-scaled free Hessian, rigid motions and the
uniform ring's sliding mode left out, :func:`..solve.lowest_modes`), between two accepted
points of a path:

* a sign change of ``t_p`` is a turning point of the parameter: a **fold** when the critical
  mode is transversal to ``dg/dp`` (``|cos| > FOLD_COS``), else a symmetric **branch point**
  that the path turned onto; located from the parabola ``p(s)`` through the refined bracket;
* a sign change of the lowest eigenvalue without one is a **branch point** where stability is
  lost or regained: the bracket is re-traced twice with an eighth of the step and the zero
  located by the root finder (Brent) on the eigenvalue of the state solved by Newton at each
  trial ``p`` in the refined bracket.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
import scipy.sparse as sp

from ...errors import NotConverged, RodstabInputError
from ...numerics import refine_root
from ..discrete import DiscreteRod
from ..parameters import Parameter
from ..solve import lowest_modes, newton
from .corrector import Stepper
from .path import SpecialKind

#: |cos(critical mode, dg/dp)| above which a turning point of the parameter is a fold.
FOLD_COS = 1e-3


def lowest(rod: DiscreteRod, hessian: sp.spmatrix | None = None) -> float:
    """Return the lowest (scaled) Hessian eigenvalue of ``rod``: > 0 stable.

    ``hessian``: the full Hessian at ``rod``'s state when the caller has it.
    """
    return float(lowest_modes(rod, 1, hessian)[0][0])


def _refine(param: Parameter, prev: DiscreteRod, tq: np.ndarray, tp: float, h: float,
            indicator: Callable[[DiscreteRod, Stepper], float], v0: float,
            phase: np.ndarray | None) -> tuple[DiscreteRod, tuple, tuple | None, float]:
    """Re-trace a bracket twice with an eighth of the step until ``indicator`` changes sign.

    Returns the state at the bracket's start, its (p, indicator) ends and the step used.
    """
    lo, lo_tq, lo_tp = prev.copy(), tq, tp
    b0, b1 = (param.get(prev), v0), None
    for _ in range(2):
        h = h / 8
        walker = lo.copy()
        path = Stepper(walker, param, lo_tq, lo_tp, h, phase=phase)
        last = b0
        for _ in range(24):
            saved = (walker.copy(), path.tq.copy(), path.tp)
            if not path.step():
                break
            v = indicator(walker, path)
            if (v > 0) != (b0[1] > 0):
                b0, b1 = last, (param.get(walker), v)
                lo, lo_tq, lo_tp = saved
                break
            last = (param.get(walker), v)
    return lo, b0, b1, h


def locate(rod: DiscreteRod, param: Parameter, prev: DiscreteRod, prev_tq: np.ndarray,
           prev_tp: float, prev_h: float, e0: float, e1: float, tp_now: float, *,
           phase: np.ndarray | None = None) -> tuple[dict, DiscreteRod | None]:
    """Classify and locate the special point between ``prev`` and ``rod`` (module docstring).

    Returns the point (``kind``, ``value``, ``bracket``, and for turning points
    ``mode_cosine_with_dg_dp``) and the state there (None if Newton failed there).
    """
    if (prev_tp > 0) != (tp_now > 0):
        # Near a turning point p(s) is a parabola in the arclength s, t_p = dp/ds linear: from
        # the two ends of the refined bracket, s* = ds tp0 / (tp0 - tp1), p* = p0 + tp0 s* / 2.
        lo, (p0, t0), b1, h = _refine(param, prev, prev_tq, prev_tp, prev_h,
                                      lambda r, path: path.tp, prev_tp, phase)
        if b1 is None:
            p0, t0, p1, t1 = param.get(prev), prev_tp, param.get(rod), tp_now
            h = prev_h
        else:
            p1, t1 = b1
        ds = 2 * (p1 - p0) / (t0 + t1) if abs(t0 + t1) > 1e-3 * abs(t0 - t1) else h
        p_fold = p0 + t0 * (ds * t0 / (t0 - t1)) / 2
        # A fold has its critical mode transversal to dg/dp; a symmetric branch point (where
        # the path turned onto the secondary branch) has it orthogonal.
        _, vec = lowest_modes(lo, 1)
        gp = param.dgrad(lo)[lo.free_dofs()]
        cos = abs(vec[:, 0] @ gp) / max(np.linalg.norm(vec[:, 0]) * np.linalg.norm(gp), 1e-300)
        kind = SpecialKind.FOLD if cos > FOLD_COS else SpecialKind.BRANCH_TURNED
        return ({"kind": kind.value, "value": float(p_fold), "bracket": sorted([p0, p1]),
                 "mode_cosine_with_dg_dp": float(cos)}, lo)
    lo, b0, b1, _ = _refine(param, prev, prev_tq, prev_tp, prev_h, lambda r, path: lowest(r),
                            e0, phase)
    (m0, v0), (m1, v1) = b0, b1 if b1 is not None else (param.get(rod), e1)
    p_c = m0 + (m1 - m0) * v0 / (v0 - v1)
    kind = SpecialKind.LOST if e0 > 0 else SpecialKind.REGAINED

    def at_value(p: float) -> DiscreteRod | None:
        s = lo.copy()
        param.set(s, p)
        return s if newton(s)[0] else None

    def eig(p: float) -> float:
        s = at_value(p)
        if s is None:  # a NaN would stop Brent with a ValueError (64 el., contact, measured)
            raise NotConverged(f"no equilibrium at {p!r} inside the bracket")
        return lowest(s)

    # Refine the interpolated zero by the one root finder on the bracket (Brent to XTOL of it):
    # at the exact branch point both eigenvalues of a double pair vanish, which is how
    # .branches tells a double eigenvalue from a small second one.
    note = None
    if m0 != m1 and (v0 > 0) != (v1 > 0):
        try:
            p_c = refine_root(eig, m0, m1)
        except RodstabInputError:  # re-solved ends without a sign change: the interpolation
            pass
        except NotConverged as exc:  # said, not hidden: the value is the interpolation
            note = f"not refined ({exc}): interpolated in the bracket"
    point: dict = {"kind": kind.value, "value": float(p_c),
                   "bracket": sorted([float(m0), float(m1)])}
    if note is not None:
        point["refined"] = note
    return point, at_value(p_c)


def crossed(e0: float, e1: float, tp0: float, tp1: float) -> bool:
    """Test for a special point between two points with these eigenvalues and tangents ``t_p``."""
    return (e0 > 0) != (e1 > 0) or (tp0 > 0) != (tp1 > 0)
