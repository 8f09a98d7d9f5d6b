"""Continuation parameters of the discrete rod: how a design value enters the energy.

A parameter ``p`` is anything the equilibrium equations ``g(q, p) = 0`` depend on smoothly. The
continuation methods (:mod:`.continuation`) need three things from it: read ``p``, set ``p`` on
a state, and ``dg/dp`` exactly (the bordered Newton matrices use it; an approximate column would
cost the corrector its quadratic convergence, never its accuracy, because the residual is exact).

* :class:`LoadFactor` ``mu``: scales every natural curvature and natural twist; the energy is
  quadratic in ``mu`` with ``g`` affine, so ``dg/dmu = g(mu + 1) - g(mu)`` exactly.
* :class:`SegmentValue` ``segment.<name>.natural_curvature`` / ``.natural_twist``: the natural
  shape of one segment (at load factor 1). ``g`` is affine in it as well (the held geometry and
  stiffnesses do not change), so the same exact difference applies; the rod's natural
  curvatures are rebuilt by :func:`.discretise` for the new value, which keeps the held state's
  moment balance exact (:func:`.discrete._balanced_link_curvatures`).
* :class:`EndRotation` ``support.<i>.rotation.<axis>``: one component ``r_c`` of the rotation
  vector imposed on a clamped end (its frame is ``F = F_held exp(hat r)``). Then
  ``dg/dr_c = H[:, joint] J_r(r) e_c`` exactly, with ``J_r`` the right Jacobian of SO(3) and
  ``H`` the full Hessian (which includes the clamped joint's rotation unknowns).
"""

from __future__ import annotations

import dataclasses
from typing import Any

import numpy as np

from ..errors import RodstabInputError
from ..model import ROTATION_AXES, SUPPORT_KINDS, Assembly
from .discrete import DiscreteRod, discretise
from .jets import hat

#: Keys of one segment whose values enter the discrete energy affinely.
SEGMENT_KEYS = ("natural_curvature", "natural_twist")


class LoadFactor:
    """The load factor ``mu`` (natural curvatures and twists are ``mu`` times the design's)."""

    key = "load_factor"

    def get(self, rod: DiscreteRod) -> float:
        """Return ``mu`` of ``rod``."""
        return float(rod.load_factor)

    def set(self, rod: DiscreteRod, value: float) -> None:
        """Set ``mu`` of ``rod`` to ``value``."""
        rod.load_factor = float(value)

    def dgrad(self, rod: DiscreteRod) -> np.ndarray:
        """``dg/dmu`` (all unknowns), exact: ``g`` is affine in ``mu``."""
        mu = rod.load_factor
        g0 = rod.energy_terms()[1]
        rod.load_factor = mu + 1.0
        g1 = rod.energy_terms()[1]
        rod.load_factor = mu
        return g1 - g0


@dataclasses.dataclass
class SegmentValue:
    """``segment.<name>.natural_curvature`` or ``.natural_twist`` of one segment."""

    assembly: Assembly
    name: str
    attr: str
    elements_per_segment: int
    _cache: dict = dataclasses.field(default_factory=dict)

    def __post_init__(self) -> None:
        if self.attr not in SEGMENT_KEYS:
            raise RodstabInputError(
                f"segment.{self.name}.{self.attr} cannot be continued: a continuation parameter "
                f"of a segment must be one of {SEGMENT_KEYS} (the held geometry and stiffnesses "
                "define the discretisation; vary them with `rodstab sweep`)")
        self.assembly.segment(self.name)

    @property
    def key(self) -> str:
        """Design key of the parameter, ``segment.<name>.<attr>``."""
        return f"segment.{self.name}.{self.attr}"

    def _natural(self, value: float) -> tuple:
        if value not in self._cache:
            change: dict[str, Any] = {self.attr: float(value)}
            segs = tuple(dataclasses.replace(s, **change)
                         if s.name == self.name else s for s in self.assembly.segments)
            a = dataclasses.replace(self.assembly, segments=segs)  # validated again
            r = discretise(a, self.elements_per_segment)
            if len(self._cache) > 8:
                self._cache.clear()  # keep memory flat along long paths
            self._cache[value] = (r.edge_kn, r.edge_tw, r.k0_links, value)
        return self._cache[value]

    def get(self, rod: DiscreteRod) -> float:
        """Return the segment's value on ``rod`` (the design's until it was set)."""
        return float(rod.param_values.get(
            self.key, getattr(self.assembly.segment(self.name), self.attr)))

    def set(self, rod: DiscreteRod, value: float) -> None:
        """Set the segment's value on ``rod`` to ``value`` (natural curvatures rebuilt)."""
        # Incremental (exact: everything is affine in the value), so that changes made to the
        # rod's natural shape elsewhere (an imperfection) are kept.
        new, old = self._natural(float(value)), self._natural(self.get(rod))
        rod.edge_kn = rod.edge_kn + (new[0] - old[0])
        if new[1] is not None or old[1] is not None:
            z = np.zeros(len(rod.edge_kn))
            base = rod.edge_tw if rod.edge_tw is not None else z
            rod.edge_tw = base + ((new[1] if new[1] is not None else z)
                                  - (old[1] if old[1] is not None else z))
        assert rod.k0_links is not None  # set by discretise
        rod.k0_links = tuple(c + (n_ - o)
                             for c, n_, o in zip(rod.k0_links, new[2], old[2], strict=True))
        rod.param_values[self.key] = float(value)

    def dgrad(self, rod: DiscreteRod) -> np.ndarray:
        """``dg/dp`` (all unknowns), exact: ``g`` is affine in a natural curvature or twist."""
        p = self.get(rod)
        g0 = rod.energy_terms()[1]
        self.set(rod, p + 1.0)
        g1 = rod.energy_terms()[1]
        self.set(rod, p)
        return g1 - g0


