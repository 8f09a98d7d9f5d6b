"""The stable states of a design that is no ring, as ``discover`` lists them (issue 22, 4).

A ring's states have names (:meth:`.states.Ring.states`); a bi-rod's or a clamped arc's do not:
its held state is an equilibrium of the design, and the others are found by deflated Newton
from it (:func:`~.discover.discover`, seeded by :func:`~.discover.search_start`). The stable
ones are labelled as ``rodstab discover DESIGN`` numbers its rows: ``#k`` (``k``-th lowest
energy among all equilibria found), followed by ``held`` for the held state. With the same
``starts`` and ``seed`` the two commands find the same list.

``discover`` lists a state and its mirror image once (:func:`~.identify.same_state` is modulo
reflection), but a barrier may join exactly these two: the bi-rod of Section 4 past its
buckling load has one stable state up to reflection, buckled out of its plane to one side or
the other. So each stable state that leaves the held state's plane is listed with its mirror
image in that plane, ``#k mirror`` (:func:`mirror_image`), when that is an equilibrium of the
same energy (the design is symmetric about the plane: its held state is planar and its welds
and supports are).
"""

from __future__ import annotations

import numpy as np

from ..errors import RodstabInputError
from ..model import Assembly
from ..nonlinear.constraint import mean_length
from ..nonlinear.discrete import PENALTY, DiscreteRod
from ..nonlinear.solve import NEWTON_RTOL
from .discover import discover, search_start
from .identify import PLANAR_TOL, Snapshot, best_fit_plane

#: Tolerance of a mirror image's energy (relative) and gauge (frame entries, positions over L).
MIRROR_RTOL = 1e-9

#: Perturbed starts of the search (as ``rodstab discover``'s default ``--starts``).
DESIGN_STARTS = 8


def design_states(a: Assembly, elements_per_segment: int, load_factor: float, *,
                  starts: int = DESIGN_STARTS, seed: int = 0) -> list[tuple[str, DiscreteRod]]:
    """Return the stable equilibria of design ``a`` at ``load_factor``, labelled, lowest first.

    Each a copy of the one common discrete model (``elements_per_segment`` el. per rod) in
    that state, all in one gauge. ``starts``, ``seed``: :func:`~.discover.discover`'s.
    """
    rod, seeds, known, directions = search_start(None, a, "held", elements_per_segment,
                                                 load_factor)
    found, snaps = discover(rod, seeds, known, starts=starts, seed=seed, directions=directions)
    held = rod.copy()
    seeds[0][1].put(held)
    out = []
    for i, (st, snap) in enumerate(zip(found.states, snaps, strict=True)):
        if st.stable:
            r = rod.copy()
            snap.put(r)
            out.append((f"#{i + 1}" + ("" if st.label == "unnamed" else f" {st.label}"), r))
            m = None if st.invariants.planar else mirror_image(r, held)
            if m is not None:
                out.append((f"#{i + 1} mirror", m))
    return out


def mirror_image(r: DiscreteRod, held: DiscreteRod) -> DiscreteRod | None:
    """Return state ``r`` reflected in the plane of the planar state ``held``, or None.

    Positions ``x' = P x`` (``P = I - 2 n n^T`` about the plane through the held nodes'
    centroid, normal ``n``); frames ``R' = P R diag(1, 1, -1)``: reflected, and the director
    along the normal turned back so the frame stays right-handed and a planar frame (``d3 =
    n``) is unchanged, so the gauge joint stays put (bi-rod at load factor 3, 8 el.: same energy
    8.5976102, gradient 6e-10). None when ``held`` is not planar, the image moves the gauge,
    or it is not an equilibrium of ``r``'s energy (the design is not symmetric about the
    plane: relative energy or gradient above :data:`MIRROR_RTOL`).
    """
    s = Snapshot.of(held)
    c, n = best_fit_plane(s.x, s.R_edge[:, :, 2])
    L = mean_length(held)
    if float(np.max(np.abs((s.x - c) @ n))) > PLANAR_TOL * L:
        return None
    P = np.eye(3) - 2.0 * np.outer(n, n)
    D = np.diag([1.0, 1.0, -1.0])
    m = r.copy()
    m.x, m.R_edge, m.R_joint = (r.x - c) @ P.T + c, P @ r.R_edge @ D, P @ r.R_joint @ D
    j, nd = r.fixed_joints[0], r.fixed_nodes[0]
    if (np.max(np.abs(m.R_joint[j] - r.R_joint[j])) > MIRROR_RTOL
            or np.max(np.abs(m.x[nd] - r.x[nd])) > MIRROR_RTOL * L):
        return None
    E, g = r.energy(), m.energy_terms()
    scale = float(PENALTY * np.max(r.edge_B) / np.min(r.rest_length))
    if (abs(g[0] - E) > MIRROR_RTOL * max(abs(E), 1.0)
            or float(np.max(np.abs(g[1][m.free_dofs()]))) > NEWTON_RTOL * scale):
        return None
    return m


def pick_state(states: list[tuple[str, DiscreteRod]], label: str, option: str
               ) -> tuple[str, DiscreteRod]:
    """Return the state of ``states`` that ``label`` names: its label, its ``#k`` or its name.

    Raises :class:`RodstabInputError` naming ``option`` and the labels when none or several do.
    """
    hits = [(lab, r) for lab, r in states if label in (lab, *lab.split(" ", 1))]
    if len(hits) != 1:
        raise RodstabInputError(
            f"{option} {label!r} names {'no' if not hits else 'more than one'} stable state of "
            f"the design here; its stable states: {', '.join(lab for lab, _ in states) or 'none'} "
            "(rows of `rodstab discover DESIGN` at this load factor and mesh)")
    return hits[0]
