"""Discrete geometrically exact rod (Cosserat edges, Kirchhoff limit by stiff stretch/shear).

Why this model: every unknown is a position or a rotation, so welds at any angle, clamps and
closed multi-loop rings are exact (shared joint frames, no parallel transport or reference
twist), and the energy is a short algebraic function of rotation matrices whose exact Hessian
comes from second-order jets (:mod:`.jets`).

Unknowns: node positions ``x`` (lab), one frame ``R_e`` per edge (columns ``d1 = n``,
``d2 = tangent``, ``d3 = e3`` in the held state, as in the paper's (e1, e2, e3)), and one frame
``R_J`` per joint (segment end or weld), every segment end's frame being ``R_J Q`` with ``Q``
fixed by the held geometry (welds keep full rotational continuity at any angle).

Energy (consistent with (2.9), Kirchhoff limit as the penalty grows):

* bending/twist between consecutive frames ``R_a``, ``R_b``:
  ``1/2 (k - k0)^T diag(B1, B2, B3) (k - k0) ds`` with the Cayley curvature
  ``k = (2/ds) vee(P - P^T) / (1 + tr P)``, ``P = R_a^T R_b`` (= ``(2/ds) tan(theta/2) axis``),
  ``k0 = k_held + (0, 0, mu kappa_n - 1/R)`` (``k_held``: the same measure in the held state,
  so each joint carries the continuum moment there); between an end edge and its joint frame
  ``ds`` is half an edge;
* stretch and shear of edge ``e``: ``1/2 eps^T diag(K, K, K) eps l_e``,
  ``eps = R_e^T (x_(i+1) - x_i) / l_e - (0, 1, 0)``, ``K = PENALTY * max(B) / l_e^2``.

With a natural twist on a curved segment the held state is an equilibrium only up to
``O(l_e^2)``: the continuum carries the twisting moment round the curve by a shear force (Michell's
ring), which the discrete joints reproduce to second order; Newton moves the state by that much
(0.13, 0.032, 0.0077 R for 16/32/64 elements in Michell's ring at twice the unit twist), which acts
as a vanishing imperfection (a bifurcation of the continuum shows as a nearby fold).

Increments: ``x <- x + dx``, ``R <- R exp(hat(phi))``; gradients and Hessians are exact at
``phi = 0`` (the current state).
"""

from __future__ import annotations

import dataclasses
from typing import Any

import numpy as np
import scipy.sparse as sp

from ..errors import RodstabInputError, require_positive
from ..model import NONLINEAR, SUPPORT_KINDS, Assembly, held_frame, kinds_of
from .contact import ContactMesh, contact_terms
from .element_terms import _T0, bend_jet, stretch_jet
from .hessian_plan import hessian_plan, padded
from .jets import Jet, JetMat, rodrigues, rotation_jet, rotation_vector, vector_jet
from .mesh import MAX_ELEMENT_TURNING as MAX_ELEMENT_TURNING  # re-exported
from .mesh import MAX_NATURAL_TURNING as MAX_NATURAL_TURNING  # re-exported
from .mesh import check_mesh, cusp_offsets, element_counts, read_end_offsets

#: Stretch/shear stiffness K = PENALTY * max(B1, B2, B3) / l_e^2. The discrete model tends to
#: the inextensible, unshearable Kirchhoff rod as l_e -> 0 with an error ~ l_e^2 / PENALTY.
PENALTY = 1e3


