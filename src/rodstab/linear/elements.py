"""Element matrices of P2 (eq 2.12) for one segment element.

P2 is written in its own unknowns ``(beta, omega)``, (2.11)-(2.12): both by quadratic Lagrange
elements on an element of length ``h`` (``xi = (s - s0)/h`` in [0, 1]; end nodes and
mid-node), so the eigenvalue error falls as ``h^4``. The out-of-plane displacement
``w = u3`` enters P2 only through ``beta = w'`` and is not an unknown inside a segment: the
constraint that ``w`` is single valued, ``w(end) - w(start) = int beta ds`` (the paper's
``int beta ds = 0`` of Section 3 for a clamped arc), is imposed on each segment by
:mod:`.assembly`. A second-order operator instead of the fourth-order one in ``w`` (Hermite
cubics) keeps the factorised matrices' condition number ~ ``n^2`` rather than ``n^4``, the
round-off floor that stopped refinement at ~1e-8 (six-ring, 256 elements per segment).

With held curvature ``k = 1/R`` (signed) and held moment ``m = B3 (k - mu kappa_n) = B3 M / R``,
the density of (2.12) is ``1/2 q^T D q`` with ``q = (beta, beta', omega, omega')``::

    B1 (beta' - k omega)^2 + B2 (omega' + k beta)^2 - m (k beta^2 + k omega^2 + 2 beta omega')

The end term ``B3 M alpha beta / R |`` of (2.12) is not included here: with ``alpha`` an Euler
angle it is no function of the linearised rotation alone. The exact second variation (a
rotation ``exp(Theta) R0`` with ``Theta`` continuous at welds) is this density plus
``1/2 m [beta omega]`` over every segment, which :mod:`.assembly` adds at the segment ends
(:func:`~rodstab.linear.assembly.end_term_matrices`). Those terms cancel across smooth welds
and cusps, which is why (2.12) alone is right for every structure of the paper, and not
across a weld of any other angle.

``D = D0 + mu D1`` is affine in the load factor ``mu``.

Element DOF order: ``(beta1, omega1, beta2, omega2, beta_mid, omega_mid)``.
"""

from __future__ import annotations

import numpy as np

_GAUSS_X, _GAUSS_W = np.polynomial.legendre.leggauss(3)
_XI = 0.5 * (_GAUSS_X + 1.0)
_WQ = 0.5 * _GAUSS_W
#: ``int beta ds`` over an element in its DOF order, per unit length (Simpson, exact).
SIMPSON = np.array([1.0, 0.0, 1.0, 0.0, 4.0, 0.0]) / 6.0


def _shape_rows(h: float) -> np.ndarray:
    """``B`` of shape (n_gauss, 4, 6): rows ``(beta, beta', omega, omega')`` at Gauss points."""
    x = _XI
    n = (2 * (x - 0.5) * (x - 1), 2 * x * (x - 0.5), -4 * x * (x - 1))  # node 1, node 2, mid
    dn = ((4 * x - 3) / h, (4 * x - 1) / h, (-8 * x + 4) / h)
    B = np.zeros((x.size, 4, 6))
    for col, (f, df) in zip(((0, 1), (2, 3), (4, 5)), zip(n, dn, strict=True), strict=True):
        B[:, 0, col[0]] = f
        B[:, 1, col[0]] = df
        B[:, 2, col[1]] = f
        B[:, 3, col[1]] = df
    return B


def density_matrices(k: float, kappa_n: float, B1: float, B2: float,
                     B3: float) -> tuple[np.ndarray, np.ndarray]:
    """``(D0, D1)`` with ``D = D0 + mu D1`` for ``q = (beta, beta', omega, omega')``."""

    def D_of(m: float, with_elastic: bool) -> np.ndarray:
        D = np.zeros((4, 4))
        e = 1.0 if with_elastic else 0.0
        D[0, 0] = e * B2 * k * k - m * k
        D[1, 1] = e * B1
        D[2, 2] = e * B1 * k * k - m * k
        D[3, 3] = e * B2
        D[1, 2] = D[2, 1] = -e * B1 * k
        # beta omega' collects B2 k from (omega' + k beta)^2 and -m from the prestress term.
        D[3, 0] = D[0, 3] = e * B2 * k - m
        return D

    # m = B3 k - mu B3 kappa_n: D0 carries m = B3 k, D1 the part proportional to mu.
    return D_of(B3 * k, True), D_of(-B3 * kappa_n, False)


def element_matrices(h: float, D0: np.ndarray, D1: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``(K0, K1)`` (6x6): ``int B^T D B ds`` for ``D0`` and ``D1`` by exact 3-point Gauss."""
    B = _shape_rows(h)
    K0 = np.einsum("g,gai,ab,gbj->ij", _WQ * h, B, D0, B)
    K1 = np.einsum("g,gai,ab,gbj->ij", _WQ * h, B, D1, B)
    return K0, K1


def element_strains(dofs: np.ndarray, h: float) -> np.ndarray:
    """``q = (beta, beta', omega, omega')`` at the Gauss points, ``(n_el, n_gauss, 4)``.

    ``dofs`` is ``(n_el, 6)`` in the element order. The derivatives are formed from the
    differences ``u2 - u1`` and ``u1 + u2 - 2 u_mid`` first: ``u'`` is ~``h`` times smaller
    than ``u``, and the assembled ``B`` rows (whose rounded entries cancel only approximately,
    the same way in every element) would add ~``eps / h`` to it coherently along the rod.
    """
    x = _XI[None, :]
    out = np.empty((dofs.shape[0], x.size, 4))
    for k, (c1, c2, cm) in enumerate(((0, 2, 4), (1, 3, 5))):
        u1, u2, um = dofs[:, c1, None], dofs[:, c2, None], dofs[:, cm, None]
        d1 = u2 - u1
        d2 = u1 + u2 - 2.0 * um
        out[:, :, 2 * k] = 2 * (x - 0.5) * (x - 1) * u1 + 2 * x * (x - 0.5) * u2 \
            - 4 * x * (x - 1) * um
        out[:, :, 2 * k + 1] = (d1 + (4.0 * x - 2.0) * d2) / h
    return out


def strain_energy(q: np.ndarray, D: np.ndarray, h: float) -> float:
    """``sum_e int q^T D q ds`` (twice the energy of the density ``D``) by the element rule."""
    return float(h * np.einsum("g,ega,ab,egb->", _WQ, q, D, q))
