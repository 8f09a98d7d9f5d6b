"""The chain (multistable/chain.py) and the landscape graph (multistable/landscape.py).

A string that passes another minimum is split at it; each link's saddle must be the saddle the
string method finds between those two states directly (an independent run from another
start), and the landscape's lowest path must be the min-max over the saddles it holds.
"""

from __future__ import annotations

import pytest

from rodstab.multistable.chain import _route, chain, chain_result
from rodstab.multistable.discover import common_rod
from rodstab.multistable.landscape import Landscape
from rodstab.multistable.string_method import (
    relax_string,
    string_barrier,
    to_gauge,
)
from rodstab.nonlinear.newton import newton
from rodstab.problems.barrier_states import state_assembly
from rodstab.sections import rectangle


def test_route_collapses_runs_skips_unresolved_and_cuts_loops() -> None:
    """Basins in order: runs collapsed, None skipped, a basin visited again cuts the loop."""
    assert _route(["a", "a", None, "m", "m", "b"]) == [("a", 0, 1), ("m", 3, 4), ("b", 5, 5)]
    # back in a: the excursion to m is cut, a's run now ends at image 3
    assert _route(["a", "m", "m", "a", "b"]) == [("a", 0, 3), ("b", 4, 4)]
    # the string reaches b before its end, leaves and comes back: one b
    assert _route(["a", "b", "m", "b"]) == [("a", 0, 0), ("b", 1, 3)]
    assert _route(["a", None, None, "b"]) == [("a", 0, 0), ("b", 3, 3)]


def _graph(edges: list[tuple[float, str, str]], labels: list[str]) -> Landscape:
    land = Landscape([(lab, None, 0.0) for lab in labels],  # type: ignore[misc]
                     dict.fromkeys(labels))  # type: ignore[arg-type]
    land.saddles = [{"energy": e, "descent_ends": (u, v), "ends_converged": (True, True)}
                    for e, u, v in edges]
    return land


def test_lowest_path_is_the_min_max_path() -> None:
    """A direct saddle at 10 against a detour whose highest saddle is 7: the detour (a
    disconnectivity graph joins a and b at 7); an unconverged end does not count."""
    land = _graph([(10.0, "a", "b"), (5.0, "a", "m"), (7.0, "m", "n"), (6.0, "n", "b"),
                   (3.0, "m", "b")], ["a", "b", "m", "n"])
    land.saddles[-1]["ends_converged"] = (True, False)
    level, states, saddles = land.lowest_path("a", "b")
    assert level == 7.0
    assert states == ["a", "m", "n", "b"] and saddles == [5.0, 7.0, 6.0]
    lone = _graph([(1.0, "a", "m")], ["a", "b", "m"])
    assert lone.lowest_path("a", "b") is None


SEC = rectangle(aspect=4.0)
MU, N, IMAGES = 1.5, 6, 11


@pytest.fixture(scope="module")
def direct() -> dict[str, object]:
    """The string method's barriers line -> star and star -> daisy (hexagram, h/t = 4,
    kappa_n R0 = 1.5, 6 el./rod), each run on its own: results and paths."""
    line, star, daisy = (state_assembly("hexagram", SEC, s) for s in ("line", "star", "daisy"))
    return {names: string_barrier(a, b, MU, elements_per_segment=N, images=IMAGES,
                                  name_a=names[0], name_b=names[1])
            for a, b, names in ((line, star, ("line", "star")),
                                (star, daisy, ("star", "daisy")))}


@pytest.mark.slow
def test_a_path_through_the_star_splits_into_the_two_direct_barriers(direct) -> None:
    """The two direct paths joined at the star (line -> star -> daisy, 21 images): the chain
    finds the images' basins line, star, daisy in that order; the highest link's own string
    finds the direct string's saddle again (same energy to 1e-8), and the other link, bounded
    by its path below that saddle, is not relaxed (its bound lies above its direct saddle)."""
    for b, _ in direct.values():
        assert b.converged and b.saddle_index == 1
    model = common_rod(state_assembly("hexagram", SEC, "line"), N, MU)
    newton(model)
    band: list = []
    for _, path in direct.values():
        images = []
        for snap in path:
            r = model.copy()
            snap.put(r)
            to_gauge(r, model)  # the second path is in the star's gauge: one gauge for both
            images.append(r)
        band += images if not band else images[1:]
    land = Landscape.of([("line", band[0]), ("daisy", band[-1])])
    links, paths, basins = chain(band, land, ("line", "daisy"), relax_string,
                                 images=IMAGES, max_iter=300)
    result = chain_result(links, basins, land, ("line", "daisy"))
    assert result.converged, result
    assert len(result.states) == 3 and result.states[::2] == ("line", "daisy")
    first, second = result.links
    ls, sd = direct[("line", "star")][0], direct[("star", "daisy")][0]
    assert first.converged and first.energy_saddle == pytest.approx(ls.energy_saddle, rel=1e-8)
    # star -> daisy is bounded by its path below line -> star's saddle: not relaxed; the bound
    # is a bound: at least the direct string's saddle (here equal to it up to round-off: the
    # link's start is the direct path, saddle included)
    assert not second.converged and second.iterations == 0
    assert sd.energy_saddle * (1 - 1e-12) <= second.energy_bound < first.energy_saddle
    assert result.energy_saddle == first.energy_saddle
    assert first.energy_saddle <= first.energy_bound <= first.energy_saddle * (1 + 1e-3)
    assert result.lowest is None  # no saddle star -> daisy was sought: the graph is not joined
    # the middle minimum is the star: the direct string's end
    assert result.energies[1] == pytest.approx(sd.energy_from, rel=1e-9)
    assert paths[0][first.saddle_image].energy() == first.energy_saddle
