"""Richardson extrapolation: a discretisation's value and the estimate of its error."""

from __future__ import annotations

import math


def richardson(coarse: float, fine: float, ratio: float, order: float) -> tuple[float, float]:
    """Richardson extrapolation of a discretisation of error ``~ h^order``: ``(value, error)``.

    ``coarse`` and ``fine`` on meshes ``ratio`` apart (``h_coarse = ratio h_fine``); ``value``
    is the extrapolated value and ``error = |fine - coarse| / (ratio^order - 1)`` the estimate
    of the fine value's error (the leading term). Non-finite inputs give ``(fine, nan)``.
    """
    if not (math.isfinite(coarse) and math.isfinite(fine)):
        return float(fine), math.nan
    step = (fine - coarse) / (ratio ** order - 1.0)
    return float(fine + step), float(abs(step))
