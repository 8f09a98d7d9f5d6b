"""The model types: keyword-only construction, and the one support table against every method.

Each support kind's entry in :data:`rodstab.model.SUPPORT_KINDS` says what it holds; these
tests check that the methods do exactly that -- independently of the table where possible
(frame vectors computed here from the end angle, closed-form critical loads).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from rodstab.errors import RodstabInputError
from rodstab.io import design, vary
from rodstab.linear.assembly import discretise as linear_discretise
from rodstab.linear.assembly import rigid_modes_left
from rodstab.linear.solve import linear_stability
from rodstab.model import (
    FULL_SYSTEM,
    LINEAR,
    NONLINEAR,
    ROTATION_AXES,
    SUPPORT_KINDS,
    SUPPORTS,
    Assembly,
    Segment,
    SupportKind,
    kinds_of,
)
from rodstab.nonlinear.discrete import discretise as nonlinear_discretise
from rodstab.nonlinear.parameters import EndRotation
from rodstab.transfer import full_system_critical, straight_assembly_matrix

B1, B2, L = 1.3, 0.7, 1.2
ANGLE = 0.7  # a held tangent along no lab axis: the support rows must use the end's own frame


def rod(start: str | None, end: str | None, *, kn: float = 0.0, angle: float = ANGLE,
        rotation: tuple[float, float, float] | None = None) -> Assembly:
    """Straight rod of length ``L`` at ``angle`` with the given support kinds at its ends."""
    s = Segment(name="a", length=L, curvature=0.0, natural_curvature=kn, B1=B1, B2=B2, B3=1.0,
                angle=angle)
    sup = tuple(("a", e, k) for e, k in (("start", start), ("end", end)) if k is not None)
    rot = () if rotation is None else (("a", "end", rotation),)
    return Assembly(segments=(s,), supports=sup, end_rotations=rot, reference_load=0.0)


def lam(a: Assembly, mu: float) -> float:
    """The paper's ``lam = B3 kappa_n L / sqrt(B1 B2)`` of the rod at load factor ``mu``."""
    return mu * L / math.sqrt(B1 * B2)


# ---- keyword-only model types


def test_positional_segment_raises_type_error():
    with pytest.raises(TypeError):
        Segment("a", 1.0, 0.0, 0.0, 1.0, 1.0, 1.0)


def test_positional_assembly_raises_type_error():
    s = Segment(name="a", length=1.0, curvature=0.0, natural_curvature=0.0, B1=1.0, B2=1.0,
                B3=1.0)
    with pytest.raises(TypeError):
        Assembly((s,))


def test_support_kind_is_keyword_only_and_checks_its_axes():
    with pytest.raises(TypeError):
        SupportKind("x", True, frozenset(), False, frozenset())
    with pytest.raises(ValueError, match="twist"):
        SupportKind(name="x", holds_deflection=True, held_rotations=frozenset({"twist"}),
                    slides_along_tangent=False, methods=frozenset())


# ---- the table itself


def test_one_table_of_support_kinds_and_rotation_axes():
    assert SUPPORTS == ("clamped", "sliding-clamp", "fork", "pinned", "free")
    assert SUPPORTS == tuple(SUPPORT_KINDS)
    assert all(SUPPORT_KINDS[n].name == n for n in SUPPORTS)
    assert ROTATION_AXES == ("normal", "tangent", "binormal")
    assert vary.ROTATION_AXES is ROTATION_AXES  # --vary support.<i>.rotation.<axis> reads them
    assert kinds_of(LINEAR) == SUPPORTS
    assert kinds_of(NONLINEAR) == ("clamped", "sliding-clamp", "free")
    assert kinds_of(FULL_SYSTEM) == ("clamped", "sliding-clamp", "free")
    # Only a kind holding the whole frame takes an imposed end rotation.
    assert [n for n in SUPPORTS if SUPPORT_KINDS[n].accepts_end_rotation] == \
        ["clamped", "sliding-clamp"]


@pytest.mark.parametrize("name", SUPPORTS)
def test_nonlinear_and_full_system_list_only_kinds_they_can_express(name):
    """The nonlinear rod and the full system hold a joint wholly (clamp, with or without the
    slide) or not at all: a kind holding only part of it must not list them."""
    k = SUPPORT_KINDS[name]
    whole = k.holds_deflection and k.holds_all_rotations
    nothing = not k.holds_deflection and not k.held_rotations
    for method in (NONLINEAR, FULL_SYSTEM):
        assert method not in k.methods or whole or nothing, method


