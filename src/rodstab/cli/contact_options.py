"""The contact options of the commands: one definition of each (parsing only).

``--contact-thickness`` (the contact check of ``transitions`` and ``barrier``, the capsules of
``equilibrium`` and ``continue``) and ``--contact/--no-contact`` with ``--contact-dhat``,
resolved against the design's ``[analysis] contact`` (:class:`ContactChoice`).
"""

from __future__ import annotations

import dataclasses
import functools
import math
from collections.abc import Callable
from typing import Any

import click

from ..errors import RodstabInputError, require_positive
from ..model import CONTACT_DHAT_FRACTION, CONTACT_THICKNESS_RATIO
from .options import given


def contact_thickness_option(help: str) -> Callable[..., Any]:
    """``--contact-thickness H``: the rods' out-of-plane height over the rod length, ``h / L``.

    The contact check of a path (``transitions``, ``barrier``): rods closer than ``h`` touch.
    Default :data:`rodstab.model.CONTACT_THICKNESS_RATIO`; in ``(0, 1]`` as the design key
    ``analysis.contact_thickness``, checked as it is parsed (exit 2 naming the value).
    """

    def check(ctx: click.Context, param: click.Parameter, value: float) -> float:
        h = require_positive("--contact-thickness", value)
        if h > 1.0:
            raise RodstabInputError(f"--contact-thickness must be at most 1 (h / L, a thickness "
                                    f"over the rod length), got {value!r}")
        return h

    return click.option("--contact-thickness", "contact_thickness", type=float,
                        default=CONTACT_THICKNESS_RATIO,
                        show_default=True, callback=check,
                        help=("Out-of-plane section height h over the rod length L, for the "
                              "contact check (rods closer than h touch). " + help).strip())


@dataclasses.dataclass(frozen=True)
class ContactChoice:
    """What the command line says about contact (None: the design's, else the defaults).

    ``on``: ``--contact/--no-contact``; ``thickness``: ``h / L``; ``dhat``: ``dhat / h``.
    """

    on: bool | None
    thickness: float | None
    dhat: float | None

    def resolve(self, design_contact: tuple[float, float] | None) -> tuple[float, float] | None:
        """``(h / L, dhat / h)`` of this run, or None without contact.

        The command line wins over the design's ``[analysis] contact``; a thickness or dhat
        given for a run without contact is refused (exit 2): it would be dropped.
        """
        on = design_contact is not None if self.on is None else self.on
        if not on:
            for name, v in (("--contact-thickness", self.thickness), ("--contact-dhat",
                                                                      self.dhat)):
                if v is not None:
                    raise RodstabInputError(f"{name} is a setting of contact, which is off "
                                            "for this run (--contact, or [analysis] contact "
                                            "= true in the design)")
            return None
        h, c = (design_contact if design_contact is not None
                else (CONTACT_THICKNESS_RATIO, CONTACT_DHAT_FRACTION))
        return (h if self.thickness is None else self.thickness,
                c if self.dhat is None else self.dhat)

    def judged(self, design_contact: tuple[float, float] | None) -> tuple[float, float | None]:
        """``(h / L, dhat / h)`` of a command that judges its paths with or without contact.

        ``h`` always (the path is judged against it; with contact also the capsules'
        diameter); ``dhat`` None when contact is off (``--contact-dhat`` then refused, as by
        :meth:`resolve`).
        """
        on = design_contact is not None if self.on is None else self.on
        if on:
            setting = self.resolve(design_contact)
            assert setting is not None  # contact is on
            return setting
        if self.dhat is not None:
            ContactChoice(False, None, self.dhat).resolve(design_contact)  # refuses it
        h = (self.thickness if self.thickness is not None else
             design_contact[0] if design_contact is not None else CONTACT_THICKNESS_RATIO)
        return h, None


#: ``--contact-dhat``: one definition for :func:`contact_options` and :func:`path_contact_options`.
_DHAT_OPTION = click.option(
    "--contact-dhat", "contact_dhat", type=float, default=CONTACT_DHAT_FRACTION,
    show_default=True,
    help="With contact: the barrier's reach dhat over h, in (0, 1); a result is shown "
         "converged by repeating it at smaller values [default: the design's contact_dhat].")


