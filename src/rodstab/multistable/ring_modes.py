"""What a mode of a relaxed N-loop ring does, and the contact forces on its nodes."""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from ..nonlinear.contact import contact_energy
from ..nonlinear.discrete import DiscreteRod
from ..results import Result


def contact_forces(rod: DiscreteRod) -> np.ndarray:
    """Contact force on every node (n_nodes, 3), lab frame: minus the contact gradient."""
    if rod.contact is None:
        return np.zeros_like(rod.x)
    return -contact_energy(rod.contact, rod.x)[1].reshape(-1, 3)


@dataclasses.dataclass(frozen=True)
class ModeShape(Result):
    """What a mode does (:func:`mode_shape`).

    ``harmonic_out``, ``harmonic_in``: the wavenumber ``j`` (waves over the whole ring, as in
    eq. 3.2) carrying most of the out-of-plane (``u_3``) and radial (``u_r``) displacement
    along the traversal, with ``share_out``, ``share_in`` their share of it; ``out_of_plane``:
    ``|u_3|^2 / |u|^2``; ``gap_change``: the largest first-order change of a centreline distance
    between a loaded node and the nearest node of another loop, over the largest node
    displacement (0: the mode keeps every gap; ~1: it opens or closes one as fast as it moves;
    NaN: no contact force). Rigid motions (which the gauge mixes in) are removed first.
    """

    harmonic_out: int
    share_out: float
    harmonic_in: int
    share_in: float
    out_of_plane: float
    gap_change: float


def mode_shape(rod: DiscreteRod, v_free: np.ndarray, max_harmonic: int = 12) -> ModeShape:
    """Harmonics and gap change of a mode ``v_free`` (free unknowns) of a relaxed N-loop ring."""
    v = np.zeros(rod.n_dof)
    v[rod.free_dofs()] = v_free
    u = v[: 3 * len(rod.x)].reshape(-1, 3)
    # The gauge (joint 0 held) adds a rigid motion to every mode: its harmonics j = 0, N would
    # hide the mode's own. Remove the least-squares rigid motion t + w x (x - c).
    c0 = rod.x.mean(axis=0)
    r = rod.x - c0
    Rx = np.zeros((len(r), 3, 3))
    Rx[:, 0, 1], Rx[:, 0, 2], Rx[:, 1, 2] = r[:, 2], -r[:, 1], r[:, 0]
    Rx = Rx - np.swapaxes(Rx, 1, 2)  # w x r = -[r]x w = Rx w
    G = np.concatenate([np.tile(np.eye(3), (len(r), 1, 1)), Rx], axis=2).reshape(-1, 6)
    u = u - (G @ np.linalg.lstsq(G, u.ravel(), rcond=None)[0]).reshape(-1, 3)
    nodes = rod.edge_nodes[:, 0]
    X = rod.x[nodes] - rod.x[nodes].mean(axis=0)
    N = len(rod.assembly.segments)
    theta = np.concatenate([[0.0], np.cumsum(rod.rest_length)[:-1]]) \
        * (2 * math.pi * N / rod.assembly.total_length)
    er = np.column_stack([X[:, 0], X[:, 1], np.zeros(len(X))])
    er /= np.linalg.norm(er, axis=1)[:, None]
    parts = {"out": u[nodes, 2], "in": np.einsum("ij,ij->i", u[nodes], er)}
    res: dict[str, tuple[int, float]] = {}
    for key, w in parts.items():
        power = np.array([abs(np.sum(w * np.exp(-1j * j * theta / N))) ** 2 * (1 if j else 2)
                          for j in range(max_harmonic + 1)])
        j = int(np.argmax(power))
        res[key] = (j, float(power[j] / max(power.sum(), 1e-300)))
    f = np.linalg.norm(contact_forces(rod), axis=1)
    loaded = np.flatnonzero(f > 1e-9 * max(float(f.max()), 1e-300))
    seg = np.empty(len(rod.x), int)
    seg[rod.edge_nodes.ravel()] = np.repeat(rod.edge_segment, 2)
    change = math.nan if not len(loaded) else 0.0
    for p in loaded:
        other = np.flatnonzero(seg != seg[p])
        q = other[int(np.argmin(np.linalg.norm(rod.x[other] - rod.x[p], axis=1)))]
        n = rod.x[p] - rod.x[q]
        change = max(change, abs(float((u[p] - u[q]) @ n)) / float(np.linalg.norm(n)))
    umax = float(np.max(np.linalg.norm(u, axis=1)))
    return ModeShape(res["out"][0], res["out"][1], res["in"][0], res["in"][1],
                     float(np.sum(u[:, 2] ** 2) / max(np.sum(u**2), 1e-300)),
                     change / max(umax, 1e-300))
