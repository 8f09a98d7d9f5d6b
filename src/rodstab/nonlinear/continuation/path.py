"""The one result type of every traced curve, special points, and the post-buckling verdict.

A :class:`Path` is the primary path of a continuation (with its special points and the
branches traced from them) or a branch from a bifurcation (with its verdict and the
coefficients of the initial post-buckling expansion).

Post-buckling (one definition for every tracer)::

    p / p_c = 1 + a xi + b xi^2 (+ O(xi^3)),

``xi`` = the largest out-of-plane displacement of a node, the rigid-body motion the supports
leave free removed (a least-squares fit ``a0 + a1 x + a2 y``; nothing is removed when a clamp
holds the structure), divided by the length ``L`` of the reference segment (the design's
``load_factor_segment``; by default the first segment), signed by the displacement's
projection on the critical mode. ``a`` != 0: asymmetric (transcritical); otherwise ``b`` on the
side where the primary path is unstable: supercritical (stable symmetric), on the stable side:
subcritical (unstable symmetric).
"""

from __future__ import annotations

import dataclasses
import enum
import math
from typing import Any

import numpy as np

from ...model import SUPPORT_KINDS, Assembly
from ...results import Result, jsonable
from ..discrete import DiscreteRod


class SpecialKind(str, enum.Enum):
    """Kinds of special points of a path (the string is what JSON and the CLI print)."""

    FOLD = "fold"
    BRANCH_TURNED = "branch point (path turned onto the branch)"
    LOST = "branch point (stability lost)"
    REGAINED = "branch point (stability regained)"


@dataclasses.dataclass(frozen=True)
class Path(Result):
    """A traced curve of equilibria in one parameter ``key``.

    ``amplitude``: for a branch, ``xi`` (module docstring); for a primary path, the largest
    node displacement from its first state (length unit) -- ``amplitude_definition`` says
    which. Branch fields (``value_critical``, ``coefficients`` = ``(a, b)``, ``verdict``) are
    NaN/empty on a primary path; ``special_points`` (dicts: kind, value, bracket, ...) and
    ``branches`` are empty on a branch unless it was traced with special-point detection.
    ``shapes`` (node positions, one side of a branch, at the parameter values
    ``shape_values``), ``states`` (``(value, state)`` at losses of stability and folds) and
    ``end_states`` (``(value, state)``: a branch's last point on each side traced, in the order
    of the sides) and ``landed`` (``(value, state)`` landed exactly on values the branch
    crossed, see :func:`.branches.trace_branch`) are left out of :meth:`to_dict`, and so are,
    for the pictures of the same points as ``shapes``, ``frames`` (the edge frames ``R_edge``,
    each (n_edges, 3, 3)) and ``shape_moments`` (the internal moment per edge, each
    (n_edges,)). None of them is saved with a run (:mod:`.storage`): a resumed run's branches
    have no shapes.
    """

    key: str
    value: tuple[float, ...]
    energy: tuple[float, ...]
    lowest_eigenvalue: tuple[float, ...]
    amplitude: tuple[float, ...]
    amplitude_definition: str
    converged: bool
    method: str
    value_critical: float = math.nan
    coefficients: tuple[float, float] = (math.nan, math.nan)
    verdict: str = ""
    special_points: tuple[dict, ...] = ()
    branches: tuple[Path, ...] = ()
    resumed_steps: int = 0
    shapes: tuple = ()
    shape_values: tuple[float, ...] = ()
    states: tuple = ()
    end_states: tuple = ()
    frames: tuple = ()
    shape_moments: tuple = ()
    landed: tuple = ()
    #: With a contact model: its parameters and the smallest capsule gap over the path's
    #: points (``smallest_gap``, at ``smallest_gap_value`` of the parameter; None when no pair
    #: came within reach); left out of :meth:`to_dict` without one.
    contact: dict | None = None

    def to_dict(self) -> dict[str, Any]:
        """JSON form, without the node positions and discrete states."""
        return {f.name: jsonable(getattr(self, f.name)) for f in dataclasses.fields(self)
                if f.name not in ("shapes", "shape_values", "states", "end_states", "frames",
                                  "shape_moments", "landed")
                and not (f.name == "contact" and self.contact is None)}

    @property
    def stable(self) -> tuple[bool, ...]:
        """Whether each point is stable: its lowest scaled Hessian eigenvalue is > 0."""
        return tuple(e > 0 for e in self.lowest_eigenvalue)

    @property
    def radius(self) -> tuple[float, ...]:
        """Largest distance of a node from the centroid, per point (needs ``shapes``)."""
        return tuple(float(np.max(np.linalg.norm(x - x.mean(axis=0), axis=1)))
                     for x in self.shapes)


