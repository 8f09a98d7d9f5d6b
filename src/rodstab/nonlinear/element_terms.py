"""The discrete rod's element energies in closed form: stretch/shear and bending.

Value, exact gradient and exact Hessian of each element's energy in its local variables,
vectorised over elements, returned as :class:`~.jets.Jet` for
:meth:`.discrete.DiscreteRod.energy_terms`. The same numbers as second-order jets of the same
expressions to round-off (tests/test_nonlinear.py), at a fraction of their cost: the generic
jets multiply (E, 3, 3, n, n) arrays for every product, where the closed forms need a few
small contractions.
"""

from __future__ import annotations

import numpy as np

from .jets import _HAT, _SYM, Jet, hat, vee_skew

#: The unstrained tangent in the edge frame (e2: the frames' second director).
_T0 = np.array([0.0, 1.0, 0.0])


def stretch_jet(R: np.ndarray, d: np.ndarray, le: np.ndarray, w: np.ndarray, order: int,
                t0: np.ndarray = _T0) -> Jet:
    """``w |eps|^2`` of every edge and its exact derivatives in ``(dx_i, dx_j, phi)``.

    ``eps = (R exp(hat phi))^T (d + dx_j - dx_i) / l - e2`` (stretch and shear strain; ``R``
    (E, 3, 3) the edge frames, ``d`` (E, 3) the chords, ``le`` the rest lengths, ``w`` the
    weights ``K l / 2``), in closed form at zero increments: with ``u = R^T d / l`` and
    ``A = R^T / l``, ``d eps = -A dx_i + A dx_j + hat(u) phi`` and the second derivatives
    ``d2 eps / dphi_k dphi_m = S_km u`` (``S_km`` the symmetrised ``hat(e_k) hat(e_m)``,
    second derivatives of ``exp(-hat phi)``), ``d2 eps / dphi_k dx_j = -hat(e_k) A`` (minus
    that for ``dx_i``); so the gradient is ``2 w J^T eps`` and the Hessian ``2 w (J^T J +
    sum_c eps_c d2 eps_c)``. The same numbers as second-order jets of the same expression
    (:mod:`.jets`) to round-off, in a fifth of the time; each derivative is computed by the
    same arithmetic at any ``order`` (bit-identical gradients). ``t0``: the unstrained
    ``R^T d / l`` (default ``e2``; (E, 3) for the rigid offsets of a spanning weld, ``l = 1``).
    """
    E = len(le)
    A = np.swapaxes(R, 1, 2) / le[:, None, None]
    u = np.einsum("eji,ej->ei", R, d) / le[:, None]
    eps = u - t0
    v = w * np.einsum("ei,ei->e", eps, eps)
    if order == 0:
        return Jet(v, None, None)
    J = np.empty((E, 3, 9))
    J[:, :, 0:3] = -A
    J[:, :, 3:6] = A
    J[:, :, 6:9] = hat(u)
    w2 = 2.0 * w
    g = w2[:, None] * np.einsum("eci,ec->ei", J, eps)
    if order == 1:
        return Jet(v, g, None)
    H = np.einsum("eci,ecj->eij", J, J)
    # Two-operand contractions: numpy's einsum of three operands loops in Python order.
    H[:, 6:9, 6:9] += np.einsum("kmcd,ecd->ekm", _SYM, eps[:, :, None] * u[:, None, :])
    T = -(np.einsum("ec,kcd->ekd", eps, _HAT) @ A)  # (phi_k, dx_j m)
    H[:, 6:9, 3:6] += T
    H[:, 3:6, 6:9] += np.swapaxes(T, 1, 2)
    H[:, 6:9, 0:3] -= T
    H[:, 0:3, 6:9] -= np.swapaxes(T, 1, 2)
    return Jet(v, g, w2[:, None, None] * H)