# ---- the linear engine against the table


def _expected_held_rows(name: str, angle: float) -> np.ndarray:
    """Held combinations of the joint unknowns ``(w, theta_x, theta_y)``, from the table and
    the end frame computed here (normal n = t x e3, tangent t)."""
    k = SUPPORT_KINDS[name]
    t = np.array([math.cos(angle), math.sin(angle)])
    n = np.array([t[1], -t[0]])
    rows = [[1.0, 0.0, 0.0]] if k.holds_deflection else []
    rows += [[0.0, *n]] if "normal" in k.held_rotations else []
    rows += [[0.0, *t]] if "tangent" in k.held_rotations else []
    return np.array(rows).reshape(-1, 3)


@pytest.mark.parametrize("angle", [0.0, ANGLE, 2.5])
@pytest.mark.parametrize("name", SUPPORTS)
def test_linear_engine_holds_what_the_table_says(name, angle):
    """The unknowns the FE basis ``Z`` allows at the supported joint are exactly those the
    table leaves free, in the end's own frame (the support sits on joint 1; the rigid-motion
    gauge acts on joint 0)."""
    d = linear_discretise(rod(None, name, angle=angle), 4)
    assert d.joints[1] == (("a", "end"),)
    Zj = d.Z[3:6].toarray()
    allowed = Zj[:, np.linalg.norm(Zj, axis=0) > 0]
    held = _expected_held_rows(name, angle)
    assert np.linalg.matrix_rank(allowed) == 3 - held.shape[0]
    if held.size and allowed.size:
        assert np.abs(held @ allowed).max() < 1e-12


@pytest.mark.parametrize("name", SUPPORTS)
def test_linear_rigid_modes_left_by_one_support(name):
    """A single support leaves 3 minus the held out-of-plane motions (w, rotation about n,
    about t) free; it holds all of them exactly when the table says so."""
    a = rod(None, name)
    left = rigid_modes_left(a, a.joints()).shape[1]
    assert left == 3 - _expected_held_rows(name, ANGLE).shape[0]
    assert (left == 0) == SUPPORT_KINDS[name].holds_rigid_motions


@pytest.mark.parametrize("start, end, expected, source", [
    ("clamped", "clamped", 2 * math.pi, "eq. (3.9): L kappa_n = 2 pi sqrt(b1 b2)"),
    ("sliding-clamp", "clamped", 2 * math.pi, "the linear P2 does not see the slide"),
    ("sliding-clamp", "sliding-clamp", 2 * math.pi, "the linear P2 does not see the slide"),
    ("fork", "fork", math.pi, "lateral-torsional buckling, uniform moment, fork supports"),
    ("pinned", "pinned", math.pi, "twist free at both ends: omega' = m w'/B2, pinned column"),
    ("clamped", "fork", 4.493409457909064, "clamped-pinned column: tan x = x"),
    ("clamped", "pinned", 4.493409457909064, "clamped-pinned column: tan x = x"),
    ("fork", "pinned", math.pi, "pinned column"),
])
def test_straight_rod_critical_load_for_each_support(start, end, expected, source):
    """Straight rod held straight, ends held by the named kinds, in a rotated frame:
    lam_c = B3 kappa_n L / sqrt(B1 B2) in closed form. The energy density of P2 for k = 0 is
    B1 w''^2 + B2 omega'^2 + 2 mu B3 kappa_n w' omega'; with w = 0 at both ends eliminating
    omega gives the Euler column B1 w'''' + (m^2 / B2) w'' = 0 with the ends' slope conditions
    (a fork holding the normal instead of the tangent would give 2 pi)."""
    r = linear_stability(rod(start, end, kn=1.0), 32)
    assert lam(rod(start, end, kn=1.0), r.load_factor_critical) == \
        pytest.approx(expected, rel=1e-5), source


# ---- the nonlinear rod against the table