def _dhat_given(value: float) -> float | None:
    """``--contact-dhat`` if given on the command line (checked: in (0, 1)), else None."""
    if not given("contact_dhat"):
        return None
    c = require_positive("--contact-dhat", value)
    if c >= 1.0:
        raise RodstabInputError(f"--contact-dhat must be below 1 (dhat < h), got {value!r}")
    return c


def path_contact_options(help: str) -> Callable[..., Any]:
    """``--contact/--no-contact``, ``--contact-thickness``, ``--contact-dhat`` of a path command.

    For ``barrier``: ``--contact-thickness`` judges the path with or without contact (``help``
    says how) and is the capsules' diameter with it. Passes ``contact``, a
    :class:`ContactChoice` to resolve with :meth:`ContactChoice.judged`.
    """

    def decorate(f: Callable[..., Any]) -> Callable[..., Any]:
        @click.option("--contact/--no-contact", "with_contact", default=None,
                      help="Rods are capsules that cannot pass through each other while the "
                           "path is computed (a smooth barrier on their gaps, "
                           "rodstab.multistable.string_contact); without it the path is only "
                           "judged. [default: the design's [analysis] contact, else off]")
        @contact_thickness_option(help)
        @_DHAT_OPTION
        @functools.wraps(f)
        def wrapper(with_contact: bool | None, contact_thickness: float, contact_dhat: float,
                    **kwargs: Any) -> Any:
            h = contact_thickness if given("contact_thickness") else None
            return f(contact=ContactChoice(with_contact, h, _dhat_given(contact_dhat)),
                     **kwargs)

        return wrapper

    return decorate


def contact_options(f: Callable[..., Any]) -> Callable[..., Any]:
    """Add ``--contact/--no-contact``, ``--contact-thickness``, ``--contact-dhat``.

    Passes ``contact``, a :class:`ContactChoice` (``resolve`` it with the design's
    ``[analysis] contact``): without either, every number is as without contact.
    """

    @click.option("--contact/--no-contact", "with_contact", default=None,
                  help="Rods are capsules that cannot pass through each other (a smooth "
                       "barrier on their gaps, rodstab.nonlinear.contact); the output adds "
                       "the gaps and contact forces. [default: the design's [analysis] "
                       "contact, else off]")
    @contact_thickness_option("With contact: the capsules' diameter [default: the design's "
                              "contact_thickness].")
    @_DHAT_OPTION
    @functools.wraps(f)
    def wrapper(with_contact: bool | None, contact_thickness: float, contact_dhat: float,
                **kwargs: Any) -> Any:
        h = contact_thickness if given("contact_thickness") else None
        return f(contact=ContactChoice(with_contact, h, _dhat_given(contact_dhat)), **kwargs)

    return wrapper


def layers_option(help: str) -> Callable[..., Any]:
    """``--layers``: the stacked rods' layer order (``analyze``'s cone, ``equilibrium``)."""
    return click.option("--layers", default=None, help=(
        "With contact: the stacked rods' order, NAME=K[,NAME=K...] (layer K along e3, in "
        "spacings). " + help).strip())


def parse_layers(text: str, names: list[str] | tuple[str, ...]) -> dict[str, Any] | str:
    """Read ``--layers``: ``torus``, ``folded``, or ``NAME=K[:...]`` items (commas).

    ``K`` is the layer (height in spacings along ``e3``), ``U:K`` an offset with an in-plane
    part ``U`` (:func:`rodstab.multistable.stacking.stack_layers`), ``U:K:S`` also a shift of
    ``S`` spacings along the rod (:func:`rodstab.multistable.layer_orders.layer_translations`:
    the stacked model of ``transitions`` and ``barrier``). Refuses (exit 2) a malformed item,
    an unknown name or a missing one, naming it.
    """
    text = text.strip()
    if text in ("torus", "folded"):
        return text
    out: dict[str, Any] = {}
    for item in filter(None, (t.strip() for t in text.split(","))):
        name, eq, value = item.partition("=")
        name = name.strip()
        try:
            parts = [float(v) for v in value.split(":")]
        except ValueError:
            parts = []
        if not eq or name not in names or len(parts) not in (1, 2, 3) or name in out:
            raise RodstabInputError(
                f"--layers item {item!r}: expected NAME=K, NAME=U:K or NAME=U:K:S with NAME one "
                f"of {list(names)} (each once), or 'torus' / 'folded'")
        out[name] = parts[0] if len(parts) == 1 else tuple(parts)
    missing = [n for n in names if n not in out]
    if missing:
        raise RodstabInputError(f"--layers gives no layer for {missing}: every segment needs one")
    return out