def _vee_tr(X: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``vee(X - X^T)`` (..., 3) and ``tr X`` (...) of matrices ``X`` (..., 3, 3)."""
    return vee_skew(X), X[..., 0, 0] + X[..., 1, 1] + X[..., 2, 2]


def bend_jet(Lm: np.ndarray, M: np.ndarray, Rt: np.ndarray, swap: np.ndarray, ds: np.ndarray,
             B: np.ndarray, k0: np.ndarray, order: int) -> Jet:
    """``1/2 ds (k - k0)^T B (k - k0)`` with the Cayley curvature of ``P``, in closed form.

    ``P = Lm exp(-hat(phi_a)) M exp(hat(phi_b)) Rt`` (constant ``Lm, M, Rt`` (E, 3, 3)): two
    frames turned by increments ``phi_a``, ``phi_b``; the local variables are ``(phi_a,
    phi_b)``, or ``(phi_b, phi_a)`` where ``swap`` (E,) is True. ``k = (2 / ds) vee(P - P^T) /
    (1 + tr P)`` (the Cayley measure); ``B`` (E, 3) the stiffnesses, ``k0`` (E, 3) the natural
    curvatures. The derivatives of ``P`` at zero are ``-Lm H_k M Rt``, ``Lm M H_k Rt`` and
    ``Lm S_km M Rt``, ``Lm M S_km Rt``, ``-Lm H_k M H_m Rt`` (``H_k = hat(e_k)``, ``S_km`` its
    symmetrised products: second derivatives of the exponential); ``k = N / D`` by the
    quotient rule. The same numbers as second-order jets of ``P`` to round-off (tested), each
    derivative by the same arithmetic at any ``order``.
    """
    X = M @ Rt
    Y = Lm @ M
    N, D = _vee_tr(Y @ Rt)
    D = D + 1.0
    f = 2.0 / ds
    r = f[:, None] * N / D[:, None] - k0
    wB = 0.5 * ds[:, None] * B
    v = np.einsum("ec,ec->e", wB, r * r)
    if order == 0:
        return Jet(v, None, None)
    E = len(ds)
    # Broadcast matrix products (a three-operand einsum loops in Python order: 10x slower).
    LH = Lm[:, None] @ _HAT[None]  # Lm H_k (E, 3, 3, 3)
    HR = _HAT[None] @ Rt[:, None]  # H_k Rt
    dP = np.concatenate([-(LH @ X[:, None]), Y[:, None] @ HR], axis=1)  # (E, 6, 3, 3)
    dN, dD = _vee_tr(dP)  # (E, 6, 3), (E, 6)
    dN = np.swapaxes(dN, 1, 2)  # (E, 3, 6)
    Di = 1.0 / D
    dc = dN * Di[:, None, None] - N[:, :, None] * (dD * Di[:, None] ** 2)[:, None, :]
    dk = f[:, None, None] * dc  # (E, 3, 6)
    g = np.einsum("ec,eci->ei", 2.0 * wB * r, dk)
    perm = np.where(swap[:, None], np.array([3, 4, 5, 0, 1, 2]), np.arange(6))
    if order == 1:
        return Jet(v, np.take_along_axis(g, perm, axis=1), None)
    d2P = np.empty((E, 6, 6, 3, 3))
    d2P[:, :3, :3] = Lm[:, None, None] @ _SYM[None] @ X[:, None, None]
    d2P[:, 3:, 3:] = Y[:, None, None] @ _SYM[None] @ Rt[:, None, None]
    ab = -(LH[:, :, None] @ (M[:, None] @ HR)[:, None, :])
    d2P[:, :3, 3:] = ab
    d2P[:, 3:, :3] = np.swapaxes(ab, 1, 2)
    d2N, d2D = _vee_tr(d2P)  # (E, 6, 6, 3), (E, 6, 6)
    d2N = np.moveaxis(d2N, 3, 1)  # (E, 3, 6, 6)
    Di2 = Di**2
    cross = dN[:, :, :, None] * dD[:, None, None, :]
    d2c = (d2N * Di[:, None, None, None]
           - (cross + np.swapaxes(cross, 2, 3)) * Di2[:, None, None, None]
           - N[:, :, None, None] * (d2D * Di2[:, None, None])[:, None]
           + 2.0 * N[:, :, None, None] * (dD[:, :, None] * dD[:, None, :]
                                          * (Di2 * Di)[:, None, None])[:, None])
    H = (np.swapaxes((2.0 * wB)[:, :, None] * dk, 1, 2) @ dk
         + np.einsum("ec,ecij->eij", (2.0 * wB * r) * f[:, None], d2c))
    Hp = np.take_along_axis(np.take_along_axis(H, perm[:, :, None], axis=1),
                            perm[:, None, :], axis=2)
    return Jet(v, np.take_along_axis(g, perm, axis=1), Hp)
