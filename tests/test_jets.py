"""Jets in products of positions (``QuadraticProducts``) against jets in the positions."""

import numpy as np
import pytest

from rodstab.nonlinear.jets import Jet, QuadraticProducts, cross_rows, vector_jet


def _direct(X: np.ndarray, coeffs, order: int) -> list[Jet]:
    """The same products formed from jets of the 3 k coordinates (the independent route)."""
    m, k = X.shape[:2]
    comps = [vector_jet(X[:, i], 3 * k, 3 * i, order) for i in range(k)]
    out = []
    for cu, cv in coeffs:
        u = [sum(c * comps[i][d] for i, c in enumerate(cu)) for d in range(3)]
        v = [sum(c * comps[i][d] for i, c in enumerate(cv)) for d in range(3)]
        out.append(u[0] * v[0] + u[1] * v[1] + u[2] * v[2])
    return out


@pytest.mark.parametrize("order", [0, 1, 2])
def test_lifted_function_of_products_equals_the_position_jet(order: int) -> None:
    rng = np.random.default_rng(3)
    X = rng.normal(size=(5, 3, 3))
    coeffs = (((1.0, -1.0, 0.0), (1.0, -1.0, 0.0)), ((1.0, -1.0, 0.0), (0.0, -1.0, 1.0)),
              ((0.0, -1.0, 1.0), (0.0, -1.0, 1.0)))
    Q = QuadraticProducts(X, coeffs, order)
    ww, we, ee = Q.jets
    lifted = Q.lift(ww - we * we / ee)  # squared distance of node 0 from the line of 1, 2
    a, b, c = _direct(X, coeffs, order)
    direct = a - b * b / c
    np.testing.assert_allclose(lifted.v, direct.v, rtol=1e-12)
    if order >= 1:
        np.testing.assert_allclose(lifted.g, direct.g, rtol=1e-10, atol=1e-12)
    else:
        assert lifted.g is None
    if order >= 2:
        np.testing.assert_allclose(lifted.H, direct.H, rtol=1e-10, atol=1e-12)
        # and the closed form of the value: |p - a|^2 - ((p - a).(b - a))^2 / |b - a|^2
        w, e = X[:, 0] - X[:, 1], X[:, 2] - X[:, 1]
        np.testing.assert_allclose(lifted.v, (np.cross(w, e) ** 2).sum(1)
                                   / (e * e).sum(1), rtol=1e-12)


def test_cross_rows_is_numpys_cross_bit_for_bit() -> None:
    # The contact model's distances must not move a bit when np.cross is replaced: every
    # recorded number with contact depends on them. Rows over 16 decades, and exact zeros.
    rng = np.random.default_rng(3)
    u = rng.normal(size=(2000, 3)) * 10.0 ** rng.uniform(-8, 8, (2000, 1))
    v = rng.normal(size=(2000, 3))
    v[:10] = u[:10]  # parallel rows: the cross product is zero
    assert np.array_equal(cross_rows(u, v), np.cross(u, v))
