"""The equilibrium of a design at one load: mesh, Newton from the held state, verdict.

:func:`equilibrium` meshes an assembly (:func:`resolving_elements` by default), applies its
imposed end rotations, runs Newton (or relaxes a perturbed start) and decides stability from
the lowest scaled Hessian eigenvalues (:func:`~rodstab.nonlinear.stability.stability_eigenvalues`),
returned as an :class:`Equilibrium` with its residual and largest strain (:func:`max_strain`).

Split from :mod:`rodstab.nonlinear.solve` (issue 20), which re-exports every public name.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from ..errors import RodstabInputError, require_positive
from ..limits import DEFAULT as DEFAULT_LIMITS
from ..limits import Limits, require_nonlinear
from ..model import CONTACT_DHAT_FRACTION, Assembly
from ..results import Result
from .contact_model import ContactModel
from .contact_step import ContactState, attach_contact, contact_state
from .discrete import DiscreteRod, discretise
from .newton import newton, relax, settle
from .stability import (
    ZERO_EIG_ROUNDOFF,
    kirchhoff_polish,
    lowest_modes,
    stability_eigenvalues,
    uses_kirchhoff,
)


@dataclasses.dataclass(frozen=True)
class Equilibrium(Result):
    """A (converged or not) Newton solve; never report ``converged`` unless it is."""

    converged: bool
    energy: float
    residual: float
    iterations: int
    stable: bool
    lowest_eigenvalues: tuple[float, ...]
    n_dof: int
    load_factor: float
    method: str
    max_strain: float = 0.0  # largest stretch/shear strain of an edge (Kirchhoff: ~0)
    #: False when the verdict rests on round-off: the lowest scaled eigenvalue within
    #: ZERO_EIG_ROUNDOFF of zero on a mesh so fine that a resolved neutral or soft mode would
    #: lie there too; ``stable`` is then False and means "not shown stable" -- use fewer
    #: elements. Fine meshes are decided in Kirchhoff coordinates (:func:`stability_eigenvalues`),
    #: whose soft floor ``KIRCHHOFF_ZERO_EIG (l_e / L)^2`` reaches round-off only at
    #: ``min l_e / L`` below ~7e-7 (one segment: 1.4e6 elements, beyond ``MAX_DOF_NONLINEAR``;
    #: reachable only by a segment ~1e-4 of the total length meshed as finely as the others),
    #: where the absolute coordinates' floor ``(l_e / L)^4 / PENALTY`` reached it near 1000.
    stability_resolved: bool = True
    #: Gaps and contact forces at the equilibrium when solved with a contact model (the
    #: JSON's ``contact`` block is added by the caller; None without contact).
    contact: ContactState | None = dataclasses.field(default=None, metadata={"json": False})


#: An equilibrium whose largest stretch/shear strain exceeds this is not a Kirchhoff rod's:
#: the supports impose a motion an inextensible rod cannot make (reported, never hidden).
STRAIN_WARN = 1e-3


def max_strain(rod: DiscreteRod) -> float:
    """Largest |R_e^T (x_j - x_i) / l_e - e2| over the edges (stretch and shear strain)."""
    d = (rod.x[rod.edge_nodes[:, 1]] - rod.x[rod.edge_nodes[:, 0]]) / rod.rest_length[:, None]
    eps = np.einsum("eji,ej->ei", rod.R_edge, d) - np.array([0.0, 1.0, 0.0])
    return float(np.max(np.linalg.norm(eps, axis=1)))


#: Largest ``h k`` (element length times the wavenumber the held state's moment sets) of the
#: mesh :func:`resolving_elements` chooses: the discrete rod is second order, its error on a
#: mode of wavenumber ``k`` ~ ``(h k)^2 / 12``, 1 % at 0.35.
RESOLVE_HK = 0.35


def resolving_elements(a: Assembly, load_factor: float, minimum: int = 32) -> int:
    """Elements per segment that resolve the held state of ``a`` at ``load_factor``.

    At least ``minimum``, and ``L k / RESOLVE_HK`` for every segment, with ``k`` the larger of
    the held curvature ``|kappa|`` and ``B3 |kappa - mu kappa_n| / sqrt(B1 B2)``: the
    wavenumber of a rod bent by the moment ``m = B3 (kappa - mu kappa_n)`` out of its plane
    (Greenhill, lateral buckling: ``m / sqrt(B1 B2)``; the paper's load (5.7) is this group
    times ``L``). A fixed 32 elements called a clamped arc (L/R = 6.542, ellipse h/t = 7.54)
    stable 3 % past its lower limit (``h k`` = 0.81 there; 64 elements, 0.40, right).
    """
    n = int(minimum)
    for s in a.segments:
        m = abs(s.B3 * (s.curvature - load_factor * s.natural_curvature))
        k = max(abs(s.curvature), m / math.sqrt(s.B1 * s.B2))
        n = max(n, math.ceil(s.length * k / RESOLVE_HK))
    return n


def rod_contact_model(a: Assembly, thickness_ratio: float,
                      dhat_fraction: float = CONTACT_DHAT_FRACTION) -> ContactModel:
    """Return the contact model of ``a``'s rods: capsules of diameter ``thickness_ratio L``.

    ``L``: the mean rod length (total length over the number of segments); the rule of
    :meth:`~.contact_model.ContactModel.for_rods` with ``dhat = dhat_fraction h`` and the
    largest bending stiffness ``B3`` of the segments.
    """
    L = a.total_length / len(a.segments)
    return ContactModel.for_rods(require_positive("thickness_ratio", thickness_ratio) * L,
                                 dhat_fraction=dhat_fraction,
                                 bending_stiffness=max(s.B3 for s in a.segments), length=L)


def stacked_layers(a: Assembly, order: dict[str, int], thickness_ratio: float,
                   dhat_fraction: float, laminate: float | None = None
                   ) -> tuple[dict[str, float], float | None]:
    """Heights of the layers ``order`` (segment -> layer K) and the rods' axial stiffness.

    Layer ``K`` at ``z = K (h + g0)``: ``h = thickness_ratio L`` the capsules' diameter
    (:func:`rod_contact_model`), ``g0 = START_GAP_FRACTION dhat`` the gap the barrier holds
    from the first step; for :func:`~.discrete.discretise` ``layers`` (welds spanning
    layers). ``laminate``: ``s = EA h^2 / B3`` (``B3`` the largest of the rods'), giving the
    axial stiffness ``EA`` (force) in place of the stretch penalty; None: the penalty (a
    stacked welded state's limit then depends on it, docs/theory/contact.md).
    """
    from .contact_model import START_GAP_FRACTION

    h = require_positive("thickness_ratio", thickness_ratio) * a.total_length / len(a.segments)
    spacing = h * (1.0 + START_GAP_FRACTION * require_positive("dhat_fraction", dhat_fraction))
    layers = {name: k * spacing for name, k in order.items()}
    if laminate is None:
        return layers, None
    return layers, require_positive("laminate", laminate) * max(s.B3 for s in a.segments) / h**2


def equilibrium(a: Assembly, *, load_factor: float = 1.0,
                elements_per_segment: int | None = None, n_eig: int = 4, perturb: float = 0.0,
                limits: Limits = DEFAULT_LIMITS, contact: ContactModel | None = None,
                layers: dict[str, float] | None = None, axial_stiffness: float | None = None,
                start: DiscreteRod | None = None) -> tuple[Equilibrium, DiscreteRod]:
    """Find the equilibrium from the held state at ``load_factor`` and its Hessian stability.

    ``elements_per_segment`` None: :func:`resolving_elements` (at least 32).

    ``contact``: the rods are capsules that cannot pass through each other
    (:mod:`.contact`): the energy includes the contact barrier, Newton's steps are filtered,
    the stability verdict is that of the Hessian of rod and contact energy together, and the
    result carries the gaps and contact forces (``contact``). A held state whose rods already
    interpenetrate is refused (exit 2), naming the elements.

    With ``perturb``: from the held state plus a seeded random mix of its four softest modes with a
    largest node displacement of ``perturb`` x the total length, relaxed to a stable equilibrium
    when one is reachable (:func:`relax`). A model past ``limits.max_dof_nonlinear`` unknowns is
    refused before it is built. ``layers``, ``axial_stiffness``: the stacked state with welds
    spanning its layers (:func:`~.discrete.discretise`, :func:`stacked_layers`). ``start``: a
    state of a model of ``a`` to start from instead of the held state, with its own contact
    model (e.g. the braided eight, :func:`rodstab.multistable.braid.hold_braid`); ``contact``
    and ``layers`` must then be None.
    """
    if elements_per_segment is None:
        elements_per_segment = resolving_elements(a, load_factor)
    require_nonlinear([elements_per_segment] * len(a.segments), len(a.joints()),
                      f"{elements_per_segment} elements per segment", limits)
    if start is not None:
        if start.assembly is not a or contact is not None or layers is not None:
            raise RodstabInputError("equilibrium: a start is a state of the design's own "
                                    "model, with its contact model (no contact or layers "
                                    "given beside it)")
        rod = start.copy()
        rod.load_factor = load_factor
    else:
        rod = discretise(a, elements_per_segment, load_factor, layers=layers,
                         axial_stiffness=axial_stiffness)
        if contact is not None:
            attach_contact(rod, contact)
        settle(rod)
    if perturb:
        # A smooth, mesh-independent perturbation: a seeded random mix of the held state's
        # four softest modes, scaled to a largest node displacement of perturb x total length.
        _, vecs = lowest_modes(rod, 4)
        v = vecs @ np.random.default_rng(0).standard_normal(vecs.shape[1])
        dq = np.zeros(rod.n_dof)
        free = rod.free_dofs()
        dq[free] = v
        disp = np.linalg.norm(dq[: 3 * len(rod.x)].reshape(-1, 3), axis=1).max()
        dq *= perturb * a.total_length / max(disp, 1e-300)
        rod.apply(dq)
        ok, its, res = relax(rod)
    else:
        ok, its, res = newton(rod)
    if ok and uses_kirchhoff(rod):
        # Newton's tolerance (the absolute coordinates' round-off) leaves soft misfits on a
        # fine mesh: settle them where the verdict is taken.
        its += kirchhoff_polish(rod)
        gf = rod.gradient()[rod.free_dofs()]
        res = float(np.max(np.abs(gf))) if gf.size else 0.0
    E = rod.energy()
    method = ("discrete Cosserat rod (stiff stretch/shear), Newton + line search, exact "
              "Hessian by second-order jets")
    ev, floor, tol, kirchhoff = stability_eigenvalues(rod, n_eig)
    if kirchhoff:
        method += "; stability in Kirchhoff coordinates (stiff penalty on the diagonal)"
    resolved = not (abs(ev[0]) <= ZERO_EIG_ROUNDOFF and floor < ZERO_EIG_ROUNDOFF)
    state = None
    if rod.contact is not None:
        method += "; contact: capsule barrier (rodstab.nonlinear.contact), steps filtered"
        state = contact_state(rod.contact, rod.x)
    return Equilibrium(ok, E, res, its, bool(ok and ev[0] > tol),
                       tuple(float(v) for v in ev), len(rod.free_dofs()), load_factor,
                       method, max_strain(rod), resolved, state), rod
