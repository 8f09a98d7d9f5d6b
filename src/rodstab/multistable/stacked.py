"""N-loop rings held with contact, and their stability limits with contact (issue 21, parts 2-3).

The stacked state of :func:`~.stacking.stack_loops` (the ``(N, 1)`` torus curve at thickness
``h`` and gap ``g0``) is relaxed with the contact model of :mod:`rodstab.nonlinear.contact`
switched on, by Newton at load factor ``mu`` (natural curvature ``mu kappa_n``; the ring's units
``R0 = B3 = 1``, so ``mu = R0 kappa_n`` and ``(L / 2 pi) kappa_n = N mu``), and its stability is
the sign of the lowest eigenvalue of the unprojected rod + contact Hessian (the verdict of
:func:`~rodstab.nonlinear.stability.stability_eigenvalues`, absolute coordinates, with its zero
tolerance :func:`~rodstab.nonlinear.stability.zero_eigenvalue_tol`).

What holds the strands together. The torus curve is the coincident ring plus its Fourier mode
``j = 1`` (``u_r = a cos(theta / N)``, ``u_3 = a sin(theta / N)``, ``theta`` the angle along
all ``N`` loops). Inside the no-contact interval that mode is stable (eq. 3.3: ``M < M^-(k =
1/N)``, 0.560 for the circle at ``N = 3``), so the rod's energy rises as ``a^2`` and the
strands press on one another even at zero natural-curvature mismatch (``mu = 1``): each is
pushed towards the bundle's axis with a line load ``p ~ s(M) B3 a / R0^4``, ``s`` the mode's
stiffness, which vanishes at ``M = M^-(1/N)``; there the strands would part.

What it relaxes to (measured, circle, ``N = 3``, ``mu = 1``, 32 elements per loop, ``h / L =
0.01``, ``dhat = 0.1 h``): not the torus curve. The strands settle into layers (largest
``|z|`` 1.3 h against the torus's ``a`` = 0.64 h) that change over in a crossing region, with
contact on ~70 % of the nodes and line loads from ~0 to 3.5 times their mean; energy 0.032
``B3 / R0`` above the coincident ring (the torus start: 0.077). The excess falls as ``(h /
L)^2`` and the height as ``h`` (tests): the planar held state is the thin limit.

Contact model (the rule, :func:`stacked_contact_model`): capsules of radius ``h / 2``;
``dhat = c h`` (``c = dhat_fraction``); stiffness by
:func:`~rodstab.nonlinear.contact.stiffness_for_line_load` from the line load scale ``B3 a /
R0^4`` held at ``dhat / 2`` (measured mean loads over the loaded nodes: 0.3-0.4 of it, peaks up
to 3 times it; held within ``(0, dhat)`` all the same, every limit shown at several ``dhat``).

The sliding mode. A uniform closed ring has the same energy when its material slides along its
own centreline, contact included (the gaps do not change). On the coincident circle sliding is
a rigid rotation, which the gauge removes; on the torus curve it is not (the strands' triangle
turns), so it is a zero mode of the continuum and a near-zero one, of either sign, of the
discrete rod (measured: it is the lowest mode, cosine 0.8-0.95 with :func:`ring_sliding_field`,
eigenvalue -2.4e-8 .. +2.5e-8 at 32 elements per loop). It is left out of the verdict by
Rayleigh-Ritz on the lowest :data:`RITZ_MODES` eigenvectors, orthogonal to it
(:func:`verdict_eigenvalue`); :class:`~rodstab.nonlinear.stability` does this for one-segment
rings only.

Limits (:func:`stacked_limits`): the equilibrium is followed in ``mu`` from a stable ``mu``
inside the no-contact interval, re-relaxed at each step from the previous state, in steps of
1/:data:`SCAN_STEPS` of the no-contact interval's width, out to :data:`WINDOW_WIDTHS` widths
beyond each no-contact limit. A step landing on an unstable state, or where Newton fails, is
halved (:data:`HALVINGS` times) so the bracket is tight and reached along the branch; its sign
change is refined by :func:`rodstab.numerics.refine_root` (each evaluation relaxed from the
stable end) and probed on both sides (:func:`_crossing`): only a smooth crossing is reported
as a limit. A jump of the eigenvalue, or a Newton failure (no equilibrium near the last one:
a fold, or the strands rearranging), ends the branch and is reported as such, never as a
limit.

Results: ``benchmarks/stacked_limits.py`` and docs/theory/contact.md (not converged in
``dhat``, ``h`` or the mesh).
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable

import numpy as np

from ..errors import RodstabInputError, require_positive, require_positive_int
from ..model import Assembly
from ..nonlinear.constraint import mean_length
from ..nonlinear.contact import (
    START_GAP_FRACTION,
    ContactModel,
    mesh_of_rod,
    stiffness_for_line_load,
)
from ..nonlinear.discrete import DiscreteRod, discretise
from ..nonlinear.newton import newton
from ..nonlinear.stability import uses_kirchhoff, vee_log, zero_eigenvalue_tol
from ..numerics import jacobi_scaling, lowest_eigenpairs, refine_root
from ..results import Result
from .folding import fold_loops
from .ring_modes import ModeShape, contact_forces, mode_shape
from .stacking import StackedState, _pair_gaps, _where, stack_loops

#: Newton iterations allowed per relaxation (the first, from the torus curve, took 58 at 32
#: elements per loop: the strands settle onto the barrier, each step cut by the filter).
RELAX_MAX_ITER = 200
#: Lowest eigenpairs on which the sliding mode is removed by Rayleigh-Ritz.
RITZ_MODES = 6
#: The sliding field counts when more than this fraction of its norm lies in their span.
SLIDING_SPAN = 0.5
#: ... and when, after the gauge correction, more than this fraction of it is left (on the
#: circle sliding is the gauged rigid rotation: no mode).
SLIDING_RATIO = 1e-3
#: Scan steps per width of the no-contact interval, and the search window beyond each of its
#: ends, in widths.
SCAN_STEPS = 12
WINDOW_WIDTHS = 1.0
#: Relaxed states followed per side at most (halved steps included); past it the search
#: stops and says where.
MAX_STATES = 80
#: Refinement of a bracketed limit, relative to the bracket (Brent: ~8 relaxations).
ROOT_RTOL = 1e-3
#: A limit is probed this fraction of its bracket either side (:func:`_crossing`): a jump
#: keeps there at least this fraction of the bracket's larger eigenvalue.
JUMP_PROBE = 1e-2
JUMP_FRACTION = 0.3
#: Halvings of a scan step that lands on an unstable state, fails or jumps (:func:`_side`).
HALVINGS = 4
#: A followed state has left its branch when it lies farther than this times the secant's
#: predicted move (plus :data:`JUMP_FLOOR` times the mean segment length) from the secant
#: prediction through the last two states (:func:`_side`). On a smooth branch the secant
#: misses by ``O(h^2)`` against a move of ``O(h)``; past a fold Newton lands on another
#: branch, ``O(1)`` away. Measured on the braided eight (16 el., h/L = 0.01, dhat = 0.1 h,
#: steps of 0.195 from 3): without this check the search stepped over the fold at 6.2273
#: (arclength continuation, ``benchmarks/eight_braid_fold.py``) onto stable states of other
#: branches and reported no sign change up to 6.58, and downwards over the sign change at
#: 2.6147 (which the continuation finds too) to a Newton failure at 0.445.
JUMP_SECANT = 1.0
JUMP_FLOOR = 1e-6
#: ... unless, relaxed back at the last state's load, it returns there (to this fraction of
#: its miss): then the branch only bent sharply (a layer lifting off, a contact zone's onset),
#: while a state of another branch stays on it. Measured on the stacked 3-loop ring (16 el.,
#: circle, h/L = 0.01 and 0.005, five dhat): with the secant test alone 9 of the 10 searches
#: ended as jumps, among them the upper side at h/L = 0.01, dhat = 0.2 h at N mu = 3.84,
#: which with the return test runs on to a smooth crossing at 4.0650.
JUMP_RETURN = 0.1
#: ... or when it differs from it by a slide along the ring: this cosine with the sliding
#: field or more (:func:`unslid_distance`; measured on slides: 0.991, 0.992, 0.941, 0.822).
SLIDE_COS = 0.8


class BranchEnded(RodstabInputError):
    """Newton found no equilibrium near the previous one (the followed branch ends)."""


def line_load_scale(a: float, R0: float, B3: float) -> float:
    """``B3 a / R0^4`` (force / length): the scale of the line load holding the strands."""
    return B3 * a / R0**4


def stacked_contact_model(thickness: float, dhat_fraction: float, a: float, R0: float,
                          B3: float) -> ContactModel:
    """Contact model of the rule (module doc): ``dhat = c h``, load ``B3 a / R0^4`` at ``dhat/2``.

    Parameters
    ----------
    thickness : float
        ``h`` (length): capsule diameter.
    dhat_fraction : float
        ``c = dhat / h`` in (0, 1).
    a, R0, B3 : float
        Strand circumradius and loop radius (length), bending stiffness (force length^2).
    """
    h = require_positive("thickness", thickness)
    c = require_positive("dhat_fraction", dhat_fraction)
    if c >= 1.0:
        raise RodstabInputError(f"dhat_fraction must be below 1 (dhat < h), got {dhat_fraction!r}")
    dhat = c * h
    kappa = stiffness_for_line_load(line_load_scale(a, R0, B3), dhat, 0.5)
    return ContactModel.from_thickness(h, dhat=dhat, stiffness=kappa)


#: ``wound``: :func:`~.stacking.stack_loops` (Lk = -(N - 1)); ``folded``: :mod:`.folding` (Lk 0).
STACKINGS = ("wound", "folded")


def stacked_ring(a: Assembly, *, thickness_ratio: float, elements_per_loop: int,
                 dhat_fraction: float, load_factor: float = 1.0, stacking: str = "wound"
                 ) -> tuple[DiscreteRod, StackedState]:
    """Return the stacked N-loop ring with its contact model set, at ``load_factor`` (unrelaxed).

    ``a``: the N-loop ring (``rodstab.problems.ring.build``: one segment per loop, ``R0 = B3
    = 1``); ``thickness_ratio = h / L``; ``g0 = START_GAP_FRACTION dhat``; ``stacking`` one of
    :data:`STACKINGS`. Returns the rod (with ``rod.contact``) and the state it was built from.
    Both stackings get the wound ring's contact stiffness (its ``a`` in the rule's line load).
    """
    hL = require_positive("thickness_ratio", thickness_ratio)
    n = require_positive_int("elements_per_loop", elements_per_loop)
    c = require_positive("dhat_fraction", dhat_fraction)
    if c >= 1.0:
        raise RodstabInputError(f"dhat_fraction must be below 1 (dhat < h), got {dhat_fraction!r}")
    if stacking not in STACKINGS:
        raise RodstabInputError(f"stacking must be one of {list(STACKINGS)}, got {stacking!r}")
    h = hL * a.total_length
    g0 = START_GAP_FRACTION * c * h
    coincident = discretise(a, n, load_factor)
    wound = stack_loops(coincident, h, g0)
    assert wound.torus is not None
    st = wound if stacking == "wound" else fold_loops(coincident, h, g0)
    rod = st.rod.copy()
    rod.load_factor = load_factor
    B3 = float(np.max(rod.edge_B[:, 2]))
    rod.contact = mesh_of_rod(rod, stacked_contact_model(h, c, wound.torus.a, wound.torus.R0,
                                                         B3))
    return rod, st


@dataclasses.dataclass(frozen=True)
class StackedEquilibrium(Result):
    """A relaxed stacked ring at one load factor (contact on), with its verdict.

    Attributes
    ----------
    load_factor : float
        ``mu``; ``(L / 2 pi) kappa_n = N mu``.
    converged : bool
        Newton converged (never True otherwise); ``iterations``, ``residual`` (free gradient).
    min_gap, min_gap_where : float, str
        Smallest capsule gap (length) and the two elements where.
    dhat : float
        The barrier's activation distance (length).
    contact_total : float
        Sum over nodes of ``|f|`` (force): every contact force counted on both bodies.
    line_load_mean, line_load_min, line_load_max : float
        Net contact force per node over its tributary length (force / length), over the nodes
        within ``dhat`` of another strand (the rest carry none).
    loaded_fraction : float
        Fraction of the nodes carrying a contact force.
    energy, energy_coincident : float
        Energy of the relaxed state (rod + contact) and of the coincident planar held state
        at the same ``mu`` (force length).
    max_move : float
        Largest node distance from the torus-curve start (length).
    max_height : float
        Largest ``|z|`` of a node (length): ``a`` on the torus curve.
    lowest_eigenvalue, zero_tol : float
        The verdict eigenvalue (sliding mode left out, :func:`verdict_eigenvalue`) and the
        tolerance below which it counts as zero; ``stable`` = converged and above it.
    sliding_removed : bool
        Whether the sliding field was found among the lowest modes and left out.
    """

    load_factor: float
    converged: bool
    iterations: int
    residual: float
    min_gap: float
    min_gap_where: str
    dhat: float
    contact_total: float
    line_load_mean: float
    line_load_min: float
    line_load_max: float
    loaded_fraction: float
    energy: float
    energy_coincident: float
    max_move: float
    max_height: float
    lowest_eigenvalue: float
    zero_tol: float
    stable: bool
    sliding_removed: bool


def _tributary(rod: DiscreteRod) -> np.ndarray:
    return np.bincount(rod.edge_nodes.ravel(), weights=np.repeat(0.5 * rod.rest_length, 2),
                       minlength=len(rod.x))


def relax(rod: DiscreteRod, load_factor: float) -> tuple[bool, int, float]:
    """Newton at ``load_factor`` from the rod's current state, in place (contact filtered)."""
    rod.load_factor = float(load_factor)
    # A start outside the contact model raises Interpenetration (naming the pair): bad input,
    # not hidden here; trials outside it are rejected inside Newton.
    return newton(rod, max_iter=RELAX_MAX_ITER)


