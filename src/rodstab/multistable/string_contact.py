"""The string method with contact: a path whose every image keeps the rods apart (issue 21).

With a contact model (:class:`~rodstab.nonlinear.contact.ContactModel`) every state of the path
must lie inside it -- no two capsules overlap -- and the barrier energy includes the contact
energy. The string method's initial path (the belt path, :func:`~.string_method.belt_path`)
brings rods through one another, and the barrier is infinite there, so the string cannot start
with it. :func:`relax_with_contact` reaches a path inside the model in three steps:

0. the string is relaxed without contact (:func:`~.string_method.relax_string`, stopped at its
   first index-1 saddle): the minimum energy path without contact. Its rods may come closer
   than the thickness ``h``, nearly through one another (the hexagram's star -> daisy at
   kappa_n R0 = 1.5, 6 el./rod, h = 0.02 L: 0.0004 L apart);
1. **soft contact**: the same capsules of diameter ``h`` with the cubic
   :func:`~rodstab.nonlinear.contact.penalty` in place of the barrier (``soft``: finite for
   overlaps too), acting to the reach ``h + dhat_s = f (h + dhat)`` (``f`` the model's
   exclusion factor; the soft model's exclusion factor is then 1, so the excluded pairs are
   exactly the final model's). Its stiffness starts where the final model's line load is held
   at ``dhat_s / 2`` and grows :data:`STIFFEN` times per stage (at most :data:`MAX_STAGES`,
   :data:`STAGE_ITER` string iterations each, no saddle attempts) until every interior image
   has its non-excluded elements more than ``h + TARGET_GAP dhat`` apart
   (:data:`TARGET_GAP`; if the stages run out first, more than ``h`` is enough to go on;
   a stage ends early once that holds, measured every :data:`~.string_method.STOP_EVERY`
   iterations). A penalty that held no line load ``q`` above ``3 kappa dhat_s^2`` could
   not: the stages raise ``kappa`` past the path's contact loads;
2. the final model (the barrier) on every image -- each is inside it now -- and the string
   relaxed with it until a local maximum refines to an index-1 saddle the caller accepts, as
   without contact. Its steps are filtered so no gap closes
   (:func:`~rodstab.nonlinear.contact.max_step_fraction`) and an interpolated image outside
   the model is refused (the string is then not reparametrised in that iteration).

The soft stages are reported (:class:`ContactStages`). A path that reaches no state inside
the model in :data:`MAX_STAGES` stages raises :class:`~rodstab.errors.NotConverged` naming the
smallest distance reached. The ends are the caller's (relaxed with the final model); a state
whose rods are stacked (touching layers: the line, the eight) is refused by the caller.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable
from typing import Any

from ..errors import NotConverged, require_int
from ..nonlinear.contact import (
    ContactModel,
    Interpenetration,
    mesh_of_rod,
    smallest_gap,
    stiffness_for_line_load,
)
from ..nonlinear.discrete import DiscreteRod
from ..results import Result

#: Soft stages: the penalty's stiffness grows this many times per stage.
STIFFEN = 10.0
#: Most soft stages.
MAX_STAGES = 8
#: String iterations per soft stage (no saddle attempts: the stage only moves the rods apart).
STAGE_ITER = 20
#: The final model's line load sets the first soft stiffness, held at this fraction of reach.
GAP_FRACTION = 0.5
#: The soft stages go on until every interior image's closest gap is at least this times the
#: final model's dhat (where its barrier holds the line load it was chosen for), or the stages
#: run out. Stopping as soon as the gaps were positive left images barely inside the model:
#: the hexagram's star -> daisy (8 el., cusp welds 1.15 h wide) stopped after 4 stages at a
#: gap of 0.08 dhat, and the barrier's forces there threw its images 2.7 rad apart (not
#: converged, also with 33 images); with a cusp width that differed in its last bit it took 7
#: stages and converged. With this rule both take 5-7 stages and give 4.6921695 (session 33).
TARGET_GAP = 0.5


@dataclasses.dataclass(frozen=True)
class ContactStages(Result):
    """How the string reached a path inside the contact model (module docstring).

    ``stiffnesses``: the soft model's stiffness at every stage (force / length^2, its
    penalty ``kappa (dhat_s - g)^3`` per unit length); ``reach``: ``h + dhat_s`` (length);
    ``distances``: the smallest centreline distance of non-excluded elements over the interior
    images before the first stage and after each (length), the last above ``h`` (above
    ``h + TARGET_GAP dhat`` unless the stages ran out);
    ``start_crossing``: ``k`` when images ``k`` and ``k + 1`` of the path the stages reached
    pass rods through each other between them (a pair's separation reverses while the
    straight path between them comes within ``h``,
    :class:`~.transitions.ContactTracker`), else None. Each image is inside the model, but the
    path is not: the string may then stall (the stacked line -> star) or still converge to a
    saddle whose descents are the path (star -> daisy).
    """

    stiffnesses: tuple[float, ...]
    reach: float
    distances: tuple[float, ...]
    start_crossing: int | None = None


def _start_crossing(band: list[DiscreteRod], h: float) -> int | None:
    """First ``k`` whose images ``k``, ``k + 1`` pass rods through each other, else None."""
    from .transitions import ContactTracker

    rep = ContactTracker(band[0], h, band[0].x).stretch(
        "start", [(float(i), r.x) for i, r in enumerate(band)])
    return None if rep.pass_through_at is None else int(rep.pass_through_at) - 1


def soft_model(final: ContactModel, stage: int) -> ContactModel:
    """Return the soft model of stage ``stage`` (0, 1, ...) on the way to ``final`` (module doc).

    The final model's capsules, the cubic penalty to the final model's exclusion reach
    ``f (h + dhat)``; stiffness: ``4 q / (3 dhat_s^2)`` (the final model's line load ``q`` held
    at ``g = dhat_s / 2``) times ``STIFFEN ** stage``.
    """
    h = 2.0 * _radius(final)
    dhat = final.exclusion_factor * (h + final.dhat) - h
    load = final.stiffness / stiffness_for_line_load(1.0, final.dhat, GAP_FRACTION)
    kappa = 4.0 * load / (3.0 * (GAP_FRACTION * 2.0 * dhat) ** 2) * STIFFEN**stage
    return ContactModel(final.radius, dhat, kappa, 1.0, soft=True)


def _radius(model: ContactModel) -> float:
    r = model.radius
    return float(max(r)) if isinstance(r, tuple) else float(r)


def state_distance(r: DiscreteRod, final: ContactModel, mesh: Any = None) -> float:
    """Smallest centreline distance of ``r``'s non-excluded element pairs (length).

    The pairs and exclusions are the final model's (``mesh``: its mesh of ``r``'s model, built
    if not given); pairs beyond its reach do not count (the distance is then the reach).
    """
    mesh = mesh_of_rod(r, final) if mesh is None else mesh
    h = 2.0 * _radius(final)
    reach = final.exclusion_factor * (h + final.dhat)
    near = smallest_gap(mesh, r.x)
    return reach if near is None else min(reach, near[0] + h)


def path_distance(band: list[DiscreteRod], final: ContactModel) -> float:
    """Smallest :func:`state_distance` over the interior images of ``band`` (length)."""
    mesh = mesh_of_rod(band[0], final)
    h = 2.0 * _radius(final)
    return min([final.exclusion_factor * (h + final.dhat)]
               + [state_distance(r, final, mesh) for r in band[1:-1]])


def _with_model(band: list[DiscreteRod], model: ContactModel | None) -> bool:
    """Give every image ``model`` (None: no contact); False if an image lies outside it."""
    mesh = None if model is None else mesh_of_rod(band[0], model)
    for r in band:
        r.contact = mesh
    if mesh is None:
        return True
    try:
        for r in band:
            r.energy()
    except Interpenetration:
        return False
    return True


def _coarse(run: Any) -> None:
    """Raise NotConverged when the string stopped as too coarse (its images too far apart)."""
    if run.too_coarse:
        raise NotConverged(f"the string with contact: neighbouring images are "
                           f"{run.largest_gap:.3g} rad apart, more images are needed")


def relax_with_contact(band: list[DiscreteRod], final: ContactModel,
                       relax_string: Callable[..., tuple[list[DiscreteRod], Any, Any]], *,
                       max_iter: int, accept: Callable[[DiscreteRod], bool],
                       stage_iter: int = STAGE_ITER, max_stages: int = MAX_STAGES
                       ) -> tuple[list[DiscreteRod], DiscreteRod | None, Any, ContactStages]:
    """Relax the string ``band`` to a minimum energy path inside the contact model ``final``.

    The three steps of the module docstring, each relaxation by ``relax_string``
    (:func:`~.string_method.relax_string`, passed in: this module sits beside the string
    method, not below it). ``band``'s ends must lie inside ``final`` (the caller relaxed them
    with it); every image's contact setting is replaced (the final model's at the end).
    ``stage_iter``, ``max_stages``: string iterations per soft stage and most soft stages
    (the defaults :data:`STAGE_ITER`, :data:`MAX_STAGES`). The hexagram's star -> daisy with
    cusp welds of width ``h + 1.5 dhat`` (h = 0.02 L, dhat = 0.1 h) got inside the model with
    60 iterations a stage in 9 stages at 6 el. and 8 at 8 el.; with 20 a stage, 16 stages
    left pairs 0.89 h apart at 6 el. (the cusps' end elements, which cross in the path
    without contact, part slowly).
    Returns the string, the saddle (None if none was accepted), the
    :class:`~.string_method.StringRun` of the final model's relaxation and the
    :class:`ContactStages`.

    Raises
    ------
    NotConverged
        When the soft stages reached no path inside the model, with the distances reached,
        or a relaxation before the final one stopped as too coarse (more images needed).
    """
    _with_model(band, None)
    band, _, run = relax_string(band, max_iter=max_iter, accept=None)
    _coarse(run)
    h = 2.0 * _radius(final)
    dist = [path_distance(band, final)]
    kappas: list[float] = []
    stage_iter = require_int("stage_iter", stage_iter, 1)
    max_stages = require_int("max_stages", max_stages, 0)
    target = h + TARGET_GAP * final.dhat
    while dist[-1] <= target and len(kappas) < max_stages:
        model = soft_model(final, len(kappas))
        _with_model(band, model)
        kappas.append(model.stiffness)
        band, _, run = relax_string(band, max_iter=stage_iter, try_every=stage_iter + 1,
                                    stop=lambda b: path_distance(b, final) > target)
        _coarse(run)
        dist.append(path_distance(band, final))
    stages = ContactStages(tuple(kappas), h + soft_model(final, 0).dhat, tuple(dist),
                           _start_crossing(band, h))
    if not (dist[-1] > h and _with_model(band, final)):
        raise NotConverged(f"the string found no path inside the contact model (thickness "
                           f"{h:g}) in {len(kappas)} soft stages: smallest distances "
                           f"{[float(f'{v:.4g}') for v in dist]}")
    band, saddle, run = relax_string(band, max_iter=max_iter, accept=accept)
    return band, saddle, run, stages
