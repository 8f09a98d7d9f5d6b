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
* :class:`SegmentLength` ``segment.<name>.length``: the rest lengths of one segment's
  elements (the same material made longer). ``g`` is smooth, not affine, in them: ``dg/dL``
  by a central difference (the bordered corrector keeps its accuracy).
* :class:`EndRotation` ``support.<i>.rotation.<axis>``: one component ``r_c`` of the rotation
  vector imposed on a clamped end (its frame is ``F = F_held exp(hat r)``). Then
  ``dg/dr_c = H[:, joint] J_r(r) e_c`` exactly, with ``J_r`` the right Jacobian of SO(3) and
  ``H`` the full Hessian (which includes the clamped joint's rotation unknowns).
* :class:`WeldRotation` ``welds.<i>,<j>.rotation.<axis>``: equal and opposite rotations
  ``+phi`` and ``-phi`` of welds ``i`` and ``j`` (indices into the assembly's welds) about
  ``axis`` of each weld's reference frame (its frame when the parameter is prepared on a state):
  the ring bent by hand as in the experiments. Both weld frames are held (a constraint, like a
  clamped end); on a free assembly the rigid-motion gauge moves from joint 0 to weld ``i``
  (its position and frame; weld ``j``'s frame is then the one relative rotation imposed), so
  the reactions are a pure couple. ``dg/dphi = H[:, i] e_c - H[:, j] e_c`` exactly (the
  rotation vectors stay along ``e_c``, where the right Jacobian of SO(3) is the identity).
* :class:`WeldMoment` ``weld.<i>.moment.<axis>``: a point moment ``M`` on weld ``i`` (component
  ``axis`` of its reference frame), the work term ``-M . theta`` in the energy with ``theta``
  the exact rotation vector of the weld's frame (:meth:`.DiscreteRod._moment_work`). ``g`` is
  linear in ``M``: ``dg/dM_c = -d theta_c / d phi`` at the weld, exact from the same jets. On a
  free assembly the reaction is carried by the gauge joint 0 (held in position and frame), so
  weld 0 itself cannot be loaded.
* :class:`WeldForce` ``weld.<i>.force.<axis>``: a dead point force ``F`` on weld ``i``'s node,
  along director ``axis`` of the weld's frame when the parameter is prepared (then fixed in
  space), the work term ``-F d . (x - x_ref)``. ``g`` is linear in ``F`` and the Hessian does
  not change: ``dg/dF = -d`` on the node's position unknowns, exact. The reaction is carried by
  the gauge (weld 0 cannot be loaded), as for the moment.

Every parameter has ``prepare(rod)``, called once on the start state of a continuation (it
changes the held unknowns of the weld rotation, and takes the reference frames of a weld
parameter from the state).
"""

from __future__ import annotations

import dataclasses
from typing import Any

import numpy as np

from ..errors import RodstabInputError
from ..model import ROTATION_AXES, SUPPORT_KINDS, Assembly
from .discrete import DiscreteRod, discretise
from .jets import hat, rotation_jet, rotation_vector

#: Keys of one segment whose values enter the discrete energy affinely.
#: ``(E, g, H)`` of :meth:`DiscreteRod.energy_terms` at the current state: a caller that has
#: them passes them to ``dgrad``, which then spends no second evaluation on them.
Terms = tuple[float, np.ndarray, Any]

SEGMENT_KEYS = ("natural_curvature", "natural_twist")


class LoadFactor:
    """The load factor ``mu`` (natural curvatures and twists are ``mu`` times the design's)."""

    key = "load_factor"

    def prepare(self, rod: DiscreteRod) -> None:
        """Nothing to prepare: the load factor needs no held unknowns."""

    def get(self, rod: DiscreteRod) -> float:
        """Return ``mu`` of ``rod``."""
        return float(rod.load_factor)

    def set(self, rod: DiscreteRod, value: float) -> None:
        """Set ``mu`` of ``rod`` to ``value``."""
        rod.load_factor = float(value)

    def dgrad(self, rod: DiscreteRod, terms: Terms | None = None) -> np.ndarray:
        """``dg/dmu`` (all unknowns), exact: ``g`` is affine in ``mu``."""
        mu = rod.load_factor
        g0 = rod.gradient() if terms is None else terms[1]
        rod.load_factor = mu + 1.0
        g1 = rod.gradient()
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

    def prepare(self, rod: DiscreteRod) -> None:
        """Nothing to prepare: a natural shape needs no held unknowns."""

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

    def dgrad(self, rod: DiscreteRod, terms: Terms | None = None) -> np.ndarray:
        """``dg/dp`` (all unknowns), exact: ``g`` is affine in a natural curvature or twist."""
        p = self.get(rod)
        g0 = rod.gradient() if terms is None else terms[1]
        self.set(rod, p + 1.0)
        g1 = rod.gradient()
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

    def prepare(self, rod: DiscreteRod) -> None:
        """Nothing to prepare: the clamped end is held by :func:`.discretise`."""

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

    def dgrad(self, rod: DiscreteRod, terms: Terms | None = None) -> np.ndarray:
        """``dg/dr_c = H[:, joint] J_r(Q r) Q e_c`` (exact)."""
        j, Q, r = self._r(rod)
        _, _, H = rod.energy_terms() if terms is None else terms
        direction = _right_jacobian(Q @ r) @ Q[:, self._c]
        return np.asarray(H[:, rod.joint_dofs(j)] @ direction).ravel()


def _weld_index(assembly: Assembly, text: str) -> int:
    """Parse a weld index ``0..n_welds - 1`` of ``assembly`` (raise naming it otherwise)."""
    n = len(assembly.welds)
    if not (text.isascii() and text.isdigit()) or len(text) > 9 or int(text) >= n:
        raise RodstabInputError(f"weld index {text!r} is not one of 0..{n - 1}"
                                if n else f"weld index {text!r}: the assembly has no welds")
    return int(text)


def weld_joint(assembly: Assembly, rod: DiscreteRod, weld: int) -> tuple[int, int]:
    """Return the joint and its node of weld ``weld`` (index into ``assembly.welds``)."""
    name, end = assembly.welds[weld][0]
    i = [s.name for s in assembly.segments].index(name)
    e, j, _, _ = rod.end_links[2 * i + (end == "end")]
    return int(j), int(rod.edge_nodes[e, 1 if end == "end" else 0])


def _take_reference(rod: DiscreteRod, joints: list[int]) -> None:
    """Make the current frames of ``joints`` their reference frames.

    A new array: copies of the state share the old one.
    """
    assert rod.R_joint_held is not None  # set by discretise
    ref = rod.R_joint_held.copy()
    for j in joints:
        ref[j] = rod.R_joint[j]
        rod.joint_rotation.pop(j, None)
    rod.R_joint_held = ref


@dataclasses.dataclass
class WeldRotation:
    """Equal and opposite rotations ``+phi``, ``-phi`` (radians) of two welds (module doc)."""

    assembly: Assembly
    welds: tuple[int, int]
    axis: str

    def __post_init__(self) -> None:
        if self.welds[0] == self.welds[1]:
            raise RodstabInputError(f"welds {self.welds[0]},{self.welds[1]}: the two welds "
                                    "turned against each other must differ")
        if self.axis not in ROTATION_AXES:
            raise RodstabInputError(f"rotation axis {self.axis!r} is not one of {ROTATION_AXES}")
        self._c = ROTATION_AXES.index(self.axis)

    @property
    def key(self) -> str:
        """Design key of the parameter, ``welds.<i>,<j>.rotation.<axis>``."""
        return f"welds.{self.welds[0]},{self.welds[1]}.rotation.{self.axis}"

    def _joints(self, rod: DiscreteRod) -> tuple[int, int]:
        return (weld_joint(self.assembly, rod, self.welds[0])[0],
                weld_joint(self.assembly, rod, self.welds[1])[0])

    def prepare(self, rod: DiscreteRod) -> None:
        """Hold both welds' frames at their current ones (``phi = 0``), moving a free gauge.

        On a free assembly (held only by the gauge of :func:`.discretise`: joint 0's position
        and frame) the gauge becomes weld ``i``'s position and frame.
        """
        ji, jj = self._joints(rod)
        if not self.assembly.supports:
            rod.fixed_nodes = [weld_joint(self.assembly, rod, self.welds[0])[1]]
            rod.fixed_joints = []
        rod.fixed_joints = sorted(set(rod.fixed_joints) | {ji, jj})
        _take_reference(rod, [ji, jj])
        rod.param_values[self.key] = 0.0

    def get(self, rod: DiscreteRod) -> float:
        """Return ``phi`` (radians): weld ``i``'s rotation component about ``axis``."""
        return float(rod.param_values.get(self.key, 0.0))

    def set(self, rod: DiscreteRod, value: float) -> None:
        """Turn weld ``i`` by ``+value`` and weld ``j`` by ``-value`` about ``axis``."""
        ji, jj = self._joints(rod)
        r = np.zeros(3)
        r[self._c] = float(value)
        rod.rotate_joint(ji, r)
        rod.rotate_joint(jj, -r)
        rod.param_values[self.key] = float(value)

    def dgrad(self, rod: DiscreteRod, terms: Terms | None = None) -> np.ndarray:
        """``dg/dphi = H[:, i] e_c - H[:, j] e_c`` (exact, module docstring)."""
        ji, jj = self._joints(rod)
        _, _, H = rod.energy_terms() if terms is None else terms
        return np.asarray(H[:, rod.joint_dofs(ji)[self._c]].toarray().ravel()
                          - H[:, rod.joint_dofs(jj)[self._c]].toarray().ravel())


@dataclasses.dataclass
class WeldMoment:
    """Component ``axis`` of a point moment on weld ``weld`` (module docstring)."""

    assembly: Assembly
    weld: int
    axis: str

    def __post_init__(self) -> None:
        if self.axis not in ROTATION_AXES:
            raise RodstabInputError(f"moment axis {self.axis!r} is not one of {ROTATION_AXES}")
        self._c = ROTATION_AXES.index(self.axis)

    @property
    def key(self) -> str:
        """Design key of the parameter, ``weld.<i>.moment.<axis>``."""
        return f"weld.{self.weld}.moment.{self.axis}"

    def _joint(self, rod: DiscreteRod) -> int:
        j = weld_joint(self.assembly, rod, self.weld)[0]
        if j in rod.fixed_joints:
            raise RodstabInputError(
                f"weld {self.weld} is held (the rigid-motion gauge of a free assembly is weld "
                "0's joint, or a clamp): a moment on it does no work; load another weld")
        return j

    def prepare(self, rod: DiscreteRod) -> None:
        """Take the weld's current frame as the reference of its rotation ``theta``."""
        j = self._joint(rod)
        if not np.any(rod.joint_moment.get(j, 0.0)):
            _take_reference(rod, [j])

    def get(self, rod: DiscreteRod) -> float:
        """Return the moment component ``M_c`` on the weld."""
        m = rod.joint_moment.get(self._joint(rod))
        return 0.0 if m is None else float(m[self._c])

    def set(self, rod: DiscreteRod, value: float) -> None:
        """Set the moment component ``M_c`` on the weld to ``value``."""
        j = self._joint(rod)
        m = np.array(rod.joint_moment.get(j, np.zeros(3)), float)
        m[self._c] = float(value)
        rod.joint_moment[j] = m

    def dgrad(self, rod: DiscreteRod, terms: Terms | None = None) -> np.ndarray:
        """``dg/dM_c = -d theta_c / d phi`` on the weld's rotation unknowns (exact)."""
        j = self._joint(rod)
        assert rod.R_joint_held is not None  # set by discretise
        P = rotation_jet((rod.R_joint_held[j].T @ rod.R_joint[j])[None], 3, 0, order=1)
        dtheta = rotation_vector(P)[self._c].g
        assert dtheta is not None  # a first-order jet
        out = np.zeros(rod.n_dof)
        out[rod.joint_dofs(j)] = -dtheta[0]
        return out


@dataclasses.dataclass
class WeldForce:
    """Component ``axis`` of a dead point force on weld ``weld``'s node (module docstring)."""

    assembly: Assembly
    weld: int
    axis: str

    def __post_init__(self) -> None:
        if self.axis not in ROTATION_AXES:
            raise RodstabInputError(f"force axis {self.axis!r} is not one of {ROTATION_AXES}")
        self._c = ROTATION_AXES.index(self.axis)

    @property
    def key(self) -> str:
        """Design key of the parameter, ``weld.<i>.force.<axis>``."""
        return f"weld.{self.weld}.force.{self.axis}"

    def _node(self, rod: DiscreteRod) -> int:
        j, node = weld_joint(self.assembly, rod, self.weld)
        if node in rod.fixed_nodes or j in rod.fixed_joints:
            raise RodstabInputError(
                f"weld {self.weld} is held (the rigid-motion gauge of a free assembly is weld "
                "0's joint, or a clamp): a force on it does no work; load another weld")
        return node

    def prepare(self, rod: DiscreteRod) -> None:
        """Fix the force's direction (the weld frame's ``axis`` now) and reference position."""
        node = self._node(rod)
        if (node, self._c) not in rod.node_force:
            direction = rod.R_joint[weld_joint(self.assembly, rod, self.weld)[0]][:, self._c]
            rod.node_force[(node, self._c)] = (0.0, direction.copy(), rod.x[node].copy())

    def get(self, rod: DiscreteRod) -> float:
        """Return the force ``F`` (along the fixed direction)."""
        entry = rod.node_force.get((self._node(rod), self._c))
        return 0.0 if entry is None else float(entry[0])

    def set(self, rod: DiscreteRod, value: float) -> None:
        """Set the force to ``value`` (prepared first if it was not)."""
        self.prepare(rod)
        key = (self._node(rod), self._c)
        _, direction, x_ref = rod.node_force[key]
        rod.node_force[key] = (float(value), direction, x_ref)

    def dgrad(self, rod: DiscreteRod, terms: Terms | None = None) -> np.ndarray:
        """``dg/dF = -d`` on the weld node's position unknowns (exact, module docstring)."""
        self.prepare(rod)
        node = self._node(rod)
        out = np.zeros(rod.n_dof)
        out[rod.node_dofs(node)] = -rod.node_force[(node, self._c)][1]
        return out


@dataclasses.dataclass
class SegmentLength:
    """``segment.<name>.length``: one segment's length, the rest lengths of its elements.

    The same material made longer (its natural curvature per unit length kept, the same
    number of elements): the state that no design holds, a ring with one rod longer
    (:mod:`rodstab.multistable.morph`). The energy is smooth but not affine in the rest
    lengths (bending ``B |k - k0|^2 l / 2`` with the Cayley curvature over ``l``, stretching
    ``K |x_j - x_i - l d|^2 / 2 l``), so ``dg/dL`` is a central difference, step
    :data:`LENGTH_STEP` of the length: O(step^2), ~1e-12 relative (the bordered corrector
    keeps its accuracy, the residual being exact).
    """

    assembly: Assembly
    name: str

    def __post_init__(self) -> None:
        names = [s.name for s in self.assembly.segments]
        if self.name not in names:
            raise RodstabInputError(f"segment {self.name!r} is not in the design; its segments "
                                    f"are {names}")
        self._k = names.index(self.name)

    @property
    def key(self) -> str:
        """Design key of the parameter, ``segment.<name>.length``."""
        return f"segment.{self.name}.length"

    def _edges(self, rod: DiscreteRod) -> slice:
        ne = len(rod.R_edge) // len(self.assembly.segments)
        return slice(self._k * ne, (self._k + 1) * ne)

    def prepare(self, rod: DiscreteRod) -> None:
        """Nothing to prepare: a length needs no held unknowns."""

    def get(self, rod: DiscreteRod) -> float:
        """Return the segment's length on ``rod``: the sum of its elements' rest lengths."""
        return float(rod.rest_length[self._edges(rod)].sum())

    def set(self, rod: DiscreteRod, value: float) -> None:
        """Give the segment's elements the rest length ``value / elements`` (a new array).

        The constraint's cached topology is keyed on the arrays it was built from; the
        state is left as it is, out of equilibrium until solved again.
        """
        if not (np.isfinite(value) and value > 0):
            raise RodstabInputError(f"{self.key} must be a positive length, got {value!r}")
        e = self._edges(rod)
        rest = rod.rest_length.copy()
        rest[e] = float(value) / (e.stop - e.start)
        rod.rest_length = rest
        rod.__dict__.pop("_relabellings", None)  # the ring's symmetries may change with it

    def dgrad(self, rod: DiscreteRod, terms: Terms | None = None) -> np.ndarray:
        """``dg/dL`` (all unknowns) by a central difference (class docstring)."""
        L = self.get(rod)
        h = LENGTH_STEP * L
        self.set(rod, L + h)
        g1 = rod.gradient()
        self.set(rod, L - h)
        g0 = rod.gradient()
        self.set(rod, L)
        return (g1 - g0) / (2 * h)


#: Relative step of :meth:`SegmentLength.dgrad`'s central difference.
LENGTH_STEP = 1e-5


Parameter = (LoadFactor | SegmentValue | SegmentLength | EndRotation | WeldRotation
             | WeldMoment | WeldForce)


def parameter(assembly: Assembly, key: str, elements_per_segment: int) -> Parameter:
    """Return the continuation parameter named ``key`` (module docstring).

    Parameters
    ----------
    assembly : Assembly
        The design's assembly.
    key : str
        ``load_factor``, ``segment.<name>.<natural_curvature|natural_twist|length>`` or
        ``support.<i>.rotation.<normal|tangent|binormal>``,
        ``welds.<i>,<j>.rotation.<normal|tangent|binormal>`` or
        ``weld.<i>.<moment|force>.<normal|tangent|binormal>`` (``i``, ``j``: weld indices).
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
    forms = (f"load_factor, segment.<name>.<{'|'.join(SEGMENT_KEYS)}|length> or "
             f"support.<i>.rotation.<{'|'.join(ROTATION_AXES)}>, "
             f"welds.<i>,<j>.rotation.<{'|'.join(ROTATION_AXES)}> or "
             f"weld.<i>.<moment|force>.<{'|'.join(ROTATION_AXES)}>")
    try:
        if key == "load_factor":
            return LoadFactor()
        if parts[0] == "segment" and len(parts) == 3 and parts[2] == "length":
            return SegmentLength(assembly, parts[1])
        if parts[0] == "segment" and len(parts) == 3:
            return SegmentValue(assembly, parts[1], parts[2], elements_per_segment)
        if parts[0] == "support" and len(parts) == 4 and parts[2] == "rotation":
            index = parts[1]
            if not (index.isascii() and index.isdigit()) or len(index) > 9:
                raise RodstabInputError(f"support index {index!r} is not a number "
                                        f"0..{len(assembly.supports) - 1}")
            return EndRotation(assembly, int(index), parts[3])
        if parts[0] == "welds" and len(parts) == 4 and parts[2] == "rotation":
            pair = parts[1].split(",")
            if len(pair) != 2:
                raise RodstabInputError(f"welds {parts[1]!r} is not two weld indices i,j")
            return WeldRotation(assembly, (_weld_index(assembly, pair[0]),
                                           _weld_index(assembly, pair[1])), parts[3])
        if parts[0] == "weld" and len(parts) == 4 and parts[2] == "moment":
            return WeldMoment(assembly, _weld_index(assembly, parts[1]), parts[3])
        if parts[0] == "weld" and len(parts) == 4 and parts[2] == "force":
            return WeldForce(assembly, _weld_index(assembly, parts[1]), parts[3])
    except RodstabInputError as exc:
        raise RodstabInputError(f"--vary key {key!r}: {exc}") from None
    raise RodstabInputError(f"--vary key {key!r} cannot be continued; use {forms}")
