"""Equilibria and Hessian stability of discrete rods: the names of the four modules below.

Split in issue 20 by idea (each module under 800 lines); every public name that lived here is
imported here too, so ``from rodstab.nonlinear.solve import newton`` keeps working:

* :mod:`rodstab.nonlinear.stability` -- the lowest eigenvalues of the Jacobi-scaled free
  Hessian (absolute and Kirchhoff coordinates), their zero tolerance, the sliding mode;
* :mod:`rodstab.nonlinear.newton` -- Newton with a Levenberg-Marquardt safeguard, relaxation to
  a stable state, the residual tolerance;
* :mod:`rodstab.nonlinear.equilibrium` -- the equilibrium of a design at one load and its
  verdict;
* :mod:`rodstab.nonlinear.critical` -- the critical load factor of a held state, on one mesh
  and converged in the mesh.

New code imports from those modules. A test that replaces a function (``monkeypatch``) must
replace it where it is used, in the module that defines or imports it, not here.
"""

from __future__ import annotations

from .critical import (
    ASYMPTOTIC_RATIO as ASYMPTOTIC_RATIO,
)
from .critical import (
    CONVERGED_MAX_ELEMENTS as CONVERGED_MAX_ELEMENTS,
)
from .critical import (
    CONVERGED_RTOL as CONVERGED_RTOL,
)
from .critical import (
    COUPLING_TOL as COUPLING_TOL,
)
from .critical import (
    HELD_RTOL as HELD_RTOL,
)
from .critical import (
    MIN_SEGMENT_ELEMENTS as MIN_SEGMENT_ELEMENTS,
)
from .critical import (
    RELAX_ITER as RELAX_ITER,
)
from .critical import (
    RELAX_MAX_SHIFT as RELAX_MAX_SHIFT,
)
from .critical import (
    RELAX_REFINE_RATIO as RELAX_REFINE_RATIO,
)
from .critical import (
    RELAX_STALL_RTOL as RELAX_STALL_RTOL,
)
from .critical import (
    RELAX_XTOL as RELAX_XTOL,
)
from .critical import (
    TWO_MESH_MARGIN as TWO_MESH_MARGIN,
)
from .critical import (
    ConvergedCritical as ConvergedCritical,
)
from .critical import (
    NonlinearCritical as NonlinearCritical,
)
from .critical import (
    converged_critical_load_factor as converged_critical_load_factor,
)
from .critical import (
    critical_load_factor as critical_load_factor,
)
from .critical import (
    relaxation_shift as relaxation_shift,
)
from .critical import (
    uniform_elements as uniform_elements,
)
from .equilibrium import (
    RESOLVE_HK as RESOLVE_HK,
)
from .equilibrium import (
    STRAIN_WARN as STRAIN_WARN,
)
from .equilibrium import (
    Equilibrium as Equilibrium,
)
from .equilibrium import (
    equilibrium as equilibrium,
)
from .equilibrium import (
    max_strain as max_strain,
)
from .equilibrium import (
    resolving_elements as resolving_elements,
)
from .newton import (
    ALIGN_SHEAR as ALIGN_SHEAR,
)
from .newton import (
    LM_TRIES as LM_TRIES,
)
from .newton import (
    NEWTON_MAX_ITER as NEWTON_MAX_ITER,
)
from .newton import (
    NEWTON_ROUNDOFF as NEWTON_ROUNDOFF,
)
from .newton import (
    NEWTON_RTOL as NEWTON_RTOL,
)
from .newton import (
    NEWTON_RTOL_BEND as NEWTON_RTOL_BEND,
)
from .newton import (
    RELAX_MAX_ITER as RELAX_MAX_ITER,
)
from .newton import (
    ROTATION_STEP as ROTATION_STEP,
)
from .newton import (
    lm_step as lm_step,
)
from .newton import (
    newton as newton,
)
from .newton import (
    relax as relax,
)
from .newton import (
    residual_tolerance as residual_tolerance,
)
from .newton import (
    settle as settle,
)
from .stability import (
    KIRCHHOFF_MARGIN as KIRCHHOFF_MARGIN,
)
from .stability import (
    KIRCHHOFF_POLISH_ITER as KIRCHHOFF_POLISH_ITER,
)
from .stability import (
    KIRCHHOFF_POLISH_STEP as KIRCHHOFF_POLISH_STEP,
)
from .stability import (
    KIRCHHOFF_ZERO_EIG as KIRCHHOFF_ZERO_EIG,
)
from .stability import (
    SLIDING_OVERLAP as SLIDING_OVERLAP,
)
from .stability import (
    SLIDING_RATIO as SLIDING_RATIO,
)
from .stability import (
    ZERO_EIG as ZERO_EIG,
)
from .stability import (
    ZERO_EIG_DISPLACEMENT as ZERO_EIG_DISPLACEMENT,
)
from .stability import (
    ZERO_EIG_ROUNDOFF as ZERO_EIG_ROUNDOFF,
)
from .stability import (
    kirchhoff_eigenvalues as kirchhoff_eigenvalues,
)
from .stability import (
    kirchhoff_modes as kirchhoff_modes,
)
from .stability import (
    kirchhoff_polish as kirchhoff_polish,
)
from .stability import (
    kirchhoff_zero_tol as kirchhoff_zero_tol,
)
from .stability import (
    lowest_eigenvalues as lowest_eigenvalues,
)
from .stability import (
    lowest_modes as lowest_modes,
)
from .stability import (
    sliding_mode as sliding_mode,
)
from .stability import (
    soft_eigenvalue_floor as soft_eigenvalue_floor,
)
from .stability import (
    stability_eigenvalues as stability_eigenvalues,
)
from .stability import (
    stiffness_ratio as stiffness_ratio,
)
from .stability import (
    uses_kirchhoff as uses_kirchhoff,
)
from .stability import (
    vee_log as vee_log,
)
from .stability import (
    zero_eigenvalue_tol as zero_eigenvalue_tol,
)
