"""Printed Euler-Lagrange equations tested against the first variation of P2 (2.12).

For the quadratic functional ``I[y] = int p2_density`` (:func:`rodstab.kinematics.p2_density`),
the first variation is exactly ``DI(y)[d] = (I[y + d] - I[y - d]) / 2``. If the ODEs ``E(y) = 0``
are the Euler-Lagrange equations of ``I``, then ``DI(y)[d] = int E(y) . d`` (up to a fixed factor
and sign, which the caller states) for *every* field ``y`` and every test field ``d`` that
vanishes at the ends with enough derivatives to kill the boundary terms. Fields here are random
polynomials on ``[0, 1]`` (seeded), so derivatives are exact and Gauss-Legendre quadrature with
:data:`N_GAUSS` nodes integrates every product exactly: only round-off separates the two sides
when the ODEs are right. This uses no sympy and none of the algebra of :mod:`rodstab.transfer`.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Protocol, cast

import numpy as np
from numpy.polynomial import Polynomial

#: Gauss-Legendre nodes on [0, 1]: exact for polynomials up to degree 2 N_GAUSS - 1 = 47; the
#: integrands (products of two fields of degree <= 8) have degree <= 16.
N_GAUSS = 24
#: Degree of the random state fields.
STATE_DEGREE = 8
#: Degree of the random factor of the test fields (times the vanishing envelope).
TEST_DEGREE = 4


class Field(Protocol):
    """What the checks do with a field: evaluate it, differentiate it, combine it linearly.

    A :class:`numpy.polynomial.Polynomial` is one. The checks see fields through this
    protocol, not numpy's stubs: resolving the stubs' overloads for every term of (3.1) and
    (3.4) took mypy 8 s of its 27 s on ``src``.
    """

    def __call__(self, x: np.ndarray) -> np.ndarray: ...  # noqa: D102
    def deriv(self, m: int = 1) -> Field: ...  # noqa: D102
    def __add__(self, other: Field | float) -> Field: ...
    def __radd__(self, other: float) -> Field: ...
    def __sub__(self, other: Field | float) -> Field: ...
    def __rsub__(self, other: float) -> Field: ...
    def __mul__(self, other: Field | float) -> Field: ...
    def __rmul__(self, other: float) -> Field: ...


def random_fields(seed: int, n_fields: int, vanish: tuple[int, ...] = ()) -> list[Field]:
    """Return ``n_fields`` random polynomials on ``[0, 1]``.

    Field ``i`` is multiplied by ``(x (1 - x))**vanish[i]`` (so it and its first ``vanish[i] - 1``
    derivatives vanish at both ends) when ``vanish`` is given, and has degree ``STATE_DEGREE``
    otherwise.
    """
    rng = np.random.default_rng(seed)
    env = Polynomial([0.0, 1.0, -1.0])  # x (1 - x)
    fields = ([Polynomial(rng.uniform(-1.0, 1.0, STATE_DEGREE + 1)) for _ in range(n_fields)]
              if not vanish else
              [env**k * Polynomial(rng.uniform(-1.0, 1.0, TEST_DEGREE + 1)) for k in vanish])
    # A Polynomial combines with a Field at run time; its stubs accept only ABCPolyBase.
    return cast("list[Field]", fields)


def integral(f: Callable[[np.ndarray], np.ndarray]) -> float:
    """``int_0^1 f(x) dx`` by ``N_GAUSS``-point Gauss-Legendre quadrature."""
    x, w = np.polynomial.legendre.leggauss(N_GAUSS)
    return float(0.5 * w @ f(0.5 * (x + 1.0)))


def first_variation(functional: Callable[[list[Field]], float],
                    state: list[Field], test: list[Field]) -> float:
    """``DI(state)[test] = (I[state + test] - I[state - test]) / 2``, exact for quadratic I."""
    plus = functional([y + d for y, d in zip(state, test, strict=True)])
    minus = functional([y - d for y, d in zip(state, test, strict=True)])
    return 0.5 * (plus - minus)


def relative_mismatch(a: float, b: float) -> float:
    """Return ``|a - b| / max(|a|, |b|)``: 0 when two first variations agree, ~1 when not."""
    return abs(a - b) / max(abs(a), abs(b), np.finfo(float).tiny)
