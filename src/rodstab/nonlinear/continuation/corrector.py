"""One bordered Newton corrector and the predictor-corrector stepper built on it.

Every traced curve of :mod:`rodstab.nonlinear.continuation` -- the primary path in any
parameter ``p``, a branch from a bifurcation under arclength control, a branch under amplitude
control -- solves the equilibrium equations ``g(q, p) = 0`` together with **one linear
constraint row** on the increment ``(dq, dp)`` accumulated since the start of the step::

    [ H      dg/dp  z ] [dq   ]     [ g + sigma z                      ]
    [ r_q^T  r_p    0 ] [dp   ] = - [ r_q . acc_q + r_p . acc_p - c    ]
    [ z^T    0      0 ] [sigma]     [ z . acc_q                        ]

* arclength (Keller): ``r = (t_q, t_p)``, ``c = h`` (the step length along the unit tangent);
* amplitude: ``r = (e_k, 0)``, ``c`` = the prescribed change of the free unknown ``k``;
* phase (optional third row and column, ``z``): picks one member of a continuous family of
  equilibria (a uniform ring's material sliding, an isotropic rod's rotation about its axis)
  where the bordered matrix alone is singular; a true equilibrium has ``sigma = 0``, checked.

Converged when the free gradient is below ``FORCE_RTOL`` of the stiff (stretch/shear) force
scale, the constraint holds, and the last Newton update is below ``STEP_TOL`` (length unit, and
relative to ``max(1, |p|)`` for ``p``). The update test matters: the force test alone stops
while ``p`` is still wrong by ~1e-6, which is the size of ``p - p_c`` on a branch at
amplitude 1e-3 and flips a fitted post-buckling coefficient (issue 9). Failed after
``MAX_ITER`` iterations, or as soon as an update leaves a free gradient above
``DIVERGED_RTOL`` of that scale.
"""

from __future__ import annotations

import math
import warnings
from typing import NamedTuple

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from ..contact import Interpenetration
from ..discrete import PENALTY, DiscreteRod
from ..newton import contact_fraction
from ..parameters import Parameter, Terms
from ..solve import sliding_mode, vee_log

#: Free-gradient tolerance, relative to PENALTY max|B| / min l_e (the stiffest forces).
FORCE_RTOL = 1e-9
#: Largest last Newton update of a converged point (length unit; relative for p).
STEP_TOL = 1e-11
#: Constraint residual tolerance relative to the constraint's target.
CONSTRAINT_RTOL = 1e-10
#: |sigma| max|z| below this times the force scale: the phase-pinned point is an equilibrium.
PHASE_RTOL = 1e-8
#: Corrector iterations before a step is declared failed (and halved).
MAX_ITER = 25
#: After a Newton update, a free gradient above this times the stiff force scale (stretch and
#: shear strains of order one, where an equilibrium has ~1/PENALTY) means the iteration has
#: left the path: the step fails at once instead of after MAX_ITER iterations. Measured over
#: every corrector call of ``rodstab reproduce`` (2249): the converged ones stayed below 0.23
#: after their first update, and all 149 that exceeded 1 went on to fail after MAX_ITER (29 %
#: of all the Newton iterations, 64 % of the transition checks').
DIVERGED_RTOL = 1.0
#: Largest turn of the path's tangent over one accepted step (rad). Near a fold the tangent
#: is almost pure q and the corrector, which moves across it, may slide far in p within the
#: jump guard's ``2 h``: the six-ring's saddle path at 12 el./segment (the T-six check) once
#: jumped from kappa_n R0 = 0.0733 past its fold (0.0726) to -0.264, turning its tangent by
#: 54 deg, while every other step of that path and of the 8-element one turned by at most
#: 32 deg (the first, off the bifurcation) and mostly by under 10 (measured 2026-12-06).
MAX_TANGENT_TURN = math.pi / 4


def force_scale(rod: DiscreteRod) -> float:
    """PENALTY max|B| / min l_e: the scale of the stiff stretch/shear forces of ``rod``."""
    return float(PENALTY * np.max(rod.edge_B) / np.min(rod.rest_length))


def solve_bordered(M: sp.spmatrix, rhs: np.ndarray) -> np.ndarray | None:
    """Solve a bordered system, with a minimum-norm fallback at a double eigenvalue.

    At a double eigenvalue (singular ``M``: a second critical mode) take the minimum-norm solution,
    which keeps that mode's amplitude. None if that fails too (or the system is too large for the
    dense fallback).
    """
    with np.errstate(all="ignore"), warnings.catch_warnings():
        warnings.simplefilter("ignore")
        sol = spla.spsolve(M.tocsc(), rhs)
    if np.all(np.isfinite(sol)):
        return sol
    if M.shape[0] > 4000:
        return None
    sol = np.linalg.lstsq(M.toarray(), rhs, rcond=1e-12)[0]
    return sol if np.all(np.isfinite(sol)) else None