def hold_loops(a: Assembly, elements_per_segment: int, load_factor: float,
               thickness_ratio: float, dhat_fraction: float, stacking: str = "folded"
               ) -> tuple[StackedState, DiscreteRod, bool, int, float]:
    """Build the stacked N-loop ring and relax it with contact at ``load_factor``.

    ``a``: the N-loop ring (``rodstab.problems.ring.build``, or one segment of ``N`` turns);
    ``thickness_ratio``: ``h`` over the mean segment length and ``dhat_fraction`` ``dhat / h``
    (the command line's contact options: the model of
    :func:`~rodstab.nonlinear.equilibrium.rod_contact_model`); ``stacking`` ``"folded"``
    (:func:`fold_loops`) or ``"wound"`` (:func:`~.stacking.stack_loops`), started ``dhat / 2``
    apart. Relaxed by :func:`~rodstab.nonlinear.newton.relax` (Newton, then down any unstable
    mode). Returns the built state, the relaxed rod (its contact model attached) and Newton's
    ``(converged, iterations, residual)``, as :func:`~.braid.hold_braid` does.
    """
    from ..nonlinear.contact import attach_contact
    from ..nonlinear.equilibrium import rod_contact_model
    from ..nonlinear.newton import relax as relax_down

    per_segment = a.total_length / len(a.segments)
    h = require_positive("thickness_ratio", thickness_ratio) * per_segment
    try:
        _, st = stacked_ring(a, thickness_ratio=h / a.total_length,
                             elements_per_loop=elements_per_segment,  # discretise's, per segment
                             dhat_fraction=dhat_fraction, load_factor=load_factor,
                             stacking=stacking)
    except RodstabInputError as exc:
        if "too large" not in str(exc):  # not a ring of loops, an even N: said as it is
            raise
        raise RodstabInputError(f"{exc} (h = {h:.6g}: the contact thickness "
                                f"{thickness_ratio:g} times the mean segment length "
                                f"{per_segment:.6g})") from None
    rod = st.rod.copy()
    rod.load_factor = float(load_factor)
    attach_contact(rod, rod_contact_model(a, thickness_ratio, dhat_fraction))
    ok, its, res = relax_down(rod)
    return st, rod, ok, its, res