@pytest.mark.parametrize("name", SUPPORTS)
def test_nonlinear_rod_holds_what_the_table_says(name):
    """At the end joint (node 1, joint 1) the discrete rod holds the position components and
    joint rotations the table says; kinds it does not implement raise naming its kinds."""
    a = rod("clamped", name, angle=0.0)  # a sliding clamp needs a tangent along x or y
    k = SUPPORT_KINDS[name]
    if NONLINEAR not in k.methods:
        with pytest.raises(RodstabInputError, match="nonlinear model supports"):
            nonlinear_discretise(a, 4)
        return
    r = nonlinear_discretise(a, 4)
    assert np.allclose(r.x[1], [L, 0.0, 0.0])
    free = set(r.free_dofs().tolist())
    pos_held = [int(d) not in free for d in r.node_dofs(1)]
    rot_held = [int(d) not in free for d in r.joint_dofs(1)]
    # Position: x (the tangent) held unless the support slides; y and z held with w.
    assert pos_held == [k.holds_deflection and not k.slides_along_tangent,
                        k.holds_deflection, k.holds_deflection]
    assert rot_held == [axis in k.held_rotations for axis in ROTATION_AXES]


# ---- the full system of straight segments against the table


@pytest.mark.parametrize("name", SUPPORTS)
def test_full_system_takes_the_kinds_the_table_lists(name):
    # A free end must carry no held moment: natural curvature 0 there.
    a = rod("clamped", name, kn=0.0 if name == "free" else 1.0)
    if FULL_SYSTEM not in SUPPORT_KINDS[name].methods:
        with pytest.raises(RodstabInputError, match="supports only clamped or free"):
            straight_assembly_matrix(a, 1.0)
        return
    A = straight_assembly_matrix(a, 1.0)
    assert A.shape == (6, 6)


@pytest.mark.parametrize("end", ["clamped", "sliding-clamp"])
def test_full_system_clamps_give_eq_3_9(end):
    """Eq. (3.9), lam_c = 2 pi, by the exact general solutions (no discretisation)."""
    a = rod("clamped", end, kn=1.0)
    got = full_system_critical(a, math.sqrt(B1 * B2) / L, known_nullity=0, lambda_max=8.0)
    assert got.lambda_c == pytest.approx(2 * math.pi, rel=1e-8)


# ---- imposed end rotations


@pytest.mark.parametrize("name", SUPPORTS)
def test_end_rotation_only_where_the_table_accepts_it(name):
    if SUPPORT_KINDS[name].accepts_end_rotation:
        a = rod("clamped", name, rotation=(0.0, 0.1, 0.0))
        assert EndRotation(a, 1, "tangent").key == "support.1.rotation.tangent"
        return
    with pytest.raises(RodstabInputError, match="needs a clamped or sliding-clamp"):
        rod("clamped", name, rotation=(0.0, 0.1, 0.0))
    with pytest.raises(RodstabInputError, match="only a clamped or sliding-clamp"):
        EndRotation(rod("clamped", name), 1, "tangent")


def test_design_file_support_type_is_looked_up_in_the_table():
    data = {"segment": [{"name": "a", "length": 1.0}],
            "support": [{"end": "a.start", "type": "fork"}, {"end": "a.end", "type": "hinge"}]}
    with pytest.raises(RodstabInputError, match=r"support\[1\]\.type .*'hinge'"):
        design.parse_design(data)
    data["support"][1]["type"] = "pinned"
    assert design.parse_design(data).assembly.supports[1] == ("a", "end", "pinned")
    del data["support"][1]["type"]
    assert design.parse_design(data).assembly.supports[1] == ("a", "end", "clamped")


def test_free_support_does_not_excuse_an_unbalanced_joint():
    """A free end of a rod with natural curvature held straight carries the unbalanced held
    moment B3 kappa_n: it is rejected without a support entry, and a 'free' entry holds
    nothing, so it must be rejected as well."""
    with pytest.raises(RodstabInputError, match="moment equilibrium"):
        rod("clamped", None, kn=1.0)
    with pytest.raises(RodstabInputError, match="moment equilibrium"):
        rod("clamped", "free", kn=1.0)


def test_a_weld_of_an_end_to_itself_is_refused_naming_the_end():
    """Issue 10: ends = ["rod.end", "rod.end"] was accepted as a joint of one end."""
    s = Segment(name="a", length=1.0, curvature=0.0, natural_curvature=0.0, B1=1.0, B2=0.75,
                B3=1.0)
    with pytest.raises(RodstabInputError, match=r"joins an end to itself: \['a.end'\]"):
        Assembly(segments=(s,), welds=((("a", "end"), ("a", "end")),))


def test_an_unknown_segment_is_named_with_the_known_ones():
    s = Segment(name="a", length=1.0, curvature=0.0, natural_curvature=0.0, B1=1.0, B2=0.75,
                B3=1.0)
    a = Assembly(segments=(s,))
    with pytest.raises(RodstabInputError, match=r"unknown segment 'nope'; the segments are a"):
        a.segment("nope")
