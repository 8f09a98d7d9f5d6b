"""The ``rodstab`` command. Holds no mathematics: it parses, calls a solver, prints.

Every analysis subcommand prints a readable table, or with ``--json`` exactly one JSON object on
stdout (non-dimensional quantities as in the paper; NaN/inf become ``null``). A design file with
units (:mod:`rodstab.units`) adds a ``"units"`` block of the same results in SI, and the
physical values to the table.

Exit status (:func:`main`):

* 0 -- done;
* 2 -- invalid input (:class:`~rodstab.errors.RodstabInputError` or a usage error): one line
  on stderr naming the offending option and value, nothing on stdout (except ``sweep``, whose
  design may be invalid at values inside its range: it prints its table first);
* 3 -- a solver did not converge (:class:`~rodstab.errors.NotConverged`): one line on stderr
  saying what did not converge; ``equilibrium``, ``continue`` and ``sweep`` print their table
  or JSON first (with ``converged: false``, or the point's ``status``).

Any other exception is a bug in rodstab and propagates with its traceback.

The package: :mod:`.main` (the group, the entry point and its exit statuses), :mod:`.options`
(every shared option, once), :mod:`.output` (tables, JSON, warnings), and one module per
command group (:mod:`.paper`, :mod:`.design`, :mod:`.continuation`, :mod:`.states`,
:mod:`.multistable`, :mod:`.barrier`), each of which parses and prints only.
"""

from __future__ import annotations

from .main import EXIT_BAD_INPUT, EXIT_NOT_CONVERGED, EXIT_OK, cli, main

__all__ = ["EXIT_BAD_INPUT", "EXIT_NOT_CONVERGED", "EXIT_OK", "cli", "main"]
