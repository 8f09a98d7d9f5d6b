"""The discrete rod's Hessian in CSR form from its element terms, by a plan made per dof layout.

:meth:`~.discrete.DiscreteRod.energy_terms` adds every element term's dense Hessian block
(stretch/shear, bending, half-joints, offsets, point moments) at the term's dofs; this module
turns them into one CSR matrix (:func:`hessian_plan`), and pads the contact term's Hessian,
which is over the node positions only, to the rod's size (:func:`padded`).
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp


class HessianPlan:
    """Where each element term's Hessian entries land in the CSR matrix, for one dof layout.

    The element terms of :meth:`DiscreteRod._evaluate` fill the same (row, column) triplets at
    every evaluation of a mesh; only their values change. The plan sorts the triplets once
    (duplicates summed into one slot) so that each evaluation is one ``bincount`` into the
    CSR data, instead of scipy's triplet conversion (a third of an evaluation at 6 elements
    per rod, measured 2026-12-06). Slots are summed in triplet order, as the conversion did.
    """

    def __init__(self, blocks: list[np.ndarray], n: int) -> None:
        rows = np.concatenate([np.repeat(d, d.shape[1], axis=1).ravel() for d in blocks])
        cols = np.concatenate([np.tile(d, (1, d.shape[1])).ravel() for d in blocks])
        key = rows.astype(np.int64) * n + cols
        unique, self.slot = np.unique(key, return_inverse=True)
        self.indices = (unique % n).astype(np.int32)
        self.indptr = np.searchsorted(unique // n, np.arange(n + 1)).astype(np.int32)
        self.n = n

    def assemble(self, values: np.ndarray) -> sp.csr_matrix:
        """Return the CSR matrix with ``values`` (the terms' Hessians, raveled) summed in."""
        data = np.bincount(self.slot, weights=values, minlength=len(self.indices))
        H = sp.csr_matrix((data, self.indices.copy(), self.indptr.copy()), shape=(self.n, self.n))
        H.has_canonical_format = True
        return H


#: Dof layouts whose :class:`HessianPlan` is kept (the least recently used is dropped first).
HESSIAN_PLANS = 8
_PLANS: dict[tuple[int, bytes], HessianPlan] = {}


def hessian_plan(blocks: list[np.ndarray], n: int) -> HessianPlan:
    """Return the plan of this dof layout (the terms' dof arrays, exactly), made once."""
    key = (n, b"".join(np.ascontiguousarray(d, np.int64).tobytes() + bytes(str(d.shape), "ascii")
                       for d in blocks))
    plan = _PLANS.pop(key, None)
    if plan is None:
        plan = HessianPlan(blocks, n)
        while len(_PLANS) >= HESSIAN_PLANS:
            del _PLANS[next(iter(_PLANS))]
    _PLANS[key] = plan  # last: most recently used
    return plan


def padded(H: sp.spmatrix, n: int) -> sp.csr_matrix:
    """``H`` (the contact Hessian over the positions) as an ``n x n`` CSR matrix."""
    H = H.tocsr()
    H.resize((n, n))
    return H