def stack_from_options(a: Any, touch: tuple[float, float] | None, layers: str | None,
                       laminate: float | None, n: int, load_factor: float
                       ) -> tuple[dict[str, float] | None, float | None, Any]:
    """``--layers`` and ``--laminate`` of equilibrium: the heights, EA and the braid.

    ``(None, None, None)`` without ``--layers``; ``--layers braid``: ``(None, None, braid)``,
    the braided figure-eight built and relaxed with contact (``n`` elements per segment):
    :func:`rodstab.multistable.braid.hold_braid`'s tuple (state, rod, converged, iterations,
    residual).
    """
    from ..nonlinear.equilibrium import stacked_layers

    if layers is None:
        if laminate is not None:
            raise RodstabInputError("--laminate is a setting of --layers (a stacked state)")
        return None, None, None
    if touch is None:
        raise RodstabInputError("--layers is a setting of contact, which is off for this run "
                                "(--contact, or [analysis] contact = true in the design)")
    if layers.strip().lower() in ("folded", "wound"):
        from ..multistable.stacked import hold_loops

        if laminate is not None:
            raise RodstabInputError(f"--laminate is a setting of --layers NAME=K (welded "
                                    f"layers), not of --layers {layers.strip()}")
        try:
            return None, None, hold_loops(a, n, load_factor, *touch, layers.strip().lower())
        except RodstabInputError as exc:
            raise RodstabInputError(f"--layers {layers.strip()}: {exc}") from None
    if layers.strip().lower() == "braid":
        from ..multistable.braid import hold_braid

        if laminate is not None:
            raise RodstabInputError("--laminate is a setting of --layers NAME=K (welded "
                                    "layers), not of --layers braid")
        try:
            return None, None, hold_braid(a, n, load_factor, *touch)
        except RodstabInputError as exc:
            raise RodstabInputError(f"--layers braid: {exc}") from None
    order = parse_layers(layers, [s.name for s in a.segments])
    if not isinstance(order, dict) or any(isinstance(k, tuple) or not float(k).is_integer()
                                          for k in order.values()):
        raise RodstabInputError(f"--layers {layers!r}: equilibrium lifts whole segments to "
                                "whole layers, NAME=K (K an integer), or braid; 'torus' and "
                                "in-plane offsets are analyze's cone test")
    return (*stacked_layers(a, {k: int(v) for k, v in order.items()}, *touch, laminate), None)


def layers_report(rod: Any, stack: dict[str, float] | None, axial: float | None,
                  laminate: float | None, braid: Any) -> tuple[dict[str, Any], list[str]]:
    """Equilibrium's ``layers`` JSON block and lines: the layers' heights or the braid."""
    from ..multistable.layered import weld_spans
    from ..multistable.linking import NOT_A_RING, describe_linking, self_linking
    from .output import fmt, layers_line, weld_line

    def linking_line(lk: Any) -> str:
        return (f"linking      {describe_linking('the stacked ring', lk)} (ribbon pushed "
                f"along {lk.director}; rods that cannot cross keep it: a state of this "
                "model with another number is out of reach, rodstab.multistable.linking)")

    if braid is not None and not braid[0].method.startswith("figure-eight braid"):
        from ..multistable.folding import layer_swaps

        st, held, ok, its, _ = braid  # an N-loop ring, folded or wound (hold_loops)
        lk, swaps = self_linking(held), [math.degrees(v) for v in layer_swaps(held)]
        return ({"stacking": st.to_dict(), "spanning_welds": False,
                 "relaxed": {"converged": ok, "iterations": its},
                 "swaps_deg": swaps, "linking": lk.to_dict()},
                [f"layers       {st.method}; {'; '.join(st.changes)}; built with every gap at "
                 f"least {fmt(st.check.min_gap)}, relaxed from there with contact ({its} "
                 f"Newton iterations{'' if ok else ', NOT converged'}), then the Newton below",
                 "swaps        the layer order changes at azimuth "
                 + ", ".join(f"{v:.1f}" for v in swaps) + " deg (relaxed state, from the "
                 "first node; rodstab.multistable.folding.layer_swaps)",
                 linking_line(lk)])
    if braid is not None:
        st, _, ok, its, _ = braid
        return ({"braid": st.to_dict(), "spanning_welds": True,
                 "relaxed": {"converged": ok, "iterations": its}},
                [f"layers       {st.method}; {'; '.join(st.changes)}; built with every gap at "
                 f"least {fmt(st.check.min_gap)}, relaxed from there with contact ({its} "
                 f"Newton iterations{'' if ok else ', NOT converged'}; from dhat = 0.1 h, "
                 "halved to the one asked), then the Newton below"])
    welds = (None if rod.contact is None
             else weld_spans(rod, 2.0 * float(rod.contact.radius.max())))
    lines = [layers_line(stack or {}, axial, laminate)]
    if welds is not None and rod.offsets is not None:
        lines.append(weld_line(welds))
    lk = self_linking(rod)
    if lk.reason != NOT_A_RING:
        lines.append(linking_line(lk))
    return ({"heights": stack, "spanning_welds": rod.offsets is not None,
             "laminate": laminate, "axial_stiffness": axial,
             "welds": None if welds is None else welds.to_dict(),
             "linking": lk.to_dict()}, lines)


