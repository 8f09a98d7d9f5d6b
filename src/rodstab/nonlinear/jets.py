"""Second-order jets: values with exact gradients and Hessians, vectorised over elements.

A :class:`Jet` holds, for ``E`` elements and ``n`` local variables, ``v`` (E,), ``g`` (E, n) and
``H`` (E, n, n): a scalar function and its first and second derivatives at one point. Sums,
products and quotients follow the chain rule exactly, so element energies built from them have
exact (not finite-difference) gradients and Hessians. Matrices of jets are :class:`JetMat`
(``v`` (E, 3, 3), ``g`` (E, 3, 3, n), ``H`` (E, 3, 3, n, n)).

A jet of lower order carries ``H = None`` (value and gradient) or also ``g = None`` (value
only), and every operation then skips the missing derivatives: an energy without its Hessian
costs a third of one with it. Each derivative present is computed by the same arithmetic at any
order, so it is the same to the last bit.
"""

from __future__ import annotations

import dataclasses
import functools

import numpy as np


def _sum(a: np.ndarray | None, b: np.ndarray | None) -> np.ndarray | None:
    """Add two derivatives of one order (None when either is absent)."""
    return None if a is None or b is None else a + b


@dataclasses.dataclass
class Jet:
    """Scalar jet (value, gradient, Hessian), vectorised over elements; see the module doc."""

    v: np.ndarray
    g: np.ndarray | None
    H: np.ndarray | None

    def __add__(self, o: Jet | float) -> Jet:
        if isinstance(o, Jet):
            return Jet(self.v + o.v, _sum(self.g, o.g), _sum(self.H, o.H))
        return Jet(self.v + o, self.g, self.H)

    __radd__ = __add__

    def __neg__(self) -> Jet:
        return Jet(-self.v, None if self.g is None else -self.g,
                   None if self.H is None else -self.H)

    def __sub__(self, o: Jet | float) -> Jet:
        return self + (-o)

    def __rsub__(self, o: float) -> Jet:
        return (-self) + o

    def __mul__(self, o: Jet | float | np.ndarray) -> Jet:
        if isinstance(o, Jet):
            g = H = None
            if self.g is not None and o.g is not None:
                g = self.v[:, None] * o.g + o.v[:, None] * self.g
                if self.H is not None and o.H is not None:
                    outer = self.g[:, :, None] * o.g[:, None, :]
                    H = (self.v[:, None, None] * o.H + o.v[:, None, None] * self.H
                         + outer + np.swapaxes(outer, 1, 2))
            return Jet(self.v * o.v, g, H)
        o = np.asarray(o, dtype=float)
        if o.ndim == 1:
            return Jet(self.v * o, None if self.g is None else self.g * o[:, None],
                       None if self.H is None else self.H * o[:, None, None])
        return Jet(self.v * o, None if self.g is None else self.g * o,
                   None if self.H is None else self.H * o)

    __rmul__ = __mul__

    def reciprocal(self) -> Jet:
        """``1 / self``: derivatives ``-1/v^2`` and ``2/v^3``."""
        inv = 1.0 / self.v
        if self.g is None:
            return Jet(inv, None, None)
        H = None
        if self.H is not None:
            H = (2.0 * np.einsum("ei,ej->eij", self.g, self.g) * inv[:, None, None] ** 3
                 - self.H * inv[:, None, None] ** 2)
        return Jet(inv, -self.g * inv[:, None] ** 2, H)

    def __truediv__(self, o: Jet | float) -> Jet:
        if isinstance(o, Jet):
            return self * o.reciprocal()
        return self * (1.0 / o)

    @staticmethod
    def stack(jets: list[Jet]) -> Jet:
        """Stack the jets along the element axis (``k`` jets of E elements: one of k E).

        Elementwise operations on the stack are those on each part, to the last bit; one
        operation on a stack replaces ``k`` (numpy's cost per call, not per element, dominated
        the rod's energy at a few hundred elements).
        """
        def cat(parts: list[np.ndarray | None]) -> np.ndarray | None:
            present = [a for a in parts if a is not None]
            return np.concatenate(present) if len(present) == len(parts) else None

        v = np.concatenate([j.v for j in jets])
        return Jet(v, cat([j.g for j in jets]), cat([j.H for j in jets]))

    def split(self, k: int) -> list[Jet]:
        """Split into ``k`` jets of equal length: the inverse of :meth:`stack`."""
        E = len(self.v) // k
        return [Jet(self.v[i * E:(i + 1) * E],
                    None if self.g is None else self.g[i * E:(i + 1) * E],
                    None if self.H is None else self.H[i * E:(i + 1) * E]) for i in range(k)]


