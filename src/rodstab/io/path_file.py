"""``path.npz``: a path of states written so that anyone can check its gaps independently.

Arrays (NumPy ``.npz``, model units: lengths in ``L``, the rod length):

* ``x`` (n_states, n_nodes, 3) -- node positions of every state of the path, in order;
* ``edges`` (n_elements, 2) -- node indices of every element (rods welded at a joint share
  its node);
* ``rest_length`` (n_elements,) -- rest lengths (distances along the structure);
* ``energy`` (n_states,) -- the energy of every state (``B3 / L``), when computed (a
  barrier's; a transition's sampled states have none);
* ``thickness`` () -- only when known: the smallest centreline distance two
  non-neighbouring elements may have (``h`` for rods of thickness ``h``, capsules of radius
  ``h / 2``). A path with a smaller distance passes rods through each other.

Written by ``rodstab barrier --out DIR`` (``DIR/path.npz``) and ``rodstab transitions --out
DIR`` (one file per edge); :func:`rodstab.nonlinear.contact_gaps.path_gaps` is rodstab's own
check of such a file.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np

from ..errors import RodstabInputError

#: File name of a path in an output directory.
PATH_FILE = "path.npz"


def write_path_file(path: str | Path, x: np.ndarray, edges: np.ndarray,
                    rest_length: np.ndarray, energies: Sequence[float] | None = None, *,
                    thickness: float | None = None) -> Path:
    """Write a path to ``path`` (``.npz``, the arrays of the module docstring).

    Parameters
    ----------
    path : str or Path
        The file (its directory must exist).
    x : ndarray (n_states, n_nodes, 3)
        Node positions of the path's states in order (``L``).
    edges : ndarray (n_elements, 2)
        Node indices of every element.
    rest_length : ndarray (n_elements,)
        Rest lengths (``L``).
    energies : sequence of float, optional
        The states' energies (``B3 / L``), one per state; left out when not computed (the
        sampled states of a transition).
    thickness : float, optional
        The rods' thickness (``L``); left out when not known.

    Returns
    -------
    Path
    """
    x = np.asarray(x, float)
    if x.ndim != 3 or x.shape[2] != 3 or len(x) == 0:
        raise RodstabInputError(f"x must have shape (n_states, n_nodes, 3), got {x.shape}")
    if energies is not None and len(energies) != len(x):
        raise RodstabInputError(f"{len(x)} states but {len(energies)} energies")
    arrays: dict[str, np.ndarray] = {
        "x": x,
        "edges": np.asarray(edges, np.int64),
        "rest_length": np.asarray(rest_length, float),
    }
    if energies is not None:
        arrays["energy"] = np.asarray(energies, float)
    if thickness is not None:
        arrays["thickness"] = np.asarray(float(thickness))
    out = Path(path)
    with out.open("wb") as f:
        np.savez(f, **arrays)  # type: ignore[arg-type]
    return out


def read_path_file(path: str | Path) -> dict[str, Any]:
    """Read a file of :func:`write_path_file`: its arrays (``thickness`` a float or None)."""
    try:
        with np.load(Path(path), allow_pickle=False) as z:
            data = {k: z[k] for k in z.files}
    except (OSError, ValueError) as exc:
        raise RodstabInputError(f"{path}: not a path file ({exc})") from None
    missing = [k for k in ("x", "edges", "rest_length") if k not in data]
    if missing:
        raise RodstabInputError(f"{path}: not a path file (no {', '.join(missing)})")
    data["thickness"] = float(data["thickness"]) if "thickness" in data else None
    return data
