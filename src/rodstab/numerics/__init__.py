"""The one root finder and the one eigen solver of rodstab.

Every characteristic equation and every linear stability pencil in the package goes through
this package, so that the accuracy statement is made once. Its modules: :mod:`.roots` (scalar
and matrix roots, the multiplicity rule), :mod:`.eigen` (pencils, eigenpairs, constrained
factorisations), :mod:`.richardson`, :mod:`.threads` (one BLAS thread for the small dense
systems); every public name is re-exported here
(``from rodstab.numerics import find_roots``).

* :func:`find_roots` -- roots of a real scalar function on an interval: scan on a uniform grid,
  bracket every sign change and every near-zero local minimum of ``|f|`` (a root of even
  multiplicity, where ``f`` touches zero without changing sign), refine (Brent), and estimate
  each root's multiplicity from the local order of vanishing.
* :func:`matrix_roots` -- values ``x`` where a square matrix ``A(x)`` is singular: scan the
  *smallest singular value* relative to the largest (never only a determinant's sign, which
  misses repeated roots), refine the minimum, polish by the determinant's sign change when there
  is one, and report the multiplicity as the number of (near-)zero singular values.
* :func:`lowest_eigenpairs` -- the lowest eigenpairs of a sparse symmetric matrix (dense
  solver for small ones, shift-invert Lanczos with an inertia-certified shift beyond), each
  pair's residual checked; :func:`jacobi_scaling` is the one diagonal scaling used before it
  and before the sparse pencil solve.
* :func:`pencil_interval` -- for a pencil ``K(p) = A - p C`` with ``A`` symmetric positive
  definite, the open interval of the load parameter ``p`` containing 0 on which ``K(p)`` stays
  positive definite, with the critical modes, their multiplicities and residuals.

"Never miss a root" is stated precisely: every root ``x*`` of ``f`` that is separated from every
other root by more than two scan spacings ``h = (hi - lo) / n_scan`` is found; a pair of simple
roots closer than that is still found when it is separated by more than ``h / SUBSCAN`` (a
local re-scan at every minimum of the scan measure); closer pairs may be returned as one root
whose multiplicity counts both.
"""

from __future__ import annotations

from .eigen import (
    DENSE_EIG_MAX,
    DENSE_FALLBACK_MAX,
    EIG_RESIDUAL_TOL,
    EIG_SHIFT_FLOOR,
    LANCZOS_ATTEMPTS,
    LANCZOS_MAXITER,
    NEAR_VALUES,
    SMALL_PENCIL,
    SOLVE_BLOCK_ENTRIES,
    SPARSE_RESIDUAL_TOL,
    ConstrainedFactor,
    PencilInterval,
    count_below,
    definite_on,
    jacobi_scaling,
    lowest_eigenpairs,
    lowest_eigenpairs_on,
    pencil_interval,
    pencil_interval_sparse,
    pencil_window,
)
from .richardson import (
    richardson,
)
from .roots import (
    EPS,
    MULTIPLICITY_ERROR_FACTOR,
    MULTIPLICITY_RTOL,
    NULL_SLOPE_STEP,
    SCAN_INTERVALS,
    SINGULAR_TOL,
    SUBSCAN,
    TOUCH_SINGULAR_TOL,
    TOUCH_TOL,
    XTOL,
    Root,
    RootSearch,
    find_roots,
    golden_min,
    matrix_roots,
    multiplicity_of,
    multiplicity_tolerance,
    refine_root,
    sigma_min_2x2,
)
from .threads import serial_blas, serially

__all__ = [
    "ConstrainedFactor",
    "DENSE_EIG_MAX",
    "DENSE_FALLBACK_MAX",
    "EIG_RESIDUAL_TOL",
    "EIG_SHIFT_FLOOR",
    "EPS",
    "LANCZOS_ATTEMPTS",
    "LANCZOS_MAXITER",
    "MULTIPLICITY_ERROR_FACTOR",
    "MULTIPLICITY_RTOL",
    "NEAR_VALUES",
    "NULL_SLOPE_STEP",
    "PencilInterval",
    "Root",
    "RootSearch",
    "SCAN_INTERVALS",
    "SINGULAR_TOL",
    "SMALL_PENCIL",
    "SOLVE_BLOCK_ENTRIES",
    "SPARSE_RESIDUAL_TOL",
    "SUBSCAN",
    "TOUCH_SINGULAR_TOL",
    "TOUCH_TOL",
    "XTOL",
    "count_below",
    "definite_on",
    "find_roots",
    "golden_min",
    "jacobi_scaling",
    "lowest_eigenpairs",
    "lowest_eigenpairs_on",
    "matrix_roots",
    "multiplicity_of",
    "multiplicity_tolerance",
    "pencil_interval",
    "pencil_interval_sparse",
    "pencil_window",
    "refine_root",
    "richardson",
    "serial_blas",
    "serially",
    "sigma_min_2x2",
]