@dataclasses.dataclass
class DiscreteRod:
    """A discretised assembly and its current state (mutable: Newton updates it)."""

    assembly: Assembly
    x: np.ndarray  # (n_nodes, 3)
    R_edge: np.ndarray  # (n_edges, 3, 3)
    R_joint: np.ndarray  # (n_joints, 3, 3)
    edge_nodes: np.ndarray  # (n_edges, 2)
    rest_length: np.ndarray  # (n_edges,)
    edge_B: np.ndarray  # (n_edges, 3) B1, B2, B3 of the edge's segment
    edge_kn: np.ndarray  # (n_edges,) natural curvature at load factor 1
    edge_k: np.ndarray  # (n_edges,) held curvature of the edge's segment
    bend_pairs: np.ndarray  # (n_bend, 2) consecutive edges inside segments
    end_links: list  # (edge, joint, Q (3x3), 'start' | 'end')
    fixed_nodes: list
    fixed_joints: list
    load_factor: float = 1.0
    k_held_pairs: np.ndarray | None = None  # (n_bend, 3) Cayley curvature of the held state
    k_held_links: np.ndarray | None = None  # (n_links, 3)
    k0_links: tuple[np.ndarray, np.ndarray] | None = None  # natural curvature a + mu b
    fixed_components: list = dataclasses.field(default_factory=list)  # (node, [components])
    edge_tw: np.ndarray | None = None  # (n_edges,) natural twist at load factor 1
    R_joint_held: np.ndarray | None = None  # joint frames of the held state
    #: imposed rotations of clamped joints: joint -> rotation vector in the held joint frame
    joint_rotation: dict = dataclasses.field(default_factory=dict)
    #: values of continuation parameters set on this state (key -> value), see .parameters
    param_values: dict = dataclasses.field(default_factory=dict)
    #: point moments on joints: joint -> moment (components in the joint's reference frame
    #: ``R_joint_held``); each adds the work term ``-M . theta`` (:meth:`_moment_work`)
    joint_moment: dict = dataclasses.field(default_factory=dict)
    #: dead point forces on nodes: ``(node, component) -> (F, direction, x_ref)``, the force
    #: ``F direction`` (lab frame, fixed); each adds the work term ``-F direction . (x - x_ref)``
    #: (zero at the reference position, so energies stay those of the unloaded state there)
    node_force: dict = dataclasses.field(default_factory=dict)
    #: contact between non-neighbouring elements (:mod:`.contact`, built by
    #: ``contact.mesh_of_rod(rod, model)``): its energy joins the rod's in every evaluation
    #: (positions are the first ``3 n_nodes`` dofs). Immutable: copies share it. None: no
    #: contact, every number as without this field.
    contact: ContactMesh | None = None
    #: spanning welds (:func:`discretise` with ``layers``): the rigid offsets of segment ends
    #: from their joint, ``(nodes (m, 2): joint node and end node, joints (m,), vectors (m, 3)
    #: in the joint's frame, weights (m,))``; each adds ``w |R_J^T (x_end - x_joint) - o|^2``,
    #: the stretch penalty of the end edge on the offset's misfit. None: ends share the joint's
    #: node (every number as without this field).
    offsets: tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray] | None = None
    #: the stretch/shear stiffness ``K`` of every edge (force): None for the penalty
    #: ``PENALTY max(B) / l_e^2`` (the Kirchhoff limit), else the rods' axial stiffness EA
    #: (:func:`discretise` ``axial_stiffness``; shear taken as stiff, slender rods)
    edge_K: np.ndarray | None = None

    def stretch_stiffness(self, per_length: bool = False) -> np.ndarray:
        """``K`` of every edge (force): :attr:`edge_K`, else the penalty (module docstring).

        ``per_length``: ``K / l_e`` instead (the retraction's weights), the penalty's by the
        arithmetic ``PENALTY max(B) / l_e^3`` the retraction has always used.
        """
        le = self.rest_length
        if self.edge_K is not None:
            return self.edge_K / le if per_length else self.edge_K
        return PENALTY * self.edge_B.max(axis=1) / (le**3 if per_length else le**2)

    # ---- degrees of freedom: positions, edge rotations, joint rotations
    @property
    def n_dof(self) -> int:
        """Total number of unknowns (before constraints)."""
        return 3 * (len(self.x) + len(self.R_edge) + len(self.R_joint))

    def node_dofs(self, i):
        """Global indices of node ``i``'s position."""
        return 3 * np.asarray(i)[..., None] + np.arange(3)

    def edge_dofs(self, e):
        """Global indices of edge ``e``'s rotation increment."""
        return 3 * (len(self.x) + np.asarray(e))[..., None] + np.arange(3)

    def joint_dofs(self, j):
        """Global indices of joint ``j``'s rotation increment."""
        return 3 * (len(self.x) + len(self.R_edge) + np.asarray(j))[..., None] + np.arange(3)

    def free_dofs(self) -> np.ndarray:
        """Return the indices not held by clamps or the rigid-motion gauge."""
        fixed = set()
        for i in self.fixed_nodes:
            fixed.update(self.node_dofs(i).tolist())
        for j in self.fixed_joints:
            fixed.update(self.joint_dofs(j).tolist())
        for i, comps in self.fixed_components:
            fixed.update(int(self.node_dofs(i)[c]) for c in comps)
        return np.array([d for d in range(self.n_dof) if d not in fixed])

    # ---- energy
    def energy_terms(self, *, links: bool = True) -> tuple[float, np.ndarray, sp.csr_matrix]:
        """Energy, exact gradient (n_dof,) and exact sparse Hessian at the current state."""
        E, g, H = self._evaluate(2, links)
        assert g is not None and H is not None  # order 2
        return E, g, H

    def kirchhoff_hessian(self) -> KirchhoffHessian:
        """Return the free Hessian in Kirchhoff coordinates, where the stiff penalty is diagonal.

        The same quadratic form as :meth:`energy_terms`' Hessian on the free unknowns, written
        in other coordinates ``z`` (Sylvester: the same inertia, hence the same stable/unstable
        verdict). Per edge, the node positions enter only through the chord ``d = x_j - x_i``,
        and ``(d, phi_e)`` is replaced by ``(eta_e, phi_e)`` with ``eta_e = J_d d + J_phi phi_e``
        the linearised stretch/shear strain (``J_d = R_e^T / l_e``, so ``d = l_e R_e (eta -
        J_phi phi_e)``). The penalty ``1/2 K l_e |eps|^2`` then has the Gauss-Newton part
        ``K l_e |eta|^2`` -- stiff, but alone on the diagonal -- and the stress part ``K l_e
        (eps - e2) . d^2 eps`` (the internal force times the frame's second variation), which is
        on the bending scale. In the absolute coordinates ``(x, phi)`` every entry carries the
        stiff scale, and its round-off ``u K / l_e`` swamps the soft (bending) eigenvalues, which
        lie ``(l_e / L)^4 / PENALTY`` below it (below ``u`` from ~1000 elements per unit length).

        The positions are recovered from the chords: the free components of the joint nodes
        are kept (``border``, first), interior nodes follow by summing the chords along each
        segment, and each segment closes with three linear constraints ``G z = 0`` (sum of its
        chords = end joint - start joint). The map from the free unknowns onto ``{G z = 0}`` is
        one-to-one, so ``z^T A z`` on it has the inertia of the free Hessian.
        """
        _, gb, H = self._evaluate(2, True, stretch=False, with_contact=False)
        assert H is not None and gb is not None  # order 2
        ne = len(self.R_edge)
        le = self.rest_length
        i, j = self.edge_nodes[:, 0], self.edge_nodes[:, 1]
        # eps(d, phi) = R^T d / l_e - e2, variables (d 0..2, phi 3..5), d = x_j - x_i.
        dj = vector_jet((self.x[j] - self.x[i]) / le[:, None], 6, 0, 2)
        for c in range(3):  # the jet is of d / l_e: rescale its derivatives to d
            assert dj[c].g is not None
            dj[c].g /= le[:, None]
        eps = rotation_jet(self.R_edge, 6, 3, 2).T.apply(dj)
        K = self.stretch_stiffness()
        S = np.zeros((ne, 6, 6))
        Jphi = np.zeros((ne, 3, 3))
        for k, ek in enumerate(eps):
            assert ek.H is not None and ek.g is not None  # order 2
            S += ((K * le) * (ek.v - _T0[k]))[:, None, None] * ek.H
            Jphi[:, k, :] = ek.g[:, 3:6]
        Td_eta = le[:, None, None] * self.R_edge  # d d / d eta
        Td_phi = -Td_eta @ Jphi  # d d / d phi (eta fixed)
        Sdd, Sdp, Spp = S[:, :3, :3], S[:, :3, 3:], S[:, 3:, 3:]
        tT = np.swapaxes
        A_ee = tT(Td_eta, 1, 2) @ Sdd @ Td_eta + (K * le)[:, None, None] * np.eye(3)
        A_ep = tT(Td_eta, 1, 2) @ (Sdd @ Td_phi + Sdp)
        A_pp = Spp + tT(Td_phi, 1, 2) @ Sdp + tT(Sdp, 1, 2) @ Td_phi \
            + tT(Td_phi, 1, 2) @ Sdd @ Td_phi
        # z layout: [joint-node positions (free components) | eta | phi_e | phi_J (free)].
        free = set(self.free_dofs().tolist())
        nx = len(self.x)
        jnodes = sorted({int(self.edge_nodes[lk[0], 0 if lk[3] == "start" else 1])
                         for lk in self.end_links}
                        | ({int(v) for v in self.offsets[0][:, 0]} if self.offsets else set()))
        border_dofs = [int(d) for n_ in jnodes for d in self.node_dofs(n_) if int(d) in free]
        b = len(border_dofs)
        zmap = np.full(self.n_dof, -1)
        zmap[border_dofs] = np.arange(b)
        zmap[3 * nx: 3 * (nx + ne)] = b + 3 * ne + np.arange(3 * ne)  # phi_e
        jd = [d for d in range(3 * (nx + ne), self.n_dof) if d in free]
        zmap[jd] = b + 6 * ne + np.arange(len(jd))
        n = b + 6 * ne + len(jd)
        eta = b + 3 * np.arange(ne)[:, None] + np.arange(3)  # (ne, 3)
        phi = zmap[self.edge_dofs(np.arange(ne))]
        blocks = np.concatenate([np.concatenate([A_ee, A_ep], axis=2),
                                 np.concatenate([tT(A_ep, 1, 2), A_pp], axis=2)], axis=1)
        loc = np.concatenate([eta, phi], axis=1)  # (ne, 6)
        Hc = H.tocoo()
        keep = (zmap[Hc.row] >= 0) & (zmap[Hc.col] >= 0)
        rows = np.concatenate([np.repeat(loc, 6, axis=1).ravel(), zmap[Hc.row[keep]]])
        cols = np.concatenate([np.tile(loc, (1, 6)).ravel(), zmap[Hc.col[keep]]])
        vals = np.concatenate([blocks.ravel(), Hc.data[keep]])
        A = sp.csr_matrix((vals, (rows, cols)), shape=(n, n))
        # Closure of each segment: sum_e (Td_eta eta_e + Td_phi phi_e) - x_end + x_start = 0.
        seg = self.edge_segment
        grows, gcols, gvals = [], [], []
        for s_ in range(len(self.assembly.segments)):
            es = np.flatnonzero(seg == s_)
            for c in range(3):
                r = 3 * s_ + c
                for T, idx in ((Td_eta, eta), (Td_phi, phi)):
                    grows.append(np.full(3 * len(es), r))
                    gcols.append(idx[es].ravel())
                    gvals.append(T[es, c, :].ravel())
                for node, sign in ((self.edge_nodes[es[-1], 1], -1.0),
                                   (self.edge_nodes[es[0], 0], 1.0)):
                    zc = zmap[3 * node + c]
                    if zc >= 0:
                        grows.append(np.array([r]))
                        gcols.append(np.array([zc]))
                        gvals.append(np.array([sign]))
        G = sp.csr_matrix((np.concatenate(gvals), (np.concatenate(grows),
                                                  np.concatenate(gcols))),
                          shape=(3 * len(self.assembly.segments), n))
        # Gradient: the stretch force K l_e (eps - e2) on eta; bending (and the work of point
        # loads) on the rotations and joint positions -- the stretch term has no derivative in
        # phi at fixed eta. A dead force on an interior node would also load the chords before
        # it: not formed (None).
        grad = None
        joint_nodes = set(jnodes)
        if all(node in joint_nodes for node, _ in self.node_force):
            grad = np.zeros(n)
            kept = np.flatnonzero(zmap >= 0)
            grad[zmap[kept]] = gb[kept]
            grad[eta.ravel()] = ((K * le)[:, None] * (np.stack([ek.v for ek in eps], axis=1)
                                                      - _T0)).ravel()
        chord = np.concatenate([Td_eta, Td_phi], axis=2)
        if self.contact is not None:
            # Contact acts on positions: x = T z (chords summed along each segment), so its
            # Hessian enters as T^T H_c T and its gradient as T^T g_c.
            from .contact_chords import contact_in_chords

            A, grad = contact_in_chords(self, zmap, chord, b, A, grad)
        return KirchhoffHessian(A, G, b, zmap, chord, grad)

    def from_kirchhoff(self, kh: KirchhoffHessian, z: np.ndarray) -> np.ndarray:
        """Map ``z`` (Kirchhoff coordinates, ``G z = 0``) to the increment ``v`` (n_dof,).

        Rotations and joint-node positions are copied; each segment's interior nodes follow
        from its start node by summing the chords ``d_e = Td (eta_e, phi_e)``.
        """
        v = np.zeros(self.n_dof)
        has = kh.zmap >= 0
        v[has] = z[kh.zmap[has]]
        ne = len(self.R_edge)
        b = kh.border
        ep = np.concatenate([z[b: b + 3 * ne].reshape(-1, 3),
                             z[b + 3 * ne: b + 6 * ne].reshape(-1, 3)], axis=1)
        d = np.einsum("eij,ej->ei", kh.chord, ep)
        seg = self.edge_segment
        for s_ in range(len(self.assembly.segments)):
            es = np.flatnonzero(seg == s_)
            start = v[self.node_dofs(self.edge_nodes[es[0], 0])]
            inner = self.edge_nodes[es[:-1], 1]
            v[self.node_dofs(inner).ravel()] = (start + np.cumsum(d[es[:-1]], axis=0)).ravel()
        return v

    def gradient(self, *, links: bool = True) -> np.ndarray:
        """Exact gradient (n_dof,) at the current state, without the Hessian (a third the cost).

        The same to the last bit as :meth:`energy_terms`' gradient.
        """
        g = self._evaluate(1, links)[1]
        assert g is not None  # order 1
        return g

    def energy(self) -> float:
        """Energy only (for line searches, path points): no derivatives are formed."""
        return self._evaluate(0, True)[0]

    def _evaluate(self, order: int, links: bool, stretch: bool = True,
                  with_contact: bool = True
                  ) -> tuple[float, np.ndarray | None, sp.csr_matrix | None]:
        """Energy and its derivatives up to ``order`` (0, 1, 2); None for those not formed.

        ``stretch`` False leaves out the stretch/shear penalty, ``with_contact`` False the
        contact energy (:meth:`kirchhoff_hessian` forms both in its own coordinates).
        """
        blocks: list[np.ndarray] = []  # the terms' dof lists, in order (the plan's key)
        vals: list[np.ndarray] = []
        grad = np.zeros(self.n_dof) if order >= 1 else None
        total = 0.0

        def scatter(jet: Jet, dofs: np.ndarray) -> None:
            nonlocal total
            total += float(jet.v.sum())
            if grad is not None and jet.g is not None:
                np.add.at(grad, dofs, jet.g)
            if jet.H is not None:
                blocks.append(dofs)
                vals.append(jet.H.ravel())

        mu = self.load_factor
        le = self.rest_length
        if stretch:
            # Stretch and shear of every edge: variables (x_i, x_j, phi_e).
            e = np.arange(len(self.R_edge))
            i, j = self.edge_nodes[:, 0], self.edge_nodes[:, 1]
            K = self.stretch_stiffness()
            scatter(stretch_jet(self.R_edge, self.x[j] - self.x[i], le, 0.5 * K * le, order),
                    np.concatenate([self.node_dofs(i), self.node_dofs(j), self.edge_dofs(e)],
                                   axis=1))
        # Bending between consecutive edges of a segment: variables (phi_a, phi_b).
        if len(self.bend_pairs):
            a, b = self.bend_pairs[:, 0], self.bend_pairs[:, 1]
            eye = np.broadcast_to(np.eye(3), (len(a), 3, 3))
            scatter(bend_jet(eye, np.swapaxes(self.R_edge[a], 1, 2) @ self.R_edge[b], eye,
                             np.zeros(len(a), bool), 0.5 * (le[a] + le[b]), self.edge_B[a],
                             self._k0(self.k_held_pairs, a, mu), order),
                    np.concatenate([self.edge_dofs(a), self.edge_dofs(b)], axis=1))
        # Half-joints between an end edge and its joint frame.
        if self.end_links and links:
            ee, jj, Lm, M, Rt, start = self._link_factors()
            k0 = (self._k0(self.k_held_links, ee, mu) if self.k0_links is None
                  else self.k0_links[0] + mu * self.k0_links[1])
            scatter(bend_jet(Lm, M, Rt, start, 0.5 * le[ee], self.edge_B[ee], k0, order),
                    np.concatenate([self.edge_dofs(ee), self.joint_dofs(jj)], axis=1))
        if self.offsets is not None:  # in absolute coordinates, also for kirchhoff_hessian
            on, oj, ov, ow = self.offsets
            scatter(stretch_jet(self.R_joint[oj], self.x[on[:, 1]] - self.x[on[:, 0]],
                                np.ones(len(oj)), ow, order, ov),
                    np.concatenate([self.node_dofs(on[:, 0]), self.node_dofs(on[:, 1]),
                                    self.joint_dofs(oj)], axis=1))
        loaded = [j for j, m in self.joint_moment.items() if np.any(m)]
        if loaded:
            scatter(self._moment_work(np.array(loaded), order), self.joint_dofs(np.array(loaded)))
        for (node, _), (F, direction, x_ref) in self.node_force.items():
            # linear in x: gradient only, no Hessian entry
            total -= F * float(direction @ (self.x[node] - x_ref))
            if grad is not None:
                grad[self.node_dofs(node)] -= F * direction
        H = None
        if order >= 2:
            H = hessian_plan(blocks, self.n_dof).assemble(np.concatenate(vals))
        if self.contact is not None and with_contact:
            # Raises contact.Interpenetration outside the model (Newton rejects such a trial).
            Ec, gc, Hc = contact_terms(self.contact, self.x, order)
            total += Ec
            if grad is not None and gc is not None:
                grad[: gc.size] += gc
            if H is not None and Hc is not None:
                H = (H + padded(Hc, self.n_dof)).tocsr()
        return total, grad, H

    def _k0(self, k_held: np.ndarray | None, e: np.ndarray, mu: float) -> np.ndarray:
        """Return the discrete natural curvature: held curvature plus continuum prestress.

        The held state's discrete curvature shifted by the continuum prestress
        ``(0, 0, mu kappa_n - k)``, so that every joint of the held state carries exactly the
        continuum moment ``B3 (k - mu kappa_n)`` -- the held state is then an exact equilibrium of
        the discrete model, as it is of the continuum.
        """
        k0 = np.zeros((len(e), 3)) if k_held is None else k_held.copy()
        k0[:, 2] += mu * self.edge_kn[e] - self.edge_k[e]
        if self.edge_tw is not None:
            k0[:, 1] += mu * self.edge_tw[e]  # natural twist about the tangent d2
        return k0

    def _moment_work(self, joints: np.ndarray, order: int = 2) -> Jet:
        """``-M . theta`` of point moments on ``joints`` (variables: the joint's phi 0..2).

        ``theta``: the exact rotation vector of the joint frame from its reference frame
        ``R_joint_held`` (``P = R_held^T R_J``), components in the reference frame, as ``M``.
        A moment of fixed components conjugate to the rotation vector is conservative by
        construction (it has this potential); for a rotation about one fixed axis it is the dead
        moment ``M theta``.
        """
        assert self.R_joint_held is not None  # set by discretise
        P = rotation_jet(np.swapaxes(self.R_joint_held[joints], 1, 2) @ self.R_joint[joints],
                         3, 0, order)
        with np.errstate(all="ignore"):  # past a half turn: NaN energy, the step is refused
            theta = rotation_vector(P)
        M = np.array([self.joint_moment[int(j)] for j in joints], float)
        return sum((theta[c] * -M[:, c] for c in range(1, 3)), start=theta[0] * -M[:, 0])

    def _link_factors(self) -> tuple[np.ndarray, ...]:
        """Edges, joints and the factors of the half-joints' ``P`` for :func:`bend_jet`.

        ``P = R_e^T R_J Q`` at a segment end (variables ``(phi_e, phi_J)``), ``(R_J Q)^T R_e``
        at a start (``(phi_J, phi_e)``, ``swap``): as :meth:`link_rotations` forms them.
        """
        ee = np.array([lk[0] for lk in self.end_links])
        jj = np.array([lk[1] for lk in self.end_links])
        Q = np.array([lk[2] for lk in self.end_links])
        start = np.array([lk[3] == "start" for lk in self.end_links])
        Re, RJ = self.R_edge[ee], self.R_joint[jj]
        eye = np.broadcast_to(np.eye(3), Q.shape)
        at = start[:, None, None]
        return (ee, jj, np.where(at, np.swapaxes(Q, 1, 2), eye),
                np.where(at, np.swapaxes(RJ, 1, 2) @ Re, np.swapaxes(Re, 1, 2) @ RJ),
                np.where(at, eye, Q), start)

    def link_rotations(self, order: int = 2) -> tuple[np.ndarray, np.ndarray, JetMat]:
        """Return the edges, joints and relative-rotation jets ``P`` of the half-joints.

        Vars: phi_edge 0..2, phi_joint 3..5. ``P`` is ``R_e^T R_J Q`` at a segment end,
        ``(R_J Q)^T R_e`` at a start; derivatives up to ``order``.
        """
        ee = np.array([lk[0] for lk in self.end_links])
        jj = np.array([lk[1] for lk in self.end_links])
        Q = np.array([lk[2] for lk in self.end_links])
        start = np.array([lk[3] == "start" for lk in self.end_links])
        Re = rotation_jet(self.R_edge[ee], 6, 0, order)
        RJQ = rotation_jet(self.R_joint[jj], 6, 3, order).times(Q)
        # Each link's product in its own order only (forming both and picking one per link
        # doubled the cost of the links).
        at_start = RJQ.take(start).T @ Re.take(start)
        at_end = Re.take(~start).T @ RJQ.take(~start)
        return ee, jj, JetMat.merge(start, at_start, at_end)

    def edge_moments(self) -> np.ndarray:
        """Return the magnitude of the internal moment ``|B (k - k0)|`` per edge (n_edges,).

        The average of the joints on either side of the edge (lab units of B x curvature).
        """
        mom = np.zeros(len(self.R_edge))
        cnt = np.zeros(len(self.R_edge))
        if len(self.bend_pairs):
            a, b = self.bend_pairs[:, 0], self.bend_pairs[:, 1]
            P = np.swapaxes(self.R_edge[a], 1, 2) @ self.R_edge[b]
            k = _cayley(P, 0.5 * (self.rest_length[a] + self.rest_length[b]))
            m = np.linalg.norm(self.edge_B[a] * (k - self._k0(self.k_held_pairs, a,
                                                                 self.load_factor)), axis=1)
            for idx in (a, b):
                np.add.at(mom, idx, m)
                np.add.at(cnt, idx, 1.0)
        return mom / np.maximum(cnt, 1.0)

    def max_internal_moment(self) -> float:
        """Return the largest internal moment magnitude of an edge (0 without edges).

        The largest of :meth:`edge_moments`, lab units of B x curvature.
        """
        return float(np.max(self.edge_moments(), initial=0.0))

    def max_out_of_plane(self) -> float:
        """Return the largest ``|z|`` of a node (length units).

        How far the rod leaves the plane ``z = 0`` of a planar design's held state.
        """
        return float(np.max(np.abs(self.x[:, 2])))

    def edge_twist(self, R_edge: np.ndarray | None = None) -> np.ndarray:
        """Return the rate of twist per edge (n_edges,), radians per length.

        The component about the tangent ``d2`` of the Cayley curvature between consecutive
        frames (the measure of the energy), averaged over the joints on either side of the
        edge like :meth:`edge_moments`. ``R_edge`` (n_edges, 3, 3): other frames of this rod
        (e.g. a stored state of a continuation path); default the current ones. The held state
        is untwisted, so this is the twist the loads put in (a natural twist included).
        """
        R = self.R_edge if R_edge is None else np.asarray(R_edge, dtype=float)
        tw = np.zeros(len(R))
        cnt = np.zeros(len(R))
        if len(self.bend_pairs):
            a, b = self.bend_pairs[:, 0], self.bend_pairs[:, 1]
            k = _cayley(np.swapaxes(R[a], 1, 2) @ R[b],
                        0.5 * (self.rest_length[a] + self.rest_length[b]))
            for idx in (a, b):
                np.add.at(tw, idx, k[:, 1])
                np.add.at(cnt, idx, 1.0)
        return tw / np.maximum(cnt, 1.0)

    @property
    def edge_segment(self) -> np.ndarray:
        """Index in ``assembly.segments`` of each edge's segment (n_edges,).

        :func:`discretise` lays out each segment's edges in turn, the same number for each.
        """
        n_seg = len(self.assembly.segments)
        return np.repeat(np.arange(n_seg), len(self.R_edge) // n_seg)

    # ---- updates
    def copy(self) -> DiscreteRod:
        """Return an independent copy of the state."""
        return dataclasses.replace(self, x=self.x.copy(), R_edge=self.R_edge.copy(),
                                   R_joint=self.R_joint.copy(),
                                   joint_rotation=dict(self.joint_rotation),
                                   param_values=dict(self.param_values),
                                   joint_moment=dict(self.joint_moment),
                                   node_force=dict(self.node_force))

    def assign(self, other: DiscreteRod) -> None:
        """Take over ``other``'s state and parameter values in place (undo a failed step)."""
        self.x, self.R_edge, self.R_joint = other.x.copy(), other.R_edge.copy(), \
            other.R_joint.copy()
        self.load_factor = other.load_factor
        self.joint_rotation = dict(other.joint_rotation)
        self.param_values = dict(other.param_values)
        self.joint_moment = dict(other.joint_moment)
        self.node_force = dict(other.node_force)
        self.edge_kn, self.edge_tw, self.k0_links = other.edge_kn, other.edge_tw, other.k0_links

    def shear(self) -> np.ndarray:
        """Angle (rad) between each edge's frame tangent ``d2`` and its chord."""
        chord = self.x[self.edge_nodes[:, 1]] - self.x[self.edge_nodes[:, 0]]
        t = chord / np.linalg.norm(chord, axis=1)[:, None]
        d2 = self.R_edge[:, :, 1]
        return np.arctan2(np.linalg.norm(np.cross(d2, t), axis=1), np.einsum("ei,ei->e", d2, t))

    def align_frames(self) -> None:
        """Turn every edge frame by the smallest rotation that puts ``d2`` on the chord.

        The shear of the stiff penalty goes to zero; the twist about the chord is kept.
        """
        chord = self.x[self.edge_nodes[:, 1]] - self.x[self.edge_nodes[:, 0]]
        t = chord / np.linalg.norm(chord, axis=1)[:, None]
        d2 = self.R_edge[:, :, 1]
        axis = np.cross(d2, t)
        sn = np.linalg.norm(axis, axis=1)
        ang = np.arctan2(sn, np.einsum("ei,ei->e", d2, t))
        phi = axis * (ang / np.where(sn < 1e-300, 1.0, sn))[:, None]
        self.R_edge = rodrigues(phi) @ self.R_edge  # lab-frame rotation

    def rotate_joint(self, j: int, r: np.ndarray) -> None:
        """Hold clamped joint ``j`` at its held frame turned by the rotation vector ``r``.

        The components of ``r`` are in the held joint frame.
        """
        self.joint_rotation[j] = np.asarray(r, float).copy()
        assert self.R_joint_held is not None  # set by discretise
        self.R_joint[j] = self.R_joint_held[j] @ rodrigues(self.joint_rotation[j][None])[0]

    def apply(self, dq: np.ndarray) -> None:
        """``x += dx``, ``R <- R exp(hat(phi))`` for the full increment vector ``dq``."""
        nx, ne = len(self.x), len(self.R_edge)
        self.x += dq[: 3 * nx].reshape(-1, 3)
        self.R_edge = self.R_edge @ rodrigues(dq[3 * nx: 3 * (nx + ne)].reshape(-1, 3))
        self.R_joint = self.R_joint @ rodrigues(dq[3 * (nx + ne):].reshape(-1, 3))


@dataclasses.dataclass(frozen=True)
class KirchhoffHessian:
    """The free Hessian in Kirchhoff coordinates (:meth:`DiscreteRod.kirchhoff_hessian`).

    ``A`` (sparse symmetric ``n x n``) on ``G z = 0`` (``G`` sparse, three rows per segment);
    the first ``border`` unknowns are joint-node positions (no stiffness of their own).
    """

    A: sp.csr_matrix
    G: sp.csr_matrix
    border: int
    zmap: np.ndarray  # (n_dof,) index in z of each unknown kept (-1: none)
    chord: np.ndarray  # (n_edges, 3, 6): d_e = chord (eta_e, phi_e)
    gradient: np.ndarray | None = None  # (n,) energy gradient in z (None: not formed)


def discretise(a: Assembly, elements_per_segment: int | dict[str, int] = 32,
               load_factor: float = 1.0, layers: dict[str, Any] | None = None,
               axial_stiffness: float | None = None,
               cusp_width: float | None = None,
               end_offsets: dict[tuple[str, str], Any] | None = None) -> DiscreteRod:
    """Return the discrete rod of an assembly in its held state (an equilibrium when P2 says so).

    Supports are read from :data:`~rodstab.model.SUPPORT_KINDS`: a kind that holds all
    rotations holds the joint's frame; one that holds the deflection holds the joint's position,
    except along the end tangent if it slides (that tangent must then be along x or y). Kinds
    without :data:`~rodstab.model.NONLINEAR` in their methods (fork, pinned: not implemented
    here) raise :class:`RodstabInputError`. ``elements_per_segment``: one count for every
    segment, or a count per segment name (:func:`element_counts`).

    ``layers``: the stacked state (issue 21): every node of segment ``name`` lifted by
    ``layers[name]`` (length, along ``e3``; 0 for a segment not named), or moved by it when
    it is a translation ``(x, y, z)`` (lab frame; a bundle of straight rods offset across
    their common line, :func:`rodstab.multistable.stacking.layer_translations`). Where the
    segments at a joint lie at different offsets the weld spans them: the joint keeps a node
    of its own at their mean offset ``v_J``, and each segment end is a node held at the rigid
    offset ``o = R_J^T (v_seg - v_J)`` from it (:attr:`DiscreteRod.offsets`, penalised as
    stiffly as an edge's stretch). The moved held state is an equilibrium whenever the planar
    one is (each segment translated rigidly: chords, frames and offsets unchanged).

    ``axial_stiffness``: the rods' EA (force; stretch and shear alike) in place of the penalty
    that stands in for inextensibility (:attr:`DiscreteRod.edge_K`): an extensible rod, for
    what the Kirchhoff limit does not determine (layers joined by spanning welds).

    ``cusp_width``: a weld of that width (length) at every cusp, where two segment ends leave
    their joint along one line (outward tangents equal to 1e-9). Rods of thickness ``h``
    cannot both leave a point along one line; with contact they are forced apart within an
    element of the weld, at a cost that grows without bound as the elements shorten
    (docs/theory/contact.md). Here the two ends are held ``cusp_width / 2`` on either side of
    the joint's node, across the tangent in the plane, by the spanning weld's rigid offsets;
    each end goes to the side its segment curves towards (the first-listed end to ``+n``,
    ``n = e3 x t``, when they curve alike). Only the end nodes move, so the state returned
    is not an equilibrium: relax it (Newton). ``None`` or 0: point welds, every number as
    without it.

    ``end_offsets``: ``{(segment, "start" | "end"): (x, y, z)}``, lab offsets (length) of
    segment ends, added to the above: each such end is held by a spanning weld from its
    joint's node (at the mean offset of the joint's ends); only the end nodes move
    (:func:`rodstab.multistable.braid.braid_eight` places the rest).
    """
    counts = element_counts(a, elements_per_segment)
    check_mesh(a, counts, load_factor)
    joints = a.joints()
    joint_of = {end: k for k, joint in enumerate(joints) for end in joint}
    xs, edge_nodes, lengths, Bs, kns, pairs, links = [], [], [], [], [], [], []
    R_edge: list[np.ndarray] = []
    joint_node = {}
    n_nodes = 0
    lift = {seg.name: np.zeros(3) for seg in a.segments}
    for name, z in (layers or {}).items():
        a.segment(name)  # raises naming an unknown segment
        v = np.atleast_1d(np.asarray(z, float))
        if v.shape not in ((1,), (3,)) or not np.all(np.isfinite(v)):
            raise RodstabInputError(f"layers[{name!r}] must be a finite height or a finite "
                                    f"translation (x, y, z), got {z!r}")
        lift[name] = v if len(v) == 3 else np.array([0.0, 0.0, v[0]])

    def node_at(p: np.ndarray, v: np.ndarray | None = None) -> int:
        nonlocal n_nodes
        xs.append(np.array([p[0], p[1], 0.0]) + (0.0 if v is None else v))
        n_nodes += 1
        return n_nodes - 1

    R_joint = np.zeros((len(joints), 3, 3))
    joint_v = np.zeros((len(joints), 3))
    split: set[int] = set()  # joints whose segments lie at different offsets
    cusp_off = cusp_offsets(a, joints, cusp_width)
    for key, v in read_end_offsets(a, end_offsets).items():
        cusp_off[key] = cusp_off.get(key, 0.0) + v
    for k, joint in enumerate(joints):
        name, end = joint[0]
        seg = a.segment(name)
        s_end = 0.0 if end == "start" else seg.length
        vs = np.array([lift[nm] + cusp_off.get((nm, e), 0.0) for nm, e in joint])
        joint_v[k] = vs.mean(axis=0)
        if np.any(vs.max(axis=0) > vs.min(axis=0)) or any(e in cusp_off for e in joint):
            split.add(k)
        joint_node[k] = node_at(seg.position(s_end), joint_v[k])
        R_joint[k] = held_frame(seg.tangent(s_end))
    off_nodes, off_joints, off_vecs, off_w = [], [], [], []
    ks, tws = [], []
    for seg in a.segments:
        n = counts[seg.name]
        s = np.linspace(0.0, seg.length, n + 1)
        pts = seg.position(s)
        z = lift[seg.name]
        ends = []
        for end, p in (("start", pts[0]), ("end", pts[-1])):
            k = joint_of[(seg.name, end)]
            if k not in split:
                ends.append(joint_node[k])
                continue
            v = z + cusp_off.get((seg.name, end), 0.0)
            ends.append(node_at(p, v))
            off_nodes.append((joint_node[k], ends[-1]))
            off_joints.append(k)
            off_vecs.append(R_joint[k].T @ (v - joint_v[k]))
            le = seg.length / n
            K = (PENALTY * max(seg.B1, seg.B2, seg.B3) / le**2 if axial_stiffness is None
                 else axial_stiffness)
            off_w.append(0.5 * K / le)
        ids = [ends[0]] + [node_at(p, z) for p in pts[1:-1]] + [ends[1]]
        first = len(R_edge)
        for e in range(n):
            chord = pts[e + 1] - pts[e]
            L = float(np.linalg.norm(chord))
            edge_nodes.append((ids[e], ids[e + 1]))
            lengths.append(L)
            Bs.append((seg.B1, seg.B2, seg.B3))
            kns.append(seg.natural_curvature)
            ks.append(seg.curvature)
            tws.append(seg.natural_twist)
            R_edge.append(held_frame(chord / L))
            if e:
                pairs.append((first + e - 1, first + e))
        for end, e in (("start", first), ("end", first + n - 1)):
            k = joint_of[(seg.name, end)]
            F = held_frame(seg.tangent(0.0 if end == "start" else seg.length))
            links.append((e, k, R_joint[k].T @ F, end))
    fixed_nodes, fixed_joints, fixed_components = [], [], []
    supports_ok = kinds_of(NONLINEAR)
    for name, end, kind_name in a.supports:
        kind = SUPPORT_KINDS[kind_name]
        if NONLINEAR not in kind.methods:
            raise RodstabInputError(f"the nonlinear model supports {supports_ok} supports, "
                                    f"got {kind_name!r}")
        k = joint_of[(name, end)]
        if kind.holds_all_rotations:
            fixed_joints.append(k)
        if kind.holds_deflection and not kind.slides_along_tangent:
            fixed_nodes.append(joint_node[k])
        elif kind.holds_deflection:
            seg = a.segment(name)
            t = seg.tangent(0.0 if end == "start" else seg.length)
            axis = int(np.argmax(np.abs(t)))
            if abs(abs(t[axis]) - 1.0) > 1e-12:
                raise RodstabInputError(f"a sliding-clamp needs an end tangent along x or y; "
                                        f"{name}.{end} has tangent {t.round(6).tolist()}")
            fixed_components.append((joint_node[k], [c for c in range(3) if c != axis]))
    if not fixed_nodes and not fixed_joints:
        # Free assembly: gauge the six rigid motions by holding joint 0 (position and frame).
        fixed_nodes.append(joint_node[0])
        fixed_joints.append(0)
    rod = DiscreteRod(a, np.array(xs), np.array(R_edge), R_joint, np.array(edge_nodes),
                      np.array(lengths), np.array(Bs), np.array(kns), np.array(ks),
                      np.array(pairs, int).reshape(-1, 2), links, fixed_nodes, fixed_joints,
                      load_factor, fixed_components=fixed_components)
    rod.edge_tw = np.array(tws) if any(tws) else None
    if axial_stiffness is not None:
        rod.edge_K = np.full(len(lengths), require_positive("axial_stiffness", axial_stiffness))
    if off_joints:
        rod.offsets = (np.array(off_nodes, int), np.array(off_joints, int),
                       np.array(off_vecs), np.array(off_w))
    rod.k_held_pairs, rod.k_held_links = held_curvatures(rod)
    rod.k0_links = _balanced_link_curvatures(rod)
    rod.R_joint_held = rod.R_joint.copy()
    seg_index = {s.name: i for i, s in enumerate(a.segments)}
    for name, end, r in a.end_rotations:
        # The rotation is given in the named end's frame F = R_J Q: F exp(r) = R_J exp(Q r) Q^T.
        Q = links[2 * seg_index[name] + (end == "end")][2]
        if any(r):
            rod.rotate_joint(joint_of[(name, end)], Q @ np.asarray(r, float))
    return rod


def _balanced_link_curvatures(rod: DiscreteRod) -> tuple[np.ndarray, np.ndarray]:
    """Return the half-joint natural curvatures ``a + mu b`` that balance the held end edges.

    With them the held state is an exact equilibrium of every end edge.

    A half-joint spans half an edge, so the same curvature mismatch gives a slightly different
    generalised moment than a full joint (the Cayley measure's ``sec^2`` factor): its natural
    curvature is chosen so that it balances the moment of the neighbouring full joint exactly.
    The correction vanishes as the edge length goes to zero (it is ``O(k^2 l_e^2)``).
    """
    ee, _, P = rod.link_rotations()
    den = (P.entry(0, 0) + P.entry(1, 1) + P.entry(2, 2) + 1.0).reciprocal()
    ds = 0.5 * rod.rest_length[ee]
    vee = [P.entry(2, 1) - P.entry(1, 2), P.entry(0, 2) - P.entry(2, 0),
           P.entry(1, 0) - P.entry(0, 1)]
    kap = [vee[c] * den * (2.0 / ds) for c in range(3)]
    kval = np.stack([k.v for k in kap], axis=1)  # (n_links, 3)
    J = np.stack([k.g[:, 0:3] for k in kap], axis=1)  # d kappa / d phi_edge: (n_links, 3, 3)
    JtB = np.einsum("lci,lc->lic", J, rod.edge_B[ee] * ds[:, None])  # J^T B ds
    out = []
    saved = rod.load_factor
    for mu in (0.0, 1.0):
        rod.load_factor = mu
        # No stretch: zero on a held state; with moved ends (cusp_width, end_offsets) the
        # construction's shear, which relaxing removes and k0 must not absorb.
        f = rod._evaluate(1, False, False)[1][rod.edge_dofs(ee)]  # type: ignore[index]
        # f + J^T B ds (k - k0) = 0  ->  k0 = k + (J^T B ds)^-1 f (J invertible near P = I).
        out.append(kval + np.linalg.solve(JtB, f[..., None])[..., 0])
    rod.load_factor = saved
    return out[0], out[1] - out[0]


def _cayley(P: np.ndarray, ds: np.ndarray) -> np.ndarray:
    vee = np.stack([P[:, 2, 1] - P[:, 1, 2], P[:, 0, 2] - P[:, 2, 0], P[:, 1, 0] - P[:, 0, 1]],
                   axis=1)
    return vee * (2.0 / ds / (1.0 + np.trace(P, axis1=1, axis2=2)))[:, None]


def held_curvatures(rod: DiscreteRod) -> tuple[np.ndarray, np.ndarray]:
    """Cayley curvatures of the held state for the joints and the half-joints."""
    a, b = rod.bend_pairs[:, 0], rod.bend_pairs[:, 1]
    kp = _cayley(np.swapaxes(rod.R_edge[a], 1, 2) @ rod.R_edge[b],
                 0.5 * (rod.rest_length[a] + rod.rest_length[b])) if len(a) else np.zeros((0, 3))
    kl = []
    for e, j, Q, end in rod.end_links:
        RJQ = rod.R_joint[j] @ Q
        P = rod.R_edge[e].T @ RJQ if end == "end" else RJQ.T @ rod.R_edge[e]
        kl.append(_cayley(P[None], np.array([0.5 * rod.rest_length[e]]))[0])
    return kp, np.array(kl).reshape(-1, 3)
