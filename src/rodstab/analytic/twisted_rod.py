"""Greenhill's twisted rod: the end rotation at which a straight twisted rod buckles.

Beyond the paper (report row GR-rot). A straight rod of isotropic bending stiffness
``B = B1 = B3`` and torsional stiffness ``B2``, clamped at one end and held at the other by a
clamp free to slide along the rod (no axial force), twisted by an end rotation ``phi``: the
twisting moment is ``B2 phi / L`` and Greenhill's threshold for clamped ends is
``M_t L / B = 2 x`` with ``x`` the first positive root of ``tan x = x``, i.e.
``phi_c B2 / (B L) = 2 x = 8.9868``.
"""

from __future__ import annotations

import math

from ..errors import RodstabInputError, require_positive
from ..numerics import refine_root

#: Bracket of the first positive root of ``tan x = x`` (``x = 4.4934``, just below 3 pi / 2).
_TAN_X_BRACKET = (4.0, 4.6)


def greenhill_end_rotation(b1: float, b2: float) -> float:
    """Critical end rotation in ``phi_c B2 / (B L) = 2 x`` (``tan x = x``), clamped ends.

    Parameters
    ----------
    b1, b2 : float
        ``B1 / B3`` (must be 1: isotropic bending) and ``B2 / B3`` (> 0). The returned
        non-dimensional rotation does not depend on ``b2``; it is validated all the same.
    """
    require_positive("b2", b2)
    if abs(require_positive("b1", b1) - 1.0) > 1e-12:
        raise RodstabInputError(f"b1 must be 1 for Greenhill's rod (isotropic bending), "
                                f"got {b1!r}")
    x = refine_root(lambda x: math.tan(x) - x, *_TAN_X_BRACKET)  # the one root finder
    return 2 * x