def _right_jacobian(r: np.ndarray) -> np.ndarray:
    """``J_r(r)``: ``exp(hat(r + dr)) = exp(hat r) exp(hat(J_r dr)) + O(dr^2)``."""
    th = float(np.linalg.norm(r))
    K = hat(r)
    if th < 1e-6:
        return np.eye(3) - 0.5 * K + K @ K / 6.0
    return (np.eye(3) - (1 - np.cos(th)) / th**2 * K + (th - np.sin(th)) / th**3 * (K @ K))


@dataclasses.dataclass
class EndRotation:
    """Component ``axis`` of the rotation vector imposed on a clamped end (radians)."""

    assembly: Assembly
    support: int
    axis: str

    def __post_init__(self) -> None:
        sups = self.assembly.supports
        if not 0 <= self.support < len(sups):
            raise RodstabInputError(f"support index {self.support!r} is not one of "
                                    f"0..{len(sups) - 1}")
        name, end, kind = sups[self.support]
        if not SUPPORT_KINDS[kind].accepts_end_rotation:
            turnable = " or ".join(k.name for k in SUPPORT_KINDS.values()
                                   if k.accepts_end_rotation)
            raise RodstabInputError(f"support {self.support} ({name}.{end}) is {kind!r}: only a "
                                    f"{turnable} end can be turned")
        if self.axis not in ROTATION_AXES:
            raise RodstabInputError(f"rotation axis {self.axis!r} is not one of {ROTATION_AXES}")
        self._c = ROTATION_AXES.index(self.axis)

    @property
    def key(self) -> str:
        """Design key of the parameter, ``support.<i>.rotation.<axis>``."""
        return f"support.{self.support}.rotation.{self.axis}"

    def _joint_Q(self, rod: DiscreteRod) -> tuple[int, np.ndarray]:
        name, end, _ = self.assembly.supports[self.support]
        i = [s.name for s in self.assembly.segments].index(name)
        e, j, Q, _ = rod.end_links[2 * i + (end == "end")]
        return j, Q

    def _r(self, rod: DiscreteRod) -> tuple[int, np.ndarray, np.ndarray]:
        j, Q = self._joint_Q(rod)
        return j, Q, Q.T @ rod.joint_rotation.get(j, np.zeros(3))

    def get(self, rod: DiscreteRod) -> float:
        """Return the imposed rotation component ``r_c`` of ``rod`` (radians)."""
        return float(self._r(rod)[2][self._c])

    def set(self, rod: DiscreteRod, value: float) -> None:
        """Turn the clamped end of ``rod`` so that ``r_c`` equals ``value`` (radians)."""
        j, Q, r = self._r(rod)
        r = r.copy()
        r[self._c] = float(value)
        rod.rotate_joint(j, Q @ r)

    def dgrad(self, rod: DiscreteRod) -> np.ndarray:
        """``dg/dr_c = H[:, joint] J_r(Q r) Q e_c`` (exact)."""
        j, Q, r = self._r(rod)
        _, _, H = rod.energy_terms()
        direction = _right_jacobian(Q @ r) @ Q[:, self._c]
        return np.asarray(H[:, rod.joint_dofs(j)] @ direction).ravel()


Parameter = LoadFactor | SegmentValue | EndRotation


def parameter(assembly: Assembly, key: str, elements_per_segment: int) -> Parameter:
    """Return the continuation parameter named ``key`` (module docstring).

    Parameters
    ----------
    assembly : Assembly
        The design's assembly.
    key : str
        ``load_factor``, ``segment.<name>.<natural_curvature|natural_twist>`` or
        ``support.<i>.rotation.<normal|tangent|binormal>``.
    elements_per_segment : int
        Elements per segment of the discrete rod (a segment value rebuilds it).

    Returns
    -------
    Parameter
        The parameter.

    Raises
    ------
    RodstabInputError
        Naming ``--vary key KEY``, the part of it that is wrong and the valid forms.
    """
    parts = key.split(".")
    forms = (f"load_factor, segment.<name>.<{'|'.join(SEGMENT_KEYS)}> or "
             f"support.<i>.rotation.<{'|'.join(ROTATION_AXES)}>")
    try:
        if key == "load_factor":
            return LoadFactor()
        if parts[0] == "segment" and len(parts) == 3:
            return SegmentValue(assembly, parts[1], parts[2], elements_per_segment)
        if parts[0] == "support" and len(parts) == 4 and parts[2] == "rotation":
            index = parts[1]
            if not (index.isascii() and index.isdigit()) or len(index) > 9:
                raise RodstabInputError(f"support index {index!r} is not a number "
                                        f"0..{len(assembly.supports) - 1}")
            return EndRotation(assembly, int(index), parts[3])
    except RodstabInputError as exc:
        raise RodstabInputError(f"--vary key {key!r}: {exc}") from None
    raise RodstabInputError(f"--vary key {key!r} cannot be continued; use {forms}")
