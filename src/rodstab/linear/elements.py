"""Element matrices of P2 (eq 2.12) for one segment element.

Fields on an element of length ``h`` (``xi = (s - s0)/h`` in [0, 1]): out-of-plane displacement
``w = u3`` by cubic Hermite (nodal ``w``, ``w'``), twist ``omega`` by quadratic Lagrange
(end nodes and mid-node), so both fields' eigenvalue errors fall as ``h^4``.

With ``beta = w'`` (2.11), held curvature ``k = 1/R`` (signed) and held moment
``m = B3 (k - mu kappa_n) = B3 M / R``, the density of (2.12) is ``1/2 q^T D q`` with
``q = (w', w'', omega, omega')``::

    B1 (w'' - k omega)^2 + B2 (omega' + k w')^2 - m (k w'^2 + k omega^2 + 2 w' omega')

The end term ``B3 M alpha beta / R |`` of (2.12) is not included: it vanishes at clamps, and at
a joint in moment equilibrium the ends' contributions cancel (the second-order rotation is
shared, the held moments balance) -- the argument of the paper after (4.4) and (5.2).
``D = D0 + mu D1`` is affine in the load factor ``mu``.

Element DOF order: ``(w1, w1', w2, w2', omega1, omega_mid, omega2)``.
"""

from __future__ import annotations

import numpy as np

_GAUSS_X, _GAUSS_W = np.polynomial.legendre.leggauss(4)
_XI = 0.5 * (_GAUSS_X + 1.0)
_WQ = 0.5 * _GAUSS_W


def _shape_rows(h: float) -> np.ndarray:
    """``B`` of shape (n_gauss, 4, 7): rows ``(w', w'', omega, omega')`` at each Gauss point."""
    x = _XI
    B = np.zeros((x.size, 4, 7))
    # Hermite first and second derivatives with respect to s.
    B[:, 0, 0] = (-6 * x + 6 * x**2) / h
    B[:, 0, 1] = 1 - 4 * x + 3 * x**2
    B[:, 0, 2] = (6 * x - 6 * x**2) / h
    B[:, 0, 3] = -2 * x + 3 * x**2
    B[:, 1, 0] = (-6 + 12 * x) / h**2
    B[:, 1, 1] = (-4 + 6 * x) / h
    B[:, 1, 2] = (6 - 12 * x) / h**2
    B[:, 1, 3] = (-2 + 6 * x) / h
    # Quadratic Lagrange and its derivative.
    B[:, 2, 4] = 2 * (x - 0.5) * (x - 1)
    B[:, 2, 5] = -4 * x * (x - 1)
    B[:, 2, 6] = 2 * x * (x - 0.5)
    B[:, 3, 4] = (4 * x - 3) / h
    B[:, 3, 5] = (-8 * x + 4) / h
    B[:, 3, 6] = (4 * x - 1) / h
    return B


def density_matrices(k: float, kappa_n: float, B1: float, B2: float,
                     B3: float) -> tuple[np.ndarray, np.ndarray]:
    """``(D0, D1)`` with ``D = D0 + mu D1`` for ``q = (w', w'', omega, omega')``."""

    def D_of(m: float, with_elastic: bool) -> np.ndarray:
        D = np.zeros((4, 4))
        e = 1.0 if with_elastic else 0.0
        D[0, 0] = e * B2 * k * k - m * k
        D[1, 1] = e * B1
        D[2, 2] = e * B1 * k * k - m * k
        D[3, 3] = e * B2
        D[1, 2] = D[2, 1] = -e * B1 * k
        # w' omega' collects B2 k from (omega' + k w')^2 and -m from the prestress term.
        D[3, 0] = D[0, 3] = e * B2 * k - m
        return D

    # m = B3 k - mu B3 kappa_n: D0 carries m = B3 k, D1 the part proportional to mu.
    return D_of(B3 * k, True), D_of(-B3 * kappa_n, False)


def element_matrices(h: float, D0: np.ndarray, D1: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``(K0, K1)`` (7x7) with ``int B^T D B ds`` for ``D0`` and ``D1`` (4-point Gauss, exact)."""
    B = _shape_rows(h)
    K0 = np.einsum("g,gai,ab,gbj->ij", _WQ * h, B, D0, B)
    K1 = np.einsum("g,gai,ab,gbj->ij", _WQ * h, B, D1, B)
    return K0, K1