def bordered_matrix(H: sp.spmatrix, gp: np.ndarray, row_q: np.ndarray, row_p: float,
                    z: np.ndarray | None) -> sp.spmatrix:
    """``[[H, g_p, z], [r_q^T, r_p, 0], [z^T, 0, 0]]`` (the last row/column only with ``z``).

    Assembled from coordinate lists in one conversion (scipy's ``bmat`` of the same blocks
    gives the same matrix, entry order included, at four times the cost: a third of a
    corrector iteration on the small systems of the report).
    """
    n = H.shape[0]
    m = n + (1 if z is None else 2)
    Hc = H.tocoo()
    rows, cols, vals = [Hc.row], [Hc.col], [Hc.data]

    def add(r: np.ndarray | int, c: np.ndarray | int, v: np.ndarray) -> None:
        keep = v != 0  # only the nonzeros, as a sparse block of them would hold
        rows.append(np.broadcast_to(r, v.shape)[keep])
        cols.append(np.broadcast_to(c, v.shape)[keep])
        vals.append(v[keep])

    # Block order of bmat: row by row of blocks, each block's entries in its own order.
    every = np.arange(n)
    add(every, n, gp)
    if z is not None:
        add(every, n + 1, z)
    add(n, every, row_q)
    add(n, n, np.array([row_p], float))
    if z is not None:
        add(n + 1, every, z)
    return sp.coo_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
                         shape=(m, m)).tocsc()


class Corrected(NamedTuple):
    """A converged :func:`correct`: the phase multiplier and the energy terms at the point."""

    sigma: float
    #: ``(E, g, H)`` of the converged state, which the corrector formed for its last test:
    #: the tangent and the stability there need not form them again.
    terms: Terms


def correct(rod: DiscreteRod, param: Parameter, row_q: np.ndarray, row_p: float,
            target: float, *, acc_q: np.ndarray, acc_p: float, phase: np.ndarray | None = None,
            max_iter: int = MAX_ITER) -> Corrected | None:
    """Newton on ``g(q, p) = 0`` and ``r_q . acc_q + r_p . acc_p = target`` (in place).

    ``acc_q``, ``acc_p``: the increment already accumulated since the start of the step (the
    predictor's). Returns the phase multiplier ``sigma`` (0 without ``phase``) of the converged
    point (module docstring) with the energy terms there, or None; on failure the state is left
    where the iteration stopped (the caller restores it). :func:`pinned_equilibrium` says
    whether ``sigma`` is 0.
    """
    free = rod.free_dofs()
    n = len(free)
    scale = force_scale(rod)
    ctol = CONSTRAINT_RTOL * max(abs(target), 1e-12)
    sigma, last = 0.0, math.inf
    acc_q = np.array(acc_q, float)
    for it in range(max_iter + 1):
        try:
            terms = rod.energy_terms()
        except Interpenetration:  # only with contact: a predictor outside the model
            return None
        _, g, H = terms
        gf = g[free] if phase is None else g[free] + sigma * phase
        if it > 0 and np.max(np.abs(gf)) > DIVERGED_RTOL * scale:
            return None
        c = float(row_q @ acc_q + row_p * acc_p - target)
        c2 = 0.0 if phase is None else float(phase @ acc_q)
        if (np.max(np.abs(gf)) <= FORCE_RTOL * scale and abs(c) <= ctol and abs(c2) <= ctol
                and last <= STEP_TOL):
            return Corrected(sigma, terms)
        gp = param.dgrad(rod, terms)[free]
        rhs = -np.concatenate([gf, [c]] + ([] if phase is None else [[c2]]))
        sol = solve_bordered(bordered_matrix(H[free][:, free], gp, row_q, row_p, phase), rhs)
        if sol is None:
            return None
        if rod.contact is not None:  # damped: the step closes no gap (the step filter)
            sol = sol * contact_fraction(rod, free, sol[:n])
        dq = np.zeros(rod.n_dof)
        dq[free] = sol[:n]
        rod.apply(dq)
        p = param.get(rod) + float(sol[n])
        param.set(rod, p)
        acc_q += sol[:n]
        acc_p += float(sol[n])
        if phase is not None:
            sigma += float(sol[n + 1])
        last = max(float(np.max(np.abs(sol[:n]))), abs(float(sol[n])) / max(1.0, abs(p)))
    return None


