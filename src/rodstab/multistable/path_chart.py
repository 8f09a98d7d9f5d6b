"""Paths of states of one discrete rod: chart differences, arclength, interpolation, bounds.

The chart of :mod:`.string_method`'s module docstring: the difference of two states is taken
in the chart of the first (:func:`chart_difference`), a path between images is the piecewise
chart geodesic (each interpolated state retracted onto the inextensible states), and its
arclength the scaled Euclidean norm of the free unknowns (positions over the mean rod length
``L``, frames in radians). Used by the chain (:mod:`.chain`) and
the string method above it.
"""

from __future__ import annotations

import math

import numpy as np

from ..nonlinear.constraint import retract_step
from ..nonlinear.contact import Interpenetration
from ..nonlinear.discrete import DiscreteRod
from ..nonlinear.solve import vee_log
from .discover import Snapshot

#: Energy samples per string segment in :func:`path_bound`.
BOUND_SAMPLES = 8


def chart_difference(a: DiscreteRod, b: DiscreteRod | Snapshot) -> np.ndarray:
    """State ``b`` minus state ``a`` in ``a``'s chart, ``(n_dof,)``.

    Nodes ``x_b - x_a``; frames the rotation vectors of ``R_a^T R_b`` (body frame of ``a``),
    so that ``a.apply(chart_difference(a, b))`` reproduces ``b`` (rotations below a half turn).
    """
    phi_e = vee_log(np.swapaxes(a.R_edge, 1, 2) @ b.R_edge)
    phi_j = vee_log(np.swapaxes(a.R_joint, 1, 2) @ b.R_joint)
    return np.concatenate([(b.x - a.x).ravel(), phi_e.ravel(), phi_j.ravel()])


def chart_scale(r: DiscreteRod) -> np.ndarray:
    """Per-unknown scale of chart norms, ``(n_dof,)``: ``1 / L`` for positions, 1 for frames."""
    scale = np.ones(r.n_dof)
    scale[: 3 * len(r.x)] = len(r.assembly.segments) / r.assembly.total_length
    return scale


def reparametrise(band: list[DiscreteRod], free: np.ndarray, count: int | None = None
                  ) -> list[DiscreteRod]:
    """Return the string through ``band`` with its interior images at equal chart arclength.

    ``count``: images of the new string, ends included (default: as many as ``band``; more
    refines the string, :func:`~.string_method.relax_string`).

    Arclength: the Euclidean chart norm (positions over ``L``, radians) of the free parts of
    consecutive differences. A new image at arclength ``s`` between images ``k`` and ``k + 1``
    is ``band[k]`` moved by the fraction of :func:`chart_difference` ``(band[k], band[k + 1])``
    (piecewise geodesic), then retracted
    (:func:`~rodstab.nonlinear.constraint.restore_inextensible`). The ends are kept (the same
    objects). Raises :class:`~rodstab.nonlinear.contact.Interpenetration` for an image outside
    the contact model.
    """
    scale = chart_scale(band[0])
    diffs = _differences(band, free)
    seg = np.array([np.linalg.norm(scale * dk) for dk in diffs])
    s = np.concatenate([[0.0], np.cumsum(seg)])
    out = [band[0]]
    for target in np.linspace(0.0, s[-1], len(band) if count is None else count)[1:-1]:
        k = min(int(np.searchsorted(s, target, side="right")) - 1, len(seg) - 1)
        r = _between(band[k], diffs[k], (target - s[k]) / seg[k])
        if r.contact is not None:
            r.energy()  # raises outside the contact model
        out.append(r)
    out.append(band[-1])
    return out


def _differences(band: list[DiscreteRod], free: np.ndarray) -> list[np.ndarray]:
    """Chart differences of neighbouring images, free unknowns only (the rest zero)."""
    mask = np.zeros(band[0].n_dof)
    mask[free] = 1.0
    return [mask * chart_difference(band[k], band[k + 1]) for k in range(len(band) - 1)]


def _between(r: DiscreteRod, diff: np.ndarray, t: float) -> DiscreteRod:
    """Return the state a fraction ``t`` along chart difference ``diff`` from ``r``, retracted."""
    out = r.copy()
    dq = t * diff
    out.apply(dq)
    retract_step(out, dq)
    return out


def path_bound(band: list[DiscreteRod], per_segment: int = BOUND_SAMPLES) -> float:
    """Highest energy along the string ``band`` read as a continuous path (an upper bound).

    The path is the piecewise chart geodesic :func:`reparametrise` interpolates on, each state
    retracted; its energy is sampled at the images and ``per_segment - 1`` points between
    neighbours. Any continuous path from one end to the other bounds the barrier between them
    from above (sampled: to the resolution of the samples). With contact, a sample outside
    the model gives ``inf`` (the path is not inside it).
    """
    free = band[0].free_dofs()
    top = max(r.energy() for r in band)
    for r, diff in zip(band, _differences(band, free), strict=False):
        for t in np.arange(1, per_segment) / per_segment:
            try:
                top = max(top, _between(r, diff, float(t)).energy())
            except Interpenetration:
                return math.inf
    return float(top)


def arclength(band: list[DiscreteRod]) -> np.ndarray:
    """Cumulative chart arclength of ``band`` at its images, normalised to end at 1."""
    free = band[0].free_dofs()
    scale = chart_scale(band[0])[free]
    seg = [float(np.linalg.norm(scale * chart_difference(band[k], band[k + 1])[free]))
           for k in range(len(band) - 1)]
    s = np.concatenate([[0.0], np.cumsum(seg)])
    return s / s[-1]
