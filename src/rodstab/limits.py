"""Resource limits: the size of every run estimated from its inputs before anything is allocated.

A run that would exceed a limit is refused with a :class:`~rodstab.errors.RodstabInputError`
(exit status 2) naming the option that set the size, the estimate, the limit and the option
that raises it; nothing is allocated first. The estimates are exact counts of unknowns (tested
against the discretisations, tests/test_limits.py) and a memory bound from them.

Limits (defaults; the CLI raises them with ``--max-dof``, ``--max-steps``, ``--max-memory``):

* :data:`MAX_DOF` unknowns of one linear (FE of P2) solve, :data:`MAX_DOF_NONLINEAR` of one
  nonlinear (discrete rod) state;
* :data:`MAX_STEPS` steps of a continuation, points of a sweep, or Fourier modes of an
  analytic ring check (each a separate solve);
* :data:`MAX_MEMORY` bytes of the estimated peak memory of one solve.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Iterable

from .errors import RodstabInputError

#: Unknowns of one linear solve (a million is the speed target; the sparse factorisation of a
#: banded P2 pencil stays within a few GiB there).
MAX_DOF = 2_000_000
#: Unknowns of one nonlinear state (its Hessian has ~60 entries per row, twice for the jets).
MAX_DOF_NONLINEAR = 500_000
#: Steps of one continuation, points of one sweep, modes of one analytic ring check.
MAX_STEPS = 100_000
#: Estimated peak memory of one solve, bytes (the machine this was written on has 24 GiB).
MAX_MEMORY = 8 * 2**30
#: Bytes per unknown of a sparse solve: the matrices (K0, K1, Z, the reduced pencil: ~10
#: entries per row, 12 bytes each, several copies), the banded LU, the Lanczos basis (25
#: vectors): a bound ~4x the measured peak (1.0 kB per unknown above the interpreter's
#: baseline, six-ring at 10^3..10^6 unknowns; benchmarks/bench_linear.py).
BYTES_PER_DOF = 4096


@dataclasses.dataclass(frozen=True, kw_only=True)
class Limits:
    """The limits of one run; see the module docstring for the meaning of each."""

    max_dof: int = MAX_DOF
    max_dof_nonlinear: int = MAX_DOF_NONLINEAR
    max_steps: int = MAX_STEPS
    max_memory: int = MAX_MEMORY

    def __post_init__(self) -> None:
        """Every limit a positive integer."""
        for f in dataclasses.fields(self):
            v = getattr(self, f.name)
            if isinstance(v, bool) or not isinstance(v, int) or v <= 0:
                raise RodstabInputError(f"--{f.name.replace('_', '-')} must be a positive "
                                        f"integer, got {v!r}")


DEFAULT = Limits()


def linear_dof(elements: Iterable[int], n_joints: int) -> int:
    """Unknowns of the linear engine before constraints: ``3 J + sum(4 n - 2)``.

    Per segment of ``n`` elements: ``(beta, omega)`` at ``n + 1`` nodes and at ``n`` mid-nodes,
    less the two end nodes' two, which are the joint's rotation (``3 J`` with the joint ``w``).
    """
    return 3 * int(n_joints) + sum(4 * int(n) - 2 for n in elements)


def nonlinear_dof(elements: Iterable[int], n_joints: int) -> int:
    """Unknowns of the discrete rod: ``3 (2 sum n - S + 2 J)`` for ``S`` segments.

    Node positions (``sum (n - 1)`` interior nodes and one per joint) and a rotation per edge
    (``sum n``) and per joint, three each.
    """
    ns = [int(n) for n in elements]
    return 3 * (2 * sum(ns) - len(ns) + 2 * int(n_joints))


def linear_memory(elements: Iterable[int], n_joints: int) -> int:
    """Estimated peak bytes of one linear solve: ``BYTES_PER_DOF`` per unknown.

    The assembly is sparse throughout (element matrices scattered into sparse local matrices),
    so memory grows linearly with the unknowns.
    """
    return BYTES_PER_DOF * linear_dof(elements, n_joints)


def _gib(n: float) -> str:
    return f"{n / 2**30:.3g} GiB"


def require_linear(elements: Iterable[int], n_joints: int, cause: str,
                   limits: Limits = DEFAULT) -> int:
    """Return the linear engine's unknown count, or refuse a run past the limits.

    ``cause`` names the input that set the size (e.g. ``"--elements 100000000"``) for the
    message. Raises :class:`RodstabInputError` past ``max_dof`` or ``max_memory``.
    """
    ns = [int(n) for n in elements]
    dof = linear_dof(ns, n_joints)
    if dof > limits.max_dof:
        raise RodstabInputError(
            f"{cause}: the linear solve would have {dof:.4g} unknowns, above the limit of "
            f"{limits.max_dof:,} (raise it with --max-dof)")
    mem = linear_memory(ns, n_joints)
    if mem > limits.max_memory:
        raise RodstabInputError(
            f"{cause}: the linear solve would need about {_gib(mem)} of memory, above the "
            f"limit of {_gib(limits.max_memory)} (raise it with --max-memory)")
    return dof


def require_linear_uniform(elements: int, n_segments: int, n_joints: int, cause: str,
                           limits: Limits = DEFAULT) -> int:
    """:func:`require_linear` for ``n_segments`` segments of ``elements`` each, in closed form.

    Nothing of the size of ``n_segments`` is allocated (``folded-ring --segments 1e12`` must be
    refused, not build a list of 1e12 element counts first).

    Parameters
    ----------
    elements : int
        Elements per segment.
    n_segments : int
        Number of segments.
    n_joints : int
        Number of joints.
    cause : str
        The input that set the size, for the message.
    limits : Limits
        The limits.

    Returns
    -------
    int
        The unknown count.
    """
    big = int(n_segments) > 1000
    if not big:
        return require_linear([int(elements)] * int(n_segments), n_joints, cause, limits)
    # The same count and message as require_linear, without the list.
    dof = 3 * int(n_joints) + int(n_segments) * (4 * int(elements) - 3)
    if dof > limits.max_dof:
        raise RodstabInputError(
            f"{cause}: the linear solve would have {dof:.4g} unknowns, above the limit of "
            f"{limits.max_dof:,} (raise it with --max-dof)")
    if BYTES_PER_DOF * dof > limits.max_memory:
        raise RodstabInputError(
            f"{cause}: the linear solve would need about {_gib(BYTES_PER_DOF * dof)} of memory, "
            f"above the limit of {_gib(limits.max_memory)} (raise it with --max-memory)")
    return dof


def require_nonlinear(elements: Iterable[int], n_joints: int, cause: str,
                      limits: Limits = DEFAULT, *, copies: int = 1) -> int:
    """Return the discrete rod's unknown count, or refuse a run past ``max_dof_nonlinear``.

    ``copies``: states of the model solved together (the images of a string, relaxed as one
    band): the limit is on their total, so the most copies allowed is derived from it
    (``max_dof_nonlinear`` over one state's unknowns), named in the message. Nothing of the
    size of ``copies`` is allocated.
    """
    one = nonlinear_dof(elements, n_joints)
    dof = int(copies) * one
    if dof > limits.max_dof_nonlinear:
        what = ("the nonlinear model would have" if copies == 1 else
                f"{int(copies):,} states of the nonlinear model ({one:,} unknowns each; at most "
                f"{limits.max_dof_nonlinear // max(one, 1):,} fit) would have")
        raise RodstabInputError(
            f"{cause}: {what} {dof:.4g} unknowns, above the limit of "
            f"{limits.max_dof_nonlinear:,} (raise it with --max-dof)")
    return dof


def require_steps(n: int, cause: str, what: str = "steps", limits: Limits = DEFAULT) -> int:
    """Return ``n``, or refuse a run of more than ``max_steps`` separate solves."""
    if n > limits.max_steps:
        raise RodstabInputError(
            f"{cause}: {n:.4g} {what}, above the limit of {limits.max_steps:,} "
            "(raise it with --max-steps)")
    return int(n)


# Defaults and accepted ranges of a design's runs (named by rodstab.io.design; here so that the
# command line reads them without importing the design module).

#: Accepted segment lengths and stiffnesses B3, in the file's own (consistent) units: wide
#: enough for any unit system, narrow enough that the FE matrices (length^-3 x stiffness) and
#: the held-state geometry stay far from overflow and underflow.
LENGTH_RANGE = (1e-9, 1e9)
STIFFNESS_RANGE = (1e-30, 1e30)
#: Default N of ``--vary KEY=START:STOP[:N]``: values of a sweep, steps of a continuation.
SWEEP_DEFAULT_N = 9
CONTINUE_DEFAULT_N = 40
#: Fewest elements per segment of the nonlinear rod (``rodstab equilibrium``): a design's
#: ``[analysis] elements`` is chosen for the linear engine (FE, fourth order), the
#: discrete rod converges at second order and needs at least this many.
NONLINEAR_MIN_ELEMENTS = 16
#: Default elements per segment of a continuation (``rodstab continue``).
CONTINUATION_ELEMENTS = 16