def pinned_equilibrium(rod: DiscreteRod, result: Corrected | None,
                       phase: np.ndarray | None) -> bool:
    """Return whether :func:`correct` converged to a true equilibrium (``sigma`` ~ 0)."""
    if result is None:
        return False
    return phase is None or abs(result.sigma) * float(np.max(np.abs(phase))) <= PHASE_RTOL * \
        force_scale(rod)


def tangent(rod: DiscreteRod, param: Parameter, tq_prev: np.ndarray, tp_prev: float,
            phase: np.ndarray | None = None, terms: Terms | None = None
            ) -> tuple[np.ndarray, float]:
    """Return the unit tangent of the path: ``[H dg/dp; t_prev^T] t = [0; 1]``, normalised.

    Oriented along the previous tangent (kept if the solve fails). ``terms``: the energy terms
    at ``rod``'s state when the caller has them.
    """
    free = rod.free_dofs()
    n = len(free)
    terms = rod.energy_terms() if terms is None else terms
    H = terms[2]
    gp = param.dgrad(rod, terms)[free]
    rhs = np.zeros(n + (1 if phase is None else 2))
    rhs[n] = 1.0
    t = solve_bordered(bordered_matrix(H[free][:, free], gp, tq_prev, tp_prev, phase), rhs)
    if t is None:
        return tq_prev, tp_prev
    t = t[: n + 1] / np.linalg.norm(t[: n + 1])
    if t[:n] @ tq_prev + t[n] * tp_prev < 0:
        t = -t
    return t[:n], float(t[n])


def distance(rod: DiscreteRod, other: DiscreteRod, dp: float) -> float:
    """Distance in (positions, rotation increments, p) between two states of one rod."""
    dx = (rod.x - other.x).ravel()
    de = vee_log(np.swapaxes(other.R_edge, 1, 2) @ rod.R_edge).ravel()
    dj = vee_log(np.swapaxes(other.R_joint, 1, 2) @ rod.R_joint).ravel()
    return math.sqrt(float(dx @ dx + de @ de + dj @ dj) + dp * dp)


class Stepper:
    """Pseudo-arclength predictor-corrector on ``rod`` (updated in place).

    Predictor ``(q, p) + h t``, :func:`correct` with the arclength row, next tangent from
    :func:`tangent`. The step halves when the corrector fails, the corrected point lies
    farther than ``2 h`` from the step's start (it jumped to another branch) or the tangent
    turned by more than :data:`MAX_TANGENT_TURN` (it slid past a fold), and grows by 1.5
    after a success up to ``h_max``. On a non-circular state of a uniform closed ring the
    material-sliding family is pinned by its own mode; otherwise by ``phase`` if given.
    ``terms``: the energy terms at the state of the last accepted step (None before one; no
    longer the rod's once the caller moves it).
    """

    def __init__(self, rod: DiscreteRod, param: Parameter, tq: np.ndarray, tp: float,
                 h: float, h_max: float | None = None, phase: np.ndarray | None = None) -> None:
        nrm = math.sqrt(float(tq @ tq) + tp * tp)
        self.rod, self.param, self.phase = rod, param, phase
        self.tq, self.tp = tq / nrm, tp / nrm
        self.h = h
        self.h_min = 1e-4 * h
        self.h_max = h if h_max is None else h_max
        self.last_h = h
        self.terms: Terms | None = None

    def _phase(self) -> np.ndarray | None:
        z = sliding_mode(self.rod)
        return self.phase if z is None else z / np.linalg.norm(z)

    def step(self) -> bool:
        """One accepted step (halving on failure); False once the step is below ``h_min``."""
        rod, free = self.rod, self.rod.free_dofs()
        phase = self._phase()
        while self.h >= self.h_min:
            saved = rod.copy()
            p0 = self.param.get(rod)
            dq = np.zeros(rod.n_dof)
            dq[free] = self.h * self.tq
            rod.apply(dq)
            self.param.set(rod, p0 + self.h * self.tp)
            result = correct(rod, self.param, self.tq, self.tp, self.h, acc_q=self.h * self.tq,
                             acc_p=self.h * self.tp, phase=phase)
            if result is not None and pinned_equilibrium(rod, result, phase) \
                    and distance(rod, saved, self.param.get(rod) - p0) <= 2 * self.h:
                tq, tp = tangent(rod, self.param, self.tq, self.tp, phase, result.terms)
                if float(tq @ self.tq) + tp * self.tp >= math.cos(MAX_TANGENT_TURN):
                    self.terms = result.terms
                    self.tq, self.tp = tq, tp
                    self.last_h = self.h
                    self.h = min(1.5 * self.h, self.h_max)
                    return True
            rod.assign(saved)
            self.h *= 0.5
        return False