def cone_block(a: Any, layers: str | None, thickness_ratio: float, n: int
               ) -> tuple[dict[str, Any], list[str]]:
    """``analyze --contact``: the cone verdicts and the limits with contact, JSON and lines.

    The layer order is ``--layers`` or the default (:func:`rodstab.multistable.cone.
    default_layers`); the verdicts are :func:`~rodstab.multistable.cone.contact_cone`'s, the
    limits :func:`~rodstab.multistable.cone_limit.cone_limits`' on the same FE mesh.
    """
    from ..multistable.cone import contact_cone, default_layers
    from ..multistable.cone_limit import cone_limits, rod_cone_limits
    from .output import cone_lines

    names = [s.name for s in a.segments]
    order, how = ((parse_layers(layers, names), "as given") if layers is not None
                  else default_layers(a, thickness_ratio))
    cone = contact_cone(a, order, n, thickness_ratio=thickness_ratio)
    limits = cone_limits(a, order, n) if cone.pairs else None
    # The rod engine's cone has the in-plane motions too: the physical limit at zero gap.
    full = rod_cone_limits(a, order, n, thickness_ratio=thickness_ratio) if cone.pairs else None
    block = cone.to_dict() | {"layers_chosen": how, "thickness_ratio": thickness_ratio,
                              "limits": None if limits is None else limits.to_dict(),
                              "limits_in_plane": None if full is None else full.to_dict()}
    return block, cone_lines(cone, how, limits, full)


#: ``--cusp-width``: one definition for ``barrier`` and ``transitions``.
cusp_width_option = click.option(
    "--cusp-width", "cusp_width", type=float, default=None,
    help="Cusp welds of this width W, in units of --contact-thickness h (W >= 1): the two rod "
         "ends of every cusp held W h apart across the tangent, so rods of thickness can "
         "leave it (at a point weld they overlap); every pair the contact model sees is then "
         "judged. Not with --layers.")


def check_cusp_width(w: float, a: Any, h: float, state: str) -> float:
    """``--cusp-width`` checked on state ``state`` (assembly ``a``), as a length.

    ``w h`` times the mean rod length (``h``: ``h / L``). Refused, naming the value: not
    finite or below 1 (narrower than the rods), or ``a`` has no cusp (two rod ends leaving a
    joint along one line).
    """
    import math

    from ..nonlinear.mesh import cusp_offsets

    if not (math.isfinite(w) and w >= 1.0):
        raise RodstabInputError(f"--cusp-width {w!r} must be a finite number >= 1, in units "
                                "of --contact-thickness (a weld narrower than the rods' "
                                "thickness puts the two ends' rods into one another)")
    length = w * h * a.total_length / len(a.segments)
    if not cusp_offsets(a, a.joints(), length):
        raise RodstabInputError(f"--cusp-width {w!r}: the state {state!r} has no cusp (two rod "
                                "ends leaving a joint along one line)")
    return length
