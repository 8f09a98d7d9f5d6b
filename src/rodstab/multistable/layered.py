"""States of a ring whose welds span its layers, for barriers from a stacked state (issue 21).

A stacked state (the hexagram's line, the folded six-ring) is held with its rods on layers
joined by welds that span them (:func:`~rodstab.nonlinear.discrete.discretise` ``layers``;
the layers' translations from :func:`~.layer_orders.layer_translations`): each segment end is
a node held at a rigid offset ``o`` from its joint's node, in the joint's frame. The offsets
are part of the model: a path from the stacked state to another state keeps them, so the
other state is the planar one with every weld carrying its offsets -- its rods leave each
weld ``R_J o`` apart.

:func:`lift` puts a state of the planar model (a string image, the other end state) into the
layered model: each joint's node at the planar joint plus its offset in the stacked state
turned with the joint's frame, segment ends at ``R_J o`` from it, each segment's nodes between
moved by the linear blend of its two ends' offsets, frames turned onto the new chords.
Lifted rods may overlap where the planar state's rods leave a weld together (a cusp) on the
side opposite to their offsets. Measured (``python
benchmarks/layered_star.py``): the hexagram's star lifted into the line on the hexagon
(rectangle h/t = 4, 8 el./rod, h = 0.02 L, kappa_n R0 = 1) has two of its six cusps so, in
all 12 assignments of the rods to the hexagon's vertices (the weld between neighbours turns
their offset by 60 degrees from one weld to the next, while every cusp of the star curves its
rods apart the same way): closest rods 0.525 h apart. Relaxed with soft contact the rods
there pass over one another out of the plane (up to 4 h before the barrier, 6.9 h with it),
and Newton with the barrier does not converge (the rods press together as the gap closes, at
1, 100 and 10^4 times its stiffness): a barrier from the stacked line to the star is not
built yet.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable, Sequence
from typing import Any

import numpy as np

from ..errors import RodstabInputError
from ..model import Assembly
from ..nonlinear.contact import ContactModel, Interpenetration, segment_distance
from ..nonlinear.discrete import DiscreteRod
from ..results import Result
from .stacking import _segment_nodes

#: Layers' start gap over dhat for :func:`pressed_hold`: out of the barrier's reach (1).
OUT_OF_REACH = 1.5


def lift(model: DiscreteRod, held: DiscreteRod, planar: DiscreteRod) -> DiscreteRod:
    """Return ``planar``'s state in the layered ``model`` (module docstring).

    ``model`` is ``held`` (the planar state it was made from, e.g. the line) with spanning
    welds, and ``planar`` another state of ``held``'s model (same segments, elements and
    joints). A joint's node keeps its offset from ``held``'s joint, turned with the joint's
    frame; the segment ends keep theirs (``R_J o``). The copy of ``model`` returned has
    ``planar``'s frames and load factor; ``lift(model, held, held)`` is ``model``'s state.
    """
    if model.offsets is None:
        return planar.copy()
    out = model.copy()
    out.R_edge, out.R_joint = planar.R_edge.copy(), planar.R_joint.copy()
    out.load_factor = planar.load_factor
    on, oj, ov, _ = model.offsets
    n_joints = len(model.R_joint)
    # each joint node's offset from the held joint, in the joint's frame, turned to planar's
    c = np.einsum("jik,ji->jk", model.R_joint, model.x[:n_joints] - held.x[:n_joints])
    w = np.einsum("jik,jk->ji", planar.R_joint, c)
    x = np.zeros_like(model.x)
    x[:n_joints] = planar.x[:n_joints] + w  # joint nodes come first in both (discretise)
    shift = {int(end): w[j] + planar.R_joint[j] @ o
             for (_, end), j, o in zip(on, oj, ov, strict=True)}
    for k in range(len(model.assembly.segments)):
        mine, theirs = _segment_nodes(model, k), _segment_nodes(planar, k)
        s = np.linspace(0.0, 1.0, len(mine))[:, None]
        ends = []
        for node, joint_node in ((mine[0], theirs[0]), (mine[-1], theirs[-1])):
            ends.append(shift.get(int(node), w[int(joint_node)] if joint_node < n_joints
                                  else np.zeros(3)))
        x[mine] = planar.x[theirs] + (1.0 - s) * ends[0] + s * ends[1]
    out.x = x
    out.align_frames()
    return out


def stacked_band(band: list[DiscreteRod], layers: dict[str, Any], contact: ContactModel | None,
                 names: tuple[str, str] = ("A", "B")) -> list[DiscreteRod]:
    """Return the string ``band`` of the planar model lifted into its stacked model.

    ``band[0]`` is the stacked state's planar held state (the rods on one another), relaxed;
    ``layers`` its layer order (:func:`~.layer_orders.layer_translations`: a layer ``k`` or an
    offset ``(u, k)`` per segment, in units of ``h + g0``, ``h`` the contact model's capsule
    diameter and ``g0 = START_GAP_FRACTION dhat``). The stacked model
    (:func:`~.discover.common_rod` with the translations: welds spanning the layers) gets every
    image by :func:`lift`; the ends are relaxed with ``contact`` by Newton and must be stable.

    Raises
    ------
    RodstabInputError
        No contact model (the stacked rods need one), an end outside it (naming the
        elements) or not a stable equilibrium with contact.
    """
    held = band[0]
    model = stacked_model(held, layers, contact)
    out = [lift(model, held, r) for r in band]
    for r, label in ((out[0], names[0]), (out[-1], names[1])):
        stable_end(r, label, contact, f"layers = {layers}, load factor {held.load_factor:g}")
    for r in out[1:-1]:
        r.contact = None
    return out


def stacked_model(held: DiscreteRod, layers: dict[str, Any], contact: ContactModel | None,
                  *, gap_fraction: float | None = None) -> DiscreteRod:
    """Return ``held``'s model with its segments on ``layers``, welds spanning them.

    As :func:`stacked_band` builds it: capsules of ``contact``'s diameter ``h``, layers ``h +
    g0`` apart (:func:`~.layer_orders.layer_translations`), the same elements per segment and
    load factor as ``held``; its nodes differ from ``held``'s (each weld's segment ends are
    nodes of their own). ``g0 = gap_fraction dhat`` (default
    :data:`~rodstab.nonlinear.contact_model.START_GAP_FRACTION`, 0.5: inside the barrier's
    reach, every stacked pair pressed by it; above 1 the layers start out of reach, with no
    contact force).
    """
    from ..nonlinear.contact_model import START_GAP_FRACTION
    from .discover import common_rod
    from .layer_orders import layer_translations

    if contact is None:
        raise RodstabInputError(f"layers = {layers!r} need a contact model (the stacked rods)")
    h = 2.0 * float(np.max(contact.radius))
    g0 = (START_GAP_FRACTION if gap_fraction is None else gap_fraction) * contact.dhat
    shift = layer_translations(held, layers, h, g0)
    n = len(held.R_edge) // len(held.assembly.segments)
    return common_rod(held.assembly, n, held.load_factor, layers=shift)


def stable_end(r: DiscreteRod, label: str, contact: ContactModel | None, where: str) -> None:
    """Relax an end state of a path by Newton (with ``contact`` if given); refuse it unless stable.

    Raises :class:`~rodstab.nonlinear.contact.Interpenetration` when ``r``'s rods overlap under
    ``contact``, :class:`~rodstab.errors.RodstabInputError` when Newton fails or the state is
    unstable; ``where`` (e.g. ``"load factor 1"``) leads the message.
    """
    from ..nonlinear.contact import attach_contact
    from ..nonlinear.newton import newton
    from ..nonlinear.solve import lowest_modes, zero_eigenvalue_tol

    if contact is not None:
        try:
            attach_contact(r, contact)
        except RodstabInputError as exc:
            raise Interpenetration(f"state {label!r}: {exc}") from None
    if not newton(r)[0] or lowest_modes(r, 1)[0][0] < -zero_eigenvalue_tol(r):
        raise RodstabInputError(f"{where}: state {label!r} is not a stable equilibrium there "
                                "(outside its stable interval)")


def pressed_hold(a: Assembly, layers: dict[str, Any], contact: ContactModel, n: int,
                 loads: Sequence[float], *, gap_fraction: float = OUT_OF_REACH,
                 each: Callable[[DiscreteRod, tuple[float, bool, float]], None] | None = None
                 ) -> tuple[DiscreteRod, list[tuple[float, bool, float]]]:
    """Load stacked state ``a`` quasi-statically in the load factor; return its last state.

    The planar state in the common model lifted into its stacked model (layers ``gap_fraction
    dhat`` apart: out of the barrier's reach by default, no force at the start), then for each
    load of ``loads`` in turn relaxed from the last (:func:`~rodstab.nonlinear.newton.relax`:
    Newton, then down any unstable mode, every step filtered). Returns the final state and,
    per load, ``(load, relaxed, lowest scaled Hessian eigenvalue)``. Past the first loss of
    stability the rods move through the clearance and press on one another; the pressed stack
    is held while the eigenvalue stays positive (docs/theory/contact.md). ``each`` is called
    with the state and its row after every load.
    """
    from ..nonlinear.contact import attach_contact
    from ..nonlinear.newton import newton, relax
    from ..nonlinear.solve import lowest_modes
    from .discover import common_rod

    planar = common_rod(a, n, float(loads[0]))
    newton(planar)
    rod = lift(stacked_model(planar, layers, contact, gap_fraction=gap_fraction), planar, planar)
    attach_contact(rod, contact)
    out = []
    for lam in loads:
        rod.load_factor = float(lam)
        ok = relax(rod)[0]
        out.append((float(lam), bool(ok), float(lowest_modes(rod, 1)[0][0])))
        if each is not None:
            each(rod, out[-1])
    return rod, out


@dataclasses.dataclass(frozen=True)
class WeldSpans(Result):
    """Whether a stacked model's spanning welds overlap one another (:func:`weld_spans`).

    ``overlapping``: pairs of welds (each named by its segment ends, ``"1.end + 2.start"``)
    whose spans come nearer than ``h``; ``clearance``: the smallest distance between spans of
    two welds over ``h`` (None with fewer than two spanning welds: nothing to measure).
    """

    overlapping: tuple[tuple[str, str], ...]
    clearance: float | None


def weld_spans(rod: DiscreteRod, thickness: float) -> WeldSpans:
    """Check a stacked model's spanning welds against one another.

    A spanning weld (:attr:`~rodstab.nonlinear.discrete.DiscreteRod.offsets`) joins its
    segments' ends, each at a rigid offset from the joint's node; its span is the straight
    segments joint node -> end node. A weld is at least as thick as the rods it joins, so two
    welds whose spans come nearer than ``h`` (``thickness``, length) overlap. Contact sees the
    rods only, so such welds pass through each other unseen: a model no object can be built
    as. The hexagram's line in two columns has its three welds at ``x = 0`` so, in every
    order of its layers (the spans lie in one plane across the line and cannot all keep the
    layers' order; as constructed its ring centreline meets itself,
    :func:`~.knots.knot_class`; ``tests/test_spanning_weld.py``).
    """
    h = float(thickness)
    names = [" + ".join(f"{seg}.{end}" for seg, end in ends)
             for ends in rod.assembly.joints()]
    if rod.offsets is None:
        return WeldSpans(overlapping=(), clearance=None)
    on, oj = rod.offsets[0], rod.offsets[1]
    a, b = np.triu_indices(len(on), 1)
    a, b = a[oj[a] != oj[b]], b[oj[a] != oj[b]]
    if not len(a):
        return WeldSpans(overlapping=(), clearance=None)
    x = rod.x
    d = segment_distance(x[on[a, 0]], x[on[a, 1]], x[on[b, 0]], x[on[b, 1]]) / h
    close = sorted({tuple(sorted((int(oj[i]), int(oj[k])))) for i, k in
                    zip(a[d < 1.0], b[d < 1.0], strict=True)})
    return WeldSpans(overlapping=tuple((names[i], names[k]) for i, k in close),
                     clearance=float(d.min()))
