"""Continuation of discrete-rod equilibria.

One corrector, one path type, special points, branches and their post-buckling, studies, run
storage.

:mod:`.corrector` (the bordered Newton corrector with arclength/amplitude/phase rows, the
stepper) -> :mod:`.path` (the :class:`Path` result, the amplitude ``xi`` and the post-buckling
verdict) -> :mod:`.special` (folds, branch points) -> :mod:`.branches` (directions at simple
and double eigenvalues, arclength and amplitude tracers) -> :mod:`.run` (:func:`continuation`
in any parameter, with :mod:`.storage`) -> :mod:`.studies` (critical load along a primary path,
imperfection sensitivity).
"""

from .branches import (
    Direction,
    amplitude_branch,
    arclength_from_bifurcation,
    branch_directions,
    post_buckling_branch,
    trace_branch,
)
from .path import Path, SpecialKind, post_buckling, xi
from .run import continuation, special_point_errors
from .studies import (
    ImperfectionSensitivity,
    PrimaryCritical,
    critical_along_primary,
    imperfection_sensitivity,
)

__all__ = ["Direction", "ImperfectionSensitivity", "Path", "PrimaryCritical", "SpecialKind",
           "amplitude_branch", "arclength_from_bifurcation", "branch_directions",
           "continuation", "critical_along_primary", "imperfection_sensitivity",
           "post_buckling", "post_buckling_branch", "special_point_errors", "trace_branch",
           "xi"]