@dataclasses.dataclass
class JetMat:
    """3x3 matrix of jets (``g`` and ``H`` None below second order, as for :class:`Jet`)."""

    v: np.ndarray
    g: np.ndarray | None
    H: np.ndarray | None

    def entry(self, i: int, j: int) -> Jet:
        """Element ``(i, j)`` as a :class:`Jet`."""
        return Jet(self.v[:, i, j], None if self.g is None else self.g[:, i, j],
                   None if self.H is None else self.H[:, i, j])

    @property
    def T(self) -> JetMat:
        """Transpose."""
        return JetMat(np.swapaxes(self.v, 1, 2),
                      None if self.g is None else np.swapaxes(self.g, 1, 2),
                      None if self.H is None else np.swapaxes(self.H, 1, 2))

    def __matmul__(self, o: JetMat) -> JetMat:
        v = np.einsum("eij,ejk->eik", self.v, o.v)
        g = H = None
        if self.g is not None and o.g is not None:
            g = (np.einsum("eij,ejkn->eikn", self.v, o.g)
                 + np.einsum("eijn,ejk->eikn", self.g, o.v))
            if self.H is not None and o.H is not None:
                cross = np.einsum("eijn,ejkm->eiknm", self.g, o.g)
                H = (np.einsum("eij,ejknm->eiknm", self.v, o.H)
                     + np.einsum("eijnm,ejk->eiknm", self.H, o.v)
                     + cross + np.swapaxes(cross, 3, 4))
        return JetMat(v, g, H)

    def times(self, Q: np.ndarray) -> JetMat:
        """``self @ Q`` for constant matrices ``Q`` (E, 3, 3)."""
        return JetMat(np.einsum("eij,ejk->eik", self.v, Q),
                      None if self.g is None else np.einsum("eijn,ejk->eikn", self.g, Q),
                      None if self.H is None else np.einsum("eijnm,ejk->eiknm", self.H, Q))

    def take(self, mask: np.ndarray) -> JetMat:
        """Return the elements selected by the boolean ``mask`` (E,)."""
        return JetMat(self.v[mask], None if self.g is None else self.g[mask],
                      None if self.H is None else self.H[mask])

    @staticmethod
    def merge(mask: np.ndarray, where: JetMat, elsewhere: JetMat) -> JetMat:
        """Elements of ``where`` at the True entries of ``mask``, of ``elsewhere`` at the others.

        The inverse of :meth:`take`: ``where = m.take(mask)``, ``elsewhere = m.take(~mask)``.
        """
        def fill(a: np.ndarray | None, b: np.ndarray | None) -> np.ndarray | None:
            if a is None or b is None:
                return None
            out = np.empty((len(mask),) + a.shape[1:])
            out[mask], out[~mask] = a, b
            return out

        v = fill(where.v, elsewhere.v)
        assert v is not None  # values are always formed
        return JetMat(v, fill(where.g, elsewhere.g), fill(where.H, elsewhere.H))

    def column(self, j: int) -> Jet:
        """Column ``j``: the entries ``(0, j), (1, j), (2, j)`` stacked (:meth:`Jet.stack`)."""
        def col(a: np.ndarray | None) -> np.ndarray | None:
            if a is None:
                return None
            c = np.moveaxis(a[:, :, j], 1, 0)  # (3, E, ...)
            return c.reshape((-1,) + c.shape[2:])

        v = col(self.v)
        assert v is not None  # values are always formed
        return Jet(v, col(self.g), col(self.H))

    def apply(self, x: list[Jet]) -> list[Jet]:
        """Matrix times a 3-vector of jets: ``sum_j A_ij x_j``, the three rows stacked."""
        acc = _zero_like(Jet.stack([x[0]] * 3))
        for j in range(3):
            acc = acc + self.column(j) * Jet.stack([x[j]] * 3)
        return acc.split(3)


@functools.lru_cache(maxsize=None)
def _product_hessians(coeffs: tuple[tuple[tuple[float, ...], tuple[float, ...]], ...]
                      ) -> np.ndarray:
    """Constant Hessians ``(p, 3k, 3k)`` of the products of :class:`QuadraticProducts`."""
    return np.stack([np.kron(np.outer(a, b) + np.outer(b, a), np.eye(3))
                     for a, b in (np.asarray(c, float) for c in coeffs)])