def describe(rod: DiscreteRod, start: DiscreteRod, ok: bool, its: int, res: float
             ) -> StackedEquilibrium:
    """Gaps, contact forces, energies and the verdict of a relaxed stacked ring."""
    mu = rod.load_factor
    model = rod.contact.model if rod.contact is not None else None
    if model is not None:
        P, g = _pair_gaps(rod, model)
        k = int(np.argmin(g)) if len(g) else -1
        gmin = float(g[k]) if len(g) else math.inf
        where = f"{_where(rod, int(P[k, 0]))} and {_where(rod, int(P[k, 1]))}" if len(g) else \
            "no pair within reach"
        dhat = model.dhat
    else:
        gmin, where, dhat = math.nan, "no contact model", math.nan
    f = contact_forces(rod)
    fn = np.linalg.norm(f, axis=1)
    # A joint node of a spanning weld has no element (no tributary length) and no contact.
    trib = _tributary(rod)
    loaded = (fn > 1e-12 * max(float(fn.max()), 1e-300)) & (trib > 0.0)
    q = np.divide(fn, trib, out=np.zeros_like(fn), where=trib > 0.0)
    coincident = discretise(rod.assembly, len(rod.R_edge) // len(rod.assembly.segments), mu)
    lam, tol, slid = verdict_eigenvalue(rod)
    return StackedEquilibrium(
        load_factor=mu, converged=ok, iterations=its, residual=res, min_gap=gmin,
        min_gap_where=where, dhat=dhat, contact_total=float(fn.sum()),
        line_load_mean=float(q[loaded].mean()) if loaded.any() else 0.0,
        line_load_min=float(q[loaded].min()) if loaded.any() else 0.0,
        line_load_max=float(q[loaded].max()) if loaded.any() else 0.0,
        loaded_fraction=float(loaded.mean()), energy=rod.energy(),
        energy_coincident=coincident.energy(),
        max_move=float(np.max(np.linalg.norm(rod.x - start.x, axis=1))),
        max_height=float(np.max(np.abs(rod.x[:, 2]))), lowest_eigenvalue=lam, zero_tol=tol,
        stable=bool(ok and lam > tol), sliding_removed=slid)


# ---------------------------------------------------------------- the verdict
def ring_sliding_field(rod: DiscreteRod) -> np.ndarray | None:
    """Material sliding along a closed ring whose edges run in one cycle (free unknowns).

    As :func:`rodstab.nonlinear.stability.sliding_mode` (central differences: nodes along the
    cycle, edge frames half their relative rotations, joint frames between their two edges),
    for rings of several welded segments; the rigid motion that restores the gauge (joint 0)
    is removed. None when the edges do not form one cycle in index order, or when what is
    left is below :data:`SLIDING_RATIO` of the field (a circle: sliding is rigid).
    """
    E = rod.edge_nodes
    if not np.array_equal(E[:, 1], np.roll(E[:, 0], -1)) or not rod.fixed_joints \
            or not rod.fixed_nodes:
        return None
    nodes = E[:, 0]
    x = rod.x[nodes]
    dx = 0.5 * (np.roll(x, -1, axis=0) - np.roll(x, 1, axis=0))
    R = rod.R_edge
    RT = np.swapaxes(R, 1, 2)
    dphi = 0.5 * (vee_log(RT @ np.roll(R, -1, axis=0)) - vee_log(RT @ np.roll(R, 1, axis=0)))
    starts = {j: e for e, j, _, end in rod.end_links if end == "start"}
    ends = {j: e for e, j, _, end in rod.end_links if end == "end"}
    dJ = {j: vee_log(rod.R_joint[j].T @ R[e]) - vee_log(rod.R_joint[j].T @ R[ends[j]])
          for j, e in starts.items()}

    def sin_scaled(v: np.ndarray) -> np.ndarray:
        # As in sliding_mode: the circle's central difference is then exactly rigid.
        th = np.linalg.norm(v, axis=-1, keepdims=True)
        return v * np.where(th < 1e-12, 1.0, np.sin(th) / np.where(th < 1e-12, 1.0, th))

    dphi = sin_scaled(dphi)
    J0, n0 = rod.fixed_joints[0], rod.fixed_nodes[0]
    i0 = np.flatnonzero(nodes == n0)
    if J0 not in dJ or not len(i0):
        return None
    dJ = {j: sin_scaled(v) for j, v in dJ.items()}
    t, w = dx[int(i0[0])], rod.R_joint[J0] @ dJ[J0]
    v = np.zeros(rod.n_dof)
    for i, nd in enumerate(nodes):
        v[rod.node_dofs(nd)] = dx[i] - t - np.cross(w, rod.x[nd] - rod.x[n0])
    for e in range(len(R)):
        v[rod.edge_dofs(e)] = dphi[e] - R[e].T @ w
    for j, d in dJ.items():
        v[rod.joint_dofs(j)] = d - rod.R_joint[j].T @ w
    raw = math.sqrt(float(np.sum(dx**2) + np.sum(dphi**2)))
    vf = v[rod.free_dofs()]
    return vf if np.linalg.norm(vf) > SLIDING_RATIO * raw else None


def unslid_distance(back: DiscreteRod, prev: DiscreteRod) -> float:
    """Return how far ``back`` lies from ``prev`` (node positions), 0 if it only slid.

    A uniform closed ring keeps its energy when its material slides along the centreline
    (the continuum's symmetry; :func:`ring_sliding_field`, with the rigid motion that keeps
    the gauge). On the mesh it is only nearly kept: a stacked ring's pattern of layer swaps is
    pinned to the nodes and, followed in the load, hops to a neighbouring pinned copy of
    itself. Measured (3 folded loops, h/L = 0.01, dhat = 0.1 h): both swaps moving 7.5 deg
    (16 el. per loop, upper side), 19.5 deg (16 el., lower) and 3.5 deg (32 el., lower), and
    10 deg (16 el., dhat = 0.05 h, lower), at unchanged energy (to 3e-5, 2.7e-4, 6e-6 and 5e-5
    relative), the difference's cosine with the field's node part 0.991, 0.992, 0.941, 0.822.
    A difference within :data:`SLIDE_COS` of the field counts as that state (0); otherwise the
    largest node distance (length).
    """
    dx = back.x - prev.x
    v = ring_sliding_field(prev)
    if v is not None:
        full = np.zeros(prev.n_dof)
        full[prev.free_dofs()] = v
        f = np.array([full[prev.node_dofs(k)] for k in range(len(prev.x))])
        cos = float(np.sum(f * dx)) / max(float(np.linalg.norm(f) * np.linalg.norm(dx)), 1e-300)
        if abs(cos) >= SLIDE_COS:
            return 0.0
    return float(np.max(np.linalg.norm(dx, axis=1)))


def verdict_eigenvalue(rod: DiscreteRod) -> tuple[float, float, bool]:
    """Lowest eigenvalue of the Jacobi-scaled free Hessian (rod + contact), sliding left out.

    The scaled Hessian ``A = D H D`` of :func:`~rodstab.nonlinear.stability.lowest_modes`
    (same inertia as ``H``, Sylvester); its :data:`RITZ_MODES` lowest eigenpairs ``A V = V
    Lambda``; the sliding field in the same coordinates ``z = D^-1 s / |D^-1 s|``. When more
    than :data:`SLIDING_SPAN` of ``z`` lies in the span of ``V``, the verdict is the lowest
    Ritz value of ``A`` on the part of that span orthogonal to ``V^T z`` (by interlacing it
    lies between the lowest two eigenvalues), else the lowest eigenvalue.

    Returns
    -------
    lam, tol, removed : float, float, bool
        The eigenvalue, :func:`~rodstab.nonlinear.stability.zero_eigenvalue_tol`, and whether
        the sliding mode was left out. Meshes whose verdict the project takes in Kirchhoff
        coordinates (``uses_kirchhoff``) are refused: not done here.
    """
    lam, tol, removed, _ = verdict_mode(rod)
    return lam, tol, removed


def verdict_mode(rod: DiscreteRod) -> tuple[float, float, bool, np.ndarray]:
    """:func:`verdict_eigenvalue` with its mode on the free unknowns (``(n_free,)``, unscaled)."""
    if uses_kirchhoff(rod):
        raise RodstabInputError("verdict_eigenvalue: a mesh this fine is decided in Kirchhoff "
                                f"coordinates, not done here ({len(rod.R_edge)} elements)")
    free = rod.free_dofs()
    H = rod.energy_terms()[2][free][:, free].tocsc()
    H = 0.5 * (H + H.T)
    d = jacobi_scaling(H)
    A = (H.multiply(d[:, None]).multiply(d[None, :])).tocsc()
    vals, V = lowest_eigenpairs(A, RITZ_MODES)
    tol = zero_eigenvalue_tol(rod)
    s = ring_sliding_field(rod)
    z = None if s is None else s / d
    if z is not None:
        z /= np.linalg.norm(z)
        c = V.T @ z
    if z is None or np.linalg.norm(c) <= SLIDING_SPAN:
        return float(vals[0]), tol, False, d * V[:, 0]
    # An orthonormal basis of c's complement in R^k: the last k - 1 columns of a QR of [c | I].
    Q = np.linalg.qr(np.column_stack([c, np.eye(len(c))]))[0][:, 1:len(c)]
    ritz, Y = np.linalg.eigh(Q.T @ (vals[:, None] * Q))
    return float(ritz[0]), tol, True, d * (V @ (Q @ Y[:, 0]))


def random_move(rod: DiscreteRod, size: float, rng: np.random.Generator) -> float:
    """Move every free unknown of ``rod`` at random (in place); return the largest node move.

    Seeded normal displacements scaled to a largest node move ``size`` (length); with contact
    shortened by :func:`~rodstab.nonlinear.contact.max_step_fraction` so that no gap closes.
    For checking a held state by moving it and relaxing (benchmarks/eight_braid_perturb.py).
    """
    from ..nonlinear.contact import max_step_fraction

    dq = np.zeros(rod.n_dof)
    free = rod.free_dofs()
    dq[free] = rng.standard_normal(len(free))
    n = 3 * len(rod.x)
    dq *= require_positive("size", size) / float(np.max(np.linalg.norm(dq[:n].reshape(-1, 3),
                                                                       axis=1)))
    if rod.contact is not None:
        dq *= max_step_fraction(rod.contact, rod.x, dq[:n].reshape(-1, 3))
    rod.apply(dq)
    return float(np.max(np.linalg.norm(dq[:n].reshape(-1, 3), axis=1)))


def held_closed_eigenvalue(rod: DiscreteRod) -> tuple[float, int, int]:
    """Lowest eigenvalue of the scaled free Hessian on the perturbations holding every gap.

    A second verdict for a state held with contact: at a pressed contact, opening the gap
    costs the contact force's work to first order, so in the hard-contact limit the second
    variation is decided on the directions that keep the pressed gaps closed. Here every
    active term's gap (:func:`~rodstab.nonlinear.contact.active_gap_gradients`) is held, and
    the Hessian of rod and contact energy (Jacobi-scaled as in :func:`verdict_mode`) is taken
    on that subspace: the barrier's own stiffness along the gaps drops out there, the rest is
    the Hessian of the Lagrangian. Restricting raises the lowest eigenvalue, so this bounds
    :func:`verdict_eigenvalue` from above, and the two meet as ``dhat -> 0`` when the active
    terms are the pressed ones. Dependent rows are dropped (SVD, rank at ``1e-10`` of the
    largest singular value). Returns ``(eigenvalue, active terms, independent rows)``.
    """
    from ..nonlinear.contact import active_gap_gradients
    from ..numerics import lowest_eigenpairs_on

    if rod.contact is None:
        raise RodstabInputError("held_closed_eigenvalue needs a state with contact")
    free = rod.free_dofs()
    H = rod.energy_terms()[2][free][:, free].tocsc()
    H = 0.5 * (H + H.T)
    d = jacobi_scaling(H)
    A = (H.multiply(d[:, None]).multiply(d[None, :])).tocsc()
    G = np.zeros((0, len(free)))
    rows = active_gap_gradients(rod.contact, rod.x)
    if len(rows):
        full = np.zeros((len(rows), rod.n_dof))
        full[:, : rows.shape[1]] = rows
        _, sv, Vt = np.linalg.svd(full[:, free] * d[None, :], full_matrices=False)
        G = Vt[: int(np.sum(sv > 1e-10 * sv[0]))]
    vals = lowest_eigenpairs_on(A, G, 0, 1)[0] if len(G) else lowest_eigenpairs(A, 1)[0]
    return float(vals[0]), len(rows), len(G)


# ---------------------------------------------------------------- following and limits
@dataclasses.dataclass(frozen=True)
class SideLimit(Result):
    """One side of the stable interval with contact.

    ``limit``: the refined load factor (NaN when none was bracketed); ``bracket``: the two
    scan loads with eigenvalues of opposite sign (``eigenvalues``); ``branch_end``: the first
    load where Newton failed or the state left the branch, if the branch ended before a sign
    change (NaN otherwise);
    ``searched_to``: the last load reached; ``how``: a sentence; ``at_limit``: the state just on
    the stable side of the bracket, described; ``mode``: the verdict mode on the unstable side
    of the bracket (:func:`mode_shape`); ``path``: ``(mu, verdict eigenvalue, largest |z|,
    energy)`` of every state followed (a jump to another branch shows as a jump of the last
    two).
    """

    limit: float
    bracket: tuple[float, float]
    eigenvalues: tuple[float, float]
    branch_end: float
    searched_to: float
    how: str
    at_limit: StackedEquilibrium | None
    mode: ModeShape | None = None
    path: tuple[tuple[float, float, float, float], ...] = ()

    def outcome(self) -> str:
        """One line: the limit, or where the branch ends and how, or the search's sentence."""
        if math.isfinite(self.limit):
            return f"limit {self.limit:.5f}"
        if math.isfinite(self.branch_end):  # between the last state and this load
            kind = "jumps" if "JUMPS" in self.how else "Newton fails"
            return f"ends in ({self.searched_to:.4f}, {self.branch_end:.4f}): {kind}"
        return self.how[:60]


@dataclasses.dataclass(frozen=True)
class StackedLimits(Result):
    """Stable interval of an N-loop ring's load factor, with or without contact.

    ``lower``, ``upper``: :class:`SideLimit` in ``mu`` (``(L / 2 pi) kappa_n = N mu``);
    ``no_contact``: the interval without contact that set the scan (eq. 3.3, given by the
    caller); ``start``: the relaxed state the search started from; ``step``: the scan step in
    ``mu``.
    """

    loops: int
    thickness_ratio: float
    elements_per_loop: int
    dhat_fraction: float
    contact: bool
    no_contact: tuple[float, float]
    step: float
    start: StackedEquilibrium
    lower: SideLimit
    upper: SideLimit


def _node_distance(a: DiscreteRod, b: DiscreteRod) -> float:
    return float(np.max(np.linalg.norm(a.x - b.x, axis=1)))


def _side(rod: DiscreteRod, start: DiscreteRod, mu0: float, step: float, end: float,
          apart: Callable[[DiscreteRod, DiscreteRod], float] = _node_distance) -> SideLimit:
    """Follow from ``mu0`` by ``step`` to ``end``; bracket and refine the first sign change.

    A state counts as stable when its verdict eigenvalue is above the zero tolerance and as
    unstable below minus it (states between: followed, neutral to the verdict). A step that
    lands on an unstable state, or where Newton fails, is halved (from the same state) up to
    :data:`HALVINGS` times, so that the bracket is tight and its unstable end is reached
    from a state on the branch a small step away: Newton finds any equilibrium, and a full
    step can land on another branch (measured: 64 elements per loop, h / L = 0.01, the state
    at (L/2pi) kappa_n = 2.715 reached from 2.857 had twice the energy and eigenvalue
    -5.4e-6, while every state relaxed from 2.857 up to 2.7148 was stable). The refined limit
    is then probed (:func:`_crossing`): only a smooth crossing is a limit; a jump is reported
    as the branch ending there. A step whose state lies off the secant through the last two
    states by more than the secant's own move (:data:`JUMP_SECANT`; :func:`_secant_miss`), and
    which relaxed back at the last state's load does not return to it (:data:`JUMP_RETURN`),
    has left the branch without any sign change (Newton past a fold lands on another stable
    state): it is halved too, and after :data:`HALVINGS` halvings the branch is reported as
    ending there ("the state JUMPS"), never as stable further on. A state that returns is on
    the branch, which only bent sharply. ``apart``: the state relaxed back from the last one
    (nodes; N-loop rings: :func:`unslid_distance`, a slide being a return).

    A window of instability narrower than the scan step, with stable states at both of its
    scan neighbours, is not seen (measured: the braided eight, 16 el., h/L = 0.01, dhat =
    0.05 h, unstable on 2.175-2.183 between scan states 0.195 apart). The pseudo-arclength
    continuation's eigenvalue monitoring (``benchmarks/eight_braid_fold.py``) found that
    window's edge, but at dhat = 0.1 h it passed the window at 2.609-2.615 with 40 steps (it
    found it with 28): neither method certifies that no such window exists.
    """
    prev = rod.copy()  # the last state followed (stable or neutral)
    lam_prev, tol, _ = verdict_eigenvalue(prev)
    if not lam_prev > tol:
        raise RodstabInputError(f"_side: the state at mu = {mu0!r} is not stable (verdict "
                                f"eigenvalue {lam_prev:.3g}, tolerance {tol:.3g})")
    mu_prev = mu0
    path = [(mu0, lam_prev, float(np.max(np.abs(prev.x[:, 2]))), prev.energy())]
    info = (0, float(np.max(np.abs(prev.gradient()[prev.free_dofs()]))))  # its, residual
    h, halvings = step, 0
    before: tuple[float, np.ndarray] | None = None  # (mu, x) of the state before ``prev``
    while (end - mu_prev) * np.sign(step) > 1e-12 * abs(step):
        if len(path) > MAX_STATES:
            return SideLimit(math.nan, (math.nan, math.nan), (math.nan, math.nan), math.nan,
                             mu_prev, f"search stopped at mu = {mu_prev:.6g} after {MAX_STATES} "
                             "states (steps halved where they left the branch): no sign "
                             "change up to there", None, None, tuple(path))
        mu = mu_prev + h
        if (mu - end) * np.sign(step) > 0:
            mu = end
        trial = prev.copy()
        ok, its, res = relax(trial, mu)
        lam = verdict_eigenvalue(trial)[0] if ok else math.nan
        miss = _secant_miss(before, prev, mu_prev, trial, mu) if ok else (0.0, 0.0)
        jumped = miss[0] > JUMP_SECANT * miss[1] + JUMP_FLOOR * mean_length(prev)
        if jumped:  # off the secant: on the branch still if it relaxes back to ``prev``
            back = trial.copy()
            back_ok = relax(back, mu_prev)[0]
            jumped = not (back_ok and apart(back, prev)
                          <= JUMP_RETURN * miss[0] + JUMP_FLOOR * mean_length(prev))
        if (not ok or lam < -tol or jumped) and halvings < HALVINGS:
            h, halvings = 0.5 * h, halvings + 1
            continue
        if jumped:
            return SideLimit(math.nan, (mu_prev, mu), (lam_prev, lam), mu, mu_prev,
                             f"the state JUMPS at mu = {mu:.6g}, {abs(mu - mu_prev):.3g} past "
                             f"the last state: Newton lands {miss[0]:.3g} from the secant's "
                             f"prediction, which moves {miss[1]:.3g} (node positions), and "
                             f"relaxed back at {mu_prev:.6g} it does not return, before any "
                             "sign change: the branch ends (a fold) or the state left it; no "
                             "limit reported", describe(prev, start, True, *info), None,
                             tuple(path))
        if not ok:
            return SideLimit(math.nan, (mu_prev, mu), (lam_prev, math.nan), mu, mu_prev,
                             f"Newton failed at mu = {mu:.6g} ({its} iterations, residual "
                             f"{res:.3g}), {abs(mu - mu_prev):.3g} past the last state, before "
                             "any sign change: the branch ends (a fold, or the strands part); "
                             "no limit reported", describe(prev, start, True, *info), None,
                             tuple(path))
        path.append((mu, lam, float(np.max(np.abs(trial.x[:, 2]))), trial.energy()))
        if lam < -tol:
            stable_side = prev.copy()

            def f(m: float, stable_side: DiscreteRod = stable_side) -> float:
                r = stable_side.copy()
                ok_m = relax(r, m)[0]
                if not ok_m:
                    raise BranchEnded(f"Newton failed at mu = {m!r} inside the bracket")
                return verdict_eigenvalue(r)[0]

            try:
                x = refine_root(f, mu_prev, mu, rel_xtol=ROOT_RTOL)
                kind, words = _crossing(f, x, mu_prev, mu, lam_prev, lam)
                how = f"sign change bracketed (width {abs(mu - mu_prev):.3g}), refined: {words}"
                if kind != "smooth":
                    x = math.nan
            except BranchEnded as exc:
                x, how = math.nan, f"bracketed, but the refinement failed: {exc}"
            return SideLimit(x, (mu_prev, mu), (lam_prev, lam), math.nan, mu, how,
                             describe(prev, start, True, *info),
                             mode_shape(trial, verdict_mode(trial)[3]), tuple(path))
        before = (mu_prev, prev.x.copy())
        prev, lam_prev, mu_prev, info = trial, lam, mu, (its, res)
        if halvings and lam > tol:  # back towards the scan step
            h, halvings = 2.0 * h, halvings - 1
    return SideLimit(math.nan, (math.nan, math.nan), (math.nan, math.nan), math.nan, mu_prev,
                     f"no sign change up to mu = {mu_prev:.6g} (the search window)", None,
                     None, tuple(path))


def _secant_miss(before: tuple[float, np.ndarray] | None, prev: DiscreteRod, mu_prev: float,
                 trial: DiscreteRod, mu: float) -> tuple[float, float]:
    """Return how far ``trial`` lies from the secant's prediction, and the predicted move.

    The secant through ``before`` and ``prev`` (node positions, length), extended to ``mu``:
    ``x_p = x_prev + (mu - mu_prev) / (mu_prev - mu_before) (x_prev - x_before)``; both
    numbers are the largest node distance (``|x_trial - x_p|``, ``|x_p - x_prev|``). ``(0, 0)``
    without a state before ``prev`` (the first step is not judged).
    """
    if before is None:
        return 0.0, 0.0
    mu_b, x_b = before
    move = (mu - mu_prev) / (mu_prev - mu_b) * (prev.x - x_b)
    miss = trial.x - (prev.x + move)
    return (float(np.max(np.linalg.norm(miss, axis=1))),
            float(np.max(np.linalg.norm(move, axis=1))))


def _crossing(f: Callable[[float], float], x: float, a: float, b: float, lam_a: float,
              lam_b: float) -> tuple[str, str]:
    """Say whether the verdict eigenvalue crosses zero smoothly at ``x`` in ``[a, b]``.

    ``f`` (the verdict eigenvalue, stable side ``a``) at ``x`` moved :data:`JUMP_PROBE` of the
    bracket towards each end (clamped inside): a smooth crossing has the signs of the ends
    there and values below :data:`JUMP_FRACTION` of the larger end value; otherwise the
    eigenvalue jumps (the state leaves the branch, or a contact zone switches) and ``kind`` is
    ``"jump"``. Returns ``(kind, sentence)``.
    """
    d = JUMP_PROBE * (b - a)
    xa = x - d if (x - d - a) * (b - a) > 0 else 0.5 * (a + x)
    xb = x + d if (b - x - d) * (b - a) > 0 else 0.5 * (x + b)
    fa, fb = f(xa), f(xb)
    smooth = fa > 0 > fb and max(abs(fa), abs(fb)) < JUMP_FRACTION * max(abs(lam_a), abs(lam_b))
    words = (f"eigenvalue {fa:.3g} at mu = {xa:.6g}, {fb:.3g} at {xb:.6g} (ends {lam_a:.3g}, "
             f"{lam_b:.3g})")
    if smooth:
        return "smooth", "a smooth crossing: " + words
    return "jump", "a JUMP of the eigenvalue, not a smooth crossing (no limit reported): " + words


def stacked_limits(a: Assembly, no_contact: tuple[float, float], *,
                   thickness_ratio: float = 0.01,
                   elements_per_loop: int = 32, dhat_fraction: float = 0.1,
                   contact: bool = True, start_load_factor: float = 1.0,
                   stacking: str = "wound",
                   scan_steps: int = SCAN_STEPS, window: float = WINDOW_WIDTHS
                   ) -> StackedLimits:
    """Return the stable interval in ``mu`` of the stacked N-loop ring with contact.

    Or, with ``contact`` False, of the coincident ring without; by following the relaxed
    equilibrium both ways (module doc).

    Parameters
    ----------
    a : Assembly
        The N-loop ring (``rodstab.problems.ring.build``).
    no_contact : (float, float)
        The stable interval of ``mu`` without contact (eq. 3.3: ``1 - M^+ .. 1 - M^-``), which
        sets the scan step and window.
    thickness_ratio : float
        ``h / L``.
    elements_per_loop : int
    dhat_fraction : float
        ``dhat / h``.
    contact : bool
        False: the coincident planar ring without contact (the same routine: the check
        against eq. 3.3).
    start_load_factor : float
        A ``mu`` strictly inside the no-contact interval.
    stacking : str
        ``"wound"`` or ``"folded"`` (:data:`STACKINGS`; with ``contact`` only).
    scan_steps, window : int, float
        Scan steps per width of the no-contact interval; the window beyond each of its ends,
        in widths.
    """
    N = len(a.segments)
    lo, hi = (float(v) for v in no_contact)
    if not lo < hi:
        raise RodstabInputError(f"no_contact must be an interval (lo < hi), got {no_contact!r}")
    mu0 = float(start_load_factor)
    if not lo < mu0 < hi:
        raise RodstabInputError(f"start_load_factor must lie inside the no-contact interval "
                                f"({lo:.6g}, {hi:.6g}), got {start_load_factor!r}")
    steps = require_positive_int("scan_steps", scan_steps)
    w = require_positive("window", window)
    step = (hi - lo) / steps
    if contact:
        rod, st = stacked_ring(a, thickness_ratio=thickness_ratio,
                               elements_per_loop=elements_per_loop,
                               dhat_fraction=dhat_fraction, load_factor=mu0,
                               stacking=stacking)
        start = st.rod
    else:
        require_positive("thickness_ratio", thickness_ratio)
        rod = discretise(a, require_positive_int("elements_per_loop", elements_per_loop), mu0)
        start = rod.copy()
    ok, its, res = relax(rod, mu0)
    first = describe(rod, start, ok, its, res)
    if not first.stable:
        raise RodstabInputError(f"start_load_factor {mu0!r}: the relaxed state is not stable "
                                f"(converged {ok}, eigenvalue {first.lowest_eigenvalue:.3g}); "
                                "start elsewhere")
    width = hi - lo
    apart = unslid_distance if contact else _node_distance
    lower = _side(rod, start, mu0, -step, lo - w * width, apart)
    upper = _side(rod, start, mu0, step, hi + w * width, apart)
    return StackedLimits(N, float(thickness_ratio), int(elements_per_loop),
                         float(dhat_fraction), bool(contact), (lo, hi), step, first, lower,
                         upper)