def reference_length(a: Assembly, segment: str | None = None) -> float:
    """Length of the reference segment of the amplitude ``xi`` (default: the first)."""
    return (a.segments[0] if segment is None else a.segment(segment)).length


def _rigid_free(rod: DiscreteRod) -> bool:
    # Any clamp (plain or sliding) holds the out-of-plane rigid motions; a structure without
    # one is held only by the gauge, which is no support. (The nonlinear model accepts no
    # support that holds only some of them: fork and pinned are refused by discretise.)
    return not any(SUPPORT_KINDS[kind].holds_rigid_motions
                   for _, _, kind in rod.assembly.supports)


def out_of_plane(rod: DiscreteRod, x: np.ndarray, ref: np.ndarray) -> np.ndarray:
    """Return the out-of-plane displacement ``x - ref`` per node, less the free rigid part.

    The rigid part the supports leave free is removed by least squares on ``1, x, y`` of the
    reference positions.
    """
    w = x[:, 2] - ref[:, 2]
    if _rigid_free(rod):
        A = np.column_stack([np.ones(len(ref)), ref[:, 0], ref[:, 1]])
        w = w - A @ np.linalg.lstsq(A, w, rcond=1e-10)[0]
    return w


def xi(rod: DiscreteRod, x: np.ndarray, ref: np.ndarray, mode_w: np.ndarray,
       length: float) -> float:
    """Return the signed amplitude ``xi`` of state ``x`` relative to ``ref`` (module docstring).

    ``mode_w``: the critical mode's :func:`out_of_plane` field, for the sign.
    """
    w = out_of_plane(rod, x, ref)
    return math.copysign(float(np.max(np.abs(w))) / length, float(w @ mode_w) or 1.0)


def mode_out_of_plane(rod: DiscreteRod, vec: np.ndarray) -> np.ndarray:
    """:func:`out_of_plane` field of a mode ``vec`` (free unknowns) at state ``rod``."""
    full = np.zeros(rod.n_dof)
    full[rod.free_dofs()] = vec
    disp = full[: 3 * len(rod.x)].reshape(-1, 3)
    return out_of_plane(rod, rod.x + disp, rod.x)


#: The linear term is significant (asymmetric branch) when |a| xi_max > this times |b| xi_max^2.
ASYMMETRY_RATIO = 0.2


def post_buckling(xis: np.ndarray, values: np.ndarray, p_c: float, stable_side: float
                  ) -> tuple[str, float, float]:
    """Return the verdict and ``(a, b)`` of ``p/p_c = 1 + a xi + b xi^2`` from a branch's points.

    The points cover both signs of ``xi``; ``stable_side``: the sign of ``p - p_c`` where the
    primary path is stable. A quartic fit (when there are >= 6 points) keeps ``b`` from absorbing
    the higher-order terms, so tracers that sample different amplitudes agree.
    """
    xis, values = np.asarray(xis, float), np.asarray(values, float)
    if len(xis) < 3 or p_c == 0 or not math.isfinite(p_c):
        return "undetermined (branch too short)", math.nan, math.nan
    deg = 4 if len(xis) >= 6 else 2
    coef = np.polyfit(xis, values / p_c - 1.0, deg)
    b, a = float(coef[-3]), float(coef[-2])
    amax = float(np.max(np.abs(xis)))
    if abs(a) * amax > ASYMMETRY_RATIO * abs(b) * amax**2 and abs(a) > 0:
        return "asymmetric (transcritical): unstable on one side", a, b
    if b * p_c * stable_side > 0:
        return ("unstable symmetric (subcritical): the branch lies where the primary is "
                "stable", a, b)
    return "stable symmetric (supercritical): the branch lies where the primary is unstable", a, b