class QuadraticProducts:
    """Products ``u . v`` of fixed combinations of a term's node positions, and their lift.

    A term's energy depends on its ``k`` node positions only through ``p`` such products
    (``u = sum_i cu_i X_i``, ``v = sum_i cv_i X_i``), whose Hessians in the ``3 k`` positions
    are constant. So the energy is formed as a jet in the ``p`` products (:attr:`jets`: value,
    unit gradient, zero Hessian) and lifted to the positions once (:meth:`lift`): ``g = F_q
    G_q``, ``H = F_q K_q + G^T F_qq G``. The chain of operations then runs on ``p x p`` Hessians
    instead of ``3k x 3k`` ones (4 against 9 for a contact node-segment term, 6 against 12 for
    an edge pair, :mod:`.contact_model`): the contact jets cost half as much at 32 elements per
    rod (``benchmarks/contact.py``, the stacked line).

    ``X`` (m, k, 3): the ``k`` node positions of ``m`` terms; ``coeffs``: one ``(cu, cv)`` pair
    of ``k`` coefficients per product; ``order``: derivatives formed (0, 1, 2).
    """

    def __init__(self, X: np.ndarray, coeffs: tuple[tuple[tuple[float, ...],
                                                       tuple[float, ...]], ...], order: int):
        m, k = X.shape[:2]
        p = len(coeffs)
        cu, cv = (np.array([c[s] for c in coeffs], float) for s in (0, 1))  # (p, k)
        U, V = np.einsum("qi,mic->mqc", cu, X), np.einsum("qi,mic->mqc", cv, X)
        vals = np.einsum("mqc,mqc->qm", U, V)
        self.G = (cu[None, :, :, None] * V[:, :, None] + cv[None, :, :, None] * U[:, :, None]
                  ).reshape(m, p, 3 * k)  # (m, p, 3k)
        self.K = _product_hessians(coeffs)
        self.order = order
        eye = np.broadcast_to(np.eye(p), (m, p, p))
        self.jets = [Jet(vals[q], eye[:, q] if order >= 1 else None,
                         np.zeros((m, p, p)) if order >= 2 else None) for q in range(p)]

    def lift(self, F: Jet) -> Jet:
        """``F`` (a jet in the products) as a jet in the node positions."""
        if F.g is None:
            return F
        g = np.einsum("mp,mpk->mk", F.g, self.G)
        H = None
        if F.H is not None:
            H = np.einsum("mp,pkl->mkl", F.g, self.K) + np.matmul(
                np.swapaxes(self.G, 1, 2), np.matmul(F.H, self.G))
        return Jet(F.v, g, H)


def _zero_like(j: Jet) -> Jet:
    return Jet(np.zeros_like(j.v), None if j.g is None else np.zeros_like(j.g),
               None if j.H is None else np.zeros_like(j.H))


_HAT = np.zeros((3, 3, 3))  # _HAT[k] = hat(e_k), hat(a) b = a x b
_HAT[0, 2, 1], _HAT[0, 1, 2] = 1.0, -1.0
_HAT[1, 0, 2], _HAT[1, 2, 0] = 1.0, -1.0
_HAT[2, 1, 0], _HAT[2, 0, 1] = 1.0, -1.0


#: ``_SYM[k, m] = (hat(e_k) hat(e_m) + hat(e_m) hat(e_k)) / 2``: the second derivatives of
#: ``exp(hat(phi))`` at 0.
_SYM = np.array([[0.5 * (_HAT[k] @ _HAT[m] + _HAT[m] @ _HAT[k]) for m in range(3)]
                 for k in range(3)])


def hat(a: np.ndarray) -> np.ndarray:
    """Skew matrices ``(..., 3, 3)`` with ``hat(a) b = a x b``."""
    return np.einsum("...k,kij->...ij", a, _HAT)


def vee_skew(A: np.ndarray) -> np.ndarray:
    """``vee(A - A^T)`` of matrices ``A`` (..., 3, 3): twice the axial vector of the skew part.

    On a skew matrix, twice the inverse of :func:`hat`: ``vee_skew(hat(a)) = 2 a``.
    """
    return np.stack([A[..., 2, 1] - A[..., 1, 2], A[..., 0, 2] - A[..., 2, 0],
                     A[..., 1, 0] - A[..., 0, 1]], axis=-1)


def rotation_jet(R: np.ndarray, n: int, offset: int, order: int = 2) -> JetMat:
    """``R exp(hat(phi))`` at ``phi = 0`` as a jet in local variables ``offset..offset+2``.

    ``exp(hat(phi)) = I + hat(phi) + hat(phi)^2 / 2 + O(phi^3)``: first and second derivatives
    at ``phi = 0`` are exact. ``R`` has shape (E, 3, 3); derivatives up to ``order`` (0, 1, 2).
    """
    E = R.shape[0]
    g = np.zeros((E, 3, 3, n)) if order >= 1 else None
    H = np.zeros((E, 3, 3, n, n)) if order >= 2 else None
    for k in range(3):
        if g is not None:
            g[..., offset + k] = R @ _HAT[k]
        if H is not None:
            for m in range(k, 3):  # the second derivatives are symmetric in (k, m)
                H[..., offset + k, offset + m] = H[..., offset + m, offset + k] = R @ _SYM[k, m]
    return JetMat(R.copy(), g, H)


def vector_jet(x: np.ndarray, n: int, offset: int, order: int = 2) -> list[Jet]:
    """Positions ``x`` (E, 3) as jets in local variables ``offset..offset+2`` (up to ``order``)."""
    E = x.shape[0]
    out = []
    for k in range(3):
        g = None
        if order >= 1:
            g = np.zeros((E, n))
            g[:, offset + k] = 1.0
        out.append(Jet(x[:, k].copy(), g, np.zeros((E, n, n)) if order >= 2 else None))
    return out


def rodrigues(phi: np.ndarray) -> np.ndarray:
    """Exact ``exp(hat(phi))`` for rotation vectors ``phi`` (..., 3)."""
    th = np.linalg.norm(phi, axis=-1)[..., None, None]
    K = hat(phi)
    small = th < 1e-8
    ths = np.where(small, 1.0, th)
    a = np.where(small, 1.0 - th**2 / 6, np.sin(ths) / ths)
    b = np.where(small, 0.5 - th**2 / 24, (1 - np.cos(ths)) / ths**2)
    return np.eye(3) + a * K + b * (K @ K)


#: Below this ``u = |c|^2`` (``c`` the Cayley vector, ``tan(theta / 2)``) the series of
#: :func:`_half_atan_ratio` is used: 10 terms leave an error below ``u^10 / 21`` (< 1e-22).
_SERIES_U = 1e-2
_SERIES_TERMS = 10


def _half_atan_ratio(u: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``h(u) = 2 atan(sqrt u) / sqrt u`` and its first two derivatives (analytic at ``u = 0``).

    ``theta = h(|c|^2) c`` turns the Cayley vector ``c = tan(theta / 2) axis`` into the rotation
    vector. Near 0 the series ``2 sum_k (-u)^k / (2k + 1)``, else the closed forms.
    """
    u = np.asarray(u, float)
    small = u < _SERIES_U
    us = np.where(small, u, 0.0)
    k = np.arange(_SERIES_TERMS)[:, None]
    coef = 2.0 * (-1.0) ** k / (2 * k + 1)
    h_s = np.sum(coef * us ** k, axis=0)
    d1_s = np.sum((coef * k)[1:] * us ** (k[1:] - 1), axis=0)
    d2_s = np.sum((coef * k * (k - 1))[2:] * us ** (k[2:] - 2), axis=0)
    ub = np.where(small, 1.0, u)
    s = np.sqrt(ub)
    at = np.arctan(s)
    h_b = 2.0 * at / s
    d1_b = 1.0 / (ub * (1.0 + ub)) - at / s**3
    d2_b = (-(1.0 + 2.0 * ub) / (ub**2 * (1.0 + ub) ** 2) - 0.5 / (ub**2 * (1.0 + ub))
            + 1.5 * at / ub**2.5)
    return (np.where(small, h_s, h_b), np.where(small, d1_s, d1_b),
            np.where(small, d2_s, d2_b))


def rotation_vector(P: JetMat) -> list[Jet]:
    """Rotation vector ``theta axis`` (exact log map) of a rotation-matrix jet, as three jets.

    ``theta = h(|c|^2) c`` with the Cayley vector ``c = vee(P - P^T) / (1 + tr P)`` and
    ``h(u) = 2 atan(sqrt u) / sqrt u`` (:func:`_half_atan_ratio`): smooth for ``theta < pi``
    (at a half turn ``1 + tr P = 0``).
    """
    den = (P.entry(0, 0) + P.entry(1, 1) + P.entry(2, 2) + 1.0).reciprocal()
    c = [(P.entry(2, 1) - P.entry(1, 2)) * den, (P.entry(0, 2) - P.entry(2, 0)) * den,
         (P.entry(1, 0) - P.entry(0, 1)) * den]
    u = c[0] * c[0] + c[1] * c[1] + c[2] * c[2]
    h0, h1, h2 = _half_atan_ratio(u.v)
    h = Jet(h0, None if u.g is None else h1[:, None] * u.g,
            None if u.g is None or u.H is None else
            h1[:, None, None] * u.H + h2[:, None, None] * np.einsum("ei,ej->eij", u.g, u.g))
    return [h * ci for ci in c]


def cross_rows(u: np.ndarray, v: np.ndarray) -> np.ndarray:
    """Row-wise cross products ``u x v`` of (k, 3) arrays.

    np.cross's arithmetic, bit for bit (tested), without its axis handling, which cost more
    than the products on the contact model's few hundred rows (a third of its broad phase).
    """
    out = np.empty_like(u)
    out[:, 0] = u[:, 1] * v[:, 2] - u[:, 2] * v[:, 1]
    out[:, 1] = u[:, 2] * v[:, 0] - u[:, 0] * v[:, 2]
    out[:, 2] = u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0]
    return out
